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

/// `n` points spread evenly over the unit sphere (the Fibonacci lattice): a deterministic,
/// normal-free sphere "scan" for tests, benchmarks and demos. Scale and shift as needed.
pub fn fibonacci_sphere(n: usize) -> Vec<DVec3> {
    let golden = std::f64::consts::PI * (3.0 - 5f64.sqrt());
    (0..n)
        .map(|i| {
            let z = 1.0 - 2.0 * (i as f64 + 0.5) / n as f64;
            let rho = (1.0 - z * z).sqrt();
            let a = golden * i as f64;
            DVec3::new(rho * crate::fmath::cos(a), rho * crate::fmath::sin(a), z)
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fibonacci_points_lie_on_the_sphere_and_balance() {
        let p = fibonacci_sphere(1000);
        assert!(p.iter().all(|q| (q.length() - 1.0).abs() < 1e-12));
        let c = p.iter().copied().sum::<DVec3>() / 1000.0;
        assert!(c.length() < 1e-3, "centroid {c:?}");
        assert!((mean_radius(&p) - 1.0).abs() < 1e-3);
    }
}
