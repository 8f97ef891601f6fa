//! A uniform bucket grid over points (counting sort, no hashing) for "the k nearest points within
//! a radius" queries. The final fit asks one per vertex; on a dense scan the radius holds
//! thousands of points, so the grid is refined until a query touches O(k) points instead of all
//! of them.

use super::radix::radix_sort_by_cell;
use glam::DVec3;

/// Points bucketed by a uniform grid, stored cell by cell so that a query reads memory in order.
pub struct PointGrid {
    /// The points in cell order; `order[j]` is the input index of `points[j]`.
    points: Vec<DVec3>,
    origin: DVec3,
    cell: f64,
    dims: [usize; 3],
    start: Vec<u32>,
    order: Vec<u32>,
}

/// Average points per occupied cell the grid aims at: a query for k points then opens about
/// k/8 cells near the centre plus one ring.
const POINTS_PER_CELL: f64 = 8.0;

impl PointGrid {
    /// Buckets `points` for queries of radius `radius` (> 0): cells of that size, refined (at most
    /// 8 times finer) while the occupied cells hold many more than [`POINTS_PER_CELL`] points.
    /// Scans sample surfaces, so a cell's count falls with the square of its size.
    pub fn new(points: &[DVec3], radius: f64) -> Self {
        let per_cell = points.len() as f64 / Self::occupied_cells(points, radius).max(1) as f64;
        let refine = (per_cell / POINTS_PER_CELL).sqrt().ceil().clamp(1.0, 8.0);
        Self::with_cell(points, radius / refine)
    }

    /// How many cells of size `cell` hold a point (the grid's keys only: no buckets, no copy).
    fn occupied_cells(points: &[DVec3], cell: f64) -> usize {
        let probe = PointGrid::empty(points, cell);
        let mut seen = vec![false; probe.start.len() - 1];
        points
            .iter()
            .for_each(|&p| seen[probe.key(probe.cell_of(p))] = true);
        seen.iter().filter(|&&s| s).count()
    }

    /// The grid's frame (origin, cell, dims) over `points`, with empty buckets.
    fn empty(points: &[DVec3], cell: f64) -> Self {
        let bbox = crate::geometry::aabb::Aabb::from_points(points);
        let dims = ((bbox.size() / cell).floor() + DVec3::ONE)
            .to_array()
            .map(|d| (d as usize).clamp(1, 1 << 10));
        PointGrid {
            points: Vec::new(),
            origin: bbox.min,
            cell,
            dims,
            start: vec![0; dims[0] * dims[1] * dims[2] + 1],
            order: vec![0; points.len()],
        }
    }

    /// Buckets `points` into cells of size `cell` (> 0; at most 1024 per axis).
    ///
    /// Points in cell order, and in input order within a cell, by a radix sort of (cell, index)
    /// pairs (see [`super::radix`]).
    pub fn with_cell(points: &[DVec3], cell: f64) -> Self {
        let mut g = PointGrid::empty(points, cell);
        let cells = g.start.len() - 1;
        // (The keys and the gather below in parallel: each costs about as much as the sort.)
        let pairs: Vec<(u32, u32)> = crate::parallel::map(points.len(), |i| {
            (g.key(g.cell_of(points[i])) as u32, i as u32)
        });
        let pairs = radix_sort_by_cell(pairs, cells as u64);
        // start[k]: the first point of cell k or later. Filled a stretch of cells at a time
        // (a dense cloud's fit grid has millions of cells, and a compare per cell is slow).
        let mut next = 0;
        for (j, &(c, _)) in pairs.iter().enumerate() {
            let c = c as usize;
            if c >= next {
                g.start[next..=c].fill(j as u32);
                next = c + 1;
            }
        }
        g.start[next..].fill(pairs.len() as u32);
        g.order = pairs.iter().map(|&(_, i)| i).collect();
        g.points = crate::parallel::map(g.order.len(), |j| points[g.order[j] as usize]);
        g
    }

    /// The indices of `queries` in the order of the cells they fall in (input order within a
    /// cell): asked in this order, queries that lie close together read the same cells one
    /// after another, from the cache, where in a scan's order each query's cells are a miss.
    pub fn query_order(&self, queries: &[DVec3]) -> Vec<u32> {
        let pairs: Vec<(u32, u32)> = crate::parallel::map(queries.len(), |i| {
            (self.key(self.cell_of(queries[i])) as u32, i as u32)
        });
        let sorted = radix_sort_by_cell(pairs, (self.start.len() - 1) as u64);
        sorted.into_iter().map(|(_, i)| i).collect()
    }

    /// The points in cell order and each one's index in the order they were given.
    pub fn cell_ordered(&self) -> (&[DVec3], &[u32]) {
        (&self.points, &self.order)
    }

