//! The tuning table: the heuristics and constants of a wrap that are not the method's parameters
//! (docs/method.md §10.1) — each one a rule for a class of inputs, with its decision record in
//! docs/decisions/. The table is versioned: a version's values never change, a new value is a
//! new version, and settings name the version they were made with (share links carry it), so an
//! old link keeps its result after the defaults move on.

use crate::flow::guard::GuardSettings;
use crate::remesh::{FeatureDetector, FeatureSettings};
use crate::solve::SolverSettings;
use serde::{Deserialize, Deserializer, Serialize};
use serde_json::Value;

/// The version new settings get.
pub const CURRENT_VERSION: u32 = 3;

/// The versions of the table, oldest first, each with what it changed (for `lsw info` and the
/// panel): version 1 is the tuning of every share link made before the table (link formats 1–3).
pub const VERSIONS: &[(u32, &str)] = &[
    (
        1,
        "the tuning of share links before the table (formats 1–3)",
    ),
    (
        2,
        "regrowth, tunnels, the principal-box grid, a sphere per part, enclosed regions signed, \
         gaps covered, far bubbles deflated",
    ),
    (3, "a cloud's fit moves along the data's fitted normal"),
];

/// Every tuned value of a wrap, by stage, with the version of the table they come from.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Tuning {
    /// The table version these values start from (values given beside it override it).
    pub version: u32,
    /// The start surface.
    pub start: StartTuning,
    /// The distance field.
    pub field: FieldTuning,
    /// The evolution.
    pub flow: FlowTuning,
    /// Remeshing.
    pub remesh: RemeshTuning,
    /// The final fit.
    pub fit: FitTuning,
    /// The contact and divergence guards.
    pub guard: GuardSettings,
    /// Topology surgery.
    pub surgery: SurgeryTuning,
    /// The linear solver.
    pub solver: SolverSettings,
}

/// Tuning of the start surface.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct StartTuning {
    /// Icosphere start on a point cloud: parts lying apart (no cell of this share of the
    /// target's diagonal links them) start from a sphere each (see `flow::start`). 0: one sphere
    /// around all. Range 0–1.
    pub part_gap: f64,
}

/// Tuning of the distance field (the field's own options are [`crate::field::FieldSettings`]).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FieldTuning {
    /// Optional truncation: distances are capped at `truncation·β_min`. None: no cap.
    pub truncation: Option<f64>,
    /// Cap on fast-sweeping passes (one ordering each; 8 make a full cycle). Range ≥ 1.
    pub max_sweep_passes: u32,
    /// Sweeping stops after the first pass (from the 8th on) in which no value dropped by more
    /// than this many cells; 0: until no value changes. Range 0–1.
    pub sweep_tolerance: f64,
    /// Point clouds: the cell is at least this many median nearest-neighbour spacings, so the
    /// offset surface cannot slip between a sparse cloud's points. 0: off. Range 0–10.
    pub min_cell_spacings: f64,
    /// Point clouds: a point with fewer than 6 points within this many median spacings, in a
    /// region not as sparse as it is, is a stray return and left out. 0 keeps every point.
    /// Range 0–100.
    pub outlier_spacings: f64,
    /// A target lying turned gets the grid of its principal box: β_min is the smaller of the
    /// axis-aligned box's and this many times the principal box's. 0: the axis-aligned box.
    /// Range 0 or 1–100.
    pub principal_slack: f64,
    /// Point clouds: nodes deeper than this many cells inside a region the cloud encloses get a
    /// negative distance, so a vertex that slips into a solid is held and regrown. 0: unsigned.
    /// Range 0 or 1–16.
    pub enclosed_cells: f64,
    /// A wrap from an isosurface start grows the field's box by the room that start needs (its
    /// level and the band), not by the ζ·β_min an icosphere needs; one that falls back to the
    /// icosphere gets the ζ·β_min box (docs/decisions/0030-field-margin.md). Off: the trimmed
    /// lattice matches the full one only up to rounding.
    pub isosurface_margin: bool,
}

