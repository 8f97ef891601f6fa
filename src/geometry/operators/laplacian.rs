//! Cotangent Laplace–Beltrami operator over mixed Voronoi co-volumes (Meyer et al. 2003),
//! with the reference's clamping (docs/method.md §6.2).

use crate::mesh::HalfedgeMesh;
use crate::solve::{ScaledRows, SolveError};
use glam::DVec3;

/// Cotangents are clamped to ±19.1, i.e. angles are treated as lying in [3°, 177°], so needle
/// triangles cannot produce huge weights.
pub const COT_CLAMP: f64 = 19.1;

/// The discrete Laplacian of a mesh: per-edge cotangent weights and per-vertex co-volumes.
///
/// For vertex `i`: `(ΔF)_i = (1/A_i) · Σ_j w_ij (F_j − F_i)` with `w_ij = (cot α_ij + cot β_ij)/2`
/// and `A_i` the mixed Voronoi area. `ΔF = −2HN` (mean-curvature normal).
#[derive(Clone, Debug)]
pub struct CotanLaplacian {
    /// Mixed Voronoi area `A_i` per vertex.
    pub covolumes: Vec<f64>,
    /// Symmetric edge weight `w_e = (cot α + cot β)/2` per edge (index = halfedge / 2).
    pub edge_weights: Vec<f64>,
}

/// The clamped cotangents of a face's corners from twice its area `c = |a × b|` and the dot
/// products of each corner's two edge vectors; `None` for a degenerate face.
#[inline]
pub(crate) fn cot_of(c: f64, dots: [f64; 3]) -> Option<[f64; 3]> {
    if c <= f64::MIN_POSITIVE {
        return None;
    }
    let inv = 1.0 / c;
    Some(dots.map(|d| (d * inv).clamp(-COT_CLAMP, COT_CLAMP)))
}

/// Each corner's share of the mixed Voronoi area of a face: the Voronoi part for non-obtuse
/// triangles, else T/2 at the obtuse corner and T/4 at the others. `len2[k]` is the squared
/// length of the edge from corner k to corner k+1.
#[inline]
pub(crate) fn corner_covolumes(cots: [f64; 3], len2: [f64; 3], area: f64) -> [f64; 3] {
    let obtuse = (0..3).find(|&k| cots[k] < 0.0);
    std::array::from_fn(|k| match obtuse {
        Some(o) if o == k => 0.5 * area,
        Some(_) => 0.25 * area,
        None => {
            // |p_k p_l|² opposite corner j, |p_k p_j|² opposite corner l.
            let (j, l) = ((k + 1) % 3, (k + 2) % 3);
            (len2[l] * cots[j] + len2[k] * cots[l]) / 8.0
        }
    })
}

impl CotanLaplacian {
    /// Computes weights and co-volumes from the current positions.
    pub fn new(mesh: &HalfedgeMesh) -> Self {
        let mut covolumes = vec![0.0; mesh.n_vertices()];
        let mut edge_weights = vec![0.0; mesh.n_edges()];
        for f in 0..mesh.n_faces() as u32 {
            let h0 = mesh.face_halfedge(f);
            let hs = [h0, mesh.next(h0), mesh.prev(h0)];
            // Corner k sits at from(hs[k]); the edge opposite corner k is hs[(k+1)%3].
            let vs = hs.map(|h| mesh.from(h));
            let ps = vs.map(|v| mesh.position(v));
            let e = [ps[1] - ps[0], ps[2] - ps[1], ps[0] - ps[2]];
            let c = e[0].cross(-e[2]).length();
            let dots = [-e[0].dot(e[2]), -e[1].dot(e[0]), -e[2].dot(e[1])];
            let Some(cots) = cot_of(c, dots) else {
                continue;
            };
            for k in 0..3 {
                edge_weights[(hs[(k + 1) % 3] >> 1) as usize] += 0.5 * cots[k];
            }
            let shares = corner_covolumes(cots, e.map(|v| v.length_squared()), 0.5 * c);
            for k in 0..3 {
                covolumes[vs[k] as usize] += shares[k];
            }
        }
        Self {
            covolumes,
            edge_weights,
        }
    }

    /// `(ΔF)_i` for every vertex: the mean-curvature normal `−2H·N`.
    pub fn apply(&self, mesh: &HalfedgeMesh, values: &[DVec3]) -> Vec<DVec3> {
        let mut out = vec![DVec3::ZERO; mesh.n_vertices()];
        for e in 0..mesh.n_edges() as u32 {
            let (i, j) = (mesh.to(2 * e + 1), mesh.to(2 * e));
            let w = self.edge_weights[e as usize];
            let d = values[j as usize] - values[i as usize];
            out[i as usize] += w * d;
            out[j as usize] -= w * d;
        }
        for (o, a) in out.iter_mut().zip(&self.covolumes) {
            *o = if *a > 0.0 { *o / *a } else { DVec3::ZERO };
        }
        out
    }

