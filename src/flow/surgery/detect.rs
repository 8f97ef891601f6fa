//! Collision detection for surgery: pairs of surface vertices that are close in space, lie back
//! to back (a thin slab of the inside between them: normals opposed, each behind the other), and
//! both lie far from the target. A genus-0 surface shrinking onto a handle grows two
//! membranes across the handle's hole that approach each other in empty space; those are the
//! pairs found here. Sheets meeting *at the data* (the two sides of one scan layer, a membrane
//! sagging onto the inside of a scan) are never paired: their vertices are near the target.
//!
//! Cost: one bucket grid over the far vertices and one k-nearest query per far vertex, O(V).

use crate::geometry::spatial::point_grid::{Near, PointGrid};
use crate::mesh::HalfedgeMesh;
use glam::DVec3;

/// Neighbours examined per far vertex.
const NEIGHBOURS: usize = 16;

/// Facing: the normals of the two vertices make an angle above ≈ 135°.
const FACING_COS: f64 = -0.7;

/// What to pair.
#[derive(Clone, Debug, PartialEq)]
pub struct FacingQuery {
    /// A vertex is in empty space when its distance to the target exceeds this.
    pub empty: f64,
    /// Two facing vertices pair when their gap along the normals is below this fraction of the
    /// smaller of their distances to the target (and they are at most an edge apart sideways).
    pub gap_ratio: f64,
    /// Balls (centre, radius) where nothing pairs: the holes already opened. The membrane left
    /// around a fresh tube still faces its other half across the tube; cutting it again would
    /// open a second handle in the same hole.
    pub opened: Vec<(DVec3, f64)>,
}

/// For every vertex, the nearest vertex of a facing sheet in empty space (`None` when there is
/// none). `distances` are the vertices' distances to the target, `normals` their unit normals.
/// Deterministic: ties go to the smaller index.
pub fn facing_pairs(
    mesh: &HalfedgeMesh,
    normals: &[DVec3],
    distances: &[f64],
    q: &FacingQuery,
) -> Vec<Option<u32>> {
    let n = mesh.n_vertices();
    let mut partner = vec![None; n];
    let far: Vec<u32> = (0..n as u32)
        .filter(|&v| !mesh.is_deleted_vertex(v) && distances[v as usize].abs() > q.empty)
        .filter(|&v| {
            let p = mesh.position(v);
            q.opened.iter().all(|&(c, r)| p.distance_squared(c) > r * r)
        })
        .collect();
    if far.len() < 2 {
        return partner;
    }
    let pts: Vec<DVec3> = far.iter().map(|&v| mesh.position(v)).collect();
    let part = components(mesh);
    // Vertices are spaced by their edges, which may be far longer than the gap between two
    // sheets: the gap is measured along the normal, and a partner may sit up to an edge away
    // sideways.
    let edge = |v: u32| {
        let (mut sum, mut k) = (0.0, 0);
        for u in mesh.neighbors(v) {
            sum += mesh.position(u).distance(mesh.position(v));
            k += 1;
        }
        sum / k.max(1) as f64
    };
    let edges: Vec<f64> = far.iter().map(|&v| edge(v)).collect();
    let reach = |i: usize| q.gap_ratio * distances[far[i] as usize].abs() + edges[i];
    let max_reach = (0..far.len()).map(reach).fold(0.0, f64::max);
    if !(max_reach > 0.0 && max_reach.is_finite()) {
        return partner;
    }
    let grid = PointGrid::new(&pts, max_reach);
    let mut near: Vec<Near> = Vec::with_capacity(NEIGHBOURS);
    for (i, &v) in far.iter().enumerate() {
        let (p, nv, dv) = (pts[i], normals[v as usize], distances[v as usize].abs());
        grid.nearest_within(p, reach(i), NEIGHBOURS, &mut near);
        partner[v as usize] = near.iter().find_map(|c| {
            let j = c.index as usize;
            let u = far[j];
            let (nu, du) = (normals[u as usize], distances[u as usize].abs());
            let w = c.point - p;
            // Separation along the normals and sideways. Back to back (u behind v and v behind
            // u: a slab of the inside between them) on one surface; face to face (the outside
            // between them) only across two components, which then merge.
            let (sv, su) = (-w.dot(nv), w.dot(nu));
            let side = (w + sv * nv).length();
            let back_to_back = sv > 0.0 && su > 0.0;
            let face_to_face = sv < 0.0 && su < 0.0 && part[u as usize] != part[v as usize];
            let facing = nv.dot(nu) < FACING_COS
                && (back_to_back || face_to_face)
                && sv.abs().max(su.abs()) < q.gap_ratio * du.min(dv)
                && side <= edges[i].max(edges[j]);
            (u != v && facing).then_some(u)
        });
    }
    partner
}

