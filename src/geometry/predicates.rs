//! Exact triangle–triangle intersection from Shewchuk's adaptive orientation predicates (the
//! `robust` crate): the answer is the true one for the given floating-point coordinates, however
//! close to degenerate, so a self-intersection count built on it cannot miss a pair that only
//! touches or report one that does not.
//!
//! Triangles are closed sets (boundaries count). Two faces of one mesh that share a vertex or an
//! edge always meet there; [`faces_intersect`] asks whether they meet *anywhere else*, which is
//! what a fold-over or a sheet passing through its neighbour looks like (the definition of CGAL's
//! `does_self_intersect`).

use glam::DVec3;
use robust::{orient2d, orient3d, Coord, Coord3D};
use std::cmp::Ordering;

#[inline]
fn c3(p: DVec3) -> Coord3D<f64> {
    Coord3D {
        x: p.x,
        y: p.y,
        z: p.z,
    }
}

/// Sign of the orientation of `d` relative to the plane through `a, b, c`: `Greater` when `d`
/// lies below the plane (the side where `a, b, c` appear clockwise, Shewchuk's convention),
/// `Equal` when the four points are coplanar. Exact.
#[inline]
pub fn orient3d_sign(a: DVec3, b: DVec3, c: DVec3, d: DVec3) -> Ordering {
    orient3d(c3(a), c3(b), c3(c), c3(d))
        .partial_cmp(&0.0)
        .unwrap_or(Ordering::Equal)
}

/// The two coordinates kept when points of a plane with normal `n` are projected along its
/// dominant axis (orientation signs in the projection equal those in the plane, up to one global
/// sign, as long as the dropped component of `n` is non-zero).
#[inline]
fn projection_axes(n: DVec3) -> (usize, usize) {
    let a = n.abs();
    if a.x >= a.y && a.x >= a.z {
        (1, 2)
    } else if a.y >= a.z {
        (2, 0)
    } else {
        (0, 1)
    }
}

#[inline]
fn c2(p: DVec3, (i, j): (usize, usize)) -> Coord<f64> {
    Coord { x: p[i], y: p[j] }
}

#[inline]
fn o2(a: DVec3, b: DVec3, c: DVec3, ax: (usize, usize)) -> Ordering {
    orient2d(c2(a, ax), c2(b, ax), c2(c, ax))
        .partial_cmp(&0.0)
        .unwrap_or(Ordering::Equal)
}

/// True when all three orderings are ≥ 0 or all are ≤ 0 (a point inside or on a triangle's
/// boundary, or a line through it).
#[inline]
fn same_side(s: [Ordering; 3]) -> bool {
    !s.contains(&Ordering::Less) || !s.contains(&Ordering::Greater)
}

/// 2-D closed segment–segment test in the projection `ax`.
fn segments_meet_2d(p: DVec3, q: DVec3, a: DVec3, b: DVec3, ax: (usize, usize)) -> bool {
    let (d1, d2) = (o2(a, b, p, ax), o2(a, b, q, ax));
    let (d3, d4) = (o2(p, q, a, ax), o2(p, q, b, ax));
    // Strictly on one side of the other's line: no contact.
    if (d1 == d2 && d1 != Ordering::Equal) || (d3 == d4 && d3 != Ordering::Equal) {
        return false;
    }
    if d1 != Ordering::Equal || d2 != Ordering::Equal {
        // The lines cross in one point, which both straddle tests put inside both segments.
        return true;
    }
    // Collinear: overlap of the coordinate ranges.
    let on = |x: DVec3, s: DVec3, t: DVec3| {
        let (i, j) = ax;
        x[i] >= s[i].min(t[i])
            && x[i] <= s[i].max(t[i])
            && x[j] >= s[j].min(t[j])
            && x[j] <= s[j].max(t[j])
    };
    on(p, a, b) || on(q, a, b) || on(a, p, q) || on(b, p, q)
}

/// 2-D closed point-in-triangle test in the projection `ax`.
fn point_in_triangle_2d(p: DVec3, t: [DVec3; 3], ax: (usize, usize)) -> bool {
    same_side([
        o2(t[0], t[1], p, ax),
        o2(t[1], t[2], p, ax),
        o2(t[2], t[0], p, ax),
    ])
}

