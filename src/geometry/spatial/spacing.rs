//! The typical sampling spacing of a point cloud: the median of its points' surface spacings
//! ([`super::surface_spacing`]: the nearest other distinct point, or off a curve-like
//! neighbourhood the nearest point off its line), over an evenly strided sample of at most 4096
//! points (deterministic); and, from the same sample, the spacing of its widest gaps.

use super::point_grid::{Near, PointGrid};
use super::surface_spacing::surface_spacing_at;
use glam::DVec3;

/// Median distance from a point to its nearest *distinct* point (0 when there is none), over an
/// evenly strided sample of at most 4096 points. Exact: the same distances as a search of every
/// point.
pub fn median_spacing(points: &[DVec3]) -> f64 {
    spacings(points).0
}

/// The 99th percentile of the same distances as [`median_spacing`]: the gaps of the sampling.
/// For a random sampling of a surface the share of points whose nearest point lies farther than
/// r is the share of the surface lying farther than r from every point (both e^{−πλr²} at
/// density λ), so an offset of this distance leaves about 1 % of the surface uncovered; a
/// regular sampling's is close to its median.
pub fn gap_spacing(points: &[DVec3]) -> f64 {
    spacings(points).1
}

/// (median, 99th percentile) of the nearest-distinct-point distances, remembered.
fn spacings(points: &[DVec3]) -> (f64, f64) {
    if points.len() < 2 {
        return (0.0, 0.0);
    }
    // One wrap asks up to three times for the same cloud (field grid floor, start surface,
    // surgery): remember the last answer, keyed by a checksum of every coordinate (a pass over
    // the points costs a few ms on a million; the tree costs hundreds).
    let key = checksum(points);
    if let Some(d) = LAST.with(|l| l.get().filter(|(k, _)| *k == key).map(|(_, d)| d)) {
        return d;
    }
    let d = compute(points, surface_spacing_at);
    LAST.with(|l| l.set(Some((key, d))));
    d
}

/// (median, gap) spacings of the points with this checksum.
type Remembered = ((usize, u64), (f64, f64));

thread_local! {
    /// The last call's answer on this thread.
    static LAST: std::cell::Cell<Option<Remembered>> = const { std::cell::Cell::new(None) };
}

/// FNV-1a over the coordinates' bits, with the count.
fn checksum(points: &[DVec3]) -> (usize, u64) {
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    for p in points {
        for c in p.to_array() {
            h = (h ^ c.to_bits()).wrapping_mul(0x0000_0100_0000_01b3);
        }
    }
    (points.len(), h)
}

/// A point's spacing on the grid of the cloud it belongs to (`near`: scratch space).
type PointSpacing = fn(&PointGrid, DVec3, &mut Vec<Near>) -> Option<f64>;

/// (median, 99th percentile) of `spacing` over the strided sample of `points`.
fn compute(points: &[DVec3], spacing: PointSpacing) -> (f64, f64) {
    // A bucket grid of about one cell per point (its memory bounded by the point count): on a
    // scanned surface a query opens a few cells of ~n^⅓ points each. Built in one counting
    // sort, against the median-split or Morton tree's sort of every point.
    let bbox = crate::geometry::aabb::Aabb::from_points(points);
    let longest = bbox.size().max_element();
    let cell = longest / crate::fmath::powf(points.len() as f64, 1.0 / 3.0).max(1.0);
    if cell.is_nan() || cell <= 0.0 {
        return (0.0, 0.0); // Every point is a copy of the first.
    }
    let grid = PointGrid::with_cell(points, cell);
    let stride = points.len().div_ceil(4096);
    let mut near = Vec::new();
    let mut d: Vec<f64> = (0..points.len())
        .step_by(stride)
        .filter_map(|i| spacing(&grid, points[i], &mut near))
        .collect();
    if d.is_empty() {
        return (0.0, 0.0);
    }
    let mid = d.len() / 2;
    let median = *d.select_nth_unstable_by(mid, f64::total_cmp).1;
    let wide = (d.len() - 1) * 99 / 100;
    (median, *d.select_nth_unstable_by(wide, f64::total_cmp).1)
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
        // The remembered answer belongs to the points it was computed for.
        let twice: Vec<DVec3> = pts.iter().map(|p| *p * 2.0).collect();
        assert!((median_spacing(&pts) - 0.5).abs() < 1e-12);
        assert!((median_spacing(&twice) - 1.0).abs() < 1e-12);
        assert!((median_spacing(&pts) - 0.5).abs() < 1e-12);
    }

    /// The grid search for each sampled point's nearest against every point, bit for bit: a
    /// noisy sphere with copies of some points (triple ones too), a flat patch, and a line.
    #[test]
    fn agrees_with_brute_force() {
        let brute = |points: &[DVec3]| {
            let stride = points.len().div_ceil(4096);
            let mut d: Vec<f64> = (0..points.len())
                .step_by(stride)
                .filter_map(|i| {
                    let p = points[i];
                    let d2 = points
                        .iter()
                        .map(|q| (*q - p).length_squared())
                        .filter(|&d2| d2 > 0.0)
                        .fold(f64::INFINITY, f64::min);
                    d2.is_finite().then(|| d2.sqrt())
                })
                .collect();
            let mid = d.len() / 2;
            let median = *d.select_nth_unstable_by(mid, f64::total_cmp).1;
            let wide = (d.len() - 1) * 99 / 100;
            (median, *d.select_nth_unstable_by(wide, f64::total_cmp).1)
        };
        let mut sphere = crate::demo::noisy_sphere_cloud(9000, 0.02, 3);
        for i in (0..9000).step_by(7) {
            sphere.push(sphere[i]);
            if i % 3 == 0 {
                sphere.push(sphere[i]);
            }
        }
        let flat: Vec<DVec3> = (0..5000)
            .map(|i| DVec3::new((i * 37 % 101) as f64, (i * 53 % 97) as f64 * 0.3, 0.0))
            .collect();
        let line: Vec<DVec3> = (0..3000).map(|i| DVec3::X * (i as f64).sqrt()).collect();
        for points in [sphere, flat, line] {
            let nearest: PointSpacing = |g, p, near| g.nearest_other_within(p, g.diagonal(), near);
            let ((m, w), (bm, bw)) = (compute(&points, nearest), brute(&points));
            assert_eq!((m.to_bits(), w.to_bits()), (bm.to_bits(), bw.to_bits()));
        }
    }
}
