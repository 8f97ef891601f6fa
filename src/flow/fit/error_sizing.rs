//! Error-adaptive sizing for the final fit on mesh targets: where the target is still
//! far from the fitted wrap — an eye socket, a mouth, the valley where a fin meets a body, all
//! bridged — the wrap's edges there are made shorter, so the next fit pass has vertices to put
//! into it.
//!
//! The curvature sizing only sees the wrap's own curvature, which is low exactly where the wrap
//! bridges a concavity. The miss is judged from the target's side instead (the direction of
//! the Hausdorff distance that the bridging hides): each target sample farther than the
//! tolerance from the wrap caps the edge length at the wrap face nearest to it. A hole in a scan
//! has no samples, so a wrap spanning it is left coarse.

use crate::geometry::creases::Creases;
use crate::geometry::spatial::bvh::TriangleBvh;
use crate::mesh::HalfedgeMesh;
use crate::metrics::creases::crease_errors;
use glam::DVec3;

/// Per-vertex caps on the remesher's target edge length (`f64::INFINITY`: no cap), and the
/// indices of the `samples` that missed; None when none did.
///
/// `samples` are target points (a mesh's vertices), `check` the indices to test (all of them at
/// first; a later pass can test only the previous misses). A sample farther than `tol` from the
/// wrap caps the three vertices of the nearest wrap face at half its longest edge. Caps never go
/// below `floor` (the finest edge the settings allow); a face already that fine counts as no
/// miss, so the refinement stops there. `wrap` is the tree over `mesh`'s faces ([`wrap_faces`]).
pub fn error_caps(
    mesh: &HalfedgeMesh,
    wrap: &TriangleBvh,
    samples: &[DVec3],
    check: &[u32],
    tol: f64,
    floor: f64,
) -> Option<(Vec<f64>, Vec<u32>)> {
    let tris = wrap.triangles();
    let half_longest = |f: u32| {
        let [a, b, c] = tris[f as usize].map(|v| mesh.position(v));
        0.5 * (b - a).length().max((c - b).length()).max((a - c).length())
    };
    let hits =
        wrap.closest_points_within(check.len(), |i| samples[check[i] as usize], f64::INFINITY);
    let nearest: Vec<Option<u32>> = crate::parallel::map(check.len(), |i| {
        let hit = hits[i].as_ref()?;
        let f = hit.triangle;
        (hit.distance_squared > tol * tol && half_longest(f) >= floor).then_some(f)
    });
    let mut caps = vec![f64::INFINITY; mesh.n_vertices()];
    let mut missed = Vec::new();
    for (i, f) in nearest.iter().enumerate() {
        if let Some(f) = *f {
            let l = half_longest(f).max(floor);
            for v in tris[f as usize] {
                caps[v as usize] = caps[v as usize].min(l);
            }
            missed.push(check[i]);
        }
    }
    (!missed.is_empty()).then_some((caps, missed))
}

/// A crease whose dihedral angle the wrap misses by more than this many degrees is refined
/// by [`crease_caps`] (the faces of a coarse wrap beside a crease lean, and its crease vertices
/// then slide off). A tighter or looser tolerance keeps fewer creases sharp (see
/// docs/decisions/).
pub const BEVEL_TOL_DEG: f64 = 2.0;

/// Per-vertex caps (as [`error_caps`]) where the wrap still bevels a sharp crease of the target:
/// the wrap's dihedral angle read `offset` beside a crease edge (the measure of
/// [`crate::metrics::creases`]) is off the target's by more than `tol` radians. Both wrap faces
/// read there are capped at half their longest edge, not below `floor`; None when no crease is
/// bevelled.
///
/// A wrap face that stands for several of the target's narrow facets beside a crease (a hole's
/// faceted wall under its rim) is a chord whose normal leans away from the wall's, while the
/// wall lies off it by less than the distance [`error_caps`] would notice: only the angle
/// shows the bevel.
pub fn crease_caps(
    mesh: &HalfedgeMesh,
    wrap: &TriangleBvh,
    creases: &Creases,
    offset: f64,
    tol: f64,
    floor: f64,
) -> Option<Vec<f64>> {
    let tris = wrap.triangles();
    let half_longest = |f: u32| {
        let [a, b, c] = tris[f as usize].map(|v| mesh.position(v));
        0.5 * (b - a).length().max((c - b).length()).max((a - c).length())
    };
    let mut caps = vec![f64::INFINITY; mesh.n_vertices()];
    let mut any = false;
    for e in crease_errors(mesh.positions(), tris, wrap, creases, offset) {
        if e.error <= tol {
            continue;
        }
        for f in e.faces.into_iter().flatten() {
            let l = half_longest(f);
            if l >= floor {
                for v in tris[f as usize] {
                    caps[v as usize] = caps[v as usize].min(l);
                }
                any = true;
            }
        }
    }
    any.then_some(caps)
}

