//! Adaptive isotropic remeshing after Dunyach et al. 2013 as implemented by PMP's
//! `Remeshing::adaptive_remeshing` (docs/method.md §7.3): split long edges, collapse short ones,
//! equalise valences by flips, smooth tangentially, remove caps — with a curvature-adaptive
//! sizing field and locked / sliding feature vertices.
//!
//! Differences from the reference, all deliberate:
//! * collapses and flips also reject geometric fold-overs (a remaining face turning by more than
//!   60°, or a degenerate face), so `validate()` holds after every call;
//! * vertex normals for the smoothing are area-weighted (cheaper than angle-weighted and only used
//!   to remove the normal component of a tangential update);
//! * features are re-detected on every call (see [`super::features`]), never accumulated;
//! * caps on feature edges are left alone instead of moving the cap vertex.
//!
//! The mesh must be garbage-free on entry and is garbage-free on exit. Boundary vertices are
//! locked and boundary edges never edited (LSW surfaces are closed).
//!
//! The phases live in their own files: `driver` (the call), `split`, `collapse`, `flip` (with
//! the cap removal) and `smooth` (tangential smoothing and back-projection).

// `!(x > y)` is used deliberately: it is also true when x is NaN.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

mod collapse;
mod driver;
mod flip;
mod smooth;
mod split;

pub(super) use flip::flip_geometry_ok;

use super::features::{FeatureSettings, Features};
use super::sizing::EdgeSizes;
use crate::geometry::spatial::bvh::TriangleBvh;
use crate::mesh::HalfedgeMesh;
use driver::remesh_impl;
use glam::DVec3;
use serde::{Deserialize, Serialize};

/// Sweeps per phase (split / collapse / flip) before giving up on convergence (PMP: 10).
const MAX_SWEEPS: usize = 10;
/// Splits always allowed under [`RemeshSettings::max_splits_per_vertex`], whatever the size
/// of the input (a coarse start refines many times over).
pub const SPLIT_ALLOWANCE: usize = 10_000;

/// Settings of one adaptive remeshing call. Lengths are in mesh units (the flow works in its
/// stabilised frame, so it passes the scaled lengths).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default)]
pub struct RemeshSettings {
    /// Shortest target edge length l_min (> 0). Default 0.01.
    pub min_edge_length: f64,
    /// Longest target edge length l_max (≥ l_min). Default 0.04 (= 4·l_min, the reference's ratio).
    pub max_edge_length: f64,
    /// Approximation error ε_rem (> 0): edges are sized so that their chords deviate about this
    /// much from a sphere of the local curvature radius. Default 0.0125 (= 0.25·(l_min + l_max)).
    pub approx_error: f64,
    /// Outer iterations (split, collapse, flip, smooth), `NRemeshingIters`. Default 2.
    pub iterations: u32,
    /// Tangential smoothing passes per outer iteration, `NTanSmoothingIters`. Default 5.
    pub smoothing_iterations: u32,
    /// Settling tolerance of the smoothing, as a fraction of the local target edge length h:
    /// a vertex is recomputed only while it or a neighbour moved by more than `tol·h` in the
    /// previous pass, and an outer iteration that changes nothing (no edit, no move above the
    /// tolerance) ends the call. 0 runs every pass on every vertex (the reference). Range
    /// [0, 0.1]; default 0.01 (a move that small barely changes κ).
    pub smoothing_tolerance: f64,
    /// Project moved and new vertices back onto the surface as it was when the call started
    /// (`UseBackProjection`). Default false (the reference's evolution runs; true only for the
    /// initial marching-cubes remesh).
    pub use_projection: bool,
    /// Cap removal: flip an edge whose larger opposite angle exceeds this many degrees.
    /// Default 170.
    pub cap_angle_deg: f64,
    /// Feature detection, redone on every call. Default: off.
    pub features: FeatureSettings,
    /// Splits insert the midpoint of the curve through the edge's ends along their normals
    /// ([`curved_midpoint`]) instead of the chord's (the reference's). Without projection the
    /// chord midpoints of a convex rim lie inside the surface, where the flow's positive support
    /// never pushes them back: corners and sharp edges would be shaved a little at every
    /// remesh. Ignored with `use_projection` (the projection places the vertex).
    /// A mesh with the vertex layer [`CURVED_SPLITS_LAYER`] gets them only on edges whose ends
    /// both have a value above ½ there. Default true.
    pub curved_splits: bool,
    /// After a call that split or collapsed more than 5 % of the vertices, renumber the mesh in
    /// spatial order ([`HalfedgeMesh::reorder_spatially`]) so neighbours stay close in memory —
    /// splits append vertices, and after many remeshes neighbouring indices lie thousands apart.
    /// Default true.
    pub reorder: bool,
    /// Most splits per vertex of the input (plus [`SPLIT_ALLOWANCE`]) before the call gives up
    /// with [`RemeshError::Runaway`]. None: no limit (default). The final fit sets it: a fit
    /// over too few points can crumple the wrap, and its remeshes would then churn through
    /// millions of splits and nearly as many collapses, only to be undone for intersecting.
    pub max_splits_per_vertex: Option<f64>,
}

