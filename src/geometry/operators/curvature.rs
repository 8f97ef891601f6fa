//! Principal curvatures from the edge-based curvature tensor (Cohen-Steiner & Morvan; PMP's
//! `Curvature::analyze_tensor`, docs/method.md §8.1), shared by the sizing field and the feature
//! detector so one remesh call computes it once.

// `!(x > y)` is used deliberately: it is also true when x is NaN.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

use crate::geometry::operators::laplacian::CotanLaplacian;
use crate::mesh::{HalfedgeMesh, INVALID};
use glam::DVec3;

/// Per-vertex principal curvatures (convex → positive) and the quantities they were built from.
#[derive(Clone, Debug, Default)]
pub struct Curvatures {
    /// Smaller principal curvature κ_min per vertex (1/length).
    pub kmin: Vec<f64>,
    /// Larger principal curvature κ_max per vertex (1/length).
    pub kmax: Vec<f64>,
    /// Signed dihedral angle β per edge (radians, convex → positive, 0 on the boundary).
    pub dihedral: Vec<f64>,
    /// Clamped-to-non-negative cotangent weight per edge (for smoothing passes).
    pub cotan: Vec<f64>,
    /// Unit area-weighted vertex normals.
    pub normals: Vec<DVec3>,
}

/// Unit face normals (zero for a degenerate face).
pub fn face_normals(mesh: &HalfedgeMesh, out: &mut Vec<DVec3>) {
    out.clear();
    out.extend((0..mesh.n_faces() as u32).map(|f| mesh.face_normal_area(f).0));
}

/// Unit area-weighted vertex normals (`Σ` of the incident faces' cross products, normalised).
/// Deleted faces are skipped; vertices without faces get a zero normal.
pub fn vertex_normals(mesh: &HalfedgeMesh, out: &mut Vec<DVec3>) {
    out.clear();
    out.resize(mesh.n_vertices(), DVec3::ZERO);
    for f in 0..mesh.n_faces() as u32 {
        if mesh.is_deleted_face(f) {
            continue;
        }
        let vs = mesh.face_vertices(f);
        let [a, b, c] = vs.map(|v| mesh.position(v));
        let n = (b - a).cross(c - a);
        for v in vs {
            out[v as usize] += n;
        }
    }
    for n in out.iter_mut() {
        *n = n.normalize_or_zero();
    }
}

