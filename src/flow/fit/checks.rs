//! The fit's edits kept free of intersections where the certificate looks for them: on the
//! positions as written (in the target's frame, rounded to f32). The same check in the
//! stabilised frame can differ where faces nearly touch (the frame's scaling rounds), and a fit
//! that passed it could be certified invalid.

use super::crease_fit::snap_to_creases;
use crate::flow::guard::{
    freeze_where_intersecting, resolve_contacts, GuardSettings, REMESH_TRIES,
};
use crate::flow::guarded::{guarded, GuardPolicy, Verdict};
use crate::flow::scaling::written;
use crate::geometry::creases::Creases;
use crate::geometry::spatial::bvh::TriangleBvh;
use crate::mesh::HalfedgeMesh;
use crate::metrics::intersections::{count_self_intersections, self_intersecting_pairs};
use crate::remesh::features::Features;
use crate::remesh::slivers::{remove_slivers, SliverReport, SliverSettings};
use glam::DVec3;

/// True when faces of `m` intersect as written: the certificate's check.
pub(super) fn intersects_as_written(m: &HalfedgeMesh, phi: f64, center: DVec3) -> bool {
    let written: Vec<DVec3> = m
        .positions()
        .iter()
        .map(|&p| written(p, phi, center))
        .collect();
    count_self_intersections(&written, &m.triangles()) > 0
}

/// [`resolve_contacts`] on the positions as written (see [`intersects_as_written`]); `mesh` is
/// left at its written positions, mapped back into the stabilised frame (`phi`, `center`).
pub(super) fn resolve_contacts_as_written(
    mesh: &mut HalfedgeMesh,
    old: &[DVec3],
    guard: &GuardSettings,
    phi: f64,
    center: DVec3,
) {
    let mut w = mesh.clone();
    for p in w.positions_mut() {
        *p = written(*p, phi, center);
    }
    let old: Vec<DVec3> = old.iter().map(|&p| written(p, phi, center)).collect();
    resolve_contacts(&mut w, &old, guard);
    for (p, q) in mesh.positions_mut().iter_mut().zip(w.positions()) {
        *p = (*q - center) * phi;
    }
}

/// Fractions of a reverted move tried again, in turn (see [`partial_moves`]).
const PARTIAL_MOVES: [f64; 3] = [0.5, 0.25, 0.125];

/// After [`resolve_contacts_as_written`] put vertices back from their `wanted` positions to
/// `old`, moves them part of the way again — half, then a quarter, an eighth — each time
/// keeping what intersects nothing: a flap tip whose move onto the target crosses a face still
/// ends closer to it.
pub(super) fn partial_moves(
    mesh: &mut HalfedgeMesh,
    old: &[DVec3],
    wanted: &[DVec3],
    guard: &GuardSettings,
    phi: f64,
    center: DVec3,
) {
    let reach = |v: usize| (wanted[v] - old[v]).length();
    let from_old = |mesh: &HalfedgeMesh, v: usize| (mesh.positions()[v] - old[v]).length();
    // Put back: nearer where it was than where it went (positions come back through the written
    // frame, so not bit for bit).
    let mut pending: Vec<bool> = (0..wanted.len())
        .map(|v| reach(v) > 0.0 && from_old(mesh, v) < 0.5 * reach(v))
        .collect();
    for frac in PARTIAL_MOVES {
        if !pending.contains(&true) {
            return;
        }
        let now = mesh.positions().to_vec();
        for (v, p) in mesh.positions_mut().iter_mut().enumerate() {
            if pending[v] {
                *p = old[v] + frac * (wanted[v] - old[v]);
            }
        }
        resolve_contacts_as_written(mesh, &now, guard, phi, center);
        for (v, pending) in pending.iter_mut().enumerate() {
            if *pending && from_old(mesh, v) > 0.5 * frac * reach(v) {
                *pending = false;
            }
        }
    }
}

/// Tries of the crease snap per fit pass (see [`snap_creases_checked`]).
const CREASE_TRIES: usize = 3;

