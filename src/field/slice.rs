//! Planes of grid nodes, for viewing a field as a slice (the browser app's "Field" view).
//!
//! A plane normal to axis `a` (0 = x, 1 = y, 2 = z) is spanned by the other two axes in
//! increasing order, `(u, v)`: x → (y, z), y → (x, z), z → (x, y). Its values are stored with
//! `u` fastest (`width` = nodes along u, `height` = nodes along v), so row 0 is the lowest v.
//!
//! [`FieldView`] shows a field that [`DistanceField::scaled`] moved into the flow's stabilised
//! frame back in the target's units: its planes and its isosurfaces.

use super::DistanceField;
use glam::DVec3;

/// The nodes of one grid plane and their values.
#[derive(Clone, Debug, PartialEq)]
pub struct NodePlane {
    /// The axis the plane is normal to (0 = x, 1 = y, 2 = z).
    pub axis: usize,
    /// Index of the plane's node layer along `axis`.
    pub index: usize,
    /// Nodes along the first in-plane axis u.
    pub width: usize,
    /// Nodes along the second in-plane axis v.
    pub height: usize,
    /// Corner node positions: (u₀, v₀), (u₁, v₀), (u₁, v₁), (u₀, v₁).
    pub corners: [DVec3; 4],
    /// Node values, `u` fastest: `values[iu + width·iv]`.
    pub values: Vec<f64>,
}

/// The in-plane axes (u, v) of a plane normal to `axis`.
pub fn plane_axes(axis: usize) -> Option<(usize, usize)> {
    match axis {
        0 => Some((1, 2)),
        1 => Some((0, 2)),
        2 => Some((0, 1)),
        _ => None,
    }
}

/// The plane of nodes normal to `axis` nearest to the fraction `t` ∈ [0, 1] of the grid along
/// that axis (`t` is clamped into [0, 1]). `None` for an axis other than 0, 1, 2 or a non-finite
/// `t`.
pub fn node_plane(field: &DistanceField, axis: usize, t: f64) -> Option<NodePlane> {
    let (ua, va) = plane_axes(axis)?;
    if !t.is_finite() {
        return None;
    }
    let g = field.grid();
    let dims = g.dims;
    let index = (t.clamp(0.0, 1.0) * (dims[axis] - 1) as f64).round() as usize;
    let (width, height) = (dims[ua], dims[va]);
    let node = |iu: usize, iv: usize| {
        let mut ijk = [0usize; 3];
        ijk[axis] = index;
        ijk[ua] = iu;
        ijk[va] = iv;
        ijk
    };
    let values = field.values();
    let mut out = Vec::with_capacity(width * height);
    for iv in 0..height {
        for iu in 0..width {
            let [x, y, z] = node(iu, iv);
            out.push(values[g.index(x, y, z)]);
        }
    }
    let pos = |iu: usize, iv: usize| {
        let [x, y, z] = node(iu, iv);
        g.node_position(x, y, z)
    };
    let corners = [
        pos(0, 0),
        pos(width - 1, 0),
        pos(width - 1, height - 1),
        pos(0, height - 1),
    ];
    Some(NodePlane {
        axis,
        index,
        width,
        height,
        corners,
        values: out,
    })
}

/// A field built in the frame `x' = φ·(x − center)` (see [`DistanceField::scaled`]), seen in
/// the original frame (the target's units): what the app's "Field" view draws.
#[derive(Clone, Copy, Debug)]
pub struct FieldView<'a> {
    field: &'a DistanceField,
    center: DVec3,
    phi: f64,
}

/// An isosurface of a [`FieldView`], in the original frame.
#[derive(Clone, Debug, PartialEq)]
pub struct ViewIsosurface {
    /// The level drawn (target units; see [`FieldView::isosurface`]).
    pub level: f64,
    /// Vertex positions (target units).
    pub positions: Vec<DVec3>,
    /// Counter-clockwise triangles.
    pub triangles: Vec<[u32; 3]>,
}

