//! The app's one "Detail" control, from coarse to fine: a level scales the distance grid
//! (`field.cells_per_min_dimension`) and the smallest edge (`remesh.min_edge_multiplier`, λ_min)
//! together, so the surface resolves what the field resolves. This is the only place that maps
//! a level to those two settings; the app reads the result from the catalog ([`table`]).

use super::settings::{Preset, StartSurface, WrapSettings};
use serde::Serialize;
use std::collections::BTreeMap;

/// The app's "Close gaps up to" control: (label, `surgery.close_gaps`), automatic first. Handles
/// whose hole is narrower than the fraction of the diagonal stay closed; "all" keeps every one.
pub const CLOSE_GAPS: [(&str, f64); 7] = [
    ("auto", 0.0),
    ("1 %", 0.01),
    ("2 %", 0.02),
    ("5 %", 0.05),
    ("10 %", 0.1),
    ("25 %", 0.25),
    ("all", 1.0),
];

/// A level of detail. `Normal` leaves a preset as it is.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Detail {
    Coarse,
    Low,
    Normal,
    High,
    Fine,
}

impl Detail {
    /// Every level, coarse first.
    pub const ALL: [Detail; 5] = [
        Detail::Coarse,
        Detail::Low,
        Detail::Normal,
        Detail::High,
        Detail::Fine,
    ];

    /// The stable name (lower case).
    pub fn name(self) -> &'static str {
        match self {
            Detail::Coarse => "coarse",
            Detail::Low => "low",
            Detail::Normal => "normal",
            Detail::High => "high",
            Detail::Fine => "fine",
        }
    }

    /// Factor g on the grid's cells per minimum dimension; λ_min is divided by it where it
    /// applies. Steps of about 1.25: each level changes the vertex count by about 1.25² ≈ 1.6×.
    pub fn grid_factor(self) -> f64 {
        match self {
            Detail::Coarse => 0.6,
            Detail::Low => 0.8,
            Detail::Normal => 1.0,
            Detail::High => 1.25,
            Detail::Fine => 1.6,
        }
    }

    /// `s` at this level: N ← round(g·N); λ_min ← λ_min/g (to three significant digits) where
    /// λ_min is relative to the start sphere's edge, i.e.
    ///
    /// * icosphere start: always;
    /// * isosurface start: never — its λ_min is relative to the grid cell, so the finer grid
    ///   alone refines it;
    /// * auto: only for the coarser levels (g < 1). Auto picks the isosurface start for closed
    ///   meshes and then replaces a λ_min still at its default by the isosurface start's own
    ///   (`AUTO_ISOSURFACE_MIN_EDGE`); a smaller λ_min would be kept instead and, with the finer
    ///   grid, multiply the vertex count many times over. So with auto the finer levels refine
    ///   the grid only.
    pub fn apply(self, mut s: WrapSettings) -> WrapSettings {
        let g = self.grid_factor();
        if g == 1.0 {
            return s;
        }
        let n = s.field.cells_per_min_dimension as f64;
        s.field.cells_per_min_dimension = (g * n).round().max(2.0) as u32;
        let edge = match s.start.surface {
            StartSurface::Icosphere => true,
            StartSurface::Isosurface => false,
            StartSurface::Auto => g < 1.0,
        };
        if edge {
            s.remesh.min_edge_multiplier = three_digits(s.remesh.min_edge_multiplier / g);
        }
        s
    }
}

/// `x` rounded to three significant digits (short values in share links).
fn three_digits(x: f64) -> f64 {
    if x == 0.0 || !x.is_finite() {
        return x;
    }
    let scale = 10f64.powi(2 - crate::fmath::log10(x.abs()).floor() as i32);
    (x * scale).round() / scale
}

/// The two settings a level sets.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct DetailValues {
    /// `field.cells_per_min_dimension`.
    pub cells: u32,
    /// `remesh.min_edge_multiplier` by start surface, keyed by its settings name (`auto`,
    /// `icosphere`, `isosurface`).
    pub min_edge: BTreeMap<String, f64>,
}

/// One level as the app lists it: its values for every preset.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct DetailRow {
    /// Stable name (the menu's value).
    pub name: &'static str,
    /// `(cells, λ_min by start surface)` per preset name.
    pub presets: BTreeMap<&'static str, DetailValues>,
}

