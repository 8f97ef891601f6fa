//! The oracle of a voxel volume's iso-surface: a closed mesh to every distance, but its angles
//! and its genus are the sampling's, and its misses lie in folds narrower than a voxel.

use super::oracle::{CreaseSource, Surface, TargetKind, TargetOracle};
use super::soup::Soup;
use crate::mesh::MeshReport;

/// An iso-surface's answers: a mesh's, but for what its voxel sampling makes of them.
pub struct IsoSurface<'a> {
    pub mesh: Soup<'a>,
}

impl<'a> TargetOracle<'a> for IsoSurface<'a> {
    fn kind(&self) -> TargetKind {
        self.mesh.kind()
    }

    fn surface(&self) -> Surface<'a> {
        self.mesh.surface()
    }

    fn has_inside(&self) -> bool {
        self.mesh.has_inside()
    }

    fn spacing(&self) -> Option<f64> {
        self.mesh.spacing()
    }

    fn gap_spacing(&self) -> Option<f64> {
        self.mesh.gap_spacing()
    }

    fn creases(&self) -> Option<CreaseSource> {
        None // (The crease fit would spend its time on the voxel staircase.)
    }

    fn topology(&self) -> Option<MeshReport> {
        self.mesh.topology()
    }

    fn start_keeps_genus(&self) -> bool {
        false // (Its genus is the noise's; the icosphere costs time for no better genus.)
    }

    fn splits_start_by_parts(&self) -> bool {
        self.mesh.splits_start_by_parts()
    }

    fn removes_strays(&self) -> bool {
        self.mesh.removes_strays()
    }

    fn removes_specks(&self) -> bool {
        self.mesh.removes_specks()
    }

    fn second_pass_pays(&self) -> bool {
        false // (A large volume's second pass would double a long run.)
    }

    fn refine_passes_help(&self) -> bool {
        false
    }
}
