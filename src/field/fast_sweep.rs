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
//!   `√|disc|` instead, §13.6).
//!
//! A value is only ever lowered. Sweeping stops after the first pass in which no value dropped
//! by more than `tolerance·h`. Nodes none of whose neighbours dropped (by more than that) since
//! their last update are skipped ("locking", Bak et al. 2010): their update could not change.
//! With
//! `tolerance = 0` this is "until no value changes": in a Gauss–Seidel pass that changes nothing
//! every node was updated against the final values of its neighbours, so the discrete solution
//! is reached exactly, but round-off ripples (drops of 1e-12 h) can keep that going for ~60 passes
//! on a real scan. The drops after the first cycle are already below 1e-4 h (bunny: 4e-5 h after
//! pass 9, 3e-8 h after pass 16), far below the scheme's O(h) discretisation error, hence the
//! default tolerance 1e-4 (see `FieldSettings::sweep_tolerance`). [`SweepReport::converged`] is
//! false when the pass cap stopped it first.

use super::grid::Grid;

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
pub fn fast_sweep(
    grid: &Grid,
    values: &mut [f64],
    frozen: &[bool],
    max_passes: u32,
    tolerance: f64,
    pass_done: &mut dyn FnMut(f64),
) -> SweepReport {
    let [nx, ny, nz] = grid.dims;
    assert!(
        nx >= 2 && ny >= 2 && nz >= 2,
        "sweeping needs ≥ 2 nodes per axis"
    );
    assert_eq!(values.len(), nx * ny * nz);
    let h = grid.cell as f32;
    let tol = (tolerance * grid.cell) as f32;
    let sxy = nx * ny;
    let mut work: Vec<f32> = values.iter().map(|&x| x as f32).collect();
    // Locking (Bak, McLaughlin & Renzi 2010): a node is only recomputed while "active", i.e. when
    // one of its neighbours dropped since its own last update; otherwise its update could not
    // change. Frozen nodes are never active.
    let mut state: Vec<u8> = frozen
        .iter()
        .map(|&f| if f { FROZEN } else { ACTIVE })
        .collect();
    // Per row (iy, iz): whether it may hold an active node, so that late passes, with only a few
    // active nodes left, skip whole rows.
    let mut row_active = vec![true; ny * nz];
    let mut passes = 0;
    while passes < max_passes {
        let ordering = passes % 8;
        let (rx, ry, rz) = (ordering & 1 != 0, ordering & 2 != 0, ordering & 4 != 0);
        passes += 1;
        let mut changed = false;
        for kz in 0..nz {
            let iz = if rz { nz - 1 - kz } else { kz };
            let zm = if iz > 0 { sxy } else { 0 };
            let zp = if iz + 1 < nz { sxy } else { 0 };
            let mut ky = 0;
            while ky < ny {
                // A group of up to GROUP consecutive rows (in sweep order) of this z plane.
                let mut group = [RowJob::default(); GROUP];
                let mut len = 0;
                for (k, job) in group.iter_mut().enumerate().take(ny - ky) {
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
                        run: row_active[r],
                        woke: false,
                    };
                    row_active[r] = false;
                    len = k + 1;
                }
                // A row woken by the row before it in the same group must still run in this
                // pass (as it would row by row), so a group runs whole or not at all.
                if group[..len].iter().any(|j| j.run) {
                    for job in &mut group[..len] {
                        job.run = true;
                    }
                    sweep_rows(&mut work, &mut state, &mut group[..len], nx, rx, h, tol);
                }
                for job in &group[..len] {
                    if job.woke {
                        changed = true;
                        // Rows of the neighbours that may have been re-activated (a missing
                        // neighbour is the row itself).
                        let r = job.start / nx;
                        let [ym, yp, zm, zp] = job.offsets;
                        row_active[r] = true;
                        row_active[r - ym / nx] = true;
                        row_active[r + yp / nx] = true;
                        row_active[r - zm / nx] = true;
                        row_active[r + zp / nx] = true;
                    }
                }
                ky += len;
            }
        }
        pass_done(passes as f64 / max_passes.max(1) as f64);
        if !changed {
            // No node dropped, so none was re-activated: every later pass would be a no-op.
            write_back(values, &work, frozen);
            return SweepReport {
                passes,
                converged: true,
            };
        }
    }
    write_back(values, &work, frozen);
    SweepReport {
        passes,
        converged: false,
    }
}

