//! Self-intersection count: pairs of faces of one mesh that meet anywhere other than in the
//! vertices or edge they share, decided by exact predicates
//! ([`crate::geometry::predicates::faces_intersect`]) — the definition of CGAL's
//! `does_self_intersect`, so adjacent faces folded onto each other count too.
//!
//! Broad phase: a uniform grid over the face boxes (a BVH where their sizes vary too much);
//! every pair of overlapping boxes is tested once. A
//! cheap floating-point plane-side filter with a safe margin rejects most pairs before the exact
//! test (it only ever says "certainly apart").

// `!(x > y)` is used deliberately: it is also true when x is NaN.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

use crate::geometry::predicates::faces_intersect;
use crate::geometry::spatial::box_grid;
use crate::geometry::spatial::bvh::Bvh;
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

/// True when a plane through an edge of `t`, square to `t`, has all of `u` strictly on the far
/// side (by a margin over rounding): then they cannot meet. Faces in one plane — a machined
/// part's flat sides — are never apart by [`certainly_apart`], and would take the exact coplanar
/// test.
#[inline]
fn apart_across_an_edge(t: [DVec3; 3], u: [DVec3; 3]) -> bool {
    let n = (t[1] - t[0]).cross(t[2] - t[0]);
    (0..3).any(|k| {
        let (a, b, c) = (t[k], t[(k + 1) % 3], t[(k + 2) % 3]);
        // Points towards `c`'s side.
        let m = n.cross(b - a);
        let scale = m.length() * {
            let d = u.map(|q| (q - a).abs().max_element());
            d[0].max(d[1]).max(d[2]).max((c - a).abs().max_element())
        };
        let eps = 1e-12 * scale;
        m.dot(c - a) > eps && u.iter().all(|&q| m.dot(q - a) < -eps)
    })
}

#[inline]
fn same_side_certainly(n: DVec3, o: DVec3, p: DVec3, q: DVec3) -> bool {
    let (sp, sq) = (n.dot(p - o), n.dot(q - o));
    let eps = 1e-12 * n.length() * (p - o).abs().max(q - o).abs().max_element();
    (sp > eps && sq > eps) || (sp < -eps && sq < -eps)
}

