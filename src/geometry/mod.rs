//! Geometric primitives and starting surfaces.

pub mod aabb;
pub mod angle;
pub mod cloud_creases;
pub mod creases;
pub mod curved_midpoint;
pub mod eigen3;
pub mod icosphere;
pub mod marching_cubes;
pub mod operators;
pub mod predicates;
pub mod primitives;
pub mod principal_box;
pub mod spatial;
pub mod specks;
pub mod sphere;
