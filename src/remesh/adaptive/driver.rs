//! The driver of one remesh call: checks, features and locks, the sizing field and reference
//! surface, then the split / collapse / flip / smooth iterations and the final cap removal.

use super::collapse::collapse_short_edges;
use super::flip::{flip_edges, remove_caps};
use super::smooth::tangential_smoothing;
use super::split::split_long_edges;
use super::{Reference, RemeshError, RemeshReport, RemeshSettings, Work, SPLIT_ALLOWANCE};
use crate::clock::now_ms;
use crate::geometry::operators::curvature::principal_curvatures;
use crate::geometry::spatial::bvh::TriangleBvh;
use crate::mesh::HalfedgeMesh;
use crate::remesh::features::{detect_features, FeatureDetector, Features};
use crate::remesh::sizing::curvature_sizing;

/// One remesh call with optional caller-supplied features and per-vertex length caps.
pub(super) fn remesh_impl(
    mesh: &mut HalfedgeMesh,
    s: &RemeshSettings,
    given: Option<&Features>,
    caps: Option<&[f64]>,
) -> Result<RemeshReport, RemeshError> {
    check_sizes(s)?;
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
    let features = call_features(mesh, s, given);
    let locked = locked_vertices(mesh, &features);
    report.feature_vertices = features.n_vertices();
    report.feature_edges = features.n_edges();
    report.locked_vertices = locked.iter().filter(|&&b| b).count();
    let (h, reference) = sizing_and_reference(mesh, s, &features, &locked, caps);
    let mut w = new_work(s, h, locked, features, reference, report, nv);
    let mut laps = Laps { t: now_ms() };
    w.report.time_ms.sizing = laps.t - t_start;
    iterate(mesh, &mut w, &mut laps, nv)?;
    finish(mesh, &mut w, &mut laps, nv);
    w.report.time_ms.total = now_ms() - t_start;
    w.report.vertices_after = mesh.n_vertices();
    Ok(w.report)
}

/// Rejects target lengths or an approximation error that are not positive and finite, or a
/// minimum above the maximum.
fn check_sizes(s: &RemeshSettings) -> Result<(), RemeshError> {
    let (lmin, lmax, eps) = (s.min_edge_length, s.max_edge_length, s.approx_error);
    let ok = |x: f64| x > 0.0 && x.is_finite();
    if !(ok(lmin) && ok(lmax) && ok(eps) && lmin <= lmax) {
        return Err(RemeshError::InvalidSizes {
            min: lmin,
            max: lmax,
            eps,
        });
    }
    Ok(())
}

/// The call's features: the given ones, none, or those detected per `s.features`.
fn call_features(mesh: &HalfedgeMesh, s: &RemeshSettings, given: Option<&Features>) -> Features {
    match given {
        Some(f) => f.clone(),
        None if s.features.detector == FeatureDetector::Off => Features::none(mesh),
        None => detect_features(mesh, &principal_curvatures(mesh, None, 1), &s.features),
    }
}

/// The vertices the call never moves: on a boundary, pinned, frozen, or feature vertices with
/// other than two feature edges.
fn locked_vertices(mesh: &HalfedgeMesh, features: &Features) -> Vec<bool> {
    let nv = mesh.n_vertices();
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
    locked
}

/// The sizing field (curvature sizing capped by `caps`) and, with projection on, the reference
/// surface as it is for the back-projection.
fn sizing_and_reference(
    mesh: &HalfedgeMesh,
    s: &RemeshSettings,
    features: &Features,
    locked: &[bool],
    caps: Option<&[f64]>,
) -> (Vec<f64>, Option<Reference>) {
    // Sizing: curvatures with one smoothing pass that skips features; beside it, the tree of
    // the surface as it is for the back-projection (independent work, a seventh of the call).
    let nv = mesh.n_vertices();
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
    (h, reference)
}

/// The working state at the start of the call.
fn new_work<'a>(
    s: &'a RemeshSettings,
    h: Vec<f64>,
    locked: Vec<bool>,
    features: Features,
    reference: Option<Reference>,
    report: RemeshReport,
    nv: usize,
) -> Work<'a> {
    let lmin = s.min_edge_length;
    Work {
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
    }
}

/// A phase clock: each lap adds the time since the previous one to a phase's total.
struct Laps {
    t: f64,
}

impl Laps {
    /// Adds the time since the last lap to `acc`.
    fn lap(&mut self, acc: &mut f64) {
        let now = now_ms();
        *acc += now - self.t;
        self.t = now;
    }
}

/// The outer iterations: split, collapse, flip and smooth until nothing changes or
/// `s.iterations` are done; a runaway split is an error.
fn iterate(
    mesh: &mut HalfedgeMesh,
    w: &mut Work,
    laps: &mut Laps,
    nv: usize,
) -> Result<(), RemeshError> {
    for _ in 0..w.s.iterations {
        let edits = w.report.splits + w.report.collapses + w.report.flips;
        if !split_long_edges(mesh, w) {
            return Err(RemeshError::Runaway {
                splits: w.report.splits,
                vertices: nv,
            });
        }
        laps.lap(&mut w.report.time_ms.split);
        collapse_short_edges(mesh, w);
        laps.lap(&mut w.report.time_ms.collapse);
        flip_edges(mesh, w);
        laps.lap(&mut w.report.time_ms.flip);
        let at_rest = tangential_smoothing(mesh, w);
        laps.lap(&mut w.report.time_ms.smooth);
        if at_rest && edits == w.report.splits + w.report.collapses + w.report.flips {
            break; // Nothing changed: further iterations would repeat this one.
        }
    }
    Ok(())
}

/// Removes caps, compacts the mesh and, after many edits, reorders it spatially.
fn finish(mesh: &mut HalfedgeMesh, w: &mut Work, laps: &mut Laps, nv: usize) {
    remove_caps(mesh, w);
    mesh.garbage_collect();
    if w.s.reorder && (w.report.splits + w.report.collapses) * 20 > nv {
        mesh.reorder_spatially();
        w.report.reordered = true;
    }
    laps.lap(&mut w.report.time_ms.caps);
}
