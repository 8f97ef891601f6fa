//! Target edge lengths: the curvature-adaptive sizing field of one remesh call (docs/method.md §7.3
//! step 4) and the start-size rules and schedule of §7.2 / §6.6.

use crate::geometry::operators::curvature::Curvatures;
use crate::mesh::HalfedgeMesh;
use serde::{Deserialize, Serialize};

/// The three lengths that drive adaptive remeshing, in mesh units.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct EdgeSizes {
    /// Shortest target edge length l_min.
    pub min_edge_length: f64,
    /// Longest target edge length l_max.
    pub max_edge_length: f64,
    /// Approximation error ε_rem: the allowed distance between an edge and the curved surface
    /// it approximates; smaller → shorter edges where the curvature is high.
    pub approx_error: f64,
}

/// Start sizes for an icosphere start surface (docs/method.md §7.2, paper eq. 9):
/// `l_min = λ_min·2·r_φ·sin(2π/10·2^{−s})`, `l_max = 4·l_min`, `ε_rem = 0.25·(l_min + l_max)`.
///
/// `radius` is the (scaled) icosphere radius r_φ, `level` the subdivision level s and
/// `min_edge_multiplier` λ_min (0.14 in the point-cloud experiments).
pub fn icosphere_sizes(min_edge_multiplier: f64, radius: f64, level: u32) -> EdgeSizes {
    let angle = std::f64::consts::TAU / 10.0 * 0.5f64.powi(level as i32);
    let l_min = min_edge_multiplier * 2.0 * radius * crate::fmath::sin(angle);
    from_min_edge(l_min)
}

/// Start sizes for a marching-cubes start surface (docs/method.md §7.2, paper eq. 10):
/// `l_min = √2·c·φ·λ_min`, `l_max = 4·l_min`, `ε_rem = 0.25·(l_min + l_max)`, with `cell_size`
/// the (resampled) grid cell size c, `scale` the stabilisation factor φ and `min_edge_multiplier`
/// λ_min (0.4 in the genus tests).
pub fn isosurface_sizes(min_edge_multiplier: f64, cell_size: f64, scale: f64) -> EdgeSizes {
    from_min_edge(std::f64::consts::SQRT_2 * cell_size * scale * min_edge_multiplier)
}

/// `l_max = 4·l_min`, `ε_rem = 0.25·(l_min + l_max)`: the reference's start relation.
pub fn from_min_edge(l_min: f64) -> EdgeSizes {
    let l_max = 4.0 * l_min;
    EdgeSizes {
        min_edge_length: l_min,
        max_edge_length: l_max,
        approx_error: 0.25 * (l_min + l_max),
    }
}

/// One schedule adjustment (docs/method.md §6.6): `l_min, l_max ← λ_dec·l_min, λ_dec·l_max`,
/// `ε_rem ← 0.1·(l_min + l_max)`. `decay` is λ_dec (0.7 in the reference).
pub fn decayed(sizes: EdgeSizes, decay: f64) -> EdgeSizes {
    let (l_min, l_max) = (decay * sizes.min_edge_length, decay * sizes.max_edge_length);
    EdgeSizes {
        min_edge_length: l_min,
        max_edge_length: l_max,
        approx_error: 0.1 * (l_min + l_max),
    }
}

/// Target edge length for a curvature radius `r` and approximation error `eps` (the chord of a
/// circle of radius r whose sagitta is ε): `h = sqrt(6·ε·r − 3·ε²)` if `ε < r`, else `√3·ε`;
/// then clamped to `[l_min, l_max]`. `r = ∞` (flat) gives `l_max`.
pub fn edge_length_for_radius(r: f64, eps: f64, l_min: f64, l_max: f64) -> f64 {
    let h = if eps < r {
        (6.0 * eps * r - 3.0 * eps * eps).sqrt()
    } else {
        3f64.sqrt() * eps
    };
    if h.is_nan() {
        l_max
    } else {
        h.clamp(l_min, l_max)
    }
}

/// The per-vertex sizing field of one remesh call (PMP's adaptive sizing, docs/method.md §7.3 step
/// 4): `κ = max(|κ_min|, |κ_max|)`, −1 for `fixed` (boundary/feature) vertices, two in-place passes
/// replacing each value by the cotan-weighted mean of its neighbours' positive values, then
/// [`edge_length_for_radius`] with `r = 1/κ`.
pub fn curvature_sizing(
    mesh: &HalfedgeMesh,
    curv: &Curvatures,
    sizes: &EdgeSizes,
    fixed: &[bool],
) -> Vec<f64> {
    let nv = mesh.n_vertices();
    let mut k: Vec<f64> = (0..nv)
        .map(|v| {
            if fixed[v] {
                -1.0
            } else {
                curv.kmin[v].abs().max(curv.kmax[v].abs())
            }
        })
        .collect();
    for _ in 0..2 {
        for v in 0..nv as u32 {
            let (mut ww, mut cc) = (0.0, 0.0);
            for h in mesh.outgoing(v) {
                let c = k[mesh.to(h) as usize];
                if c > 0.0 {
                    let w = curv.cotan[(h >> 1) as usize];
                    ww += w;
                    cc += w * c;
                }
            }
            k[v as usize] = if ww > 0.0 { cc / ww } else { 0.0 };
        }
    }
    k.iter()
        .map(|&kv| {
            let r = if kv > 0.0 { 1.0 / kv } else { f64::INFINITY };
            edge_length_for_radius(
                r,
                sizes.approx_error,
                sizes.min_edge_length,
                sizes.max_edge_length,
            )
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sizes_follow_the_reference_rules() {
        let s = icosphere_sizes(0.14, 1.0, 0);
        assert!(
            (s.min_edge_length - 0.14 * 2.0 * crate::fmath::sin(std::f64::consts::TAU / 10.0))
                .abs()
                < 1e-15
        );
        assert_eq!(s.max_edge_length, 4.0 * s.min_edge_length);
        assert!((s.approx_error - 1.25 * s.min_edge_length).abs() < 1e-15);
        let d = decayed(s, 0.7);
        assert!((d.min_edge_length - 0.7 * s.min_edge_length).abs() < 1e-15);
        assert!((d.approx_error - 0.5 * d.min_edge_length).abs() < 1e-15);
        let iso = isosurface_sizes(0.4, 0.1, 2.0);
        assert!((iso.min_edge_length - 2f64.sqrt() * 0.08).abs() < 1e-15);
    }

    #[test]
    fn edge_length_formula() {
        // Flat: l_max. Sharp: √3 ε clamped. Sagitta check: a chord h on radius r has sagitta
        // ≈ h²/(8r); the formula's h² ≈ 6 ε r gives sagitta ≈ 0.75 ε.
        assert_eq!(edge_length_for_radius(f64::INFINITY, 0.1, 0.01, 1.0), 1.0);
        assert_eq!(
            edge_length_for_radius(0.05, 0.1, 0.01, 1.0),
            3f64.sqrt() * 0.1
        );
        let h = edge_length_for_radius(10.0, 0.01, 0.0, 100.0);
        assert!((h - (0.6f64 - 0.0003).sqrt()).abs() < 1e-12);
        assert_eq!(edge_length_for_radius(1e-6, 0.1, 0.5, 1.0), 0.5);
    }
}
