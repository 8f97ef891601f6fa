//! Clouds sampled only along curves: cross-section contours and edges, dense along each curve
//! and empty between them, as from a slicer, a contour tracer or a wireframe. The surface they
//! stand for is the one the curves lie on; a wrap must span the gaps between them, not read
//! them as holes.

use glam::DVec3;
use std::f64::consts::{PI, TAU};

/// `n` points evenly along the circle of radius `r` about `centre` in the plane spanned by the
/// unit vectors `u` and `v`.
fn circle(centre: DVec3, u: DVec3, v: DVec3, r: f64, n: usize) -> impl Iterator<Item = DVec3> {
    (0..n).map(move |i| {
        let t = TAU * i as f64 / n as f64;
        centre + r * (crate::fmath::cos(t) * u + crate::fmath::sin(t) * v)
    })
}

/// The unit sphere along 6 great circles through the poles (30° apart) and the 5 parallels
/// z = 0, ±0.4, ±0.8: 200 points on each of the 11 circles.
pub fn sphere_curves() -> Vec<DVec3> {
    let mut pts = Vec::new();
    for k in 0..6 {
        let a = PI * k as f64 / 6.0;
        let u = DVec3::new(crate::fmath::cos(a), crate::fmath::sin(a), 0.0);
        pts.extend(circle(DVec3::ZERO, u, DVec3::Z, 1.0, 200));
    }
    for z in [-0.8, -0.4, 0.0, 0.4, 0.8] {
        let r = (1.0f64 - z * z).sqrt();
        pts.extend(circle(DVec3::Z * z, DVec3::X, DVec3::Y, r, 200));
    }
    pts
}

/// A torus (R 0.5, r 0.2) along 12 cross-sections of its tube (30° apart, 100 points each) and
/// 4 circles round its axis (the outer, inner, top and bottom equators, 300 points each).
pub fn torus_curves() -> Vec<DVec3> {
    let (big, small) = (0.5, 0.2);
    let mut pts = Vec::new();
    for k in 0..12 {
        let a = TAU * k as f64 / 12.0;
        let out = DVec3::new(crate::fmath::cos(a), crate::fmath::sin(a), 0.0);
        pts.extend(circle(big * out, out, DVec3::Z, small, 100));
    }
    for (radius, z) in [
        (big + small, 0.0),
        (big - small, 0.0),
        (big, small),
        (big, -small),
    ] {
        pts.extend(circle(DVec3::Z * z, DVec3::X, DVec3::Y, radius, 300));
    }
    pts
}

/// The 12 edges of the unit cube [0, 1]³, 60 points along each (its corners included once per
/// edge: the copies are left to the reader's deduplication).
pub fn cube_edges() -> Vec<DVec3> {
    let mut pts = Vec::new();
    for axis in 0..3 {
        let (b, c) = ((axis + 1) % 3, (axis + 2) % 3);
        for corner in 0..4 {
            for i in 0..60 {
                let mut p = [0.0; 3];
                p[axis] = i as f64 / 59.0;
                p[b] = (corner & 1) as f64;
                p[c] = (corner >> 1) as f64;
                pts.push(DVec3::from_array(p));
            }
        }
    }
    pts
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_curves_lie_on_their_surfaces() {
        let sphere = sphere_curves();
        assert_eq!(sphere.len(), 2200);
        assert!(sphere.iter().all(|p| (p.length() - 1.0).abs() < 1e-12));
        let torus = torus_curves();
        assert_eq!(torus.len(), 2400);
        for q in &torus {
            let ring = (q.x * q.x + q.y * q.y).sqrt() - 0.5;
            assert!(
                ((ring * ring + q.z * q.z).sqrt() - 0.2).abs() < 1e-12,
                "{q}"
            );
        }
        let cube = cube_edges();
        assert_eq!(cube.len(), 720);
        // On an edge: two coordinates are 0 or 1.
        for p in &cube {
            let ends = p
                .to_array()
                .iter()
                .filter(|c| **c == 0.0 || **c == 1.0)
                .count();
            assert!(ends >= 2, "{p}");
        }
    }
}