/// Every start surface (the keys of [`DetailValues::min_edge`]).
const START_SURFACES: [StartSurface; 3] = [
    StartSurface::Auto,
    StartSurface::Icosphere,
    StartSurface::Isosurface,
];

/// A start surface's name in settings JSON (`auto`, …).
fn surface_name(s: StartSurface) -> String {
    serde_json::to_value(s)
        .ok()
        .and_then(|v| v.as_str().map(str::to_owned))
        .unwrap_or_default()
}

/// Every level applied to every preset (with each start surface): the app's Detail menu sets
/// the two settings from this table and shows the level whose values are in force.
pub fn table() -> Vec<DetailRow> {
    Detail::ALL
        .iter()
        .map(|&d| DetailRow {
            name: d.name(),
            presets: Preset::ALL
                .iter()
                .map(|&p| {
                    let with = |surface| {
                        let mut s = p.settings();
                        s.start.surface = surface;
                        d.apply(s)
                    };
                    let values = DetailValues {
                        cells: with(StartSurface::Auto).field.cells_per_min_dimension,
                        min_edge: START_SURFACES
                            .iter()
                            .map(|&s| (surface_name(s), with(s).remesh.min_edge_multiplier))
                            .collect(),
                    };
                    (p.name(), values)
                })
                .collect(),
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::flow::settings::AUTO_ISOSURFACE_MIN_EDGE;

    #[test]
    fn normal_is_the_preset_and_levels_are_monotone() {
        for p in Preset::ALL {
            assert_eq!(Detail::Normal.apply(p.settings()), p.settings());
        }
        let ico = |d: Detail| {
            let mut s = WrapSettings::default();
            s.start.surface = StartSurface::Icosphere;
            let s = d.apply(s);
            (
                s.field.cells_per_min_dimension,
                s.remesh.min_edge_multiplier,
            )
        };
        let levels: Vec<(u32, f64)> = Detail::ALL.iter().map(|&d| ico(d)).collect();
        assert_eq!(
            levels,
            [
                (24, 0.233),
                (32, 0.175),
                (40, 0.14),
                (50, 0.112),
                (64, 0.0875)
            ]
        );
        for &d in &Detail::ALL {
            assert!(d.apply(WrapSettings::default()).check().is_ok(), "{d:?}");
        }
    }

    #[test]
    fn auto_keeps_the_isosurface_starts_own_edge_on_finer_levels() {
        for d in [Detail::High, Detail::Fine] {
            let s = d.apply(WrapSettings::default());
            assert!(s.field.cells_per_min_dimension > 40);
            // A closed mesh: auto resolves to the isosurface start with its own λ_min …
            let closed = s.clone().resolved_for(true);
            assert_eq!(closed.remesh.min_edge_multiplier, AUTO_ISOSURFACE_MIN_EDGE);
            // … a cloud to the icosphere with the preset's.
            assert_eq!(s.resolved_for(false).remesh.min_edge_multiplier, 0.14);
        }
        let coarse = Detail::Coarse.apply(WrapSettings::default());
        assert_eq!(coarse.remesh.min_edge_multiplier, 0.233);
        let iso = Detail::Fine.apply(Preset::Isosurface.settings());
        assert_eq!(iso.remesh.min_edge_multiplier, 0.4);
        assert_eq!(iso.field.cells_per_min_dimension, 64);
    }

    #[test]
    fn table_lists_every_level_and_preset() {
        let t = table();
        assert_eq!(t.len(), Detail::ALL.len());
        assert_eq!(t[2].name, "normal");
        let full = &t[4].presets["full-wrap"];
        assert_eq!(full.cells, 64);
        let edges = |v: &DetailValues| {
            ["auto", "icosphere", "isosurface"].map(|k| v.min_edge.get(k).copied())
        };
        assert_eq!(edges(full), [Some(0.14), Some(0.0875), Some(0.14)]);
        let iso = &t[0].presets["isosurface"];
        assert_eq!(edges(iso), [Some(0.667), Some(0.667), Some(0.4)]);
        assert_eq!(t[2].presets.len(), Preset::ALL.len());
    }
}
