//! The settings' documentation for the app's panel and the CLI: the doc comment of every field
//! and the variants of every enum field, read from the Rust sources at compile time so the help
//! text is the code's own.

/// Sources whose struct fields are documented for the settings panel: (key prefix, struct name,
/// source).
const DOC_SOURCES: [(&str, &str, &str); 18] = [
    ("", "WrapSettings", include_str!("mod.rs")),
    ("start", "StartSettings", include_str!("stages.rs")),
    ("field", "FieldParams", include_str!("stages.rs")),
    ("flow", "FlowSettings", include_str!("stages.rs")),
    ("remesh", "RemeshingSettings", include_str!("stages.rs")),
    ("fit", "FitSettings", include_str!("stages.rs")),
    ("stop", "StopSettings", include_str!("stages.rs")),
    ("surgery", "SurgerySettings", include_str!("stages.rs")),
    ("tuning", "Tuning", include_str!("tuning.rs")),
    ("tuning.start", "StartTuning", include_str!("tuning.rs")),
    ("tuning.field", "FieldTuning", include_str!("tuning.rs")),
    ("tuning.flow", "FlowTuning", include_str!("tuning.rs")),
    ("tuning.remesh", "RemeshTuning", include_str!("tuning.rs")),
    ("tuning.fit", "FitTuning", include_str!("tuning.rs")),
    ("tuning.surgery", "SurgeryTuning", include_str!("tuning.rs")),
    ("tuning.guard", "GuardSettings", include_str!("../guard.rs")),
    (
        "tuning.solver",
        "SolverSettings",
        include_str!("../../solve/mod.rs"),
    ),
    (
        "tuning.remesh.features",
        "FeatureSettings",
        include_str!("../../remesh/features.rs"),
    ),
];

/// Sources of enums that settings fields name, besides [`DOC_SOURCES`].
const ENUM_SOURCES: [&str; 1] = [include_str!("../../field/mod.rs")];

/// The text of `pub struct name { … }` in `src`, from its header to before the closing brace.
fn struct_body<'a>(src: &'a str, name: &str) -> Option<&'a str> {
    let body = &src[src.find(&format!("pub struct {name} {{"))?..];
    Some(&body[..body.find("\n}").unwrap_or(body.len())])
}

/// The doc comment of every public field of the settings structs, keyed by its path in the
/// settings JSON (`tau`, `field.band_cells`, …). Read from the Rust sources at compile time, so
/// the panel's help text is the code's own documentation.
pub fn settings_docs() -> Vec<(String, String)> {
    let mut out = Vec::new();
    for (prefix, name, src) in DOC_SOURCES {
        let Some(body) = struct_body(src, name) else {
            continue;
        };
        let mut doc = String::new();
        for line in body.lines().skip(1) {
            let t = line.trim();
            if let Some(d) = t.strip_prefix("///") {
                if !doc.is_empty() {
                    doc.push(' ');
                }
                doc.push_str(d.trim());
            } else if let Some(rest) = t.strip_prefix("pub ") {
                if let Some((field, _)) = rest.split_once(':') {
                    let key = if prefix.is_empty() {
                        field.to_string()
                    } else {
                        format!("{prefix}.{field}")
                    };
                    out.push((
                        key,
                        doc.replace("[`", "").replace("`]", "").replace('`', ""),
                    ));
                }
                doc.clear();
            } else if !t.starts_with("#[") {
                doc.clear();
            }
        }
    }
    out
}

/// [`settings_docs`] of the parameters: every key outside `tuning`, and `tuning` itself.
pub fn parameter_docs() -> Vec<(String, String)> {
    let mut docs = settings_docs();
    docs.retain(|(k, _)| !k.starts_with("tuning."));
    docs
}

/// CamelCase → snake_case (serde's `rename_all = "snake_case"`, used by every settings enum).
fn snake_case(name: &str) -> String {
    let mut out = String::new();
    for (i, ch) in name.chars().enumerate() {
        if ch.is_uppercase() {
            if i > 0 {
                out.push('_');
            }
            out.extend(ch.to_lowercase());
        } else {
            out.push(ch);
        }
    }
    out
}

/// The variants (as serialised) of every enum-typed settings field, keyed like
/// [`settings_docs`]: read from the Rust sources at compile time.
pub fn settings_enums() -> Vec<(String, Vec<String>)> {
    let all_src: String = DOC_SOURCES
        .iter()
        .map(|s| s.2)
        .chain(ENUM_SOURCES)
        .collect();
    let mut out = Vec::new();
    for (prefix, name, src) in DOC_SOURCES {
        let Some(body) = struct_body(src, name) else {
            continue;
        };
        for line in body.lines().skip(1) {
            let Some(rest) = line.trim().strip_prefix("pub ") else {
                continue;
            };
            let Some((field, ty)) = rest.split_once(':') else {
                continue;
            };
            let ty = ty.trim().trim_end_matches(',');
            let Some(e) = all_src.find(&format!("pub enum {ty} {{")) else {
                continue;
            };
            let ebody = &all_src[e..];
            let ebody = &ebody[..ebody.find("\n}").unwrap_or(ebody.len())];
            let variants: Vec<String> = ebody
                .lines()
                .skip(1)
                .map(str::trim)
                .filter(|l| !l.starts_with("//") && !l.starts_with("#[") && !l.is_empty())
                .filter_map(|l| {
                    let id: String = l
                        .chars()
                        .take_while(|c| c.is_alphanumeric() || *c == '_')
                        .collect();
                    (!id.is_empty()).then(|| snake_case(&id))
                })
                .collect();
            let key = if prefix.is_empty() {
                field.to_string()
            } else {
                format!("{prefix}.{field}")
            };
            out.push((key, variants));
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::flow::WrapSettings;

    #[test]
    fn settings_docs_cover_every_field() {
        let docs = settings_docs();
        fn walk(prefix: &str, v: &serde_json::Value, docs: &[(String, String)], n: &mut usize) {
            for (k, v) in v.as_object().unwrap() {
                let key = if prefix.is_empty() {
                    k.clone()
                } else {
                    format!("{prefix}.{k}")
                };
                assert!(
                    docs.iter().any(|(d, text)| d == &key && !text.is_empty()),
                    "no doc for {key}"
                );
                *n += 1;
                if v.is_object() {
                    walk(&key, v, docs, n);
                }
            }
        }
        let mut n = 0;
        walk(
            "",
            &serde_json::to_value(WrapSettings::default()).unwrap(),
            &docs,
            &mut n,
        );
        assert!(n > 60, "only {n} settings documented");
    }

    #[test]
    fn settings_enums_list_the_serialised_variants() {
        let e = settings_enums();
        let get = |k: &str| {
            e.iter()
                .find(|(key, _)| key == k)
                .map(|(_, v)| v.clone())
                .unwrap()
        };
        assert_eq!(get("start.surface"), ["auto", "icosphere", "isosurface"]);
        assert_eq!(get("remesh.trigger"), ["always", "quality_band", "auto"]);
        assert_eq!(
            get("tuning.remesh.features.detector"),
            ["off", "mean_curvature", "dihedral_angle", "both"]
        );
        assert_eq!(get("field.sign"), ["auto", "unsigned"]);
        // Every listed variant deserialises.
        for v in get("start.surface") {
            let json = format!("{{\"start\": {{\"surface\": \"{v}\"}}}}");
            assert!(WrapSettings::from_json(&json).is_ok(), "{json}");
        }
    }
}
