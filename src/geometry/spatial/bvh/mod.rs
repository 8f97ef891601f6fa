//! A bounding-volume hierarchy over triangles or points, with exact closest-point queries and box
//! overlap queries (the acceleration behind distances, back-projection and the self-intersection
//! count).
//!
//! Built top-down by median split along the widest centroid axis (leaves of ≤ 4 primitives);
//! deterministic for a given input. Queries visit the nearer child first and prune by the
//! squared box distance, so results are exact, not approximate.
//!
//! The builders are in `build`, the box queries in `query`; [`TriangleBvh`] and [`PointBvh`]
//! wrap the tree for triangle sets and point clouds.

// `!(x > y)` is used deliberately: it is also true when x is NaN.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

mod build;
mod points;
mod query;
mod triangles;

pub use points::PointBvh;
pub use triangles::{closest_point_on_triangle, ClosestHit, TriangleBvh};

use glam::DVec3;

/// Primitives per leaf at most in [`Bvh::new`].
const LEAF_SIZE: usize = 4;

/// One node: its box and either two children or a run of primitives.
#[derive(Clone, Copy, Debug)]
struct Node {
    min: DVec3,
    max: DVec3,
    /// Inner node: index of the left child. Leaf: first index into `order`.
    start: u32,
    /// Leaf: primitive count; 0 for an inner node.
    count: u32,
    /// Inner node: right child.
    right: u32,
}

impl Node {
    /// A node whose box and links the builder fills in later.
    const PLACEHOLDER: Node = Node {
        min: DVec3::ZERO,
        max: DVec3::ZERO,
        start: 0,
        count: 0,
        right: 0,
    };
}

/// A BVH over primitives given by their boxes. Primitive ids are indices into the input.
#[derive(Clone, Debug, Default)]
pub struct Bvh {
    nodes: Vec<Node>,
    order: Vec<u32>,
}

/// The squared distance from `p` to the box `[min, max]` (0 inside).
#[inline]
fn box_dist2(p: DVec3, min: DVec3, max: DVec3) -> f64 {
    let d = (min - p).max(p - max).max(DVec3::ZERO);
    d.length_squared()
}

#[cfg(test)]
mod tests {
    use super::build::{halving_tree_nodes, Boxes, PARALLEL_BUILD};
    use super::*;

    /// Both builders fill their node lists exactly to the capacity counted up front: no list
    /// outgrows it (and doubles), none is left half empty.
    #[test]
    fn the_node_lists_are_counted_exactly() {
        let mut seed = 3u64;
        let mut rnd = move || {
            seed = seed.wrapping_mul(6364136223846793005).wrapping_add(1);
            (seed >> 11) as f64 / (1u64 << 53) as f64
        };
        for n in [1, 2, 4, 5, 7, 100, 1000, 4095, 4096, 10_007, 65_536] {
            let mins: Vec<DVec3> = (0..n).map(|_| DVec3::new(rnd(), rnd(), rnd())).collect();
            let maxs: Vec<DVec3> = mins.iter().map(|&m| m + 0.01).collect();
            for leaf in [1, 2, 4] {
                let bvh = Bvh::new_morton(&mins, &maxs, leaf);
                assert_eq!(bvh.nodes.len(), halving_tree_nodes(n, leaf), "{n} {leaf}");
                assert_eq!(bvh.nodes.capacity(), bvh.nodes.len(), "{n} {leaf}");
            }
            let bvh = Bvh::new(&mins, &maxs);
            assert_eq!(bvh.nodes.len(), halving_tree_nodes(n, LEAF_SIZE), "{n}");
        }
        // By hand: 9 primitives in leaves of up to 2 split 4 + 5, then 2 + 2 and 2 + 3, and the 3
        // into 1 + 2: 1 + 2 + 4 + 2 nodes.
        assert_eq!(halving_tree_nodes(9, 2), 9);
    }

