//! Stabilisation scaling (docs/method.md §3): surface, grid and distances are scaled uniformly by
//! φ = sqrt(τ/(σ·μ₀)) so that the start surface's mean co-volume is τ/σ. The constants C1, C2, D1,
//! τ of the method are tuned for this frame, which makes them independent of the target's size.

use crate::geometry::icosphere::vertex_count;
use crate::mesh::HalfedgeMesh;
use glam::DVec3;

/// φ for an icosphere of `radius` (original units) and `level`: μ₀ = 4πr²/N_V.
pub fn icosphere_scale(tau: f64, shrink_factor: f64, radius: f64, level: u32) -> f64 {
    let mu0 = 4.0 * std::f64::consts::PI * radius * radius / vertex_count(level) as f64;
    (tau / (shrink_factor * mu0)).sqrt()
}

/// φ for a marching-cubes start on cells of size `cell` (original units): μ₀ = 4√2/3·c².
pub fn isosurface_scale(tau: f64, shrink_factor: f64, cell: f64) -> f64 {
    let mu0 = 4.0 * std::f64::consts::SQRT_2 / 3.0 * cell * cell;
    (tau / (shrink_factor * mu0)).sqrt()
}

/// `p` (stabilised frame, scale `phi` about `center`) as written: in the target's units,
/// rounded to f32.
pub(crate) fn written(p: DVec3, phi: f64, center: DVec3) -> DVec3 {
    (p / phi + center).as_vec3().as_dvec3()
}

/// Moves every vertex of `mesh` onto its written position mapped back into the stabilised frame,
/// so that a check of the mesh is a check of the file: rounding to f32 can make two faces that
/// nearly touch cross.
pub(crate) fn round_as_written(mesh: &mut HalfedgeMesh, phi: f64, center: DVec3) {
    for p in mesh.positions_mut() {
        *p = (written(*p, phi, center) - center) * phi;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bunny_reference_value() {
        // docs/method.md §3.1 (run): r = 0.141672, s = 2, τ = 0.07 → φ = 14.9935.
        assert!((icosphere_scale(0.07, 0.2, 0.141672, 2) - 14.9935).abs() < 1e-3);
    }
}
