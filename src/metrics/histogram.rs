//! Fixed-bin histograms for metric distributions (quality, distances, per-vertex d).

// `!(x > y)` is used deliberately: it is also true when x is NaN.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

use glam::DVec3;
use serde::{Deserialize, Serialize};

/// Counts of values in `bins` equal bins over `[lo, hi)`, with under- and overflow.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[cfg_attr(target_arch = "wasm32", derive(tsify::Tsify))]
pub struct Histogram {
    /// Lower edge of the first bin.
    pub lo: f64,
    /// Upper edge of the last bin.
    pub hi: f64,
    /// Count per bin.
    pub counts: Vec<usize>,
    /// Values below `lo`.
    pub below: usize,
    /// Values at or above `hi` (and NaN).
    pub above: usize,
}

impl Histogram {
    /// Bins `values` into `bins` equal bins over `[lo, hi)` (`bins ≥ 1`, `lo < hi`).
    pub fn new(values: &[f64], lo: f64, hi: f64, bins: usize) -> Self {
        let bins = bins.max(1);
        let mut h = Histogram {
            lo,
            hi,
            counts: vec![0; bins],
            below: 0,
            above: 0,
        };
        let w = (hi - lo) / bins as f64;
        for &v in values {
            if v < lo {
                h.below += 1;
            } else if v >= hi || v.is_nan() {
                h.above += 1;
            } else {
                let k = (((v - lo) / w) as usize).min(bins - 1);
                h.counts[k] += 1;
            }
        }
        h
    }
    /// Bins over the data's own range.
    pub fn auto(values: &[f64], bins: usize) -> Self {
        let finite = values.iter().copied().filter(|v| v.is_finite());
        let (lo, hi) = finite.fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), v| {
            (a.min(v), b.max(v))
        });
        if !(lo < hi) {
            let lo = if lo.is_finite() { lo } else { 0.0 };
            return Self::new(values, lo, lo + 1.0, bins);
        }
        // Nudge the top so the maximum falls in the last bin.
        Self::new(values, lo, hi + (hi - lo) * 1e-12, bins)
    }
    /// Lower edge of bin `k`.
    pub fn bin_lo(&self, k: usize) -> f64 {
        self.lo + (self.hi - self.lo) * k as f64 / self.counts.len() as f64
    }
}

/// The app's quality histogram: the per-triangle κ(J_Δ) (equilateral = 1, see
/// [`super::quality::kappa`]) of a mesh over [1, `hi`) in `bins` bins. A `hi` not above 1 or not
/// finite means 3; `bins` is kept within 1..=1000.
pub fn kappa_histogram(
    positions: &[DVec3],
    triangles: &[[u32; 3]],
    bins: usize,
    hi: f64,
) -> Histogram {
    let kappa: Vec<f64> = triangles
        .iter()
        .map(|t| {
            let [a, b, c] = t.map(|v| positions[v as usize]);
            super::quality::kappa(a, b, c)
        })
        .collect();
    let hi = if hi > 1.0 && hi.is_finite() { hi } else { 3.0 };
    Histogram::new(&kappa, 1.0, hi, bins.clamp(1, 1000))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bins_and_overflow() {
        let h = Histogram::new(&[0.0, 0.1, 0.5, 0.99, 1.0, -1.0, f64::NAN], 0.0, 1.0, 2);
        assert_eq!(h.counts, vec![2, 2]);
        assert_eq!((h.below, h.above), (1, 2));
        let a = Histogram::auto(&[1.0, 2.5, 3.0], 2);
        assert_eq!(a.counts, vec![1, 2]);
        assert_eq!(a.bin_lo(0), 1.0);
    }

    #[test]
    fn kappa_histogram_of_three_triangles() {
        let h = 3f64.sqrt() / 2.0;
        let p = [
            DVec3::ZERO,
            DVec3::X,
            DVec3::new(0.5, h, 0.0),
            DVec3::Y,
            DVec3::new(0.5, 1e-3, 0.0),
        ];
        // Equilateral (κ = 1), right isosceles (κ = 2/√3), a needle (κ ≫ 3).
        let t = [[0, 1, 2], [0, 1, 3], [0, 1, 4]];
        let k = kappa_histogram(&p, &t, 4, 3.0);
        assert_eq!((k.lo, k.hi, k.counts.clone()), (1.0, 3.0, vec![2, 0, 0, 0]));
        assert_eq!((k.below, k.above), (0, 1));
        // Bad bounds fall back to [1, 3); the bin count is clamped.
        assert_eq!(kappa_histogram(&p, &t, 0, f64::NAN).hi, 3.0);
        assert_eq!(kappa_histogram(&p, &t, 0, 0.5).counts.len(), 1);
        assert_eq!(kappa_histogram(&p, &t, 5000, 2.0).counts.len(), 1000);
    }
}
