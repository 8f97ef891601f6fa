//! Isolated points of a cloud: stray returns of a scanner (dust, a reflection, a point behind
//! the object) lying far from every other sample. Wrapped as they are, each pulls a tentacle out
//! of the shrinking surface or needs a component of its own; a small share of strays scattered
//! over a cloud's box can make the evolution diverge.
//!
//! The test: a point is isolated when fewer than [`ISOLATED_BELOW`] distinct positions (its own
//! included) lie within `radius` of it: copies of a point count once, so a stray recorded six
//! times over is still a stray. With a radius of
//! several median spacings, a point of a densely sampled surface has dozens within it, also
//! along a thin wire or at a cube's corner; a stray point (or a speck of a few) farther than the
//! radius from the surface has only itself. Points are bucketed on cells whose diagonal is the
//! radius, so a cell holding enough distinct positions settles all of them at once, and the
//! others count their neighbours in the face-adjacent cells, then in the rest of the 5 × 5 × 5
//! cells around, nearest first, until they have enough. The answer does not depend on the
//! points' order.
//!
//! [`stray_points`] then keeps the isolated points whose neighbours are as sparse as they are:
//! a region of the surface sampled more sparsely than the median, not a stray.

use super::point_grid::{Near, PointGrid};
use glam::DVec3;
use std::collections::HashMap;
use std::hash::{BuildHasherDefault, Hasher};

/// A multiply–rotate hash for cell keys: with the default SipHash, hashing would be most of the
/// test's cost. (The answer never depends on the hash: only counts and lookups.)
#[derive(Default)]
struct CellHasher(u64);

impl Hasher for CellHasher {
    fn write(&mut self, bytes: &[u8]) {
        for chunk in bytes.chunks(8) {
            let mut word = [0u8; 8];
            word[..chunk.len()].copy_from_slice(chunk);
            self.write_u64(u64::from_le_bytes(word));
        }
    }

    fn write_u64(&mut self, v: u64) {
        self.0 = (self.0.rotate_left(5) ^ v).wrapping_mul(0x517c_c1b7_2722_0a95);
    }

    fn write_i64(&mut self, v: i64) {
        self.write_u64(v as u64);
    }

    fn write_usize(&mut self, v: usize) {
        self.write_u64(v as u64);
    }

    fn finish(&self) -> u64 {
        // The multiplications leave the low bits, which pick the bucket, depending on the low
        // bits of the words only: neighbouring cells collided, and lookups probed long chains
        // (a quarter of the test's time on a million points). MurmurHash3's finaliser mixes
        // every bit into every other.
        let mut h = self.0;
        h ^= h >> 33;
        h = h.wrapping_mul(0xff51_afd7_ed55_8ccd);
        h ^= h >> 33;
        h = h.wrapping_mul(0xc4ce_b9fe_1a85_ec53);
        h ^ (h >> 33)
    }
}

/// A point needs at least this many distinct positions (its own included) within the radius to
/// count as part of the sampled surface.
pub const ISOLATED_BELOW: usize = 6;

