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

// `!(x > y)` is used deliberately: it is also true when x is NaN.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

use super::features::{detect_features, FeatureDetector, FeatureSettings, Features};
use super::sizing::{curvature_sizing, EdgeSizes};
use crate::clock::now_ms;
use crate::geometry::curved_midpoint::curved_midpoint;
use crate::geometry::operators::curvature::principal_curvatures;
use crate::geometry::operators::normals::area_weighted_normal;
use crate::geometry::spatial::bvh::TriangleBvh;
use crate::mesh::{HalfedgeMesh, INVALID};
use glam::{DMat3, DVec3};
use serde::{Deserialize, Serialize};

/// Sweeps per phase (split / collapse / flip) before giving up on convergence (PMP: 10).
const MAX_SWEEPS: usize = 10;
/// Splits always allowed under [`RemeshSettings::max_splits_per_vertex`], whatever the size
/// of the input (a coarse start refines many times over).
pub const SPLIT_ALLOWANCE: usize = 10_000;
/// A collapse may turn a remaining face's normal by at most 60° (cos 60° = 0.5).
const COLLAPSE_MIN_COS: f64 = 0.5;

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
    /// [0, 0.1]; default 0.01 (moves below 1 % of an edge change κ by well under 1 %).
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
/// its target (see `flow::error_sizing`) can ask for shorter edges there.
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

fn remesh_impl(
    mesh: &mut HalfedgeMesh,
    s: &RemeshSettings,
    given: Option<&Features>,
    caps: Option<&[f64]>,
) -> Result<RemeshReport, RemeshError> {
    let (lmin, lmax, eps) = (s.min_edge_length, s.max_edge_length, s.approx_error);
    let ok = |x: f64| x > 0.0 && x.is_finite();
    if !(ok(lmin) && ok(lmax) && ok(eps) && lmin <= lmax) {
        return Err(RemeshError::InvalidSizes {
            min: lmin,
            max: lmax,
            eps,
        });
    }
    let t_start = now_ms();
    mesh.garbage_collect();
    if mesh.n_faces() == 0 {
        return Err(RemeshError::Empty);
    }
    let nv = mesh.n_vertices();
    let mut report = RemeshReport {
        vertices_before: nv,
        ..Default::default()
    };

    // Features and locks.
    let features = match given {
        Some(f) => f.clone(),
        None if s.features.detector == FeatureDetector::Off => Features::none(mesh),
        None => detect_features(mesh, &principal_curvatures(mesh, None, 1), &s.features),
    };
    let mut locked = vec![false; nv];
    for v in 0..nv as u32 {
        let boundary = mesh.outgoing(v).any(|h| mesh.is_boundary_halfedge(h));
        let nfe = mesh
            .outgoing(v)
            .filter(|&h| features.edges[(h >> 1) as usize])
            .count();
        let pinned = features.pinned.get(v as usize).copied().unwrap_or(false);
        let frozen = features.frozen.get(v as usize).copied().unwrap_or(false);
        locked[v as usize] =
            boundary || pinned || frozen || (features.vertices[v as usize] && nfe != 2);
    }
    report.feature_vertices = features.n_vertices();
    report.feature_edges = features.n_edges();
    report.locked_vertices = locked.iter().filter(|&&b| b).count();

    // Sizing: curvatures with one smoothing pass that skips features; beside it, the tree of
    // the surface as it is for the back-projection (independent work, a seventh of the call).
    let fixed: Vec<bool> = (0..nv).map(|v| locked[v] || features.vertices[v]).collect();
    let (bvh, mut h) = crate::parallel::beside(
        || {
            s.use_projection
                .then(|| TriangleBvh::new(mesh.positions(), &mesh.triangles()))
        },
        || {
            let curv = principal_curvatures(mesh, Some(&fixed), 1);
            curvature_sizing(mesh, &curv, &s.sizes(), &fixed)
        },
    );
    if let Some(caps) = caps {
        for (h, &c) in h.iter_mut().zip(caps) {
            *h = h.min(c);
        }
    }

    let reference = bvh.map(|bvh| Reference {
        sizing: h.clone(),
        bvh,
    });

    let mut w = Work {
        s,
        h,
        locked,
        frozen: {
            let mut f = features.frozen.clone();
            f.resize(nv, false);
            f
        },
        vfeat: features.vertices,
        efeat: features.edges,
        upd: Vec::new(),
        active: Vec::new(),
        moved: Vec::new(),
        ring_off: Vec::new(),
        ring: Vec::new(),
        dirty: Vec::new(),
        dirty_next: Vec::new(),
        valence: Vec::new(),
        min_area: 1e-8 * lmin * lmin,
        reference,
        split_limit: s.max_splits_per_vertex.map_or(usize::MAX, |k| {
            (k.max(0.0) * nv as f64).min(1e15) as usize + SPLIT_ALLOWANCE
        }),
        report,
    };

    let mut t = now_ms();
    w.report.time_ms.sizing = t - t_start;
    let mut lap = |acc: &mut f64| {
        let now = now_ms();
        *acc += now - t;
        t = now;
    };
    for _ in 0..s.iterations {
        let edits = w.report.splits + w.report.collapses + w.report.flips;
        if !split_long_edges(mesh, &mut w) {
            return Err(RemeshError::Runaway {
                splits: w.report.splits,
                vertices: nv,
            });
        }
        lap(&mut w.report.time_ms.split);
        collapse_short_edges(mesh, &mut w);
        lap(&mut w.report.time_ms.collapse);
        flip_edges(mesh, &mut w);
        lap(&mut w.report.time_ms.flip);
        let at_rest = tangential_smoothing(mesh, &mut w);
        lap(&mut w.report.time_ms.smooth);
        if at_rest && edits == w.report.splits + w.report.collapses + w.report.flips {
            break; // Nothing changed: further iterations would repeat this one.
        }
    }
    remove_caps(mesh, &mut w);
    mesh.garbage_collect();
    if s.reorder && (w.report.splits + w.report.collapses) * 20 > nv {
        mesh.reorder_spatially();
        w.report.reordered = true;
    }
    lap(&mut w.report.time_ms.caps);
    w.report.time_ms.total = now_ms() - t_start;
    w.report.vertices_after = mesh.n_vertices();
    Ok(w.report)
}

