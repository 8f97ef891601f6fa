//! The voxel lattice of a distance field: where its nodes are and how they are numbered.
//!
//! Values live at **nodes** `origin + (ix, iy, iz)·c` for `0 ≤ ix < nx` etc.; there is no
//! half-cell shift (a node's value is the distance at that very node). Storage index:
//! `i = ix + nx·(iy + ny·iz)` (x fastest, then y, then z), as in the reference and in VTK
//! structured points.
//!
//! Layout [docs/method.md §2.1–2.2]: `c = β_min / N` with `β_min` the smallest side of the target's
//! bounding box (of its principal box when that is much tighter: [`reference_length_of`]) and `N`
//! the cells per minimum dimension; the box is expanded by `ζ·β_min` on every side; the node count
//! per axis is the number of cells plus one, so the last node plane lies on or just beyond the
//! expanded box (the reference reports cell counts: here each axis has one node more). The lattice
//! starts at the expanded box's corner (not at the world origin; nothing depends on that).

use super::{FieldError, FieldSettings};
use crate::geometry::aabb::Aabb;
use crate::geometry::principal_box::principal_sides;
use glam::DVec3;
use serde::{Deserialize, Serialize};

/// Bytes held per node by a finished field: f64 value, 3×f32 gradient, 1 byte band flag.
pub const BYTES_PER_NODE: u64 = 8 + 12 + 1;

/// Sides shorter than this fraction of the longest side count as flat (zero thickness).
pub const FLAT_RELATIVE: f64 = 1e-6;

/// A regular lattice of nodes: origin, cell size and node counts.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Grid {
    /// Position of node (0, 0, 0).
    pub origin: DVec3,
    /// Cell size c (distance between neighbouring nodes), > 0.
    pub cell: f64,
    /// Node counts (nx, ny, nz), each ≥ 2.
    pub dims: [usize; 3],
}

impl Grid {
    /// The lattice for a target with bounding box `bbox` under `settings` (see the module docs).
    ///
    /// The reference length is `β_min`, the smallest side; sides flatter than
    /// [`FLAT_RELATIVE`] × the longest side are skipped (a planar target uses its smaller in-plane
    /// side). Fails when all points coincide or when the grid would exceed the memory cap.
    pub fn for_bbox(bbox: &Aabb, settings: &FieldSettings) -> Result<Self, FieldError> {
        Self::for_box(bbox, reference_length(bbox), settings)
    }

    /// [`Grid::for_bbox`] with the reference length `beta` given (see [`reference_length_of`]).
    pub fn for_box(bbox: &Aabb, beta: f64, settings: &FieldSettings) -> Result<Self, FieldError> {
        settings.check()?;
        let size = bbox.size();
        let longest = size.max_element();
        if longest <= 0.0 || !longest.is_finite() || !(beta > 0.0 && beta.is_finite()) {
            return Err(FieldError::DegenerateTarget);
        }
        let cell = beta / settings.cells_per_min_dimension as f64;
        let margin = settings.margin(beta);
        let grid = Self::covering(bbox.expanded(margin), cell);
        let bytes = grid.node_count_u64().saturating_mul(BYTES_PER_NODE);
        if bytes > settings.memory_cap_bytes {
            let fit = cells_that_fit(bbox, beta, settings);
            return Err(FieldError::TooLarge {
                dims: grid.dims,
                bytes,
                cap_bytes: settings.memory_cap_bytes,
                cells_that_fit: fit,
            });
        }
        Ok(grid)
    }

    /// The smallest lattice with cell size `cell` starting at `b.min` whose nodes reach `b.max`.
    pub fn covering(b: Aabb, cell: f64) -> Self {
        // Capped so that absurd requests stay representable (they fail the memory cap later).
        let n = |ext: f64| ((ext / cell - 1e-9).ceil().clamp(1.0, 1e9) as usize) + 1;
        let s = b.size();
        Self {
            origin: b.min,
            cell,
            dims: [n(s.x), n(s.y), n(s.z)],
        }
    }

    /// Total number of nodes nx·ny·nz, in u64 (on wasm32 an over-large grid's count overflows
    /// usize); saturates.
    pub fn node_count_u64(&self) -> u64 {
        self.dims
            .iter()
            .fold(1u64, |a, &n| a.saturating_mul(n as u64))
    }

    /// Total number of nodes nx·ny·nz (only for grids that passed the memory cap).
    pub fn node_count(&self) -> usize {
        self.dims[0] * self.dims[1] * self.dims[2]
    }

