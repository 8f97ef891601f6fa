//! The oracle of a triangle mesh or soup: a continuous surface whose faces bound an inside where
//! it is closed, and whose edges carry its creases.

use super::oracle::{CreaseSource, Surface, TargetKind, TargetOracle};
use crate::mesh::MeshReport;
use glam::DVec3;

/// A mesh's answers: distances to its triangles, its topology from its faces.
pub struct Soup<'a> {
    pub points: &'a [DVec3],
    pub triangles: &'a [[u32; 3]],
}

impl<'a> TargetOracle<'a> for Soup<'a> {
    fn kind(&self) -> TargetKind {
        TargetKind::Mesh
    }

    fn surface(&self) -> Surface<'a> {
        Surface::Triangles {
            points: self.points,
            triangles: self.triangles,
        }
    }

    fn has_inside(&self) -> bool {
        true
    }

    fn spacing(&self) -> Option<f64> {
        None
    }

    fn gap_spacing(&self) -> Option<f64> {
        None
    }

    fn creases(&self) -> Option<CreaseSource> {
        Some(CreaseSource::Dihedral)
    }

    fn topology(&self) -> Option<MeshReport> {
        crate::mesh::closed_topology(self.points.len(), self.triangles)
    }

    fn start_keeps_genus(&self) -> bool {
        true
    }

    fn splits_start_by_parts(&self) -> bool {
        false // (Its field is signed where it is closed, and the isosurface start keeps parts apart.)
    }

    fn removes_strays(&self) -> bool {
        false
    }

    fn removes_specks(&self) -> bool {
        true
    }

    fn second_pass_pays(&self) -> bool {
        true
    }

    fn refine_passes_help(&self) -> bool {
        true
    }
}
