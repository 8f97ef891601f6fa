//! The spacing at which a cloud samples a *surface* around one of its points. Where the points
//! nearest to it spread in two directions, this is its nearest-point distance. Where they lie
//! along a curve (a cross-section contour, a scan line, a sampled edge), the surface between
//! the curves is sampled only as densely as the curves lie apart: the spacing is the distance
//! to the nearest point off the curve (docs/decisions/0029-surface-spacing.md).

use super::point_grid::{Near, PointGrid};
use glam::DVec3;

/// Points whose spread tells whether a neighbourhood is curve-like: few, so that a point a few
/// spacings from where curves cross still reads its own curve. (A surface sampling's few that
/// happen to line up find their nearest point off the line about as near as their nearest.)
pub const LINE_POINTS: usize = 8;

/// A neighbourhood is curve-like when its second principal variance is at most this share of
/// its first (it spreads across its line less than about a fifth as far as along it).
pub const LINE_SPREAD: f64 = 0.05;

/// A point lies off the line when its distance from the line is at least this share of its
/// distance (30° or more from the line's direction).
pub const OFF_LINE: f64 = 0.5;

/// The most points looked through for one off the line; beyond, the spacing is read as at
/// least the distance of the last one looked at.
const MOST_POINTS: usize = 1024;

/// The surface spacing at `grid`'s point `q`: its nearest distinct point's distance, or on a
/// curve-like neighbourhood the nearest point's off the curve's line (see the module note);
/// None when `q` has no distinct neighbour. `near` is scratch space.
pub fn surface_spacing_at(grid: &PointGrid, q: DVec3, near: &mut Vec<Near>) -> Option<f64> {
    grid.nearest_within(q, grid.diagonal(), LINE_POINTS, near);
    // (The nearest distinct point is among these unless q has that many copies.)
    let nearest = match near.iter().find(|n| n.d2 > 0.0) {
        Some(n) => n.d2.sqrt(),
        None => grid.nearest_other_within(q, grid.diagonal(), &mut Vec::new())?,
    };
    let Some(axis) = line_axis(near.iter().map(|n| n.point)) else {
        return Some(nearest);
    };
    let mut k = 2 * LINE_POINTS;
    loop {
        grid.nearest_within(q, grid.diagonal(), k, near);
        let off = near.iter().find(|n| {
            let d = n.point - q;
            (d - axis * d.dot(axis)).length_squared() >= OFF_LINE * OFF_LINE * n.d2 && n.d2 > 0.0
        });
        if let Some(n) = off {
            return Some(n.d2.sqrt().max(nearest));
        }
        if near.len() < k || k >= MOST_POINTS {
            let last = near.last().map_or(nearest, |n| n.d2.sqrt());
            return Some(last.max(nearest));
        }
        k *= 2;
    }
}

/// The direction of the line the points lie along, or None when they spread in two directions
/// (or are too few to tell).
fn line_axis(points: impl Iterator<Item = DVec3> + Clone) -> Option<DVec3> {
    let (mut c, mut k) = (DVec3::ZERO, 0usize);
    for p in points.clone() {
        c += p;
        k += 1;
    }
    if k < LINE_POINTS {
        return None;
    }
    c /= k as f64;
    let mut cov = nalgebra::Matrix3::<f64>::zeros();
    for p in points {
        let d = nalgebra::Vector3::new(p.x - c.x, p.y - c.y, p.z - c.z);
        cov += d * d.transpose();
    }
    let eig = nalgebra::SymmetricEigen::new(cov);
    let mut order = [0usize, 1, 2];
    order.sort_by(|&a, &b| eig.eigenvalues[b].total_cmp(&eig.eigenvalues[a]));
    let (first, second) = (eig.eigenvalues[order[0]], eig.eigenvalues[order[1]]);
    if first.is_nan() || first <= 0.0 || second > LINE_SPREAD * first {
        return None;
    }
    let v = eig.eigenvectors.column(order[0]);
    Some(DVec3::new(v[0], v[1], v[2]).normalize())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Circles of radius 1 in the planes z = 0.2·j, each sampled every 0.01 of its length.
    fn contours(count: usize) -> Vec<DVec3> {
        let per = (std::f64::consts::TAU / 0.01) as usize;
        (0..count)
            .flat_map(|j| {
                (0..per).map(move |i| {
                    let t = std::f64::consts::TAU * i as f64 / per as f64;
                    DVec3::new(crate::fmath::cos(t), crate::fmath::sin(t), 0.2 * j as f64)
                })
            })
            .collect()
    }

    #[test]
    fn reads_stacked_contours_at_their_distance_apart() {
        let pts = contours(5);
        let grid = PointGrid::new(&pts, 0.05);
        let mut near = Vec::new();
        let s = surface_spacing_at(&grid, pts[3 * 628 + 100], &mut near).unwrap();
        assert!((s - 0.2).abs() < 1e-9, "{s}");
        // A single contour has no point off its line within the points looked through.
        let one = contours(1);
        let grid = PointGrid::new(&one, 0.05);
        let s = surface_spacing_at(&grid, one[10], &mut near).unwrap();
        assert!(s > 0.3, "{s}");
    }

    #[test]
    fn reads_a_surface_sampling_at_its_nearest_point() {
        // A lattice spaced 0.01 along x and 0.025 along y still spreads both ways.
        let pts: Vec<DVec3> = (0..10_000)
            .map(|i| DVec3::new((i % 100) as f64 * 0.01, (i / 100) as f64 * 0.025, 0.0))
            .collect();
        let grid = PointGrid::new(&pts, 0.05);
        let mut near = Vec::new();
        let s = surface_spacing_at(&grid, pts[5050], &mut near).unwrap();
        assert!((s - 0.01).abs() < 1e-12, "{s}");
        assert_eq!(
            surface_spacing_at(
                &PointGrid::new(&[DVec3::ONE; 3], 0.1),
                DVec3::ONE,
                &mut near
            ),
            None
        );
    }
}
