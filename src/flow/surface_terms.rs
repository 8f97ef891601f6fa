//! Everything one LSW step needs from the surface's shape — angle-weighted normals, cotangent
//! weights, mixed Voronoi co-volumes and the tangential-redistribution sums — in **one pass over
//! the faces**.
//!
//! The four share every edge vector, length and cross product, and a face loop reads memory in
//! order, whereas the per-vertex one-ring walks of the stand-alone versions chase pointers
//! through the halfedge arrays (on large meshes those walks dominate a step). Each
//! result equals its stand-alone definition — [`angle_weighted_normals`],
//! [`CotanLaplacian::new`], [`tangential_velocity`] — up to rounding; the tests check that.
//!
//! [`angle_weighted_normals`]: crate::geometry::operators::normals::angle_weighted_normals
//! [`tangential_velocity`]: super::tangential::tangential_velocity

use crate::geometry::angle::corner_angle;
use crate::geometry::operators::laplacian::{corner_covolumes, cot_of, CotanLaplacian};
use crate::mesh::HalfedgeMesh;
use glam::DVec3;
use std::f64::consts::PI;

/// The per-step surface quantities of a closed triangle mesh.
#[derive(Clone, Debug)]
pub struct SurfaceTerms {
    /// Unit angle-weighted vertex normals (zero where every incident face is degenerate).
    pub normals: Vec<DVec3>,
    /// Cotangent weights and co-volumes.
    pub laplacian: CotanLaplacian,
    /// Per-vertex sums for the tangential term.
    sums: Vec<VertexSums>,
}

/// What the face pass accumulates per vertex, in one cache line: each corner then updates one
/// line instead of four scattered arrays.
#[derive(Clone, Copy, Debug, Default)]
#[repr(C, align(64))]
struct VertexSums {
    /// Σ angle · face normal.
    normal: DVec3,
    /// `Σ (1 + ê_a·ê_b)(e_a + e_b)` over the vertex's corners, `e_a`, `e_b` the corner's two
    /// spokes. On a closed mesh the corners around a vertex are exactly its consecutive spoke
    /// pairs, so this is the cyclic sum of docs/method.md §6.3.
    tangential: DVec3,
    /// Mixed Voronoi area.
    covolume: f64,
    /// Corners (incident faces): the spoke count `m` on a closed mesh.
    corners: f64,
}

/// Faces from which [`SurfaceTerms::new`] splits its pass between two threads natively.
const PARALLEL_FACES: usize = 4096;

impl SurfaceTerms {
    /// One pass over the faces of `mesh` (which must be free of deleted elements).
    ///
    /// Natively, on larger meshes, two threads share it by owner: one accumulates into the
    /// vertices below the middle index and the edges whose first end lies there, the other into
    /// the rest, each going through the faces in order. Every sum thus receives the same terms
    /// in the same order as in one pass, so the result is bit for bit the same (and the same as
    /// in wasm); only the faces that straddle the two halves are computed twice, few on a mesh
    /// the remesher keeps in spatial order.
    pub fn new(mesh: &HalfedgeMesh) -> Self {
        let nv = mesh.n_vertices();
        let ne = mesh.n_edges();
        let mut sums = vec![VertexSums::default(); nv];
        let mut edge_weights = vec![0.0; ne];
        if cfg!(target_arch = "wasm32") || mesh.n_faces() < PARALLEL_FACES {
            accumulate(mesh, 0, &mut sums, &mut edge_weights);
        } else {
            let mid = nv / 2;
            let (low, high) = sums.split_at_mut(mid);
            let mut high_weights = vec![0.0; ne];
            crate::parallel::beside(
                || accumulate(mesh, mid as u32, high, &mut high_weights),
                || accumulate(mesh, 0, low, &mut edge_weights),
            );
            for (e, w) in edge_weights.iter_mut().enumerate() {
                if mesh.to(2 * e as u32 + 1) as usize >= mid {
                    *w = high_weights[e];
                }
            }
        }
        let normals = sums.iter().map(|s| s.normal.normalize_or_zero()).collect();
        let covolumes = sums.iter().map(|s| s.covolume).collect();
        Self {
            normals,
            laplacian: CotanLaplacian {
                covolumes,
                edge_weights,
            },
            sums,
        }
    }