/// Closed segment `[p, q]` against closed triangle `t` (non-degenerate). Exact.
pub fn segment_meets_triangle(p: DVec3, q: DVec3, t: [DVec3; 3]) -> bool {
    let [a, b, c] = t;
    let (sp, sq) = (orient3d_sign(a, b, c, p), orient3d_sign(a, b, c, q));
    if sp != Ordering::Equal && sp == sq {
        return false;
    }
    if sp == Ordering::Equal && sq == Ordering::Equal {
        // The segment lies in the triangle's plane.
        let ax = projection_axes((b - a).cross(c - a));
        return point_in_triangle_2d(p, t, ax)
            || point_in_triangle_2d(q, t, ax)
            || segments_meet_2d(p, q, a, b, ax)
            || segments_meet_2d(p, q, b, c, ax)
            || segments_meet_2d(p, q, c, a, ax);
    }
    // The segment meets the plane in one point; it lies in the triangle iff the line pq passes
    // on the same side of all three edges.
    same_side([
        orient3d_sign(p, q, a, b),
        orient3d_sign(p, q, b, c),
        orient3d_sign(p, q, c, a),
    ])
}

/// Segment `[p, q]` passes through triangle `t` from one side of its plane to the other: the
/// ends lie strictly on opposite sides, and the line meets the closed triangle. A segment that
/// only touches the plane (an end on it, or lying in it) does not cross. Exact.
pub fn segment_crosses_triangle(p: DVec3, q: DVec3, t: [DVec3; 3]) -> bool {
    let [a, b, c] = t;
    let (sp, sq) = (orient3d_sign(a, b, c, p), orient3d_sign(a, b, c, q));
    if sp == Ordering::Equal || sq == Ordering::Equal || sp == sq {
        return false;
    }
    same_side([
        orient3d_sign(p, q, a, b),
        orient3d_sign(p, q, b, c),
        orient3d_sign(p, q, c, a),
    ])
}

/// Closed triangles `t` and `u` intersect (any configuration, coplanar included). Exact.
///
/// The intersection of two triangles, when not empty, has a point on an edge of one of them, so
/// six closed segment–triangle tests decide it (in the coplanar case a triangle inside the other
/// is caught by its edges' endpoints lying inside).
pub fn triangles_intersect(t: [DVec3; 3], u: [DVec3; 3]) -> bool {
    (0..3).any(|k| segment_meets_triangle(t[k], t[(k + 1) % 3], u))
        || (0..3).any(|k| segment_meets_triangle(u[k], u[(k + 1) % 3], t))
}

