//! Error-adaptive sizing for the final fit on mesh targets (issue 15): where the target is still
//! far from the fitted wrap — an eye socket, a mouth, the valley where a fin meets a body, all
//! bridged — the wrap's edges there are made shorter, so the next fit pass has vertices to put
//! into it.
//!
//! The curvature sizing only sees the wrap's own curvature, which is low exactly where the wrap
//! bridges a concavity. The miss is measured from the target's side instead (the direction of
//! the Hausdorff distance that the bridging hides): each target sample farther than the
//! tolerance from the wrap caps the edge length at the wrap face nearest to it. A hole in a scan
//! has no samples, so a wrap spanning it is left coarse.

use crate::geometry::spatial::bvh::TriangleBvh;
use crate::mesh::HalfedgeMesh;
use glam::DVec3;

/// Per-vertex caps on the remesher's target edge length (`f64::INFINITY`: no cap), and the
/// indices of the `samples` that missed; None when none did.
///
/// `samples` are target points (a mesh's vertices), `check` the indices to test (all of them at
/// first; a later pass can test only the previous misses). A sample farther than `tol` from the
/// wrap caps the three vertices of the nearest wrap face at half its longest edge. Caps never go
/// below `floor` (the finest edge the settings allow); a face already that fine counts as no
/// miss, so the refinement stops there.
pub fn error_caps(
    mesh: &HalfedgeMesh,
    samples: &[DVec3],
    check: &[u32],
    tol: f64,
    floor: f64,
) -> Option<(Vec<f64>, Vec<u32>)> {
    let tris = mesh.triangles();
    let wrap = TriangleBvh::new(mesh.positions(), &tris);
    let half_longest = |f: u32| {
        let [a, b, c] = tris[f as usize].map(|v| mesh.position(v));
        0.5 * (b - a).length().max((c - b).length()).max((a - c).length())
    };
    let nearest: Vec<Option<u32>> = crate::parallel::map(check.len(), |i| {
        let p = samples[check[i] as usize];
        // Most samples are on the wrap: a search bounded by the tolerance ends at once.
        if wrap.closest_point_within(p, tol).is_some() {
            return None;
        }
        let f = wrap.closest_point(p)?.triangle;
        (half_longest(f) >= floor).then_some(f)
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
        let fine = icosphere(4, 1.0, DVec3::ZERO).unwrap();
        let samples = fine.positions().to_vec();
        let all: Vec<u32> = (0..samples.len() as u32).collect();
        let edge = (coarse.position(coarse.to(0)) - coarse.position(coarse.to(1))).length();
        // The icosahedron's inradius: the farthest a sphere point lies from it is 1 − r_in.
        let gap = 1.0 - 0.794_654_472_291_766;
        let (caps, missed) = error_caps(&coarse, &samples, &all, 0.5 * gap, 0.0).unwrap();
        assert!(!missed.is_empty() && missed.len() < samples.len());
        for c in caps {
            assert!((c - 0.5 * edge).abs() < 1e-9, "{c} vs {}", 0.5 * edge);
        }
        // Only the misses are rechecked, with the same answer.
        let (_, again) = error_caps(&coarse, &samples, &missed, 0.5 * gap, 0.0).unwrap();
        assert_eq!(again, missed);
        assert!(error_caps(&coarse, &samples, &all, 1.01 * gap, 0.0).is_none());
        assert!(error_caps(&coarse, &samples, &all, 0.5 * gap, 0.6 * edge).is_none());
        // The floor bounds every cap from below.
        let (caps, _) = error_caps(&coarse, &samples, &all, 0.5 * gap, 0.45 * edge).unwrap();
        assert!(caps.iter().all(|&c| c >= 0.45 * edge));
    }
}
