//! The start surface `auto` settles on, by its stated rule: the start the settings ask for; where
//! that is an isosurface that meets itself or (for a closed one-part mesh) lost the target's
//! topology, the same start with the isosurface preset's coarser edges if it keeps the topology,
//! else the icosphere; and for a closed one-part target whose start fell back (or a volume's
//! iso-surface whose start has another topology), the isosurface start on finer grids, the first
//! with the target's topology.

use super::EvolveError;
use crate::field::{DistanceField, FieldError};
use crate::flow::settings::{StartSurface, WrapSettings};
use crate::flow::start::{build_start, Start};
use crate::mesh::{HalfedgeMesh, MeshReport};
use crate::progress::Progress;
use crate::target::Target;

/// Grid refinements tried for an isosurface start that lost a closed mesh's topology (see
/// [`finer_start`]); one over the field's memory cap becomes the finest grid the cap allows,
/// where that is finer than the refinement before.
const FINER_GRIDS: [f64; 2] = [1.5, 2.0];

/// `auto`'s isosurface start `resolved` with the isosurface preset's λ_min instead of its own
/// finer one, unless the user chose λ_min (in `requested`) or the start is not the isosurface.
fn coarser_isosurface_start(
    requested: &WrapSettings,
    resolved: &WrapSettings,
) -> Option<WrapSettings> {
    let preset = WrapSettings::default().with_isosurface_start();
    let chosen =
        requested.remesh.min_edge_multiplier != WrapSettings::default().remesh.min_edge_multiplier;
    let coarser = preset.remesh.min_edge_multiplier > resolved.remesh.min_edge_multiplier;
    (resolved.start.surface == StartSurface::Isosurface && !chosen && coarser).then(|| {
        let mut s = resolved.clone();
        s.remesh.min_edge_multiplier = preset.remesh.min_edge_multiplier;
        s
    })
}

/// Whether `mesh` has the Euler characteristic and the component count of `target`'s triangles
/// (false when those do not form a manifold mesh). From connectivity alone: degenerate faces of
/// an iso-surface do not matter here. `closed`: the target's [`crate::mesh::closed_topology`],
/// computed once per wrap (it sorts all of the target's edges); a target that is not closed is
/// built as a half-edge mesh.
fn same_topology(mesh: &HalfedgeMesh, target: &Target, closed: Option<&MeshReport>) -> bool {
    let t = mesh.topology();
    let mine = (t.euler_characteristic, t.components);
    match closed {
        Some(t) => (t.euler_characteristic, t.components) == mine,
        None => {
            HalfedgeMesh::from_triangles(target.points.clone(), &target.triangles).is_ok_and(|t| {
                let t = t.topology();
                (t.euler_characteristic, t.components) == mine
            })
        }
    }
}

/// The start of `settings` (resolved), falling back as `auto` promises: its isosurface
/// start is tried again with the isosurface preset's coarser edges (a start can intersect
/// itself after the finer remesh and not after the coarser one, and it keeps the handles the
/// icosphere would lose: see docs/decisions/0002-start-ladder.md); where the exterior leaked
/// into gaps of the target (noisy volumes, sparse clouds) the icosphere, which cannot leak,
/// takes over; the same when the start of a mesh of one closed part has another topology than
/// the mesh.
/// `settings` becomes those of the start built.
pub(super) fn build_start_with_fallback(
    target: &Target,
    closed: Option<&MeshReport>,
    field: &DistanceField,
    requested: &WrapSettings,
    settings: &mut WrapSettings,
) -> Result<Start, EvolveError> {
    let auto = requested.start.surface == StartSurface::Auto;
    let built = build_start(target, field, settings);
    // A mesh of one closed part has a genus the wrap must keep, and a Lagrangian surface
    // keeps its start's: an offset that joins two parts lying close (where the grid is
    // coarse) starts with handles the target lacks. (Not a volume's iso-surface: its genus is
    // the noise's, and the icosphere there costs time for no better genus.)
    let wrong_topology = |start: &Start| {
        settings.start.surface == StartSurface::Isosurface
            && target.oracle().start_keeps_genus()
            && closed.is_some_and(|t| t.components == 1)
            && !same_topology(&start.mesh, target, closed)
    };
    match built {
        Ok(start) if auto && wrong_topology(&start) => {
            fall_back(target, closed, field, requested, settings)
        }
        Err(EvolveError::StartIntersects { .. }) if auto => {
            fall_back(target, closed, field, requested, settings)
        }
        other => other,
    }
}

