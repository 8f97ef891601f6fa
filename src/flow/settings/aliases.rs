//! The flat setting keys of the first releases (`tau`, `remesh_iterations`, `final_fit`, …), still
//! accepted everywhere a key is read: settings JSON, `lsw wrap --set`, share links. One table,
//! read by [`super::WrapSettings::from_json`], the CLI and (through the facade) the app.

use serde_json::{Map, Value};

/// Settings added since share links carry every setting (version 3), with the value that
/// computes what a link made before them computed: a link without the key decodes to it, so
/// the link keeps its result (`flow.regrow_depth` 0 is the flow before `flow::regrow`,
/// `surgery.tunnel_ratio` 0 the surgery before tunnels, `field.principal_slack` 0 the grid of
/// the axis-aligned box, `start.part_gap` 0 one icosphere around all, `field.enclosed_cells`
/// 0 a cloud's field unsigned everywhere, `flow.cover_gaps` 1 a cloud's d₀ from the cell alone,
/// `flow.deflate_far` 0 no bubble deflated).
pub const ADDED: &[(&str, f64)] = &[
    ("flow.regrow_depth", 0.0),
    ("surgery.tunnel_ratio", 0.0),
    ("field.principal_slack", 0.0),
    ("start.part_gap", 0.0),
    ("field.enclosed_cells", 0.0),
    ("flow.cover_gaps", 1.0),
    ("flow.deflate_far", 0.0),
];

/// `(old flat key, key in the nested settings)`. An old key that was an object (`features`)
/// also maps its sub-keys (`features.enabled` → `remesh.features.enabled`).
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

/// The current key for `key`: itself unless it is an old flat key (or under an old object key).
pub fn canonical_key(key: &str) -> String {
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

/// Every old key down to the leaves (`features.detector` as well as `tau`) with its current key:
/// what a reader that cannot apply [`canonical_key`]'s prefix rule (the app's link decoder) needs.
pub fn leaf_aliases() -> Vec<(String, String)> {
    let defaults = serde_json::to_value(super::WrapSettings::default()).unwrap_or_default();
    let mut out = Vec::new();
    for (old, new) in ALIASES {
        let at = new.split('.').try_fold(&defaults, |v, k| v.get(k));
        match at.and_then(Value::as_object) {
            Some(obj) if OBJECT_ALIASES.contains(old) => {
                for k in obj.keys() {
                    out.push((format!("{old}.{k}"), format!("{new}.{k}")));
                }
            }
            _ => out.push(((*old).to_string(), (*new).to_string())),
        }
    }
    out
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
            old.push((canonical_key(&k), v));
        } else {
            out.insert(k, v);
        }
    }
    for (path, v) in old {
        insert_path(&mut out, &path, v);
    }
    Value::Object(out)
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
            "remesh.features.detector"
        );
        assert_eq!(canonical_key("flow.tau"), "flow.tau");
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
            "remesh.features.detector".into()
        )));
        let defaults = serde_json::to_value(super::super::WrapSettings::default()).unwrap();
        for (old, new) in &leaves {
            let v = new.split('.').try_fold(&defaults, |v, k| v.get(k));
            assert!(v.is_some_and(|v| !v.is_object()), "{old} → {new}");
            assert_eq!(&canonical_key(old), new);
        }
    }

    #[test]
    fn added_settings_are_numeric_leaves_whose_old_value_differs_from_the_default() {
        let defaults = serde_json::to_value(super::super::WrapSettings::default()).unwrap();
        for &(key, before) in ADDED {
            let v = key.split('.').try_fold(&defaults, |v, k| v.get(k));
            let now = v.and_then(|v| v.as_f64());
            assert!(now.is_some_and(|now| now != before), "{key}: {v:?}");
        }
    }

    #[test]
    fn migrate_nests_old_leaves_and_keeps_new_groups() {
        let v = serde_json::json!({"start": "icosphere", "remesh": false, "tau": 0.05,
            "features": {"detector": "both"}, "flow": {"c1": 2.0}, "field": {"band_cells": 4}});
        let m = migrate(v);
        assert_eq!(
            m,
            serde_json::json!({"start": {"surface": "icosphere"}, "remesh": {"enabled": false,
                "features": {"detector": "both"}}, "flow": {"c1": 2.0, "tau": 0.05},
                "field": {"band_cells": 4}})
        );
        let nested = serde_json::json!({"start": {"surface": "auto"}, "remesh": {"iterations": 3}});
        assert_eq!(migrate(nested.clone()), nested);
    }
}