/// Which of `points` are isolated: fewer than [`ISOLATED_BELOW`] distinct positions within
/// `radius` (> 0).
pub fn isolated_points(points: &[DVec3], radius: f64) -> Vec<bool> {
    if radius.is_nan() || radius <= 0.0 || points.is_empty() {
        return vec![false; points.len()];
    }
    let cell = radius / 3f64.sqrt();
    let origin = points.iter().fold(DVec3::INFINITY, |a, &p| a.min(p));
    // Every point is at or above the origin, so truncation is the floor (and no libm call).
    let key = |p: DVec3| {
        let q = (p - origin) / cell;
        [q.x as i64, q.y as i64, q.z as i64]
    };
    let keys: Vec<[i64; 3]> = crate::parallel::map(points.len(), |i| key(points[i]));
    let cells = Cells::new(&keys);
    // The points in cell order, so that a cell's are side by side in memory (looked up by index
    // each would be a cache miss).
    let sorted: Vec<DVec3> =
        crate::parallel::map(cells.order.len(), |j| points[cells.order[j] as usize]);
    let r2 = radius * radius;
    // Distinct positions found so far around a point: copies of a point (a scan's repeated
    // records, merged passes) are one sample of the surface, and a stray recorded six times is
    // still a stray.
    struct Found {
        at: [DVec3; ISOLATED_BELOW],
        n: usize,
    }
    impl Found {
        fn add(&mut self, q: DVec3) {
            if self.n < ISOLATED_BELOW && !self.at[..self.n].contains(&q) {
                self.at[self.n] = q;
                self.n += 1;
            }
        }
        fn enough(&self) -> bool {
            self.n >= ISOLATED_BELOW
        }
    }
    // Adds the distinct positions of a run within the radius of `p`, until there are enough.
    let within = |p: DVec3, (a, b): (usize, usize), found: &mut Found| {
        for q in &sorted[a..b] {
            if found.enough() {
                break;
            }
            if (*q - p).length_squared() <= r2 {
                found.add(*q);
            }
        }
    };
    // A cell short of distinct positions looks at its six face neighbours for each of its points,
    // then at the other cells within reach (±2), nearest first, until the point has enough (nearly
    // every cell of a random sampling is short). The answer per cell is the list of its isolated
    // points (empty: no allocation).
    let answers: Vec<Vec<u32>> = crate::parallel::map(cells.runs.len(), |c| {
        let (k, a, b) = cells.runs[c];
        // (Every point of a cell lies within the radius of every other: the cell's diagonal.)
        let mut own = Found {
            at: [DVec3::ZERO; ISOLATED_BELOW],
            n: 0,
        };
        for &q in &sorted[a..b] {
            own.add(q);
            if own.enough() {
                return Vec::new();
            }
        }
        let faces = FACES.map(|d| cells.get(k, d));
        let mut alone = Vec::new();
        for (j, &p) in sorted[a..b].iter().enumerate() {
            let mut found = Found { ..own };
            for run in faces.iter().flatten() {
                within(p, *run, &mut found);
            }
            for d in OTHERS.iter() {
                if found.enough() {
                    break;
                }
                if let Some(run) = cells.get(k, *d) {
                    within(p, run, &mut found);
                }
            }
            if !found.enough() {
                alone.push(j as u32);
            }
        }
        alone
    });
    let mut isolated = vec![false; points.len()];
    for (&(_, a, _), alone) in cells.runs.iter().zip(answers) {
        for j in alone {
            isolated[cells.order[a + j as usize] as usize] = true;
        }
    }
    isolated
}

/// Which of `points` are stray: [isolated](isolated_points) at `radius`, and also far from the
/// sampled surface as seen at their neighbours' own spacing.
///
/// The count alone also flags a part of the surface sampled more sparsely than the rest: a
/// random sampling's median spacing is half its mean one, so a region with a third of the
/// median density already has points with fewer than six within six median spacings (left out,
/// they would thin such a side further, and a side sampled far more sparsely would lose all its
/// points and let the wrap slip inside). An isolated point is kept when the
/// distance to its [`ISOLATED_BELOW`]−1-th nearest point is at most [`STRAY_RATIO`] times the
/// median of that distance over its [`STRAY_NEIGHBOURS`] nearest points: a sparse patch's
/// points all see the same wide spacing, while a stray's nearest points lie on a surface that
/// is dense for its own points (or in a speck of fewer than six, whose nearest points beyond
/// the speck are the surface's). Where no point is isolated (most scans) this costs nothing.
pub fn stray_points(points: &[DVec3], radius: f64) -> Vec<bool> {
    let mut stray = isolated_points(points, radius);
    let candidates: Vec<usize> = (0..points.len()).filter(|&i| stray[i]).collect();
    if candidates.is_empty() {
        return stray;
    }
    // Farther than this, a point is alone whatever its neighbours are like.
    let reach = STRAY_REACH * radius;
    let grid = PointGrid::new(points, reach);
    // The `k` nearest distinct positions (the point's own first), as the count sees them.
    let nearest = |i: usize, k: usize| {
        let mut asked = 2 * k;
        loop {
            let mut out = Vec::new();
            grid.nearest_within(points[i], reach, asked, &mut out);
            let full = out.len() == asked;
            let mut distinct: Vec<Near> = Vec::with_capacity(k);
            for n in out {
                if !distinct.iter().any(|d| d.point == n.point) {
                    distinct.push(n);
                    if distinct.len() == k {
                        return distinct;
                    }
                }
            }
            if !full || asked >= MOST_COPIES_ASKED {
                return distinct;
            }
            asked *= 4;
        }
    };
    // The distance from a point to its (ISOLATED_BELOW − 1)-th nearest other position, the one
    // the count tests against the radius; infinite beyond the reach.
    let spread = |i: usize| {
        let near = nearest(i, ISOLATED_BELOW);
        match near.len() == ISOLATED_BELOW {
            true => near[ISOLATED_BELOW - 1].d2.sqrt(),
            false => f64::INFINITY,
        }
    };
    let keep = crate::parallel::map(candidates.len(), |c| {
        let i = candidates[c];
        let own = spread(i);
        if !own.is_finite() {
            return false;
        }
        let mut around: Vec<f64> = nearest(i, STRAY_NEIGHBOURS + 1)
            .iter()
            .filter(|n| n.point != points[i])
            .map(|n| spread(n.index as usize))
            .collect();
        if around.len() < STRAY_NEIGHBOURS {
            return false;
        }
        let mid = around.len() / 2;
        let typical = *around.select_nth_unstable_by(mid, f64::total_cmp).1;
        own <= STRAY_RATIO * typical
    });
    for (&i, keep) in candidates.iter().zip(keep) {
        stray[i] = !keep;
    }
    stray
}

