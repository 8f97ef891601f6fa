//! Fixed-bin histograms for metric distributions (quality, distances, per-vertex d).

// `!(x > y)` is used deliberately: it is also true when x is NaN.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

use serde::{Deserialize, Serialize};

/// Counts of values in `bins` equal bins over `[lo, hi)`, with under- and overflow.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
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
}
