//! The normalised negative gradient `g = −∇d/|∇d|` at every node [method §2.7].
//!
//! Central differences `(d[i+1] − d[i−1])/(2c)` inside, one-sided differences on the border
//! planes (the reference leaves border nodes at zero; one-sided values keep the field pulling
//! there). Where `|∇d| < 1e-6` (a ridge or a plateau) `g = 0`.
//!
//! Stored as `[f32; 3]`: g is a unit vector whose trilinear interpolation error is O(c), far above
//! f32 rounding (6e-8), and f32 halves the memory of the largest array of the field.

use super::grid::Grid;

/// Computes `−∇d/|∇d|` per node (storage order of [`Grid`]).
pub fn normalized_negative_gradient(grid: &Grid, d: &[f64]) -> Vec<[f32; 3]> {
    let [nx, ny, nz] = grid.dims;
    assert_eq!(d.len(), nx * ny * nz);
    let sxy = nx * ny;
    let mut out = vec![[0f32; 3]; d.len()];
    // Difference quotient along one axis (in index units): central inside, one-sided at the
    // border; `k` is the node's coordinate on that axis, `n` the node count (≥ 2).
    let diff = |i: usize, n: usize, k: usize, stride: usize| -> f64 {
        let m = if k > 0 { i - stride } else { i };
        let p = if k + 1 < n { i + stride } else { i };
        let span = ((k + 1).min(n - 1) - k.saturating_sub(1)) as f64;
        (d[p] - d[m]) / span
    };
    let inv_c = 1.0 / grid.cell;
    for iz in 0..nz {
        for iy in 0..ny {
            let row = nx * (iy + ny * iz);
            for ix in 0..nx {
                let i = row + ix;
                let gx = if ix > 0 && ix + 1 < nx {
                    0.5 * (d[i + 1] - d[i - 1])
                } else {
                    diff(i, nx, ix, 1)
                };
                let gy = diff(i, ny, iy, nx);
                let gz = diff(i, nz, iz, sxy);
                let (gx, gy, gz) = (gx * inv_c, gy * inv_c, gz * inv_c);
                let len = (gx * gx + gy * gy + gz * gz).sqrt();
                if len >= 1e-6 && len.is_finite() {
                    let s = -1.0 / len;
                    out[i] = [(gx * s) as f32, (gy * s) as f32, (gz * s) as f32];
                }
            }
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::DVec3;

    #[test]
    fn linear_field_has_constant_gradient() {
        let g = Grid {
            origin: DVec3::ZERO,
            cell: 0.1,
            dims: [4, 5, 6],
        };
        let dir = DVec3::new(1.0, -2.0, 0.5).normalize();
        let d: Vec<f64> = (0..g.node_count())
            .map(|i| g.position_of(i).dot(dir))
            .collect();
        let gr = normalized_negative_gradient(&g, &d);
        for v in gr {
            let v = DVec3::new(v[0] as f64, v[1] as f64, v[2] as f64);
            assert!((v + dir).length() < 1e-6, "{v:?}");
        }
    }
}
