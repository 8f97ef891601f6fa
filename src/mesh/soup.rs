//! Edge statistics of a plain triangle list (a "soup" that may not be a manifold), for reporting
//! on files before any halfedge structure can be built from them.

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

#[cfg(test)]
mod tests {
    use super::*;

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