/// How many nearest points [`stray_points`] takes as an isolated point's neighbourhood: a speck
/// of up to half as many strays still has the surface's points as the majority.
pub const STRAY_NEIGHBOURS: usize = 12;

/// How much wider than its neighbours' an isolated point's spacing may be and the point still
/// belong to the sampled surface (see [`stray_points`]). A point of a random sampling exceeds
/// twice its neighbours' by chance about once in a thousand; a stray beyond the radius from a
/// surface sampled at the median spacing is more than twice as far as that surface's own.
pub const STRAY_RATIO: f64 = 2.0;

/// Most points [`stray_points`] asks for to find enough distinct positions among copies.
const MOST_COPIES_ASKED: usize = 4096;

/// Radii (of the isolation test) within which [`stray_points`] looks for an isolated point's
/// neighbours: a sparse region's points are kept down to about a sixtieth of the median density.
const STRAY_REACH: f64 = 4.0;

/// The points bucketed by cell: their indices sorted by cell, each occupied cell's run of that
/// order, and a lookup from a cell to its run. (The order within a cell, and of the cells, never
/// changes an answer: only counts.) Not a [`super::point_grid::PointGrid`]: that one keeps a
/// start for every cell of the box and caps the cells per axis, and this test's cells must stay
/// exactly radius/√3 wide — a dense scan's box holds tens of millions of them, few occupied.
struct Cells {
    order: Vec<u32>,
    /// (cell, start, end) per occupied cell.
    runs: Vec<([i64; 3], usize, usize)>,
    lookup: Lookup,
}

/// Where an occupied cell's run is.
enum Lookup {
    /// Cells numbered `(z·ny + y)·nx + x` in the points' box and sorted so: each (y, z) row's
    /// runs are consecutive, in x order, found from a table of row starts.
    Rows { dims: [u64; 3], row_start: Vec<u32> },
    /// A hash map, where the box has too many rows (a stray point far off).
    Hash(HashMap<[i64; 3], usize, BuildHasherDefault<CellHasher>>),
}

/// Most (y, z) rows of cells for which [`Lookup::Rows`] keeps a table (a few megabytes, more
/// rows than a dense scan's box has).
const MAX_ROWS: u64 = 1 << 20;

impl Cells {
    /// Buckets points by their non-negative cell `keys`: by a radix sort of one integer per cell
    /// where the cells of the points' box can be numbered in 64 bits (much faster than a
    /// comparison sort of the triples), else by that sort.
    fn new(keys: &[[i64; 3]]) -> Self {
        let dims = keys.iter().fold([1u64; 3], |d, k| {
            std::array::from_fn(|a| d[a].max(k[a] as u64 + 1))
        });
        let rows = dims[1].checked_mul(dims[2]).filter(|&r| r <= MAX_ROWS);
        let total = rows
            .and_then(|r| r.checked_mul(dims[0]))
            .filter(|&n| n < 1 << 62);
        // (cell, point) in cell order; the runs read the cells from it, not from `keys` by
        // point index (a cache miss per point).
        let mut runs: Vec<([i64; 3], usize, usize)> = Vec::new();
        let mut add = |n: usize, k: [i64; 3]| match runs.last_mut() {
            Some((last, _, end)) if *last == k => *end = n + 1,
            _ => runs.push((k, n, n + 1)),
        };
        let order: Vec<u32> = match total {
            Some(total) => {
                let [nx, ny, _] = dims;
                let index = |k: &[i64; 3]| (k[2] as u64 * ny + k[1] as u64) * nx + k[0] as u64;
                let pairs: Vec<(u64, u32)> =
                    crate::parallel::map(keys.len(), |i| (index(&keys[i]), i as u32));
                let pairs = super::radix::radix_sort_by_cell(pairs, total);
                let (mut last, mut k) = (u64::MAX, [0; 3]);
                for (n, &(c, _)) in pairs.iter().enumerate() {
                    if c != last {
                        k = [c % nx, c / nx % ny, c / nx / ny].map(|x| x as i64);
                        last = c;
                    }
                    add(n, k);
                }
                pairs.into_iter().map(|(_, i)| i).collect()
            }
            None => {
                let mut order: Vec<([i64; 3], u32)> = (keys.iter().enumerate())
                    .map(|(i, &k)| (k, i as u32))
                    .collect();
                order.sort_unstable();
                for (n, &(k, _)) in order.iter().enumerate() {
                    add(n, k);
                }
                order.into_iter().map(|(_, i)| i).collect()
            }
        };
        let lookup = match (total, rows) {
            (Some(_), Some(rows)) => {
                let mut row_start = vec![0u32; rows as usize + 1];
                for (k, _, _) in &runs {
                    row_start[(k[2] as u64 * dims[1] + k[1] as u64) as usize + 1] += 1;
                }
                for r in 1..row_start.len() {
                    row_start[r] += row_start[r - 1];
                }
                Lookup::Rows { dims, row_start }
            }
            _ => Lookup::Hash(
                runs.iter()
                    .enumerate()
                    .map(|(r, &(k, _, _))| (k, r))
                    .collect(),
            ),
        };
        Cells {
            order,
            runs,
            lookup,
        }
    }