/// Copies swept values back, never raising one (f32 rounding could otherwise nudge a value up).
fn write_back(values: &mut [f64], work: &[f32], frozen: &[bool]) {
    for ((v, &w), &f) in values.iter_mut().zip(work).zip(frozen) {
        if !f {
            *v = v.min(w as f64);
        }
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

/// Rows swept together, skewed by one node each (see [`sweep_rows`]).
const GROUP: usize = 4;

/// One row of a pass: first storage index, neighbour offsets (y−, y+, z−, z+; 0 = missing),
/// whether it may hold active nodes, and (out) whether some node in it woke its neighbours.
#[derive(Clone, Copy, Default)]
struct RowJob {
    start: usize,
    offsets: [usize; 4],
    run: bool,
    woke: bool,
}

/// Sweeps a group of consecutive rows of one z plane in one pass direction. Row `k` of the group
/// trails row `k − 1` by one node, so that the Gauss–Seidel dependencies (each node needs its x-
/// and y-upwind neighbours updated first) are the same as row after row, while the group's rows
/// form independent dependency chains the CPU can overlap (a single row is one long chain of
/// sqrt-bound updates).
fn sweep_rows(
    v: &mut [f32],
    state: &mut [u8],
    rows: &mut [RowJob],
    nx: usize,
    reverse: bool,
    h: f32,
    tol: f32,
) {
    let n = rows.len();
    for job in rows.iter() {
        let [ym, yp, zm, zp] = job.offsets;
        // Every index used lies in rows start − zm … start + zp, which exist by construction.
        assert!(job.start >= ym.max(zm) && job.start + nx + yp.max(zp) <= v.len());
    }
    assert_eq!(v.len(), state.len());
    for step in 0..nx + n - 1 {
        for (k, job) in rows.iter_mut().enumerate() {
            if !job.run || step < k || step - k >= nx {
                continue;
            }
            let s = step - k;
            let ix = if reverse { nx - 1 - s } else { s };
            job.woke |= visit(v, state, job.start, ix, nx, job.offsets, h, tol);
        }
    }
}

/// Updates node `ix` of the row starting at `row`; returns whether it dropped by more than `tol`
/// (and so re-activated its neighbours). Offsets of 0 point a missing neighbour at the node
/// itself, which can never lower the node (the update is ≥ its smallest input): it acts as +∞.
#[inline(always)]
#[allow(clippy::too_many_arguments)]
fn visit(
    v: &mut [f32],
    state: &mut [u8],
    row: usize,
    ix: usize,
    nx: usize,
    [ym, yp, zm, zp]: [usize; 4],
    h: f32,
    tol: f32,
) -> bool {
    let i = row + ix;
    let xm = if ix > 0 { i - 1 } else { i };
    let xp = if ix + 1 < nx { i + 1 } else { i };
    let nb = [xm, xp, i - ym, i + yp, i - zm, i + zp];
    debug_assert!(nb.iter().all(|&j| j < v.len()) && v.len() == state.len());
    // SAFETY: `sweep_rows` asserted that rows start − ym/zm … start + yp/zp lie inside `v`
    // (and `state`, of equal length), and ix < nx, so i and all of `nb` are in bounds.
    unsafe {
        let st = state.get_unchecked_mut(i);
        if *st != ACTIVE {
            return false;
        }
        *st = LOCKED;
        let g = |j: usize| *v.get_unchecked(j);
        let a = fmin(g(nb[0]), g(nb[1]));
        let b = fmin(g(nb[2]), g(nb[3]));
        let c = fmin(g(nb[4]), g(nb[5]));
        let cur = g(i);
        if fmin(fmin(a, b), c) >= cur {
            return false;
        }
        let u = godunov_update_f32(a, b, c, h);
        if u >= cur {
            return false;
        }
        *v.get_unchecked_mut(i) = u;
        if cur - u <= tol {
            return false;
        }
        for j in nb {
            let s = state.get_unchecked_mut(j);
            if *s == LOCKED {
                *s = ACTIVE;
            }
        }
        // A missing neighbour is the node itself: keep it locked.
        *state.get_unchecked_mut(i) = LOCKED;
    }
    true
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
}
