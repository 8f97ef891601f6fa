//! Keys of earlier settings, still accepted everywhere a key is read (settings JSON,
//! `lsw wrap --set`, share links): the flat keys of the first releases (`tau`, `final_fit`, …),
//! one table, and the values the tuning table now holds, at their stage's key before it
//! (`flow.regrow_depth` is `tuning.flow.regrow_depth`), one rule.

use serde_json::{Map, Value};

/// `(old flat key, key in the nested settings)`. An old key that was an object (`features`)
/// also maps its sub-keys (`features.enabled` → `tuning.remesh.features.enabled`).
pub const ALIASES: &[(&str, &str)] = &[
    ("start", "start.surface"),
    ("icosphere_level", "start.icosphere_level"),
    ("icosphere_radius_factor", "start.icosphere_radius_factor"),
    ("isosurface_level_cells", "start.isosurface_level_cells"),
    ("isosurface_resampling", "start.isosurface_resampling"),
    ("use_target", "flow.use_target"),
    ("tau", "flow.tau"),
    ("c1", "flow.c1"),
    ("c2", "flow.c2"),
    ("d1", "flow.d1"),
    ("d2", "flow.d2"),
    ("tangential_weight", "flow.tangential_weight"),
    ("mcf_positive_support", "flow.mcf_positive_support"),
    (
        "advection_positive_support",
        "flow.advection_positive_support",
    ),
    ("iso_level_factor", "flow.iso_level_factor"),
    ("shrink_factor", "flow.shrink_factor"),
    ("schedule", "flow.schedule"),
    ("decay", "flow.decay"),
    ("max_retries", "flow.max_retries"),
    ("remesh", "remesh.enabled"),
    ("remesh_from_step", "remesh.from_step"),
    ("remesh_trigger", "remesh.trigger"),
    ("remesh_max_kappa", "remesh.max_kappa"),
    ("min_edge_multiplier", "remesh.min_edge_multiplier"),
    ("remesh_iterations", "remesh.iterations"),
    ("smoothing_iterations", "remesh.smoothing_iterations"),
    ("features", "remesh.features"),
    ("final_fit", "fit.enabled"),
    ("fit_radius_cells", "fit.radius_cells"),
    ("fit_max_move_cells", "fit.max_move_cells"),
    ("fit_passes", "fit.passes"),
    ("steps", "stop.steps"),
    ("stop_fraction", "stop.fraction"),
    ("stop_displacement_cells", "stop.displacement_cells"),
];

/// Old keys whose value was an object: their sub-keys move with them. (`start` and `remesh`
/// were leaves, so `start.surface` and `remesh.iterations` are new keys, not old ones.)
const OBJECT_ALIASES: &[&str] = &["features"];

/// The current key for `key`: an old flat key's nested key (also under an old object key), and
/// a tuned value's key under `tuning`.
pub fn canonical_key(key: &str) -> String {
    tuned_key(&nested_key(key))
}

/// `key` with an old flat key (or an old object key's prefix) replaced by its nested key.
fn nested_key(key: &str) -> String {
    if let Some((_, new)) = ALIASES.iter().find(|(old, _)| *old == key) {
        return (*new).to_string();
    }
    for old in OBJECT_ALIASES {
        if let Some(rest) = key.strip_prefix(old).and_then(|r| r.strip_prefix('.')) {
            let new = ALIASES.iter().find(|(o, _)| o == old).map(|a| a.1);
            return format!("{}.{rest}", new.unwrap_or(old));
        }
    }
    key.to_string()
}

/// `tuning.{key}` where `key` names no parameter but a value of the tuning table, else `key`.
fn tuned_key(key: &str) -> String {
    let (public, tuning) = defaults_split();
    let at = |root: &Value| key.split('.').try_fold(root, |v, k| v.get(k)).is_some();
    if !at(&public) && at(&tuning) {
        format!("tuning.{key}")
    } else {
        key.to_string()
    }
}

