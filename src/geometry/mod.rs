//! Geometric primitives and starting surfaces.

pub mod aabb;
pub mod icosphere;
pub mod sphere;
