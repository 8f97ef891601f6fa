//! Fast sweeping (Zhao 2005) for the eikonal equation |∇d| = 1 outside the frozen near band.
//!
//! Gauss–Seidel passes over the grid in the 8 alternating orderings (x±, y±, z±). Each unfrozen
//! node takes the standard first-order Godunov upwind update from its smallest neighbour per axis
//! `a ≤ b ≤ c` (a missing neighbour at the border counts as +∞):
//!
//! * `u = a + h`; if `u ≤ b` done (one-dimensional);
//! * else `u = (a + b + √(2h² − (a − b)²))/2`; if `u ≤ c` done (two-dimensional);
//! * else the three-term root `u = (a + b + c + √((a+b+c)² − 3(a² + b² + c² − h²)))/3`;
//!   a negative discriminant falls back to the two-dimensional value (the reference takes
//!   `√|disc|` instead, docs/method.md §13.6).
//!
//! A value is only ever lowered. Sweeping stops after the first pass in which no value dropped
//! by more than `tolerance·h`. Nodes none of whose neighbours dropped (by more than that) since
//! their last update are skipped ("locking", Bak et al. 2010): their update could not change.
//! With `tolerance = 0` this is "until no value changes": in a Gauss–Seidel pass that changes
//! nothing every node was updated against the final values of its neighbours, so the discrete
//! solution is reached exactly, but round-off ripples can keep that going for dozens of passes.
//! The drops after the first cycle are typically already below 1e-4 h, far below the scheme's
//! O(h) discretisation error, hence the default tolerance 1e-4 (see
//! `FieldSettings::sweep_tolerance`). [`SweepReport::converged`] is false when the pass cap
//! stopped it first.

use super::grid::Grid;
use std::sync::atomic::Ordering::{Acquire, Relaxed, Release};
use std::sync::atomic::{AtomicBool, AtomicU32, AtomicU8, AtomicUsize};

/// What a sweep run did.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct SweepReport {
    /// Number of single-ordering passes over the grid.
    pub passes: u32,
    /// True when the last pass changed nothing (false: stopped by the cap).
    pub converged: bool,
}