    /// The points in the order they were given (a copy).
    pub fn points_in_input_order(&self) -> Vec<DVec3> {
        let mut out = vec![DVec3::ZERO; self.points.len()];
        for (&i, &p) in self.order.iter().zip(&self.points) {
            out[i as usize] = p;
        }
        out
    }

    /// The cell size in use.
    pub fn cell(&self) -> f64 {
        self.cell
    }

    fn cell_of(&self, p: DVec3) -> [usize; 3] {
        // Truncation after the clamp at 0 is the floor (and needs no call to `floor`, which is
        // not one instruction on every x86-64).
        let q = (p - self.origin) / self.cell;
        [0, 1, 2].map(|k| (q[k].max(0.0) as usize).min(self.dims[k] - 1))
    }

    fn key(&self, c: [usize; 3]) -> usize {
        (c[2] * self.dims[1] + c[1]) * self.dims[0] + c[0]
    }

    /// Appends the points of the cells `x0..=x1` of row (`y`, `z`) within `sqrt(bound)` of `p`, as
    /// [`Candidate`]s.
    #[allow(clippy::too_many_arguments)]
    fn scan_row(
        &self,
        x0: isize,
        x1: isize,
        y: isize,
        z: isize,
        p: DVec3,
        bound: f64,
        out: &mut Vec<Candidate>,
    ) {
        let first = self.key([x0, y, z].map(|v| v as usize));
        let last = self.key([x1, y, z].map(|v| v as usize));
        for j in self.start[first] as usize..self.start[last + 1] as usize {
            let d2 = (self.points[j] - p).length_squared();
            if d2 <= bound {
                // A non-negative f64's bits order like the f64: integer keys select fast.
                out.push((d2.to_bits(), self.order[j], j as u32));
            }
        }
    }

    /// Distance along `axis` from `p` to the slab of cells with index `c` on that axis (0 when
    /// p lies in it).
    #[inline]
    fn axis_gap(&self, p: DVec3, axis: usize, c: isize) -> f64 {
        let lo = self.origin[axis] + c as f64 * self.cell;
        (lo - p[axis]).max(p[axis] - (lo + self.cell)).max(0.0)
    }

    /// Cell indices on `axis` (unclamped) of the cells meeting `[a, b]`.
    #[inline]
    fn cell_span(&self, axis: usize, a: f64, b: f64) -> (isize, isize) {
        let o = self.origin[axis];
        (
            ((a - o) / self.cell).floor() as isize,
            ((b - o) / self.cell).floor() as isize,
        )
    }

    /// The at most `k` points nearest to `p` within `radius`, as [`Near`] in increasing order of
    /// distance (ties by input index, so the answer depends on the points alone, not on the
    /// grid). Opens the cells in rings around `p`'s cell and stops once no unopened cell can be
    /// nearer than the k-th point found.
    pub fn nearest_within(&self, p: DVec3, radius: f64, k: usize, out: &mut Vec<Near>) {
        self.k_nearest_within(p, radius, k, out);
        out.sort_unstable_by(Near::order);
    }

    /// The diagonal of the grid's box: a radius from any point inside it that holds every point.
    pub fn diagonal(&self) -> f64 {
        self.size().length()
    }

    fn size(&self) -> DVec3 {
        DVec3::new(
            self.dims[0] as f64,
            self.dims[1] as f64,
            self.dims[2] as f64,
        ) * self.cell
    }

    /// The nearest point to `p` (ties: the smaller input index); `None` without points. The
    /// radius that surely holds one: p's distance to the grid's box plus the box's diagonal.
    pub fn nearest(&self, p: DVec3) -> Option<Near> {
        let size = self.size();
        let outside = (self.origin - p)
            .max(p - (self.origin + size))
            .max(DVec3::ZERO);
        let mut out = Vec::with_capacity(1);
        self.k_nearest_within(p, outside.length() + size.length(), 1, &mut out);
        out.pop()
    }

    /// The distance from `p` to the nearest point within `radius` at another position than `p`
    /// (copies of `p` skipped: the k nearest hold every copy before any other point, so k
    /// doubles until one is not a copy); None when there is none. `near` is scratch space.
    pub fn nearest_other_within(&self, p: DVec3, radius: f64, near: &mut Vec<Near>) -> Option<f64> {
        let mut k = 2;
        loop {
            self.nearest_within(p, radius, k, near);
            if let Some(n) = near.iter().find(|n| n.d2 > 0.0) {
                return Some(n.d2.sqrt());
            }
            if near.len() < k {
                return None;
            }
            k *= 2;
        }
    }

