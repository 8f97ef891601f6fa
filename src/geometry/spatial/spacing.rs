//! The typical sampling spacing of a point cloud: the median distance from a point to its
//! nearest other point, over an evenly strided sample of at most 4096 points (deterministic).

use super::bvh::PointBvh;
use glam::DVec3;

/// Median nearest-neighbour distance of the distinct points of `points` (0 for fewer than two
/// distinct points).
pub fn median_spacing(points: &[DVec3]) -> f64 {
    let mut pts = points.to_vec();
    pts.sort_unstable_by(|a, b| {
        a.x.total_cmp(&b.x)
            .then(a.y.total_cmp(&b.y))
            .then(a.z.total_cmp(&b.z))
    });
    pts.dedup();
    if pts.len() < 2 {
        return 0.0;
    }
    let bvh = PointBvh::new(&pts);
    let stride = pts.len().div_ceil(4096);
    let mut d: Vec<f64> = (0..pts.len())
        .step_by(stride)
        .filter_map(|i| bvh.nearest_other(pts[i], i as u32).map(|(_, d2)| d2.sqrt()))
        .collect();
    if d.is_empty() {
        return 0.0;
    }
    let mid = d.len() / 2;
    *d.select_nth_unstable_by(mid, f64::total_cmp).1
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lattice_spacing() {
        let pts: Vec<DVec3> = (0..1000)
            .map(|i| DVec3::new((i % 10) as f64, ((i / 10) % 10) as f64, (i / 100) as f64) * 0.5)
            .collect();
        assert!((median_spacing(&pts) - 0.5).abs() < 1e-12);
        let mut dup = pts.clone();
        dup.extend_from_slice(&pts);
        assert!((median_spacing(&dup) - 0.5).abs() < 1e-12);
        assert_eq!(median_spacing(&[DVec3::ONE; 3]), 0.0);
    }
}
