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
use crate::metrics::intersections::self_intersecting_pairs;
use bridge::{glue_facing_regions, Cut, Tube};
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
    /// What happened: `"handle"` (two membranes cut and joined by a tube: genus +1), `"merge"`
    /// (a tube between two components), `"pinch"` (a neck in empty space cut and both sides
    /// capped), `"drop"` (a component enclosing no data removed).
    pub kind: &'static str,
    /// Where (centre of the tube), in the target's units.
    pub position: [f64; 3],
    /// Radius of the cut (farthest loop vertex from `position`), in the target's units.
    pub radius: f64,
    /// Genus of the surface before and after (summed over components).
    pub genus_before: i64,
    pub genus_after: i64,
    /// Connected components before and after.
    pub components_before: usize,
    pub components_after: usize,
}

/// A surface after successful surgery.
pub struct Operated {
    pub mesh: HalfedgeMesh,
    pub tubes: Vec<Tube>,
    pub genus_before: i64,
    pub genus_after: i64,
    pub components_before: usize,
    pub components_after: usize,
}

/// Membranes have settled when their count of paired vertices grew by less than this factor
/// since the last look.
const SETTLED_GROWTH: f64 = 1.1;

/// What one look for facing membranes found.
pub struct Look {
    /// Vertices paired with a facing sheet (pass it to the next look).
    pub paired: usize,
    /// The operated surface, if surgery was done.
    pub operated: Option<Operated>,
}

/// Looks for facing membranes in empty space: glues each facing pair of patches with a tube and
/// cuts each neck that faces itself, capping both sides. The result is kept only when it is a
/// closed, oriented manifold free of self-intersections whose Euler characteristic changed by
/// −2 per tube and +2 per cut neck (else the surface stays as it was). `distances` are
/// the vertices' distances to the target; `previous` is the last look's `paired`.
pub fn open_handles(
    mesh: &HalfedgeMesh,
    distances: &[f64],
    query: &FacingQuery,
    min_vertices: usize,
    previous: usize,
) -> Look {
    let normals = angle_weighted_normals(mesh);
    let partner = facing_pairs(mesh, &normals, distances, query);
    let paired = partner.iter().filter(|p| p.is_some()).count();
    let settled = paired as f64 <= SETTLED_GROWTH * previous as f64;
    let operated = if paired < 2 * min_vertices {
        None
    } else {
        operate(mesh, &partner, distances, query, settled, min_vertices)
    };
    Look { paired, operated }
}

/// Cuts and glues; `None` when nothing qualified or the result failed a check. When some of the
/// new faces cross others, the operations they belong to are left out and the rest tried once
/// more (one bad tube must not hold back the other holes).
fn operate(
    mesh: &HalfedgeMesh,
    partner: &[Option<u32>],
    distances: &[f64],
    query: &FacingQuery,
    settled: bool,
    min_vertices: usize,
) -> Option<Operated> {
    let before = mesh.validate().ok()?;
    let rim = RIM * query.empty;
    let mut skip = Vec::new();
    for _attempt in 0..2 {
        let glued =
            glue_facing_regions(mesh, partner, distances, rim, settled, min_vertices, &skip)?;
        let out = HalfedgeMesh::from_triangles(glued.positions, &glued.triangles).ok()?;
        let after = out.validate().ok()?;
        let change: i64 = glued
            .tubes
            .iter()
            .map(|t| if t.cut == Cut::Tube { -2 } else { 2 })
            .sum();
        if after.euler_characteristic != before.euler_characteristic + change {
            return None;
        }
        let pairs = self_intersecting_pairs(out.positions(), &out.triangles());
        if pairs.is_empty() {
            return Some(Operated {
                mesh: out,
                tubes: glued.tubes,
                genus_before: before.genus,
                genus_after: after.genus,
                components_before: before.components,
                components_after: after.components,
            });
        }
        let bad: Vec<u32> = glued
            .tubes
            .iter()
            .filter(|t| {
                let hit = |f: u32| t.faces.contains(&(f as usize));
                pairs.iter().any(|&(f, g)| hit(f) || hit(g))
            })
            .map(|t| t.region)
            .collect();
        // Crossings among the old faces only, or every operation at fault: nothing to retry.
        if bad.is_empty() || bad.len() == glued.tubes.len() {
            return None;
        }
        skip.extend(bad);
    }
    None
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
            kind: match t.cut {
                Cut::Pinch => "pinch",
                Cut::Tube if op.components_after < op.components_before => "merge",
                Cut::Tube => "handle",
            },
            position: to_target(t.position).to_array(),
            radius: t.radius / scale,
            genus_before: op.genus_before,
            genus_after: op.genus_after,
            components_before: op.components_before,
            components_after: op.components_after,
        })
        .collect()
}

