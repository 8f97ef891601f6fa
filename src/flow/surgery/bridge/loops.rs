//! The boundary loops of a region's faces, when they form a disk or an annulus.

use crate::mesh::HalfedgeMesh;

/// The boundary loop of region `r`'s faces (those with all three vertices in `r`) when they
/// form a disk.
pub(super) fn disk_loop(
    mesh: &HalfedgeMesh,
    region: &[Option<u32>],
    r: u32,
    removed: &[bool],
) -> Option<Vec<Vec<u32>>> {
    region_loops(mesh, region, r, removed, 1)
}

/// The boundary loops of region `r`'s faces (those with all three vertices in `r`) when they
/// form a connected surface of Euler characteristic `euler` — a disk (1: one loop) or an annulus
/// (0: two loops) — with simple loops of at least three vertices, each in the direction of the
/// region's own halfedges. Faces already `removed` disqualify the region.
pub(super) fn region_loops(
    mesh: &HalfedgeMesh,
    region: &[Option<u32>],
    r: u32,
    removed: &[bool],
    euler: i64,
) -> Option<Vec<Vec<u32>>> {
    let inside = |f: u32| {
        !mesh.is_deleted_face(f)
            && mesh
                .face_vertices(f)
                .iter()
                .all(|&v| region[v as usize] == Some(r))
    };
    let faces: Vec<u32> = (0..mesh.n_faces() as u32).filter(|&f| inside(f)).collect();
    if faces.is_empty() || faces.iter().any(|&f| removed[f as usize]) {
        return None;
    }
    // Boundary halfedges of the region: in a region face, opposite outside the region.
    let mut next_of = std::collections::BTreeMap::new();
    let mut verts = std::collections::BTreeSet::new();
    let mut interior_edges = 0usize;
    for &f in &faces {
        let h0 = mesh.face_halfedge(f);
        let mut h = h0;
        loop {
            verts.insert(mesh.from(h));
            let o = HalfedgeMesh::opposite(h);
            if mesh.is_boundary_halfedge(o) || !inside(mesh.face(o)) {
                if next_of.insert(mesh.from(h), mesh.to(h)).is_some() {
                    return None; // a loop touches itself at a vertex
                }
            } else {
                interior_edges += 1;
            }
            h = mesh.next(h);
            if h == h0 {
                break;
            }
        }
    }
    let edges = interior_edges / 2 + next_of.len();
    if verts.len() as i64 - edges as i64 + faces.len() as i64 != euler {
        return None;
    }
    let mut loops = Vec::new();
    let mut seen = std::collections::BTreeSet::new();
    for &first in next_of.keys() {
        if !seen.insert(first) {
            continue;
        }
        let mut lp = vec![first];
        let mut v = next_of[&first];
        while v != first {
            if !seen.insert(v) {
                return None;
            }
            lp.push(v);
            v = *next_of.get(&v)?;
        }
        if lp.len() < 3 {
            return None;
        }
        loops.push(lp);
    }
    // A connected region with χ = 2 − 2g − b: one loop for a disk, two for an annulus.
    (loops.len() as i64 == 2 - euler && connected(mesh, &faces, &inside)).then_some(loops)
}

/// Whether `faces` are edge-connected through faces for which `inside` holds.
fn connected(mesh: &HalfedgeMesh, faces: &[u32], inside: &impl Fn(u32) -> bool) -> bool {
    let mut seen = std::collections::BTreeSet::from([faces[0]]);
    let mut stack = vec![faces[0]];
    while let Some(f) = stack.pop() {
        let h0 = mesh.face_halfedge(f);
        let mut h = h0;
        loop {
            let o = HalfedgeMesh::opposite(h);
            if !mesh.is_boundary_halfedge(o) {
                let g = mesh.face(o);
                if inside(g) && seen.insert(g) {
                    stack.push(g);
                }
            }
            h = mesh.next(h);
            if h == h0 {
                break;
            }
        }
    }
    seen.len() == faces.len()
}

/// Marks the faces with all three vertices in one of `regions` as removed.
pub(super) fn remove_region(
    mesh: &HalfedgeMesh,
    region: &[Option<u32>],
    regions: &[u32],
    removed: &mut [bool],
) {
    for f in 0..mesh.n_faces() as u32 {
        if !mesh.is_deleted_face(f) {
            let r = mesh.face_vertices(f).map(|v| region[v as usize]);
            if regions.iter().any(|&x| r.iter().all(|&y| y == Some(x))) {
                removed[f as usize] = true;
            }
        }
    }
}