    /// The same points as [`Self::nearest_within`], in an order fixed by the points and the grid
    /// (not by distance): for callers that only sum over them (a plane fit), which then need no
    /// sort and still get the same bits on every run.
    pub fn nearest_within_unordered(&self, p: DVec3, radius: f64, k: usize, out: &mut Vec<Near>) {
        self.k_nearest_within(p, radius, k, out);
    }

    fn k_nearest_within(&self, p: DVec3, radius: f64, k: usize, result: &mut Vec<Near>) {
        result.clear();
        if k == 0 || self.points.is_empty() {
            return;
        }
        let mut out: Vec<Candidate> = Vec::with_capacity(2 * k.min(1024));
        let out = &mut out;
        let r2 = radius * radius;
        // The k-th nearest so far bounds what is worth keeping.
        let mut bound = r2;
        let c0 = self.cell_of(p).map(|c| c as isize);
        let max_ring = (radius / self.cell).ceil() as isize + 1;
        let dims = self.dims.map(|d| d as isize);
        // How far p lies inside its own cell: every cell of ring r is then at least
        // (r − 1) cells plus this much away, which usually spares the last ring. 0 when p lies
        // outside the grid and its cell was clamped.
        let lo = self.origin + DVec3::new(c0[0] as f64, c0[1] as f64, c0[2] as f64) * self.cell;
        let inside = (p - lo)
            .min(lo + DVec3::splat(self.cell) - p)
            .min_element()
            .max(0.0);
        for ring in 0..=max_ring {
            if ring > 0 {
                // Every cell of this ring is at least (ring − 1) cells from p (also when p lies
                // outside the grid and its cell was clamped).
                let lb = (ring - 1) as f64 * self.cell + inside;
                if lb * lb > bound {
                    break;
                }
            }
            let lo = c0.map(|c| (c - ring).max(0));
            let hi = [0, 1, 2].map(|a| (c0[a] + ring).min(dims[a] - 1));
            for z in lo[2]..=hi[2] {
                let dz = self.axis_gap(p, 2, z);
                if dz * dz > bound {
                    continue;
                }
                for y in lo[1]..=hi[1] {
                    let dy = self.axis_gap(p, 1, y);
                    let dyz2 = dy * dy + dz * dz;
                    if dyz2 > bound {
                        continue; // No cell of this row can hold a point within the bound.
                    }
                    // Rows inside the ring's shell only touch it at their two ends.
                    let inner = (z - c0[2]).abs() < ring && (y - c0[1]).abs() < ring;
                    let (x0, x1) = (c0[0] - ring, c0[0] + ring);
                    if inner {
                        for x in [x0, x1] {
                            let dx = self.axis_gap(p, 0, x);
                            if x >= 0 && x < dims[0] && dx * dx + dyz2 <= bound {
                                self.scan_row(x, x, y, z, p, bound, out);
                            }
                        }
                    } else {
                        // The row's cells are consecutive in the bucket order: one scan of the
                        // x-range that the bound leaves, not a lookup per cell.
                        let reach = (bound - dyz2).max(0.0).sqrt();
                        let (a, b) = self.cell_span(0, p.x - reach, p.x + reach);
                        let (a, b) = (a.max(lo[0]), b.min(hi[0]));
                        if a <= b {
                            self.scan_row(a, b, y, z, p, bound, out);
                        }
                    }
                }
            }
            // Keep the k best of what was found (a linear-time selection per ring).
            if out.len() >= k {
                if out.len() > k {
                    out.select_nth_unstable(k - 1);
                    out.truncate(k);
                }
                bound = f64::from_bits(out.iter().map(|c| c.0).max().unwrap_or(0));
            }
        }
        result.extend(out.iter().map(|&(d2, index, j)| Near {
            d2: f64::from_bits(d2),
            index,
            point: self.points[j as usize],
        }));
    }
}

/// A point met by a query: (squared distance's bits, input index, position in the grid's order).
/// Ordered as a tuple: nearer first, then the smaller input index, like [`Near::order`].
type Candidate = (u64, u32, u32);

/// A point found by [`PointGrid::nearest_within`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Near {
    /// Squared distance to the query.
    pub d2: f64,
    /// Index of the point in the input.
    pub index: u32,
    /// The point.
    pub point: DVec3,
}

impl Near {
    /// Nearer first; as near, the smaller input index first.
    fn order(a: &Near, b: &Near) -> std::cmp::Ordering {
        a.key().cmp(&b.key())
    }