    /// Storage index of node (ix, iy, iz).
    #[inline]
    pub fn index(&self, ix: usize, iy: usize, iz: usize) -> usize {
        ix + self.dims[0] * (iy + self.dims[1] * iz)
    }

    /// Node coordinates (ix, iy, iz) of storage index `i`.
    #[inline]
    pub fn coords(&self, i: usize) -> [usize; 3] {
        let [nx, ny, _] = self.dims;
        [i % nx, (i / nx) % ny, i / (nx * ny)]
    }

    /// Storage indices of the (up to six) axis neighbours of node `i`: −x, +x, −y, +y, −z, +z.
    #[inline]
    pub fn axis_neighbours(&self, i: usize) -> [Option<usize>; 6] {
        let [nx, ny, nz] = self.dims;
        let [x, y, z] = self.coords(i);
        [
            (x > 0).then(|| i - 1),
            (x + 1 < nx).then_some(i + 1),
            (y > 0).then(|| i - nx),
            (y + 1 < ny).then_some(i + nx),
            (z > 0).then(|| i - nx * ny),
            (z + 1 < nz).then_some(i + nx * ny),
        ]
    }

    /// World position of node (ix, iy, iz).
    #[inline]
    pub fn node_position(&self, ix: usize, iy: usize, iz: usize) -> DVec3 {
        self.origin + self.cell * DVec3::new(ix as f64, iy as f64, iz as f64)
    }

    /// World position of the node with storage index `i`.
    #[inline]
    pub fn position_of(&self, i: usize) -> DVec3 {
        let [x, y, z] = self.coords(i);
        self.node_position(x, y, z)
    }

    /// The box spanned by the nodes: `origin .. origin + (dims − 1)·c`.
    pub fn bbox(&self) -> Aabb {
        let n = DVec3::new(
            (self.dims[0] - 1) as f64,
            (self.dims[1] - 1) as f64,
            (self.dims[2] - 1) as f64,
        );
        Aabb {
            min: self.origin,
            max: self.origin + self.cell * n,
        }
    }
}

/// β_min: the smallest non-flat side of `bbox` (see [`Grid::for_bbox`]), but at least
/// [`MIN_REFERENCE_RATIO`] × the longest side, so a thin target (a plate, a sheet) gets a grid
/// sized by its extent rather than a refusal for memory: its thin side is then padded by the
/// grid's margin like any other.
pub fn reference_length(bbox: &Aabb) -> f64 {
    reference_length_of_sides(bbox.size())
}

/// The reference length of a target with these `points`: [`reference_length`] of their
/// axis-aligned box as the method has it, unless the points are turned away from the axes: then
/// `slack` (`tuning.field.principal_slack`, default [`TURNED_SLACK`]; 0: never) × that of their
/// principal box (see [`principal_sides`]), so a plate or a flat chain of tori gets about the
/// same grid whichever way it lies.
pub fn reference_length_of(points: &[DVec3], slack: f64) -> f64 {
    let aligned = reference_length(&Aabb::from_points(points));
    if slack <= 0.0 {
        return aligned;
    }
    principal_sides(points).map_or(aligned, |s| {
        aligned.min(slack * reference_length_of_sides(s))
    })
}

/// A target about aligned with the axes keeps the method's grid bit for bit: its principal box
/// must be this much tighter than the axis-aligned one to count (its reference length below
/// 1/1.25 of the aligned one), which scans lying about straight are not. A target lying turned
/// gets a grid at most this much coarser than lying flat.
pub const TURNED_SLACK: f64 = 1.25;

fn reference_length_of_sides(s: DVec3) -> f64 {
    let longest = s.max_element();
    [s.x, s.y, s.z]
        .into_iter()
        .filter(|&e| e > FLAT_RELATIVE * longest)
        .fold(f64::INFINITY, f64::min)
        .max(MIN_REFERENCE_RATIO * longest)
}

/// The smallest β_min relative to the longest side: at most 40 / 0.16 = 250 cells along the
/// longest side at the default N. Real scans are above it; flat targets are not, and a finer
/// grid costs them time and vertices without a measurable gain in detail (see
/// docs/decisions/).
pub const MIN_REFERENCE_RATIO: f64 = 0.16;