#[inline]
fn ends(mesh: &HalfedgeMesh, e: u32) -> (u32, u32) {
    (mesh.to(2 * e + 1), mesh.to(2 * e))
}

/// Splits the edges longer than 4/3 of their target length; false when the splits passed
/// `w.split_limit` (the mesh is then part-way split).
fn split_long_edges(mesh: &mut HalfedgeMesh, w: &mut Work) -> bool {
    for _ in 0..MAX_SWEEPS {
        let mut any = false;
        let ne = mesh.n_edges() as u32;
        for e in 0..ne {
            if mesh.is_deleted_edge(e) || !mesh.is_interior_edge(e) {
                continue;
            }
            let (a, b) = ends(mesh, e);
            if w.frozen[a as usize] || w.frozen[b as usize] {
                continue;
            }
            let (pa, pb) = (mesh.position(a), mesh.position(b));
            let hmax = 4.0 / 3.0 * w.h[a as usize].min(w.h[b as usize]);
            if (pb - pa).length_squared() <= hmax * hmax {
                continue;
            }
            let feature = w.efeat[e as usize];
            let curved = w.s.curved_splits && !feature && w.reference.is_none() && {
                let layer = mesh.vertex_scalars(CURVED_SPLITS_LAYER);
                layer.is_none_or(|l| l[a as usize] > 0.5 && l[b as usize] > 0.5)
            };
            let mut p = if curved {
                let (na, nb) = (area_weighted_normal(mesh, a), area_weighted_normal(mesh, b));
                curved_midpoint(pa, na, pb, nb)
            } else {
                0.5 * (pa + pb)
            };
            let mut hm = 0.5 * (w.h[a as usize] + w.h[b as usize]);
            if !feature {
                if let Some(r) = &w.reference {
                    let (q, hq) = r.project(p);
                    p = q;
                    if hq.is_finite() {
                        hm = hq;
                    }
                }
            }
            mesh.split_edge(e, p);
            w.h.push(hm);
            w.locked.push(false);
            w.frozen.push(false);
            w.vfeat.push(feature);
            w.efeat.extend([feature, false, false]);
            w.report.splits += 1;
            if w.report.splits > w.split_limit {
                return false;
            }
            any = true;
        }
        if !any {
            break;
        }
    }
    true
}

