//! Slivers left by moves made after the last remesh: the fit's last round puts vertices on a
//! target's crease lines and corners without a remesh after it, so three vertices can end on
//! one polyline (a *cap*: an angle near 180°, a chord across a bend of the rim of a hole) or two
//! on one corner (a *needle*: an edge far shorter than the face's others). A cap spans the gap
//! between its chord and the crease, which the crease metric reads as a bevel, and a folded one
//! holds its neighbours off the target (a rim edge beside it stays bent, since the guard does not
//! let a neighbour flatten it). A cap's long edge is flipped,
//! a needle's short edge collapsed: neither moves a vertex that stays.

use super::adaptive::flip_geometry_ok;
use crate::mesh::HalfedgeMesh;

/// When a face is a sliver.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SliverSettings {
    /// A face with an angle above this many degrees is a cap. Default 170 (the remesh's cap
    /// angle).
    pub cap_angle_deg: f64,
    /// A face whose shortest edge is below this fraction of its longest is a needle. Default
    /// 0.05 (a smallest angle under about 3°; the remesh leaves none under 10° on smooth parts).
    pub needle_ratio: f64,
    /// A collapse may turn a remaining face's normal by at most the angle of this cosine.
    /// Default 0.5 (60°, the remesh's bound).
    pub collapse_min_cos: f64,
}

impl Default for SliverSettings {
    fn default() -> Self {
        Self {
            cap_angle_deg: 170.0,
            needle_ratio: 0.05,
            collapse_min_cos: 0.5,
        }
    }
}

/// What [`remove_slivers`] did.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct SliverReport {
    pub caps_flipped: usize,
    pub needles_collapsed: usize,
}

/// Sweeps over the faces before giving up (each edit can make a neighbour a sliver).
const SWEEPS: usize = 3;

/// Flips the long edge of every cap and collapses the short edge of every needle where that is
/// legal and folds nothing, leaving faces with a `frozen` vertex alone (indices of the mesh as
/// given; shorter: not frozen); positions are untouched. The mesh is garbage-collected after an
/// edit (vertex indices change then).
pub fn remove_slivers(
    mesh: &mut HalfedgeMesh,
    s: &SliverSettings,
    frozen: &[bool],
) -> SliverReport {
    let mut report = SliverReport::default();
    let cos_cap = crate::fmath::cos(s.cap_angle_deg.to_radians());
    for _ in 0..SWEEPS {
        let before = report;
        for f in 0..mesh.n_faces() as u32 {
            if mesh.is_deleted_face(f) {
                continue;
            }
            let h0 = mesh.face_halfedge(f);
            let hs = [h0, mesh.next(h0), mesh.next(mesh.next(h0))];
            if hs
                .iter()
                .any(|&h| frozen.get(mesh.to(h) as usize) == Some(&true))
            {
                continue;
            }
            let len =
                hs.map(|h| (mesh.position(mesh.to(h)) - mesh.position(mesh.from(h))).length());
            let longest = (0..3)
                .max_by(|&i, &j| len[i].total_cmp(&len[j]))
                .unwrap_or(0);
            let shortest = (0..3)
                .min_by(|&i, &j| len[i].total_cmp(&len[j]))
                .unwrap_or(0);
            if len[longest].is_nan() || len[longest] <= 0.0 {
                continue;
            }
            // The angle opposite the longest edge, at the vertex after it.
            let h = hs[longest];
            let apex = mesh.position(mesh.to(mesh.next(h)));
            let (u, v) = (
                mesh.position(mesh.from(h)) - apex,
                mesh.position(mesh.to(h)) - apex,
            );
            let cos_apex = u.dot(v) / (u.length() * v.length());
            if cos_apex < cos_cap {
                // (A cap whose flip is illegal, beside a vertex of valence 3, loses its
                // shortest edge instead: its apex lies nearly on the long edge.)
                if flip_cap(mesh, h >> 1) {
                    report.caps_flipped += 1;
                } else if collapse_needle(mesh, hs[shortest], s.collapse_min_cos) {
                    report.needles_collapsed += 1;
                }
            } else if len[shortest] < s.needle_ratio * len[longest]
                && collapse_needle(mesh, hs[shortest], s.collapse_min_cos)
            {
                report.needles_collapsed += 1;
            }
        }
        if report == before {
            break;
        }
    }
    if report != SliverReport::default() {
        mesh.garbage_collect();
    }
    report
}

/// Flips edge `e` when legal and the two new faces are sound and face the old pair's way.
fn flip_cap(mesh: &mut HalfedgeMesh, e: u32) -> bool {
    if !mesh.is_flip_ok(e) {
        return false;
    }
    let (h0, h1) = (2 * e, 2 * e + 1);
    let (a, b) = (mesh.to(h1), mesh.to(h0));
    let (c, d) = (mesh.to(mesh.next(h0)), mesh.to(mesh.next(h1)));
    let scale = (mesh.position(a) - mesh.position(b)).length_squared();
    if !flip_geometry_ok(mesh, a, b, c, d, 1e-12 * scale) {
        return false;
    }
    mesh.flip_edge(e);
    true
}

