//! How well a mesh reproduces a target's sharp creases: for every crease edge of the target
//! ([`crate::geometry::creases`]), the mesh's dihedral angle there against the target's.
//!
//! The mesh's angle is read just beside the edge: at the points a small `offset` into each of
//! the two target faces (from the edge's midpoint), the mesh face nearest to each point gives
//! a normal, and the angle between those two normals is the mesh's dihedral. A bevel or a
//! rounded edge wider than the offset puts a slanted face nearest and shows as an error of up
//! to half the crease's angle; a crease kept sharp shows as 0.

use crate::geometry::creases::Creases;
use crate::geometry::spatial::bvh::TriangleBvh;
use glam::DVec3;
use serde::Serialize;

/// Default offset beside a crease, as a fraction of the target's diagonal (0.5 %).
pub const CREASE_OFFSET: f64 = 0.005;
/// Default crease angle of the measurement, degrees (the fit's default).
pub const CREASE_ANGLE_DEG: f64 = 40.0;
/// The acceptance bar: a crease is reproduced when its angle is within this many degrees.
pub const CREASE_TOLERANCE_DEG: f64 = 10.0;

/// Summary over the target's crease edges (angles in degrees).
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct CreaseFidelity {
    /// Crease edges of the target.
    pub edges: usize,
    /// Of those, how many the mesh reproduces within [`CREASE_TOLERANCE_DEG`].
    pub within_tolerance: usize,
    /// Mean and largest |mesh dihedral − target dihedral|.
    pub mean_error_deg: f64,
    pub max_error_deg: f64,
    /// Midpoint of the worst edge (target units).
    pub worst_at: [f64; 3],
}

/// The crease fidelity of mesh `(positions, triangles)` to `creases`, read `offset` beside
/// each edge; None when the target has no creases or the mesh no faces.
pub fn crease_fidelity(
    positions: &[DVec3],
    triangles: &[[u32; 3]],
    creases: &Creases,
    offset: f64,
) -> Option<CreaseFidelity> {
    if creases.is_empty() || triangles.is_empty() {
        return None;
    }
    let bvh = TriangleBvh::new(positions, triangles);
    let errors: Vec<(f64, DVec3)> = crease_errors(positions, triangles, &bvh, creases, offset)
        .into_iter()
        .zip(&creases.edges)
        .map(|(e, c)| (e.error.to_degrees(), 0.5 * (c.ends[0] + c.ends[1])))
        .collect();
    let worst = errors
        .iter()
        .copied()
        .max_by(|a, b| a.0.total_cmp(&b.0))
        .unwrap_or((0.0, DVec3::ZERO));
    Some(CreaseFidelity {
        edges: errors.len(),
        within_tolerance: errors
            .iter()
            .filter(|e| e.0 <= CREASE_TOLERANCE_DEG)
            .count(),
        mean_error_deg: errors.iter().map(|e| e.0).sum::<f64>() / errors.len() as f64,
        max_error_deg: worst.0,
        worst_at: worst.1.to_array(),
    })
}

/// How one crease edge of the target is reproduced (see [`crease_errors`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CreaseError {
    /// |mesh dihedral − target dihedral|, radians.
    pub error: f64,
    /// The mesh faces read beside the edge, one per side (None: no face).
    pub faces: [Option<u32>; 2],
}

/// Per crease edge of `creases`, in order: the mesh's dihedral error there, read `offset`
/// beside the edge (see the module's doc) on the mesh `(positions, triangles)` whose tree is
/// `bvh`. (The measure of [`crease_fidelity`], and the final fit's test of where a crease is
/// still bevelled.)
pub fn crease_errors(
    positions: &[DVec3],
    triangles: &[[u32; 3]],
    bvh: &TriangleBvh,
    creases: &Creases,
    offset: f64,
) -> Vec<CreaseError> {
    let face_near = |q: DVec3| {
        let f = bvh.closest_point(q)?.triangle;
        let [a, b, c] = triangles[f as usize].map(|v| positions[v as usize]);
        Some((f, (b - a).cross(c - a).normalize_or_zero()))
    };
    crate::parallel::map(creases.edges.len(), |i| {
        let e = &creases.edges[i];
        let mid = 0.5 * (e.ends[0] + e.ends[1]);
        let side = |k: usize| face_near(mid + offset.min(0.5 * e.heights[k]) * e.inward[k]);
        let (s0, s1) = (side(0), side(1));
        let wrap = match (s0, s1) {
            (Some((_, n0)), Some((_, n1))) => crate::fmath::acos(n0.dot(n1).clamp(-1.0, 1.0)),
            _ => 0.0,
        };
        CreaseError {
            error: (wrap - e.turn).abs(),
            faces: [s0.map(|s| s.0), s1.map(|s| s.0)],
        }
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::demo::shapes::grid_box;
    use crate::geometry::creases::detect_creases;

    #[test]
    fn a_cube_reproduces_itself_and_a_bevelled_cube_does_not() {
        let (p, t) = grid_box(DVec3::ONE, [8, 8, 8]);
        let creases = detect_creases(&p, &t, CREASE_ANGLE_DEG.to_radians());
        let same = crease_fidelity(&p, &t, &creases, 0.01).unwrap();
        assert_eq!((same.edges, same.within_tolerance), (96, 96));
        assert!(same.max_error_deg < 1e-6);
        // Cut every edge by a 45° bevel 0.04 wide: the measurement 0.01 beside the edge lands
        // on the bevel, whose normal is 45° from either face; the mesh's dihedral reads 0.
        let bevel = |q: DVec3| {
            let mut r = q;
            for a in 0..3 {
                let (b, c) = ((a + 1) % 3, (a + 2) % 3);
                let (u, v) = (q[b].abs(), q[c].abs());
                if u > 0.46 && v > 0.46 {
                    // Slide the vertex onto the plane |x_b| + |x_c| = 0.96 along the bisector.
                    let s = 0.5 * (u + v - 0.96);
                    r[b] = q[b].signum() * (u - s);
                    r[c] = q[c].signum() * (v - s);
                }
            }
            r
        };
        let (fine, tf) = grid_box(DVec3::ONE, [50, 50, 50]);
        let bevelled: Vec<DVec3> = fine.iter().map(|&q| bevel(q)).collect();
        let worse = crease_fidelity(&bevelled, &tf, &creases, 0.01).unwrap();
        assert!(worse.within_tolerance < worse.edges / 2, "{worse:?}");
        assert!(worse.max_error_deg > 40.0, "{worse:?}");
    }
}
