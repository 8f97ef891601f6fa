//! A sparse matrix stored as `A = D·(I + M)`: its diagonal `D` and the off-diagonal part of
//! the row-scaled matrix `D⁻¹A`.
//!
//! This is the form the Jacobi-preconditioned solver iterates on (`D⁻¹A x = D⁻¹b`, unit
//! diagonal: no preconditioned vectors to write), so the flow assembles it directly instead of
//! building a CSR matrix that the solver would copy and scale every step. Off-diagonal entries
//! are stored with 32-bit column indices, in any order within a row: 12 bytes per entry per
//! product instead of 16, and the products are what the solve spends its time on.

use super::SolveError;
use sprs::{CsMat, TriMat};

type V3 = [f64; 3];

/// `A = D·(I + M)`, `D` diagonal, `M` zero on its diagonal.
#[derive(Clone, Debug, PartialEq)]
pub struct ScaledRows {
    diag: Vec<f64>,
    indptr: Vec<u32>,
    cols: Vec<u32>,
    vals: Vec<f64>,
}

impl ScaledRows {
    /// From the diagonal of `A` and the rows of `M = D⁻¹A − I` (`indptr` of length n + 1 into
    /// `cols`/`vals`). Checks the structure once, so products need no further checks: every
    /// diagonal entry finite and non-zero, every column in range and off the diagonal, every
    /// value finite.
    pub fn from_parts(
        diag: Vec<f64>,
        indptr: Vec<u32>,
        cols: Vec<u32>,
        vals: Vec<f64>,
    ) -> Result<Self, SolveError> {
        let n = diag.len();
        let bad_shape = SolveError::Dimension {
            rows: n,
            cols: n,
            len: cols.len(),
        };
        if indptr.len() != n + 1
            || indptr[0] != 0
            || cols.len() != vals.len()
            || indptr[n] as usize != cols.len()
        {
            return Err(bad_shape);
        }
        if let Some(row) = diag.iter().position(|d| *d == 0.0 || !d.is_finite()) {
            return Err(SolveError::BadDiagonal { row });
        }
        for row in 0..n {
            let (lo, hi) = (indptr[row] as usize, indptr[row + 1] as usize);
            if lo > hi
                || cols[lo..hi]
                    .iter()
                    .any(|&j| j as usize >= n || j as usize == row)
            {
                return Err(bad_shape);
            }
        }
        if !vals.iter().all(|v| v.is_finite()) {
            return Err(SolveError::NonFinite { iterations: 0 });
        }
        Ok(Self {
            diag,
            indptr,
            cols,
            vals,
        })
    }

    /// From a square CSR matrix (the Jacobi scaling of any matrix with a non-zero diagonal).
    pub fn from_csr(a: &CsMat<f64>) -> Result<Self, SolveError> {
        let n = a.rows();
        if !a.is_csr() || a.cols() != n || u32::try_from(a.nnz()).is_err() {
            return Err(SolveError::Dimension {
                rows: n,
                cols: a.cols(),
                len: n,
            });
        }
        let mut diag = vec![0.0; n];
        let (mut indptr, mut cols, mut vals) = (vec![0u32], vec![], vec![]);
        for (row, vec) in a.outer_iterator().enumerate() {
            for (j, &v) in vec.iter() {
                if j == row {
                    diag[row] += v;
                } else {
                    cols.push(j as u32);
                    vals.push(v);
                }
            }
            indptr.push(cols.len() as u32);
        }
        if let Some(row) = diag.iter().position(|d| *d == 0.0 || !d.is_finite()) {
            return Err(SolveError::BadDiagonal { row });
        }
        for row in 0..n {
            let inv = 1.0 / diag[row];
            for v in &mut vals[indptr[row] as usize..indptr[row + 1] as usize] {
                *v *= inv;
            }
        }
        Self::from_parts(diag, indptr, cols, vals)
    }

    /// Number of rows (and columns).
    pub fn n(&self) -> usize {
        self.diag.len()
    }

