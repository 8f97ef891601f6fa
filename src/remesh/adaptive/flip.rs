//! The flip phase: edges flipped where that brings the four vertices' valences closer to 6, and
//! the cap removal at the end of a call (flipping the edge opposite a near-straight angle).

use super::{next_sweep, start_sweeps, Work, MAX_SWEEPS};
use crate::mesh::HalfedgeMesh;
use glam::DVec3;

/// True when the two faces that flipping edge `(a, b)` (opposite vertices c, d) would create,
/// `(c, a, d)` and `(d, b, c)`, are non-degenerate and face the same side as the old pair.
pub(in crate::remesh) fn flip_geometry_ok(
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

/// Flips the edges whose flip brings the valences of their four vertices closer to 6, sweeping
/// until none does.
pub(super) fn flip_edges(mesh: &mut HalfedgeMesh, w: &mut Work) {
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

/// Flips away caps: the edge opposite an angle wider than `cap_angle_deg` in one of its faces,
/// unless it is a feature edge or the flip would fold the pair over.
pub(super) fn remove_caps(mesh: &mut HalfedgeMesh, w: &mut Work) {
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
