//! The thing to wrap: a point cloud or a triangle soup/mesh, as read from a file.

use crate::geometry::aabb::Aabb;
use crate::io::volume::{Inside, VoxelVolume};
use glam::DVec3;
use serde::{Deserialize, Serialize};

/// Whether a target is a bare point cloud or carries triangles.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum TargetKind {
    /// Points only (no connectivity, no normals needed).
    Points,
    /// A triangle soup or mesh (faces index into `points`).
    Mesh,
}

/// A target for wrapping: points plus optional triangles indexing them.
///
/// Invariants (checked by [`Target::new`]): every coordinate is finite and every triangle index is
/// in range.
#[derive(Clone, Debug, PartialEq)]
pub struct Target {
    /// Vertex positions (for a point cloud: the points).
    pub points: Vec<DVec3>,
    /// Triangles as vertex-index triples; empty for a point cloud.
    pub triangles: Vec<[u32; 3]>,
    /// Axis-aligned bounding box of `points`.
    pub bbox: Aabb,
}

/// Why a [`Target`] could not be built.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum TargetError {
    /// The input has no points at all. Fix: give a file with at least one vertex.
    #[error("the target is empty: it has no points")]
    Empty,
    /// A coordinate is NaN or infinite. Fix: clean the input; the index names the first bad point.
    #[error("point {index} has a non-finite coordinate ({x}, {y}, {z})")]
    NonFinite {
        index: usize,
        x: f64,
        y: f64,
        z: f64,
    },
    /// A triangle refers to a vertex that does not exist.
    #[error("triangle {triangle} refers to vertex {vertex}, but there are only {count} vertices")]
    IndexOutOfRange {
        triangle: usize,
        vertex: u32,
        count: usize,
    },
    /// A volume's level set {v = iso} is empty: the iso-value lies outside the values (or the
    /// volume has fewer than two distinct values, so no default iso-value exists). Fix: choose
    /// an iso-value strictly between the minimum and the maximum.
    #[error("the iso-surface at {iso} is empty: the volume's values span [{min}, {max}]")]
    NoIsosurface { iso: f64, min: f64, max: f64 },
}

impl Target {
    /// Builds a target, checking that coordinates are finite and indices in range.
    pub fn new(points: Vec<DVec3>, triangles: Vec<[u32; 3]>) -> Result<Self, TargetError> {
        if points.is_empty() {
            return Err(TargetError::Empty);
        }
        if let Some((index, p)) = points.iter().enumerate().find(|(_, p)| !p.is_finite()) {
            return Err(TargetError::NonFinite {
                index,
                x: p.x,
                y: p.y,
                z: p.z,
            });
        }
        let count = points.len();
        for (t, tri) in triangles.iter().enumerate() {
            if let Some(&v) = tri.iter().find(|&&v| v as usize >= count) {
                return Err(TargetError::IndexOutOfRange {
                    triangle: t,
                    vertex: v,
                    count,
                });
            }
        }
        let bbox = Aabb::from_points(&points);
        Ok(Self {
            points,
            triangles,
            bbox,
        })
    }

    /// The target of a voxel volume: the closed surface S = {v = iso} (see
    /// [`VoxelVolume::isosurface`]) in world millimetres, as a triangle mesh. The whole pipeline
    /// (signed distance field, start surface, flow, metrics) then works on volumes unchanged; the
    /// triangles are exact to the piecewise-linear interpolant, so the field near S is exact too.
    pub fn from_volume(
        volume: &VoxelVolume,
        iso: f64,
        inside: Inside,
    ) -> Result<Self, TargetError> {
        let (points, triangles) = volume.isosurface(iso, inside);
        if triangles.is_empty() {
            let (min, max) = volume.value_range().unwrap_or((f64::NAN, f64::NAN));
            return Err(TargetError::NoIsosurface { iso, min, max });
        }
        Self::new(points, triangles)
    }

    /// Points or mesh.
    pub fn kind(&self) -> TargetKind {
        if self.triangles.is_empty() {
            TargetKind::Points
        } else {
            TargetKind::Mesh
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rejects_empty_nan_and_bad_index() {
        assert_eq!(Target::new(vec![], vec![]), Err(TargetError::Empty));
        let nan = vec![DVec3::ZERO, DVec3::new(0.0, f64::NAN, 0.0)];
        assert!(matches!(
            Target::new(nan, vec![]),
            Err(TargetError::NonFinite { index: 1, .. })
        ));
        let pts = vec![DVec3::ZERO, DVec3::X, DVec3::Y];
        assert!(matches!(
            Target::new(pts.clone(), vec![[0, 1, 3]]),
            Err(TargetError::IndexOutOfRange {
                triangle: 0,
                vertex: 3,
                count: 3
            })
        ));
        let t = Target::new(pts, vec![[0, 1, 2]]).unwrap();
        assert_eq!(t.kind(), TargetKind::Mesh);
        assert_eq!(t.bbox.max, DVec3::new(1.0, 1.0, 0.0));
    }
}
