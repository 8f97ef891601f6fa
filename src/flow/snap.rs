//! Final fit: moves the settled surface from the offset level set d = d₀ onto the target.
//!
//! The evolution stops where the distance field equals d₀ (about one cell out), because a
//! smaller d₀ would let the surface slip between the points of a cloud. Once it has settled,
//! each vertex is moved along its normal onto the target: for a point cloud, onto the plane
//! fitted (weighted PCA) to the points around it — a one-step moving-least-squares projection;
//! for a mesh, onto the closest point of the triangles. Vertices without a clear local surface
//! (too few points, plane nearly parallel to the normal, a move longer than the limit — e.g.
//! where the surface bridges a hole in a scan) stay where they are.

use crate::geometry::spatial::bvh::TriangleBvh;
use crate::mesh::HalfedgeMesh;
use crate::target::Target;
use glam::DVec3;
use nalgebra::{Matrix3, SymmetricEigen};

/// Settings of the final fit, in the stabilised frame's units (the evolver converts cells).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SnapParams {
    /// Neighbourhood radius for the plane fit.
    pub radius: f64,
    /// Longest allowed move of a vertex.
    pub max_move: f64,
    /// Fewest points a plane may be fitted to.
    pub min_points: usize,
}

/// A uniform bucket grid over points for radius queries (counting sort, no hashing).
pub struct PointGrid {
    points: Vec<DVec3>,
    origin: DVec3,
    cell: f64,
    dims: [usize; 3],
    start: Vec<u32>,
    order: Vec<u32>,
}

impl PointGrid {
    /// Buckets `points` into cells of size `cell` (> 0).
    pub fn new(points: &[DVec3], cell: f64) -> Self {
        let bbox = crate::geometry::aabb::Aabb::from_points(points);
        let dims = ((bbox.size() / cell).floor() + DVec3::ONE)
            .to_array()
            .map(|d| (d as usize).clamp(1, 1 << 10));
        let mut g = PointGrid {
            points: points.to_vec(),
            origin: bbox.min,
            cell,
            dims,
            start: vec![0; dims[0] * dims[1] * dims[2] + 1],
            order: vec![0; points.len()],
        };
        let keys: Vec<usize> = points.iter().map(|&p| g.key(g.cell_of(p))).collect();
        for &k in &keys {
            g.start[k + 1] += 1;
        }
        for i in 1..g.start.len() {
            g.start[i] += g.start[i - 1];
        }
        let mut fill = g.start.clone();
        for (i, &k) in keys.iter().enumerate() {
            g.order[fill[k] as usize] = i as u32;
            fill[k] += 1;
        }
        g
    }

    fn cell_of(&self, p: DVec3) -> [usize; 3] {
        let q = ((p - self.origin) / self.cell).floor();
        [0, 1, 2].map(|k| (q[k].max(0.0) as usize).min(self.dims[k] - 1))
    }

    fn key(&self, c: [usize; 3]) -> usize {
        (c[2] * self.dims[1] + c[1]) * self.dims[0] + c[0]
    }

    /// Calls `f(point)` for every point within `radius` of `p` (radius ≤ a few cells).
    pub fn for_each_within(&self, p: DVec3, radius: f64, mut f: impl FnMut(DVec3)) {
        let lo = self.cell_of(p - DVec3::splat(radius));
        let hi = self.cell_of(p + DVec3::splat(radius));
        let r2 = radius * radius;
        for z in lo[2]..=hi[2] {
            for y in lo[1]..=hi[1] {
                for x in lo[0]..=hi[0] {
                    let k = self.key([x, y, z]);
                    for &i in &self.order[self.start[k] as usize..self.start[k + 1] as usize] {
                        let q = self.points[i as usize];
                        if (q - p).length_squared() <= r2 {
                            f(q);
                        }
                    }
                }
            }
        }
    }
}

/// What the target looks like to the fit.
pub enum SnapTarget {
    /// A point cloud, bucketed.
    Points(PointGrid),
    /// A triangle mesh.
    Triangles(TriangleBvh),
}

impl SnapTarget {
    /// The target in the stabilised frame (`phi·(p − center)`): a point grid of cell `radius`
    /// for clouds, a BVH for meshes.
    pub fn new(target: &Target, center: DVec3, phi: f64, radius: f64) -> Self {
        let pts: Vec<DVec3> = target.points.iter().map(|&p| phi * (p - center)).collect();
        if target.triangles.is_empty() {
            SnapTarget::Points(PointGrid::new(&pts, radius))
        } else {
            SnapTarget::Triangles(TriangleBvh::new(&pts, &target.triangles))
        }
    }
}