/// Tuning of the evolution.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FlowTuning {
    /// A wrap that leaves part of its target outside starts over once with D₂ = `second_pass_d2`
    /// and, on a cloud, d₀ grown towards the sampling's gap spacing by at most this factor; the
    /// pass that leaves fewer points outside is kept. Not for volumes. 1: off. Range 1–4.
    pub cover_gaps: f64,
    /// D₂ of that second pass (0, the obstacle setting, keeps the wrap off an open sheet's rim).
    /// Range ≥ 0.
    pub second_pass_d2: f64,
    /// After a cut, a surface farther from the data than this many surgery empty distances that
    /// faces the data is a bubble of the wrap's inside: its advection is mirrored so it deflates.
    /// 0: off. Range 0–100.
    pub deflate_far: f64,
    /// Times a failed solve is retried (zero-clamped weights, then τ halved). Range ≥ 0.
    pub max_retries: u32,
    /// A vertex inside the offset surface whose level lies farther than this many d₀ along its
    /// normal sits on a chord through a thin part and moves out to it. 0: off. Range 0–100.
    pub regrow_depth: f64,
    /// How far such a vertex looks for the offset level, in cells. Range 0–1000.
    pub regrow_cells: f64,
    /// The most such a vertex moves in one step, in mean edge lengths. Range 0–100.
    pub regrow_edges: f64,
}

/// Tuning of remeshing.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RemeshTuning {
    /// With trigger auto: remesh at least every this many steps. Range 1–1000.
    pub every: u32,
    /// Vertex-averaged κ(J_Δ) above which the quality band remeshes.
    pub max_kappa: f64,
    /// Splits put the new vertex on the curve through the edge's ends along their normals, not
    /// on the chord, which rounds corners and crease lines off.
    pub curved_splits: bool,
    /// Feature detection in the remesher (re-detected each call).
    pub features: FeatureSettings,
}

/// Tuning of the final fit.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FitTuning {
    /// Most cloud points a vertex's plane is fitted to (the nearest within the fit radius).
    /// Range ≥ 6.
    pub max_points: usize,
    /// Mesh targets: where a target vertex still lies farther than this many cells from the wrap
    /// after a pass, the nearest wrap face's edges are halved and the fit takes another pass.
    /// 0: off. Range ≥ 0.
    pub refine_error_cells: f64,
    /// Most extra passes of that error-adaptive sizing. Range 0–10.
    pub refine_passes: u32,
    /// The error-adaptive passes on a volume's iso-surface, whose misses lie in folds narrower
    /// than a cell that no pass reaches. Range 0–10.
    pub volume_refine_passes: u32,
    /// The error-adaptive sizing's vertex budget. Range ≥ 100.
    pub refine_max_vertices: usize,
    /// Mesh targets: the wrap vertex nearest to a target vertex still missed moves onto it when
    /// the way is clear, so a slit narrower than a cell is lined instead of bridged.
    pub reach: bool,
    /// Clouds: the fit is a moving-least-squares projection — along the normal of the plane
    /// fitted to the points around the vertex, not along the vertex's own normal, which folds
    /// the surface where the moves are longer than its edges — and its fold check holds a moved
    /// face to its vertices' fitted normals (docs/decisions/0029-surface-spacing.md).
    pub moving_least_squares: bool,
}

/// Tuning of topology surgery.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SurgeryTuning {
    /// Sheets are looked for every this many steps. Range ≥ 1.
    pub check_every: u32,
    /// Empty space: farther from the target than this many cells (and than `empty_spacings`).
    /// Range ≥ 0.
    pub empty_cells: f64,
    /// Empty space on a point cloud: also farther than this many median point spacings.
    /// Range ≥ 0.
    pub empty_spacings: f64,
    /// Two facing sheets meet when their gap is below this fraction of their distance to the
    /// target. Range (0, 1].
    pub gap_ratio: f64,
    /// Through-holes: facing sheets far from the data also meet when their gap is below this
    /// multiple of their distance and the path between them is ringed by data. 0: off.
    /// Range ≥ 0.
    pub tunnel_ratio: f64,
    /// Smallest patch (vertices) that is cut. Range ≥ 3.
    pub min_vertices: usize,
}

