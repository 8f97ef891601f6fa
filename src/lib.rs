//! LSW — Lagrangian Shrink-Wrapping.
//!
//! A simple closed surface (an icosphere, or a marching-cubes isosurface) evolves onto a target
//! (point cloud, triangle soup or voxel volume), driven by a distance field, smoothed by
//! mean-curvature flow and kept well-shaped by adaptive remeshing. The result is a watertight,
//! manifold triangle mesh.
//!
//! Data flows one way: `io` → [`target::Target`] → `field` → `flow` (with `remesh`) → `io`.
//! The core knows nothing of the browser; [`wasm`] is a thin facade over it. Every core error
//! explains itself to users through [`error::Explain`] (a code and a hint).

pub mod catalog;
pub mod clock;
pub mod demo;
pub mod error;
pub mod field;
pub mod flow;
pub mod fmath;
pub mod geometry;
pub mod io;
pub mod mesh;
pub mod metrics;
pub mod parallel;
pub mod pipeline;
pub mod progress;
pub mod remesh;
pub mod solve;
pub mod target;

#[cfg(not(target_arch = "wasm32"))]
pub mod cli;
#[cfg(target_arch = "wasm32")]
pub mod wasm;

pub use glam::DVec3;

/// The crate version, recorded in file metadata written by LSW.
pub const VERSION: &str = env!("CARGO_PKG_VERSION");
