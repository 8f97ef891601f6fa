//! The collapse phase: edges shorter than 4/5 of their target length are collapsed into the
//! end that is kept, unless that creates a long edge, turns a face over or breaks a feature.

use super::{ends, next_sweep, start_sweeps, Work, MAX_SWEEPS};
use crate::mesh::{HalfedgeMesh, INVALID};

/// A collapse may turn a remaining face's normal by at most 60° (cos 60° = 0.5).
const COLLAPSE_MIN_COS: f64 = 0.5;

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

/// Collapses the edges shorter than 4/5 of their target length, sweeping until none collapses,
/// then compacts the mesh and the work arrays.
pub(super) fn collapse_short_edges(mesh: &mut HalfedgeMesh, w: &mut Work) {
    // Later sweeps only revisit edges at vertices whose neighbourhood changed (a refused
    // collapse is refused again otherwise), so failing candidates cost once, not ten times.
    start_sweeps(w, mesh.n_vertices());
    for _ in 0..MAX_SWEEPS {
        let mut any = false;
        let ne = mesh.n_edges() as u32;
        for e in 0..ne {
            let Some(h) = collapse_choice(mesh, w, e) else {
                continue;
            };
            collapse(mesh, w, h);
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

/// The halfedge along which edge `e` is to be collapsed (its `from` vertex removed), or None
/// when the edge is not a short, dirty, editable edge with a legal, harmless collapse.
fn collapse_choice(mesh: &HalfedgeMesh, w: &Work, e: u32) -> Option<u32> {
    if mesh.is_deleted_edge(e) || !mesh.is_interior_edge(e) {
        return None;
    }
    let (v0, v1) = ends(mesh, e);
    if !w.dirty[v0 as usize] && !w.dirty[v1 as usize] {
        return None;
    }
    let (h0, h1) = (w.h[v0 as usize], w.h[v1 as usize]);
    let hmin = 0.8 * h0.min(h1);
    if (mesh.position(v1) - mesh.position(v0)).length_squared() >= hmin * hmin {
        return None;
    }
    if w.frozen[v0 as usize] || w.frozen[v1 as usize] {
        return None;
    }
    let (h01, h10) = (2 * e, 2 * e + 1);
    let mut c01 = !w.locked[v0 as usize];
    let mut c10 = !w.locked[v1 as usize];
    if !c01 && !c10 {
        return None;
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
    let h = order
        .into_iter()
        .find(|&(ok, h)| ok && mesh.is_collapse_ok(h))
        .map(|(_, h)| h)?;
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
        return None;
    }
    Some(h)
}

/// Collapses along `h`, merging the feature flags of the edge pairs that merge and marking the
/// kept vertex's neighbourhood dirty for the next sweep.
fn collapse(mesh: &mut HalfedgeMesh, w: &mut Work, h: u32) {
    let vk = mesh.to(h);
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
