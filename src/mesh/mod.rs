//! Halfedge triangle mesh: connectivity, per-vertex properties, one-ring iteration, validation,
//! and the topology edits (split, collapse, flip, garbage collection) of `edit.rs`.
//!
//! The halfedge structure (rather than an index list) is what the adaptive remesher needs:
//! split, collapse and flip are local pointer edits on it.

pub mod disjoint;
mod edit;
pub mod fingerprint;
mod halfedge;
pub mod repair;
mod soup;
pub mod stars;
mod validate;

pub use edit::GarbageMaps;
pub use halfedge::{HalfedgeMesh, MeshBuildError, INVALID};
pub use repair::Repairs;
pub use soup::{closed_topology, edge_counts, EdgeCounts};
pub use validate::{MeshReport, ValidationError};