/// May the feature vertex `from(h)` be collapsed into `to(h)`? Only along a feature edge between
/// two feature vertices, and only if none of the four edges that merge is a feature.
fn feature_collapse_ok(mesh: &HalfedgeMesh, w: &Work, h: u32) -> bool {
    let o = h ^ 1;
    let fe = |x: u32| w.efeat[(x >> 1) as usize];
    w.vfeat[mesh.to(h) as usize]
        && fe(h)
        && !fe(mesh.next(h))
        && !fe(mesh.prev(h))
        && !fe(mesh.next(o))
        && !fe(mesh.prev(o))
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

fn collapse_short_edges(mesh: &mut HalfedgeMesh, w: &mut Work) {
    // Later sweeps only revisit edges at vertices whose neighbourhood changed (a refused
    // collapse is refused again otherwise), so failing candidates cost once, not ten times.
    start_sweeps(w, mesh.n_vertices());
    for _ in 0..MAX_SWEEPS {
        let mut any = false;
        let ne = mesh.n_edges() as u32;
        for e in 0..ne {
            if mesh.is_deleted_edge(e) || !mesh.is_interior_edge(e) {
                continue;
            }
            let (v0, v1) = ends(mesh, e);
            if !w.dirty[v0 as usize] && !w.dirty[v1 as usize] {
                continue;
            }
            let (h0, h1) = (w.h[v0 as usize], w.h[v1 as usize]);
            let hmin = 0.8 * h0.min(h1);
            if (mesh.position(v1) - mesh.position(v0)).length_squared() >= hmin * hmin {
                continue;
            }
            if w.frozen[v0 as usize] || w.frozen[v1 as usize] {
                continue;
            }
            let (h01, h10) = (2 * e, 2 * e + 1);
            let mut c01 = !w.locked[v0 as usize];
            let mut c10 = !w.locked[v1 as usize];
            if !c01 && !c10 {
                continue;
            }
            if c01 && w.vfeat[v0 as usize] {
                c01 = feature_collapse_ok(mesh, w, h01);
            }
            if c10 && w.vfeat[v1 as usize] {
                c10 = feature_collapse_ok(mesh, w, h10);
            }
            // Prefer removing the lower-valence end (keeping the higher-valence one); fall back to
            // the other direction if the preferred collapse is illegal — the same choice as
            // testing both first, with fewer legality tests.
            let order = if c01 && c10 && mesh.valence(v0) >= mesh.valence(v1) {
                [(c10, h10), (c01, h01)]
            } else {
                [(c01, h01), (c10, h10)]
            };
            let Some(h) = order
                .into_iter()
                .find(|&(ok, h)| ok && mesh.is_collapse_ok(h))
                .map(|(_, h)| h)
            else {
                continue;
            };
            let (vr, vk) = (mesh.from(h), mesh.to(h));
            let pk = mesh.position(vk);
            let hk = w.h[vk as usize];
            let creates_long = mesh.neighbors(vr).any(|u| {
                if u == vk {
                    return false;
                }
                let lim = 4.0 / 3.0 * hk.min(w.h[u as usize]);
                (mesh.position(u) - pk).length_squared() > lim * lim
            });
            if creates_long || mesh.collapse_flips_faces(h, pk, COLLAPSE_MIN_COS, w.min_area) {
                continue;
            }
            // The merged edge pairs keep the feature flag of either.
            let o = h ^ 1;
            let (keep1, gone1) = (mesh.prev(h) >> 1, mesh.next(h) >> 1);
            let (keep2, gone2) = (mesh.next(o) >> 1, mesh.prev(o) >> 1);
            w.efeat[keep1 as usize] |= w.efeat[gone1 as usize];
            w.efeat[keep2 as usize] |= w.efeat[gone2 as usize];
            mesh.collapse_edge(h);
            w.dirty_next[vk as usize] = true;
            for u in mesh.neighbors(vk) {
                w.dirty_next[u as usize] = true;
            }
            w.report.collapses += 1;
            any = true;
        }
        next_sweep(w);
        if !any {
            break;
        }
    }
    if !mesh.has_garbage() {
        return;
    }
    let maps = mesh.garbage_collect();
    remap(&mut w.h, &maps.vertices);
    remap(&mut w.locked, &maps.vertices);
    remap(&mut w.frozen, &maps.vertices);
    remap(&mut w.vfeat, &maps.vertices);
    remap(&mut w.efeat, &maps.edges);
}

/// Compacts `data` by an old→new index map (`INVALID` = dropped); new indices never exceed old.
fn remap<T: Copy>(data: &mut Vec<T>, map: &[u32]) {
    let mut n = 0;
    for (old, &new) in map.iter().enumerate() {
        if new != INVALID {
            data[new as usize] = data[old];
            n += 1;
        }
    }
    data.truncate(n);
}

/// True when the two faces that flipping edge `(a, b)` (opposite vertices c, d) would create,
/// `(c, a, d)` and `(d, b, c)`, are non-degenerate and face the same side as the old pair.
pub(super) fn flip_geometry_ok(
    mesh: &HalfedgeMesh,
    a: u32,
    b: u32,
    c: u32,
    d: u32,
    min_area: f64,
) -> bool {
    let [pa, pb, pc, pd] = [a, b, c, d].map(|v| mesh.position(v));
    let m =
        (pb - pa).cross(pc - pa).normalize_or_zero() + (pa - pb).cross(pd - pb).normalize_or_zero();
    let n1 = (pa - pc).cross(pd - pc);
    let n2 = (pb - pd).cross(pc - pd);
    0.5 * n1.length() > min_area
        && 0.5 * n2.length() > min_area
        && n1.dot(m) > 0.0
        && n2.dot(m) > 0.0
}

fn flip_edges(mesh: &mut HalfedgeMesh, w: &mut Work) {
    let nv = mesh.n_vertices();
    w.valence.clear();
    w.valence.resize(nv, 0);
    for hh in 0..mesh.n_halfedges() as u32 {
        w.valence[mesh.to(hh) as usize] += 1;
    }
    let dev = |x: i32| (x - 6) * (x - 6);
    start_sweeps(w, nv);
    for _ in 0..MAX_SWEEPS {
        let mut any = false;
        for e in 0..mesh.n_edges() as u32 {
            if w.efeat[e as usize] || !mesh.is_interior_edge(e) {
                continue;
            }
            let (h0, h1) = (2 * e, 2 * e + 1);
            let (a, b) = (mesh.to(h1), mesh.to(h0));
            if !w.dirty[a as usize] && !w.dirty[b as usize] {
                continue;
            }
            let c = mesh.to(mesh.next(h0));
            let d = mesh.to(mesh.next(h1));
            if [a, b, c, d].iter().any(|&v| w.locked[v as usize]) {
                continue;
            }
            let [va, vb, vc, vd] = [a, b, c, d].map(|v| w.valence[v as usize]);
            let before = dev(va) + dev(vb) + dev(vc) + dev(vd);
            let after = dev(va - 1) + dev(vb - 1) + dev(vc + 1) + dev(vd + 1);
            if after >= before || va <= 3 || vb <= 3 || c == d || mesh.are_adjacent(c, d) {
                continue;
            }
            if !flip_geometry_ok(mesh, a, b, c, d, w.min_area) {
                continue;
            }
            mesh.flip_edge(e);
            w.valence[a as usize] -= 1;
            w.valence[b as usize] -= 1;
            w.valence[c as usize] += 1;
            w.valence[d as usize] += 1;
            for v in [a, b, c, d] {
                w.dirty_next[v as usize] = true;
            }
            w.report.flips += 1;
            any = true;
        }
        next_sweep(w);
        if !any {
            break;
        }
    }
}

/// Builds the one-rings of all vertices as a CSR array: the neighbours of `v` are
/// `ring[off[v]..off[v + 1]]`, counter-clockwise, so `(v, ring[k], ring[k + 1])` is a face.
fn build_rings(mesh: &HalfedgeMesh, off: &mut Vec<u32>, ring: &mut Vec<u32>) {
    off.clear();
    ring.clear();
    off.push(0);
    for v in 0..mesh.n_vertices() as u32 {
        ring.extend(mesh.outgoing(v).map(|h| mesh.to(h)));
        off.push(ring.len() as u32);
    }
}

/// Tangential target of an interior vertex `x` with counter-clockwise ring `ring`: the minimiser
/// of `Σ_{ring edges pq} |(x − p)×(q − p)|² / |q − p|` (PMP's `minimize_squared_areas`), or,
/// when that 3×3 system is (nearly) singular, the centroid of the incident faces' centroids
/// weighted by `area / h̄²`. Also returns the area-weighted vertex normal.
fn smoothing_target(pos: &[DVec3], h: &[f64], x: DVec3, hx: f64, ring: &[u32]) -> (DVec3, DVec3) {
    let (mut xx, mut xy, mut xz, mut yy, mut yz, mut zz) = (0.0, 0.0, 0.0, 0.0, 0.0, 0.0);
    let mut rhs = DVec3::ZERO;
    let mut normal = DVec3::ZERO;
    let Some(&last) = ring.last() else {
        return (x, DVec3::ZERO);
    };
    // Ring edges (p, q) = (ring[k], ring[k + 1]), cyclically; p - x and q - x relative to x
    // (translation-invariant system, better conditioned far from the origin).
    let mut p = pos[last as usize] - x;
    for &qi in ring {
        let q = pos[qi as usize] - x;
        normal += p.cross(q);
        let d = q - p;
        let l2 = d.length_squared();
        if !(l2 > 0.0) {
            continue;
        }
        let wgt = 1.0 / l2.sqrt();
        let (axx, axy, axz) = (wgt * (l2 - d.x * d.x), -wgt * d.x * d.y, -wgt * d.x * d.z);
        let (ayy, ayz, azz) = (
            wgt * (l2 - d.y * d.y),
            -wgt * d.y * d.z,
            wgt * (l2 - d.z * d.z),
        );
        xx += axx;
        xy += axy;
        xz += axz;
        yy += ayy;
        yz += ayz;
        zz += azz;
        rhs += DVec3::new(
            axx * p.x + axy * p.y + axz * p.z,
            axy * p.x + ayy * p.y + ayz * p.z,
            axz * p.x + ayz * p.y + azz * p.z,
        );
        p = q;
    }
    let normal = normal.normalize_or_zero();
    let m = DMat3::from_cols(
        DVec3::new(xx, xy, xz),
        DVec3::new(xy, yy, yz),
        DVec3::new(xz, yz, zz),
    );
    let det = m.determinant();
    let scale = (xx + yy + zz) / 3.0;
    if det.abs() > 1e-6 * scale * scale * scale {
        let t = m.inverse() * rhs;
        if t.is_finite() {
            return (x + t, normal);
        }
    }
    let (mut sum, mut ww) = (DVec3::ZERO, 0.0);
    let mut b = last as usize;
    for &ci in ring {
        let c = ci as usize;
        let (pb, pc) = (pos[b], pos[c]);
        let area = 0.5 * (pb - x).cross(pc - x).length();
        let hm = (hx + h[b] + h[c]) / 3.0;
        let wt = area / (hm * hm);
        sum += wt * (x + pb + pc) / 3.0;
        ww += wt;
        b = c;
    }
    (if ww > 0.0 { sum / ww } else { x }, normal)
}

/// Update of a feature vertex with exactly two feature edges: towards the mean of the two
/// feature-edge midpoints weighted by `|e| / h̄`, along the feature line's tangent only.
fn feature_update(mesh: &HalfedgeMesh, w: &Work, v: u32) -> DVec3 {
    let vi = v as usize;
    let x = mesh.position(v);
    let mut dirs = [DVec3::ZERO; 2];
    let mut k = 0;
    let (mut target, mut ww) = (DVec3::ZERO, 0.0);
    for h in mesh.outgoing(v) {
        if !w.efeat[(h >> 1) as usize] {
            continue;
        }
        let u = mesh.to(h);
        let pu = mesh.position(u);
        let len = (pu - x).length();
        if k < 2 {
            dirs[k] = (pu - x) / len;
        }
        k += 1;
        let wt = len / (0.5 * (w.h[vi] + w.h[u as usize]));
        target += wt * 0.5 * (x + pu);
        ww += wt;
    }
    if k != 2 || !(ww > 0.0) {
        return DVec3::ZERO;
    }
    let t = (dirs[0] - dirs[1]).normalize_or_zero();
    t * t.dot(target / ww - x)
}

/// Tangential smoothing passes (Jacobi: all updates computed, then applied). With a positive
/// `smoothing_tolerance`, a vertex is recomputed only while it or a neighbour moved by more than
/// that fraction of its target length in the previous pass. Returns true when the first pass
/// already moved no vertex by more than the tolerance (the mesh is at rest).
fn tangential_smoothing(mesh: &mut HalfedgeMesh, w: &mut Work) -> bool {
    let nv = mesh.n_vertices();
    // (No projection before the passes: every vertex is on the reference already — the call's
    // own vertices are its vertices, a split projects the one it adds, and collapses and flips
    // move none. Projecting them again would only cost time.)
    build_rings(mesh, &mut w.ring_off, &mut w.ring);
    let tol = w.s.smoothing_tolerance.max(0.0);
    w.active.clear();
    w.active.resize(nv, true);
    let mut at_rest = false;
    for pass in 0..w.s.smoothing_iterations {
        // Jacobi: every update reads the old positions only, so the vertices are independent.
        let (m, wr) = (&*mesh, &*w);
        let pos = m.positions();
        w.upd = crate::parallel::map(nv, |v| {
            if wr.locked[v] || !wr.active[v] {
                return DVec3::ZERO;
            }
            if wr.vfeat[v] {
                return feature_update(m, wr, v as u32);
            }
            let ring = &wr.ring[wr.ring_off[v] as usize..wr.ring_off[v + 1] as usize];
            let x = pos[v];
            let (target, n) = smoothing_target(pos, &wr.h, x, wr.h[v], ring);
            let u = target - x;
            u - n * n.dot(u)
        });
        w.moved.clear();
        w.moved.resize(nv, false);
        let mut any_moved = false;
        for v in 0..nv {
            let lim = tol * w.h[v];
            if w.upd[v].length_squared() > lim * lim {
                w.moved[v] = true;
                any_moved = true;
            }
        }
        for (p, u) in mesh.positions_mut().iter_mut().zip(&w.upd) {
            *p += *u;
        }
        if tol > 0.0 {
            if !any_moved {
                at_rest = pass == 0;
                break;
            }
            for v in 0..nv {
                let ring = &w.ring[w.ring_off[v] as usize..w.ring_off[v + 1] as usize];
                w.active[v] = w.moved[v] || ring.iter().any(|&u| w.moved[u as usize]);
            }
        }
    }
    if w.reference.is_some() {
        project_all(mesh, w);
    }
    at_rest
}

/// Projects every unlocked, non-feature vertex onto the reference surface and takes its sizing.
fn project_all(mesh: &mut HalfedgeMesh, w: &mut Work) {
    let Some(r) = &w.reference else { return };
    let (pos, locked, vfeat) = (mesh.positions(), &w.locked, &w.vfeat);
    let projected = crate::parallel::map(mesh.n_vertices(), |v| {
        (!(locked[v] || vfeat[v])).then(|| r.project(pos[v]))
    });
    for (v, pr) in projected.into_iter().enumerate() {
        let Some((q, hq)) = pr else { continue };
        mesh.positions_mut()[v] = q;
        if hq.is_finite() {
            w.h[v] = hq;
        }
    }
}

fn remove_caps(mesh: &mut HalfedgeMesh, w: &mut Work) {
    let cos_cap = crate::fmath::cos(w.s.cap_angle_deg.to_radians());
    for e in 0..mesh.n_edges() as u32 {
        if w.efeat[e as usize] || !mesh.is_interior_edge(e) {
            continue;
        }
        let (h0, h1) = (2 * e, 2 * e + 1);
        let (a, b) = (mesh.to(h1), mesh.to(h0));
        let c = mesh.to(mesh.next(h0));
        let d = mesh.to(mesh.next(h1));
        let [pa, pb, pc, pd] = [a, b, c, d].map(|v| mesh.position(v));
        let cos_at = |q: DVec3| {
            let (u, v) = (pa - q, pb - q);
            u.dot(v) / (u.length() * v.length())
        };
        let worst = cos_at(pc).min(cos_at(pd));
        if !(worst < cos_cap) {
            continue;
        }
        if mesh.is_flip_ok(e) && flip_geometry_ok(mesh, a, b, c, d, w.min_area) {
            mesh.flip_edge(e);
            w.report.caps_removed += 1;
        }
    }
}
