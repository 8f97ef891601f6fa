//! Transcendental functions that give the same bits on every platform.
//!
//! `f64::exp`, `sin`, `acos`… call the platform's libm: glibc natively, a port of musl in wasm.
//! They may differ in the last bit, and one bit can flip a remesh decision, so the browser and
//! the CLI would give different meshes for the same link. Everything in the core calls these
//! instead (`clippy.toml` forbids the `f64` methods); they are the `libm` crate's pure-Rust
//! code on both targets. `sqrt`, `mul_add` and `+ − × ÷` are exactly rounded everywhere and stay
//! as they are.

#[inline]
pub fn exp(x: f64) -> f64 {
    libm::exp(x)
}

#[inline]
pub fn ln(x: f64) -> f64 {
    libm::log(x)
}

#[inline]
pub fn log10(x: f64) -> f64 {
    libm::log10(x)
}

#[inline]
pub fn powf(x: f64, y: f64) -> f64 {
    libm::pow(x, y)
}

#[inline]
pub fn sin(x: f64) -> f64 {
    libm::sin(x)
}

#[inline]
pub fn cos(x: f64) -> f64 {
    libm::cos(x)
}

/// `(sin x, cos x)`.
#[inline]
pub fn sin_cos(x: f64) -> (f64, f64) {
    libm::sincos(x)
}

#[inline]
pub fn tanh(x: f64) -> f64 {
    libm::tanh(x)
}

/// `acos`, its argument clamped to [−1, 1] first (a dot product of unit vectors can overshoot).
#[inline]
pub fn acos(x: f64) -> f64 {
    libm::acos(x.clamp(-1.0, 1.0))
}

#[inline]
pub fn atan2(y: f64, x: f64) -> f64 {
    libm::atan2(y, x)
}

#[inline]
pub fn hypot(x: f64, y: f64) -> f64 {
    libm::hypot(x, y)
}

#[inline]
pub fn sinf(x: f32) -> f32 {
    libm::sinf(x)
}

#[inline]
pub fn cosf(x: f32) -> f32 {
    libm::cosf(x)
}

#[cfg(test)]
mod tests {
    /// The wrappers are the functions they stand for, to within the last bits.
    #[test]
    #[allow(clippy::disallowed_methods)]
    fn agree_with_std_to_rounding() {
        let close = |a: f64, b: f64| (a - b).abs() <= 4.0 * f64::EPSILON * b.abs().max(1e-300);
        for i in 0..1000 {
            let x = -3.0 + 6.0 * i as f64 / 999.0;
            assert!(close(super::exp(x), x.exp()), "exp {x}");
            assert!(
                close(super::sin(x), x.sin()) || x.sin().abs() < 1e-15,
                "sin {x}"
            );
            assert!(
                close(super::cos(x), x.cos()) || x.cos().abs() < 1e-15,
                "cos {x}"
            );
            assert!(close(super::atan2(x, 0.7), x.atan2(0.7)), "atan2 {x}");
            assert!(
                close(super::tanh(x), x.tanh()) || x.abs() < 1e-12,
                "tanh {x}"
            );
            let c = x / 3.0;
            assert!(close(super::acos(c), c.acos()), "acos {c}");
            let (s, co) = super::sin_cos(x);
            assert_eq!((s, co), (super::sin(x), super::cos(x)));
            if x > 0.0 {
                assert!(
                    close(super::ln(x), x.ln()) || (x - 1.0).abs() < 1e-9,
                    "ln {x}"
                );
                assert!(close(super::powf(x, 1.7), x.powf(1.7)), "powf {x}");
                assert!(close(super::log10(x), x.log10()) || (x - 1.0).abs() < 1e-9);
            }
        }
        assert_eq!(super::acos(1.0 + 1e-15), 0.0);
        assert_eq!(super::hypot(3.0, 4.0), 5.0);
    }
}
