//! The lists the app offers, exported once from their Rust sources: file formats
//! ([`crate::io::formats::FORMATS`]), colour maps ([`crate::flow::colour::COLOUR_MAPS`]),
//! presets ([`crate::flow::Preset::ALL`]) and export formats; a preset's settings and the
//! settings' documentation, options, ranges and old keys ([`crate::flow::settings`]). The wasm
//! facade hands them to the page as they are.

use crate::flow::settings::{aliases::leaf_aliases, docs, tuning, RANGES};
use crate::flow::{ColourMap, Preset, COLOUR_MAPS, LESSONS, LESSON_COLOUR_MAPS};
use crate::io::{Format, FORMATS};

/// The catalog as JSON: `{formats, colourMaps, presets, exportFormats}`.
///
/// * `formats`: `[{name, label, extensions, kind, read, write}]` — every format LSW knows;
///   `kind` is "mesh", "cloud", "mesh-or-cloud" or "volume"; extensions without the dot, the
///   usual one first (`nii.gz` is one extension).
/// * `colourMaps`: `[{name, label, legend, unit, exportName}]` — the names `scalar()` takes;
///   `exportName` is the per-vertex property name in exported files, or null.
/// * `presets`: preset names in menu order (see `presetSettings`); `presetLabels` their menu
///   labels.
/// * `exportFormats`: names of the formats `export` and `exportMesh` write.
/// * `settingRanges`: `[{key, min, max, min_open, text}]` — the ranges the core enforces
///   (unbounded limits are null).
/// * `detail`: `[{name, presets: {preset: {cells, min_edge: {auto, icosphere, isosurface}}}}]`
///   — the Detail levels, coarse first ([`crate::flow::detail::table`]).
/// * `closeGaps`: `[{label, value}]` — the "Close gaps up to" choices, `surgery.close_gaps`
///   values ([`crate::flow::detail::CLOSE_GAPS`]).
/// * `lessonColourMaps`: the colour-map names the MCF lesson offers.
/// * `tuning`: `{current, versions: [{version, changes}], rows: {version: tuning}}` — the tuning
///   table ([`crate::flow::settings::tuning`]): a link names its version, and its settings decode
///   against that version's row.
/// * `lessons`: `[{name, label, title, needsMesh}]` — the MCF lessons
///   ([`crate::flow::LESSONS`]): the sphere, and the loaded mesh (offered only for a mesh).
pub fn catalog_json() -> serde_json::Value {
    serde_json::json!({
        "lessons": LESSONS,
        "detail": crate::flow::detail::table(),
        "closeGaps": crate::flow::detail::CLOSE_GAPS
            .iter()
            .map(|&(label, value)| serde_json::json!({"label": label, "value": value}))
            .collect::<Vec<_>>(),
        "lessonColourMaps": LESSON_COLOUR_MAPS.map(ColourMap::name),
        "formats": FORMATS,
        "colourMaps": COLOUR_MAPS,
        "presets": Preset::ALL.map(Preset::name),
        "presetLabels": Preset::ALL.map(Preset::label),
        "exportFormats": Format::WRITABLE.map(Format::name),
        "settingRanges": RANGES,
        "tuning": {
            "current": tuning::CURRENT_VERSION,
            "versions": tuning::VERSIONS
                .iter()
                .map(|&(version, changes)| serde_json::json!({"version": version, "changes": changes}))
                .collect::<Vec<_>>(),
            "rows": tuning::Tuning::table_json(),
        },
    })
}

/// `(key, value)` pairs as a JSON object string.
pub fn object<V: Into<serde_json::Value>>(pairs: Vec<(String, V)>) -> String {
    let map: serde_json::Map<String, serde_json::Value> =
        pairs.into_iter().map(|(k, v)| (k, v.into())).collect();
    serde_json::Value::Object(map).to_string()
}

/// The doc comment of every settings field, as a JSON object keyed by the field's path in the
/// settings JSON (`flow.tau`, `field.band_cells`, …).
pub fn settings_docs() -> String {
    object(docs::settings_docs())
}

/// The options of every enum-valued settings field, as a JSON object keyed by the field's path.
pub fn settings_enums() -> String {
    object(docs::settings_enums())
}

/// The old flat settings keys (down to the leaves) with their current nested keys, as a JSON
/// object: share links made before the settings were nested still decode.
pub fn setting_aliases() -> String {
    object(leaf_aliases())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn catalog_lists_every_format_map_and_preset() {
        let c = catalog_json();
        let formats = c["formats"].as_array().unwrap();
        assert_eq!(formats.len(), FORMATS.len());
        assert_eq!(formats[0]["name"], "ply");
        assert_eq!(formats[0]["kind"], "mesh-or-cloud");
        let nifti = formats.iter().find(|f| f["name"] == "nifti").unwrap();
        assert_eq!(nifti["extensions"][1], "nii.gz");
        assert_eq!(
            (nifti["read"].as_bool(), nifti["write"].as_bool()),
            (Some(true), Some(false))
        );
        let maps: Vec<&str> = c["colourMaps"]
            .as_array()
            .unwrap()
            .iter()
            .map(|m| m["name"].as_str().unwrap())
            .collect();
        assert_eq!(
            maps,
            [
                "distance",
                "curvature",
                "kappa",
                "covolume",
                "features",
                "flagged"
            ]
        );
        assert_eq!(c["colourMaps"][1]["exportName"], "mean_curvature");
        assert_eq!(c["presets"][0], "full-wrap");
        assert_eq!(c["lessons"][0]["name"], "mcf");
        assert_eq!(c["lessons"][1]["needsMesh"], true);
        assert_eq!(c["presetLabels"][3], "MCF (ignore target)");
        assert_eq!(c["presets"].as_array().unwrap().len(), Preset::ALL.len());
        assert_eq!(c["settingRanges"][0]["key"], "start.icosphere_level");
        assert_eq!(c["detail"][2]["name"], "normal");
        assert_eq!(c["closeGaps"][0]["label"], "auto");
        assert_eq!(c["closeGaps"][0]["value"], 0.0);
        assert_eq!(c["detail"][4]["presets"]["full-wrap"]["cells"], 64);
        assert_eq!(
            c["detail"][4]["presets"]["full-wrap"]["min_edge"]["icosphere"],
            0.0875
        );
        assert_eq!(
            c["lessonColourMaps"],
            serde_json::json!(["curvature", "kappa"])
        );
        let docs: serde_json::Value = serde_json::from_str(&settings_docs()).unwrap();
        assert!(docs["flow"]["tau"].is_null() && docs["flow.tau"].is_string());
        let aliases: serde_json::Value = serde_json::from_str(&setting_aliases()).unwrap();
        assert_eq!(aliases["tau"], "flow.tau");
        assert_eq!(
            c["exportFormats"],
            serde_json::json!(["ply", "obj", "stl", "glb", "vtk"])
        );
    }
}