    /// The implicit-diffusion matrix `I + τ·diag(ε)·(−L)`:
    /// `A_ii = 1 + τ ε_i Σ_j w_ij/A_i`, `A_ij = −τ ε_i w_ij/A_i`, in the solver's row-scaled form
    /// (see [`ScaledRows`]; `to_csr()` gives it as a plain matrix).
    ///
    /// `eps = None` means ε ≡ 1 (pure mean-curvature flow); a vertex with `ε_i = 0` or zero
    /// co-volume gets an identity row (it does not diffuse this step). With `clamp_negative`,
    /// negative edge weights (obtuse configurations) are clamped to zero: the matrix is then
    /// strictly diagonally dominant, so the solve always converges; the flow falls back to this
    /// when a solve on a badly shaped mesh fails. Rebuilt from scratch every call, so no stale
    /// entries survive connectivity changes.
    pub fn implicit_system(
        &self,
        mesh: &HalfedgeMesh,
        tau: f64,
        eps: Option<&[f64]>,
        clamp_negative: bool,
    ) -> Result<ScaledRows, SolveError> {
        let n = mesh.n_vertices();
        // Co-volumes are floored at 1 % of their mean: a vertex whose faces have (nearly)
        // collapsed would otherwise get an enormous row (τ/A_i → ∞) and stall the solver, while
        // on any reasonable mesh the floor never binds.
        let floor = 0.01 * self.covolumes.iter().sum::<f64>() / n.max(1) as f64;
        let scale: Vec<f64> = (0..n)
            .map(|i| {
                let e = eps.map_or(1.0, |e| e[i]);
                let a = self.covolumes[i].max(floor);
                if a > 0.0 && e != 0.0 {
                    tau * e / a
                } else {
                    0.0
                }
            })
            .collect();
        // Assembled from a linear pass over the halfedges (one-ring walks chase pointers): count
        // the row lengths, scatter each outgoing halfedge into its row, then divide each row by its
        // diagonal. Row order is halfedge order (deterministic).
        let nh = 2 * mesh.n_edges();
        let mut indptr = vec![0u32; n + 1];
        for h in 0..nh as u32 {
            let i = mesh.from(h) as usize;
            if scale[i] != 0.0 {
                indptr[i + 1] += 1;
            }
        }
        for i in 0..n {
            indptr[i + 1] += indptr[i];
        }
        let nnz = indptr[n] as usize;
        let mut cols = vec![0u32; nnz];
        let mut vals = vec![0.0; nnz];
        let mut fill: Vec<u32> = indptr[..n].to_vec();
        let mut diag = vec![1.0; n];
        for h in 0..nh as u32 {
            let i = mesh.from(h) as usize;
            let sc = scale[i];
            if sc == 0.0 {
                continue;
            }
            let mut w = sc * self.edge_weights[(h >> 1) as usize];
            if clamp_negative {
                w = w.max(0.0);
            }
            let k = fill[i] as usize;
            cols[k] = mesh.to(h);
            vals[k] = -w;
            fill[i] += 1;
            diag[i] += w;
        }
        for (i, d) in diag.iter().enumerate() {
            let inv = 1.0 / d;
            for v in &mut vals[indptr[i] as usize..indptr[i + 1] as usize] {
                *v *= inv;
            }
        }
        ScaledRows::from_parts(diag, indptr, cols, vals)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::icosphere::icosphere;

    /// A flat hexagonal patch with an irregular interior, all in the plane z = 0.5·x − 0.3·y.
    fn flat_patch() -> HalfedgeMesh {
        let ring: Vec<DVec3> = (0..7)
            .map(|k| {
                let a = k as f64 * std::f64::consts::TAU / 7.0 + 0.3 * (k % 2) as f64;
                let r = 1.0 + 0.2 * ((k * 3) % 5) as f64;
                DVec3::new(r * crate::fmath::cos(a), r * crate::fmath::sin(a), 0.0)
            })
            .collect();
        let mut p = vec![DVec3::new(0.1, -0.05, 0.0)];
        p.extend(ring);
        for q in &mut p {
            q.z = 0.5 * q.x - 0.3 * q.y;
        }
        let faces: Vec<[u32; 3]> = (0..7).map(|k| [0, 1 + k, 1 + (k + 1) % 7]).collect();
        HalfedgeMesh::from_triangles(p, &faces).unwrap()
    }

    #[test]
    fn annihilates_linear_functions_on_flat_patch() {
        let m = flat_patch();
        let lap = CotanLaplacian::new(&m);
        // Positions themselves are linear in the plane; so is any linear map of them.
        let f: Vec<DVec3> = m
            .positions()
            .iter()
            .map(|p| DVec3::new(2.0 * p.x - p.y + 3.0, p.z, 7.0))
            .collect();
        let lf = lap.apply(&m, &f);
        assert!(lf[0].length() < 1e-12, "interior vertex: {:?}", lf[0]);
        // A quadratic is not annihilated (guards against a Laplacian that is identically zero).
        let q: Vec<DVec3> = m
            .positions()
            .iter()
            .map(|p| DVec3::splat(p.x * p.x + p.y * p.y))
            .collect();
        assert!(lap.apply(&m, &q)[0].length() > 0.1);
    }

    #[test]
    fn mean_curvature_normal_on_unit_sphere_has_magnitude_two() {
        let m = icosphere(5, 1.0, DVec3::ZERO).unwrap();
        let lap = CotanLaplacian::new(&m);
        let hn = lap.apply(&m, m.positions());
        let mut worst = 0.0f64;
        for (v, p) in hn.iter().zip(m.positions()) {
            worst = worst.max((v.length() - 2.0).abs() / 2.0);
            assert!(v.dot(*p) < 0.0, "ΔF must point inwards");
        }
        assert!(worst < 0.02, "worst relative error {worst}");
        let total: f64 = lap.covolumes.iter().sum();
        assert!(
            (total - m.surface_area()).abs() < 1e-9 * total,
            "co-volumes tile the surface"
        );
    }
}
