//! The settings of each stage of a wrap, with the method's names and defaults (docs/method.md
//! §10.1). Lengths are relative to the target: cells of the distance grid, or multiples of the
//! start surface; τ, C1, C2, D1 act in the stabilised frame (docs/method.md §3), which makes them
//! scale-free.

use crate::field::SignMode;
use serde::{Deserialize, Serialize};

/// The starting surface.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum StartSurface {
    /// Chosen per target (see docs/decisions/): the exterior isosurface for targets with a
    /// signed field (closed meshes: it keeps their genus), the icosphere for point clouds and
    /// open meshes (it spans scan holes); the icosphere also where the isosurface start would
    /// leak through gaps and intersect itself (noisy volumes). Settings still at their full-wrap
    /// defaults follow the chosen start's own defaults ([`super::WrapSettings::resolved_for`]).
    Auto,
    /// An icosphere around the target's bounding box (genus 0 results).
    Icosphere,
    /// The boundary of the exterior region `d ≥ d_iso` (marching tetrahedra of the field, flooded
    /// from the grid's border) plus one remesh: keeps the genus of closed targets and never seeds
    /// the inner sheet of an unsigned field.
    Isosurface,
}

/// When the adaptive remesher runs.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum RemeshTrigger {
    /// After every step from `remesh.from_step` on (what the reference does in effect).
    Always,
    /// When some vertex's mean κ(J_Δ) exceeds `tuning.remesh.max_kappa`, or the schedule has changed
    /// the target edge lengths since the last remesh.
    QualityBand,
    /// As `quality_band`, and also every `tuning.remesh.every`-th step, so the curvature sizing follows
    /// the moving surface and no sliver outlives a few steps.
    Auto,
}

/// The distance field's parameters (docs/method.md §2.2); its tuning is [`super::FieldTuning`].
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct FieldParams {
    /// Cells per minimum bounding-box dimension N: the cell size is `c = β_min/N`, β_min the
    /// smallest (non-flat) side of the target's bounding box, or of its principal box where
    /// that is much tighter. Range 2–4096; default 40 (the method's "40 voxels per minimum
    /// dimension").
    pub cells_per_min_dimension: u32,
    /// Volume expansion factor ζ: the box is grown by `ζ·β_min` on every side. Range 0–10;
    /// default 1.0.
    pub expansion: f64,
    /// Width k of the exact near band, in cells: every node within `k·c` of the target gets its
    /// exact distance and is frozen for sweeping. Range 1–16; default 3.
    pub band_cells: f64,
    /// Signing of mesh fields (auto: signed for closed, consistently oriented meshes; or
    /// unsigned); point clouds are always unsigned. Default auto.
    pub sign: SignMode,
    /// Memory cap in bytes for the finished field; a larger grid is refused. Default 1 GiB.
    pub memory_cap_bytes: u64,
}

impl Default for FieldParams {
    fn default() -> Self {
        Self {
            cells_per_min_dimension: 40,
            expansion: 1.0,
            band_cells: 3.0,
            sign: SignMode::Auto,
            memory_cap_bytes: 1 << 30,
        }
    }
}

/// The start surface.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct StartSettings {
    /// Start surface: auto, icosphere or isosurface. Default auto.
    pub surface: StartSurface,
    /// Icosphere subdivision level s (0–7; 0–3 for a wrap, whose edge sizes follow the
    /// icosphere's, see `WrapSettings::check`). Default 2 (162 vertices).
    pub icosphere_level: u32,
    /// Icosphere radius as a multiple of the paper's rule `r = 0.4·(β_min + 1.5·β_max)`
    /// (β = bounding-box sides). Range 0.1–10; default 1.
    pub icosphere_radius_factor: f64,
    /// Isosurface start: d_iso in cells of the distance grid (raised to 1.1·d₀ if below d₀).
    /// Default 1.5.
    pub isosurface_level_cells: f64,
    /// Isosurface start: marching-cubes cell size as a multiple of the field's. Range 0.5–8;
    /// default 1.5.
    pub isosurface_resampling: f64,
}

impl Default for StartSettings {
    fn default() -> Self {
        Self {
            surface: StartSurface::Auto,
            icosphere_level: 2,
            icosphere_radius_factor: 1.0,
            isosurface_level_cells: 1.5,
            isosurface_resampling: 1.5,
        }
    }
}

/// The evolution equation and its schedule.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct FlowSettings {
    /// False: ignore the target (ε ≡ 1, η ≡ 0), i.e. pure MCF. Default true.
    pub use_target: bool,
    /// Initial time step τ (stabilised frame). Range (0, 10]; default 0.07.
    pub tau: f64,
    /// C1: strength of the curvature term ε(δ) = C1·(1 − exp(−δ²/C2)). Range ≥ 0;
    /// default 1.
    pub c1: f64,
    /// C2: width of ε's cut-off near the target (squared stabilised length). Range > 0; default 1.
    pub c2: f64,
    /// D1: strength of the advection η = D1·δ·(cos θ − D2·sin θ). Range ≥ 0; default 2.
    pub d1: f64,
    /// D2: full-wrap push into concavities (0 = obstacle). Range ≥ 0; default 1.
    pub d2: f64,
    /// ω: tangential redistribution weight, ρ = ω·ε. Range 0–1; default 0.05.
    pub tangential_weight: f64,
    /// ε⁺: no curvature motion where δ = d − d₀ < 0. Default true.
    pub mcf_positive_support: bool,
    /// η⁺: no advection where δ < 0. Default true.
    pub advection_positive_support: bool,
    /// d₀ as a multiple of half the voxel diagonal (√3/2·c_G): the surface settles where the
    /// field equals d₀. Range 0–10; default 1.0 (the reference's 2.0 compensates a field that
    /// overestimates distances; this field is exact near the target).
    pub iso_level_factor: f64,
    /// σ: the stabilisation scales the start so its mean co-volume is τ/σ. Range (0, 10];
    /// default 0.2.
    pub shrink_factor: f64,
    /// Steps after which sizes shrink by λ_dec, τ by λ_dec² and D1 grows by 1/λ_dec.
    /// Default [3, 10, 20, 50, 100, 120, 140, 145].
    pub schedule: Vec<u32>,
    /// λ_dec, the schedule's decay factor. Range (0, 1]; default 0.7.
    pub decay: f64,
}

