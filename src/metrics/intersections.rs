//! Self-intersection count: pairs of faces that share no vertex and intersect (BVH-accelerated).
//!
//! Two non-coplanar triangles intersect iff an edge of one crosses the other, so the test is six
//! segment–triangle tests (Möller–Trumbore, boundaries included). Coplanar overlaps are not
//! counted, and faces that share a vertex are "adjacent" and never tested — the usual definition
//! of a self-intersecting face pair in mesh repair tools.

use super::bvh::TriangleBvh;
use glam::DVec3;

/// True when segment `[p, q]` meets triangle `(a, b, c)` (non-parallel case; boundaries count).
pub fn segment_hits_triangle(p: DVec3, q: DVec3, a: DVec3, b: DVec3, c: DVec3) -> bool {
    let d = q - p;
    let (e1, e2) = (b - a, c - a);
    let h = d.cross(e2);
    let det = e1.dot(h);
    if det == 0.0 {
        return false;
    }
    let inv = 1.0 / det;
    let s = p - a;
    let u = inv * s.dot(h);
    if !(0.0..=1.0).contains(&u) {
        return false;
    }
    let qv = s.cross(e1);
    let v = inv * d.dot(qv);
    if v < 0.0 || u + v > 1.0 {
        return false;
    }
    let t = inv * e2.dot(qv);
    (0.0..=1.0).contains(&t)
}

/// True when triangles `t` and `u` (non-coplanar) intersect.
pub fn triangles_intersect(t: [DVec3; 3], u: [DVec3; 3]) -> bool {
    (0..3).any(|k| segment_hits_triangle(t[k], t[(k + 1) % 3], u[0], u[1], u[2]))
        || (0..3).any(|k| segment_hits_triangle(u[k], u[(k + 1) % 3], t[0], t[1], t[2]))
}

/// Intersecting pairs `(i, j)`, `i < j`, of faces that share no vertex, in ascending order.
pub fn self_intersecting_pairs(positions: &[DVec3], triangles: &[[u32; 3]]) -> Vec<(u32, u32)> {
    let bvh = TriangleBvh::new(positions, triangles);
    let mut out = Vec::new();
    let mut cand = Vec::new();
    for (i, ti) in triangles.iter().enumerate() {
        let pi = ti.map(|v| positions[v as usize]);
        let (min, max) = (pi[0].min(pi[1]).min(pi[2]), pi[0].max(pi[1]).max(pi[2]));
        cand.clear();
        bvh.bvh().for_each_overlap(min, max, |j| {
            if j as usize > i {
                cand.push(j)
            }
        });
        cand.sort_unstable();
        for &j in &cand {
            let tj = triangles[j as usize];
            if ti.iter().any(|v| tj.contains(v)) {
                continue;
            }
            if triangles_intersect(pi, tj.map(|v| positions[v as usize])) {
                out.push((i as u32, j));
            }
        }
    }
    out
}

/// Number of intersecting non-adjacent face pairs (0 for a clean surface).
pub fn count_self_intersections(positions: &[DVec3], triangles: &[[u32; 3]]) -> usize {
    self_intersecting_pairs(positions, triangles).len()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::icosphere::icosphere;

    #[test]
    fn sphere_is_clean_two_spheres_overlap() {
        let m = icosphere(3, 1.0, DVec3::ZERO).unwrap();
        let (p, t) = (m.positions().to_vec(), m.triangles());
        assert_eq!(count_self_intersections(&p, &t), 0);
        // A second sphere shifted by 1: the two surfaces cross along a circle.
        let mut p2 = p.clone();
        p2.extend(p.iter().map(|q| *q + DVec3::new(1.0, 0.0, 0.0)));
        let n = p.len() as u32;
        let mut t2 = t.clone();
        t2.extend(t.iter().map(|f| f.map(|v| v + n)));
        let k = count_self_intersections(&p2, &t2);
        assert!(k > 20, "{k}");
        // Crossing triangles vs. separated ones.
        let a = [DVec3::ZERO, DVec3::X, DVec3::Y];
        let b = [
            DVec3::new(0.2, 0.2, -1.0),
            DVec3::new(0.2, 0.2, 1.0),
            DVec3::new(0.9, 0.9, 0.0),
        ];
        assert!(triangles_intersect(a, b));
        let c = b.map(|q| q + DVec3::new(2.0, 0.0, 0.0));
        assert!(!triangles_intersect(a, c));
    }
}