impl<'a> FieldView<'a> {
    /// The view of `field`, scaled by `phi` (> 0) about `center`.
    pub fn new(field: &'a DistanceField, center: DVec3, phi: f64) -> Self {
        FieldView { field, center, phi }
    }

    /// [`node_plane`] with corners and values in the original frame.
    pub fn plane(&self, axis: usize, t: f64) -> Option<NodePlane> {
        let mut p = node_plane(self.field, axis, t)?;
        for c in &mut p.corners {
            *c = *c / self.phi + self.center;
        }
        for v in &mut p.values {
            *v /= self.phi;
        }
        Some(p)
    }

    /// The isosurface d = `level` (target units), or `None` for a non-finite level. For an
    /// unsigned field the level is raised to at least half a cell: its zero set is the target
    /// itself, not a surface.
    pub fn isosurface(&self, level: f64) -> Option<ViewIsosurface> {
        let iso = iso_level(
            level * self.phi,
            self.field.cell_size(),
            self.field.is_signed(),
        )?;
        let (positions, triangles) = self.field.isosurface(iso);
        Some(ViewIsosurface {
            level: iso / self.phi,
            positions: positions
                .into_iter()
                .map(|p| p / self.phi + self.center)
                .collect(),
            triangles,
        })
    }
}

/// The level to draw for `scaled` (field frame): as given for a signed field, at least half a
/// cell for an unsigned one; `None` when not finite.
fn iso_level(scaled: f64, cell: f64, signed: bool) -> Option<f64> {
    if !scaled.is_finite() {
        return None;
    }
    Some(if signed {
        scaled
    } else {
        scaled.max(0.5 * cell)
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::field::FieldSettings;
    use crate::target::Target;

    fn sphere_field() -> DistanceField {
        // Fibonacci sphere of radius 1 about the origin.
        let n = 4000;
        let golden = std::f64::consts::PI * (3.0 - 5f64.sqrt());
        let pts: Vec<DVec3> = (0..n)
            .map(|i| {
                let y = 1.0 - 2.0 * (i as f64 + 0.5) / n as f64;
                let r = (1.0 - y * y).sqrt();
                let a = golden * i as f64;
                DVec3::new(r * crate::fmath::cos(a), y, r * crate::fmath::sin(a))
            })
            .collect();
        let settings = FieldSettings {
            cells_per_min_dimension: 16,
            ..Default::default()
        };
        DistanceField::new(&Target::new(pts, vec![]).unwrap(), &settings).unwrap()
    }

    #[test]
    fn middle_z_plane_of_a_sphere_field() {
        let f = sphere_field();
        let g = *f.grid();
        let p = node_plane(&f, 2, 0.5).unwrap();
        assert_eq!((p.width, p.height), (g.dims[0], g.dims[1]));
        assert_eq!(p.values.len(), p.width * p.height);
        assert_eq!(p.index, ((g.dims[2] - 1) as f64 * 0.5).round() as usize);
        // All corners on one z plane, near z = 0, spanning the grid in x and y.
        for c in p.corners {
            assert_eq!(c.z, p.corners[0].z);
        }
        assert!(p.corners[0].z.abs() <= g.cell);
        assert_eq!(p.corners[0], g.origin.with_z(p.corners[0].z));
        let span = p.corners[2] - p.corners[0];
        assert!((span.x - (g.dims[0] - 1) as f64 * g.cell).abs() < 1e-9);
        assert!((span.y - (g.dims[1] - 1) as f64 * g.cell).abs() < 1e-9);
        // Values are the sphere's distance at the node positions (bilinear in corners), negative
        // deep inside: the cloud encloses the ball (`tuning.field.enclosed_cells`).
        let mut worst = 0.0f64;
        let mut negative = 0;
        for iv in 0..p.height {
            for iu in 0..p.width {
                let x = p.corners[0]
                    + (p.corners[1] - p.corners[0]) * (iu as f64 / (p.width - 1) as f64)
                    + (p.corners[3] - p.corners[0]) * (iv as f64 / (p.height - 1) as f64);
                let exact = (x.length() - 1.0).abs();
                let v = p.values[iu + p.width * iv];
                worst = worst.max((v.abs() - exact).abs());
                if v < 0.0 {
                    negative += 1;
                    assert!(x.length() < 1.0 - g.cell, "{x}");
                }
            }
        }
        assert!(worst < 2.0 * g.cell, "worst error {worst}, cell {}", g.cell);
        assert!(negative > 0);
    }

    #[test]
    fn x_and_y_planes_and_ends() {
        let f = sphere_field();
        let g = *f.grid();
        let p = node_plane(&f, 0, 0.0).unwrap();
        assert_eq!((p.index, p.width, p.height), (0, g.dims[1], g.dims[2]));
        assert!(p.corners.iter().all(|c| c.x == g.origin.x));
        let p = node_plane(&f, 1, 1.0).unwrap();
        assert_eq!(
            (p.index, p.width, p.height),
            (g.dims[1] - 1, g.dims[0], g.dims[2])
        );
        let top = g.bbox().max.y;
        assert!(p.corners.iter().all(|c| (c.y - top).abs() < 1e-12));
        // The value at (iu, iv) is node (iu, index, iv).
        assert_eq!(
            p.values[3 + p.width * 5],
            f.values()[g.index(3, g.dims[1] - 1, 5)]
        );
        // Clamped t, bad axis, non-finite t.
        assert_eq!(node_plane(&f, 2, 7.0).unwrap().index, g.dims[2] - 1);
        assert_eq!(node_plane(&f, 2, -1.0).unwrap().index, 0);
        assert!(node_plane(&f, 3, 0.5).is_none());
        assert!(node_plane(&f, 0, f64::NAN).is_none());
    }
    #[test]
    fn iso_level_is_clamped_for_unsigned_fields() {
        // Scaled cell 0.1: half a cell is 0.05.
        assert_eq!(iso_level(0.0, 0.1, false), Some(0.05));
        assert_eq!(iso_level(0.6, 0.1, false), Some(0.6));
        assert_eq!(iso_level(-2.0, 0.1, false), Some(0.05));
        // Signed fields keep zero and negative levels.
        assert_eq!(iso_level(0.0, 0.1, true), Some(0.0));
        assert_eq!(iso_level(-0.5, 0.1, true), Some(-0.5));
        assert_eq!(iso_level(f64::NAN, 0.1, false), None);
    }

    /// A view of the scaled field shows what the unscaled field holds.
    #[test]
    fn view_of_a_scaled_field_is_in_the_original_frame() {
        let f = sphere_field();
        let (center, phi) = (DVec3::new(0.25, -0.5, 1.0), 2.5);
        let scaled = f.scaled(center, phi);
        let view = FieldView::new(&scaled, center, phi);
        let (a, b) = (view.plane(1, 0.4).unwrap(), node_plane(&f, 1, 0.4).unwrap());
        assert_eq!(
            (a.axis, a.index, a.width, a.height),
            (b.axis, b.index, b.width, b.height)
        );
        for (p, q) in a.corners.iter().zip(&b.corners) {
            assert!((*p - *q).length() < 1e-12, "{p} {q}");
        }
        for (p, q) in a.values.iter().zip(&b.values) {
            assert!((p - q).abs() < 1e-12);
        }
        assert!(view.plane(5, 0.4).is_none());
        // Unsigned: level 0 is drawn at half a cell, in target units.
        let iso = view.isosurface(0.0).unwrap();
        assert!((iso.level - 0.5 * f.cell_size()).abs() < 1e-12);
        let (pos, tris) = f.isosurface(iso.level);
        assert_eq!(iso.triangles, tris);
        for (p, q) in iso.positions.iter().zip(&pos) {
            assert!((*p - *q).length() < 1e-9);
        }
        assert!((view.isosurface(0.3).unwrap().level - 0.3).abs() < 1e-12);
        assert!(view.isosurface(f64::INFINITY).is_none());
    }
}