/// Defines the Godunov update for one float type (f64 for reference and tests, f32 for the sweep).
macro_rules! godunov {
    ($(#[$doc:meta])* $name:ident, $t:ty) => {
        $(#[$doc])*
        #[inline(always)]
        pub fn $name(a: $t, b: $t, c: $t, h: $t) -> $t {
            // Sort the three values with a small network.
            let (a, b) = if a <= b { (a, b) } else { (b, a) };
            let (b, c) = if b <= c { (b, c) } else { (c, b) };
            let (a, b) = if a <= b { (a, b) } else { (b, a) };
            let u = a + h;
            if u <= b {
                return u;
            }
            // Solved for u − a with b' = b − a, c' = c − a (both < h): every term is O(h²), so no
            // cancellation between the O(a²) terms of the textbook form (which in f32 leaves
            // noise of ~1e-4 h on a value of 100 h and keeps the sweep from settling).
            // Here b' < h, so the discriminant 2h² − b'² > h² > 0.
            let b1 = b - a;
            let u2 = 0.5 * (b1 + (2.0 * h * h - b1 * b1).sqrt());
            if a + u2 <= c {
                return a + u2;
            }
            let c1 = c - a;
            let s = b1 + c1;
            let disc = s * s - 3.0 * (b1 * b1 + c1 * c1 - h * h);
            if disc < 0.0 {
                return a + u2;
            }
            a + (s + disc.sqrt()) / 3.0
        }
    };
}

godunov!(
    /// The Godunov update of a node from its per-axis upwind neighbours `a, b, c` (any order).
    godunov_update,
    f64
);
godunov!(
    /// [`godunov_update`] in f32, the precision of the sweep itself (see [`fast_sweep`]).
    godunov_update_f32,
    f32
);

/// Sweeps `values` in place; `frozen` nodes are fixed. Stops after the first pass in which no
/// value dropped by more than `tolerance·h`, or after `max_passes` passes (the reference does
/// exactly 8). `pass_done(k / max_passes)` hears after each pass `k` (a big grid's sweeps take
/// seconds in the browser).
///
/// The sweep runs on an f32 copy: it is bound by memory traffic (three z planes of the grid are
/// live at once), f32 halves it, and its rounding (6e-8 relative) is far below the scheme's O(h)
/// error. Frozen (exact, f64) values are never touched and no value is ever raised.
///
/// Natively each pass runs on two threads, bit for bit as on one (see [`Halves`]).
pub fn fast_sweep(
    grid: &Grid,
    values: &mut [f64],
    frozen: &[bool],
    max_passes: u32,
    tolerance: f64,
    pass_done: &mut dyn FnMut(f64),
) -> SweepReport {
    let threads = cfg!(not(target_arch = "wasm32"));
    sweep_split(
        grid,
        values,
        frozen,
        max_passes,
        tolerance,
        threads.then_some(|h: &Halves| h.on_two_threads()),
        pass_done,
    )
}

/// [`fast_sweep`], with `split`: each pass's rows split in two [`Halves`] (where the grid is
/// thick enough) and the pass run by that function; without: each plane swept whole.
fn sweep_split(
    grid: &Grid,
    values: &mut [f64],
    frozen: &[bool],
    max_passes: u32,
    tolerance: f64,
    split: Option<fn(&Halves) -> bool>,
    pass_done: &mut dyn FnMut(f64),
) -> SweepReport {
    let [nx, ny, nz] = grid.dims;
    assert!(
        nx >= 2 && ny >= 2 && nz >= 2,
        "sweeping needs ≥ 2 nodes per axis"
    );
    assert_eq!(values.len(), nx * ny * nz);
    assert_eq!(frozen.len(), values.len());
    // Every array the two halves share is atomic: relaxed loads and stores are plain moves, and
    // the few nodes both halves may wake at once (where the halves meet) stay well defined.
    let lattice = Lattice {
        v: values
            .iter()
            .map(|&x| AtomicU32::new((x as f32).to_bits()))
            .collect(),
        // Locking (Bak, McLaughlin & Renzi 2010): a node is only recomputed while "active", i.e.
        // when one of its neighbours dropped since its own last update; otherwise its update
        // could not change. Frozen nodes are never active.
        state: frozen
            .iter()
            .map(|&f| AtomicU8::new(if f { FROZEN } else { ACTIVE }))
            .collect(),
        // Per row (iy, iz): whether it may hold an active node, so that late passes, with only a
        // few active nodes left, skip whole rows.
        row_active: (0..ny * nz).map(|_| AtomicBool::new(true)).collect(),
        row_work: (0..ny * nz).map(|_| AtomicU32::new(0)).collect(),
        dims: grid.dims,
        h: grid.cell as f32,
        tol: (tolerance * grid.cell) as f32,
    };
    // The halves meet at a group boundary; a grid too thin to split is one half. The first pass
    // splits the rows in the middle, later ones where the last pass's work splits in two.
    let run = split.unwrap_or(|h: &Halves| h.first());
    let split = split.is_some() && ny >= 4 * GROUP;
    let mut half = if split { ny / 2 / GROUP * GROUP } else { ny };
    let mut passes = 0;
    let mut converged = false;
    while passes < max_passes {
        let ordering = passes % 8;
        passes += 1;
        let changed = run(&Halves::new(&lattice, ordering, half));
        if split {
            half = lattice.even_split(passes % 8);
        }
        pass_done(passes as f64 / max_passes.max(1) as f64);
        if !changed {
            // No node dropped, so none was re-activated: every later pass would be a no-op.
            converged = true;
            break;
        }
    }
    // Copies the swept values back, never raising one (f32 rounding could otherwise nudge a
    // value up).
    for ((v, w), &f) in values.iter_mut().zip(&lattice.v).zip(frozen) {
        if !f {
            *v = v.min(f32::from_bits(w.load(Relaxed)) as f64);
        }
    }
    SweepReport { passes, converged }
}

/// The sweep's state, shared by the two halves of a pass.
struct Lattice {
    /// Node values (f32 bits).
    v: Vec<AtomicU32>,
    /// Per node: [`LOCKED`], [`ACTIVE`] or [`FROZEN`].
    state: Vec<AtomicU8>,
    row_active: Vec<AtomicBool>,
    /// Per row: the nodes updated in it in the last pass (to split the next one evenly).
    row_work: Vec<AtomicU32>,
    dims: [usize; 3],
    h: f32,
    tol: f32,
}

impl Lattice {
    /// Where the rows of a pass in `ordering` split into halves of about equal work, if the
    /// work per row stays as in the last pass: at a group boundary, at least a group from
    /// either end. (The place only balances the threads; the sweep's result is the same at any.)
    fn even_split(&self, ordering: u32) -> usize {
        let [_, ny, _] = self.dims;
        let mut per_y = vec![0u64; ny];
        for (r, w) in self.row_work.iter().enumerate() {
            per_y[r % ny] += u64::from(w.load(Relaxed)) + 1;
        }
        let total: u64 = per_y.iter().sum();
        let reverse = ordering & 2 != 0;
        let mut sum = 0;
        let mut at = ny / GROUP * GROUP;
        for ky in (0..ny).step_by(GROUP) {
            if 2 * sum >= total {
                at = ky;
                break;
            }
            for k in ky..(ky + GROUP).min(ny) {
                sum += per_y[if reverse { ny - 1 - k } else { k }];
            }
        }
        at.clamp(GROUP, (ny - GROUP) / GROUP * GROUP)
    }
}

/// One pass, its rows (in sweep order) split at `half`: the first half of every z plane, then
/// the second. The second half of plane k needs the first half of plane k done (its first row
/// reads its upwind y neighbours there) and nothing of the first half of any later plane. Every
/// node the two halves both touch lies on the seam between them, in a row that both orders (row
/// after row over whole planes, or half after half) reach before or after the same other rows,
/// so each node reads the same values and wakes the same neighbours as in one sweep over whole
/// planes. Natively the second half trails the first by a plane on another thread, and the
/// result is the same bit for bit.
struct Halves<'a> {
    lattice: &'a Lattice,
    ordering: u32,
    half: usize,
    /// Planes (in sweep order) whose first half is done.
    first_done: AtomicUsize,
}

impl<'a> Halves<'a> {
    fn new(lattice: &'a Lattice, ordering: u32, half: usize) -> Self {
        Self {
            lattice,
            ordering,
            half,
            first_done: AtomicUsize::new(0),
        }
    }

    /// Sweeps the pass, the second half on another thread when there is one (natively); true
    /// when a node woke its neighbours.
    fn on_two_threads(&self) -> bool {
        if self.half == self.lattice.dims[1] {
            return self.first();
        }
        /// Marks every plane's first half done when dropped, also when the first half panics,
        /// so that the second never waits forever (the scope joins it before unwinding).
        struct AllDone<'b>(&'b AtomicUsize);
        impl Drop for AllDone<'_> {
            fn drop(&mut self) {
                self.0.store(usize::MAX, Release);
            }
        }
        std::thread::scope(|scope| {
            let second = scope.spawn(|| self.second());
            let first = {
                let _all_done = AllDone(&self.first_done);
                self.first()
            };
            match second.join() {
                Ok(second) => first | second,
                Err(panic) => std::panic::resume_unwind(panic),
            }
        })
    }

    /// Whether the second half of plane `kz` may be swept.
    fn ready(&self, kz: usize) -> bool {
        self.first_done.load(Acquire) > kz
    }

    /// Sweeps the first half of every plane; true when a node woke its neighbours.
    fn first(&self) -> bool {
        let mut changed = false;
        for kz in 0..self.lattice.dims[2] {
            changed |= self.plane(kz, 0, self.half);
            self.first_done.store(kz + 1, Release);
        }
        changed
    }

    /// Sweeps the second half of every plane, each once the first half of it is done.
    fn second(&self) -> bool {
        let mut changed = false;
        let [_, ny, nz] = self.lattice.dims;
        for kz in 0..nz {
            let mut spins = 0u32;
            while !self.ready(kz) {
                spins += 1;
                if spins < 64 {
                    std::hint::spin_loop();
                } else {
                    std::thread::yield_now();
                }
            }
            changed |= self.plane(kz, self.half, ny);
        }
        changed
    }

    /// Sweeps rows `from..to` (in sweep order) of plane `kz` (in sweep order) in groups.
    fn plane(&self, kz: usize, from: usize, to: usize) -> bool {
        let l = self.lattice;
        let [nx, ny, nz] = l.dims;
        let sxy = nx * ny;
        let (rx, ry, rz) = (
            self.ordering & 1 != 0,
            self.ordering & 2 != 0,
            self.ordering & 4 != 0,
        );
        let iz = if rz { nz - 1 - kz } else { kz };
        let zm = if iz > 0 { sxy } else { 0 };
        let zp = if iz + 1 < nz { sxy } else { 0 };
        let mut changed = false;
        let mut ky = from;
        while ky < to {
            // A group of up to GROUP consecutive rows (in sweep order) of this z plane.
            let mut group = [RowJob::default(); GROUP];
            let mut len = 0;
            for (k, job) in group.iter_mut().enumerate().take(to - ky) {
                let iy = if ry { ny - 1 - (ky + k) } else { ky + k };
                let r = iy + ny * iz;
                *job = RowJob {
                    start: nx * r,
                    offsets: [
                        if iy > 0 { nx } else { 0 },
                        if iy + 1 < ny { nx } else { 0 },
                        zm,
                        zp,
                    ],
                    run: l.row_active[r].swap(false, Relaxed),
                    woke: false,
                    work: 0,
                };
                len = k + 1;
            }
            // A row woken by the row before it in the same group must still run in this
            // pass (as it would row by row), so a group runs whole or not at all.
            if group[..len].iter().any(|j| j.run) {
                for job in &mut group[..len] {
                    job.run = true;
                }
                sweep_rows(l, &mut group[..len], rx);
            }
            for job in &group[..len] {
                let r = job.start / nx;
                l.row_work[r].store(job.work, Relaxed);
                if job.woke {
                    changed = true;
                    // Rows of the neighbours that may have been re-activated (a missing
                    // neighbour is the row itself).
                    let [ym, yp, zm, zp] = job.offsets;
                    for n in [r, r - ym / nx, r + yp / nx, r - zm / nx, r + zp / nx] {
                        l.row_active[n].store(true, Relaxed);
                    }
                }
            }
            ky += len;
        }
        changed
    }
}

