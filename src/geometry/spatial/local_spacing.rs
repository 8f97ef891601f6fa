//! The sampling spacing of a cloud *here*: a scan is rarely sampled evenly (the side a scanner
//! saw at a grazing angle may hold a tenth of the points per area of the side it faced), and a
//! rule scaled by the median spacing of the whole cloud reads the sparse side's ordinary gaps as
//! holes. Computed like [`super::spacing::median_spacing`] (a point's distance to its nearest
//! distinct point), as the median over the [`SAMPLES`] points nearest to the data point nearest
//! to the place: a patch of the surface around it. (The points nearest to a place in a gap are
//! not such a patch: they are the clump beside the gap, spaced closer than the patch.)

use super::point_grid::{Near, PointGrid};
use super::surface_spacing::surface_spacing_at;
use glam::DVec3;

/// Points of the patch whose nearest-point distances are taken.
pub const SAMPLES: usize = 32;

/// The median spacing of the patch of `grid`'s points around the one nearest to `p`; None when
/// the grid holds fewer than two distinct points there.
pub fn spacing_near(grid: &PointGrid, p: DVec3) -> Option<f64> {
    spacing_at(grid, grid.nearest(p)?.point)
}

/// The median spacing of the patch of `grid`'s points around its point `q` (see
/// [`spacing_near`]).
pub fn spacing_at(grid: &PointGrid, q: DVec3) -> Option<f64> {
    let mut patch: Vec<Near> = Vec::new();
    grid.nearest_within(q, grid.diagonal(), SAMPLES, &mut patch);
    let mut around = Vec::new();
    let mut d: Vec<f64> = patch
        .iter()
        .filter_map(|n| surface_spacing_at(grid, n.point, &mut around))
        .collect();
    if d.is_empty() {
        return None;
    }
    let mid = d.len() / 2;
    Some(*d.select_nth_unstable_by(mid, f64::total_cmp).1)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A plane sampled on a square lattice of spacing 0.01 for x < 0 and 0.04 for x ≥ 0.
    fn two_densities() -> Vec<DVec3> {
        let mut pts = Vec::new();
        for i in -100..0 {
            for j in 0..100 {
                pts.push(DVec3::new(i as f64 * 0.01, j as f64 * 0.01, 0.0));
            }
        }
        for i in 0..25 {
            for j in 0..25 {
                pts.push(DVec3::new(i as f64 * 0.04, j as f64 * 0.04, 0.0));
            }
        }
        pts
    }

    #[test]
    fn reads_each_side_of_a_cloud_at_its_own_spacing() {
        let pts = two_densities();
        let grid = PointGrid::new(&pts, 0.05);
        // Above each side, and in a gap of the sparse side: its patch, not the dense side.
        for (p, want) in [
            (DVec3::new(-0.55, 0.55, 0.3), 0.01),
            (DVec3::new(0.55, 0.55, 0.3), 0.04),
            (DVec3::new(0.5, 0.5, 0.001), 0.04),
        ] {
            let got = spacing_near(&grid, p).unwrap();
            assert!((got - want).abs() < 1e-9, "{p}: {got}");
        }
        assert_eq!(
            spacing_near(&PointGrid::new(&[DVec3::ONE; 3], 0.1), DVec3::ZERO),
            None
        );
    }

    #[test]
    fn copies_of_a_point_are_not_its_neighbours() {
        let mut pts = two_densities();
        pts.extend(two_densities());
        let grid = PointGrid::new(&pts, 0.05);
        let v = spacing_near(&grid, DVec3::new(0.55, 0.55, 0.0)).unwrap();
        assert!((v - 0.04).abs() < 1e-9, "{v}");
    }
}
