//! When to remesh (docs/method.md §7.1, pitfall §13.7): the reference remeshes unless every
//! vertex-averaged κ lies strictly inside (1, 1.5) in *its* κ, whose ideal is 2/√3 — so in effect
//! every step. Here the same idea with the rotation-invariant κ(J_Δ) of
//! [`crate::metrics::quality::kappa`] (ideal exactly 1): remesh when the worst vertex average
//! exceeds a settable bound.

// `!(x <= y)` is used deliberately: it is also true when x is NaN.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

use crate::mesh::HalfedgeMesh;
use crate::metrics::quality::vertex_kappa;

/// True when some vertex's mean incident κ(J_Δ) exceeds `max_vertex_kappa` (or a face is
/// degenerate). `max_vertex_kappa ≤ 1` always fires, i.e. "remesh every step".
pub fn needs_remesh(mesh: &HalfedgeMesh, max_vertex_kappa: f64) -> bool {
    if max_vertex_kappa <= 1.0 {
        return true;
    }
    vertex_kappa(mesh).iter().any(|&k| !(k <= max_vertex_kappa))
}

/// The worst (largest) vertex-averaged κ(J_Δ) of the mesh.
pub fn worst_vertex_kappa(mesh: &HalfedgeMesh) -> f64 {
    vertex_kappa(mesh).into_iter().fold(1.0, f64::max)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::icosphere::icosphere;
    use glam::DVec3;

    #[test]
    fn fires_on_a_stretched_sphere_only() {
        let mut m = icosphere(3, 1.0, DVec3::ZERO).unwrap();
        assert!(!needs_remesh(&m, 1.2));
        assert!(needs_remesh(&m, 1.0));
        for p in m.positions_mut() {
            p.z *= 3.0;
        }
        assert!(needs_remesh(&m, 1.2));
        assert!(worst_vertex_kappa(&m) > 1.5);
    }
}