impl Default for FlowSettings {
    fn default() -> Self {
        Self {
            use_target: true,
            tau: 0.07,
            c1: 1.0,
            c2: 1.0,
            d1: 2.0,
            d2: 1.0,
            tangential_weight: 0.05,
            mcf_positive_support: true,
            advection_positive_support: true,
            iso_level_factor: 1.0,
            shrink_factor: 0.2,
            schedule: vec![3, 10, 20, 50, 100, 120, 140, 145],
            decay: 0.7,
        }
    }
}

/// When and how the evolution remeshes (one remesh call's own parameters are
/// [`crate::remesh::RemeshSettings`], derived from these and the current sizes).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct RemeshingSettings {
    /// Adaptive remeshing on. Default true.
    pub enabled: bool,
    /// First step after which remeshing may run. Default 4 (the fresh icosphere needs none).
    pub from_step: u32,
    /// When to remesh: always, quality_band or auto. Default auto: the quality band, the
    /// schedule's size changes and every `tuning.remesh.every`-th step, which remeshes less often than
    /// `always` for the same accuracy; the quality band alone can let a wrap diverge (see
    /// docs/decisions/).
    pub trigger: RemeshTrigger,
    /// λ_min: l_min as a fraction of the start surface's edge (icosphere) or of √2·c (isosurface).
    /// Range (0, 10]; default 0.14.
    pub min_edge_multiplier: f64,
    /// Remeshing outer iterations per call. Default 2.
    pub iterations: u32,
    /// Tangential smoothing passes per remeshing iteration. Default 5.
    pub smoothing_iterations: u32,
}

impl Default for RemeshingSettings {
    fn default() -> Self {
        Self {
            enabled: true,
            from_step: 4,
            trigger: RemeshTrigger::Auto,
            min_edge_multiplier: 0.14,
            iterations: 2,
            smoothing_iterations: 5,
        }
    }
}

/// The final fit: when the evolution ends, the surface moves from the offset level set d = d₀
/// onto the target along the normals (plane fits to the cloud, or closest points on a mesh).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct FitSettings {
    /// Final fit on. Default true.
    pub enabled: bool,
    /// Neighbourhood radius of the plane fit, in cells. Default 2.
    pub radius_cells: f64,
    /// Longest move of a vertex, in cells (longer moves, e.g. across a hole in the scan, are
    /// refused). Default 2.5.
    pub max_move_cells: f64,
    /// Passes (normals are recomputed between passes). Default 2.
    pub passes: u32,
    /// Sharp creases of the target: edges whose faces turn by more than this many degrees
    /// are kept sharp — the fit puts wrap vertices on the target's corners and crease lines and
    /// aligns wrap edges with them (see `flow::fit::crease_fit`). A mesh's creases come from its
    /// dihedral angles, a cloud's from plane fits around its points (lines at least 4 fit radii
    /// long, `geometry::cloud_creases`). 0 turns it off. Range 0–180; default 40.
    pub crease_angle_deg: f64,
}

impl Default for FitSettings {
    fn default() -> Self {
        Self {
            enabled: true,
            radius_cells: 2.0,
            max_move_cells: 2.5,
            passes: 2,
            crease_angle_deg: 40.0,
        }
    }
}

/// Topology surgery (see [`crate::flow::surgery`]): two membranes that meet far from the data
/// (across the hole of a handle) are cut and joined by a tube, so handles open.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct SurgerySettings {
    /// Surgery on. Default true.
    pub enabled: bool,
    /// Close gaps up to this fraction of the target's bounding-box diagonal: a handle whose hole
    /// is narrower stays closed (the app's "Close gaps up to" control). 0 leaves it to the
    /// sampling and the grid (`tuning.surgery.empty_cells`, `empty_spacings`); 1 keeps every handle closed.
    /// Range 0–1; default 0.
    pub close_gaps: f64,
}

impl Default for SurgerySettings {
    fn default() -> Self {
        Self {
            enabled: true,
            close_gaps: 0.0,
        }
    }
}

/// When the evolution ends.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct StopSettings {
    /// Step limit N_t. Range 0–100000; default 146 (the reference's step count).
    pub steps: u32,
    /// Stop early when this fraction of vertices moved less than `displacement_cells` in the
    /// last step (only after the last schedule step). Range (0, 1]; default 0.98.
    pub fraction: f64,
    /// Stop threshold on per-step displacement, in cells of the distance grid. Default 0.002
    /// (the approach to d₀ is exponential at a few per cent per step, so this leaves ≈ 0.05
    /// cells).
    pub displacement_cells: f64,
}

impl Default for StopSettings {
    fn default() -> Self {
        Self {
            steps: 146,
            fraction: 0.98,
            displacement_cells: 0.002,
        }
    }
}