/// The vertex layer that limits [`RemeshSettings::curved_splits`] to part of a mesh (1 = curved,
/// 0 = chord). The flow keeps chord midpoints away from the target: there the surface is still
/// shrinking, and curved ones would hold membranes over a handle's hole apart (no surgery,
/// genus lost).
pub const CURVED_SPLITS_LAYER: &str = "curved_splits";

impl Default for RemeshSettings {
    fn default() -> Self {
        Self {
            min_edge_length: 0.01,
            max_edge_length: 0.04,
            approx_error: 0.0125,
            iterations: 2,
            smoothing_iterations: 5,
            smoothing_tolerance: 0.01,
            use_projection: false,
            cap_angle_deg: 170.0,
            features: FeatureSettings::default(),
            curved_splits: true,
            reorder: true,
            max_splits_per_vertex: None,
        }
    }
}

impl RemeshSettings {
    /// Settings with the given sizes and every other field at its default.
    pub fn with_sizes(sizes: EdgeSizes) -> Self {
        Self {
            min_edge_length: sizes.min_edge_length,
            max_edge_length: sizes.max_edge_length,
            approx_error: sizes.approx_error,
            ..Default::default()
        }
    }
    /// The three sizes of these settings.
    pub fn sizes(&self) -> EdgeSizes {
        EdgeSizes {
            min_edge_length: self.min_edge_length,
            max_edge_length: self.max_edge_length,
            approx_error: self.approx_error,
        }
    }
}

/// Why a remesh call refused to run or gave up. The mesh is untouched except after
/// [`RemeshError::Runaway`].
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum RemeshError {
    /// A length is not positive and finite, or `l_min > l_max`. Fix: pass sizes from
    /// [`super::sizing`] or positive lengths with `min_edge_length ≤ max_edge_length`.
    #[error("invalid remesh sizes: l_min = {min}, l_max = {max}, ε_rem = {eps}")]
    InvalidSizes { min: f64, max: f64, eps: f64 },
    /// The mesh has no faces.
    #[error("cannot remesh a mesh without faces")]
    Empty,
    /// The splits passed [`RemeshSettings::max_splits_per_vertex`]. Unlike the other errors,
    /// this one leaves the mesh part-way edited (still a valid mesh): the caller restores its
    /// copy.
    #[error("remesh gave up after {splits} splits of a {vertices}-vertex mesh")]
    Runaway { splits: usize, vertices: usize },
}

/// What one remesh call did.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[cfg_attr(target_arch = "wasm32", derive(tsify::Tsify))]
pub struct RemeshReport {
    /// Vertex count before.
    pub vertices_before: usize,
    /// Vertex count after.
    pub vertices_after: usize,
    /// Edge splits.
    pub splits: usize,
    /// Edge collapses.
    pub collapses: usize,
    /// Valence-improving flips.
    pub flips: usize,
    /// Cap-removing flips.
    pub caps_removed: usize,
    /// Feature vertices detected at the start.
    pub feature_vertices: usize,
    /// Feature edges detected at the start.
    pub feature_edges: usize,
    /// Locked vertices at the start (features not on exactly two feature edges, boundary).
    pub locked_vertices: usize,
    /// True when the mesh was renumbered in spatial order at the end (see `reorder`).
    pub reordered: bool,
    /// Wall-clock time per phase.
    pub time_ms: RemeshTimings,
}