    /// The run `(start, end)` of the cell `k + d`, if occupied.
    fn get(&self, k: [i64; 3], d: [i64; 3]) -> Option<(usize, usize)> {
        let c: [i64; 3] = std::array::from_fn(|a| k[a] + d[a]);
        let run = match &self.lookup {
            Lookup::Rows { dims, row_start } => {
                if (0..3).any(|a| c[a] < 0 || c[a] as u64 >= dims[a]) {
                    return None;
                }
                let row = (c[2] as u64 * dims[1] + c[1] as u64) as usize;
                let (lo, hi) = (row_start[row] as usize, row_start[row + 1] as usize);
                lo + self.runs[lo..hi]
                    .binary_search_by_key(&c[0], |r| r.0[0])
                    .ok()?
            }
            Lookup::Hash(map) => *map.get(&c)?,
        };
        let (_, a, b) = self.runs[run];
        Some((a, b))
    }
}

/// The six face neighbours of a cell.
const FACES: [[i64; 3]; 6] = [
    [-1, 0, 0],
    [1, 0, 0],
    [0, -1, 0],
    [0, 1, 0],
    [0, 0, -1],
    [0, 0, 1],
];

/// The other cells that may hold a point within the radius of one in the centre cell (offsets
/// up to ±2, the cell being the radius over √3), nearest first.
static OTHERS: std::sync::LazyLock<Vec<[i64; 3]>> = std::sync::LazyLock::new(|| {
    let mut around = Vec::with_capacity(118);
    for z in -2..=2i64 {
        for y in -2..=2i64 {
            for x in -2..=2i64 {
                let d = [x, y, z];
                if d != [0, 0, 0] && !FACES.contains(&d) {
                    around.push(d);
                }
            }
        }
    }
    around.sort_by_key(|d| d.map(|c| c * c).iter().sum::<i64>());
    around
});

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::sphere::fibonacci_sphere as sphere;

    #[test]
    fn stray_points_and_specks_are_isolated_the_surface_is_not() {
        let mut pts = sphere(5000);
        let spacing = (4.0 * std::f64::consts::PI / 5000.0).sqrt();
        // Lone points more than the radius off the sphere, and a speck of three close together.
        let strays = [
            DVec3::new(3.0, 0.2, -1.0),
            DVec3::new(-2.5, 2.5, 0.0),
            DVec3::new(0.0, 0.1, 1.5),
            DVec3::new(0.0, -4.0, 1.0),
        ];
        pts.extend(strays);
        pts.extend([0.0, 0.01, 0.02].map(|e| DVec3::new(-3.0 + e, -3.0, 2.0)));
        let iso = isolated_points(&pts, 6.0 * spacing);
        assert_eq!(stray_points(&pts, 6.0 * spacing), iso);
        assert!(
            iso[..5000].iter().all(|&i| !i),
            "a point of the sphere counted"
        );
        assert!(iso[5000..].iter().all(|&i| i), "{:?}", &iso[5000..]);
        // A sphere sampled 9× more sparsely (3× the spacing), seen at the dense one's radius:
        // nothing is isolated.
        let sparse = sphere(5000 / 9);
        assert!(isolated_points(&sparse, 6.0 * spacing).iter().all(|&i| !i));
    }

    /// A random sampling (not a lattice) of an ellipsoid, one half of it sampled 3× to 20× more
    /// sparsely than the other: the count alone flags hundreds of points of the sparse half; at
    /// most a tenth of those are strays for the full test. Strays beside it still are: lone
    /// ones, a speck of three, one recorded six times, a speck of two recorded three times.
    #[test]
    fn a_sparsely_sampled_region_is_not_strewn_with_strays() {
        for ratio in [0.3, 0.1, 0.05] {
            let mut rng = crate::demo::Rng::new(11);
            let mut pts = Vec::new();
            while pts.len() < 20_000 {
                let d = DVec3::new(rng.normal(), rng.normal(), rng.normal()).normalize();
                if d.x < 0.0 && rng.uniform() > ratio {
                    continue;
                }
                pts.push(d * DVec3::new(1.0, 0.6, 0.4));
            }
            let surface = pts.len();
            pts.extend([
                DVec3::new(-1.3, 0.0, 0.0),
                DVec3::new(0.0, 0.0, 0.6),
                DVec3::new(-0.5, 0.9, 0.0),
            ]);
            pts.extend([0.0, 0.002, 0.004].map(|e| DVec3::new(-1.0, -0.8 + e, 0.3)));
            // A stray recorded six times, and a speck of two recorded three times each.
            pts.extend([DVec3::new(1.2, 0.5, 0.0); 6]);
            pts.extend([DVec3::new(0.0, -0.9, -0.3), DVec3::new(0.01, -0.9, -0.3)].repeat(3));
            let radius = 6.0 * crate::geometry::spatial::spacing::median_spacing(&pts);
            let counted = isolated_points(&pts, radius);
            let flagged = counted[..surface].iter().filter(|&&i| i).count();
            assert!(flagged > 100, "{ratio}: the count flags only {flagged}");
            let stray = stray_points(&pts, radius);
            let lost = stray[..surface].iter().filter(|&&i| i).count();
            // (The ones lost lie where the sparse half meets the dense one, whose points are
            // their nearest, or alone by chance inside it.)
            assert!(
                lost * 10 <= flagged,
                "{ratio}: {lost} of {flagged} surface points lost"
            );
            assert!(
                stray[surface..].iter().all(|&s| s),
                "{:?}",
                &stray[surface..]
            );
        }
    }

    /// Against counting every pair: points scattered at random in a box, at densities from
    /// "every point has company" to "most are alone", so that every path is taken (cells with
    /// enough points, face neighbours, the farther cells, counts stopped early).
    #[test]
    fn matches_brute_force_counts() {
        let mut rng = crate::demo::Rng::new(17);
        for (n, radius) in [(400, 0.05), (400, 0.12), (1500, 0.08), (3000, 0.2)] {
            let pts: Vec<DVec3> = (0..n)
                .map(|_| DVec3::new(rng.uniform(), rng.uniform(), 0.3 * rng.uniform()))
                .collect();
            // Some points recorded several times over: copies count once.
            let copies: Vec<DVec3> = (0..n / 10).flat_map(|i| [pts[i * 7]; 4]).collect();
            let pts = [pts, copies].concat();
            let want: Vec<bool> = pts
                .iter()
                .map(|p| {
                    let mut near: Vec<[u64; 3]> = pts
                        .iter()
                        .filter(|q| (**q - *p).length_squared() <= radius * radius)
                        .map(|q| q.to_array().map(f64::to_bits))
                        .collect();
                    near.sort_unstable();
                    near.dedup();
                    near.len() < ISOLATED_BELOW
                })
                .collect();
            let alone = want.iter().filter(|&&i| i).count();
            assert!(alone > 0 || n == 3000, "{n}, {radius}: none alone");
            assert_eq!(
                isolated_points(&pts, radius),
                want,
                "{n} points, radius {radius}"
            );
        }
    }

    #[test]
    fn the_answer_does_not_depend_on_the_order() {
        let mut pts = sphere(2000);
        pts.push(DVec3::splat(5.0));
        let a = isolated_points(&pts, 0.4);
        let mut rev = pts.clone();
        rev.reverse();
        let mut b = isolated_points(&rev, 0.4);
        b.reverse();
        assert_eq!(a, b);
        assert_eq!(a.iter().filter(|&&i| i).count(), 1);
    }

    /// Stray points so far off that the cells of the points' box cannot be numbered in 64 bits:
    /// the same answers by the other sort.
    #[test]
    fn a_far_stray_takes_the_unpacked_sort() {
        let mut pts = sphere(2000);
        pts.push(DVec3::splat(5.0));
        let near = isolated_points(&pts, 0.4);
        pts.extend([DVec3::new(1e7, 0.0, 0.0), DVec3::new(0.0, 1e7, 1e7)]);
        let far = isolated_points(&pts, 0.4);
        assert_eq!(far[..near.len()], near[..]);
        assert!(far[near.len()] && far[near.len() + 1]);
    }
}
