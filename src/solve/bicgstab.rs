//! Right-preconditioned BiCGStab (van der Vorst 1992) for non-symmetric systems.

use super::{spmv, Jacobi, SolveError, SolveReport, SolverSettings};
use sprs::CsMat;

fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

/// Solves `A·x = b` starting from the guess in `x`. Returns iterations and the true final
/// relative residual, or a typed error (never panics, never returns NaN).
pub fn bicgstab(
    a: &CsMat<f64>,
    b: &[f64],
    x: &mut [f64],
    pre: &Jacobi,
    settings: &SolverSettings,
) -> Result<SolveReport, SolveError> {
    let n = a.rows();
    if a.cols() != n || b.len() != n || x.len() != n {
        return Err(SolveError::Dimension {
            rows: n,
            cols: a.cols(),
            len: b.len().min(x.len()),
        });
    }
    if !b.iter().chain(x.iter()).all(|v| v.is_finite()) {
        return Err(SolveError::NonFinite { iterations: 0 });
    }
    let bnorm = dot(b, b).sqrt();
    if bnorm == 0.0 {
        x.fill(0.0);
        return Ok(SolveReport {
            iterations: 0,
            relative_residual: 0.0,
        });
    }
    let tol = settings.tolerance;
    let mut r = vec![0.0; n];
    spmv(a, x, &mut r);
    for (ri, bi) in r.iter_mut().zip(b) {
        *ri = bi - *ri;
    }
    let mut res = dot(&r, &r).sqrt() / bnorm;
    if res <= tol {
        return Ok(SolveReport {
            iterations: 0,
            relative_residual: res,
        });
    }
    let r0 = r.clone();
    let (mut p, mut v) = (vec![0.0; n], vec![0.0; n]);
    let (mut phat, mut shat, mut s, mut t) =
        (vec![0.0; n], vec![0.0; n], vec![0.0; n], vec![0.0; n]);
    let (mut rho_old, mut alpha, mut omega) = (1.0f64, 1.0f64, 1.0f64);
    // Inner products below this (relative to the scale of the vectors) count as zero.
    let tiny = f64::EPSILON * f64::EPSILON;
    for it in 1..=settings.max_iterations {
        let rho = dot(&r0, &r);
        if rho.abs() <= tiny * bnorm * bnorm {
            return Err(SolveError::Breakdown {
                iterations: it,
                residual: res,
            });
        }
        let beta = (rho / rho_old) * (alpha / omega);
        for i in 0..n {
            p[i] = r[i] + beta * (p[i] - omega * v[i]);
        }
        pre.apply(&p, &mut phat);
        spmv(a, &phat, &mut v);
        let r0v = dot(&r0, &v);
        if r0v.abs() <= tiny * bnorm * bnorm {
            return Err(SolveError::Breakdown {
                iterations: it,
                residual: res,
            });
        }
        alpha = rho / r0v;
        for i in 0..n {
            s[i] = r[i] - alpha * v[i];
        }
        let snorm = dot(&s, &s).sqrt() / bnorm;
        if snorm <= tol {
            for i in 0..n {
                x[i] += alpha * phat[i];
            }
            return finish(a, b, x, bnorm, it, tol, settings);
        }
        pre.apply(&s, &mut shat);
        spmv(a, &shat, &mut t);
        let tt = dot(&t, &t);
        if tt == 0.0 {
            return Err(SolveError::Breakdown {
                iterations: it,
                residual: res,
            });
        }
        omega = dot(&t, &s) / tt;
        for i in 0..n {
            x[i] += alpha * phat[i] + omega * shat[i];
            r[i] = s[i] - omega * t[i];
        }
        res = dot(&r, &r).sqrt() / bnorm;
        if !res.is_finite() {
            return Err(SolveError::NonFinite { iterations: it });
        }
        if res <= tol {
            return finish(a, b, x, bnorm, it, tol, settings);
        }
        if omega == 0.0 {
            return Err(SolveError::Breakdown {
                iterations: it,
                residual: res,
            });
        }
        rho_old = rho;
    }
    Err(SolveError::NotConverged {
        iterations: settings.max_iterations,
        residual: res,
        tolerance: tol,
    })
}

/// Recomputes the true residual (the recursive one drifts) and accepts within 10× tolerance.
fn finish(
    a: &CsMat<f64>,
    b: &[f64],
    x: &[f64],
    bnorm: f64,
    iterations: usize,
    tol: f64,
    settings: &SolverSettings,
) -> Result<SolveReport, SolveError> {
    let mut ax = vec![0.0; b.len()];
    spmv(a, x, &mut ax);
    let res = ax
        .iter()
        .zip(b)
        .map(|(p, q)| (q - p) * (q - p))
        .sum::<f64>()
        .sqrt()
        / bnorm;
    if !res.is_finite() || x.iter().any(|v| !v.is_finite()) {
        return Err(SolveError::NonFinite { iterations });
    }
    if res > 10.0 * tol {
        return Err(SolveError::NotConverged {
            iterations: settings.max_iterations.min(iterations),
            residual: res,
            tolerance: tol,
        });
    }
    Ok(SolveReport {
        iterations,
        relative_residual: res,
    })
}

#[cfg(test)]
mod tests {
    use super::super::solve_columns;
    use super::*;
    use sprs::TriMat;