/// Collapses the short edge of halfedge `h` one way or the other, whichever is legal and turns
/// no remaining face past `min_cos`; the survivor keeps its position.
fn collapse_needle(mesh: &mut HalfedgeMesh, h: u32, min_cos: f64) -> bool {
    for h in [h, h ^ 1] {
        let p = mesh.position(mesh.to(h));
        let scale = mesh
            .outgoing(mesh.from(h))
            .map(|o| (mesh.position(mesh.to(o)) - p).length_squared())
            .fold(0.0, f64::max);
        if mesh.is_collapse_ok(h) && !mesh.collapse_flips_faces(h, p, min_cos, 1e-12 * scale) {
            mesh.collapse_edge(h);
            return true;
        }
    }
    false
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::DVec3;

    /// A square split into a fan around its centre, with one rim vertex pushed nearly onto the
    /// chord between its neighbours: a cap.
    fn fan(points: &[DVec3]) -> HalfedgeMesh {
        let n = points.len() as u32;
        // Closed: a double-sided fan (top around apex 0 and a bottom apex).
        let mut pos = vec![DVec3::new(0.0, 0.0, 0.3)];
        pos.extend_from_slice(points);
        pos.push(DVec3::new(0.0, 0.0, -0.3));
        let bottom = n + 1;
        let mut tris = vec![];
        for i in 0..n {
            let (a, b) = (1 + i, 1 + (i + 1) % n);
            tris.push([0, a, b]);
            tris.push([bottom, b, a]);
        }
        HalfedgeMesh::from_triangles(pos, &tris).expect("a closed fan")
    }

    fn ring(k: usize) -> Vec<DVec3> {
        (0..k)
            .map(|i| {
                let t = std::f64::consts::TAU * i as f64 / k as f64;
                DVec3::new(crate::fmath::cos(t), crate::fmath::sin(t), 0.0)
            })
            .collect()
    }

    fn worst_angles(mesh: &HalfedgeMesh) -> (f64, f64) {
        let (mut lo, mut hi) = (180.0f64, 0.0f64);
        for [a, b, c] in mesh.triangles() {
            let p = [a, b, c].map(|v| mesh.position(v));
            for k in 0..3 {
                let (u, v) = (p[(k + 1) % 3] - p[k], p[(k + 2) % 3] - p[k]);
                let ang = crate::geometry::angle::corner_angle(u.cross(v).length(), u.dot(v))
                    .to_degrees();
                lo = lo.min(ang);
                hi = hi.max(ang);
            }
        }
        (lo, hi)
    }

    #[test]
    fn a_needle_is_collapsed_and_the_rest_kept() {
        let mut pts = ring(12);
        // A vertex a thousandth of the ring's edge from its neighbour: needles on both sides.
        let d = pts[1] - pts[0];
        pts.insert(1, pts[0] + 1e-3 * d);
        let mut mesh = fan(&pts);
        let before = mesh.n_vertices();
        assert!(worst_angles(&mesh).0 < 1.0);
        let r = remove_slivers(&mut mesh, &SliverSettings::default(), &[]);
        assert!(r.needles_collapsed >= 1, "{r:?}");
        assert_eq!(mesh.n_vertices(), before - 1);
        assert!(mesh.validate().is_ok());
        assert!(worst_angles(&mesh).0 > 5.0, "{:?}", worst_angles(&mesh));
    }

    #[test]
    fn a_cap_is_flipped_and_positions_kept() {
        // A rim vertex moved onto the chord of its neighbours (as a crease snap does): its two
        // faces with the apexes are fine, but a strip face is built across the chord.
        let pts = ring(10);
        let mut pos: Vec<DVec3> = pts.clone();
        // p = midpoint-ish between pts[0] and pts[1], slightly outside the chord.
        let mid = 0.5 * (pts[0] + pts[1]) + 0.002 * (pts[0] + pts[1]).normalize();
        pos.push(mid);
        let m = pos.len() as u32 - 1;
        pos.push(DVec3::new(0.0, 0.0, 0.3));
        pos.push(DVec3::new(0.0, 0.0, -0.3));
        let (top, bottom) = (m + 1, m + 2);
        let mut tris = vec![[1, 0, m], [top, 0, 1], [bottom, 1, m], [bottom, m, 0]];
        for i in 1..10u32 {
            let (a, b) = (i, (i + 1) % 10);
            tris.push([top, a, b]);
            tris.push([bottom, b, a]);
        }
        let mut mesh = HalfedgeMesh::from_triangles(pos, &tris).expect("closed");
        let positions = mesh.positions().to_vec();
        assert!(worst_angles(&mesh).1 > 170.0);
        let r = remove_slivers(&mut mesh, &SliverSettings::default(), &[]);
        assert_eq!(r.caps_flipped, 1, "{r:?}");
        assert!(mesh.validate().is_ok());
        assert_eq!(mesh.positions(), &positions[..]);
        assert!(worst_angles(&mesh).1 < 170.0, "{:?}", worst_angles(&mesh));
    }

    #[test]
    fn a_sound_mesh_is_left_alone() {
        let mut mesh = fan(&ring(8));
        let tris = mesh.triangles();
        let r = remove_slivers(&mut mesh, &SliverSettings::default(), &[]);
        assert_eq!(r, SliverReport::default());
        assert_eq!(mesh.triangles(), tris);
    }
}
