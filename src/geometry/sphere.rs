//! Measurements of (nearly) spherical meshes, used to check MCF against r(t) = sqrt(r0² − 4t).

use glam::DVec3;

/// Mean distance of the points from their centroid.
pub fn mean_radius(points: &[DVec3]) -> f64 {
    if points.is_empty() {
        return 0.0;
    }
    let n = points.len() as f64;
    let c = points.iter().copied().sum::<DVec3>() / n;
    points.iter().map(|p| (*p - c).length()).sum::<f64>() / n
}
