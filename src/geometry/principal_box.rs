//! The sides of a point set's box along its principal axes (the eigenvectors of its covariance):
//! unlike the axis-aligned box, the same for the set turned any way. A thin plate turned at
//! random has an axis-aligned box about as thick as it is wide, and a grid sized by its smallest
//! side would be several times coarser than the plate's lying flat (see
//! `field::grid::reference_length_of`).
//!
//! Only `+ − × ÷ sqrt` (through [`smallest_eigenvector`]): the same bits natively and in wasm.

use super::eigen3::smallest_eigenvector;
use glam::{DMat3, DVec3};

/// The sides of the box along the principal axes of `points`, largest spread first; `None` for
/// fewer than two points, non-finite input, or points on one line (no plane to turn into).
/// When two spreads are equal (a disc, a cube) the axes within their plane are any pair: every
/// such box holds the points, and the choice is deterministic.
pub fn principal_sides(points: &[DVec3]) -> Option<DVec3> {
    if points.len() < 2 {
        return None;
    }
    let n = points.len() as f64;
    let mean = points.iter().sum::<DVec3>() / n;
    let mut cov = DMat3::ZERO;
    for p in points {
        let d = *p - mean;
        cov += DMat3::from_cols(d * d.x, d * d.y, d * d.z);
    }
    cov *= 1.0 / n;
    if !cov.is_finite() {
        return None;
    }
    let pick = |m: DMat3| {
        [DVec3::X, DVec3::Y, DVec3::Z]
            .into_iter()
            .find_map(|g| smallest_eigenvector(m, g))
    };
    let thin = pick(cov)?;
    // The largest spread is the smallest of trace·I − cov (positive semi-definite: the trace
    // bounds every eigenvalue).
    let trace = cov.x_axis.x + cov.y_axis.y + cov.z_axis.z;
    let wide = pick(DMat3::from_diagonal(DVec3::splat(trace)) - cov)
        .map(|w| w - w.dot(thin) * thin)
        .filter(|w| w.length_squared() > 1e-12)
        .map_or_else(|| thin.any_orthonormal_vector(), DVec3::normalize);
    let middle = thin.cross(wide);
    // The extents along the three axes in one pass over the points, not three.
    let (lo, hi) = points
        .iter()
        .fold((DVec3::INFINITY, DVec3::NEG_INFINITY), |(lo, hi), p| {
            let d = *p - mean;
            let t = DVec3::new(d.dot(wide), d.dot(middle), d.dot(thin));
            (lo.min(t), hi.max(t))
        });
    Some(hi - lo)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A box's corners and random points inside it, mirrored in its three mid-planes (so its
    /// axes are the principal ones), turned at random: the sides come back.
    #[test]
    fn a_turned_box_gives_its_own_sides() {
        let mut rng = crate::demo::Rng::new(3);
        let mut rnd = || rng.uniform();
        let sides = DVec3::new(1.0, 0.6, 0.06);
        for case in 0..50 {
            let axis = DVec3::new(rnd() - 0.5, rnd() - 0.5, rnd() - 0.5).normalize();
            #[allow(clippy::disallowed_methods)] // a test input: its last bit does not matter
            let turn = DMat3::from_axis_angle(axis, 6.0 * rnd());
            let shift = DVec3::new(rnd(), rnd(), rnd()) * 100.0;
            let corner =
                |k: u32| DVec3::new((k & 1) as f64, ((k >> 1) & 1) as f64, ((k >> 2) & 1) as f64);
            let corners = (0..8).map(|k| corner(k) - 0.5);
            let inside: Vec<DVec3> = (0..50)
                .map(|_| DVec3::new(rnd(), rnd(), rnd()) - 0.5)
                .flat_map(|u| (0..8).map(move |k| u * (2.0 * corner(k) - 1.0)))
                .collect();
            let points: Vec<DVec3> = corners
                .chain(inside)
                .map(|u| turn * (u * sides) + shift)
                .collect();
            let got = principal_sides(&points).expect("a box");
            assert!(
                (got - sides).abs().max_element() < 1e-9,
                "case {case}: {got}"
            );
        }
    }

    #[test]
    fn degenerate_sets_have_no_box() {
        assert_eq!(principal_sides(&[]), None);
        assert_eq!(principal_sides(&[DVec3::ONE]), None);
        let line: Vec<DVec3> = (0..5).map(|k| DVec3::splat(k as f64)).collect();
        assert_eq!(principal_sides(&line), None);
        assert_eq!(principal_sides(&[DVec3::ZERO, DVec3::NAN]), None);
    }

    /// A square (two equal spreads): any pair of axes in its plane gives a box that holds it.
    #[test]
    fn a_square_gets_a_box_that_holds_it() {
        let square = [DVec3::ZERO, DVec3::X, DVec3::Y, DVec3::new(1.0, 1.0, 0.0)];
        let s = principal_sides(&square).expect("a plane");
        assert!(s.z.abs() < 1e-12, "{s}");
        assert!(s.x >= 1.0 - 1e-12 && s.x <= 2f64.sqrt() + 1e-12, "{s}");
    }
}
