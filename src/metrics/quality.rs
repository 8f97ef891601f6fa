//! Per-face triangle quality (docs/method.md §9.1–9.3, project decision 3) and co-volume statistics
//! (§9.4).
//!
//! * [`kappa`] — κ(J_Δ), the condition number of the map J from the unit equilateral triangle
//!   onto the triangle (in its plane), `κ = ‖J‖_F·‖J⁻¹‖_F / 2`. Rotation- and
//!   vertex-order-invariant, exactly 1 for an equilateral triangle, ∞ for a degenerate one.
//!   Closed form: `κ = (a² + b² + c²) / (4√3·T)` (sides a, b, c, area T).
//! * [`kappa_reference`] — the reference's variant (§9.1, only for comparison with published
//!   numbers): equilateral → 2/√3, depends on which vertex is the apex.
//! * [`radius_ratio`] — `2·r_in / r_circ = 8T² / (s·a·b·c)` ∈ [0, 1], 1 for equilateral.
//! * [`min_angle`] — the smallest interior angle (radians).

// `!(x > y)` is used deliberately: it is also true when x is NaN.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

use crate::geometry::operators::laplacian::CotanLaplacian;
use crate::mesh::HalfedgeMesh;
use glam::DVec3;
use serde::{Deserialize, Serialize};

/// κ(J_Δ) of triangle `(a, b, c)`: 1 for equilateral, larger is worse, ∞ if degenerate.
pub fn kappa(a: DVec3, b: DVec3, c: DVec3) -> f64 {
    let twice_area = (b - a).cross(c - a).length();
    if !(twice_area > 0.0) {
        return f64::INFINITY;
    }
    let s2 = (b - a).length_squared() + (c - b).length_squared() + (a - c).length_squared();
    // ‖J‖_F·‖J⁻¹‖_F = ‖J‖_F² / |det J| for 2×2 J; with J = T·E⁻¹ this is s2 / (2√3·T).
    s2 / (2.0 * 3f64.sqrt() * twice_area)
}

/// The reference's κ(J_Δ) variant (docs/method.md §9.1) for a face listed as `[i0, i1, i2]`:
/// apex `a = i0`, base `b0 = i2`, `b1 = i1`; `κ = ‖W‖_∞·‖W⁻¹‖_∞` with
/// `W = [[2|e0|, e1·x̂], [0, e1·ŷ]]`. Equilateral → 2/√3 ≈ 1.1547, right isosceles (apex at the
/// right angle) → 2. Degenerate → ∞ (the reference returns FLT_MAX).
pub fn kappa_reference(i0: DVec3, i1: DVec3, i2: DVec3) -> f64 {
    let (apex, b0, b1) = (i0, i2, i1);
    let m = 0.5 * (b0 + b1);
    let e0 = b1 - m;
    let e1 = apex - m;
    let eps = f32::EPSILON as f64;
    let n = e0.cross(e1);
    if e0.length() < eps || e1.length() < eps || n.length() < eps {
        return f64::INFINITY;
    }
    let x = e0.normalize();
    let z = n.normalize();
    let y = z.cross(x);
    let (p, q, s) = (2.0 * e0.length(), e1.dot(x), e1.dot(y));
    if (p * s).abs() < eps {
        return f64::INFINITY;
    }
    (p.abs() + q.abs()).max(s.abs()) * (1.0 / p.abs() + q.abs() / (p * s).abs()).max(1.0 / s.abs())
}

/// `2·r_in / r_circ` of triangle `(a, b, c)`: 1 for equilateral, 0 for degenerate.
pub fn radius_ratio(a: DVec3, b: DVec3, c: DVec3) -> f64 {
    let (la, lb, lc) = ((c - b).length(), (a - c).length(), (b - a).length());
    let t = 0.5 * (b - a).cross(c - a).length();
    let s = 0.5 * (la + lb + lc);
    let den = s * la * lb * lc;
    if !(den > 0.0) {
        return 0.0;
    }
    (8.0 * t * t / den).min(1.0)
}

/// Smallest interior angle of triangle `(a, b, c)`, radians (0 for degenerate).
pub fn min_angle(a: DVec3, b: DVec3, c: DVec3) -> f64 {
    let ang = |p: DVec3, q: DVec3, r: DVec3| {
        let (u, v) = (q - p, r - p);
        crate::fmath::atan2(u.cross(v).length(), u.dot(v))
    };
    ang(a, b, c).min(ang(b, c, a)).min(ang(c, a, b))
}

/// Order statistics of a sample.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Summary {
    /// Number of values.
    pub count: usize,
    /// Arithmetic mean (of the finite values; NaN if none).
    pub mean: f64,
    /// Median (nearest rank).
    pub median: f64,
    /// 95th percentile (nearest rank).
    pub p95: f64,
    /// Smallest value.
    pub min: f64,
    /// Largest value.
    pub max: f64,
}

