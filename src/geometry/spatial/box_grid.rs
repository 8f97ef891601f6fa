//! Every pair of overlapping boxes among many of about one size — a mesh's face boxes — by a
//! uniform grid: each box is listed in the cells it overlaps, and a pair is reported by the one
//! cell that holds the lowest corner of the two boxes' overlap, so exactly once.
//!
//! Why not the BVH's dual traversal ([`crate::geometry::spatial::bvh::Bvh::for_each_self_overlap`]):
//! on a wrap it visits several node pairs for every overlapping box pair, each a scattered read,
//! and the final fit checks several times a pass. Here the work is a sort of a few entries a box
//! and short runs of box tests.
//!
//! Boxes much larger than the typical one (a long sliver, a stray triangle) would fill many
//! cells; up to [`MAX_BIG`] of them are tested against every box instead. With more, or with
//! many boxes far smaller than the typical one crowding into a few cells, the grid declines and
//! the caller takes the BVH.

// `!(x > y)` is used deliberately: it is also true when x is NaN.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

use super::radix::radix_sort_by_cell;
use glam::DVec3;

/// Cells a box may overlap before it counts as big.
const MAX_CELLS: i64 = 64;
/// Most big boxes tested one by one against all (each costs a pass over every box).
pub const MAX_BIG: usize = 64;
/// Box-pair tests per box at most (a wrap needs a tenth of this), see the crowding check.
const TESTS_PER_BOX: usize = 256;
/// Cells per axis at most (so a cell's key fits 63 bits).
const MAX_DIM: i64 = 1 << 20;

#[inline]
fn overlap(amin: DVec3, amax: DVec3, bmin: DVec3, bmax: DVec3) -> bool {
    // One mask, no early exit: the outcome is a coin toss the branch predictor loses.
    !(amin.cmpgt(bmax) | amax.cmplt(bmin)).any()
}

/// Whether box `i` has finite corners.
fn finite(mins: &[DVec3], maxs: &[DVec3], i: usize) -> bool {
    mins[i].is_finite() && maxs[i].is_finite()
}

/// The median of the boxes' largest extents.
fn median_extent(mins: &[DVec3], maxs: &[DVec3]) -> f64 {
    let n = mins.len();
    let mut extents: Vec<f64> = mins
        .iter()
        .zip(maxs)
        .map(|(a, b)| (*b - *a).max_element())
        .collect();
    let (_, &mut median, _) = extents.select_nth_unstable_by(n / 2, |a, b| a.total_cmp(b));
    median
}

/// The (cell key, box) entries of the boxes that fit the grid, and the big boxes.
type Entries = (Vec<(u64, u32)>, Vec<u32>);

/// A uniform grid over the finite boxes: its corner, inverse cell size and cells per axis.
struct Grid {
    lo: DVec3,
    inv: f64,
    dims: [u64; 3],
}

impl Grid {
    /// The grid spanning the finite boxes with cells of twice the median extent (so a typical
    /// box spans one or two cells per axis), at most [`MAX_DIM`] per axis; None without a
    /// finite box.
    fn spanning(mins: &[DVec3], maxs: &[DVec3], median: f64) -> Option<Grid> {
        // A non-finite box is a big one; `min` passes over a NaN only in some positions, which
        // would leave the boxes before it below the grid's corner.
        let (mut lo, mut hi) = (DVec3::INFINITY, DVec3::NEG_INFINITY);
        for i in (0..mins.len()).filter(|&i| finite(mins, maxs, i)) {
            lo = lo.min(mins[i]);
            hi = hi.max(maxs[i]);
        }
        if !(lo.is_finite() && hi.is_finite()) {
            return None;
        }
        let span = (hi - lo).max_element();
        let cell = (2.0 * median)
            .max(span / (MAX_DIM - 1) as f64)
            .max(f64::MIN_POSITIVE);
        let mut grid = Grid {
            lo,
            inv: 1.0 / cell,
            dims: [0; 3],
        };
        grid.dims = grid.coord(hi).map(|t| t as u64 + 1);
        Some(grid)
    }