    /// The tangential velocity `v_T = u − (u·N)N`, `u = (weight/m)·Σ…` of vertex `v` (see
    /// [`super::tangential::tangential_velocity`]); `weight` is ω·ε_v.
    #[inline]
    pub fn tangential(&self, v: usize, weight: f64) -> DVec3 {
        let m = self.sums[v].corners;
        if weight <= 0.0 || m == 0.0 {
            return DVec3::ZERO;
        }
        let u = self.sums[v].tangential * (weight / m);
        let n = self.normals[v];
        u - u.dot(n) * n
    }
}

/// The face pass of [`SurfaceTerms::new`] for the vertices `first..first + sums.len()` (`sums`
/// indexed from `first`) and the edges whose first end (`to(2e + 1)`) is one of them; the other
/// entries of `edge_weights` are left alone.
fn accumulate(mesh: &HalfedgeMesh, first: u32, sums: &mut [VertexSums], edge_weights: &mut [f64]) {
    let end = first + sums.len() as u32;
    let mine = |v: u32| v >= first && v < end;
    for f in 0..mesh.n_faces() as u32 {
        let h0 = mesh.face_halfedge(f);
        let h1 = mesh.next(h0);
        let h2 = mesh.next(h1);
        // Corner k sits at from(hs[k]); the edge opposite corner k is hs[(k+1)%3].
        let hs = [h0, h1, h2];
        let vs = [mesh.to(h2), mesh.to(h0), mesh.to(h1)];
        if !vs.iter().any(|&v| mine(v)) {
            continue;
        }
        let ps = vs.map(|v| mesh.position(v));
        // e[k] runs from corner k to corner k+1.
        let e = [ps[1] - ps[0], ps[2] - ps[1], ps[0] - ps[2]];
        let len2 = e.map(|v| v.length_squared());
        let len = len2.map(f64::sqrt);
        let cross = e[0].cross(-e[2]);
        let c = cross.length();
        // At corner k the spokes are a = e[k] and b = −e[k+2].
        let dots = [-e[0].dot(e[2]), -e[1].dot(e[0]), -e[2].dot(e[1])];
        // 1/(|e_a|·|e_b|) for the corner's spokes = |third edge| / (product of all three),
        // one division per face instead of three.
        let prod = len[0] * len[1] * len[2];
        let inv_prod = if prod > 0.0 { 1.0 / prod } else { 0.0 };
        for k in 0..3 {
            if !mine(vs[k]) {
                continue;
            }
            let (ka, kb) = (k, (k + 2) % 3);
            let inv = if prod > 0.0 {
                len[(k + 1) % 3] * inv_prod
            } else if len[ka] > 0.0 && len[kb] > 0.0 {
                1.0 / (len[ka] * len[kb])
            } else {
                0.0
            };
            let acc = &mut sums[(vs[k] - first) as usize];
            acc.tangential += (1.0 + dots[k] * inv) * (e[ka] - e[kb]);
            acc.corners += 1.0;
        }
        let Some(cots) = cot_of(c, dots) else {
            continue;
        };
        let n = cross * (1.0 / c);
        // Two angles by atan2, the third from the angle sum (clamped against rounding).
        let a0 = corner_angle(c, dots[0]);
        let a1 = corner_angle(c, dots[1]);
        let a2 = (PI - a0 - a1).max(0.0);
        let shares = corner_covolumes(cots, len2, 0.5 * c);
        for (k, a) in [a0, a1, a2].into_iter().enumerate() {
            if mine(vs[k]) {
                let acc = &mut sums[(vs[k] - first) as usize];
                acc.normal += a * n;
                acc.covolume += shares[k];
            }
        }
        for k in 0..3 {
            // The edge opposite corner k runs from corner k+1 to corner k+2; its first end
            // (that of halfedge 2e) is the start of whichever of the two halfedges is even.
            let h = hs[(k + 1) % 3];
            let owner = if h & 1 == 0 {
                vs[(k + 1) % 3]
            } else {
                vs[(k + 2) % 3]
            };
            if mine(owner) {
                edge_weights[(h >> 1) as usize] += 0.5 * cots[k];
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::flow::tangential::tangential_velocity;
    use crate::geometry::icosphere::icosphere;
    use crate::geometry::operators::normals::angle_weighted_normals;

    /// An icosphere with every vertex pushed off the sphere and sideways by a different amount,
    /// so that the faces are irregular, some obtuse.
    fn lumpy() -> HalfedgeMesh {
        let mut m = icosphere(3, 1.0, DVec3::ZERO).unwrap();
        for (i, p) in m.positions_mut().iter_mut().enumerate() {
            let s = crate::fmath::sin(i as f64 * 0.7);
            *p =
                *p * (1.0 + 0.2 * s) + 0.03 * DVec3::new(s, crate::fmath::cos(i as f64 * 1.3), 0.0);
        }
        m
    }

    #[test]
    fn equals_the_stand_alone_definitions() {
        let m = lumpy();
        let t = SurfaceTerms::new(&m);
        let lap = CotanLaplacian::new(&m);
        let normals = angle_weighted_normals(&m);
        let obtuse = lap.edge_weights.iter().filter(|w| **w < 0.0).count();
        assert!(obtuse > 0, "the test mesh should have obtuse pairs");
        for (v, normal) in normals.iter().enumerate() {
            assert!((t.normals[v] - *normal).length() < 1e-12, "normal {v}");
            let a = lap.covolumes[v];
            assert!(
                (t.laplacian.covolumes[v] - a).abs() < 1e-12 * a,
                "co-volume {v}"
            );
            let reference = tangential_velocity(&m, v as u32, *normal, 0.3);
            let scale = reference.length().max(1e-3);
            assert!(
                (t.tangential(v, 0.3) - reference).length() < 1e-12 * scale,
                "v_T {v}"
            );
        }
        for (e, w) in lap.edge_weights.iter().enumerate() {
            assert!(
                (t.laplacian.edge_weights[e] - w).abs() < 1e-12 * w.abs().max(1.0),
                "edge {e}"
            );
        }
        assert_eq!(t.tangential(0, 0.0), DVec3::ZERO);
    }

    #[test]
    fn the_pass_shared_by_owner_is_the_single_pass_bit_for_bit() {
        // Level 5: 20 480 faces, above PARALLEL_FACES; shuffled a little so that many faces
        // straddle the two halves.
        let mut m = icosphere(5, 1.0, DVec3::ZERO).unwrap();
        for (i, p) in m.positions_mut().iter_mut().enumerate() {
            *p *= 1.0 + 0.1 * crate::fmath::sin(i as f64 * 0.37);
        }
        assert!(m.n_faces() >= PARALLEL_FACES);
        let t = SurfaceTerms::new(&m);
        let mut sums = vec![VertexSums::default(); m.n_vertices()];
        let mut weights = vec![0.0; m.n_edges()];
        accumulate(&m, 0, &mut sums, &mut weights);
        let bits = |v: DVec3| v.to_array().map(f64::to_bits);
        for (v, s) in sums.iter().enumerate() {
            assert_eq!(
                bits(t.normals[v]),
                bits(s.normal.normalize_or_zero()),
                "normal {v}"
            );
            assert_eq!(t.laplacian.covolumes[v].to_bits(), s.covolume.to_bits());
            assert_eq!(
                bits(t.sums[v].tangential),
                bits(s.tangential),
                "tangential {v}"
            );
            assert_eq!(t.sums[v].corners, s.corners);
        }
        for (e, w) in weights.iter().enumerate() {
            assert_eq!(
                t.laplacian.edge_weights[e].to_bits(),
                w.to_bits(),
                "edge {e}"
            );
        }
    }

    #[test]
    fn tangential_term_vanishes_at_the_centre_of_a_regular_star() {
        let mut p = vec![DVec3::ZERO];
        p.extend((0..6).map(|k| {
            let a = k as f64 * std::f64::consts::TAU / 6.0;
            DVec3::new(crate::fmath::cos(a), crate::fmath::sin(a), 0.0)
        }));
        let faces: Vec<[u32; 3]> = (0..6).map(|k| [0, 1 + k, 1 + (k + 1) % 6]).collect();
        let star = HalfedgeMesh::from_triangles(p.clone(), &faces).unwrap();
        assert!(SurfaceTerms::new(&star).tangential(0, 1.0).length() < 1e-14);
        // Moving the centre off-centre makes it pull back (towards the narrow wedges' side).
        p[0] = DVec3::new(0.2, 0.0, 0.0);
        let star = HalfedgeMesh::from_triangles(p, &faces).unwrap();
        let v = SurfaceTerms::new(&star).tangential(0, 1.0);
        assert!(v.x < -0.01 && v.z.abs() < 1e-14, "{v:?}");
    }
}
