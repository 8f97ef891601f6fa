//! Exact point–triangle distance with the closest feature (vertex, edge or face).
//!
//! The closest feature is what the angle-weighted pseudo-normal sign test needs
//! (Bærentzen & Aanæs 2005): the sign of `(p − c)·n_feature` is exact for a closed,
//! consistently oriented mesh when `n_feature` is the pseudo-normal of the feature holding the
//! closest point `c`.

use glam::DVec3;

/// Which part of a triangle `[a, b, c]` holds the closest point.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum TriangleFeature {
    /// Vertex 0, 1 or 2 of the triangle.
    Vertex(u8),
    /// Edge `k` joins vertex `k` and vertex `(k + 1) % 3`.
    Edge(u8),
    /// The open interior of the face.
    Face,
}

/// The closest point on triangle `[a, b, c]` to `p`, and the feature holding it.
///
/// Ericson, *Real-Time Collision Detection*, §5.1.5 (Voronoi-region tests, no square roots);
/// exact up to rounding, also for degenerate (zero-area) triangles, which fall back to an edge or a
/// vertex.
pub fn closest_point_on_triangle(
    p: DVec3,
    a: DVec3,
    b: DVec3,
    c: DVec3,
) -> (DVec3, TriangleFeature) {
    let (q, _, feature) = closest_point_barycentric(p, a, b, c);
    (q, feature)
}

/// [`closest_point_on_triangle`] with the point's barycentric coordinates `(u, v, w)` too,
/// `point = u·a + v·b + w·c` (for interpolating per-vertex data at the closest point).
pub fn closest_point_barycentric(
    p: DVec3,
    a: DVec3,
    b: DVec3,
    c: DVec3,
) -> (DVec3, DVec3, TriangleFeature) {
    let ab = b - a;
    let ac = c - a;
    let ap = p - a;
    let d1 = ab.dot(ap);
    let d2 = ac.dot(ap);
    if d1 <= 0.0 && d2 <= 0.0 {
        return (a, DVec3::X, TriangleFeature::Vertex(0));
    }
    let bp = p - b;
    let d3 = ab.dot(bp);
    let d4 = ac.dot(bp);
    if d3 >= 0.0 && d4 <= d3 {
        return (b, DVec3::Y, TriangleFeature::Vertex(1));
    }
    let vc = d1 * d4 - d3 * d2;
    if vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0 {
        let v = d1 / (d1 - d3);
        return (
            a + v * ab,
            DVec3::new(1.0 - v, v, 0.0),
            TriangleFeature::Edge(0),
        );
    }
    let cp = p - c;
    let d5 = ab.dot(cp);
    let d6 = ac.dot(cp);
    if d6 >= 0.0 && d5 <= d6 {
        return (c, DVec3::Z, TriangleFeature::Vertex(2));
    }
    let vb = d5 * d2 - d1 * d6;
    if vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0 {
        let w = d2 / (d2 - d6);
        return (
            a + w * ac,
            DVec3::new(1.0 - w, 0.0, w),
            TriangleFeature::Edge(2),
        );
    }
    let va = d3 * d6 - d5 * d4;
    if va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0 {
        let w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
        return (
            b + w * (c - b),
            DVec3::new(0.0, 1.0 - w, w),
            TriangleFeature::Edge(1),
        );
    }
    let denom = va + vb + vc;
    if denom <= 0.0 || !denom.is_finite() {
        // Degenerate triangle not caught above (collinear with p off the line): nearest edge.
        return closest_on_edges(p, a, b, c);
    }
    let v = vb / denom;
    let w = vc / denom;
    (
        a + ab * v + ac * w,
        DVec3::new(1.0 - v - w, v, w),
        TriangleFeature::Face,
    )
}

/// Fallback for degenerate triangles: the closest point on the three edges.
fn closest_on_edges(p: DVec3, a: DVec3, b: DVec3, c: DVec3) -> (DVec3, DVec3, TriangleFeature) {
    let mut best = (a, DVec3::X, TriangleFeature::Vertex(0));
    let mut best_d = f64::INFINITY;
    for (k, (s, e)) in [(a, b), (b, c), (c, a)].into_iter().enumerate() {
        let t = segment_parameter(p, s, e);
        let q = s + t * (e - s);
        let d = (p - q).length_squared();
        if d < best_d {
            best_d = d;
            let bary = match k {
                0 => DVec3::new(1.0 - t, t, 0.0),
                1 => DVec3::new(0.0, 1.0 - t, t),
                _ => DVec3::new(t, 0.0, 1.0 - t),
            };
            best = (q, bary, TriangleFeature::Edge(k as u8));
        }
    }
    best
}

