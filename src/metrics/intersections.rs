//! Self-intersection count: pairs of faces of one mesh that meet anywhere other than in the
//! vertices or edge they share, decided by exact predicates
//! ([`crate::geometry::predicates::faces_intersect`]) — the definition of CGAL's
//! `does_self_intersect`, so adjacent faces folded onto each other count too.
//!
//! Broad phase: a BVH over the face boxes; every pair of overlapping boxes is tested once. A
//! cheap floating-point plane-side filter with a safe margin rejects most pairs before the exact
//! test (it only ever says "certainly apart").

use super::bvh::Bvh;
use crate::geometry::predicates::faces_intersect;
use glam::DVec3;

pub use crate::geometry::predicates::triangles_intersect;

/// True when the three points lie strictly on one side of the plane through `t`, with a margin
/// far above the rounding error of the arithmetic (so "apart" is certain).
#[inline]
fn certainly_apart(t: [DVec3; 3], u: [DVec3; 3]) -> bool {
    let n = (t[1] - t[0]).cross(t[2] - t[0]);
    let s = u.map(|q| n.dot(q - t[0]));
    let scale = n.length() * {
        let d = u.map(|q| (q - t[0]).abs().max_element());
        d[0].max(d[1]).max(d[2])
    };
    let eps = 1e-12 * scale;
    (s[0] > eps && s[1] > eps && s[2] > eps) || (s[0] < -eps && s[1] < -eps && s[2] < -eps)
}

/// Faces `i`, `j` intersect (see the module docs); exact, with the float filter first.
#[inline]
pub fn pair_intersects(positions: &[DVec3], triangles: &[[u32; 3]], i: usize, j: usize) -> bool {
    let (fi, fj) = (triangles[i], triangles[j]);
    let shared = fi.iter().filter(|v| fj.contains(v)).count();
    let (pi, pj) = (
        fi.map(|v| positions[v as usize]),
        fj.map(|v| positions[v as usize]),
    );
    // A shared vertex lies in both planes, so the plane filter cannot separate adjacent faces.
    if shared == 0 && (certainly_apart(pi, pj) || certainly_apart(pj, pi)) {
        return false;
    }
    faces_intersect(positions, fi, fj)
}

/// Face boxes `(min, max)`.
fn face_boxes(positions: &[DVec3], triangles: &[[u32; 3]]) -> (Vec<DVec3>, Vec<DVec3>) {
    triangles
        .iter()
        .map(|t| {
            let p = t.map(|v| positions[v as usize]);
            (p[0].min(p[1]).min(p[2]), p[0].max(p[1]).max(p[2]))
        })
        .unzip()
}

/// Calls `f(i, j)` (`i < j`) for every pair of faces whose boxes overlap, each pair once, in a
/// fixed order.
pub fn for_each_overlapping_pair(
    positions: &[DVec3],
    triangles: &[[u32; 3]],
    mut f: impl FnMut(usize, usize),
) {
    let (mins, maxs) = face_boxes(positions, triangles);
    let bvh = Bvh::new(&mins, &maxs);
    let mut cand = Vec::new();
    for i in 0..triangles.len() {
        cand.clear();
        bvh.for_each_overlap(mins[i], maxs[i], |j| {
            if j as usize > i {
                cand.push(j as usize)
            }
        });
        cand.sort_unstable();
        for &j in &cand {
            f(i, j);
        }
    }
}

/// Intersecting face pairs `(i, j)`, `i < j`, in ascending order.
pub fn self_intersecting_pairs(positions: &[DVec3], triangles: &[[u32; 3]]) -> Vec<(u32, u32)> {
    let mut out = Vec::new();
    for_each_overlapping_pair(positions, triangles, |i, j| {
        if pair_intersects(positions, triangles, i, j) {
            out.push((i as u32, j as u32));
        }
    });
    out
}

/// Number of intersecting face pairs (0 for a clean surface).
pub fn count_self_intersections(positions: &[DVec3], triangles: &[[u32; 3]]) -> usize {
    self_intersecting_pairs(positions, triangles).len()
}

/// The O(F²) reference: every pair, exact test only. For tests on small meshes.
pub fn self_intersecting_pairs_brute_force(
    positions: &[DVec3],
    triangles: &[[u32; 3]],
) -> Vec<(u32, u32)> {
    let mut out = Vec::new();
    for i in 0..triangles.len() {
        for j in i + 1..triangles.len() {
            if faces_intersect(positions, triangles[i], triangles[j]) {
                out.push((i as u32, j as u32));
            }
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::demo::Rng;
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
        assert_eq!(
            self_intersecting_pairs(&p2, &t2),
            self_intersecting_pairs_brute_force(&p2, &t2)
        );
    }

    #[test]
    fn agrees_with_brute_force_on_jittered_and_folded_meshes() {
        let mut rng = Rng::new(7);
        for level in [1, 2] {
            let m = icosphere(level, 1.0, DVec3::ZERO).unwrap();
            let t = m.triangles();
            for amp in [0.0, 0.05, 0.2, 0.6] {
                let p: Vec<DVec3> = m
                    .positions()
                    .iter()
                    .map(|q| {
                        let j = DVec3::new(rng.uniform(), rng.uniform(), rng.uniform());
                        *q + amp * (2.0 * j - DVec3::ONE)
                    })
                    .collect();
                let fast = self_intersecting_pairs(&p, &t);
                assert_eq!(fast, self_intersecting_pairs_brute_force(&p, &t));
                if amp == 0.0 {
                    assert!(fast.is_empty());
                }
                if amp == 0.6 {
                    assert!(!fast.is_empty());
                }
            }
        }
        // One vertex pushed through the opposite side: its fan crosses the far faces.
        let m = icosphere(2, 1.0, DVec3::ZERO).unwrap();
        let t = m.triangles();
        let mut p = m.positions().to_vec();
        p[0] = -1.3 * p[0];
        let fast = self_intersecting_pairs(&p, &t);
        assert!(!fast.is_empty());
        assert_eq!(fast, self_intersecting_pairs_brute_force(&p, &t));
    }
}