/// Nearest-rank percentile `q ∈ [0, 1]` of an ascending slice.
pub fn percentile_sorted(sorted: &[f64], q: f64) -> f64 {
    if sorted.is_empty() {
        return f64::NAN;
    }
    let rank = (q * sorted.len() as f64).ceil() as usize;
    sorted[rank.clamp(1, sorted.len()) - 1]
}

/// Summary of `values` (sorted copy; fixed summation order). Infinite values (degenerate faces)
/// count in the order statistics but not in the mean.
pub fn summarize(values: &[f64]) -> Summary {
    let mut v = values.to_vec();
    v.sort_by(|a, b| a.total_cmp(b));
    let finite: Vec<f64> = values.iter().copied().filter(|x| x.is_finite()).collect();
    Summary {
        count: v.len(),
        mean: finite.iter().sum::<f64>() / finite.len() as f64,
        median: percentile_sorted(&v, 0.5),
        p95: percentile_sorted(&v, 0.95),
        min: v.first().copied().unwrap_or(f64::NAN),
        max: v.last().copied().unwrap_or(f64::NAN),
    }
}

/// Per-face quality values of a triangle list.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct FaceQuality {
    /// κ(J_Δ) per face (equilateral = 1).
    pub kappa: Vec<f64>,
    /// The reference's κ variant per face (equilateral = 2/√3).
    pub kappa_reference: Vec<f64>,
    /// 2·r_in/r_circ per face.
    pub radius_ratio: Vec<f64>,
    /// Smallest angle per face, degrees.
    pub min_angle_deg: Vec<f64>,
}

/// Computes every per-face quality measure.
pub fn face_quality(positions: &[DVec3], triangles: &[[u32; 3]]) -> FaceQuality {
    let mut q = FaceQuality::default();
    for t in triangles {
        let [a, b, c] = t.map(|v| positions[v as usize]);
        q.kappa.push(kappa(a, b, c));
        q.kappa_reference.push(kappa_reference(a, b, c));
        q.radius_ratio.push(radius_ratio(a, b, c));
        q.min_angle_deg.push(min_angle(a, b, c).to_degrees());
    }
    q
}

/// Quality statistics of a mesh (JSON keys are a stable interface).
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct QualityStats {
    /// κ(J_Δ) (equilateral = 1).
    pub kappa: Summary,
    /// Fraction of faces with κ(J_Δ) ≤ 1.5, in [0, 1].
    pub kappa_le_1_5: f64,
    /// The reference's κ variant (equilateral = 2/√3), for comparison with published numbers.
    pub kappa_reference: Summary,
    /// Fraction of faces with the reference's κ ≤ 1.5.
    pub kappa_reference_le_1_5: f64,
    /// 2·r_in/r_circ (equilateral = 1).
    pub radius_ratio: Summary,
    /// Smallest interior angle per face, degrees.
    pub min_angle_deg: Summary,
}

/// Summarises [`face_quality`].
pub fn quality_stats(positions: &[DVec3], triangles: &[[u32; 3]]) -> QualityStats {
    let q = face_quality(positions, triangles);
    let frac = |v: &[f64]| v.iter().filter(|&&k| k <= 1.5).count() as f64 / v.len().max(1) as f64;
    QualityStats {
        kappa: summarize(&q.kappa),
        kappa_le_1_5: frac(&q.kappa),
        kappa_reference: summarize(&q.kappa_reference),
        kappa_reference_le_1_5: frac(&q.kappa_reference),
        radius_ratio: summarize(&q.radius_ratio),
        min_angle_deg: summarize(&q.min_angle_deg),
    }
}

/// Per-vertex mean of the incident faces' κ(J_Δ) (the remeshing trigger's input, docs/method.md
/// §7.1); degenerate faces are left out of both the sum and the count (unlike the reference,
/// §13.20).
pub fn vertex_kappa(mesh: &HalfedgeMesh) -> Vec<f64> {
    let mut sum = vec![0.0; mesh.n_vertices()];
    let mut cnt = vec![0u32; mesh.n_vertices()];
    // (The remesh trigger asks every step: the faces' κ on both cores, added up in face order.)
    let faces = crate::parallel::map(mesh.n_faces(), |f| {
        let f = f as u32;
        (!mesh.is_deleted_face(f)).then(|| {
            let vs = mesh.face_vertices(f);
            let [a, b, c] = vs.map(|v| mesh.position(v));
            (vs, kappa(a, b, c))
        })
    });
    for (vs, k) in faces.into_iter().flatten() {
        if k.is_finite() {
            for v in vs {
                sum[v as usize] += k;
                cnt[v as usize] += 1;
            }
        }
    }
    sum.iter()
        .zip(&cnt)
        .map(|(s, &c)| if c > 0 { s / c as f64 } else { f64::INFINITY })
        .collect()
}

/// Co-volume (mixed Voronoi area A_i) statistics (docs/method.md §9.4).
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct CovolumeStats {
    /// Summary of A_i over the vertices.
    pub area: Summary,
    /// Standard deviation of A_i divided by its mean (0 = perfectly uniform).
    pub relative_std: f64,
    /// max A_i / min A_i.
    pub max_over_min: f64,
}

