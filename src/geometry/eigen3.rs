//! The eigenvector of a 3×3 symmetric positive semi-definite matrix with the smallest eigenvalue:
//! the normal of a weighted-PCA plane fit, asked once per vertex by the final fit.
//!
//! The adjugate adj(A) has the same eigenvectors as A with eigenvalues λ₂λ₃, λ₁λ₃, λ₁λ₂, so for
//! λ₁ ≤ λ₂ ≤ λ₃ its dominant eigenvector is A's smallest one, also when A is singular (a noise-free
//! plane: adj(A) is then the projector onto the normal, scaled). Repeated squaring of adj(A)
//! is power iteration with ratio (λ₁/λ₂)^(2^k) per squaring. Only `+ − × ÷ sqrt`: the same bits
//! natively and in wasm, and several times faster than a general QR eigen-solver.

use glam::{DMat3, DVec3};

/// Squarings of the adjugate: the error shrinks like (λ₁/λ₂)^64, so a patch whose two smallest
/// spreads differ by only 30 % (λ₁/λ₂ = 0.7) is still resolved to 1e-10. Nearer to 1 the plane's
/// normal is not determined by the points anyway.
const SQUARINGS: usize = 6;

/// The unit eigenvector of the symmetric PSD `a` with the smallest eigenvalue, with the sign
/// that agrees with `guess`; `None` when it is not determined (rank ≤ 1: collinear points, or
/// `guess` orthogonal to it).
pub fn smallest_eigenvector(a: DMat3, guess: DVec3) -> Option<DVec3> {
    let [c0, c1, c2] = [a.x_axis, a.y_axis, a.z_axis];
    // adj(A) of a symmetric A is symmetric: its columns are the cross products of A's columns.
    let mut m = DMat3::from_cols(c1.cross(c2), c2.cross(c0), c0.cross(c1));
    for _ in 0..SQUARINGS {
        let scale = m.to_cols_array().iter().fold(0.0f64, |s, v| s.max(v.abs()));
        if !(scale > 0.0 && scale.is_finite()) {
            return None;
        }
        m *= 1.0 / scale;
        m = m * m;
    }
    let v = m * guess;
    let len = v.length();
    let floor = 1e-12 * m.to_cols_array().iter().fold(0.0f64, |s, x| s.max(x.abs()));
    // Also refuses NaN.
    if len.is_nan() || len <= floor {
        return None;
    }
    let v = v / len;
    Some(if v.dot(guess) < 0.0 { -v } else { v })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A random rotation of diag(λ) must give back the axis of the smallest λ.
    #[test]
    fn finds_the_smallest_axis_of_rotated_diagonal_matrices() {
        let mut rng = crate::demo::Rng::new(7);
        let mut rnd = || rng.uniform();
        for case in 0..500 {
            let axis = DVec3::new(rnd() - 0.5, rnd() - 0.5, rnd() - 0.5).normalize();
            let angle = 6.0 * rnd();
            #[allow(clippy::disallowed_methods)] // a test input: its last bit does not matter
            let r = DMat3::from_axis_angle(axis, angle);
            // Smallest eigenvalue: 0 (a noise-free plane), tiny, or up to 0.7 of the middle one.
            let (l2, l3) = (0.5 + rnd(), 1.5 + rnd());
            let l1 = [0.0, 1e-9, 0.7 * rnd() * l2][case % 3];
            let a = r * DMat3::from_diagonal(DVec3::new(l3, l1, l2)) * r.transpose();
            let truth = r * DVec3::Y;
            let guess =
                (truth + 0.6 * DVec3::new(rnd() - 0.5, rnd() - 0.5, rnd() - 0.5)).normalize();
            let v = smallest_eigenvector(a, guess).expect("determined");
            assert!((v.length() - 1.0).abs() < 1e-12);
            assert!(v.dot(truth) > 1.0 - 1e-12, "case {case}: {v} vs {truth}");
        }
    }

    #[test]
    fn rank_one_and_zero_are_undetermined() {
        let d = DVec3::new(1.0, 2.0, 3.0);
        let rank1 = DMat3::from_cols(d * d.x, d * d.y, d * d.z);
        assert_eq!(smallest_eigenvector(rank1, DVec3::Z), None);
        assert_eq!(smallest_eigenvector(DMat3::ZERO, DVec3::Z), None);
    }

    /// Guess orthogonal to the answer: nothing to pick the sign or the vector from.
    #[test]
    fn an_orthogonal_guess_is_undetermined() {
        let a = DMat3::from_diagonal(DVec3::new(1.0, 2.0, 0.0));
        assert_eq!(smallest_eigenvector(a, DVec3::X), None);
        assert_eq!(smallest_eigenvector(a, -DVec3::Z), Some(-DVec3::Z));
    }
}