/// Moves vertices along `normals` onto the target; returns how many moved.
pub fn snap_to_target(
    mesh: &mut HalfedgeMesh,
    normals: &[DVec3],
    target: &SnapTarget,
    params: &SnapParams,
) -> usize {
    let moves: Vec<Option<DVec3>> = mesh
        .positions()
        .iter()
        .zip(normals)
        .map(|(&p, &n)| {
            let t = match target {
                SnapTarget::Points(grid) => plane_offset(grid, p, n, params)?,
                SnapTarget::Triangles(bvh) => {
                    let hit = bvh.closest_point(p)?;
                    let d = hit.point - p;
                    // Move along the normal by the signed distance, if the closest point lies
                    // roughly along the normal (not off to the side of a crease).
                    let t = d.dot(n);
                    if d.length() > 1e-300 && t.abs() < 0.8 * d.length() {
                        return None;
                    }
                    t
                }
            };
            (t.abs() <= params.max_move).then_some(p + t * n)
        })
        .collect();
    let old = mesh.positions().to_vec();
    let mut accept: Vec<bool> = moves.iter().map(|m| m.is_some()).collect();
    // Undo moves that would fold a face (turn its normal by more than 60°): the fit must not
    // create self-intersections where the offset surface bridges a hole or a narrow gap.
    for _ in 0..4 {
        let apply = |i: usize| {
            if accept[i] {
                moves[i].unwrap_or(old[i])
            } else {
                old[i]
            }
        };
        let mut changed = false;
        let mut reject = vec![];
        for f in 0..mesh.n_faces() as u32 {
            let vs = mesh.face_vertices(f);
            if !vs.iter().any(|&v| accept[v as usize]) {
                continue;
            }
            let [a, b, c] = vs.map(|v| old[v as usize]);
            let [a2, b2, c2] = vs.map(|v| apply(v as usize));
            let (n0, n1) = ((b - a).cross(c - a), (b2 - a2).cross(c2 - a2));
            if n0.dot(n1) <= 0.5 * n0.length() * n1.length() {
                reject.extend(vs);
            }
        }
        for v in reject {
            if accept[v as usize] {
                accept[v as usize] = false;
                changed = true;
            }
        }
        if !changed {
            break;
        }
    }
    let mut moved = 0;
    for (i, q) in mesh.positions_mut().iter_mut().enumerate() {
        if accept[i] {
            *q = moves[i].unwrap_or(*q);
            moved += 1;
        }
    }
    moved
}

/// Signed distance along `n` from `p` to the plane fitted to the points near `p`.
///
/// Only the sheet of points nearest along the normal takes part: points more than half the
/// radius deeper than the shallowest one belong to the far side of a thin part (an ear, a
/// fin) and would pull the fit into the middle of it.
fn plane_offset(grid: &PointGrid, p: DVec3, n: DVec3, params: &SnapParams) -> Option<f64> {
    let h2 = (0.5 * params.radius).powi(2);
    let mut near: Vec<(DVec3, f64)> = Vec::with_capacity(32);
    let mut shallowest = f64::INFINITY;
    grid.for_each_within(p, params.radius, |q| {
        let depth = (p - q).dot(n);
        shallowest = shallowest.min(depth);
        near.push((q, depth));
    });
    let keep = shallowest + 0.5 * params.radius;
    let (mut wsum, mut c, mut count) = (0.0, DVec3::ZERO, 0usize);
    for (q, depth) in &mut near {
        let w = if *depth <= keep {
            (-(*q - p).length_squared() / h2).exp()
        } else {
            0.0
        };
        *depth = w;
        if w > 0.0 {
            wsum += w;
            c += w * *q;
            count += 1;
        }
    }
    if count < params.min_points || wsum <= 0.0 {
        return None;
    }
    c /= wsum;
    let mut cov = Matrix3::zeros();
    for (q, w) in &near {
        let d = *q - c;
        let v = nalgebra::Vector3::new(d.x, d.y, d.z);
        cov += *w * v * v.transpose();
    }
    let eig = SymmetricEigen::new(cov);
    let (imin, _) = eig
        .eigenvalues
        .iter()
        .enumerate()
        .fold(
            (0, f64::INFINITY),
            |a, (i, &v)| if v < a.1 { (i, v) } else { a },
        );
    let m = eig.eigenvectors.column(imin);
    let m = DVec3::new(m[0], m[1], m[2]);
    let cos = m.dot(n);
    if cos.abs() < 0.5 {
        return None;
    }
    Some((c - p).dot(m) / cos)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::icosphere::icosphere;

    #[test]
    fn offset_sphere_snaps_onto_sampled_sphere() {
        // Points on the unit sphere; the mesh is the sphere of radius 1.05.
        let pts = crate::geometry::sphere::fibonacci_sphere(20_000);
        let grid = PointGrid::new(&pts, 0.05);
        let mut mesh = icosphere(4, 1.05, DVec3::ZERO).unwrap();
        let normals: Vec<DVec3> = mesh.positions().iter().map(|p| p.normalize()).collect();
        let params = SnapParams {
            radius: 0.1,
            max_move: 0.2,
            min_points: 6,
        };
        let moved = snap_to_target(&mut mesh, &normals, &SnapTarget::Points(grid), &params);
        assert_eq!(moved, mesh.n_vertices());
        let worst = mesh
            .positions()
            .iter()
            .map(|p| (p.length() - 1.0).abs())
            .fold(0.0, f64::max);
        assert!(worst < 2e-3, "worst radial error {worst}");
        // A move longer than the limit is refused.
        let mut far = icosphere(2, 1.5, DVec3::ZERO).unwrap();
        let normals: Vec<DVec3> = far.positions().iter().map(|p| p.normalize()).collect();
        let params = SnapParams {
            radius: 0.1,
            max_move: 0.2,
            min_points: 6,
        };
        assert_eq!(
            snap_to_target(
                &mut far,
                &normals,
                &SnapTarget::Points(PointGrid::new(&pts, 0.05)),
                &params
            ),
            0
        );
    }
}