/// `auto` on a closed one-part mesh (or a volume's one-part iso-surface) whose isosurface
/// start lost the target's topology or met itself (an offset of ~1 cell closes a bore under
/// ~4 cells wide, and the icosphere then wraps over it): the isosurface start on grids
/// [`FINER_GRIDS`] times finer, the first with the target's topology, with its field and
/// settings (a grid over the field's memory cap as [`FINER_GRIDS`] says). `None` when the start
/// taken is not that fallback, or no finer grid helps. (A noisy volume's iso-surface rarely
/// matches, so there the finer fields are mostly built in vain.)
///
/// A volume's iso-surface of one closed part whose isosurface `start` has another topology
/// tries the first of them too, and keeps `start` when it does not match (see
/// `build_start_with_fallback`: no icosphere for volumes): strands of voxels passing close can
/// be joined in the start, and the wrap keeps its start's topology to the end, where a finer
/// grid's start keeps them apart.
pub(super) fn finer_start(
    target: &Target,
    closed: Option<&MeshReport>,
    requested: &WrapSettings,
    resolved: &WrapSettings,
    start: &Start,
    progress: &mut Progress,
) -> Option<(DistanceField, Start, WrapSettings)> {
    let auto = requested.start.surface == StartSurface::Auto;
    let fell_back = resolved.start.surface == StartSurface::Icosphere;
    let volume_off = || {
        !target.oracle().start_keeps_genus()
            && resolved.start.surface == StartSurface::Isosurface
            && !same_topology(&start.mesh, target, closed)
    };
    let one_part = closed.is_some_and(|t| t.components == 1);
    if !(auto && one_part && (fell_back || volume_off())) {
        return None;
    }
    // (A volume's own start only 1.5× finer: past its voxels a finer grid rarely changes
    // the iso-surface's topology, so a second grid would mostly be built in vain.)
    let grids = match fell_back {
        true => &FINER_GRIDS[..],
        false => &FINER_GRIDS[..1],
    };
    let n = requested.field.cells_per_min_dimension as f64;
    let cells: Vec<u32> = grids.iter().map(|&k| (k * n).round() as u32).collect();
    (0..cells.len()).find_map(|i| {
        let mut s = requested.clone();
        s.field.cells_per_min_dimension = cells[i];
        let below = if i == 0 { n as u32 } else { cells[i - 1] };
        let options = |s: &WrapSettings| s.isosurface_field_options();
        let field = match DistanceField::new_with_progress(target, &options(&s), progress) {
            Err(FieldError::TooLarge { cells_that_fit, .. }) if cells_that_fit > below => {
                s.field.cells_per_min_dimension = cells_that_fit;
                DistanceField::new_with_progress(target, &options(&s), progress)
            }
            built => built,
        }
        .ok()?;
        let resolved = s.clone().resolved_for(field.is_signed());
        (resolved.start.surface == StartSurface::Isosurface).then_some(())?;
        let start = build_start(target, &field, &resolved).ok()?;
        same_topology(&start.mesh, target, closed).then_some((field, start, resolved))
    })
}

/// `auto`'s way on from an isosurface start it cannot use: the coarser isosurface start, if
/// it has the target's topology, else the icosphere.
fn fall_back(
    target: &Target,
    closed: Option<&MeshReport>,
    field: &DistanceField,
    requested: &WrapSettings,
    settings: &mut WrapSettings,
) -> Result<Start, EvolveError> {
    let coarser = coarser_isosurface_start(requested, settings);
    match coarser.map(|s| (build_start(target, field, &s), s)) {
        // Only with the target's own topology: a coarse start free of intersections can still
        // have other parts (the offsets of linked parts merge where they link).
        Some((Ok(start), s)) if same_topology(&start.mesh, target, closed) => {
            *settings = s;
            Ok(start)
        }
        _ => {
            *settings = requested.clone().resolved_for(false);
            build_start(target, field, settings)
        }
    }
}
