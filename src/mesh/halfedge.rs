//! The halfedge data structure and its construction from an indexed triangle list.
//!
//! Halfedges come in pairs: edge `e` owns halfedges `2e` and `2e + 1`, so `opposite(h) = h ^ 1`
//! needs no storage. Indices are `u32` (meshes here stay far below 4 G elements) and `INVALID`
//! marks "none" (a boundary halfedge has no face, an isolated vertex no halfedge).

use glam::DVec3;
use std::collections::HashMap;

/// Marker for a missing element index.
pub const INVALID: u32 = u32::MAX;

/// Why a triangle list could not be turned into a halfedge mesh.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum MeshBuildError {
    /// A face index points past the vertex array.
    #[error("face {face} refers to vertex {vertex}, but the mesh has {count} vertices")]
    IndexOutOfRange {
        face: usize,
        vertex: u32,
        count: usize,
    },
    /// A face repeats a vertex, so it has no area and no well-defined edges.
    #[error("face {face} repeats a vertex ({a}, {b}, {c})")]
    RepeatedVertex { face: usize, a: u32, b: u32, c: u32 },
    /// The directed edge `from → to` is used by two faces: either more than two faces share the
    /// edge (non-manifold) or two neighbours are oriented inconsistently.
    #[error("edge {from}→{to} is used twice (non-manifold edge or inconsistent orientation), second time by face {face}")]
    NonManifoldEdge { face: usize, from: u32, to: u32 },
    /// A vertex where two or more separate boundary fans meet (a "bow-tie").
    #[error("vertex {vertex} is non-manifold (several boundary fans meet there)")]
    NonManifoldVertex { vertex: u32 },
    /// More elements than `u32` indices can address.
    #[error("the mesh is too large for 32-bit indices")]
    TooLarge,
}

/// A triangle mesh stored as halfedges, with per-vertex positions and named per-vertex scalars.
#[derive(Clone, Debug, Default)]
pub struct HalfedgeMesh {
    pub(crate) positions: Vec<DVec3>,
    /// One outgoing halfedge per vertex; for boundary vertices, the boundary one.
    pub(crate) v_halfedge: Vec<u32>,
    pub(crate) h_to: Vec<u32>,
    pub(crate) h_next: Vec<u32>,
    pub(crate) h_prev: Vec<u32>,
    /// Face to the left of the halfedge, `INVALID` on the boundary.
    pub(crate) h_face: Vec<u32>,
    pub(crate) f_halfedge: Vec<u32>,
    /// Named per-vertex scalar layers (distance, feature flags, …), kept in step with `positions`.
    pub(crate) vertex_scalars: Vec<(String, Vec<f64>)>,
    /// Deleted-vertex flags left by topology edits (`mesh::edit`); empty means "none deleted".
    /// Either empty or exactly `n_vertices()` long.
    pub(crate) v_deleted: Vec<bool>,
    /// Deleted-edge flags (empty, or `n_edges()` long).
    pub(crate) e_deleted: Vec<bool>,
    /// Deleted-face flags (empty, or `n_faces()` long).
    pub(crate) f_deleted: Vec<bool>,
    /// Number of elements flagged deleted but not yet compacted by `garbage_collect()`.
    pub(crate) n_garbage: usize,
}

