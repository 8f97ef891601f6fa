//! A uniform bucket grid over points (counting sort, no hashing) for "the k nearest points within
//! a radius" queries. The final fit asks one per vertex; on a dense scan the radius holds
//! thousands of points, so the grid is refined until a query touches O(k) points instead of all
//! of them.

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
    pub fn with_cell(points: &[DVec3], cell: f64) -> Self {
        let mut g = PointGrid::empty(points, cell);
        let keys: Vec<usize> = points.iter().map(|&p| g.key(g.cell_of(p))).collect();
        for &k in &keys {
            g.start[k + 1] += 1;
        }
        for i in 1..g.start.len() {
            g.start[i] += g.start[i - 1];
        }
        let mut fill = g.start.clone();
        for (i, &k) in keys.iter().enumerate() {
            g.order[fill[k] as usize] = i as u32;
            fill[k] += 1;
        }
        g.points = g.order.iter().map(|&i| points[i as usize]).collect();
        g
    }

    /// The cell size in use.
    pub fn cell(&self) -> f64 {
        self.cell
    }

    fn cell_of(&self, p: DVec3) -> [usize; 3] {
        let q = ((p - self.origin) / self.cell).floor();
        [0, 1, 2].map(|k| (q[k].max(0.0) as usize).min(self.dims[k] - 1))
    }

    fn key(&self, c: [usize; 3]) -> usize {
        (c[2] * self.dims[1] + c[1]) * self.dims[0] + c[0]
    }

    /// The range of `points` in cell `c`.
    fn bucket(&self, c: [usize; 3]) -> std::ops::Range<usize> {
        let k = self.key(c);
        self.start[k] as usize..self.start[k + 1] as usize
    }

    /// Appends the points of cell `c` within `sqrt(bound)` of `p`.
    fn scan(&self, c: [isize; 3], p: DVec3, bound: f64, out: &mut Vec<Near>) {
        for j in self.bucket(c.map(|v| v as usize)) {
            let d2 = (self.points[j] - p).length_squared();
            if d2 <= bound {
                out.push(Near {
                    d2,
                    index: self.order[j],
                    point: self.points[j],
                });
            }
        }
    }

    /// The at most `k` points nearest to `p` within `radius`, as [`Near`] in increasing order of
    /// distance (ties by input index, so the answer depends on the points alone, not on the
    /// grid). Opens the cells in rings around `p`'s cell and stops once no unopened cell can be
    /// nearer than the k-th point found.
    pub fn nearest_within(&self, p: DVec3, radius: f64, k: usize, out: &mut Vec<Near>) {
        out.clear();
        if k == 0 || self.points.is_empty() {
            return;
        }
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
                for y in lo[1]..=hi[1] {
                    // Rows inside the ring's shell only touch it at their two ends.
                    let inner = (z - c0[2]).abs() < ring && (y - c0[1]).abs() < ring;
                    if inner {
                        for x in [c0[0] - ring, c0[0] + ring] {
                            if x >= 0 && x < dims[0] {
                                self.scan([x, y, z], p, bound, out);
                            }
                        }
                    } else {
                        for x in lo[0]..=hi[0] {
                            self.scan([x, y, z], p, bound, out);
                        }
                    }
                }
            }
            // Keep the k best of what was found (a linear-time selection per ring).
            if out.len() >= k {
                if out.len() > k {
                    out.select_nth_unstable_by(k - 1, Near::order);
                    out.truncate(k);
                }
                bound = out.iter().map(|n| n.d2).fold(0.0, f64::max);
            }
        }
        out.sort_unstable_by(Near::order);
    }
}

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
        a.d2.total_cmp(&b.d2).then(a.index.cmp(&b.index))
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
            }
        }
        // A sparse cloud keeps cells of the radius.
        let sparse = crate::geometry::sphere::fibonacci_sphere(100);
        assert_eq!(PointGrid::new(&sparse, 0.1).cell(), 0.1);
        PointGrid::new(&[], 0.1).nearest_within(DVec3::ZERO, 1.0, 4, &mut out);
        assert!(out.is_empty());
    }
}
