//! What the pipeline asks of a target's kind, answered in one place: [`TargetOracle`], with one
//! implementation per kind (a point cloud, a triangle mesh or soup, a volume's iso-surface). The
//! answers are plain data (slices, numbers, enums) that the stages above act on, so the target
//! knows nothing of fields, flows or metrics.

use crate::mesh::MeshReport;
use glam::DVec3;
use serde::{Deserialize, Serialize};

/// Whether a target is a bare point cloud or carries triangles (as reported to the user).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
#[cfg_attr(target_arch = "wasm32", derive(tsify::Tsify))]
pub enum TargetKind {
    /// Points only (no connectivity, no normals needed).
    Points,
    /// A triangle soup or mesh (faces index into `points`).
    Mesh,
}

/// What the target's surface is given as: what every distance to it is measured to.
#[derive(Clone, Copy, Debug)]
pub enum Surface<'a> {
    /// Samples of the surface with gaps between them: distances go to the nearest point, and the
    /// fit moves onto planes fitted to the points near.
    Points(&'a [DVec3]),
    /// Triangles indexing `points`: distances go to the closest point on them.
    Triangles {
        points: &'a [DVec3],
        triangles: &'a [[u32; 3]],
    },
}

impl<'a> Surface<'a> {
    /// The surface of bare `points` and `triangles` indexing them: points where there are none.
    pub fn of(points: &'a [DVec3], triangles: &'a [[u32; 3]]) -> Self {
        match triangles.is_empty() {
            true => Surface::Points(points),
            false => Surface::Triangles { points, triangles },
        }
    }
}

/// Where a target's sharp creases are found.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum CreaseSource {
    /// At the triangles' edges whose dihedral angle exceeds the crease angle.
    Dihedral,
    /// Where planes fitted to the points near meet at more than the crease angle.
    PlaneFits,
}

/// The questions the stages ask of a target's kind. Get one with [`super::Target::oracle`].
pub trait TargetOracle<'a> {
    /// Points or mesh: the kind as reported (a volume's iso-surface is a mesh to the user).
    fn kind(&self) -> TargetKind;

    /// What distances are measured to: the field's seeds, the fit's closest points, the
    /// certificate's and the metrics' distances all differ between samples and triangles.
    fn surface(&self) -> Surface<'a>;

    /// Whether the target tells inside from outside (its field is signed where it is closed);
    /// without, the field's enclosed solids are found by flooding from the border instead.
    fn has_inside(&self) -> bool;

    /// The sampling's median point spacing: finer than it the data resolve nothing (the grid's
    /// floor, the isosurface start's offset, surgery's empty space). None for a continuous surface.
    fn spacing(&self) -> Option<f64>;

    /// The widest usual gap between samples, which a second pass's offset grows to cover; None
    /// where the surface has no gaps.
    fn gap_spacing(&self) -> Option<f64>;

    /// Where the sharp creases are found; None where the target's angles are its sampling's,
    /// not the object's (a voxel staircase turns at countless edges).
    fn creases(&self) -> Option<CreaseSource>;

    /// The target's closed topology (genus, components), which a wrap should keep; None where it
    /// is not a closed manifold.
    fn topology(&self) -> Option<MeshReport>;

    /// Whether the start must have a closed target's genus, falling back to an icosphere when it
    /// has not: false where the genus is the sampling noise's and the fallback buys nothing.
    fn start_keeps_genus(&self) -> bool;

    /// Whether the icosphere start is one sphere per part lying apart: a cloud's parts show only
    /// as groups of points, and a single sphere leaves necks between them that must pinch.
    fn splits_start_by_parts(&self) -> bool;

    /// Whether lone points far from the rest are strays to leave out: a cloud's; a mesh's
    /// vertices are held by its faces.
    fn removes_strays(&self) -> bool;

    /// Whether small closed parts floating apart are specks to leave out: only faces make parts.
    fn removes_specks(&self) -> bool;

    /// Whether a second pass is worth its cost: not where the first is long and its misses are
    /// the sampling's.
    fn second_pass_pays(&self) -> bool;

    /// Whether the fit's error-adaptive passes reach what the wrap misses: not where the misses
    /// lie in folds narrower than a cell.
    fn refine_passes_help(&self) -> bool;
}
