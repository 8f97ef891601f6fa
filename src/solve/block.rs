//! BiCGStab on three right-hand sides at once (x, y, z of the flow). Each column runs its own
//! Krylov recurrence, but the matrix is streamed once per product for all three, which is ~2×
//! faster than three separate solves.
//!
//! It iterates on the row-scaled system `D⁻¹A x = D⁻¹b` ([`ScaledRows`]: unit diagonal), which
//! is Jacobi preconditioning without the two preconditioned vectors per iteration, and every
//! vector update is fused with the dot products that read it (one pass instead of two or three).
//! Convergence is still judged on the true residual `‖b − Ax‖ = ‖D·r‖`, whose norm falls out of
//! the same passes. The sparse products dominate; the vector passes take a minor share of the
//! time.

use super::{ScaledRows, SolveError, SolveReport, SolverSettings};

type V3 = [f64; 3];

#[inline(always)]
fn add_products(acc: &mut V3, a: &V3, b: &V3) {
    for c in 0..3 {
        acc[c] += a[c] * b[c];
    }
}

/// A dot product over rows in four interleaved partial sums (row i in lane i mod 4): with one
/// accumulator the n additions form a single dependency chain, which costs more than the memory
/// traffic of the fused passes. The lanes are combined in a fixed order, so results stay
/// deterministic (and identical natively and in wasm).
#[derive(Clone, Copy, Default)]
struct Dot {
    lanes: [V3; 4],
}

impl Dot {
    /// Adds `a·b` (per column) for row `i`.
    #[inline(always)]
    fn add(&mut self, i: usize, a: &V3, b: &V3) {
        add_products(&mut self.lanes[i & 3], a, b);
    }

    /// Adds `(d·a)²` (per column) for row `i`: the squared norm of an unscaled residual.
    #[inline(always)]
    fn add_scaled_square(&mut self, i: usize, d: f64, a: &V3) {
        let l = &mut self.lanes[i & 3];
        for c in 0..3 {
            let v = d * a[c];
            l[c] += v * v;
        }
    }

    fn total(&self) -> V3 {
        let l = &self.lanes;
        std::array::from_fn(|c| (l[0][c] + l[1][c]) + (l[2][c] + l[3][c]))
    }
}

fn dot3(a: &[V3], b: &[V3]) -> V3 {
    let mut s = Dot::default();
    for (i, (p, q)) in a.iter().zip(b).enumerate() {
        s.add(i, p, q);
    }
    s.total()
}