/// Co-volume statistics of a (garbage-free) mesh.
pub fn covolume_stats(mesh: &HalfedgeMesh) -> CovolumeStats {
    let a = CotanLaplacian::new(mesh).covolumes;
    let s = summarize(&a);
    let var = a.iter().map(|x| (x - s.mean) * (x - s.mean)).sum::<f64>() / a.len().max(1) as f64;
    CovolumeStats {
        area: s,
        relative_std: var.sqrt() / s.mean,
        max_over_min: s.max / s.min,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn equilateral_right_isosceles_needle() {
        let (a, b) = (DVec3::ZERO, DVec3::X);
        let c = DVec3::new(0.5, 3f64.sqrt() / 2.0, 0.0);
        assert!((kappa(a, b, c) - 1.0).abs() < 1e-14);
        assert!((radius_ratio(a, b, c) - 1.0).abs() < 1e-14);
        assert!((kappa_reference(a, b, c) - 2.0 / 3f64.sqrt()).abs() < 1e-12);
        assert!((min_angle(a, b, c).to_degrees() - 60.0).abs() < 1e-12);
        // Right isosceles with legs 1: κ = (1 + 1 + 2)/(4√3·½) = 2/√3.
        let r = DVec3::Y;
        assert!((kappa(a, b, r) - 2.0 / 3f64.sqrt()).abs() < 1e-14);
        // 2·r_in/r_circ = 8T²/(s·abc) = 2/(s·√2) = 2(√2 − 1).
        let s = (2.0 + 2f64.sqrt()) / 2.0;
        assert!((radius_ratio(a, b, r) - 8.0 * 0.25 / (s * 2f64.sqrt())).abs() < 1e-14);
        assert!((radius_ratio(a, b, r) - 2.0 * (2f64.sqrt() - 1.0)).abs() < 1e-14);
        assert!((min_angle(a, b, r).to_degrees() - 45.0).abs() < 1e-12);
        // Reference variant, apex at the right angle (i0 = a): 2.0 (docs/method.md §9.1 "facts").
        assert!((kappa_reference(a, b, r) - 2.0).abs() < 1e-12);
        // Needle: height 1e-3 on base 1 → κ ≈ (1 + 2·0.25)/(4√3·5e-4) ≈ 433.
        let n = DVec3::new(0.5, 1e-3, 0.0);
        let expect = (1.0 + 2.0 * (0.25 + 1e-6)) / (4.0 * 3f64.sqrt() * 0.5e-3);
        assert!((kappa(a, b, n) - expect).abs() < 1e-9 * expect);
        assert!(radius_ratio(a, b, n) < 0.01);
        // Degenerate.
        assert_eq!(kappa(a, b, DVec3::new(2.0, 0.0, 0.0)), f64::INFINITY);
        assert_eq!(radius_ratio(a, b, DVec3::new(2.0, 0.0, 0.0)), 0.0);
    }

    #[test]
    fn kappa_is_rotation_and_order_invariant() {
        let (a, b, c) = (
            DVec3::new(0.1, 0.2, 0.3),
            DVec3::new(1.3, -0.2, 0.5),
            DVec3::new(0.4, 0.9, -0.7),
        );
        let k = kappa(a, b, c);
        assert!((kappa(b, c, a) - k).abs() < 1e-13);
        assert!((kappa(c, b, a) - k).abs() < 1e-13);
        #[allow(clippy::disallowed_methods)] // a test input: its last bit does not matter
        let rot = glam::DQuat::from_axis_angle(DVec3::new(1.0, 2.0, 3.0).normalize(), 0.7);
        assert!((kappa(rot * a, rot * b, rot * c) - k).abs() < 1e-12);
        assert!((kappa(3.0 * a, 3.0 * b, 3.0 * c) - k).abs() < 1e-12);
        // κ = ‖J‖_F‖J⁻¹‖_F/2 directly, in the triangle's plane.
        let x = (b - a).normalize();
        let y = (b - a).cross(c - a).cross(b - a).normalize();
        let t = glam::DMat2::from_cols(
            glam::DVec2::new((b - a).dot(x), 0.0),
            glam::DVec2::new((c - a).dot(x), (c - a).dot(y)),
        );
        let e = glam::DMat2::from_cols(glam::DVec2::X, glam::DVec2::new(0.5, 3f64.sqrt() / 2.0));
        let j = t * e.inverse();
        let fro = |m: glam::DMat2| (m.x_axis.length_squared() + m.y_axis.length_squared()).sqrt();
        assert!((fro(j) * fro(j.inverse()) / 2.0 - k).abs() < 1e-12);
    }

    #[test]
    fn summary_percentiles() {
        let v: Vec<f64> = (1..=100).map(|x| x as f64).collect();
        let s = summarize(&v);
        assert_eq!((s.median, s.p95, s.min, s.max), (50.0, 95.0, 1.0, 100.0));
        assert!((s.mean - 50.5).abs() < 1e-12);
    }
}
