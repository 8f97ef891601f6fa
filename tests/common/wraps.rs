//! Test helpers for whole wraps: a generated shape's target and the coarser settings the wrap
//! tests use (a coarser grid, 24 cells per minimum side instead of 40, and coarser final edges,
//! λ_min 0.3 instead of 0.14), with the same start surfaces and guards as the defaults.
#![allow(dead_code)]

use lsw::demo::shapes::generate;
use lsw::flow::WrapSettings;
use lsw::target::Target;

/// The target of a generated shape.
pub fn target(name: &str) -> Target {
    let (p, t) = generate(name).unwrap_or_else(|e| panic!("{name}: {e}"));
    Target::new(p, t).unwrap()
}

/// The defaults with a coarser grid and coarser final edges.
pub fn coarse() -> WrapSettings {
    let mut settings = WrapSettings::default();
    settings.remesh.min_edge_multiplier = 0.3;
    settings.field.cells_per_min_dimension = 24;
    settings
}