/// Solves `A·X = B` for the three columns of `b` (rows as `[x, y, z]`), starting from `x`.
/// Same contract as [`super::bicgstab`]: true relative residual per column ≤ 10× tolerance,
/// typed errors, never NaN.
pub fn bicgstab3(
    a: &ScaledRows,
    b: &[V3],
    x: &mut [V3],
    settings: &SolverSettings,
) -> Result<SolveReport, SolveError> {
    let n = a.n();
    if b.len() != n || x.len() != n {
        return Err(SolveError::Dimension {
            rows: n,
            cols: n,
            len: b.len().min(x.len()),
        });
    }
    if !b.iter().chain(x.iter()).flatten().all(|v| v.is_finite()) {
        return Err(SolveError::NonFinite { iterations: 0 });
    }
    let diag = a.diag();
    let inv: Vec<f64> = diag.iter().map(|d| 1.0 / d).collect();
    let m = a;
    let bn = dot3(b, b).map(f64::sqrt);
    let tol = settings.tolerance;
    // r = D⁻¹(b − A x).
    let mut r = vec![[0.0; 3]; n];
    let mut rr_true = Dot::default();
    m.mul_unit_then(x, &mut r, |_, _| {});
    for (i, (ri, bi)) in r.iter_mut().zip(b).enumerate() {
        for c in 0..3 {
            ri[c] = bi[c] * inv[i] - ri[c];
        }
        rr_true.add_scaled_square(i, diag[i], ri);
    }
    let relative = |sq: V3, c: usize| sq[c].sqrt() / bn[c];
    // A column is active until its residual meets the tolerance; a zero column is solved by 0.
    let mut active = [true; 3];
    let mut res = [0.0f64; 3];
    for c in 0..3 {
        if bn[c] == 0.0 {
            for xi in x.iter_mut() {
                xi[c] = 0.0;
            }
            active[c] = false;
        } else {
            res[c] = relative(rr_true.total(), c);
            active[c] = res[c] > tol;
        }
    }
    let r0 = r.clone();
    let zero = vec![[0.0; 3]; n];
    let (mut p, mut v, mut s, mut t) = (zero.clone(), zero.clone(), zero.clone(), zero);
    let (mut rho_old, mut alpha, mut omega) = ([1.0f64; 3], [1.0f64; 3], [1.0f64; 3]);
    // Breakdown thresholds, in the scaled system's units.
    let bsn = {
        let mut q = Dot::default();
        for (i, (bi, d)) in b.iter().zip(&inv).enumerate() {
            q.add_scaled_square(i, *d, bi);
        }
        q.total()
    };
    let tiny = f64::EPSILON * f64::EPSILON;
    let mut rho = dot3(&r0, &r);
    let mut iterations = 0;
    // A finished column keeps iterating with zero coefficients, which leaves its x and r
    // unchanged, so the fused loops need no branches.
    while active.iter().any(|&a| a) {
        // Near round-off the recursive residual can stall just above the tolerance: stop at the
        // cap, or earlier once every column is within the 10× acceptance band, and let the true
        // residual below decide.
        let stalled = iterations >= 50 && (0..3).all(|c| !active[c] || res[c] <= 10.0 * tol);
        if iterations >= settings.max_iterations || stalled {
            break;
        }
        iterations += 1;
        let mut beta = [0.0; 3];
        for c in 0..3 {
            if active[c] {
                if rho[c].abs() <= tiny * bsn[c] {
                    return Err(SolveError::Breakdown {
                        iterations,
                        residual: res[c],
                    });
                }
                beta[c] = (rho[c] / rho_old[c]) * (alpha[c] / omega[c]);
            }
        }
        // p = r + β(p − ωv).
        let om = omega;
        for i in 0..n {
            for c in 0..3 {
                p[i][c] = r[i][c] + beta[c] * (p[i][c] - om[c] * v[i][c]);
            }
        }
        // v = M p and r₀·v.
        let mut r0v = Dot::default();
        m.mul_unit_then(&p, &mut v, |i, vi| r0v.add(i, &r0[i], vi));
        let r0v = r0v.total();
        for c in 0..3 {
            alpha[c] = 0.0;
            if active[c] {
                if r0v[c].abs() <= tiny * bsn[c] {
                    return Err(SolveError::Breakdown {
                        iterations,
                        residual: res[c],
                    });
                }
                alpha[c] = rho[c] / r0v[c];
            }
        }
        // s = r − αv, with the true norm ‖D s‖².
        let mut ss = Dot::default();
        for i in 0..n {
            for c in 0..3 {
                s[i][c] = r[i][c] - alpha[c] * v[i][c];
            }
            ss.add_scaled_square(i, diag[i], &s[i]);
        }
        let ss = ss.total();
        let mut half_done = [false; 3];
        for c in 0..3 {
            if active[c] && relative(ss, c) <= tol {
                half_done[c] = true;
            }
        }
        // t = M s with t·s and t·t.
        let (mut ts, mut tt) = (Dot::default(), Dot::default());
        m.mul_unit_then(&s, &mut t, |i, ti| {
            ts.add(i, ti, &s[i]);
            tt.add(i, ti, ti);
        });
        let (ts, tt) = (ts.total(), tt.total());
        let mut om = [0.0; 3];
        for c in 0..3 {
            if active[c] && !half_done[c] {
                if tt[c] == 0.0 {
                    return Err(SolveError::Breakdown {
                        iterations,
                        residual: res[c],
                    });
                }
                omega[c] = ts[c] / tt[c];
                om[c] = omega[c];
            }
        }
        // x += αp + ωs, r = s − ωt (a half-done column takes x += αp and stops), with the true
        // ‖D r‖² and the next ρ = r₀·r.
        let (mut rr, mut rho_next) = (Dot::default(), Dot::default());
        for i in 0..n {
            for c in 0..3 {
                x[i][c] += alpha[c] * p[i][c] + om[c] * s[i][c];
                r[i][c] = s[i][c] - om[c] * t[i][c];
            }
            rr.add_scaled_square(i, diag[i], &r[i]);
            rho_next.add(i, &r0[i], &r[i]);
        }
        let (rr, rho_next) = (rr.total(), rho_next.total());
        for c in 0..3 {
            if !active[c] {
                continue;
            }
            if half_done[c] {
                active[c] = false;
                continue;
            }
            res[c] = relative(rr, c);
            if !res[c].is_finite() {
                return Err(SolveError::NonFinite { iterations });
            }
            if res[c] <= tol {
                active[c] = false;
            } else if omega[c] == 0.0 {
                return Err(SolveError::Breakdown {
                    iterations,
                    residual: res[c],
                });
            }
            rho_old[c] = rho[c];
        }
        rho = rho_next;
    }
    // The recursive residual drifts: check the true one, b − A x = b − D(x + M x).
    let mut err = Dot::default();
    let mut finite = true;
    m.mul_unit_then(x, &mut r, |i, y| {
        let d = diag[i];
        let e = [b[i][0] - d * y[0], b[i][1] - d * y[1], b[i][2] - d * y[2]];
        err.add(i, &e, &e);
        finite &= x[i].iter().all(|v| v.is_finite());
    });
    let mut worst = 0.0f64;
    for (c, &norm) in bn.iter().enumerate() {
        if norm == 0.0 {
            continue;
        }
        let e = relative(err.total(), c);
        if !e.is_finite() {
            return Err(SolveError::NonFinite { iterations });
        }
        worst = worst.max(e);
    }
    if !finite {
        return Err(SolveError::NonFinite { iterations });
    }
    if worst > 10.0 * tol {
        return Err(SolveError::NotConverged {
            iterations,
            residual: worst,
            tolerance: tol,
        });
    }
    Ok(SolveReport {
        iterations,
        relative_residual: worst,
    })
}
