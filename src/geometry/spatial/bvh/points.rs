//! The hierarchy over a point cloud: nearest-neighbour queries.

use super::Bvh;
use glam::DVec3;

/// A BVH over points, for nearest-neighbour distances to a point cloud.
#[derive(Clone, Debug, Default)]
pub struct PointBvh {
    bvh: Bvh,
    points: Vec<DVec3>,
}

impl PointBvh {
    /// Builds the hierarchy over `points`.
    pub fn new(points: &[DVec3]) -> Self {
        Self {
            bvh: Bvh::new(points, points),
            points: points.to_vec(),
        }
    }
    /// Index of and squared distance to the nearest point (`None` if there are no points).
    pub fn nearest(&self, p: DVec3) -> Option<(u32, f64)> {
        self.bvh
            .nearest(p, |i| (self.points[i as usize] - p).length_squared())
    }
    /// [`PointBvh::nearest`] among the points within squared distance `max_d2` of `p`.
    pub fn nearest_within(&self, p: DVec3, max_d2: f64) -> Option<(u32, f64)> {
        self.bvh.nearest_within(p, max_d2, |i| {
            (self.points[i as usize] - p).length_squared()
        })
    }
    /// Nearest point other than point `me` (index and squared distance).
    pub fn nearest_other(&self, p: DVec3, me: u32) -> Option<(u32, f64)> {
        self.bvh.nearest(p, |i| {
            if i == me {
                f64::INFINITY
            } else {
                (self.points[i as usize] - p).length_squared()
            }
        })
    }
    /// Distance to the nearest point (∞ if there are none).
    pub fn distance(&self, p: DVec3) -> f64 {
        self.nearest(p).map_or(f64::INFINITY, |(_, d)| d.sqrt())
    }
}
