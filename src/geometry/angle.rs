//! The angle of a triangle corner from its cross- and dot-product, without the platform's libm.
//!
//! The flow needs three corner angles per face per step (angle-weighted normals), about six per
//! vertex. `acos` of a normalised dot product costs two square roots more and is poorly
//! conditioned for small angles; `f64::atan2` calls the platform's libm, which differs between
//! glibc and wasm in the last bit. This is Cephes' `atan` (rational approximation after range
//! reduction) using only `+ − × ÷`, so the same bits come out natively and in the browser — a
//! shared link reproduces the same mesh — and it is about twice as fast as libm's `atan2`.

use std::f64::consts::{FRAC_PI_2, FRAC_PI_4, PI};

const P: [f64; 5] = [
    -8.750_608_600_031_904e-1,
    -1.615_753_718_733_365e1,
    -7.500_855_792_314_705e1,
    -1.228_866_684_490_136e2,
    -6.485_021_904_942_025e1,
];
const Q: [f64; 5] = [
    2.485_846_490_142_306e1,
    1.650_270_098_316_988_5e2,
    4.328_810_604_912_903e2,
    4.853_903_996_359_137e2,
    1.945_506_571_482_614e2,
];
/// π/2 − the double nearest π/2 (Cephes' MOREBITS).
const MOREBITS: f64 = 6.123_233_995_736_766e-17;
/// tan(3π/8) = 1 + √2.
const TAN_3PI_8: f64 = 2.414_213_562_373_095;

/// `atan2(y, x)` for `y ≥ 0`, in `[0, π]`: the angle between two edge vectors `a`, `b` is
/// `corner_angle(|a × b|, a · b)`. Within two ulps of `atan2`. `(0, 0)` gives 0.
#[inline]
pub fn corner_angle(y: f64, x: f64) -> f64 {
    let ax = x.abs();
    if y == 0.0 && ax == 0.0 {
        return 0.0;
    }
    // Reduce t = y/|x| ∈ [0, ∞] to |t'| ≤ tan(π/8): atan t = π/2 − atan(1/t) for large t,
    // π/4 + atan((t − 1)/(t + 1)) for middling t.
    let (num, den, base, extra) = if y > TAN_3PI_8 * ax {
        (-ax, y, FRAC_PI_2, MOREBITS)
    } else if y > 0.66 * ax {
        (y - ax, y + ax, FRAC_PI_4, 0.5 * MOREBITS)
    } else {
        (y, ax, 0.0, 0.0)
    };
    let t = num / den;
    let z = t * t;
    let p = (((P[0] * z + P[1]) * z + P[2]) * z + P[3]) * z + P[4];
    let q = ((((z + Q[0]) * z + Q[1]) * z + Q[2]) * z + Q[3]) * z + Q[4];
    let a = base + (t * z * p / q + t + extra);
    if x < 0.0 {
        PI - a
    } else {
        a
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn matches_atan2_over_the_half_plane() {
        let mut worst = 0.0f64;
        for i in 0..=20_000 {
            let phi = PI * i as f64 / 20_000.0;
            for r in [1e-200, 1e-3, 1.0, 7.5e4, 1e200] {
                let (y, x) = (r * crate::fmath::sin(phi), r * crate::fmath::cos(phi));
                let y = y.max(0.0);
                worst = worst.max((corner_angle(y, x) - crate::fmath::atan2(y, x)).abs());
            }
        }
        // Two ulps near π (4.4e-16 each): the two are different rational approximations.
        assert!(worst <= 9e-16, "worst error {worst:e}");
        assert_eq!(corner_angle(0.0, 0.0), 0.0);
        assert_eq!(corner_angle(0.0, 2.0), 0.0);
        assert_eq!(corner_angle(0.0, -2.0), PI);
        assert_eq!(corner_angle(3.0, 0.0), FRAC_PI_2);
        assert!((corner_angle(1.0, 1.0) - FRAC_PI_4).abs() <= 1e-16);
    }
}
