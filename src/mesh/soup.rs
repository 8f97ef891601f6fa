//! Edge statistics of a plain triangle list (a "soup" that may not be a manifold), for reporting
//! on files before any halfedge structure can be built from them, and the topology of a closed
//! one without building one (for the certificate's target: a sort is several times faster than
//! building a [`crate::mesh::HalfedgeMesh`]).

use crate::mesh::MeshReport;

/// How the undirected edges of a triangle list are shared.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct EdgeCounts {
    /// Distinct undirected edges.
    pub edges: usize,
    /// Edges used by exactly one triangle (a hole's rim or an open border).
    pub boundary: usize,
    /// Edges used by more than two triangles (non-manifold).
    pub non_manifold: usize,
}

/// Counts the edges of `tris` by sorting their undirected vertex pairs.
pub fn edge_counts(tris: &[[u32; 3]]) -> EdgeCounts {
    let mut e: Vec<(u32, u32)> = tris
        .iter()
        .flat_map(|t| [(t[0], t[1]), (t[1], t[2]), (t[2], t[0])])
        .map(|(a, b)| (a.min(b), a.max(b)))
        .collect();
    e.sort_unstable();
    let mut c = EdgeCounts::default();
    for run in e.chunk_by(|a, b| a == b) {
        c.edges += 1;
        match run.len() {
            1 => c.boundary += 1,
            2 => {}
            _ => c.non_manifold += 1,
        }
    }
    c
}

/// The counts, Euler characteristic, genus and components of `tris` over `n_vertices` vertices
/// when every vertex is used and every edge joins exactly two faces that run it in opposite
/// directions (closed, edge-manifold, oriented: what [`crate::mesh::HalfedgeMesh`] accepts
/// of a closed mesh, with the same [`crate::mesh::HalfedgeMesh::topology`]); None otherwise.
pub fn closed_topology(n_vertices: usize, tris: &[[u32; 3]]) -> Option<MeshReport> {
    let mut used = vec![false; n_vertices];
    for t in tris {
        if t[0] == t[1] || t[1] == t[2] || t[2] == t[0] {
            return None;
        }
        for &v in t {
            *used.get_mut(v as usize)? = true;
        }
    }
    if tris.is_empty() || used.contains(&false) {
        return None;
    }
    // (undirected edge, runs from its smaller vertex) per face edge, so the two uses of an edge
    // sort next to each other, the backward one first.
    let mut e: Vec<(u64, bool)> = tris
        .iter()
        .flat_map(|t| [(t[0], t[1]), (t[1], t[2]), (t[2], t[0])])
        .map(|(a, b)| (((a.min(b) as u64) << 32) | a.max(b) as u64, a < b))
        .collect();
    e.sort_unstable();
    // Each edge: its backward use, then its forward one; anything else (a boundary, a third use,
    // two uses the same way) breaks the pairing.
    let paired = e.len() % 2 == 0
        && e.chunks_exact(2)
            .all(|p| p[0].0 == p[1].0 && !p[0].1 && p[1].1);
    if !paired {
        return None;
    }
    let edges = e
        .chunks_exact(2)
        .map(|p| ((p[0].0 >> 32) as u32, p[0].0 as u32));
    let components = count_components(n_vertices, edges);
    Some(MeshReport::from_counts(
        n_vertices,
        e.len() / 2,
        tris.len(),
        components,
    ))
}

/// Connected components of `n_vertices` vertices joined by `edges` (union–find; isolated
/// vertices count as components of their own).
pub fn count_components(n_vertices: usize, edges: impl IntoIterator<Item = (u32, u32)>) -> usize {
    let mut sets = super::disjoint::DisjointSets::new(n_vertices);
    for (a, b) in edges {
        sets.union(a, b);
    }
    (0..n_vertices as u32)
        .filter(|&v| sets.find(v) == v)
        .count()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::icosphere::icosphere;
    use crate::mesh::HalfedgeMesh;
    use glam::DVec3;

    #[test]
    fn closed_topology_is_the_halfedge_meshs_and_refuses_what_it_refuses() {
        let s = icosphere(2, 1.0, DVec3::ZERO).unwrap();
        let (p, t) = (s.positions().to_vec(), s.triangles());
        // Two spheres, and a chain of two tori from the demo shapes.
        let mut t2 = t.clone();
        t2.extend(t.iter().map(|f| f.map(|v| v + p.len() as u32)));
        let (chain_p, chain_t) = crate::demo::shapes::torus_chain(2);
        for (n, tris, genus, parts) in [
            (p.len(), &t, 0, 1),
            (2 * p.len(), &t2, 0, 2),
            (chain_p.len(), &chain_t, 2, 1),
        ] {
            let positions = vec![DVec3::ZERO; n];
            let want = HalfedgeMesh::from_triangles(positions, tris)
                .unwrap()
                .topology();
            let got = closed_topology(n, tris).unwrap();
            assert_eq!(got, want);
            assert_eq!((got.genus, got.components), (genus, parts));
        }
        // Open (a face gone), a face flipped, an edge used three times, an unused vertex.
        assert_eq!(closed_topology(p.len(), &t[1..]), None);
        let mut flipped = t.clone();
        flipped[3].swap(0, 1);
        assert_eq!(closed_topology(p.len(), &flipped), None);
        let mut fin = t.clone();
        let [a, b, _] = t[0];
        fin.push([a, b, 5]);
        fin.push([b, a, 7]);
        assert_eq!(closed_topology(p.len(), &fin), None);
        assert_eq!(closed_topology(p.len() + 1, &t), None);
    }

    #[test]
    fn tetrahedron_open_strip_and_fin() {
        let tet = [[0, 1, 2], [0, 3, 1], [1, 3, 2], [2, 3, 0]];
        assert_eq!(
            edge_counts(&tet),
            EdgeCounts {
                edges: 6,
                boundary: 0,
                non_manifold: 0
            }
        );
        assert_eq!(
            edge_counts(&tet[..2]),
            EdgeCounts {
                edges: 5,
                boundary: 4,
                non_manifold: 0
            }
        );
        // A third triangle on edge (0, 1) of the tetrahedron.
        let fin = [[0, 1, 2], [0, 3, 1], [1, 3, 2], [2, 3, 0], [1, 0, 4]];
        let c = edge_counts(&fin);
        assert_eq!((c.edges, c.boundary, c.non_manifold), (8, 2, 1));
    }
}
