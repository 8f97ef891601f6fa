//! The settings of each stage of a wrap, with the method's names and defaults (docs/method.md
//! §10.1). Lengths are relative to the target: cells of the distance grid, or multiples of the
//! start surface; τ, C1, C2, D1 act in the stabilised frame (docs/method.md §3), which makes them
//! scale-free.

use crate::remesh::features::FeatureSettings;
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
    /// When some vertex's mean κ(J_Δ) exceeds `remesh.max_kappa`, or the schedule has changed
    /// the target edge lengths since the last remesh.
    QualityBand,
    /// As `quality_band`, and also every `remesh.every`-th step, so the curvature sizing follows
    /// the moving surface and no sliver outlives a few steps.
    Auto,
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
    /// Icosphere start on a point cloud: parts lying apart (no cell of this share of the
    /// target's diagonal links them) start from a sphere each (see `flow::start`). 0: one
    /// sphere around all, as the method has it (share links without this key decode to 0).
    /// Range 0–1; default 0.05.
    pub part_gap: f64,
}

impl Default for StartSettings {
    fn default() -> Self {
        Self {
            surface: StartSurface::Auto,
            icosphere_level: 2,
            icosphere_radius_factor: 1.0,
            isosurface_level_cells: 1.5,
            isosurface_resampling: 1.5,
            part_gap: 0.05,
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
    /// A wrap that leaves part of its target outside starts over once with D₂ =
    /// `second_pass_d2`, and on a point cloud with d₀ grown to the sampling's gap spacing (the
    /// 99th percentile of the nearest-point distances) where that is larger, at most this many
    /// times the value above; the pass that leaves fewer points outside is kept. At a sparse
    /// cloud's usual d₀ (1.7 median spacings) a tenth of a randomly sampled surface lies farther
    /// than d₀ from every point, and round the rim of an open single-layer scan the wrap slips
    /// through those gaps (`flow/evolver/second_pass.rs`). Not for volumes. 1 turns the second
    /// pass off. Range 1–4; default 1.5.
    pub cover_gaps: f64,
    /// D₂ of that second pass: 0, the obstacle setting, does not push harder where the normal
    /// lies across the gradient, which on open single-layer sheets drives the coarse early
    /// wrap's edge past the sheet's rim (see docs/decisions/). Range ≥ 0; default 0.
    pub second_pass_d2: f64,
    /// Once the surgery has operated, where the surface lies farther from the data than this
    /// many times the surgery's empty distance (`surgery.empty_cells`, `surgery.empty_spacings`)
    /// and the data lies in front of it (cos θ > 0: the distance falls along its outward normal),
    /// its advection is mirrored, so that it moves away from the data, inwards, instead of
    /// towards it. Such a surface is a bubble of the wrap's inside: where the membranes of
    /// several holes meet (crossing bores, a frame of bars), what is left between the tubes
    /// hangs in empty space, inflated towards the walls by the advection and held back by the
    /// curvature flow, and keeps holes closed. A tube that must widen to its hole's wall has the
    /// wall behind it. Before any cut it is off: a surface far from the data that faces it has
    /// then slipped through a gap in a sparsely sampled wall, and deflating would drive it on
    /// into the inside. 0 turns this off (share links without this key decode to 0).
    /// Range 0–100; default 1 (see docs/decisions/).
    pub deflate_far: f64,
    /// σ: the stabilisation scales the start so its mean co-volume is τ/σ. Range (0, 10];
    /// default 0.2.
    pub shrink_factor: f64,
    /// Steps after which sizes shrink by λ_dec, τ by λ_dec² and D1 grows by 1/λ_dec.
    /// Default [3, 10, 20, 50, 100, 120, 140, 145].
    pub schedule: Vec<u32>,
    /// λ_dec, the schedule's decay factor. Range (0, 1]; default 0.7.
    pub decay: f64,
    /// Times a failed solve is retried before giving up: first at the same τ with negative
    /// cotangent weights clamped at zero, then with τ halved each time. Default 4.
    pub max_retries: u32,
    /// A vertex inside the offset surface whose offset level lies farther than this many d₀
    /// along its normal sits on a chord through a thin part of the target and moves out to
    /// that level ([`crate::flow::regrow`]); a vertex that settled just inside finds it within
    /// a fraction of d₀. 0 turns this off. Range 0–100; default 1.5 (deep enough that a wrap
    /// with no thin parts is left unchanged).
    pub regrow_depth: f64,
    /// How far along its normal such a vertex looks for the offset level, in grid cells.
    /// Range 0–1000; default 16.
    pub regrow_cells: f64,
    /// The most such a vertex moves in one step, in its mean edge lengths (longer moves grow
    /// spikes that the remesh splits without end). Range 0–100; default 2.
    pub regrow_edges: f64,
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
            cover_gaps: 1.5,
            second_pass_d2: 0.0,
            deflate_far: 1.0,
            shrink_factor: 0.2,
            schedule: vec![3, 10, 20, 50, 100, 120, 140, 145],
            decay: 0.7,
            max_retries: 4,
            regrow_depth: 1.5,
            regrow_cells: 16.0,
            regrow_edges: 2.0,
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
    /// schedule's size changes and every `every`-th step, which remeshes less often than
    /// `always` for the same accuracy; the quality band alone can let a wrap diverge (see
    /// docs/decisions/).
    pub trigger: RemeshTrigger,
    /// With trigger auto: remesh at least every this many steps. Range 1–1000;
    /// default 4.
    pub every: u32,
    /// Vertex-averaged κ(J_Δ) (equilateral = 1) above which [`RemeshTrigger::QualityBand`]
    /// remeshes. Default 1.5.
    pub max_kappa: f64,
    /// λ_min: l_min as a fraction of the start surface's edge (icosphere) or of √2·c (isosurface).
    /// Range (0, 10]; default 0.14.
    pub min_edge_multiplier: f64,
    /// Remeshing outer iterations per call. Default 2.
    pub iterations: u32,
    /// Tangential smoothing passes per remeshing iteration. Default 5.
    pub smoothing_iterations: u32,
    /// Feature detection in the remesher (re-detected each call). Default off.
    pub features: FeatureSettings,
    /// Splits put the new vertex on the curve through the edge's ends along their normals, not
    /// on the chord (the reference), which lies inside a convex rim and rounds corners and
    /// crease lines off. Default true.
    pub curved_splits: bool,
}

impl Default for RemeshingSettings {
    fn default() -> Self {
        Self {
            enabled: true,
            from_step: 4,
            trigger: RemeshTrigger::Auto,
            every: 4,
            max_kappa: 1.5,
            min_edge_multiplier: 0.14,
            iterations: 2,
            smoothing_iterations: 5,
            features: FeatureSettings::default(),
            curved_splits: true,
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
    /// Most cloud points a vertex's plane is fitted to: the nearest within `radius_cells`. Keeps
    /// the fit's cost per vertex bounded on dense scans, where the radius holds thousands of
    /// points. Range ≥ 6; default 64: only dense clouds reach it, and there more points cost
    /// time without bringing the fit measurably closer (see docs/decisions/).
    pub max_points: usize,
    /// Sharp creases of the target: edges whose faces turn by more than this many degrees
    /// are kept sharp — the fit puts wrap vertices on the target's corners and crease lines and
    /// aligns wrap edges with them (see `flow::fit::crease_fit`). A mesh's creases come from its
    /// dihedral angles, a cloud's from plane fits around its points (lines at least 4 fit radii
    /// long, `geometry::cloud_creases`). 0 turns it off. Range 0–180; default 40.
    pub crease_angle_deg: f64,
    /// Error-adaptive sizing of a mesh target's fit: where a target vertex still lies farther
    /// than this many cells from the wrap after a pass (a bridged eye socket, mouth or fin
    /// root), the nearest wrap face's edges are halved, down to the finest edge the settings
    /// allow, and the fit takes another pass (see `flow::fit::error_sizing`). 0 turns it off; clouds
    /// have none. Range ≥ 0; default 0.25.
    pub refine_error_cells: f64,
    /// Most extra passes the error-adaptive sizing may add after `passes` (each halves the
    /// edges that still miss). Range 0–10; default 5 (enough to line narrow slits; shapes that
    /// stop missing stop earlier), 0 on a volume's iso-surface (see
    /// [`super::VOLUME_REFINE_PASSES`]).
    pub refine_passes: u32,
    /// The error-adaptive sizing's vertex budget: a pass whose new caps could take the wrap
    /// past this many vertices (four per capped vertex) adds none. (The remesh of each pass
    /// refines beside the creases it sharpened, caps or not: a wrap that starts its fit near
    /// the budget may end a few per cent above it.) Range ≥ 100; default 80 000.
    pub refine_max_vertices: usize,
    /// Reaching into concavities on mesh targets (with the error-adaptive sizing): after a
    /// pass, the wrap vertex nearest to a target vertex still missed moves onto it when the
    /// way there is clear of the target — a slit narrower than a grid cell (a mouth,
    /// the gap under an ear) is lined instead of bridged (see `flow::fit::reach`). Default true.
    pub reach: bool,
}

impl Default for FitSettings {
    fn default() -> Self {
        Self {
            enabled: true,
            radius_cells: 2.0,
            max_move_cells: 2.5,
            passes: 2,
            max_points: 64,
            crease_angle_deg: 40.0,
            refine_error_cells: 0.25,
            refine_passes: 5,
            refine_max_vertices: 80_000,
            reach: true,
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
    /// Sheets are looked for every this many steps. Range ≥ 1; default 4.
    pub check_every: u32,
    /// Empty space: farther from the target than this many cells of the distance grid (and than
    /// `empty_spacings`). Holes narrower than about twice this stay closed. Range ≥ 0; default 2
    /// (the surface rests under a cell off the data; larger values keep the holes of sparse
    /// samplings closed, see docs/decisions/).
    pub empty_cells: f64,
    /// Empty space on a point cloud: also farther than this many median point spacings (gaps
    /// in a random sampling reach about three). Range ≥ 0; default 3.
    pub empty_spacings: f64,
    /// Two facing sheets meet when their gap is below this fraction of their distance to the
    /// target. Range (0, 1]; default 0.25.
    pub gap_ratio: f64,
    /// Through-holes at least as deep as they are wide: two facing sheets far from the data also
    /// meet when their gap is below this multiple of their distance to the target and the path
    /// between them is ringed by data (the membranes over a tunnel's two ends feel no pull
    /// towards each other, see [`crate::flow::surgery::detect`]). 0: off (share links without
    /// this key decode to 0). Range ≥ 0; default 4 (a round hole 2 radii deep has a gap ratio
    /// ≈ 2.5).
    pub tunnel_ratio: f64,
    /// Smallest patch (vertices) that is cut. Range ≥ 3; default 3: a membrane across a hole
    /// only a few edges wide has few vertices far from the data, and a larger minimum keeps
    /// such holes closed (see docs/decisions/).
    pub min_vertices: usize,
    /// Close gaps up to this fraction of the target's bounding-box diagonal: a handle whose hole
    /// is narrower stays closed (the app's "Close gaps up to" control). 0 leaves it to the
    /// sampling and the grid (`empty_cells`, `empty_spacings`); 1 keeps every handle closed.
    /// Range 0–1; default 0.
    pub close_gaps: f64,
}

impl Default for SurgerySettings {
    fn default() -> Self {
        Self {
            enabled: true,
            check_every: 4,
            empty_cells: 2.0,
            empty_spacings: 3.0,
            gap_ratio: 0.25,
            tunnel_ratio: 4.0,
            min_vertices: 3,
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