/// [`snap_to_creases`] kept intersection-free: a try that makes faces intersect is undone and
/// redone without the vertices of those faces and their neighbours, a few times at most; then
/// the mesh is as it came and the answer is None.
///
/// With `round`, the check is of the positions as written. A cloud's crease lines are many
/// short pieces found point by point, and the wrap over a cloud is finer than a mesh target's
/// fit: a vertex often lands on a line between two others already on it, touching their faces,
/// which the f32 rounding turns into a crossing that the pass's own check would then refuse
/// whole. A mesh's snap is checked as computed.
pub(super) fn snap_creases_checked(
    mesh: &mut HalfedgeMesh,
    creases: &Creases,
    reach: f64,
    round: Option<&dyn Fn(&mut HalfedgeMesh)>,
    triangles: Option<&TriangleBvh>,
) -> Option<Features> {
    mesh.garbage_collect();
    let before = mesh.clone();
    let mut banned = vec![false; before.n_vertices()];
    let mut features = None;
    let policy = GuardPolicy {
        tries: CREASE_TRIES,
        applied: false,
    };
    let outcome = guarded(
        mesh,
        &mut banned,
        policy,
        |m, banned| {
            *m = before.clone();
            features = Some(snap_to_creases(m, creases, reach, banned, triangles).0);
            if let Some(round) = round {
                round(m);
            }
            true
        },
        |m, banned| ban_where_intersecting(m, &before, banned),
        |m| *m = before.clone(),
    );
    features.filter(|_| outcome.clean)
}

/// The crease snap's check: bans the vertices of the faces of `m` that intersect and their
/// neighbours in `before`, the surface the snap started from.
fn ban_where_intersecting(m: &HalfedgeMesh, before: &HalfedgeMesh, banned: &mut [bool]) -> Verdict {
    let tris = m.triangles();
    let pairs = self_intersecting_pairs(m.positions(), &tris);
    if pairs.is_empty() {
        return Verdict::Clean;
    }
    for (f, g) in pairs {
        for v in tris[f as usize].into_iter().chain(tris[g as usize]) {
            banned[v as usize] = true;
            for u in before.neighbors(v) {
                banned[u as usize] = true;
            }
        }
    }
    Verdict::Retry
}

/// Flips the caps and collapses the needles that moves onto crease lines left since the last
/// remesh (see [`crate::remesh::slivers`]). With the contact guard on, where that makes faces
/// intersect as written it is tried again with those regions left alone, as a pass's remesh is.
pub(super) fn tidy_slivers(mesh: &mut HalfedgeMesh, contact: bool, phi: f64, center: DVec3) {
    let before = mesh.clone();
    let mut frozen = vec![false; mesh.n_vertices()];
    let policy = GuardPolicy {
        tries: REMESH_TRIES + 1,
        applied: false,
    };
    guarded(
        mesh,
        &mut frozen,
        policy,
        // Nothing to tidy (any more) gives out: the mesh stays as it came.
        |m, frozen| {
            *m = before.clone();
            remove_slivers(m, &SliverSettings::default(), frozen) != SliverReport::default()
        },
        |m, frozen| match contact {
            false => Verdict::Clean,
            true => freeze_where_intersecting(m, &before, |p| written(p, phi, center), frozen),
        },
        |m| *m = before.clone(),
    );
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::flow::scaling::round_as_written;
    use crate::geometry::icosphere::icosphere;

    #[test]
    fn a_move_put_back_for_crossing_a_face_is_made_part_of_the_way() {
        let mut m = icosphere(2, 1.0, DVec3::ZERO).unwrap();
        let (phi, center) = (1.0, DVec3::ZERO);
        round_as_written(&mut m, phi, center);
        let old = m.positions().to_vec();
        // Vertex 0 wanted through the far side of the sphere: its fan would cross it.
        let mut wanted = old.clone();
        wanted[0] = -1.3 * old[0];
        wanted[1] = 0.99 * old[1];
        m.positions_mut().copy_from_slice(&wanted);
        let guard = GuardSettings::default();
        resolve_contacts_as_written(&mut m, &old, &guard, phi, center);
        assert_eq!(m.position(0), old[0], "the whole move is put back");
        partial_moves(&mut m, &old, &wanted, &guard, phi, center);
        let p = m.positions().to_vec();
        assert_eq!(count_self_intersections(&p, &m.triangles()), 0);
        // Half way (−0.15 p₀, inside) crosses nothing; a vertex the guard kept stays.
        let half = old[0] + 0.5 * (wanted[0] - old[0]);
        assert!((p[0] - half).length() < 1e-6, "{:?} vs {half:?}", p[0]);
        assert!((p[1] - wanted[1]).length() < 1e-6);
    }
}
