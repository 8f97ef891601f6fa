//! The parts of a point set that lie apart: the connected groups of occupied cells of a coarse
//! grid (cells touching by a face, an edge or a corner). Two points in parts apart are farther
//! from each other than one cell; two parts nearer than that share a group. A cloud of two
//! objects set apart is two parts; one object is one part however it curves, since its samples
//! are far denser than the cells.
//!
//! Cost: a pass over the points and two over the cells (at most [`MOST_CELLS`]), and one more
//! over the points to label them where there are several parts.

use crate::mesh::disjoint::DisjointSets;
use glam::DVec3;

/// The grid has at most this many cells (it is coarse by design).
pub const MOST_CELLS: usize = 1 << 18;

/// The part of each point (numbered in the order of their first point) and the number of parts,
/// on a grid of cubic cells of side `cell` over the points' box; `None` for no points, a
/// non-finite point or cell, or a grid over [`MOST_CELLS`].
pub fn parts_apart(points: &[DVec3], cell: f64) -> Option<(Vec<u32>, usize)> {
    let first = *points.first()?;
    let (lo, hi) = points
        .iter()
        .fold((first, first), |(lo, hi), &p| (lo.min(p), hi.max(p)));
    if !(cell > 0.0 && lo.is_finite() && hi.is_finite()) {
        return None;
    }
    let span = ((hi - lo) / cell).floor();
    if span.max_element() >= MOST_CELLS as f64 {
        return None;
    }
    let dims = [
        span.x as usize + 1,
        span.y as usize + 1,
        span.z as usize + 1,
    ];
    let n = dims[0] * dims[1] * dims[2];
    if n > MOST_CELLS {
        return None;
    }
    let cell_of = |p: DVec3| {
        let c = ((p - lo) / cell).floor();
        let at = |k: usize| (c[k].max(0.0) as usize).min(dims[k] - 1);
        at(0) + dims[0] * (at(1) + dims[1] * at(2))
    };
    // (The cells found once, in parallel natively.)
    let keys: Vec<u32> = crate::parallel::map(points.len(), |i| cell_of(points[i]) as u32);
    let mut occupied = vec![false; n];
    for &k in &keys {
        occupied[k as usize] = true;
    }
    let mut sets = DisjointSets::new(n);
    let (dx, dy, dz) = (dims[0] as i64, dims[1] as i64, dims[2] as i64);
    for z in 0..dz {
        for y in 0..dy {
            for x in 0..dx {
                let i = (x + dx * (y + dy * z)) as usize;
                if !occupied[i] {
                    continue;
                }
                for (ox, oy, oz) in FORWARD {
                    let (u, v, w) = (x + ox, y + oy, z + oz);
                    if (0..dx).contains(&u) && (0..dy).contains(&v) && (0..dz).contains(&w) {
                        let j = (u + dx * (v + dy * w)) as usize;
                        if occupied[j] {
                            sets.union(i as u32, j as u32);
                        }
                    }
                }
            }
        }
    }
    // One part (the usual case): every point's label is 0, as numbering them would give.
    let roots = (0..n).filter(|&i| occupied[i] && sets.find(i as u32) as usize == i);
    if roots.take(2).count() == 1 {
        return Some((vec![0; points.len()], 1));
    }
    let mut number = vec![u32::MAX; n];
    let mut parts = 0;
    let labels = keys
        .iter()
        .map(|&k| {
            let root = sets.find(k) as usize;
            if number[root] == u32::MAX {
                number[root] = parts;
                parts += 1;
            }
            number[root]
        })
        .collect();
    Some((labels, parts as usize))
}

/// Half of the 26 neighbour offsets (the other half is reached from the other cell).
const FORWARD: [(i64, i64, i64); 13] = [
    (1, 0, 0),
    (-1, 1, 0),
    (0, 1, 0),
    (1, 1, 0),
    (-1, -1, 1),
    (0, -1, 1),
    (1, -1, 1),
    (-1, 0, 1),
    (0, 0, 1),
    (1, 0, 1),
    (-1, 1, 1),
    (0, 1, 1),
    (1, 1, 1),
];

#[cfg(test)]
mod tests {
    use super::*;

    /// Points on two unit spheres: 3 apart they are two parts at cells of 0.5, one at cells of 2;
    /// a diagonal chain of points one cell apart stays one part.
    #[test]
    fn spheres_apart_are_two_parts_and_a_chain_is_one() {
        let mut rng = crate::demo::Rng::new(5);
        let sphere = |c: DVec3, rng: &mut crate::demo::Rng| {
            (0..500)
                .map(|_| {
                    let d = DVec3::new(rng.normal(), rng.normal(), rng.normal()).normalize();
                    c + d
                })
                .collect::<Vec<_>>()
        };
        let mut points = sphere(DVec3::ZERO, &mut rng);
        points.extend(sphere(DVec3::new(3.0, 1.0, -0.5), &mut rng));
        let (labels, parts) = parts_apart(&points, 0.5).unwrap();
        assert_eq!(parts, 2);
        assert!(labels[..500].iter().all(|&l| l == 0) && labels[500..].iter().all(|&l| l == 1));
        // Seen as one part, every point is in part 0.
        assert_eq!(parts_apart(&points, 2.0), Some((vec![0; 1000], 1)));
        let chain: Vec<DVec3> = (0..40).map(|k| DVec3::splat(0.3 * k as f64)).collect();
        assert_eq!(parts_apart(&chain, 0.31).unwrap().1, 1);
        assert_eq!(parts_apart(&[], 1.0), None);
        assert_eq!(parts_apart(&chain, 1e-9), None);
    }
}