impl Tuning {
    /// The table at `version`, or None for a version this build does not know.
    pub fn at(version: u32) -> Option<Tuning> {
        let mut t = Self::version_1();
        if version == 1 {
            return Some(t);
        }
        if version == 0 || version > CURRENT_VERSION {
            return None;
        }
        t.version = 2;
        t.flow.regrow_depth = 1.5;
        t.surgery.tunnel_ratio = 4.0;
        t.field.principal_slack = 1.25;
        t.start.part_gap = 0.05;
        t.field.enclosed_cells = 2.0;
        t.flow.cover_gaps = 1.5;
        t.flow.deflate_far = 1.0;
        if version >= 3 {
            t.version = 3;
            t.fit.moving_least_squares = true;
        }
        Some(t)
    }

    /// Version 1, written out whole: every later version is this with its changes.
    fn version_1() -> Tuning {
        Tuning {
            version: 1,
            start: StartTuning { part_gap: 0.0 },
            field: FieldTuning {
                truncation: None,
                max_sweep_passes: 64,
                sweep_tolerance: 1e-4,
                min_cell_spacings: 2.0,
                outlier_spacings: 6.0,
                principal_slack: 0.0,
                enclosed_cells: 0.0,
                isosurface_margin: false,
            },
            flow: FlowTuning {
                cover_gaps: 1.0,
                second_pass_d2: 0.0,
                deflate_far: 0.0,
                max_retries: 4,
                regrow_depth: 0.0,
                regrow_cells: 16.0,
                regrow_edges: 2.0,
            },
            remesh: RemeshTuning {
                every: 4,
                max_kappa: 1.5,
                curved_splits: true,
                features: FeatureSettings {
                    detector: FeatureDetector::Off,
                    critical_mean_curvature_angle: std::f64::consts::FRAC_PI_2,
                    principal_curvature_factor: 3.2,
                    max_valence: 6,
                    dihedral_angle: std::f64::consts::FRAC_PI_3,
                    include_concave_edges: false,
                },
            },
            fit: FitTuning {
                max_points: 64,
                refine_error_cells: 0.25,
                refine_passes: 5,
                volume_refine_passes: 0,
                refine_max_vertices: 80_000,
                reach: true,
                moving_least_squares: false,
            },
            guard: GuardSettings {
                contact: true,
                hold_steps: 3,
                check_every: 16,
                guarded_until_clear: false,
                max_rounds: 8,
                escape_diagonals: 0.5,
                max_area_growth: 1000.0,
                max_vertices: 2_000_000,
            },
            surgery: SurgeryTuning {
                check_every: 4,
                empty_cells: 2.0,
                empty_spacings: 3.0,
                gap_ratio: 0.25,
                tunnel_ratio: 0.0,
                min_vertices: 3,
            },
            solver: SolverSettings {
                tolerance: 1e-10,
                max_iterations: 500,
            },
        }
    }

    /// Every version's values as JSON, keyed by version (the app's link decoder reads them).
    pub fn table_json() -> Value {
        let rows = VERSIONS.iter().filter_map(|&(v, _)| {
            Some((v.to_string(), serde_json::to_value(Tuning::at(v)?).ok()?))
        });
        Value::Object(rows.collect())
    }
}

impl Default for Tuning {
    fn default() -> Self {
        Tuning::at(CURRENT_VERSION).unwrap_or_else(Tuning::version_1)
    }
}