    /// The cell holding `p` (truncation is the floor here: every coordinate is at least `lo`).
    #[inline]
    fn coord(&self, p: DVec3) -> [i64; 3] {
        let q = (p - self.lo) * self.inv;
        [q.x as i64, q.y as i64, q.z as i64]
    }

    /// The sort key of a cell.
    #[inline]
    fn key(&self, c: [i64; 3]) -> u64 {
        let dims = self.dims;
        (c[0] as u64 * dims[1] + c[1] as u64) * dims[2] + c[2] as u64
    }

    /// Every (cell key, box) entry of the boxes that are not big, and the big boxes; None with
    /// more than [`MAX_BIG`] big ones.
    fn entries(&self, mins: &[DVec3], maxs: &[DVec3]) -> Option<Entries> {
        let n = mins.len();
        let mut entries: Vec<(u64, u32)> = Vec::with_capacity(4 * n);
        let mut big: Vec<u32> = Vec::new();
        for i in 0..n {
            let (a, b) = (self.coord(mins[i]), self.coord(maxs[i]));
            let cells = || (0..3).map(|k| b[k] - a[k] + 1).product::<i64>();
            if !finite(mins, maxs, i) || cells() > MAX_CELLS {
                big.push(i as u32);
                if big.len() > MAX_BIG {
                    return None;
                }
                continue;
            }
            for x in a[0]..=b[0] {
                for y in a[1]..=b[1] {
                    for z in a[2]..=b[2] {
                        entries.push((self.key([x, y, z]), i as u32));
                    }
                }
            }
        }
        Some((entries, big))
    }
}

/// Runs of two or more sorted entries in one cell, as (start, end), and the box tests they
/// take; None beyond [`TESTS_PER_BOX`] tests per box. Boxes far smaller than the median crowd
/// into few cells (a CAD mesh's fine fillets among its large faces), where every pair in a
/// cell is tested: the BVH separates them better.
fn shared_runs(keys: &[u64], n: usize) -> Option<(Vec<(usize, usize)>, usize)> {
    let mut runs: Vec<(usize, usize)> = Vec::new();
    let mut tests = 0usize;
    let mut start = 0;
    while start < keys.len() {
        let mut end = start + 1;
        while end < keys.len() && keys[end] == keys[start] {
            end += 1;
        }
        let len = end - start;
        if len > 1 {
            tests += len * (len - 1) / 2;
            if tests > TESTS_PER_BOX * n {
                return None;
            }
            runs.push((start, end));
        }
        start = end;
    }
    Some((runs, tests))
}

/// Bounds of chunks of consecutive runs with about equal work, several per thread (so that
/// one slow chunk does not leave a core idle).
fn chunk_bounds(runs: &[(usize, usize)], tests: usize) -> Vec<usize> {
    let chunks = 16;
    let mut bounds = vec![0];
    let mut done = 0;
    for (r, &(a, b)) in runs.iter().enumerate() {
        done += (b - a) * (b - a - 1) / 2;
        if done * chunks >= tests * bounds.len() && bounds.len() < chunks {
            bounds.push(r + 1);
        }
    }
    bounds.push(runs.len());
    bounds.dedup();
    bounds
}

/// The kept overlapping pairs within the cells' runs, each reported by the cell holding the
/// lowest corner of the overlap; the chunks run in parallel natively.
fn pairs_in_runs(
    grid: &Grid,
    keys: &[u64],
    ids: &[u32],
    boxes: &[(DVec3, DVec3)],
    runs: &[(usize, usize)],
    bounds: &[usize],
    keep: &(impl Fn(u32, u32) -> bool + Sync),
) -> Vec<(u32, u32)> {
    let found = crate::parallel::map_each(bounds.len() - 1, |c| {
        let mut out = Vec::new();
        for &(start, end) in &runs[bounds[c]..bounds[c + 1]] {
            let here = keys[start];
            for a in start..end {
                let (imin, imax) = boxes[a];
                for b in a + 1..end {
                    let (jmin, jmax) = boxes[b];
                    if overlap(imin, imax, jmin, jmax)
                        && grid.key(grid.coord(imin.max(jmin))) == here
                    {
                        let (i, j) = (ids[a], ids[b]);
                        let (i, j) = (i.min(j), i.max(j));
                        if keep(i, j) {
                            out.push((i, j));
                        }
                    }
                }
            }
        }
        out
    });
    found.into_iter().flatten().collect()
}

