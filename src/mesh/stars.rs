//! The corners around each vertex of a triangle list ("stars"), and what they tell about its
//! edges: boundary, shared by two faces running them both ways, or neither. Used by the field
//! to decide whether a mesh can be signed, and by [`super::repair`] to decide whether it needs
//! mending.

/// Edge statistics of a triangle soup (whether a field can sign it, whether it needs mending).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Closure {
    /// Undirected edges.
    pub edges: usize,
    /// Edges used by exactly one triangle.
    pub boundary_edges: usize,
    /// Edges used by more than two triangles, or twice in the same direction.
    pub bad_edges: usize,
}

/// The corners around each vertex (compressed rows, built by a counting sort): corner `3t + k`
/// of triangle `t` sits in the row of vertex `triangles[t][k]`, rows in ascending corner order.
/// Edge questions are answered by scanning one small row instead of hashing every edge of the
/// mesh: on a large volume iso-surface, edge hash maps spend their time in cache misses.
pub struct Stars {
    start: Vec<u32>,
    corners: Vec<u32>,
}

impl Stars {
    /// The stars of `n_vertices` vertices used by `triangles`.
    pub fn new(n_vertices: usize, triangles: &[[u32; 3]]) -> Self {
        let mut start = vec![0u32; n_vertices + 1];
        for &v in triangles.iter().flatten() {
            start[v as usize + 1] += 1;
        }
        for i in 0..n_vertices {
            start[i + 1] += start[i];
        }
        let mut fill = start.clone();
        let mut corners = vec![0u32; triangles.len() * 3];
        for (c, &v) in triangles.iter().flatten().enumerate() {
            corners[fill[v as usize] as usize] = c as u32;
            fill[v as usize] += 1;
        }
        Self { start, corners }
    }

    /// The corners at vertex `v`.
    pub fn row(&self, v: u32) -> &[u32] {
        &self.corners[self.start[v as usize] as usize..self.start[v as usize + 1] as usize]
    }
}

/// The vertex after and before corner `c` in its triangle.
#[inline]
fn next_prev(triangles: &[[u32; 3]], c: u32) -> (u32, u32) {
    let (t, k) = ((c / 3) as usize, (c % 3) as usize);
    (triangles[t][(k + 1) % 3], triangles[t][(k + 2) % 3])
}

/// Calls `f(other, forward, t)` once for every directed edge use whose smaller endpoint is `a`
/// (`other ≥ a`): `forward` when the edge runs a → other with a < other, in ascending corner
/// order. A directed edge u → v is met at u's corner when v ≥ u, else at v's corner.
pub fn edge_uses(stars: &Stars, triangles: &[[u32; 3]], a: u32, mut f: impl FnMut(u32, bool, u32)) {
    for &c in stars.row(a) {
        let (next, prev) = next_prev(triangles, c);
        if next >= a {
            f(next, next > a, c / 3);
        }
        if prev > a {
            f(prev, false, c / 3);
        }
    }
}

/// Counts boundary and non-manifold/inconsistent edges.
pub fn closure(triangles: &[[u32; 3]]) -> Closure {
    let n = vertex_count(triangles);
    closure_with(&Stars::new(n, triangles), triangles, n)
}

/// One more than the largest vertex index (0 without triangles).
fn vertex_count(triangles: &[[u32; 3]]) -> usize {
    triangles
        .iter()
        .flatten()
        .map(|&v| v as usize + 1)
        .max()
        .unwrap_or(0)
}

/// [`closure`], and the ends of every boundary edge (each vertex once per edge).
pub fn closure_and_rims(triangles: &[[u32; 3]]) -> (Closure, Vec<u32>) {
    let n = vertex_count(triangles);
    let mut rims = Vec::new();
    let c = tally(&Stars::new(n, triangles), triangles, n, |a, b| {
        rims.extend([a, b])
    });
    (c, rims)
}

/// [`closure`] with the stars already built.
pub fn closure_with(stars: &Stars, triangles: &[[u32; 3]], n_vertices: usize) -> Closure {
    tally(stars, triangles, n_vertices, |_, _| {})
}

/// The edge counts, calling `on_boundary(a, b)` for each boundary edge.
fn tally(
    stars: &Stars,
    triangles: &[[u32; 3]],
    n_vertices: usize,
    mut on_boundary: impl FnMut(u32, u32),
) -> Closure {
    let mut c = Closure {
        edges: 0,
        boundary_edges: 0,
        bad_edges: 0,
    };
    // (other endpoint, forward) uses of the edges starting at one vertex.
    let mut uses: Vec<(u32, bool)> = Vec::new();
    for a in 0..n_vertices as u32 {
        uses.clear();
        edge_uses(stars, triangles, a, |o, fwd, _| uses.push((o, fwd)));
        uses.sort_unstable();
        let mut i = 0;
        while i < uses.len() {
            let o = uses[i].0;
            let (mut f, mut b) = (0u32, 0u32);
            while i < uses.len() && uses[i].0 == o {
                if uses[i].1 {
                    f += 1;
                } else {
                    b += 1;
                }
                i += 1;
            }
            c.edges += 1;
            match (f, b) {
                (1, 1) => {}
                (1, 0) | (0, 1) => {
                    c.boundary_edges += 1;
                    on_boundary(a, o);
                }
                _ => c.bad_edges += 1,
            }
        }
    }
    c
}
