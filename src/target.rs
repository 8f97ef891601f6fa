//! The thing to wrap: a point cloud or a triangle soup/mesh, as read from a file.

use crate::geometry::aabb::Aabb;
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
