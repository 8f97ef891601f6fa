//! Enclosed volume of a closed triangle mesh (divergence theorem), used to tell a solid wrap
//! from a double-walled shell (the acceptance bar "volume ≤ 1.10 × the target's").

use glam::DVec3;

/// Signed enclosed volume `Σ (a−o)·((b−o)×(c−o))/6` (positive for an outward-oriented closed
/// surface), with the origin `o` at the mean of the vertices. For a closed surface `o` does not
/// matter (up to rounding, which it keeps small far from the world origin); for an open scan it
/// defines the value: the cone from the vertex centroid over the surface.
pub fn enclosed_volume(positions: &[DVec3], triangles: &[[u32; 3]]) -> f64 {
    if positions.is_empty() {
        return 0.0;
    }
    let o = positions.iter().fold(DVec3::ZERO, |s, p| s + *p) / positions.len() as f64;
    triangles
        .iter()
        .map(|t| {
            let [a, b, c] = t.map(|v| positions[v as usize] - o);
            a.dot(b.cross(c)) / 6.0
        })
        .sum()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::icosphere::icosphere;

    #[test]
    fn sphere_volume_converges() {
        let m = icosphere(5, 2.0, DVec3::new(10.0, -3.0, 1.0)).unwrap();
        let v = enclosed_volume(m.positions(), &m.triangles());
        let exact = 4.0 / 3.0 * std::f64::consts::PI * 8.0;
        assert!((v - exact).abs() / exact < 2e-3, "{v} vs {exact}");
        let unit_cube_tet = enclosed_volume(
            &[DVec3::ZERO, DVec3::X, DVec3::Y, DVec3::Z],
            &[[0, 2, 1], [0, 1, 3], [1, 2, 3], [0, 3, 2]],
        );
        assert!((unit_cube_tet - 1.0 / 6.0).abs() < 1e-15);
    }
}