/// Minimum by a plain comparison. `f32::min` must return the non-NaN operand, which costs extra
/// instructions on x86 and several on wasm32; sweep values are never NaN.
#[inline(always)]
fn fmin(a: f32, b: f32) -> f32 {
    if a < b {
        a
    } else {
        b
    }
}

const LOCKED: u8 = 0;
const ACTIVE: u8 = 1;
const FROZEN: u8 = 2;

/// Rows swept together, skewed by one node each (see [`sweep_rows`]). Grouping helps the
/// native cores' caches; wasm (one thread, no wide loads) is faster one row at a time, and the
/// result is bit-identical either way.
const GROUP: usize = if cfg!(target_arch = "wasm32") { 1 } else { 4 };

/// One row of a pass: first storage index, neighbour offsets (y−, y+, z−, z+; 0 = missing),
/// whether it may hold active nodes, and (out) whether some node in it woke its neighbours.
#[derive(Clone, Copy, Default)]
struct RowJob {
    start: usize,
    offsets: [usize; 4],
    run: bool,
    woke: bool,
    /// Nodes updated.
    work: u32,
}

/// Sweeps a group of consecutive rows of one z plane in one pass direction. Row `k` of the group
/// trails row `k − 1` by one node, so that the Gauss–Seidel dependencies (each node needs its x-
/// and y-upwind neighbours updated first) are the same as row after row, while the group's rows
/// form independent dependency chains the CPU can overlap (a single row is one long chain of
/// sqrt-bound updates).
fn sweep_rows(l: &Lattice, rows: &mut [RowJob], reverse: bool) {
    let nx = l.dims[0];
    let n = rows.len();
    for job in rows.iter() {
        let [ym, yp, zm, zp] = job.offsets;
        // Every index used lies in rows start − zm … start + zp, which exist by construction.
        assert!(job.start >= ym.max(zm) && job.start + nx + yp.max(zp) <= l.v.len());
    }
    assert_eq!(l.v.len(), l.state.len());
    for step in 0..nx + n - 1 {
        for (k, job) in rows.iter_mut().enumerate() {
            if !job.run || step < k || step - k >= nx {
                continue;
            }
            let s = step - k;
            let ix = if reverse { nx - 1 - s } else { s };
            let done = visit(l, job.start, ix, job.offsets);
            job.work += u32::from(done != Visit::Skipped);
            job.woke |= done == Visit::Woke;
        }
    }
}