/// The tree over a wrap's faces that [`error_caps`] and [`crease_caps`] read (one per pass).
pub fn wrap_faces(mesh: &HalfedgeMesh) -> TriangleBvh {
    TriangleBvh::new(mesh.positions(), &mesh.triangles())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::icosphere::icosphere;

    /// A coarse icosahedron inscribed in a fine sphere: the sphere's points over the middle of
    /// each face miss it by up to the inradius gap, so every face near them is capped at half
    /// its edge; a tolerance above the largest gap, or a floor above half an edge, caps nothing.
    #[test]
    fn caps_follow_the_missed_target_samples() {
        let coarse = icosphere(0, 1.0, DVec3::ZERO).unwrap();
        let tree = wrap_faces(&coarse);
        let fine = icosphere(4, 1.0, DVec3::ZERO).unwrap();
        let samples = fine.positions().to_vec();
        let all: Vec<u32> = (0..samples.len() as u32).collect();
        let edge = (coarse.position(coarse.to(0)) - coarse.position(coarse.to(1))).length();
        // The icosahedron's inradius: the farthest a sphere point lies from it is 1 − r_in.
        let gap = 1.0 - 0.794_654_472_291_766;
        let (caps, missed) = error_caps(&coarse, &tree, &samples, &all, 0.5 * gap, 0.0).unwrap();
        assert!(!missed.is_empty() && missed.len() < samples.len());
        for c in caps {
            assert!((c - 0.5 * edge).abs() < 1e-9, "{c} vs {}", 0.5 * edge);
        }
        // Only the misses are rechecked, with the same answer.
        let (_, again) = error_caps(&coarse, &tree, &samples, &missed, 0.5 * gap, 0.0).unwrap();
        assert_eq!(again, missed);
        assert!(error_caps(&coarse, &tree, &samples, &all, 1.01 * gap, 0.0).is_none());
        assert!(error_caps(&coarse, &tree, &samples, &all, 0.5 * gap, 0.6 * edge).is_none());
        // The floor bounds every cap from below.
        let (caps, _) = error_caps(&coarse, &tree, &samples, &all, 0.5 * gap, 0.45 * edge).unwrap();
        assert!(caps.iter().all(|&c| c >= 0.45 * edge));
    }

    /// A cube's own mesh reproduces its creases: no caps. A ball in its place reads nearly the
    /// same normal on both sides of each edge (a 90° error): its faces there are capped at half
    /// their longest edge, and a floor above that caps nothing.
    #[test]
    fn caps_follow_the_bevelled_creases() {
        use crate::geometry::creases::detect_creases;
        let (p, t) = crate::demo::shapes::generate("cube").unwrap();
        let creases = detect_creases(&p, &t, 40f64.to_radians());
        let cube = HalfedgeMesh::from_triangles(p.clone(), &t).unwrap();
        let tol = BEVEL_TOL_DEG.to_radians();
        assert!(crease_caps(&cube, &wrap_faces(&cube), &creases, 0.005, tol, 0.0).is_none());
        let ball = icosphere(2, 0.7, DVec3::ZERO).unwrap();
        let caps = crease_caps(&ball, &wrap_faces(&ball), &creases, 0.005, tol, 0.0).unwrap();
        let longest = ball
            .triangles()
            .iter()
            .flat_map(|t| [(t[0], t[1]), (t[1], t[2]), (t[2], t[0])])
            .map(|(a, b)| (ball.position(a) - ball.position(b)).length())
            .fold(0.0, f64::max);
        let capped: Vec<f64> = caps.into_iter().filter(|c| c.is_finite()).collect();
        assert!(capped.len() > 10, "{}", capped.len());
        assert!(capped.iter().all(|&c| c <= 0.5 * longest + 1e-12));
        assert!(crease_caps(&ball, &wrap_faces(&ball), &creases, 0.005, tol, longest).is_none());
    }
}