    #[test]
    fn inside_means_an_odd_number_of_crossings_or_a_winding_and_touching_is_no_crossing() {
        let ball = crate::geometry::icosphere::icosphere(1, 1.0, DVec3::ZERO).unwrap();
        let bvh = TriangleBvh::new(ball.positions(), &ball.triangles());
        assert!(bvh.encloses(DVec3::ZERO));
        assert!(bvh.encloses(DVec3::new(0.5, -0.3, 0.2)));
        assert!(!bvh.encloses(DVec3::new(1.5, 0.0, 0.0)));
        assert!(!bvh.encloses(DVec3::new(0.0, -2.0, 0.3)));
        // Two overlapping balls: in the overlap a ray leaves both (even parity), but the
        // winding number is 2.
        let other =
            crate::geometry::icosphere::icosphere(1, 1.0, DVec3::new(1.2, 0.0, 0.0)).unwrap();
        let n = ball.n_vertices() as u32;
        let pos: Vec<DVec3> = ball
            .positions()
            .iter()
            .chain(other.positions())
            .copied()
            .collect();
        let tris: Vec<[u32; 3]> = ball
            .triangles()
            .into_iter()
            .chain(other.triangles().into_iter().map(|t| t.map(|v| v + n)))
            .collect();
        let both = TriangleBvh::new(&pos, &tris);
        assert!(both.encloses(DVec3::new(0.6, 0.05, -0.02)));
        assert!(both.encloses(DVec3::new(-0.5, 0.0, 0.1)));
        assert!(!both.encloses(DVec3::new(0.6, 1.5, 0.0)));
        assert!(bvh.crosses(DVec3::ZERO, DVec3::new(0.0, 0.0, 2.0)));
        assert!(!bvh.crosses(DVec3::ZERO, DVec3::new(0.1, 0.2, 0.3)));
        // From a vertex of the mesh outwards: it touches, it does not cross.
        let v = ball.position(0);
        assert!(!bvh.crosses(v, 2.0 * v));
    }

    fn rng(seed: u64) -> impl FnMut() -> f64 {
        let mut s = seed;
        move || {
            s = s
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (s >> 11) as f64 / (1u64 << 53) as f64
        }
    }

    #[test]
    fn triangle_closest_point_matches_brute_force() {
        let mut r = rng(7);
        let pts: Vec<DVec3> = (0..300).map(|_| DVec3::new(r(), r(), r())).collect();
        let tris: Vec<[u32; 3]> = (0..100).map(|i| [3 * i, 3 * i + 1, 3 * i + 2]).collect();
        let bvh = TriangleBvh::new(&pts, &tris);
        for _ in 0..200 {
            let p = DVec3::new(2.0 * r() - 0.5, 2.0 * r() - 0.5, 2.0 * r() - 0.5);
            let brute = tris
                .iter()
                .map(|t| {
                    let [a, b, c] = t.map(|v| pts[v as usize]);
                    (closest_point_on_triangle(p, a, b, c).0 - p).length_squared()
                })
                .fold(f64::INFINITY, f64::min);
            let hit = bvh.closest_point(p).unwrap();
            assert_eq!(hit.distance_squared, brute);
            let [a, b, c] = tris[hit.triangle as usize].map(|v| pts[v as usize]);
            let q = hit.barycentric.x * a + hit.barycentric.y * b + hit.barycentric.z * c;
            assert!((q - hit.point).length() < 1e-12);
        }
        let cloud = PointBvh::new(&pts);
        for _ in 0..200 {
            let p = DVec3::new(r(), r(), r());
            let brute = pts
                .iter()
                .map(|q| (*q - p).length_squared())
                .fold(f64::INFINITY, f64::min);
            assert_eq!(cloud.nearest(p).unwrap().1, brute);
        }
    }

