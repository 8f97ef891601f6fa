//! The normalised negative gradient `g = −∇d/|∇d|` at every node [docs/method.md §2.7].
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
    let inv_c = 1.0 / grid.cell;
    // Per axis: (offset back, offset forward, 1/(c·span)) for coordinate k of n nodes — central
    // inside, one-sided on the border planes.
    let stencil = |k: usize, n: usize, stride: usize| -> (usize, usize, f64) {
        let back = if k > 0 { stride } else { 0 };
        let fwd = if k + 1 < n { stride } else { 0 };
        let span = ((k + 1).min(n - 1) - k.saturating_sub(1)) as f64;
        (back, fwd, inv_c / span)
    };
    let store = |o: &mut [f32; 3], gx: f64, gy: f64, gz: f64| {
        let len = (gx * gx + gy * gy + gz * gz).sqrt();
        if len >= 1e-6 && len.is_finite() {
            let s = -1.0 / len;
            *o = [(gx * s) as f32, (gy * s) as f32, (gz * s) as f32];
        }
    };
    let (xb0, xf0, xs0) = stencil(0, nx, 1);
    let (xbn, xfn, xsn) = stencil(nx - 1, nx, 1);
    let half_inv_c = 0.5 * inv_c;
    // One z-plane per chunk (in parallel natively): each node reads only `d`.
    let planes = |iz: usize, out: &mut [[f32; 3]]| {
        let (zb, zf, zs) = stencil(iz, nz, sxy);
        for iy in 0..ny {
            let (yb, yf, ys) = stencil(iy, ny, nx);
            let row = nx * (iy + ny * iz);
            let local = nx * iy;
            let g = |i: usize, xb: usize, xf: usize, xs: f64| {
                (
                    (d[i + xf] - d[i - xb]) * xs,
                    (d[i + yf] - d[i - yb]) * ys,
                    (d[i + zf] - d[i - zb]) * zs,
                )
            };
            let (gx, gy, gz) = g(row, xb0, xf0, xs0);
            store(&mut out[local], gx, gy, gz);
            for (i, o) in out[local + 1..local + nx - 1].iter_mut().enumerate() {
                let (gx, gy, gz) = g(row + 1 + i, 1, 1, half_inv_c);
                store(o, gx, gy, gz);
            }
            let last = row + nx - 1;
            let (gx, gy, gz) = g(last, xbn, xfn, xsn);
            store(&mut out[local + nx - 1], gx, gy, gz);
        }
    };
    crate::parallel::for_each_chunk_mut(&mut out, sxy, usize::MAX, planes, &mut |_| {});
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