/// Computes κ_min, κ_max per vertex: `T_v = Σ_{edges at v} β_e·(|e|/2)·ê êᵀ / A_v` (A_v the
/// mixed Voronoi co-volume), restricted to the tangent plane of the vertex normal (this drops
/// the near-zero normal eigenvalue exactly instead of guessing it), followed by `smoothing_passes`
/// cotan-weighted neighbour averages that skip vertices with `fixed[v]` (features).
pub fn principal_curvatures(
    mesh: &HalfedgeMesh,
    fixed: Option<&[bool]>,
    smoothing_passes: usize,
) -> Curvatures {
    let nv = mesh.n_vertices();
    let ne = mesh.n_edges();
    // Three independent face passes: the Laplacian beside the two kinds of normals.
    let (lap, (fnormals, normals)) = crate::parallel::beside(
        || CotanLaplacian::new(mesh),
        || {
            let (mut fnormals, mut normals) = (Vec::new(), Vec::new());
            face_normals(mesh, &mut fnormals);
            vertex_normals(mesh, &mut normals);
            (fnormals, normals)
        },
    );

    // Per edge (in parallel natively): its signed dihedral angle and its tensor term, then summed
    // into its ends in edge order (the same sums whatever the thread count).
    let per_edge = crate::parallel::map(ne, |e| {
        let (h0, h1) = (2 * e as u32, 2 * e as u32 + 1);
        let (f0, f1) = (mesh.face(h0), mesh.face(h1));
        if f0 == INVALID || f1 == INVALID {
            return (0.0, None);
        }
        let (n0, n1) = (fnormals[f0 as usize], fnormals[f1 as usize]);
        let (a, b) = (mesh.from(h0), mesh.to(h0));
        let d = mesh.to(mesh.next(h1));
        let (pa, pb) = (mesh.position(a), mesh.position(b));
        let angle = crate::fmath::atan2(n0.cross(n1).length(), n0.dot(n1));
        let convex = (mesh.position(d) - pa).dot(n0) <= 0.0;
        let beta = if convex { angle } else { -angle };
        let ev = pb - pa;
        let len = ev.length();
        if len <= 0.0 {
            return (beta, None);
        }
        let u = ev / len;
        let w = beta * 0.5 * len;
        let m = [
            w * u.x * u.x,
            w * u.x * u.y,
            w * u.x * u.z,
            w * u.y * u.y,
            w * u.y * u.z,
            w * u.z * u.z,
        ];
        (beta, Some((a, b, m)))
    });
    // Symmetric tensor per vertex: xx, xy, xz, yy, yz, zz.
    let mut t = vec![[0.0f64; 6]; nv];
    let mut dihedral = vec![0.0; ne];
    for (e, (beta, term)) in per_edge.into_iter().enumerate() {
        dihedral[e] = beta;
        let Some((a, b, m)) = term else { continue };
        for v in [a, b] {
            let tv = &mut t[v as usize];
            for k in 0..6 {
                tv[k] += m[k];
            }
        }
    }
    let (mut kmin, mut kmax): (Vec<f64>, Vec<f64>) = crate::parallel::map(nv, |v| {
        let area = lap.covolumes[v];
        let n = normals[v];
        if !(area > 0.0) || n == DVec3::ZERO {
            return (0.0, 0.0);
        }
        let (t1, t2) = n.any_orthonormal_pair();
        let tv = &t[v];
        let apply = |x: DVec3| {
            DVec3::new(
                tv[0] * x.x + tv[1] * x.y + tv[2] * x.z,
                tv[1] * x.x + tv[3] * x.y + tv[4] * x.z,
                tv[2] * x.x + tv[4] * x.y + tv[5] * x.z,
            )
        };
        let (tt1, tt2) = (apply(t1), apply(t2));
        let (a11, a12, a22) = (t1.dot(tt1), t1.dot(tt2), t2.dot(tt2));
        let mean = 0.5 * (a11 + a22);
        let r = (0.25 * (a11 - a22) * (a11 - a22) + a12 * a12).sqrt();
        ((mean - r) / area, (mean + r) / area)
    })
    .into_iter()
    .unzip();
    let cotan: Vec<f64> = lap.edge_weights.iter().map(|w| w.max(0.0)).collect();
    for _ in 0..smoothing_passes {
        // Jacobi: every vertex reads the previous values only.
        (kmin, kmax) = crate::parallel::map(nv, |v| {
            let keep = (kmin[v], kmax[v]);
            if fixed.is_some_and(|f| f[v]) {
                return keep;
            }
            let (mut ww, mut smin, mut smax) = (0.0, 0.0, 0.0);
            for h in mesh.outgoing(v as u32) {
                let w = cotan[(h >> 1) as usize];
                let u = mesh.to(h) as usize;
                ww += w;
                smin += w * kmin[u];
                smax += w * kmax[u];
            }
            if ww > 0.0 {
                (smin / ww, smax / ww)
            } else {
                keep
            }
        })
        .into_iter()
        .unzip();
    }
    Curvatures {
        kmin,
        kmax,
        dihedral,
        cotan,
        normals,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::icosphere::icosphere;

    #[test]
    fn sphere_curvature_is_one_over_radius() {
        let r = 2.5;
        let m = icosphere(4, r, DVec3::ZERO).unwrap();
        let c = principal_curvatures(&m, None, 1);
        for v in 0..m.n_vertices() {
            assert!((c.kmin[v] * r - 1.0).abs() < 0.05, "kmin {}", c.kmin[v] * r);
            assert!((c.kmax[v] * r - 1.0).abs() < 0.05, "kmax {}", c.kmax[v] * r);
        }
        assert!(c.dihedral.iter().all(|&b| b > 0.0));
    }

    #[test]
    fn inside_out_sphere_is_concave() {
        let m = icosphere(3, 1.0, DVec3::ZERO).unwrap();
        let flipped: Vec<[u32; 3]> = m.triangles().iter().map(|&[a, b, c]| [a, c, b]).collect();
        let m = HalfedgeMesh::from_triangles(m.positions().to_vec(), &flipped).unwrap();
        let c = principal_curvatures(&m, None, 0);
        assert!(c.kmax.iter().all(|&k| k < -0.9));
    }
}
