//! Preconditioners.

use super::SolveError;
use sprs::CsMat;

/// Jacobi (diagonal) preconditioner: cheap, and enough for diagonally dominant LSW systems.
#[derive(Clone, Debug)]
pub struct Jacobi {
    inv_diag: Vec<f64>,
}

impl Jacobi {
    /// Inverts the diagonal of a square CSR matrix; fails on a zero or non-finite entry.
    pub fn new(a: &CsMat<f64>) -> Result<Self, SolveError> {
        if !a.is_csr() || a.rows() != a.cols() {
            return Err(SolveError::Dimension {
                rows: a.rows(),
                cols: a.cols(),
                len: a.rows(),
            });
        }
        let mut inv_diag = vec![0.0; a.rows()];
        let (indptr, indices, data) = (a.indptr(), a.indices(), a.data());
        for (row, inv) in inv_diag.iter_mut().enumerate() {
            let range = indptr.outer_inds_sz(row);
            let d = indices[range.clone()]
                .iter()
                .position(|&j| j == row)
                .map_or(0.0, |k| data[range.start + k]);
            if d == 0.0 || !d.is_finite() {
                return Err(SolveError::BadDiagonal { row });
            }
            *inv = 1.0 / d;
        }
        Ok(Self { inv_diag })
    }

    /// The inverted diagonal.
    pub fn inv_diag(&self) -> &[f64] {
        &self.inv_diag
    }

    /// `z = M⁻¹·r`.
    pub fn apply(&self, r: &[f64], z: &mut [f64]) {
        for ((zi, ri), di) in z.iter_mut().zip(r).zip(&self.inv_diag) {
            *zi = ri * di;
        }
    }
}