/// Removes the components of a surface that enclose no data: every vertex farther than `empty`
/// from the target (`distances` per vertex), as left behind when a neck pinched beside a bubble.
/// Returns the rest and the centroid of what was dropped; `None` when every component touches
/// the data (or none does: then nothing is certain and nothing is dropped).
pub fn drop_empty_components(
    mesh: &HalfedgeMesh,
    distances: &[f64],
    empty: f64,
) -> Option<(HalfedgeMesh, DVec3)> {
    let n = mesh.n_vertices();
    let mut comp = vec![u32::MAX; n];
    let mut near = Vec::new();
    for s in 0..n as u32 {
        if comp[s as usize] != u32::MAX || mesh.is_deleted_vertex(s) {
            continue;
        }
        let id = near.len() as u32;
        let mut touches = false;
        let mut stack = vec![s];
        comp[s as usize] = id;
        while let Some(v) = stack.pop() {
            touches |= distances[v as usize].abs() <= empty;
            for u in mesh.neighbors(v) {
                if comp[u as usize] == u32::MAX {
                    comp[u as usize] = id;
                    stack.push(u);
                }
            }
        }
        near.push(touches);
    }
    let dropped = near.iter().filter(|&&t| !t).count();
    if dropped == 0 || dropped == near.len() {
        return None;
    }
    let tris: Vec<[u32; 3]> = (0..mesh.n_faces() as u32)
        .filter(|&f| !mesh.is_deleted_face(f))
        .map(|f| mesh.face_vertices(f))
        .filter(|t| near[comp[t[0] as usize] as usize])
        .collect();
    let gone: Vec<DVec3> = (0..n)
        .filter(|&v| comp[v] != u32::MAX && !near[comp[v] as usize])
        .map(|v| mesh.position(v as u32))
        .collect();
    let centroid = gone.iter().sum::<DVec3>() / gone.len().max(1) as f64;
    let (p, t) = bridge::compact(mesh.positions(), &tris);
    Some((HalfedgeMesh::from_triangles(p, &t).ok()?, centroid))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::icosphere::icosphere;
    use crate::metrics::intersections::self_intersecting_pairs_brute_force;

    /// The membrane a genus-0 surface leaves across a ring-shaped target: a unit disk squashed to
    /// a gap of `gap`, whose rim touches the ring (distance 1 − r from the axis).
    fn membrane(gap: f64) -> (HalfedgeMesh, Vec<f64>) {
        let mut m = icosphere(4, 1.0, DVec3::ZERO).unwrap();
        for p in m.positions_mut() {
            p.z *= gap / 2.0;
        }
        let d = m
            .positions()
            .iter()
            .map(|p| (1.0 - p.truncate().length()).max(0.0))
            .collect();
        (m, d)
    }

    #[test]
    fn a_membrane_across_a_ring_becomes_a_tube() {
        let (m, d) = membrane(0.02);
        let q = FacingQuery {
            empty: 0.15,
            gap_ratio: 0.25,
            opened: vec![],
        };
        // It spans the hole (its rim near the ring): cut at the first look.
        let op = open_handles(&m, &d, &q, 6, 0)
            .operated
            .expect("the membrane is cut");
        assert_eq!((op.genus_before, op.genus_after), (0, 1));
        assert_eq!(op.tubes.len(), 1);
        let r = op.mesh.validate().unwrap();
        assert_eq!((r.genus, r.components), (1, 1));
        // Exact predicates, every pair: the tube's faces cross none of their neighbours.
        let pairs = self_intersecting_pairs_brute_force(op.mesh.positions(), &op.mesh.triangles());
        assert!(pairs.is_empty(), "{pairs:?}");
        // The hole is where the membrane was deepest: around the axis, its rim near the ring.
        let t = &op.tubes[0];
        assert!(t.position.truncate().length() < 0.1, "{:?}", t.position);
        assert!(t.radius > 0.5 && t.radius < 1.0, "{}", t.radius);
        // Nothing pairs inside the opened hole any more.
        let q2 = FacingQuery {
            opened: vec![(t.position, t.radius + 1.5 * q.empty)],
            ..q
        };
        assert!(
            open_handles(&op.mesh, &vec![0.5; op.mesh.n_vertices()], &q2, 6, 1 << 20)
                .operated
                .is_none()
        );
    }

    #[test]
    fn a_first_contact_waits_until_the_membranes_settle() {
        // Sheets touching in the middle of a wide hole: the rim of the contact is as deep as
        // its centre, so the membranes are still closing in; cut once they stop.
        let (m, d) = membrane(0.02);
        let deep: Vec<f64> = d.iter().map(|d| d + 1.0).collect();
        let q = FacingQuery {
            empty: 0.15,
            gap_ratio: 0.25,
            opened: vec![],
        };
        let first = open_handles(&m, &deep, &q, 6, 0);
        assert!(first.paired > 0 && first.operated.is_none());
        let op = open_handles(&m, &deep, &q, 6, first.paired).operated;
        assert_eq!(op.map(|o| o.genus_after), Some(1));
    }

    fn far_query() -> FacingQuery {
        FacingQuery {
            empty: 0.15,
            gap_ratio: 0.25,
            opened: vec![],
        }
    }

    #[test]
    fn two_spheres_approaching_in_empty_space_merge_through_a_tube() {
        let a = icosphere(3, 1.0, DVec3::new(-1.01, 0.0, 0.0)).unwrap();
        let b = icosphere(3, 1.0, DVec3::new(1.01, 0.0, 0.0)).unwrap();
        let n = a.n_vertices() as u32;
        let mut p = a.positions().to_vec();
        p.extend_from_slice(b.positions());
        let mut t = a.triangles();
        t.extend(b.triangles().iter().map(|f| f.map(|v| v + n)));
        let m = HalfedgeMesh::from_triangles(p, &t).unwrap();
        let far = vec![1.0; m.n_vertices()];
        let op = open_handles(&m, &far, &far_query(), 6, 1 << 20)
            .operated
            .expect("the spheres merge");
        assert_eq!((op.components_before, op.components_after), (2, 1));
        assert_eq!((op.genus_before, op.genus_after), (0, 0));
        assert_eq!(events(&op, 1, 1.0, |p| p)[0].kind, "merge");
        let pairs = self_intersecting_pairs_brute_force(op.mesh.positions(), &op.mesh.triangles());
        assert!(pairs.is_empty(), "{pairs:?}");
    }

    #[test]
    fn a_neck_in_empty_space_is_cut_and_capped() {
        // A needle: its long middle faces itself across the axis, its tips do not.
        let mut m = icosphere(3, 1.0, DVec3::ZERO).unwrap();
        for p in m.positions_mut() {
            *p *= DVec3::new(1.0, 0.04, 0.04);
        }
        let far = vec![1.0; m.n_vertices()];
        let op = open_handles(&m, &far, &far_query(), 6, 1 << 20)
            .operated
            .expect("the neck is cut");
        // Each ring cut adds a component (the icosphere's symmetry may give more than one ring).
        assert_eq!(op.components_after, 1 + op.tubes.len());
        assert_eq!(op.genus_after, 0);
        assert!(events(&op, 1, 1.0, |p| p).iter().all(|e| e.kind == "pinch"));
        let pairs = self_intersecting_pairs_brute_force(op.mesh.positions(), &op.mesh.triangles());
        assert!(pairs.is_empty(), "{pairs:?}");
        // Both stumps enclose nothing (all far from the data): nothing certain, nothing dropped;
        // with one stump at the data, the other goes.
        let d_far = vec![1.0; op.mesh.n_vertices()];
        assert!(drop_empty_components(&op.mesh, &d_far, 0.15).is_none());
        let d_left: Vec<f64> = op
            .mesh
            .positions()
            .iter()
            .map(|p| if p.x < 0.0 { 0.0 } else { 1.0 })
            .collect();
        let (kept, gone) = drop_empty_components(&op.mesh, &d_left, 0.15).unwrap();
        // The right tip goes (the middle piece, if any, reaches the left half and stays).
        assert_eq!(kept.validate().unwrap().components, op.components_after - 1);
        assert!(gone.x > 0.5, "{gone:?}");
    }

    #[test]
    fn a_membrane_at_the_data_is_left_alone() {
        let (m, _) = membrane(0.02);
        let near = vec![0.1; m.n_vertices()];
        let q = FacingQuery {
            empty: 0.15,
            gap_ratio: 0.25,
            opened: vec![],
        };
        let look = open_handles(&m, &near, &q, 6, 1 << 20);
        assert_eq!(look.paired, 0);
        assert!(look.operated.is_none());
    }
}