/// Appends the kept pairs of each big box with every other box; a pair of big ones from the
/// lower index.
fn push_big_pairs(
    mins: &[DVec3],
    maxs: &[DVec3],
    big: &[u32],
    keep: &impl Fn(u32, u32) -> bool,
    out: &mut Vec<(u32, u32)>,
) {
    let n = mins.len();
    let mut is_big = vec![false; n];
    for &i in big {
        is_big[i as usize] = true;
    }
    for &i in big {
        let (imin, imax) = (mins[i as usize], maxs[i as usize]);
        for j in 0..n as u32 {
            if j == i || (is_big[j as usize] && j < i) {
                continue;
            }
            if overlap(imin, imax, mins[j as usize], maxs[j as usize]) && keep(i.min(j), i.max(j)) {
                out.push((i.min(j), i.max(j)));
            }
        }
    }
}

/// Every pair `(i, j)`, `i < j`, of boxes `[mins[i], maxs[i]]` that overlap (closed boxes:
/// touching counts) and that `keep` keeps, each once, in no particular order; None when the
/// boxes do not suit a grid (more than [`MAX_BIG`] big or non-finite ones, or a crowd of small
/// ones).
///
/// The cells' runs are tested in parallel natively, and `keep` runs there too: most overlapping
/// pairs of a mesh's faces share a vertex, and dropping
/// them where they are found spares collecting them.
pub fn overlapping_pairs(
    mins: &[DVec3],
    maxs: &[DVec3],
    keep: impl Fn(u32, u32) -> bool + Sync,
) -> Option<Vec<(u32, u32)>> {
    let n = mins.len();
    if n < 2 {
        return Some(Vec::new());
    }
    let median = median_extent(mins, maxs);
    let grid = Grid::spanning(mins, maxs, median)?;
    let (entries, big) = grid.entries(mins, maxs)?;
    let (keys, ids): (Vec<u64>, Vec<u32>) = radix_sort_by_cell(entries, grid.dims.iter().product())
        .into_iter()
        .unzip();
    let (runs, tests) = shared_runs(&keys, n)?;
    // The boxes in entry order: a run's tests then read contiguous memory (scattered reads
    // would dominate).
    let boxes: Vec<(DVec3, DVec3)> = ids
        .iter()
        .map(|&i| (mins[i as usize], maxs[i as usize]))
        .collect();
    let bounds = chunk_bounds(&runs, tests);
    let mut out = pairs_in_runs(&grid, &keys, &ids, &boxes, &runs, &bounds, &keep);
    push_big_pairs(mins, maxs, &big, &keep, &mut out);
    Some(out)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::demo::Rng;

    fn brute_force(mins: &[DVec3], maxs: &[DVec3]) -> Vec<(u32, u32)> {
        let mut out = Vec::new();
        for i in 0..mins.len() {
            for j in i + 1..mins.len() {
                if overlap(mins[i], maxs[i], mins[j], maxs[j]) {
                    out.push((i as u32, j as u32));
                }
            }
        }
        out
    }

    fn grid(mins: &[DVec3], maxs: &[DVec3]) -> Option<Vec<(u32, u32)>> {
        overlapping_pairs(mins, maxs, |_, _| true).map(|mut out| {
            out.sort_unstable();
            out
        })
    }

    #[test]
    fn every_overlapping_pair_once_with_slivers_and_touching_boxes() {
        let mut rng = Rng::new(3);
        let mut mins = Vec::new();
        let mut maxs = Vec::new();
        for k in 0..600 {
            let c = DVec3::new(rng.uniform(), rng.uniform(), rng.uniform()) * 4.0;
            // Mostly small boxes; every 50th a long sliver (big); some flat.
            let mut e = DVec3::new(rng.uniform(), rng.uniform(), rng.uniform()) * 0.6;
            if k % 50 == 0 {
                e.x = 4.0;
            }
            if k % 7 == 0 {
                e.z = 0.0;
            }
            mins.push(c);
            maxs.push(c + e);
        }
        // Boxes that only touch, along a cell boundary and at a corner.
        mins.push(DVec3::new(1.0, 1.0, 1.0));
        maxs.push(DVec3::new(2.0, 2.0, 2.0));
        mins.push(DVec3::new(2.0, 1.5, 1.5));
        maxs.push(DVec3::new(3.0, 2.5, 2.5));
        mins.push(DVec3::new(2.0, 2.0, 2.0));
        maxs.push(DVec3::new(2.0, 2.0, 2.0));
        let want = brute_force(&mins, &maxs);
        assert!(want.len() > 300, "{}", want.len());
        assert!(want.contains(&(600, 601)) && want.contains(&(600, 602)));
        assert_eq!(grid(&mins, &maxs), Some(want));
    }

    #[test]
    fn a_sparse_grid_gives_the_same_pairs() {
        // Clusters of overlapping boxes far apart along the diagonal: far more cells than
        // entries, cell keys of several radix digits.
        let mut rng = Rng::new(11);
        let (mut mins, mut maxs) = (Vec::new(), Vec::new());
        for k in 0..40 {
            for _ in 0..6 {
                let c = DVec3::splat(60.0 * k as f64)
                    + DVec3::new(rng.uniform(), rng.uniform(), rng.uniform());
                mins.push(c);
                maxs.push(c + DVec3::new(rng.uniform(), rng.uniform(), rng.uniform()) * 0.8);
            }
        }
        let cells = (60.0 * 40.0f64 / 1.6).powi(3);
        assert!(
            cells > 64.0 * mins.len() as f64
                && cells > (1u64 << (2 * super::super::radix::RADIX_BITS)) as f64
        );
        let want = brute_force(&mins, &maxs);
        assert!(want.len() > 100, "{}", want.len());
        assert_eq!(grid(&mins, &maxs), Some(want));
    }

    #[test]
    fn declines_a_crowd_of_small_boxes_among_large_ones() {
        // 5 000 unit boxes on a line (the median size: a cell of 2), and 4 000 boxes a
        // thousandth that size within half a unit, in one cell: millions of pairs to test there.
        let mut mins: Vec<DVec3> = (0..5000)
            .map(|k| DVec3::new(2.0 * k as f64, 0.0, 0.0))
            .collect();
        let mut maxs: Vec<DVec3> = mins.iter().map(|&m| m + 1.0).collect();
        let mut rng = Rng::new(5);
        for _ in 0..4000 {
            let c = 0.5 * DVec3::new(rng.uniform(), rng.uniform(), rng.uniform()) + 0.2;
            mins.push(c);
            maxs.push(c + 0.001);
        }
        assert_eq!(grid(&mins, &maxs), None);
        assert_eq!(grid(&mins[..5000], &maxs[..5000]).map(|p| p.len()), Some(0));
    }

    #[test]
    fn declines_many_big_or_non_finite_boxes() {
        let mins: Vec<DVec3> = (0..200).map(|k| DVec3::splat(k as f64)).collect();
        let mut maxs: Vec<DVec3> = mins.iter().map(|&m| m + 0.5).collect();
        assert_eq!(grid(&mins, &maxs), Some(vec![]));
        for m in maxs.iter_mut().take(MAX_BIG + 1) {
            *m += DVec3::splat(150.0);
        }
        assert_eq!(grid(&mins, &maxs), None);
        // A non-finite box is a big one, tested against all as the brute force does.
        let mut nan = mins.clone();
        nan[5] = DVec3::new(f64::NAN, 0.0, 0.0);
        let maxs: Vec<DVec3> = mins.iter().map(|&m| m + 0.5).collect();
        let want = brute_force(&nan, &maxs);
        assert_eq!(want.len(), 5);
        assert_eq!(grid(&nan, &maxs), Some(want));
    }
}