/// What [`visit`] did to a node.
#[derive(Clone, Copy, PartialEq, Eq)]
enum Visit {
    /// Not active: nothing to do.
    Skipped,
    /// Computed (and maybe lowered by at most the tolerance).
    Updated,
    /// Dropped by more than the tolerance, re-activating its neighbours.
    Woke,
}

/// Updates node `ix` of the row starting at `row`; says whether it dropped by more than the
/// tolerance (and so re-activated its neighbours). Offsets of 0 point a missing neighbour at the
/// node itself, which can never lower the node (the update is ≥ its smallest input): it acts as
/// +∞.
#[inline(always)]
fn visit(l: &Lattice, row: usize, ix: usize, [ym, yp, zm, zp]: [usize; 4]) -> Visit {
    let nx = l.dims[0];
    let i = row + ix;
    let xm = if ix > 0 { i - 1 } else { i };
    let xp = if ix + 1 < nx { i + 1 } else { i };
    let nb = [xm, xp, i - ym, i + yp, i - zm, i + zp];
    debug_assert!(nb.iter().all(|&j| j < l.v.len()) && l.v.len() == l.state.len());
    // SAFETY: `sweep_rows` asserted that rows start − ym/zm … start + yp/zp lie inside `v`
    // (and `state`, of equal length), and ix < nx, so i and all of `nb` are in bounds.
    unsafe {
        let st = l.state.get_unchecked(i);
        if st.load(Relaxed) != ACTIVE {
            return Visit::Skipped;
        }
        st.store(LOCKED, Relaxed);
        let g = |j: usize| f32::from_bits(l.v.get_unchecked(j).load(Relaxed));
        let a = fmin(g(nb[0]), g(nb[1]));
        let b = fmin(g(nb[2]), g(nb[3]));
        let c = fmin(g(nb[4]), g(nb[5]));
        let cur = g(i);
        if fmin(fmin(a, b), c) >= cur {
            return Visit::Updated;
        }
        let u = godunov_update_f32(a, b, c, l.h);
        if u >= cur {
            return Visit::Updated;
        }
        l.v.get_unchecked(i).store(u.to_bits(), Relaxed);
        if cur - u <= l.tol {
            return Visit::Updated;
        }
        for j in nb {
            let s = l.state.get_unchecked(j);
            if s.load(Relaxed) == LOCKED {
                s.store(ACTIVE, Relaxed);
            }
        }
        // A missing neighbour is the node itself: keep it locked.
        st.store(LOCKED, Relaxed);
    }
    Visit::Woke
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn update_cases() {
        let h = 1.0;
        // 1D: one close neighbour.
        assert_eq!(godunov_update(0.0, 5.0, 5.0, h), 1.0);
        // 2D: symmetric, u = a + h/√2.
        assert!((godunov_update(0.0, 0.0, 5.0, h) - std::f64::consts::FRAC_1_SQRT_2).abs() < 1e-15);
        // 3D: symmetric, u = a + h/√3.
        assert!((godunov_update(0.0, 0.0, 0.0, h) - 1.0 / 3f64.sqrt()).abs() < 1e-15);
        // Infinite neighbours are ignored.
        assert_eq!(godunov_update(f64::INFINITY, 2.0, f64::INFINITY, h), 3.0);
    }

    #[test]
    fn plane_wave_is_exact() {
        // A plane source x = 0 frozen: the sweep reproduces d = x exactly.
        let g = Grid {
            origin: glam::DVec3::ZERO,
            cell: 0.5,
            dims: [10, 6, 5],
        };
        let n = g.node_count();
        let mut v = vec![f64::INFINITY; n];
        let mut f = vec![false; n];
        for i in 0..n {
            if g.coords(i)[0] == 0 {
                v[i] = 0.0;
                f[i] = true;
            }
        }
        let mut heard = Vec::new();
        let rep = fast_sweep(&g, &mut v, &f, 64, 0.0, &mut |x| heard.push(x));
        assert!(rep.converged);
        // One report a pass, k / 64 after pass k.
        let want: Vec<f64> = (1..=rep.passes).map(|k| k as f64 / 64.0).collect();
        assert_eq!(heard, want);
        for (i, &x) in v.iter().enumerate() {
            assert!((x - g.position_of(i).x).abs() < 1e-12);
        }
    }

    #[test]
    fn two_halves_sweep_bit_for_bit_as_one() {
        // Either half after the other on one thread, as late (all of the first, then the
        // second) and as early (each second-half plane as soon as it is ready) as allowed.
        fn lagging(h: &Halves) -> bool {
            h.first() | h.second()
        }
        fn eager(h: &Halves) -> bool {
            let [_, ny, nz] = h.lattice.dims;
            let (mut changed, mut next) = (false, 0);
            for kz in 0..nz {
                changed |= h.plane(kz, 0, h.half);
                h.first_done.store(kz + 1, Release);
                while next < nz && h.ready(next) {
                    changed |= h.plane(next, h.half, ny);
                    next += 1;
                }
            }
            changed
        }
        // Scattered frozen seeds with exact distances to a few random points, so that the fronts
        // cross the seam between the halves in every direction and many passes run.
        for (dims, tolerance) in [
            ([17, 37, 11], 0.0),
            ([9, 16, 23], 1e-4),
            ([30, 41, 29], 0.0),
        ] {
            let g = Grid {
                origin: glam::DVec3::ZERO,
                cell: 0.25,
                dims,
            };
            let n = g.node_count();
            let mut rng = crate::demo::Rng::new(dims[1] as u64);
            let mut rand = || rng.uniform();
            let hi = g.position_of(n - 1);
            let sources: Vec<glam::DVec3> = (0..7)
                .map(|_| glam::DVec3::new(rand() * hi.x, rand() * hi.y, rand() * hi.z))
                .collect();
            let mut v = vec![f64::INFINITY; n];
            let mut f = vec![false; n];
            for i in 0..n {
                let p = g.position_of(i);
                let d = sources
                    .iter()
                    .map(|s| s.distance(p))
                    .fold(f64::INFINITY, f64::min);
                if d < 0.6 {
                    v[i] = d;
                    f[i] = true;
                }
            }
            let mut one = v.clone();
            let a = sweep_split(&g, &mut one, &f, 64, tolerance, None, &mut |_| {});
            let runs: [fn(&Halves) -> bool; 3] = [|h| h.on_two_threads(), lagging, eager];
            for run in runs {
                let mut two = v.clone();
                let b = sweep_split(&g, &mut two, &f, 64, tolerance, Some(run), &mut |_| {});
                assert_eq!(a, b, "{dims:?}");
                assert!(
                    one.iter()
                        .zip(&two)
                        .all(|(x, y)| x.to_bits() == y.to_bits()),
                    "{dims:?}"
                );
            }
            assert!(a.converged && a.passes > 8, "{dims:?}: {a:?}");
            assert!(one.iter().all(|x| x.is_finite()));
        }
    }
}
