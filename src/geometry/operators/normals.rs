//! Angle-weighted vertex normals (Thürmer & Wüthrich): the normal used by the LSW advection
//! term (docs/method.md §6.1 step 1) and by the viewer's shading.

use crate::geometry::angle::corner_angle;
use crate::mesh::HalfedgeMesh;
use glam::DVec3;

/// Unit vertex normals: the sum of incident face normals weighted by the face's corner angle at
/// the vertex, normalised. Insensitive to how the one-ring is triangulated, unlike area weights.
/// A vertex whose faces are all degenerate gets the zero vector.
pub fn angle_weighted_normals(mesh: &HalfedgeMesh) -> Vec<DVec3> {
    let mut normals = vec![DVec3::ZERO; mesh.n_vertices()];
    // Each face's three weighted normals on both cores, added up in face order (the same sums).
    let faces = crate::parallel::map(mesh.n_faces(), |f| {
        let vs = mesh.face_vertices(f as u32);
        let ps = vs.map(|v| mesh.position(v));
        let n = (ps[1] - ps[0]).cross(ps[2] - ps[0]);
        let len = n.length();
        (len > 0.0).then(|| {
            let n = n / len;
            let weighted = [0, 1, 2].map(|k| {
                let (a, b) = (ps[(k + 1) % 3] - ps[k], ps[(k + 2) % 3] - ps[k]);
                // Not glam's `angle_between`: its `acos` is the platform's (see `crate::fmath`).
                let angle = corner_angle(a.cross(b).length(), a.dot(b));
                angle.is_finite().then(|| angle * n)
            });
            (vs, weighted)
        })
    });
    for (vs, weighted) in faces.into_iter().flatten() {
        for (v, w) in vs.into_iter().zip(weighted) {
            if let Some(w) = w {
                normals[v as usize] += w;
            }
        }
    }
    for n in &mut normals {
        *n = n.normalize_or_zero();
    }
    normals
}

/// Unit area-weighted normal of vertex `v` alone (the sum of its faces' cross products; boundary
/// sides skipped), for edits that need one vertex's normal while the mesh changes under them.
pub fn area_weighted_normal(mesh: &HalfedgeMesh, v: u32) -> DVec3 {
    let x = mesh.position(v);
    let mut n = DVec3::ZERO;
    for h in mesh.outgoing(v) {
        if !mesh.is_boundary_halfedge(h) {
            let (a, b) = (
                mesh.position(mesh.to(h)),
                mesh.position(mesh.to(mesh.next(h))),
            );
            n += (a - x).cross(b - x);
        }
    }
    n.normalize_or_zero()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::icosphere::icosphere;

    #[test]
    fn one_vertex_area_normal_is_radial_on_a_sphere() {
        let m = icosphere(2, 1.0, DVec3::ZERO).unwrap();
        for v in 0..m.n_vertices() as u32 {
            let n = area_weighted_normal(&m, v);
            assert!(n.dot(m.position(v).normalize()) > 0.999, "{v}: {n:?}");
        }
    }

    #[test]
    fn sphere_normals_are_radial() {
        let m = icosphere(3, 2.0, DVec3::new(1.0, 0.0, 0.0)).unwrap();
        for (n, p) in angle_weighted_normals(&m).iter().zip(m.positions()) {
            let radial = (*p - DVec3::new(1.0, 0.0, 0.0)).normalize();
            assert!(n.dot(radial) > 0.999, "{n:?} vs {radial:?}");
        }
    }

    #[test]
    fn cube_corner_normal_is_the_diagonal() {
        // Angle weighting makes the corner normal of a cube the diagonal, however its faces are cut.
        let p = vec![
            DVec3::new(0., 0., 0.),
            DVec3::new(1., 0., 0.),
            DVec3::new(1., 1., 0.),
            DVec3::new(0., 1., 0.),
            DVec3::new(0., 0., 1.),
            DVec3::new(1., 0., 1.),
            DVec3::new(1., 1., 1.),
            DVec3::new(0., 1., 1.),
        ];
        let f = [
            [0, 2, 1],
            [0, 3, 2],
            [4, 5, 6],
            [4, 6, 7],
            [0, 1, 5],
            [0, 5, 4],
            [1, 2, 6],
            [1, 6, 5],
            [2, 3, 7],
            [2, 7, 6],
            [3, 0, 4],
            [3, 4, 7],
        ];
        let m = HalfedgeMesh::from_triangles(p, &f).unwrap();
        m.validate().unwrap();
        let n = angle_weighted_normals(&m);
        assert!(
            (n[6] - DVec3::ONE.normalize()).length() < 1e-12,
            "{:?}",
            n[6]
        );
        assert!(
            (n[0] + DVec3::ONE.normalize()).length() < 1e-12,
            "{:?}",
            n[0]
        );
    }
}
