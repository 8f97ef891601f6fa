//! `validate()`: the invariants every step and every remesh must keep.

use super::halfedge::{HalfedgeMesh, INVALID};
use serde::Serialize;

/// Counts and topology of a valid closed mesh.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
pub struct MeshReport {
    /// Vertex count V.
    pub vertices: usize,
    /// Edge count E.
    pub edges: usize,
    /// Face count F.
    pub faces: usize,
    /// Euler characteristic V − E + F (2 for a sphere, 0 for a torus).
    pub euler_characteristic: i64,
    /// Genus (2 − χ)/2 of the (connected, closed) surface; summed over components otherwise.
    pub genus: i64,
    /// Number of connected components.
    pub components: usize,
}

impl MeshReport {
    /// The report of a closed surface with these counts.
    pub fn from_counts(vertices: usize, edges: usize, faces: usize, components: usize) -> Self {
        let chi = vertices as i64 - edges as i64 + faces as i64;
        MeshReport {
            vertices,
            edges,
            faces,
            euler_characteristic: chi,
            genus: (2 * components as i64 - chi) / 2,
            components,
        }
    }
}

/// The first broken invariant found by [`HalfedgeMesh::validate`].
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ValidationError {
    /// The mesh has no faces.
    #[error("the mesh has no faces")]
    Empty,
    /// A halfedge without a face: the surface has a hole.
    #[error("the mesh is not closed: halfedge {halfedge} ({from}→{to}) lies on a boundary")]
    Boundary { halfedge: u32, from: u32, to: u32 },
    /// next/prev/opposite links disagree (internal corruption, e.g. after a bad edit).
    #[error("halfedge {halfedge} has inconsistent links: {what}")]
    BrokenLink { halfedge: u32, what: &'static str },
    /// A vertex referenced by no face.
    #[error("vertex {vertex} is isolated (belongs to no face)")]
    IsolatedVertex { vertex: u32 },
    /// A vertex whose faces form more than one fan (two surfaces touching at a point).
    #[error("vertex {vertex} is non-manifold: its one-ring has {ring} of its {total} edges")]
    NonManifoldVertex {
        vertex: u32,
        ring: usize,
        total: usize,
    },
    /// A vertex with a NaN or infinite coordinate.
    #[error("vertex {vertex} has a non-finite position")]
    NonFinite { vertex: u32 },
    /// A face with (numerically) zero area.
    #[error("face {face} is degenerate (area {area:e})")]
    DegenerateFace { face: u32, area: f64 },
}

impl HalfedgeMesh {
    /// Checks that the mesh is a closed, consistently oriented 2-manifold with finite positions
    /// and no degenerate faces, and reports its counts and Euler characteristic.
    ///
    /// Orientation consistency is structural here: each edge has exactly two opposite halfedges.
    /// Degenerate means area ≤ 1e-14 × (bounding-box diagonal)², i.e. relative to the mesh scale.
    pub fn validate(&self) -> Result<MeshReport, ValidationError> {
        if self.n_faces() == 0 {
            return Err(ValidationError::Empty);
        }
        for (v, p) in self.positions.iter().enumerate() {
            if !p.is_finite() {
                return Err(ValidationError::NonFinite { vertex: v as u32 });
            }
        }
        let nh = self.n_halfedges() as u32;
        let mut out_count = vec![0usize; self.n_vertices()];
        for h in 0..nh {
            if self.is_boundary_halfedge(h) {
                return Err(ValidationError::Boundary {
                    halfedge: h,
                    from: self.from(h),
                    to: self.to(h),
                });
            }
            let (n, p) = (self.next(h), self.prev(h));
            if n == INVALID || p == INVALID || self.prev(n) != h || self.next(p) != h {
                return Err(ValidationError::BrokenLink {
                    halfedge: h,
                    what: "next/prev",
                });
            }
            if self.to(p) != self.from(h) {
                return Err(ValidationError::BrokenLink {
                    halfedge: h,
                    what: "prev does not end where h starts",
                });
            }
            if self.face(n) != self.face(h) || self.next(self.next(n)) != h {
                return Err(ValidationError::BrokenLink {
                    halfedge: h,
                    what: "face is not a triangle",
                });
            }
            out_count[self.from(h) as usize] += 1;
        }
        for f in 0..self.n_faces() as u32 {
            let h = self.face_halfedge(f);
            if self.face(h) != f {
                return Err(ValidationError::BrokenLink {
                    halfedge: h,
                    what: "face halfedge",
                });
            }
        }
        for v in 0..self.n_vertices() as u32 {
            let h = self.vertex_halfedge(v);
            if h == INVALID || out_count[v as usize] == 0 {
                return Err(ValidationError::IsolatedVertex { vertex: v });
            }
            if self.from(h) != v {
                return Err(ValidationError::BrokenLink {
                    halfedge: h,
                    what: "vertex halfedge",
                });
            }
            let ring = self.outgoing(v).count();
            if ring != out_count[v as usize] {
                return Err(ValidationError::NonManifoldVertex {
                    vertex: v,
                    ring,
                    total: out_count[v as usize],
                });
            }
        }
        let (lo, hi) = self.bounds();
        let min_area = 1e-14 * (hi - lo).length_squared();
        for f in 0..self.n_faces() as u32 {
            let (_, area) = self.face_normal_area(f);
            if area.is_nan() || area <= min_area {
                return Err(ValidationError::DegenerateFace { face: f, area });
            }
        }
        Ok(self.topology())
    }

    /// The counts, Euler characteristic, genus and components from the connectivity alone
    /// (what [`Self::validate`] reports once the geometry passed; also for a closed mesh with a
    /// degenerate face, such as an iso-surface).
    pub fn topology(&self) -> MeshReport {
        let components = self.count_components();
        MeshReport::from_counts(
            self.n_vertices(),
            self.n_edges(),
            self.n_faces(),
            components,
        )
    }

    /// Connected components over edges (see [`crate::mesh::soup::count_components`]).
    pub fn count_components(&self) -> usize {
        let edges = (0..self.n_edges() as u32).map(|e| (self.to(2 * e), self.to(2 * e + 1)));
        super::soup::count_components(self.n_vertices(), edges)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::DVec3;

    fn tetra_points() -> Vec<DVec3> {
        vec![DVec3::ZERO, DVec3::X, DVec3::Y, DVec3::Z]
    }
    const TETRA: [[u32; 3]; 4] = [[0, 2, 1], [0, 1, 3], [1, 2, 3], [0, 3, 2]];

    #[test]
    fn closed_tetrahedron_is_valid_sphere() {
        let m = HalfedgeMesh::from_triangles(tetra_points(), &TETRA).unwrap();
        let r = m.validate().unwrap();
        assert_eq!(r.euler_characteristic, 2);
        assert_eq!(r.genus, 0);
        assert_eq!(r.components, 1);
    }

    #[test]
    fn detects_hole_nan_degenerate_isolated() {
        let m = HalfedgeMesh::from_triangles(tetra_points(), &TETRA[..3]).unwrap();
        assert!(matches!(
            m.validate(),
            Err(ValidationError::Boundary { .. })
        ));

        let mut m = HalfedgeMesh::from_triangles(tetra_points(), &TETRA).unwrap();
        m.positions_mut()[2].x = f64::NAN;
        assert_eq!(m.validate(), Err(ValidationError::NonFinite { vertex: 2 }));

        let mut m = HalfedgeMesh::from_triangles(tetra_points(), &TETRA).unwrap();
        m.positions_mut()[3] = DVec3::new(0.5, 0.5, 0.0); // flattens the tetrahedron's faces onto z=0
        m.positions_mut()[3] = DVec3::new(1.0, 0.0, 0.0) * 0.5; // on edge 0-1 → faces 1 degenerate
        assert!(matches!(
            m.validate(),
            Err(ValidationError::DegenerateFace { .. })
        ));

        let mut p = tetra_points();
        p.push(DVec3::ONE);
        let m = HalfedgeMesh::from_triangles(p, &TETRA).unwrap();
        assert_eq!(
            m.validate(),
            Err(ValidationError::IsolatedVertex { vertex: 4 })
        );
    }

    #[test]
    fn detects_pinched_vertex() {
        // Two tetrahedra sharing only vertex 0: closed, but vertex 0 has two fans.
        let mut p = tetra_points();
        p.extend([-DVec3::X, -DVec3::Y, -DVec3::Z]);
        let mut faces = TETRA.to_vec();
        faces.extend([[0, 5, 4], [0, 4, 6], [4, 5, 6], [0, 6, 5]]);
        let m = HalfedgeMesh::from_triangles(p, &faces).unwrap();
        assert!(matches!(
            m.validate(),
            Err(ValidationError::NonManifoldVertex { vertex: 0, .. })
        ));
    }
}
