//! Quality and accuracy metrics (docs/method.md §9 with the project's decisions 3 and 7).
//!
//! * [`quality`] — per-face κ(J_Δ) (equilateral = 1), the reference's κ variant, 2·r_in/r_circ,
//!   minimum angle, summaries, co-volume statistics.
//! * [`distance`] — exact two-sided mesh ↔ target distances (mean, RMS, p95, Hausdorff).
//! * [`intersections`] — count of intersecting non-adjacent face pairs.
//! * [`volume`] — enclosed volume.
//! * [`error_budget`] — where a wrap's remaining error comes from (features, sizing, not reached).
//! * [`creases`] — how well a mesh keeps a target's sharp creases (dihedral angles).
//! * [`histogram`] — fixed-bin histograms.
//!
//! The BVH they use lives in [`crate::geometry::spatial::bvh`].

pub mod certificate;
pub mod creases;
pub mod distance;
pub mod error_budget;
pub mod faithful;
pub mod histogram;
pub mod intersections;
pub mod quality;
pub mod volume;
