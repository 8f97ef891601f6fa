//! Adaptive remeshing (docs/method.md §7) and feature detection (§8, re-derived).
//!
//! * [`adaptive`] — one remesh call: split / collapse / flip / tangential smoothing / cap removal
//!   with a curvature-adaptive sizing field ([`adaptive::remesh`]).
//! * [`sizing`] — the sizing field and the start-size rules and schedule of §6.6 / §7.2.
//! * [`features`] — convex crease and corner detection (mean-curvature angle, dihedral angle).
//! * [`slivers`] — caps and needles left by moves after the last remesh, flipped or collapsed.
//! * [`trigger`] — when to remesh (worst vertex-averaged κ above a bound).
//!
//! Principal curvatures come from [`crate::geometry::operators::curvature`].

pub mod adaptive;
pub mod features;
pub mod sizing;
pub mod slivers;
pub mod trigger;

pub use adaptive::{
    remesh, remesh_with_features, RemeshError, RemeshReport, RemeshSettings, RemeshTimings,
    CURVED_SPLITS_LAYER, SPLIT_ALLOWANCE,
};
pub use features::{FeatureDetector, FeatureSettings, Features};
pub use sizing::EdgeSizes;
