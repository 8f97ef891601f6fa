//! The smoothing phase: tangential smoothing passes (area-minimising targets, feature vertices
//! along their feature line), then back-projection onto the reference surface.

use super::Work;
use crate::mesh::HalfedgeMesh;
use glam::{DMat3, DVec3};

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
pub(super) fn tangential_smoothing(mesh: &mut HalfedgeMesh, w: &mut Work) -> bool {
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