/// The largest cells-per-minimum-dimension whose grid fits under the memory cap (at least 1).
fn cells_that_fit(bbox: &Aabb, beta: f64, settings: &FieldSettings) -> u32 {
    let nodes_for = |n: u32| {
        let at_n = FieldSettings {
            cells_per_min_dimension: n,
            ..settings.clone()
        };
        Grid::covering(bbox.expanded(at_n.margin(beta)), beta / n as f64).node_count_u64()
    };
    let (mut lo, mut hi) = (1u32, settings.cells_per_min_dimension);
    // Invariant: answer in [lo, hi); nodes_for is monotone in n.
    while hi - lo > 1 {
        let mid = lo + (hi - lo) / 2;
        if nodes_for(mid).saturating_mul(BYTES_PER_NODE) <= settings.memory_cap_bytes {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    lo
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A flat slab's points turned about two axes: the reference length stays within
    /// [`TURNED_SLACK`] of the slab lying flat (the axis-aligned box alone would be several times
    /// longer); lying flat it is the method's.
    #[test]
    fn a_turned_slab_keeps_about_its_reference_length() {
        let flat: Vec<DVec3> = (0..4000)
            .map(|k| {
                let (u, v) = ((k % 50) as f64 / 49.0, (k / 50 % 40) as f64 / 39.0);
                DVec3::new(u, 0.6 * v, if k < 2000 { 0.0 } else { 0.05 })
            })
            .collect();
        let aligned = reference_length(&Aabb::from_points(&flat));
        assert_eq!(reference_length_of(&flat, TURNED_SLACK), aligned);
        let turn = glam::DQuat::from_euler(glam::EulerRot::XYZ, 0.9, -0.6, 0.3);
        let turned: Vec<DVec3> = flat.iter().map(|&p| turn * p).collect();
        let by_axes = reference_length(&Aabb::from_points(&turned));
        assert!(by_axes > 4.0 * aligned, "{by_axes} vs {aligned}");
        assert_eq!(reference_length_of(&turned, 0.0), by_axes);
        let got = reference_length_of(&turned, TURNED_SLACK);
        assert!(
            got >= aligned * (1.0 - 1e-9) && got <= TURNED_SLACK * aligned * (1.0 + 1e-9),
            "{got} vs {aligned}"
        );
    }

    /// The box grows by ζ·β_min, or where `margin_cells` is given by that trimmed in steps of
    /// 3 cells down to no less (40 − 11·3 = 7 cells for 5); the cap's largest grid is found
    /// with the same margin.
    #[test]
    fn the_margin_is_beta_or_the_cells_given() {
        let b = Aabb {
            min: DVec3::ZERO,
            max: DVec3::new(4.0, 1.0, 2.0),
        };
        let wide = Grid::for_box(&b, 1.0, &FieldSettings::default()).unwrap();
        assert_eq!(wide.dims, [241, 121, 161]);
        let tight = FieldSettings {
            margin_cells: Some(5.0),
            ..FieldSettings::default()
        };
        let grid = Grid::for_box(&b, 1.0, &tight).unwrap();
        assert_eq!(grid.dims, [175, 55, 95]);
        assert!((grid.origin - DVec3::splat(-7.0 / 40.0)).length() < 1e-12);
        // The trimmed lattice's nodes are the wide one's.
        let shift = (grid.origin - wide.origin) / wide.cell;
        assert!((shift - shift.round()).length() < 1e-9 && shift.x == shift.y);
        let capped = FieldSettings {
            memory_cap_bytes: 100_000 * BYTES_PER_NODE,
            ..tight
        };
        let fit = cells_that_fit(&b, 1.0, &capped);
        let at = |n: u32| {
            let s = FieldSettings {
                cells_per_min_dimension: n,
                ..capped.clone()
            };
            Grid::for_box(&b, 1.0, &s)
        };
        assert!(at(fit).is_ok() && at(fit + 1).is_err(), "{fit}");
    }

    #[test]
    fn layout_of_a_box() {
        let b = Aabb {
            min: DVec3::ZERO,
            max: DVec3::new(2.0, 1.0, 1.0),
        };
        let g = Grid::for_bbox(&b, &FieldSettings::default()).unwrap();
        assert_eq!(g.cell, 1.0 / 40.0);
        // 1 + 2·1 = 3 units = 120 cells along y, z; 4 units = 160 cells along x.
        assert_eq!(g.dims, [161, 121, 121]);
        assert_eq!(g.origin, DVec3::splat(-1.0));
        let i = g.index(3, 4, 5);
        assert_eq!(g.coords(i), [3, 4, 5]);
        assert!((g.bbox().max - DVec3::new(3.0, 2.0, 2.0)).length() < 1e-12);
    }
}