impl HalfedgeMesh {
    /// Builds the mesh from positions and counter-clockwise (outward) triangles.
    ///
    /// Vertices referenced by no face stay isolated (and make [`HalfedgeMesh::validate`] fail).
    pub fn from_triangles(
        positions: Vec<DVec3>,
        faces: &[[u32; 3]],
    ) -> Result<Self, MeshBuildError> {
        let nv = positions.len();
        if nv >= INVALID as usize || faces.len() * 3 >= (INVALID / 2) as usize {
            return Err(MeshBuildError::TooLarge);
        }
        let mut m = HalfedgeMesh {
            v_halfedge: vec![INVALID; nv],
            positions,
            ..Default::default()
        };
        m.h_to.reserve(faces.len() * 3);
        // Undirected edge (min, max) -> edge index; only used for lookup, never iterated.
        let mut edge_of: HashMap<(u32, u32), u32> = HashMap::with_capacity(faces.len() * 3 / 2);
        for (fi, &[a, b, c]) in faces.iter().enumerate() {
            for v in [a, b, c] {
                if v as usize >= nv {
                    return Err(MeshBuildError::IndexOutOfRange {
                        face: fi,
                        vertex: v,
                        count: nv,
                    });
                }
            }
            if a == b || b == c || c == a {
                return Err(MeshBuildError::RepeatedVertex { face: fi, a, b, c });
            }
            let f = fi as u32;
            let mut hs = [0u32; 3];
            for (k, (from, to)) in [(a, b), (b, c), (c, a)].into_iter().enumerate() {
                let key = (from.min(to), from.max(to));
                let e = *edge_of.entry(key).or_insert_with(|| {
                    let e = (m.h_to.len() / 2) as u32;
                    // halfedge 2e goes min→max, 2e+1 goes max→min.
                    m.h_to.extend([key.1, key.0]);
                    m.h_next.extend([INVALID, INVALID]);
                    m.h_prev.extend([INVALID, INVALID]);
                    m.h_face.extend([INVALID, INVALID]);
                    e
                });
                let h = if from < to { 2 * e } else { 2 * e + 1 };
                if m.h_face[h as usize] != INVALID {
                    return Err(MeshBuildError::NonManifoldEdge { face: fi, from, to });
                }
                m.h_face[h as usize] = f;
                hs[k] = h;
                m.v_halfedge[from as usize] = h;
            }
            for k in 0..3 {
                m.h_next[hs[k] as usize] = hs[(k + 1) % 3];
                m.h_prev[hs[(k + 1) % 3] as usize] = hs[k];
            }
            m.f_halfedge.push(hs[0]);
        }
        // Link boundary halfedges: the boundary successor of u→v starts at v.
        let mut boundary_out = vec![INVALID; nv];
        for h in 0..m.h_to.len() as u32 {
            if m.h_face[h as usize] == INVALID {
                let from = m.from(h);
                if boundary_out[from as usize] != INVALID {
                    return Err(MeshBuildError::NonManifoldVertex { vertex: from });
                }
                boundary_out[from as usize] = h;
            }
        }
        for h in 0..m.h_to.len() as u32 {
            if m.h_face[h as usize] == INVALID {
                let n = boundary_out[m.to(h) as usize];
                m.h_next[h as usize] = n;
                m.h_prev[n as usize] = h;
            }
        }
        for (v, &h) in boundary_out.iter().enumerate() {
            if h != INVALID {
                m.v_halfedge[v] = h;
            }
        }
        Ok(m)
    }

    /// True when topology edits left deleted elements that [`HalfedgeMesh::garbage_collect`]
    /// has not compacted yet. Element counts then include the deleted ones, and whole-mesh
    /// functions (`validate`, `triangles`, `signed_volume`, …) must not be used before compaction.
    pub fn has_garbage(&self) -> bool {
        self.n_garbage > 0
    }
    /// True when vertex `v` was removed by an edit and awaits garbage collection.
    #[inline]
    pub fn is_deleted_vertex(&self, v: u32) -> bool {
        self.v_deleted.get(v as usize).copied().unwrap_or(false)
    }
    /// True when edge `e` was removed by an edit and awaits garbage collection.
    #[inline]
    pub fn is_deleted_edge(&self, e: u32) -> bool {
        self.e_deleted.get(e as usize).copied().unwrap_or(false)
    }
    /// True when face `f` was removed by an edit and awaits garbage collection.
    #[inline]
    pub fn is_deleted_face(&self, f: u32) -> bool {
        self.f_deleted.get(f as usize).copied().unwrap_or(false)
    }

    /// Number of vertices.
    pub fn n_vertices(&self) -> usize {
        self.positions.len()
    }
    /// Number of edges.
    pub fn n_edges(&self) -> usize {
        self.h_to.len() / 2
    }
    /// Number of halfedges (twice the edges).
    pub fn n_halfedges(&self) -> usize {
        self.h_to.len()
    }
    /// Number of faces.
    pub fn n_faces(&self) -> usize {
        self.f_halfedge.len()
    }