/// Milliseconds spent per phase of one remesh call (summed over the outer iterations).
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[cfg_attr(target_arch = "wasm32", derive(tsify::Tsify))]
pub struct RemeshTimings {
    /// Curvatures, features, locks and the sizing field.
    pub sizing: f64,
    /// Edge splits.
    pub split: f64,
    /// Edge collapses and garbage collection.
    pub collapse: f64,
    /// Valence flips.
    pub flip: f64,
    /// Tangential smoothing (and projection).
    pub smooth: f64,
    /// Cap removal, the final compaction and the spatial renumbering.
    pub caps: f64,
    /// The whole call.
    pub total: f64,
}

/// Remeshes `mesh` in place (features detected per `settings.features`).
/// Per-vertex scalar layers follow the edits (see `mesh::edit`).
pub fn remesh(
    mesh: &mut HalfedgeMesh,
    settings: &RemeshSettings,
) -> Result<RemeshReport, RemeshError> {
    remesh_impl(mesh, settings, None, None)
}

/// Remeshes with caller-supplied features (indexed like `mesh`); `settings.features` is ignored.
pub fn remesh_with_features(
    mesh: &mut HalfedgeMesh,
    settings: &RemeshSettings,
    features: &Features,
) -> Result<RemeshReport, RemeshError> {
    remesh_impl(mesh, settings, Some(features), None)
}

/// Remeshes with caller-supplied features (or those of `settings.features` when None) and a
/// per-vertex cap on the target edge length (indexed like `mesh`): the sizing field is the
/// smaller of the curvature sizing and the cap, so a caller that knows where the surface misses
/// its target (see `flow::fit::error_sizing`) can ask for shorter edges there.
pub fn remesh_capped(
    mesh: &mut HalfedgeMesh,
    settings: &RemeshSettings,
    features: Option<&Features>,
    caps: &[f64],
) -> Result<RemeshReport, RemeshError> {
    remesh_impl(mesh, settings, features, Some(caps))
}

/// The surface at the start of the call, for back-projection.
struct Reference {
    sizing: Vec<f64>,
    bvh: TriangleBvh,
}

impl Reference {
    /// Closest point on the reference and the barycentric sizing there.
    fn project(&self, p: DVec3) -> (DVec3, f64) {
        match self.bvh.closest_point(p) {
            Some(hit) => {
                let t = self.bvh.triangles()[hit.triangle as usize];
                let h = hit.barycentric.x * self.sizing[t[0] as usize]
                    + hit.barycentric.y * self.sizing[t[1] as usize]
                    + hit.barycentric.z * self.sizing[t[2] as usize];
                (hit.point, h)
            }
            None => (p, f64::NAN),
        }
    }
}

/// Working state: per-vertex and per-edge arrays kept in step with the mesh's edits.
struct Work<'a> {
    s: &'a RemeshSettings,
    /// Target edge length per vertex.
    h: Vec<f64>,
    locked: Vec<bool>,
    /// Vertices whose edges are not edited either (see [`Features::frozen`]).
    frozen: Vec<bool>,
    vfeat: Vec<bool>,
    efeat: Vec<bool>,
    upd: Vec<DVec3>,
    /// Smoothing work lists: vertices to recompute this pass / that moved in it.
    active: Vec<bool>,
    moved: Vec<bool>,
    /// One-rings as CSR (see `build_rings`), rebuilt per smoothing phase.
    ring_off: Vec<u32>,
    ring: Vec<u32>,
    /// Sweep work lists: vertices whose neighbourhood changed in the previous / current sweep.
    dirty: Vec<bool>,
    dirty_next: Vec<bool>,
    valence: Vec<i32>,
    min_area: f64,
    reference: Option<Reference>,
    /// Splits after which the call gives up (see [`RemeshSettings::max_splits_per_vertex`]).
    split_limit: usize,
    report: RemeshReport,
}

/// The two end vertices of edge `e`.
#[inline]
fn ends(mesh: &HalfedgeMesh, e: u32) -> (u32, u32) {
    (mesh.to(2 * e + 1), mesh.to(2 * e))
}

/// Resets the sweep work lists: every vertex dirty for the first sweep.
fn start_sweeps(w: &mut Work, nv: usize) {
    w.dirty.clear();
    w.dirty.resize(nv, true);
    w.dirty_next.clear();
    w.dirty_next.resize(nv, false);
}

/// Ends a sweep: the vertices touched in it become the next sweep's work list.
fn next_sweep(w: &mut Work) {
    std::mem::swap(&mut w.dirty, &mut w.dirty_next);
    w.dirty_next.iter_mut().for_each(|d| *d = false);
}
