//! Axis-aligned bounding boxes: every user-facing length in LSW is relative to one of these.

use glam::DVec3;
use serde::{Deserialize, Serialize};

/// An axis-aligned box `[min, max]`. An empty box has `min > max` componentwise.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Aabb {
    /// Lower corner.
    pub min: DVec3,
    /// Upper corner.
    pub max: DVec3,
}

impl Aabb {
    /// The empty box (neutral element of [`Aabb::grow`]).
    pub const EMPTY: Aabb = Aabb {
        min: DVec3::INFINITY,
        max: DVec3::NEG_INFINITY,
    };

    /// Smallest box holding all `points` (empty if there are none).
    pub fn from_points(points: &[DVec3]) -> Self {
        points.iter().fold(Self::EMPTY, |b, &p| b.grow(p))
    }

    /// This box enlarged to contain `p`.
    pub fn grow(self, p: DVec3) -> Self {
        Self {
            min: self.min.min(p),
            max: self.max.max(p),
        }
    }

    /// True when no point has been added.
    pub fn is_empty(&self) -> bool {
        self.min.cmpgt(self.max).any()
    }

    /// Side lengths.
    pub fn size(&self) -> DVec3 {
        self.max - self.min
    }

    /// Centre point.
    pub fn center(&self) -> DVec3 {
        0.5 * (self.min + self.max)
    }

    /// Length of the diagonal; distances are reported as a fraction of it.
    pub fn diagonal(&self) -> f64 {
        self.size().length()
    }

    /// The box grown by `margin` on every side.
    pub fn expanded(&self, margin: f64) -> Self {
        Self {
            min: self.min - DVec3::splat(margin),
            max: self.max + DVec3::splat(margin),
        }
    }
}