/// The default settings as JSON: the parameters (without `tuning`) and the tuning apart.
fn defaults_split() -> (Value, Value) {
    let mut public = serde_json::to_value(super::WrapSettings::default()).unwrap_or_default();
    let tuning = public
        .as_object_mut()
        .and_then(|m| m.remove("tuning"))
        .unwrap_or_default();
    (public, tuning)
}

/// Every old key down to the leaves (`features.detector` as well as `tau`) with its current key:
/// what a reader that cannot apply [`canonical_key`]'s prefix rule (the app's link decoder) needs.
pub fn leaf_aliases() -> Vec<(String, String)> {
    let defaults = serde_json::to_value(super::WrapSettings::default()).unwrap_or_default();
    let mut out = Vec::new();
    for (old, new) in ALIASES {
        let new = tuned_key(new);
        let at = new.split('.').try_fold(&defaults, |v, k| v.get(k));
        match at.and_then(Value::as_object) {
            Some(obj) if OBJECT_ALIASES.contains(old) => {
                for k in obj.keys() {
                    out.push((format!("{old}.{k}"), format!("{new}.{k}")));
                }
            }
            _ => out.push(((*old).to_string(), new)),
        }
    }
    let (_, tuning) = defaults_split();
    let mut leaves = Vec::new();
    leaf_paths(&tuning, "", &mut leaves);
    for leaf in leaves {
        if leaf != "version" && tuned_key(&leaf) != leaf {
            out.push((leaf.clone(), format!("tuning.{leaf}")));
        }
    }
    out
}

/// The dotted paths of every leaf under `v`.
fn leaf_paths(v: &Value, prefix: &str, out: &mut Vec<String>) {
    match v.as_object() {
        Some(m) => {
            for (k, v) in m {
                let p = if prefix.is_empty() {
                    k.clone()
                } else {
                    format!("{prefix}.{k}")
                };
                leaf_paths(v, &p, out);
            }
        }
        None => out.push(prefix.to_string()),
    }
}

/// Whether `value` under the top-level `key` is written in the old flat form: an old key that is
/// not also a current group, or a current group name holding an old leaf (`"start": "auto"`,
/// `"remesh": false`).
fn is_old_entry(key: &str, value: &Value) -> bool {
    ALIASES.iter().any(|(old, _)| *old == key) && !(value.is_object() && is_group(key))
}

/// Top-level groups of the nested settings that share a name with an old leaf key.
fn is_group(key: &str) -> bool {
    key == "start" || key == "remesh"
}

/// Sets `value` at the dotted `path` inside `root`, creating objects on the way; a value already
/// there (given in the nested form) wins over the old key.
fn insert_path(root: &mut Map<String, Value>, path: &str, value: Value) {
    let mut parts = path.split('.').peekable();
    let mut node = root;
    while let Some(part) = parts.next() {
        if parts.peek().is_none() {
            node.entry(part.to_string()).or_insert(value);
            return;
        }
        let next = node
            .entry(part.to_string())
            .or_insert_with(|| Value::Object(Map::new()));
        let Some(obj) = next.as_object_mut() else {
            return; // a leaf where a group belongs: left for serde to reject
        };
        node = obj;
    }
}

/// Rewrites settings JSON written with old flat keys into the nested form (current keys are kept
/// as they are; unknown keys are left for serde to reject).
pub fn migrate(value: Value) -> Value {
    let Value::Object(map) = value else {
        return value;
    };
    let (mut out, mut old) = (Map::new(), Vec::new());
    for (k, v) in map {
        if is_old_entry(&k, &v) {
            old.push((nested_key(&k), v));
        } else {
            out.insert(k, v);
        }
    }
    for (path, v) in old {
        insert_path(&mut out, &nested_key(&path), v);
    }
    let mut moved = Vec::new();
    take_tuned(&mut out, "", &mut moved);
    for (path, v) in moved {
        insert_path(&mut out, &path, v);
    }
    Value::Object(out)
}