    /// The diagonal `D` of `A`.
    pub fn diag(&self) -> &[f64] {
        &self.diag
    }

    /// Stored off-diagonal entries.
    pub fn off_diagonal_count(&self) -> usize {
        self.vals.len()
    }

    /// `y = (I + M)·x`, calling `then(row, y_row)` as each row is done, so that dot products
    /// with `y` need no second pass over it.
    #[inline(always)]
    pub(crate) fn mul_unit_then(&self, x: &[V3], y: &mut [V3], mut then: impl FnMut(usize, &V3)) {
        // Rows run from one end offset to the next: one slice check per row.
        let mut start = 0usize;
        for (row, (yr, &end)) in y.iter_mut().zip(&self.indptr[1..]).enumerate() {
            let end = end as usize;
            let mut s = x[row];
            for (&v, &j) in self.vals[start..end].iter().zip(&self.cols[start..end]) {
                let xj = &x[j as usize];
                s[0] += v * xj[0];
                s[1] += v * xj[1];
                s[2] += v * xj[2];
            }
            start = end;
            *yr = s;
            then(row, yr);
        }
    }

    /// The matrix as CSR (columns sorted), for inspection and tests: `A_ij = D_i·M_ij`.
    pub fn to_csr(&self) -> CsMat<f64> {
        let n = self.n();
        let mut tri = TriMat::with_capacity((n, n), n + self.vals.len());
        for (row, &d) in self.diag.iter().enumerate() {
            tri.add_triplet(row, row, d);
            for k in self.indptr[row] as usize..self.indptr[row + 1] as usize {
                tri.add_triplet(row, self.cols[k] as usize, d * self.vals[k]);
            }
        }
        tri.to_csr()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn csr_round_trip_and_bad_input() {
        let mut tri = TriMat::new((3, 3));
        for (i, j, v) in [
            (0, 0, 4.0),
            (0, 2, -1.0),
            (1, 1, 2.0),
            (1, 0, 0.5),
            (2, 2, 8.0),
            (2, 1, -2.0),
        ] {
            tri.add_triplet(i, j, v);
        }
        let a: CsMat<f64> = tri.to_csr();
        let s = ScaledRows::from_csr(&a).unwrap();
        assert_eq!(s.diag(), &[4.0, 2.0, 8.0]);
        assert_eq!(s.off_diagonal_count(), 3);
        let back = s.to_csr();
        for (v, (i, j)) in a.iter() {
            assert!((back.get(i, j).unwrap() - v).abs() < 1e-15, "({i}, {j})");
        }
        // (I + M)·x with x = e_2: column 2 of D⁻¹A.
        let mut y = vec![[0.0; 3]; 3];
        s.mul_unit_then(&[[0.0; 3], [0.0; 3], [1.0, 0.0, 0.0]], &mut y, |_, _| {});
        assert_eq!([y[0][0], y[1][0], y[2][0]], [-0.25, 0.0, 1.0]);
        // A zero diagonal, a column out of range, a diagonal entry stored as off-diagonal.
        let mut z = TriMat::new((2, 2));
        z.add_triplet(0, 1, 1.0);
        z.add_triplet(1, 1, 1.0);
        assert_eq!(
            ScaledRows::from_csr(&z.to_csr()).unwrap_err(),
            SolveError::BadDiagonal { row: 0 }
        );
        assert!(ScaledRows::from_parts(vec![1.0, 1.0], vec![0, 1, 1], vec![2], vec![0.5]).is_err());
        assert!(ScaledRows::from_parts(vec![1.0, 1.0], vec![0, 1, 1], vec![0], vec![0.5]).is_err());
        assert!(
            ScaledRows::from_parts(vec![1.0, 1.0], vec![0, 1, 1], vec![1], vec![f64::NAN]).is_err()
        );
        assert!(ScaledRows::from_parts(vec![1.0, 1.0], vec![0, 1, 1], vec![1], vec![0.5]).is_ok());
    }
}