impl<'de> Deserialize<'de> for Tuning {
    /// `version` picks the table's row (the current one when absent); every value given beside
    /// it overrides that row's.
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        use serde::de::Error;
        let given = Value::deserialize(d)?;
        let Value::Object(given) = given else {
            return Err(D::Error::custom("tuning must be an object"));
        };
        let version = match given.get("version") {
            None => CURRENT_VERSION,
            Some(v) => v
                .as_u64()
                .and_then(|v| u32::try_from(v).ok())
                .ok_or_else(|| D::Error::custom("tuning.version must be a whole number"))?,
        };
        let row = Tuning::at(version).ok_or_else(|| {
            D::Error::custom(format!(
                "tuning version {version} is unknown to this build (it knows 1–{CURRENT_VERSION})"
            ))
        })?;
        let mut merged = serde_json::to_value(&row).map_err(D::Error::custom)?;
        for (k, v) in given {
            let Some(slot) = merged.get_mut(&k) else {
                return Err(D::Error::custom(format!("unknown tuning group `{k}`")));
            };
            overlay(slot, v);
        }
        let part = |k: &str| merged.get(k).cloned().unwrap_or(Value::Null);
        let e = D::Error::custom;
        Ok(Tuning {
            version,
            start: serde_json::from_value(part("start")).map_err(e)?,
            field: serde_json::from_value(part("field")).map_err(e)?,
            flow: serde_json::from_value(part("flow")).map_err(e)?,
            remesh: serde_json::from_value(part("remesh")).map_err(e)?,
            fit: serde_json::from_value(part("fit")).map_err(e)?,
            guard: serde_json::from_value(part("guard")).map_err(e)?,
            surgery: serde_json::from_value(part("surgery")).map_err(e)?,
            solver: serde_json::from_value(part("solver")).map_err(e)?,
        })
    }
}

/// Writes `value` over `slot`, object keys one by one (a key `slot` lacks is added, for serde to
/// reject).
fn overlay(slot: &mut Value, value: Value) {
    match (slot, value) {
        (Value::Object(slot), Value::Object(value)) => {
            for (k, v) in value {
                match slot.get_mut(&k) {
                    Some(s) => overlay(s, v),
                    None => {
                        slot.insert(k, v);
                    }
                }
            }
        }
        (slot, value) => *slot = value,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_listed_version_has_a_row_and_the_current_one_is_the_default() {
        for &(v, _) in VERSIONS {
            assert_eq!(Tuning::at(v).map(|t| t.version), Some(v));
        }
        assert_eq!(VERSIONS.last().map(|v| v.0), Some(CURRENT_VERSION));
        assert_eq!(Tuning::default().version, CURRENT_VERSION);
        assert!(Tuning::at(CURRENT_VERSION + 1).is_none() && Tuning::at(0).is_none());
    }

    /// The modules' own defaults are the current row's, so a changed default shows up here (and
    /// belongs in a new version) instead of changing old links' results.
    #[test]
    fn the_current_row_is_the_modules_defaults() {
        let t = Tuning::default();
        assert_eq!(t.guard, GuardSettings::default());
        assert_eq!(t.solver, SolverSettings::default());
        assert_eq!(t.remesh.features, FeatureSettings::default());
        let f = crate::field::FieldSettings::default();
        assert_eq!(
            (f.truncation, f.max_sweep_passes, f.sweep_tolerance),
            (
                t.field.truncation,
                t.field.max_sweep_passes,
                t.field.sweep_tolerance
            )
        );
        assert_eq!(
            (
                f.min_cell_spacings,
                f.outlier_spacings,
                f.principal_slack,
                f.enclosed_cells
            ),
            (
                t.field.min_cell_spacings,
                t.field.outlier_spacings,
                t.field.principal_slack,
                t.field.enclosed_cells
            )
        );
    }

    #[test]
    fn a_version_picks_its_row_and_given_values_override_it() {
        let one: Tuning = serde_json::from_str(r#"{"version": 1}"#).unwrap();
        assert_eq!(one, Tuning::at(1).unwrap());
        let now: Tuning = serde_json::from_str("{}").unwrap();
        assert_eq!(now, Tuning::default());
        let mixed: Tuning =
            serde_json::from_str(r#"{"version": 1, "flow": {"regrow_depth": 1.5}}"#).unwrap();
        assert_eq!(mixed.flow.regrow_depth, 1.5);
        assert_eq!(mixed.surgery.tunnel_ratio, 0.0);
        let round: Tuning = serde_json::from_value(serde_json::to_value(&mixed).unwrap()).unwrap();
        assert_eq!(round, mixed);
        for bad in [
            r#"{"version": 9}"#,
            r#"{"version": "2"}"#,
            r#"{"bogus": {}}"#,
            r#"{"flow": {"bogus": 1}}"#,
        ] {
            assert!(serde_json::from_str::<Tuning>(bad).is_err(), "{bad}");
        }
    }
}