    /// Corners (min, max) of the vertices' bounding box; (+∞, −∞) without vertices. The mesh
    /// sits below `geometry` in the layers, so it keeps this one fold instead of using `Aabb`.
    pub fn bounds(&self) -> (DVec3, DVec3) {
        self.positions.iter().fold(
            (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY)),
            |(lo, hi), p| (lo.min(*p), hi.max(*p)),
        )
    }

    /// Vertex positions.
    pub fn positions(&self) -> &[DVec3] {
        &self.positions
    }
    /// Mutable vertex positions (connectivity stays as it is).
    pub fn positions_mut(&mut self) -> &mut [DVec3] {
        &mut self.positions
    }
    /// Position of vertex `v`.
    #[inline]
    pub fn position(&self, v: u32) -> DVec3 {
        self.positions[v as usize]
    }

    /// Vertex the halfedge points to.
    #[inline]
    pub fn to(&self, h: u32) -> u32 {
        self.h_to[h as usize]
    }
    /// Vertex the halfedge starts from.
    #[inline]
    pub fn from(&self, h: u32) -> u32 {
        self.h_to[(h ^ 1) as usize]
    }
    /// The paired halfedge of the same edge.
    #[inline]
    pub fn opposite(h: u32) -> u32 {
        h ^ 1
    }
    /// The edge a halfedge belongs to.
    #[inline]
    pub fn edge(h: u32) -> u32 {
        h >> 1
    }
    /// Next halfedge around the face (or along the boundary loop).
    #[inline]
    pub fn next(&self, h: u32) -> u32 {
        self.h_next[h as usize]
    }
    /// Previous halfedge around the face.
    #[inline]
    pub fn prev(&self, h: u32) -> u32 {
        self.h_prev[h as usize]
    }
    /// Face left of `h`, or `INVALID` for a boundary halfedge.
    #[inline]
    pub fn face(&self, h: u32) -> u32 {
        self.h_face[h as usize]
    }
    /// One outgoing halfedge of `v` (`INVALID` if isolated).
    #[inline]
    pub fn vertex_halfedge(&self, v: u32) -> u32 {
        self.v_halfedge[v as usize]
    }
    /// One halfedge of face `f`.
    #[inline]
    pub fn face_halfedge(&self, f: u32) -> u32 {
        self.f_halfedge[f as usize]
    }
    /// The next outgoing halfedge of the same vertex, rotating counter-clockwise.
    #[inline]
    pub fn ccw_rotated(&self, h: u32) -> u32 {
        self.prev(h) ^ 1
    }
    /// True for a halfedge without a face.
    #[inline]
    pub fn is_boundary_halfedge(&self, h: u32) -> bool {
        self.h_face[h as usize] == INVALID
    }

    /// The three vertices of face `f`, in its orientation.
    #[inline]
    pub fn face_vertices(&self, f: u32) -> [u32; 3] {
        let h = self.f_halfedge[f as usize];
        let n = self.next(h);
        [self.from(h), self.to(h), self.to(n)]
    }

    /// Outgoing halfedges of `v` in counter-clockwise order (empty for an isolated vertex).
    ///
    /// Bounded by the halfedge count, so a corrupt mesh cannot make it loop forever.
    pub fn outgoing(&self, v: u32) -> impl Iterator<Item = u32> + '_ {
        let start = self.v_halfedge[v as usize];
        let mut h = start;
        let mut left = if start == INVALID { 0 } else { self.h_to.len() };
        std::iter::from_fn(move || {
            if left == 0 {
                return None;
            }
            let out = h;
            h = self.ccw_rotated(h);
            left = if h == start { 0 } else { left - 1 };
            Some(out)
        })
    }

    /// Neighbouring vertices of `v` in counter-clockwise order (the one-ring).
    pub fn neighbors(&self, v: u32) -> impl Iterator<Item = u32> + '_ {
        self.outgoing(v).map(|h| self.to(h))
    }

    /// `seeds` and every vertex within `rings` edges of one, sorted, each once.
    pub fn rings_around(&self, seeds: &[u32], rings: usize) -> Vec<u32> {
        let mut set = seeds.to_vec();
        set.sort_unstable();
        set.dedup();
        for _ in 0..rings {
            let grown: Vec<u32> = set.iter().flat_map(|&v| self.neighbors(v)).collect();
            set.extend(grown);
            set.sort_unstable();
            set.dedup();
        }
        set
    }

    /// Number of edges at `v`.
    pub fn valence(&self, v: u32) -> usize {
        self.outgoing(v).count()
    }

    /// Mean length of the edges at `v` (0 for an isolated vertex): the local mesh scale.
    pub fn mean_edge_length(&self, v: u32) -> f64 {
        let p = self.position(v);
        let (mut sum, mut n) = (0.0, 0usize);
        for u in self.neighbors(v) {
            sum += (self.position(u) - p).length();
            n += 1;
        }
        if n == 0 {
            0.0
        } else {
            sum / n as f64
        }
    }

    /// Indexed triangles, one per face, in face order.
    pub fn triangles(&self) -> Vec<[u32; 3]> {
        (0..self.n_faces() as u32)
            .map(|f| self.face_vertices(f))
            .collect()
    }

    /// Unit normal and area of face `f` (zero normal for a degenerate face).
    pub fn face_normal_area(&self, f: u32) -> (DVec3, f64) {
        let [a, b, c] = self.face_vertices(f).map(|v| self.position(v));
        let n = (b - a).cross(c - a);
        let len = n.length();
        let normal = if len > 0.0 { n / len } else { DVec3::ZERO };
        (normal, 0.5 * len)
    }

    /// Total surface area.
    pub fn surface_area(&self) -> f64 {
        // (Twice a step in the divergence guard: the faces on both cores, summed in order.)
        crate::parallel::map(self.n_faces(), |f| self.face_normal_area(f as u32).1)
            .into_iter()
            .sum()
    }

    /// Signed enclosed volume (positive for a closed, outward-oriented surface).
    pub fn signed_volume(&self) -> f64 {
        (0..self.n_faces() as u32)
            .map(|f| {
                let [a, b, c] = self.face_vertices(f).map(|v| self.position(v));
                a.dot(b.cross(c)) / 6.0
            })
            .sum()
    }

    /// Adds (or resets) a named per-vertex scalar layer filled with `value`.
    pub fn set_vertex_scalar_layer(&mut self, name: &str, value: f64) {
        let n = self.n_vertices();
        match self.vertex_scalars.iter_mut().find(|(k, _)| k == name) {
            Some((_, vals)) => {
                vals.clear();
                vals.resize(n, value);
            }
            None => self.vertex_scalars.push((name.to_owned(), vec![value; n])),
        }
    }
    /// Drops a named per-vertex scalar layer (nothing if absent).
    pub fn remove_vertex_scalar_layer(&mut self, name: &str) {
        self.vertex_scalars.retain(|(k, _)| k != name);
    }
    /// A named per-vertex scalar layer, if present.
    pub fn vertex_scalars(&self, name: &str) -> Option<&[f64]> {
        self.vertex_scalars
            .iter()
            .find(|(k, _)| k == name)
            .map(|(_, v)| v.as_slice())
    }
    /// A named per-vertex scalar layer, mutable, if present.
    pub fn vertex_scalars_mut(&mut self, name: &str) -> Option<&mut [f64]> {
        self.vertex_scalars
            .iter_mut()
            .find(|(k, _)| k == name)
            .map(|(_, v)| v.as_mut_slice())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn tetra() -> HalfedgeMesh {
        let p = vec![DVec3::ZERO, DVec3::X, DVec3::Y, DVec3::Z];
        HalfedgeMesh::from_triangles(p, &[[0, 2, 1], [0, 1, 3], [1, 2, 3], [0, 3, 2]]).unwrap()
    }

    #[test]
    fn tetrahedron_connectivity() {
        let m = tetra();
        assert_eq!((m.n_vertices(), m.n_edges(), m.n_faces()), (4, 6, 4));
        for v in 0..4 {
            let mut ring: Vec<u32> = m.neighbors(v).collect();
            ring.sort();
            let expect: Vec<u32> = (0..4).filter(|&u| u != v).collect();
            assert_eq!(ring, expect);
        }
        assert!((m.signed_volume() - 1.0 / 6.0).abs() < 1e-15);
    }

    #[test]
    fn rejects_bad_input() {
        let p = vec![DVec3::ZERO, DVec3::X, DVec3::Y, DVec3::Z];
        assert!(matches!(
            HalfedgeMesh::from_triangles(p.clone(), &[[0, 1, 4]]),
            Err(MeshBuildError::IndexOutOfRange { vertex: 4, .. })
        ));
        assert!(matches!(
            HalfedgeMesh::from_triangles(p.clone(), &[[0, 1, 1]]),
            Err(MeshBuildError::RepeatedVertex { .. })
        ));
        // Same orientation twice: inconsistent neighbours.
        assert!(matches!(
            HalfedgeMesh::from_triangles(p.clone(), &[[0, 1, 2], [0, 1, 3]]),
            Err(MeshBuildError::NonManifoldEdge { from: 0, to: 1, .. })
        ));
        // Bow-tie: two triangles sharing only vertex 0.
        let p5 = vec![DVec3::ZERO, DVec3::X, DVec3::Y, -DVec3::X, -DVec3::Y];
        assert!(matches!(
            HalfedgeMesh::from_triangles(p5, &[[0, 1, 2], [0, 3, 4]]),
            Err(MeshBuildError::NonManifoldVertex { vertex: 0 })
        ));
    }

    #[test]
    fn open_patch_has_boundary_loop() {
        let p = vec![DVec3::ZERO, DVec3::X, DVec3::Y, DVec3::new(1.0, 1.0, 0.0)];
        let m = HalfedgeMesh::from_triangles(p, &[[0, 1, 2], [1, 3, 2]]).unwrap();
        let bh: Vec<u32> = (0..m.n_halfedges() as u32)
            .filter(|&h| m.is_boundary_halfedge(h))
            .collect();
        assert_eq!(bh.len(), 4);
        // Walking `next` along the boundary returns to the start after 4 steps.
        let mut h = bh[0];
        for _ in 0..4 {
            assert!(m.is_boundary_halfedge(h));
            h = m.next(h);
        }
        assert_eq!(h, bh[0]);
        assert_eq!(m.valence(1), 3);
    }
}
