//! Trilinear interpolation of node values at any point [docs/method.md §2.8].
//!
//! Computed in local coordinates `t = (p − origin)/c` (the reference expands the polynomial in
//! world coordinates, which loses digits far from the origin). The point is first **clamped into
//! the grid's box**: outside it the value of the nearest box point is returned, never an
//! extrapolation (the reference extrapolates, and wraps negative coordinates to the last cell).

use super::grid::Grid;
use glam::DVec3;

/// Storage index of the lower corner of the cell holding `p` (clamped into the box) and the
/// local coordinates `f ∈ [0, 1]³` of `p` in that cell.
#[inline]
pub fn locate(grid: &Grid, p: DVec3) -> (usize, DVec3) {
    let t = (p - grid.origin) * (1.0 / grid.cell);
    let mut base = [0usize; 3];
    let mut f = [0f64; 3];
    for k in 0..3 {
        let n1 = (grid.dims[k] - 1) as f64;
        // NaN clamps to 0 via max/min on f64 (max(NaN, 0) = 0).
        let tk = t[k].max(0.0).min(n1);
        // tk ≥ 0, so truncation is floor (and, unlike `floor` on baseline x86-64, no libm call).
        let ik = (tk as usize).min(grid.dims[k] - 2);
        base[k] = ik;
        f[k] = tk - ik as f64;
    }
    (grid.index(base[0], base[1], base[2]), DVec3::from_array(f))
}

/// The eight trilinear weights of local coordinates `f`, corner `k` = bits (x, y, z) of `k`.
#[inline]
fn weights(f: DVec3) -> [f64; 8] {
    let (gx, gy, gz) = (1.0 - f.x, 1.0 - f.y, 1.0 - f.z);
    [
        gx * gy * gz,
        f.x * gy * gz,
        gx * f.y * gz,
        f.x * f.y * gz,
        gx * gy * f.z,
        f.x * gy * f.z,
        gx * f.y * f.z,
        f.x * f.y * f.z,
    ]
}

/// Storage offsets of the eight corners of a cell, in the order of [`weights`].
#[inline]
fn corner_offsets(grid: &Grid) -> [usize; 8] {
    let (sx, sy, sz) = (1, grid.dims[0], grid.dims[0] * grid.dims[1]);
    [0, sx, sy, sx + sy, sz, sx + sz, sy + sz, sx + sy + sz]
}

/// Trilinear interpolation of scalar node values at `p` (clamped into the box).
#[inline]
pub fn trilinear(grid: &Grid, values: &[f64], p: DVec3) -> f64 {
    let (i, f) = locate(grid, p);
    let w = weights(f);
    let o = corner_offsets(grid);
    (0..8).map(|k| w[k] * values[i + o[k]]).sum()
}

/// Per-component trilinear interpolation of vector node values at `p` (clamped into the box).
/// Not renormalised: for unit node vectors the norm is ≤ 1.
#[inline]
pub fn trilinear_vec(grid: &Grid, values: &[[f32; 3]], p: DVec3) -> DVec3 {
    let (i, f) = locate(grid, p);
    let w = weights(f);
    let o = corner_offsets(grid);
    let mut s = DVec3::ZERO;
    for k in 0..8 {
        let v = values[i + o[k]];
        s += w[k] * DVec3::new(v[0] as f64, v[1] as f64, v[2] as f64);
    }
    s
}

/// [`trilinear`] of `values` and [`trilinear_vec`] of `vectors` at the same point, locating the
/// cell once (the flow needs d and −∇d at every vertex every step).
#[inline]
pub fn trilinear_both(grid: &Grid, values: &[f64], vectors: &[[f32; 3]], p: DVec3) -> (f64, DVec3) {
    let (i, f) = locate(grid, p);
    let w = weights(f);
    let o = corner_offsets(grid);
    let (mut d, mut s) = (0.0, DVec3::ZERO);
    for k in 0..8 {
        let (j, wk) = (i + o[k], w[k]);
        d += wk * values[j];
        let v = vectors[j];
        s += wk * DVec3::new(v[0] as f64, v[1] as f64, v[2] as f64);
    }
    (d, s)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn both_at_once_equals_the_separate_lookups() {
        let grid = Grid {
            origin: DVec3::new(-1.0, 0.5, 2.0),
            cell: 0.25,
            dims: [5, 4, 6],
        };
        let values: Vec<f64> = (0..grid.node_count())
            .map(|i| crate::fmath::sin(i as f64 * 0.37))
            .collect();
        let vectors: Vec<[f32; 3]> = (0..grid.node_count())
            .map(|i| [crate::fmath::cosf(i as f32), 0.5, -(i as f32 * 0.1)])
            .collect();
        // Inside, on nodes, and outside the box (clamped).
        for k in 0..200 {
            let t = k as f64;
            let p = grid.origin
                + DVec3::new(
                    (t * 0.13).fract() * 1.4 - 0.2,
                    (t * 0.29).fract() * 1.0,
                    (t * 0.07).fract() * 1.6 - 0.1,
                );
            let (d, g) = trilinear_both(&grid, &values, &vectors, p);
            assert_eq!(d, trilinear(&grid, &values, p), "{p:?}");
            assert_eq!(g, trilinear_vec(&grid, &vectors, p), "{p:?}");
        }
    }
}
