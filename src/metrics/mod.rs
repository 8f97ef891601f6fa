//! Quality and accuracy metrics (method spec §9 with the project's decisions 3 and 7).
//!
//! * [`bvh`] — bounding-volume hierarchy and exact closest points on triangles / points.

pub mod bvh;
