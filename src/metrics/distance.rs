//! Exact two-sided distances between a mesh and a target (point cloud or mesh), project
//! decision 7: every distance is an exact point–triangle (or point–point) distance found through a
//! BVH, never a grid sample.
//!
//! One side is sampled at the *vertices* (or points) of the source, its distances taken to the
//! other side's *surface* — triangles when it has them, points for a cloud:
//! * `mesh_to_target`: mesh vertices → target triangles (mesh target) or nearest target point
//!   (point-cloud target, the reference's "vertex → point" figure);
//! * `target_to_mesh`: every target point (all vertices of a mesh target, also those no face
//!   uses: for a scan they are data too) → mesh triangles.
//!
//! The Hausdorff distance is the larger of the two maxima.

use super::quality::percentile_sorted;
use crate::geometry::spatial::bvh::{PointBvh, TriangleBvh};
use crate::target::Surface;
use glam::DVec3;
use serde::{Deserialize, Serialize};

/// Statistics of one-sided distances.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct DistanceStats {
    /// Number of sampled points.
    pub count: usize,
    /// Mean distance.
    pub mean: f64,
    /// Root mean square distance.
    pub rms: f64,
    /// 95th percentile (nearest rank).
    pub p95: f64,
    /// Largest distance (the one-sided Hausdorff distance).
    pub max: f64,
}

impl DistanceStats {
    /// From a list of distances (sorted copy; fixed summation order).
    pub fn from_distances(d: &[f64]) -> Self {
        let n = d.len();
        if n == 0 {
            return Self::default();
        }
        let mut s = d.to_vec();
        s.sort_by(|a, b| a.total_cmp(b));
        Self {
            count: n,
            mean: d.iter().sum::<f64>() / n as f64,
            rms: (d.iter().map(|x| x * x).sum::<f64>() / n as f64).sqrt(),
            p95: percentile_sorted(&s, 0.95),
            max: s[n - 1],
        }
    }
    /// The same statistics in percent of `diagonal` (a bounding-box diagonal).
    pub fn percent_of(&self, diagonal: f64) -> Self {
        let k = 100.0 / diagonal;
        Self {
            count: self.count,
            mean: k * self.mean,
            rms: k * self.rms,
            p95: k * self.p95,
            max: k * self.max,
        }
    }
}

/// Two-sided distances between a mesh and a target.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct TwoSidedDistances {
    /// Mesh vertices → target surface (or nearest target point for a cloud).
    pub mesh_to_target: DistanceStats,
    /// Target points / vertices → mesh triangles.
    pub target_to_mesh: DistanceStats,
    /// max of both maxima.
    pub hausdorff: f64,
}

impl TwoSidedDistances {
    /// Everything in percent of `diagonal`.
    pub fn percent_of(&self, diagonal: f64) -> Self {
        Self {
            mesh_to_target: self.mesh_to_target.percent_of(diagonal),
            target_to_mesh: self.target_to_mesh.percent_of(diagonal),
            hausdorff: 100.0 * self.hausdorff / diagonal,
        }
    }
}

/// Exact distance from every point in `points` to the triangle set.
pub fn distances_to_triangles(points: &[DVec3], tris: &TriangleBvh) -> Vec<f64> {
    let hits = tris.closest_points_within(points.len(), |i| points[i], f64::INFINITY);
    hits.iter()
        .map(|h| h.map_or(f64::INFINITY, |h| h.distance_squared.sqrt()))
        .collect()
}

/// Distance from every point in `points` to its nearest point of a cloud.
pub fn distances_to_points(points: &[DVec3], cloud: &PointBvh) -> Vec<f64> {
    crate::parallel::map(points.len(), |i| cloud.distance(points[i]))
}

/// Two-sided distances between the mesh `(positions, triangles)` and a target given by its
/// points and (possibly empty) triangles.
pub fn two_sided_distances(
    positions: &[DVec3],
    triangles: &[[u32; 3]],
    target_points: &[DVec3],
    target_triangles: &[[u32; 3]],
) -> TwoSidedDistances {
    let target = Surface::of(target_points, target_triangles);
    let (there, back) = two_sided_distance_values(positions, triangles, target);
    let a = DistanceStats::from_distances(&there);
    let b = DistanceStats::from_distances(&back);
    TwoSidedDistances {
        mesh_to_target: a,
        target_to_mesh: b,
        hausdorff: a.max.max(b.max),
    }
}

/// The per-point distances behind [`two_sided_distances`]: (mesh vertex → target, one per mesh
/// vertex; target point → mesh, one per target point).
pub fn two_sided_distance_values(
    positions: &[DVec3],
    triangles: &[[u32; 3]],
    target: Surface<'_>,
) -> (Vec<f64>, Vec<f64>) {
    let mesh_bvh = TriangleBvh::new(positions, triangles);
    let (there, target_points) = match target {
        Surface::Points(points) => (
            distances_to_points(positions, &PointBvh::new(points)),
            points,
        ),
        Surface::Triangles { points, triangles } => (
            distances_to_triangles(positions, &TriangleBvh::new(points, triangles)),
            points,
        ),
    };
    let back = distances_to_triangles(target_points, &mesh_bvh);
    (there, back)
}
