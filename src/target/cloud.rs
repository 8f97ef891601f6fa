//! The oracle of a point cloud: samples of a surface, with gaps between them and no inside.

use super::oracle::{CreaseSource, Surface, TargetKind, TargetOracle};
use crate::geometry::spatial::spacing::{gap_spacing, median_spacing};
use crate::mesh::MeshReport;
use glam::DVec3;

/// A cloud's answers: distances to its points, its spacing from their nearest neighbours.
pub struct Cloud<'a> {
    pub points: &'a [DVec3],
}

impl<'a> TargetOracle<'a> for Cloud<'a> {
    fn kind(&self) -> TargetKind {
        TargetKind::Points
    }

    fn surface(&self) -> Surface<'a> {
        Surface::Points(self.points)
    }

    fn has_inside(&self) -> bool {
        false
    }

    fn spacing(&self) -> Option<f64> {
        Some(median_spacing(self.points))
    }

    fn gap_spacing(&self) -> Option<f64> {
        Some(gap_spacing(self.points))
    }

    fn creases(&self) -> Option<CreaseSource> {
        Some(CreaseSource::PlaneFits)
    }

    fn topology(&self) -> Option<MeshReport> {
        None
    }

    fn start_keeps_genus(&self) -> bool {
        false // (It has no closed topology to keep.)
    }

    fn splits_start_by_parts(&self) -> bool {
        true
    }

    fn removes_strays(&self) -> bool {
        true
    }

    fn removes_specks(&self) -> bool {
        false
    }

    fn second_pass_pays(&self) -> bool {
        true
    }

    fn refine_passes_help(&self) -> bool {
        true
    }
}