/// Takes every value outside `tuning` whose key [`tuned_key`] moves out of `map` (whole groups
/// such as `guard` leaf by leaf), with its new key.
fn take_tuned(map: &mut Map<String, Value>, prefix: &str, out: &mut Vec<(String, Value)>) {
    let keys: Vec<String> = map.keys().cloned().collect();
    for k in keys {
        let path = if prefix.is_empty() {
            k.clone()
        } else {
            format!("{prefix}.{k}")
        };
        if path == "tuning" {
            continue;
        }
        let new = tuned_key(&path);
        if new != path {
            if let Some(v) = map.remove(&k) {
                out.push((new, v));
            }
        } else if let Some(Value::Object(sub)) = map.get_mut(&k) {
            take_tuned(sub, &path, out);
            if sub.is_empty() {
                map.remove(&k);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn old_keys_map_to_their_stage() {
        assert_eq!(canonical_key("tau"), "flow.tau");
        assert_eq!(canonical_key("start"), "start.surface");
        assert_eq!(
            canonical_key("features.detector"),
            "tuning.remesh.features.detector"
        );
        assert_eq!(canonical_key("flow.tau"), "flow.tau");
        assert_eq!(
            canonical_key("flow.regrow_depth"),
            "tuning.flow.regrow_depth"
        );
        assert_eq!(canonical_key("guard"), "tuning.guard");
        assert_eq!(canonical_key("max_retries"), "tuning.flow.max_retries");
        assert_eq!(canonical_key("tuning.version"), "tuning.version");
        assert_eq!(canonical_key("flow.bogus"), "flow.bogus");
        assert_eq!(canonical_key("start.surface"), "start.surface");
        assert_eq!(canonical_key("field.band_cells"), "field.band_cells");
        // Every alias target is distinct.
        let mut targets: Vec<_> = ALIASES.iter().map(|a| a.1).collect();
        targets.sort_unstable();
        targets.dedup();
        assert_eq!(targets.len(), ALIASES.len());
    }

    #[test]
    fn leaf_aliases_reach_leaves_that_exist() {
        let leaves = leaf_aliases();
        assert!(leaves.contains(&("tau".into(), "flow.tau".into())));
        assert!(leaves.contains(&(
            "features.detector".into(),
            "tuning.remesh.features.detector".into()
        )));
        assert!(leaves.contains(&(
            "flow.regrow_depth".into(),
            "tuning.flow.regrow_depth".into()
        )));
        let defaults = serde_json::to_value(super::super::WrapSettings::default()).unwrap();
        for (old, new) in &leaves {
            let v = new.split('.').try_fold(&defaults, |v, k| v.get(k));
            assert!(v.is_some_and(|v| !v.is_object()), "{old} → {new}");
            assert_eq!(&canonical_key(old), new);
        }
    }

    #[test]
    fn migrate_nests_old_leaves_and_keeps_new_groups() {
        let v = serde_json::json!({"start": "icosphere", "remesh": false, "tau": 0.05,
            "features": {"detector": "both"}, "flow": {"c1": 2.0}, "field": {"band_cells": 4}});
        let m = migrate(v);
        assert_eq!(
            m,
            serde_json::json!({"start": {"surface": "icosphere"}, "remesh": {"enabled": false},
                "flow": {"c1": 2.0, "tau": 0.05}, "field": {"band_cells": 4},
                "tuning": {"remesh": {"features": {"detector": "both"}}}})
        );
        // Values the tuning table now holds move under it, whole groups leaf by leaf; a value
        // given under `tuning` wins.
        let v = serde_json::json!({"flow": {"regrow_depth": 0, "tau": 0.1},
            "guard": {"check_every": 4}, "tuning": {"version": 1, "flow": {"regrow_depth": 2}}});
        assert_eq!(
            migrate(v),
            serde_json::json!({"flow": {"tau": 0.1}, "tuning": {"version": 1,
                "flow": {"regrow_depth": 2}, "guard": {"check_every": 4}}})
        );
        let nested = serde_json::json!({"start": {"surface": "auto"}, "remesh": {"iterations": 3}});
        assert_eq!(migrate(nested.clone()), nested);
    }
}