    /// Above [`PARALLEL_BUILD`] the root's halves are built apart: the tree is the one a
    /// single thread builds (the same boxes, leaves and order, read depth-first), and nearest
    /// queries agree with brute force.
    #[test]
    fn a_tree_built_in_two_halves_is_the_one_built_whole() {
        let mut r = rng(11);
        let n = 3 * PARALLEL_BUILD;
        let mins: Vec<DVec3> = (0..n).map(|_| DVec3::new(r(), r(), 0.3 * r())).collect();
        let maxs: Vec<DVec3> = mins
            .iter()
            .map(|&m| m + 0.01 * DVec3::new(r(), r(), r()))
            .collect();
        let centroids: Vec<DVec3> = mins
            .iter()
            .zip(&maxs)
            .map(|(a, b)| 0.5 * (*a + *b))
            .collect();
        let boxes = Boxes {
            mins: &mins,
            maxs: &maxs,
            centroids: &centroids,
        };
        let mut order: Vec<u32> = (0..n as u32).collect();
        let whole = Bvh {
            nodes: boxes.subtree(&mut order, 0),
            order,
        };
        let halves = Bvh::new(&mins, &maxs);
        assert_eq!(halves.order, whole.order);
        // Depth-first, left first: (box, leaf range) of every node.
        fn walk(b: &Bvh, ni: usize, out: &mut Vec<(DVec3, DVec3, u32, u32)>) {
            let node = b.nodes[ni];
            if node.count > 0 {
                out.push((node.min, node.max, node.start, node.count));
            } else {
                out.push((node.min, node.max, u32::MAX, 0));
                walk(b, node.start as usize, out);
                walk(b, node.right as usize, out);
            }
        }
        let (mut a, mut b) = (Vec::new(), Vec::new());
        walk(&whole, 0, &mut a);
        walk(&halves, 0, &mut b);
        assert!(a.len() > 100);
        assert_eq!(a, b);
        for _ in 0..100 {
            let p = DVec3::new(r(), r(), r());
            let d2 = |i: u32| {
                let (lo, hi) = (mins[i as usize], maxs[i as usize]);
                box_dist2(p, lo, hi)
            };
            let brute = (0..n as u32).map(d2).fold(f64::INFINITY, f64::min);
            assert_eq!(halves.nearest(p, d2).unwrap().1, brute);
        }
    }

    #[test]
    fn closest_point_regions() {
        let (a, b, c) = (DVec3::ZERO, DVec3::X, DVec3::Y);
        let q = closest_point_on_triangle(DVec3::new(0.2, 0.2, 1.0), a, b, c).0;
        assert!((q - DVec3::new(0.2, 0.2, 0.0)).length() < 1e-15);
        assert_eq!(
            closest_point_on_triangle(DVec3::new(-1.0, -1.0, 0.0), a, b, c).0,
            a
        );
        assert_eq!(
            closest_point_on_triangle(DVec3::new(1.0, 1.0, 0.0), a, b, c).0,
            DVec3::new(0.5, 0.5, 0.0)
        );
    }

    /// The warm-started batch gives each point the hit of its own query, ties included: on a
    /// grid of unit squares (two triangles each, many at equal distance from a query) queried
    /// along a path and at random, without a bound and with one.
    #[test]
    fn batched_closest_points_are_the_single_queries() {
        let n = 12u32;
        let pts: Vec<DVec3> = (0..=n)
            .flat_map(|j| (0..=n).map(move |i| DVec3::new(i as f64, j as f64, 0.0)))
            .collect();
        let at = |i: u32, j: u32| j * (n + 1) + i;
        let tris: Vec<[u32; 3]> = (0..n)
            .flat_map(|j| (0..n).map(move |i| (i, j)))
            .flat_map(|(i, j)| {
                let q = [at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1)];
                [[q[0], q[1], q[2]], [q[0], q[2], q[3]]]
            })
            .collect();
        let grid = TriangleBvh::new(&pts, &tris);
        let mut r = rng(3);
        let mut queries: Vec<DVec3> = (0..200)
            .map(|k| DVec3::new(0.05 * k as f64, 0.5 * (k % 7) as f64, 0.5))
            .collect();
        queries.extend((0..200).map(|_| DVec3::new(14.0 * r() - 1.0, 14.0 * r() - 1.0, r())));
        for (bvh, bound) in [(&grid, f64::INFINITY), (&grid, 0.7)] {
            let batch = bvh.closest_points_within(queries.len(), |i| queries[i], bound);
            for (q, hit) in queries.iter().zip(&batch) {
                assert_eq!(*hit, bvh.closest_point_within(*q, bound));
            }
        }
    }
}