/// Faces `f` and `g` of one mesh (vertex indices into `positions`) intersect other than in the
/// vertices or edge they share. Exact.
///
/// * no shared vertex: [`triangles_intersect`];
/// * one shared vertex `v` (`f = v a b`, `g = v c d`): they meet elsewhere iff `ab` meets `g` or
///   `cd` meets `f` — the intersection of two triangles through `v` is a segment from `v` whose
///   far end lies on an edge opposite `v`;
/// * a shared edge `ab` (third vertices `c`, `d`): iff `d` lies in `f`'s plane on the same side of
///   `ab` as `c` (the two faces fold onto each other);
/// * identical vertex sets: true (a duplicated face).
pub fn faces_intersect(positions: &[DVec3], f: [u32; 3], g: [u32; 3]) -> bool {
    let p = |i: u32| positions[i as usize];
    let shared: Vec<(usize, usize)> = (0..3)
        .filter_map(|i| (0..3).find(|&j| f[i] == g[j]).map(|j| (i, j)))
        .collect();
    match shared.len() {
        0 => triangles_intersect(f.map(p), g.map(p)),
        1 => {
            let (i, j) = shared[0];
            let (a, b) = (p(f[(i + 1) % 3]), p(f[(i + 2) % 3]));
            let (c, d) = (p(g[(j + 1) % 3]), p(g[(j + 2) % 3]));
            segment_meets_triangle(a, b, g.map(p)) || segment_meets_triangle(c, d, f.map(p))
        }
        2 => {
            let fi = (0..3).find(|&i| !g.contains(&f[i])).unwrap_or(0);
            let gj = (0..3).find(|&j| !f.contains(&g[j])).unwrap_or(0);
            let (a, b) = (p(f[(fi + 1) % 3]), p(f[(fi + 2) % 3]));
            let (c, d) = (p(f[fi]), p(g[gj]));
            if orient3d_sign(a, b, c, d) != Ordering::Equal {
                return false;
            }
            let ax = projection_axes((b - a).cross(c - a));
            let (sc, sd) = (o2(a, b, c, ax), o2(a, b, d, ax));
            sc == sd || sd == Ordering::Equal
        }
        _ => true,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const T: [DVec3; 3] = [DVec3::ZERO, DVec3::X, DVec3::Y];

    fn v(x: f64, y: f64, z: f64) -> DVec3 {
        DVec3::new(x, y, z)
    }

    #[test]
    fn crossing_separated_and_touching() {
        let crossing = [v(0.2, 0.2, -1.0), v(0.2, 0.2, 1.0), v(0.9, 0.9, 0.0)];
        assert!(triangles_intersect(T, crossing));
        assert!(!triangles_intersect(
            T,
            crossing.map(|q| q + 2.0 * DVec3::X)
        ));
        // A vertex exactly on the other triangle's interior, edge, corner: touching counts.
        for tip in [v(0.25, 0.25, 0.0), v(0.5, 0.0, 0.0), v(0.0, 0.0, 0.0)] {
            let u = [tip, tip + v(0.0, 0.0, 1.0), tip + v(0.3, -0.7, 1.0)];
            assert!(triangles_intersect(T, u), "{tip}");
        }
        // Just above (one ulp-scale gap at 1e-300 away is still a gap).
        let tip = v(0.25, 0.25, 1e-300);
        let u = [tip, tip + v(0.0, 0.0, 1.0), tip + v(0.3, -0.7, 1.0)];
        assert!(!triangles_intersect(T, u));
    }

    #[test]
    fn coplanar_cases() {
        // Overlapping, contained, edge-touching, disjoint — all in z = 0.
        let overlap = [v(0.5, 0.5, 0.0), v(-0.5, 0.2, 0.0), v(0.2, -0.5, 0.0)];
        assert!(triangles_intersect(T, overlap));
        let inside = [v(0.1, 0.1, 0.0), v(0.3, 0.1, 0.0), v(0.1, 0.3, 0.0)];
        assert!(triangles_intersect(T, inside));
        assert!(triangles_intersect(inside, T));
        let touching = [v(1.0, 0.0, 0.0), v(2.0, 0.0, 0.0), v(1.0, 1.0, 0.0)];
        assert!(triangles_intersect(T, touching));
        let disjoint = touching.map(|q| q + 0.01 * DVec3::X);
        assert!(!triangles_intersect(T, disjoint));
    }

    #[test]
    fn near_degenerate_is_exact() {
        // A segment crossing the plane at a point 1e-17 inside an edge: float arithmetic in
        // Möller–Trumbore can land on either side; the predicates cannot.
        let e = 1e-17;
        let p = v(0.5, e, -1.0);
        let q = v(0.5, e, 1.0);
        assert!(segment_meets_triangle(p, q, T));
        assert!(!segment_meets_triangle(
            v(0.5, -e, -1.0),
            v(0.5, -e, 1.0),
            T
        ));
    }

    #[test]
    fn adjacent_faces() {
        // Shared edge 0-1: the fourth vertex below (a fold of 90°), in the plane on the other
        // side (flat, fine), in the plane on the same side (folded onto f).
        let pos = vec![
            v(0.0, 0.0, 0.0),
            v(1.0, 0.0, 0.0),
            v(0.0, 1.0, 0.0),
            v(0.5, 0.0, -1.0),
            v(0.5, -1.0, 0.0),
            v(0.3, 0.3, 0.0),
        ];
        let f = [0, 1, 2];
        assert!(!faces_intersect(&pos, f, [1, 0, 3]));
        assert!(!faces_intersect(&pos, f, [1, 0, 4]));
        assert!(faces_intersect(&pos, f, [1, 0, 5]));
        // Shared vertex 0: g's far edge pierces f; g rises away from f.
        let pos2 = vec![
            v(0.0, 0.0, 0.0),
            v(1.0, 0.0, 0.0),
            v(0.0, 1.0, 0.0),
            v(0.3, 0.3, -1.0),
            v(0.3, 0.3, 1.0),
            v(-0.3, -0.3, 1.0),
            v(-0.3, 0.3, 1.0),
        ];
        assert!(faces_intersect(&pos2, [0, 1, 2], [0, 3, 4]));
        assert!(!faces_intersect(&pos2, [0, 1, 2], [0, 5, 6]));
        // Shared vertex, coplanar, wedges overlapping near the vertex.
        let pos3 = vec![
            v(0.0, 0.0, 0.0),
            v(1.0, 0.0, 0.0),
            v(0.0, 1.0, 0.0),
            v(1.0, 1.0, 0.0),
            v(-1.0, 0.5, 0.0),
        ];
        assert!(faces_intersect(&pos3, [0, 1, 2], [0, 3, 4]));
        assert!(!faces_intersect(&pos3, [0, 1, 2], [0, 2, 4]));
    }
}