/// The point of segment `[s, e]` closest to `p`.
pub fn closest_point_on_segment(p: DVec3, s: DVec3, e: DVec3) -> DVec3 {
    s + segment_parameter(p, s, e) * (e - s)
}

/// The parameter `t ∈ [0, 1]` of the point of segment `[s, e]` closest to `p` (0 for a
/// zero-length segment).
pub fn segment_parameter(p: DVec3, s: DVec3, e: DVec3) -> f64 {
    let d = e - s;
    let l2 = d.length_squared();
    if l2 <= 0.0 {
        return 0.0;
    }
    ((p - s).dot(d) / l2).clamp(0.0, 1.0)
}

/// Squared distance from `p` to triangle `[a, b, c]`.
#[inline]
pub fn point_triangle_distance_squared(p: DVec3, a: DVec3, b: DVec3, c: DVec3) -> f64 {
    (p - closest_point_on_triangle(p, a, b, c).0).length_squared()
}

/// Distance from `p` to triangle `[a, b, c]`.
#[inline]
pub fn point_triangle_distance(p: DVec3, a: DVec3, b: DVec3, c: DVec3) -> f64 {
    point_triangle_distance_squared(p, a, b, c).sqrt()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Brute force: minimum over a fine barycentric sampling (an upper bound that converges).
    fn sampled(p: DVec3, a: DVec3, b: DVec3, c: DVec3) -> f64 {
        let n = 200;
        let mut best = f64::INFINITY;
        for i in 0..=n {
            for j in 0..=(n - i) {
                let (u, v) = (i as f64 / n as f64, j as f64 / n as f64);
                let q = a + u * (b - a) + v * (c - a);
                best = best.min((p - q).length());
            }
        }
        best
    }

    #[test]
    fn matches_sampling_in_every_region() {
        let (a, b, c) = (
            DVec3::new(0.0, 0.0, 0.0),
            DVec3::new(1.0, 0.0, 0.0),
            DVec3::new(0.2, 0.9, 0.1),
        );
        let mut s = 12345u64;
        let mut rnd = || {
            s = s
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (s >> 11) as f64 / (1u64 << 53) as f64 * 3.0 - 1.0
        };
        for _ in 0..300 {
            let p = DVec3::new(rnd(), rnd(), rnd());
            let exact = point_triangle_distance(p, a, b, c);
            let approx = sampled(p, a, b, c);
            assert!(exact <= approx + 1e-12, "{p:?}: {exact} > {approx}");
            assert!(approx - exact < 1e-2, "{p:?}: {exact} vs {approx}");
        }
    }

    #[test]
    fn features() {
        let (a, b, c) = (DVec3::ZERO, DVec3::X, DVec3::Y);
        let f = |p| closest_point_on_triangle(p, a, b, c).1;
        assert_eq!(f(DVec3::new(-1.0, -1.0, 0.5)), TriangleFeature::Vertex(0));
        assert_eq!(f(DVec3::new(2.0, -0.1, 0.0)), TriangleFeature::Vertex(1));
        assert_eq!(f(DVec3::new(-0.1, 2.0, 0.0)), TriangleFeature::Vertex(2));
        assert_eq!(f(DVec3::new(0.5, -1.0, 0.0)), TriangleFeature::Edge(0));
        assert_eq!(f(DVec3::new(1.0, 1.0, 0.3)), TriangleFeature::Edge(1));
        assert_eq!(f(DVec3::new(-1.0, 0.5, 0.0)), TriangleFeature::Edge(2));
        assert_eq!(f(DVec3::new(0.2, 0.2, 1.0)), TriangleFeature::Face);
        // Degenerate (collinear) triangle.
        let d = point_triangle_distance(DVec3::new(0.5, 1.0, 0.0), a, b, 2.0 * b);
        assert!((d - 1.0).abs() < 1e-15);
    }
}
