//! Sparse linear solvers on `sprs` CSR matrices, and on the row-scaled form the flow assembles
//! directly ([`ScaledRows`]).
//!
//! The LSW system `I + τ·ε·L` is non-symmetric (rows scaled by ε_i/A_i) but strongly diagonally
//! dominant for the time steps used, so Jacobi-preconditioned BiCGStab converges in a handful of
//! iterations (docs/method.md §6.4).

mod bicgstab;
mod block;
mod precond;
mod scaled;

pub use bicgstab::bicgstab;
pub use block::bicgstab3;
pub use precond::Jacobi;
pub use scaled::ScaledRows;

use serde::{Deserialize, Serialize};
use sprs::CsMat;

/// Settings of the iterative solver.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default)]
pub struct SolverSettings {
    /// Relative residual ‖b − Ax‖/‖b‖ to reach. Default 1e-10 (the reference asks for machine
    /// epsilon and aborts when it is missed; 1e-10 is far below the discretisation error).
    pub tolerance: f64,
    /// Iteration cap per right-hand side. Default 500.
    pub max_iterations: usize,
}

impl Default for SolverSettings {
    fn default() -> Self {
        Self {
            tolerance: 1e-10,
            max_iterations: 500,
        }
    }
}

/// What a successful solve did.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize)]
pub struct SolveReport {
    /// Iterations used (the maximum over right-hand sides for multi-solves).
    pub iterations: usize,
    /// Final true relative residual ‖b − Ax‖/‖b‖ (the maximum over right-hand sides).
    pub relative_residual: f64,
}

/// Why a solve failed. None of these panics; callers retry with a smaller step or give up.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum SolveError {
    /// Matrix and vectors disagree in size (a caller bug).
    #[error("dimension mismatch: matrix is {rows}×{cols}, vector has {len} entries")]
    Dimension {
        rows: usize,
        cols: usize,
        len: usize,
    },
    /// A zero (or non-finite) diagonal entry makes the Jacobi preconditioner undefined.
    #[error("row {row} has a zero or non-finite diagonal entry; the matrix is singular or broken")]
    BadDiagonal { row: usize },
    /// BiCGStab hit a zero inner product: the Krylov process cannot continue (singular system).
    #[error("BiCGStab broke down after {iterations} iterations (relative residual {residual:e}); the matrix is probably singular")]
    Breakdown { iterations: usize, residual: f64 },
    /// The tolerance was not reached within the cap.
    #[error("no convergence after {iterations} iterations: relative residual {residual:e} > tolerance {tolerance:e}")]
    NotConverged {
        iterations: usize,
        residual: f64,
        tolerance: f64,
    },
    /// A NaN or infinity appeared in the iteration (or in the input).
    #[error("non-finite value in the solve (input or iteration {iterations})")]
    NonFinite { iterations: usize },
}

/// Solves `A·X = B` for several right-hand sides sharing one matrix and preconditioner
/// (x, y and z coordinates in the flow). `x` holds initial guesses and receives the solutions.
pub fn solve_columns(
    a: &CsMat<f64>,
    b: &[Vec<f64>],
    x: &mut [Vec<f64>],
    settings: &SolverSettings,
) -> Result<SolveReport, SolveError> {
    let pre = Jacobi::new(a)?;
    let mut report = SolveReport::default();
    for (bk, xk) in b.iter().zip(x.iter_mut()) {
        let r = bicgstab(a, bk, xk, &pre, settings)?;
        report.iterations = report.iterations.max(r.iterations);
        report.relative_residual = report.relative_residual.max(r.relative_residual);
    }
    Ok(report)
}

/// Solves `A·X = B` where each row of `B` and `X` is a 3-vector (positions): the three columns
/// share every matrix product (see [`bicgstab3`]). `x` holds the initial guess.
pub fn solve_xyz(
    a: &CsMat<f64>,
    b: &[glam::DVec3],
    x: &mut [glam::DVec3],
    settings: &SolverSettings,
) -> Result<SolveReport, SolveError> {
    solve_xyz_scaled(&ScaledRows::from_csr(a)?, b, x, settings)
}

/// [`solve_xyz`] for a matrix already in the solver's row-scaled form (as the flow assembles it).
pub fn solve_xyz_scaled(
    a: &ScaledRows,
    b: &[glam::DVec3],
    x: &mut [glam::DVec3],
    settings: &SolverSettings,
) -> Result<SolveReport, SolveError> {
    // DVec3 is three f64 in a row: the solver works on the same memory, no copies.
    bicgstab3(
        a,
        bytemuck::cast_slice(b),
        bytemuck::cast_slice_mut(x),
        settings,
    )
}

/// `y = A·x` for a CSR matrix, without allocation.
pub(crate) fn spmv(a: &CsMat<f64>, x: &[f64], y: &mut [f64]) {
    let (indptr, indices, data) = (a.indptr(), a.indices(), a.data());
    let ip = indptr.raw_storage();
    for (row, yr) in y.iter_mut().enumerate() {
        let mut s = 0.0;
        for k in ip[row]..ip[row + 1] {
            s += data[k] * x[indices[k]];
        }
        *yr = s;
    }
}