/// Faces `i`, `j` intersect (see the module docs); exact, with floating-point filters first that
/// only ever answer "certainly not".
#[inline]
pub fn pair_intersects(positions: &[DVec3], triangles: &[[u32; 3]], i: usize, j: usize) -> bool {
    let (fi, fj) = (triangles[i], triangles[j]);
    let p = |v: u32| positions[v as usize];
    let si = fi.map(|v| fj.contains(&v));
    match si.iter().filter(|&&b| b).count() {
        0 => {
            let (pi, pj) = (fi.map(p), fj.map(p));
            if certainly_apart(pi, pj)
                || certainly_apart(pj, pi)
                || apart_across_an_edge(pi, pj)
                || apart_across_an_edge(pj, pi)
            {
                return false;
            }
        }
        1 => {
            // f = v a b, g = v c d: they meet elsewhere only if ab reaches g's plane or cd f's.
            let k = si.iter().position(|&b| b).unwrap_or(0);
            let (v, a, b) = (p(fi[k]), p(fi[(k + 1) % 3]), p(fi[(k + 2) % 3]));
            let l = fj.iter().position(|&w| w == fi[k]).unwrap_or(0);
            let (c, d) = (p(fj[(l + 1) % 3]), p(fj[(l + 2) % 3]));
            let (nf, ng) = ((a - v).cross(b - v), (c - v).cross(d - v));
            if same_side_certainly(ng, v, a, b) && same_side_certainly(nf, v, c, d) {
                return false;
            }
        }
        2 => {
            // A shared edge: only a coplanar fourth vertex can fold onto the other face.
            let k = si.iter().position(|&b| !b).unwrap_or(0);
            let (c, a, b) = (p(fi[k]), p(fi[(k + 1) % 3]), p(fi[(k + 2) % 3]));
            let d = p(*fj.iter().find(|w| !fi.contains(w)).unwrap_or(&fj[0]));
            let n = (a - c).cross(b - c);
            let scale = n.length() * (d - c).length();
            if n.dot(d - c).abs() > 1e-12 * scale {
                return false;
            }
        }
        _ => {}
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

/// Every pair of faces `(i, j)`, `i < j`, whose boxes overlap and that `keep` keeps, each pair
/// once, in no particular order: by a uniform grid ([`box_grid`]), or by a BVH where the faces'
/// sizes vary too much for one.
pub fn overlapping_pairs(
    positions: &[DVec3],
    triangles: &[[u32; 3]],
    keep: impl Fn(usize, usize) -> bool + Sync,
) -> Vec<(u32, u32)> {
    let (mins, maxs) = face_boxes(positions, triangles);
    if let Some(pairs) =
        box_grid::overlapping_pairs(&mins, &maxs, |i, j| keep(i as usize, j as usize))
    {
        return pairs;
    }
    let bvh = Bvh::new_morton(&mins, &maxs, 2);
    // Boxes in tree order, so the leaf pairs read neighbouring memory.
    let order = bvh.order();
    let boxes: Vec<(DVec3, DVec3)> = order
        .iter()
        .map(|&i| (mins[i as usize], maxs[i as usize]))
        .collect();
    // (The tree walk is sequential: the pairs first, then `keep` on them in parallel.)
    let mut all = Vec::new();
    bvh.for_each_self_overlap_slots(|a, b| {
        let ((amin, amax), (bmin, bmax)) = (boxes[a], boxes[b]);
        if !(amin.cmpgt(bmax).any() || amax.cmplt(bmin).any()) {
            let (i, j) = (order[a], order[b]);
            all.push((i.min(j), i.max(j)));
        }
    });
    let kept = crate::parallel::map(all.len(), |k| keep(all[k].0 as usize, all[k].1 as usize));
    all.into_iter()
        .zip(kept)
        .filter_map(|(pair, kept)| kept.then_some(pair))
        .collect()
}

/// Vertices whose fan of faces may fold onto itself. A closed fan whose faces, projected along
/// the fan's area-weighted normal, all turn the same way (by a safe margin) and go round
/// exactly once tiles its disc: no two of its faces meet other than along their shared edges,
/// so the adjacent pairs at that vertex need no exact test. Everything else is suspect.
fn suspect_fans(positions: &[DVec3], triangles: &[[u32; 3]]) -> Vec<bool> {
    let n = positions.len();
    let mut normal = vec![DVec3::ZERO; n];
    let mut count = vec![0u32; n];
    for t in triangles {
        let p = t.map(|v| positions[v as usize]);
        let a = (p[1] - p[0]).cross(p[2] - p[0]);
        for &v in t {
            normal[v as usize] += a;
            count[v as usize] += 1;
        }
    }
    // Frames of the projection planes.
    let frames: Vec<(DVec3, DVec3)> = normal
        .iter()
        .map(|m| {
            let m = m.normalize_or_zero();
            let x = m.any_orthonormal_vector();
            (x, m.cross(x))
        })
        .collect();
    let mut suspect: Vec<bool> = normal.iter().map(|m| !(m.length() > 0.0)).collect();
    let mut winding = vec![0u32; n];
    let mut edge_balance = vec![0i64; n];
    for t in triangles {
        for k in 0..3 {
            let (v, a, b) = (t[k] as usize, t[(k + 1) % 3], t[(k + 2) % 3]);
            if suspect[v] {
                continue;
            }
            let (x, y) = frames[v];
            let o = positions[v];
            let (da, db) = (positions[a as usize] - o, positions[b as usize] - o);
            let (ua, ub) = ((da.dot(x), da.dot(y)), (db.dot(x), db.dot(y)));
            let cross = ua.0 * ub.1 - ua.1 * ub.0;
            if !(cross > 1e-9 * da.length() * db.length()) {
                suspect[v] = true;
                continue;
            }
            if ua.1 <= 0.0 && ub.1 > 0.0 {
                winding[v] += 1;
            }
            // A closed fan uses each spoke once as a start and once as an end.
            edge_balance[v] += a as i64 - b as i64;
        }
    }
    for v in 0..n {
        if count[v] > 0 && (winding[v] != 1 || edge_balance[v] != 0 || count[v] < 3) {
            suspect[v] = true;
        }
    }
    suspect
}

/// Intersecting face pairs `(i, j)`, `i < j`, in ascending order. Same answer as
/// [`self_intersecting_pairs_brute_force`], fast: pairs that share no vertex come from the BVH,
/// pairs that do are tested only around vertices whose fan may fold ([`suspect_fans`]).
pub fn self_intersecting_pairs(positions: &[DVec3], triangles: &[[u32; 3]]) -> Vec<(u32, u32)> {
    // The exact test where the pairs are found (in parallel natively), and beside it the fans
    // (sequential: a tenth of the check on its own).
    let (suspect, mut out) = crate::parallel::beside(
        || suspect_fans(positions, triangles),
        || {
            overlapping_pairs(positions, triangles, |i, j| {
                let (fi, fj) = (triangles[i], triangles[j]);
                !fi.iter().any(|v| fj.contains(v)) && pair_intersects(positions, triangles, i, j)
            })
        },
    );
    if suspect.iter().any(|&s| s) {
        let mut fans: Vec<Vec<usize>> = vec![Vec::new(); positions.len()];
        for (f, t) in triangles.iter().enumerate() {
            for &v in t {
                if suspect[v as usize] {
                    fans[v as usize].push(f);
                }
            }
        }
        for fan in &fans {
            for (k, &i) in fan.iter().enumerate() {
                for &j in &fan[k + 1..] {
                    if pair_intersects(positions, triangles, i, j) {
                        out.push((i.min(j) as u32, i.max(j) as u32));
                    }
                }
            }
        }
    }
    out.sort_unstable();
    out.dedup();
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

    #[test]
    fn agrees_with_brute_force_on_faces_in_one_plane() {
        // A flat grid (a CAD part's side), its vertices jittered within the plane: untouched,
        // faces apart across their edges; jittered far, some fold over their neighbours. Then
        // the plane tilted, so that its points are not exactly coplanar in floating point.
        let n = 8;
        let mut t = Vec::new();
        for i in 0..n {
            for j in 0..n {
                let v = |a: usize, b: usize| (a * (n + 1) + b) as u32;
                t.push([v(i, j), v(i + 1, j), v(i + 1, j + 1)]);
                t.push([v(i, j), v(i + 1, j + 1), v(i, j + 1)]);
            }
        }
        let mut rng = Rng::new(11);
        let mut folded = false;
        let tilted = (
            DVec3::new(1.0, 0.3, 0.2).normalize(),
            DVec3::new(-0.2, 1.0, 0.4).normalize(),
        );
        for (u, w) in [(DVec3::X, DVec3::Y), tilted] {
            for amp in [0.0, 0.2, 0.5, 1.0, 1.6] {
                let p: Vec<DVec3> = (0..(n + 1) * (n + 1))
                    .map(|k| {
                        let (a, b) = ((k / (n + 1)) as f64, (k % (n + 1)) as f64);
                        let x = a + amp * (rng.uniform() - 0.5);
                        let y = b + amp * (rng.uniform() - 0.5);
                        0.1 * (x * u + y * w)
                    })
                    .collect();
                let fast = self_intersecting_pairs(&p, &t);
                assert_eq!(fast, self_intersecting_pairs_brute_force(&p, &t), "{amp}");
                if amp == 0.0 {
                    assert!(fast.is_empty());
                }
                folded |= !fast.is_empty();
            }
        }
        assert!(folded, "no jitter folded a face over another");
    }
}
