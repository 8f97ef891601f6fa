//! Smooth closed test shapes as implicit surfaces: a signed distance function's zero level set
//! extracted by [`marching_cubes`], and the smooth minimum that blends parts into one body. The
//! suite's shapes ([`super::shapes`]) and the sculpted ones ([`super::sculpted`]) both build on it.

use crate::geometry::marching_cubes::{marching_cubes, ScalarGridView};
use glam::DVec3;

/// Points plus triangles (empty for a point cloud).
pub type Shape = (Vec<DVec3>, Vec<[u32; 3]>);

/// The closed surface `{sdf = 0}` (inside where `sdf < 0`) over the box `[lo, hi]`, extracted by
/// [`marching_cubes`] on a grid of spacing `cell` from `lo` (`⌈(hi − lo)/cell⌉` cells per axis).
/// Closed, oriented and welded as long as the level set stays inside the box.
pub fn implicit_surface(sdf: impl Fn(DVec3) -> f64, lo: DVec3, hi: DVec3, cell: f64) -> Shape {
    let n = ((hi - lo) / cell).ceil();
    let dims = [n.x as usize + 1, n.y as usize + 1, n.z as usize + 1];
    let mut values = Vec::with_capacity(dims[0] * dims[1] * dims[2]);
    for iz in 0..dims[2] {
        for iy in 0..dims[1] {
            for ix in 0..dims[0] {
                values.push(sdf(lo + DVec3::new(ix as f64, iy as f64, iz as f64) * cell));
            }
        }
    }
    let view = ScalarGridView {
        first: [0; 3],
        origin: lo,
        cell,
        dims,
        values: &values,
    };
    marching_cubes(&view, 0.0)
}

/// Polynomial smooth minimum of `a` and `b` with blend width `k` (Quílez).
pub(crate) fn smooth_min(a: f64, b: f64, k: f64) -> f64 {
    let h = (k - (a - b).abs()).max(0.0) / k;
    a.min(b) - h * h * k * 0.25
}
