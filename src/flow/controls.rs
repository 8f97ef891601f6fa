//! The control functions of the LSW equation (docs/method.md §4.1): ε slows mean-curvature flow to
//! zero near the target, η advects towards it, ρ = ω·ε weighs the tangential redistribution.

/// Parameters of the control functions (stabilised frame).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Controls {
    /// C1, C2 of ε.
    pub c1: f64,
    pub c2: f64,
    /// D1, D2 of η.
    pub d1: f64,
    pub d2: f64,
    /// ε⁺ / η⁺: zero where δ < 0.
    pub mcf_positive_support: bool,
    pub advection_positive_support: bool,
}

impl Controls {
    /// ε(δ) = C1·(1 − exp(−δ²/C2)), zero for δ < 0 with positive support.
    pub fn epsilon(&self, delta: f64) -> f64 {
        if self.mcf_positive_support && delta < 0.0 {
            return 0.0;
        }
        self.c1 * (1.0 - crate::fmath::exp(-delta * delta / self.c2))
    }

    /// η(δ, cos θ) = D1·δ·(cos θ − D2·sin θ) with cos θ = g·N (g = −∇d/|∇d|, N the outward normal),
    /// zero for δ < 0 with positive support. The sine term pushes harder wherever the surface is
    /// not yet facing the target (full-wrap); 1 − cos² is clamped at 0 against rounding.
    pub fn eta(&self, delta: f64, cos_theta: f64) -> f64 {
        if self.advection_positive_support && delta < 0.0 {
            return 0.0;
        }
        let c = cos_theta.clamp(-1.0, 1.0);
        self.d1 * delta * (c - self.d2 * (1.0 - c * c).max(0.0).sqrt())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const C: Controls = Controls {
        c1: 1.0,
        c2: 1.0,
        d1: 2.0,
        d2: 1.0,
        mcf_positive_support: true,
        advection_positive_support: true,
    };

    #[test]
    fn epsilon_vanishes_at_and_inside_the_target() {
        assert_eq!(C.epsilon(0.0), 0.0);
        assert_eq!(C.epsilon(-0.5), 0.0);
        assert!((C.epsilon(1.0) - (1.0 - crate::fmath::exp(-1.0f64))).abs() < 1e-15);
        assert!(C.epsilon(10.0) > 0.999);
        let two_sided = Controls {
            mcf_positive_support: false,
            ..C
        };
        assert_eq!(two_sided.epsilon(-0.5), two_sided.epsilon(0.5));
    }

    #[test]
    fn eta_pulls_inwards_when_facing_away() {
        // Outward normal N and g = −∇d pointing inwards (towards the target): cos θ = −1 for a
        // surface outside a convex target, giving η = −D1·δ: motion along −N, inwards.
        assert!((C.eta(0.5, -1.0) + 1.0).abs() < 1e-15);
        // Sideways (cos θ = 0): the full-wrap term still pushes inwards.
        assert!((C.eta(0.5, 0.0) + 1.0).abs() < 1e-15);
        let obstacle = Controls { d2: 0.0, ..C };
        assert_eq!(obstacle.eta(0.5, 0.0), 0.0);
        assert_eq!(C.eta(-0.1, -1.0), 0.0);
        assert!(C.eta(0.5, -1.0000001).is_finite());
    }
}
