//! Topology surgery (issue 14): a Lagrangian surface cannot change its genus by moving, so a
//! surface shrinking onto a handle would span the handle's hole with two membranes pressed
//! together. Surgery finds such membranes ([`detect`]) and replaces them by a tube ([`bridge`]):
//! the hole opens and the flow goes on to fit its walls.
//!
//! Only sheets that meet *far from the data* are cut. Scan holes are spanned by a single membrane
//! and the two sides of one scan layer meet at the data, so neither is ever cut.

pub mod bridge;
pub mod detect;

use crate::geometry::operators::normals::angle_weighted_normals;
use crate::mesh::HalfedgeMesh;
use crate::metrics::intersections::count_self_intersections;
use bridge::{glue_facing_regions, Tube};
use detect::{facing_pairs, FacingQuery};
use glam::DVec3;
use serde::Serialize;

/// A patch is cut once most of its rim lies within this many `empty` distances of the target.
const RIM: f64 = 2.0;

/// One topology change, for the statistics and the app's timeline.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct SurgeryEvent {
    /// The step after which it happened.
    pub step: u32,
    /// What happened: `"handle"` (two membranes cut and joined by a tube: genus +1).
    pub kind: &'static str,
    /// Where (centre of the tube), in the target's units.
    pub position: [f64; 3],
    /// Radius of the cut (farthest loop vertex from `position`), in the target's units.
    pub radius: f64,
    /// Genus of the surface before and after.
    pub genus_before: i64,
    pub genus_after: i64,
}

/// A surface after successful surgery.
pub struct Operated {
    pub mesh: HalfedgeMesh,
    pub tubes: Vec<Tube>,
    pub genus_before: i64,
    pub genus_after: i64,
}

/// Looks for facing membranes in empty space and glues each facing pair of patches with a tube.
/// The result is kept only when it is a closed, oriented manifold free of self-intersections
/// whose genus rose by the number of tubes (else `None`: the surface stays as it was).
/// `distances` are the vertices' distances to the target.
pub fn open_handles(
    mesh: &HalfedgeMesh,
    distances: &[f64],
    query: &FacingQuery,
    min_vertices: usize,
) -> Option<Operated> {
    let normals = angle_weighted_normals(mesh);
    let partner = facing_pairs(mesh, &normals, distances, query);
    if partner.iter().filter(|p| p.is_some()).count() < 2 * min_vertices {
        return None;
    }
    let before = mesh.validate().ok()?;
    let glued = glue_facing_regions(mesh, &partner, distances, RIM * query.empty, min_vertices)?;
    let out = HalfedgeMesh::from_triangles(glued.positions, &glued.triangles).ok()?;
    let after = out.validate().ok()?;
    let expected = before.genus + glued.tubes.len() as i64;
    let merged = before.components > after.components;
    if !(after.genus == expected || merged) {
        return None;
    }
    if count_self_intersections(out.positions(), &out.triangles()) > 0 {
        return None;
    }
    Some(Operated {
        mesh: out,
        tubes: glued.tubes,
        genus_before: before.genus,
        genus_after: after.genus,
    })
}

/// The event records of `op`, in the target's units: positions mapped by `to_target`, lengths
/// divided by `scale`.
pub fn events(
    op: &Operated,
    step: u32,
    scale: f64,
    to_target: impl Fn(DVec3) -> DVec3,
) -> Vec<SurgeryEvent> {
    op.tubes
        .iter()
        .map(|t| SurgeryEvent {
            step,
            kind: "handle",
            position: to_target(t.position).to_array(),
            radius: t.radius / scale,
            genus_before: op.genus_before,
            genus_after: op.genus_after,
        })
        .collect()
}