/// The connected component of every vertex (deterministic numbering).
fn components(mesh: &HalfedgeMesh) -> Vec<u32> {
    let n = mesh.n_vertices();
    let mut part = vec![u32::MAX; n];
    let mut id = 0;
    let mut stack = Vec::new();
    for s in 0..n as u32 {
        if part[s as usize] != u32::MAX {
            continue;
        }
        part[s as usize] = id;
        stack.push(s);
        while let Some(v) = stack.pop() {
            if mesh.is_deleted_vertex(v) {
                continue;
            }
            for u in mesh.neighbors(v) {
                if part[u as usize] == u32::MAX {
                    part[u as usize] = id;
                    stack.push(u);
                }
            }
        }
        id += 1;
    }
    part
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::icosphere::icosphere;
    use crate::geometry::operators::normals::angle_weighted_normals;

    /// A sphere squashed into a pancake: its top and bottom face each other across a small gap.
    fn pancake(gap: f64) -> HalfedgeMesh {
        let mut m = icosphere(4, 1.0, DVec3::ZERO).unwrap();
        for p in m.positions_mut() {
            p.z *= gap / 2.0;
        }
        m
    }

    #[test]
    fn a_pancake_in_empty_space_pairs_its_two_faces() {
        let m = pancake(0.02);
        let normals = angle_weighted_normals(&m);
        let far = vec![1.0; m.n_vertices()];
        let mut q = FacingQuery {
            empty: 0.5,
            gap_ratio: 0.25,
            opened: vec![],
        };
        let pairs = facing_pairs(&m, &normals, &far, &q);
        let paired: Vec<u32> = (0..m.n_vertices() as u32)
            .filter(|&v| pairs[v as usize].is_some())
            .collect();
        assert!(paired.len() > m.n_vertices() / 2, "{}", paired.len());
        for v in paired {
            let u = pairs[v as usize].unwrap();
            let (pv, pu) = (m.position(v), m.position(u));
            assert!(pv.z * pu.z < 0.0, "pairs join top and bottom");
            assert!((pv - pu).length() < 0.1);
        }
        // Nothing pairs inside a hole already opened.
        q.opened.push((DVec3::ZERO, 2.0));
        assert!(facing_pairs(&m, &normals, &far, &q)
            .iter()
            .all(Option::is_none));
    }

    #[test]
    fn sheets_near_the_data_or_far_apart_are_not_paired() {
        let m = pancake(0.02);
        let normals = angle_weighted_normals(&m);
        let q = FacingQuery {
            empty: 0.5,
            gap_ratio: 0.25,
            opened: vec![],
        };
        // At the data: every vertex within `empty` of the target.
        let near = vec![0.1; m.n_vertices()];
        assert!(facing_pairs(&m, &normals, &near, &q)
            .iter()
            .all(Option::is_none));
        // A round sphere: opposite sides are 2 apart, far above a quarter of their distance.
        let s = icosphere(4, 1.0, DVec3::ZERO).unwrap();
        let far = vec![1.0; s.n_vertices()];
        let ns = angle_weighted_normals(&s);
        assert!(facing_pairs(&s, &ns, &far, &q).iter().all(Option::is_none));
    }
}