    /// Deterministic xorshift so tests need no RNG crate.
    fn rng(seed: &mut u64) -> f64 {
        *seed ^= *seed << 13;
        *seed ^= *seed >> 7;
        *seed ^= *seed << 17;
        (*seed >> 11) as f64 / (1u64 << 53) as f64
    }

    #[test]
    #[allow(clippy::needless_range_loop)]
    fn solves_random_diagonally_dominant_system() {
        let n = 400;
        let mut seed = 0x9e3779b97f4a7c15u64;
        let mut tri = TriMat::new((n, n));
        let mut rowsum = vec![0.0; n];
        for i in 0..n {
            for _ in 0..6 {
                let j = (rng(&mut seed) * n as f64) as usize % n;
                if j != i {
                    let v = rng(&mut seed) * 2.0 - 1.0;
                    tri.add_triplet(i, j, v);
                    rowsum[i] += v.abs();
                }
            }
        }
        for (i, s) in rowsum.iter().enumerate() {
            tri.add_triplet(i, i, s + 0.5 + rng(&mut seed));
        }
        let a: CsMat<f64> = tri.to_csr();
        let xs: Vec<f64> = (0..n).map(|_| rng(&mut seed) - 0.5).collect();
        let mut b = vec![0.0; n];
        spmv(&a, &xs, &mut b);
        for tol in [1e-6, 1e-10, 1e-13] {
            let settings = SolverSettings {
                tolerance: tol,
                max_iterations: 1000,
            };
            let mut x = vec![vec![0.0; n]];
            let rep = solve_columns(&a, &[b.clone()], &mut x, &settings).unwrap();
            assert!(rep.relative_residual <= 10.0 * tol, "{rep:?}");
            assert!(rep.iterations > 0);
            let err = x[0]
                .iter()
                .zip(&xs)
                .map(|(p, q)| (p - q).abs())
                .fold(0.0, f64::max);
            assert!(err < 1e3 * tol, "tol {tol}: max error {err}");
        }
    }

    #[test]
    fn three_column_solver_matches_single_columns() {
        let n = 300;
        let mut seed = 0x1234_5678_9abc_def1u64;
        let mut tri = TriMat::new((n, n));
        for i in 0..n {
            let mut sum = 0.0;
            for k in [1, 7, 31] {
                let j = (i + k) % n;
                let v = rng(&mut seed) - 0.5;
                tri.add_triplet(i, j, v);
                sum += v.abs();
            }
            tri.add_triplet(i, i, sum + 0.2);
        }
        let a: CsMat<f64> = tri.to_csr();
        let b: Vec<glam::DVec3> = (0..n)
            .map(|_| glam::DVec3::new(rng(&mut seed), rng(&mut seed) - 0.5, 0.0))
            .collect();
        let settings = SolverSettings::default();
        let mut x = b.clone();
        let rep = crate::solve::solve_xyz(&a, &b, &mut x, &settings).unwrap();
        assert!(rep.relative_residual <= 1e-9);
        for c in 0..2 {
            let bc: Vec<f64> = b.iter().map(|v| v[c]).collect();
            let mut xc = bc.clone();
            let pre = Jacobi::new(&a).unwrap();
            bicgstab(&a, &bc, &mut xc, &pre, &settings).unwrap();
            let err = xc
                .iter()
                .zip(&x)
                .map(|(p, q)| (p - q[c]).abs())
                .fold(0.0, f64::max);
            assert!(err < 1e-8, "column {c}: {err}");
        }
        assert!(x.iter().all(|v| v.z == 0.0), "a zero column stays zero");
        // Failure modes surface as errors here too.
        let tight = SolverSettings {
            max_iterations: 1,
            tolerance: 1e-30,
        };
        assert!(crate::solve::solve_xyz(&a, &b, &mut x.clone(), &tight).is_err());
    }

    #[test]
    fn singular_systems_give_errors_not_panics() {
        // Rank-one matrix with an inconsistent right-hand side: no solution exists.
        let mut tri = TriMat::new((2, 2));
        for (i, j) in [(0, 0), (0, 1), (1, 0), (1, 1)] {
            tri.add_triplet(i, j, 1.0);
        }
        let a: CsMat<f64> = tri.to_csr();
        let mut x = vec![vec![0.0; 2]];
        let err =
            solve_columns(&a, &[vec![1.0, 0.0]], &mut x, &SolverSettings::default()).unwrap_err();
        assert!(
            matches!(
                err,
                SolveError::Breakdown { .. } | SolveError::NotConverged { .. }
            ),
            "{err:?}"
        );

        // Zero row: the diagonal cannot be inverted.
        let mut tri = TriMat::new((2, 2));
        tri.add_triplet(0, 0, 1.0);
        let a: CsMat<f64> = tri.to_csr();
        let err =
            solve_columns(&a, &[vec![1.0, 1.0]], &mut x, &SolverSettings::default()).unwrap_err();
        assert_eq!(err, SolveError::BadDiagonal { row: 1 });

        // NaN input.
        let mut tri = TriMat::new((1, 1));
        tri.add_triplet(0, 0, 1.0);
        let a: CsMat<f64> = tri.to_csr();
        let mut x1 = vec![vec![0.0]];
        let err =
            solve_columns(&a, &[vec![f64::NAN]], &mut x1, &SolverSettings::default()).unwrap_err();
        assert!(matches!(err, SolveError::NonFinite { .. }));
    }
}