    fn key(&self) -> (u64, u32) {
        (self.d2.to_bits(), self.index)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The k nearest within the radius, by a scan of every point.
    fn brute(points: &[DVec3], p: DVec3, radius: f64, k: usize) -> Vec<Near> {
        let mut all: Vec<Near> = points
            .iter()
            .enumerate()
            .map(|(i, q)| Near {
                d2: (*q - p).length_squared(),
                index: i as u32,
                point: *q,
            })
            .filter(|n| n.d2 <= radius * radius)
            .collect();
        all.sort_by(|a, b| (a.d2, a.index).partial_cmp(&(b.d2, b.index)).unwrap());
        all.truncate(k);
        all
    }

    #[test]
    fn nearest_within_matches_a_scan_of_every_point() {
        let mut rng = crate::demo::Rng::new(11);
        // A dense sphere (the grid refines) with duplicates, and queries inside, on and outside
        // the points' box.
        let mut pts = crate::geometry::sphere::fibonacci_sphere(20_000);
        pts.extend_from_within(..50);
        let grid = PointGrid::new(&pts, 0.1);
        assert!(grid.cell() < 0.1, "a dense cloud refines the grid");
        let mut out = Vec::new();
        for q in 0..300 {
            let p =
                DVec3::new(rng.uniform(), rng.uniform(), rng.uniform()) * 3.0 - DVec3::splat(1.5);
            let p = if q % 3 == 0 { p.normalize() } else { p };
            for (radius, k) in [(0.1, 16), (0.1, 1000), (0.3, 64), (0.02, 8)] {
                grid.nearest_within(p, radius, k, &mut out);
                assert_eq!(out, brute(&pts, p, radius, k), "p {p}, r {radius}, k {k}");
                // The unordered query finds the same points.
                grid.nearest_within_unordered(p, radius, k, &mut out);
                out.sort_unstable_by(Near::order);
                assert_eq!(
                    out,
                    brute(&pts, p, radius, k),
                    "unordered: p {p}, r {radius}, k {k}"
                );
            }
        }
        // The nearest point, against a scan, from inside and far outside the grid.
        for q in 0..200 {
            let p =
                DVec3::new(rng.uniform(), rng.uniform(), rng.uniform()) * 6.0 - DVec3::splat(3.0);
            let p = if q % 4 == 0 { p * 10.0 } else { p };
            let want = brute(&pts, p, f64::INFINITY, 1);
            assert_eq!(grid.nearest(p), want.first().copied(), "nearest to {p}");
        }
        // A sparse cloud keeps cells of the radius.
        let sparse = crate::geometry::sphere::fibonacci_sphere(100);
        assert_eq!(PointGrid::new(&sparse, 0.1).cell(), 0.1);
        PointGrid::new(&[], 0.1).nearest_within(DVec3::ZERO, 1.0, 4, &mut out);
        assert!(out.is_empty());
    }

    /// Queries in cell order: every index once, by cell, in input order within a cell (also
    /// for queries outside the points' box, clamped into its border cells).
    #[test]
    fn queries_in_cell_order() {
        let mut rng = crate::demo::Rng::new(8);
        let mut cube = || DVec3::new(rng.uniform(), rng.uniform(), rng.uniform());
        let pts: Vec<DVec3> = (0..5_000).map(|_| cube()).collect();
        let queries: Vec<DVec3> = (0..3_000)
            .map(|_| 1.4 * cube() - DVec3::splat(0.2))
            .collect();
        let g = PointGrid::with_cell(&pts, 0.05);
        let order = g.query_order(&queries);
        let key = |i: u32| g.key(g.cell_of(queries[i as usize]));
        let mut want: Vec<u32> = (0..queries.len() as u32).collect();
        want.sort_by_key(|&i| key(i)); // stable
        assert_eq!(order, want);
        assert!(key(order[0]) < key(order[order.len() - 1]));
    }

    /// The radix sort leaves the points as a counting sort does: by cell, in input order
    /// within a cell (over more cells than one digit holds, and with points outside the box's
    /// rounding clamped into the last cells); each cell's start is the first point in it or
    /// after it.
    #[test]
    fn buckets_are_those_of_a_stable_sort_by_cell() {
        let mut rng = crate::demo::Rng::new(5);
        let pts: Vec<DVec3> = (0..20_000)
            .map(|_| DVec3::new(rng.uniform(), rng.uniform(), 0.3 * rng.uniform()))
            .collect();
        for cell in [0.3, 0.01, 0.004] {
            let g = PointGrid::with_cell(&pts, cell);
            assert!(g.start.len() > 1 << super::super::radix::RADIX_BITS || cell > 0.1);
            let mut want: Vec<(usize, u32)> = (pts.iter().enumerate())
                .map(|(i, &p)| (g.key(g.cell_of(p)), i as u32))
                .collect();
            want.sort_by_key(|&(k, _)| k); // stable
            assert_eq!(g.order, want.iter().map(|&(_, i)| i).collect::<Vec<_>>());
            // Every cell, empty ones included, starts at the first point of it or later.
            for (k, &start) in g.start.iter().enumerate() {
                assert_eq!(start as usize, want.partition_point(|&(c, _)| c < k));
            }
        }
    }
}
