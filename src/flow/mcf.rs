//! One semi-implicit mean-curvature-flow step: `(I − τΔ) F^{n+1} = F^n` (docs/method.md §6.2).
//!
//! Implicit diffusion is unconditionally stable, so τ is limited by accuracy only. The pure flow
//! shrinks a sphere as r(t) = sqrt(r0² − 4t), which the tests check.

use super::FlowError;
use crate::geometry::operators::CotanLaplacian;
use crate::mesh::HalfedgeMesh;
use crate::solve::{solve_xyz_scaled, SolveReport, SolverSettings};
use glam::DVec3;
use serde::{Deserialize, Serialize};

/// Settings of a pure MCF step.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default)]
pub struct McfSettings {
    /// Time step τ (in squared length units of the mesh). Default 1e-4, suited to a unit sphere.
    pub tau: f64,
    /// Corrector passes: after the linearised step, rebuild the operator at the new positions and
    /// solve again from the old ones (a Picard iteration towards fully implicit Euler). 0 is the
    /// reference's semi-implicit scheme, whose operator lags one step behind (co-volumes of the
    /// larger, older surface) and so shrinks a sphere too slowly, a first-order error. One pass
    /// cuts that error severalfold at twice the cost.
    /// Default 1; range 0–4.
    pub corrector_passes: u32,
    /// Linear solver settings.
    pub solver: SolverSettings,
}

impl Default for McfSettings {
    fn default() -> Self {
        Self {
            tau: 1e-4,
            corrector_passes: 1,
            solver: SolverSettings::default(),
        }
    }
}

/// What one MCF step did.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct McfStepReport {
    /// Solver iterations and residual (worst of x, y, z).
    pub solve: SolveReport,
    /// Smallest co-volume (mixed Voronoi area) before the step.
    pub covolume_min: f64,
    /// Mean co-volume before the step.
    pub covolume_mean: f64,
    /// Largest co-volume before the step.
    pub covolume_max: f64,
}

/// The radius at time `t` of a sphere of initial radius `r0` under MCF: `sqrt(r0² − 4t)`
/// (NaN after the extinction time r0²/4).
pub fn exact_sphere_radius(r0: f64, t: f64) -> f64 {
    (r0 * r0 - 4.0 * t).sqrt()
}

/// The time at which a sphere of radius `r0` vanishes under MCF: r(t) = sqrt(r0² − 4t) = 0 at
/// t* = r0²/4. Past it the exact radius is undefined (NaN).
pub fn sphere_extinction_time(r0: f64) -> f64 {
    0.25 * r0 * r0
}

/// The sphere lesson stops when the exact radius reaches this fraction of r0: below it the
/// co-volumes are so small that τ is no longer small against them and the linearised flow
/// loses accuracy (the plot would show the scheme, not the law).
pub const LESSON_STOP_FRACTION: f64 = 0.15;

/// A lesson run shows the law with at least this many steps ([`TauAdvice::tau_max`]) …
pub const LESSON_MIN_STEPS: f64 = 50.0;
/// … and takes at most this many ([`TauAdvice::tau_min`]; about a minute at level 6).
pub const LESSON_MAX_STEPS: f64 = 20_000.0;

/// Steps of size `tau` the sphere lesson still takes after `step` steps: up to the first step
/// at which the exact radius is at most [`LESSON_STOP_FRACTION`]·r0, and never one that reaches
/// the extinction time r0²/4 (where the exact radius no longer exists). 0 when τ is not a
/// positive finite number.
pub fn lesson_steps_left(r0: f64, tau: f64, step: u32) -> u32 {
    if !(tau > 0.0 && tau.is_finite()) {
        return 0;
    }
    let f = LESSON_STOP_FRACTION;
    let stop = sphere_extinction_time(r0) * (1.0 - f * f);
    // The last step strictly before extinction: t = n·τ < r0²/4 (n·τ as the lesson computes it).
    let extinction = sphere_extinction_time(r0);
    let mut before_extinction = (extinction / tau).ceil() - 1.0;
    while before_extinction > 0.0 && before_extinction * tau >= extinction {
        before_extinction -= 1.0;
    }
    let total = (stop / tau).ceil().min(before_extinction).max(0.0);
    (total.min(u32::MAX as f64) as u32).saturating_sub(step)
}

/// What a time step τ means for the sphere lesson, worked out before it runs.
#[derive(Clone, Debug, PartialEq, Serialize)]
#[serde(rename_all = "camelCase")]
#[cfg_attr(target_arch = "wasm32", derive(tsify::Tsify))]
pub struct TauAdvice {
    /// The τ asked about.
    pub tau: f64,
    /// t* = r0²/4, when the sphere vanishes.
    pub extinction_time: f64,
    /// Steps the lesson will take ([`lesson_steps_left`] from the start).
    pub steps: u32,
    /// The sensible range of τ: the run takes between [`LESSON_MAX_STEPS`] and
    /// [`LESSON_MIN_STEPS`] steps to its stop.
    pub tau_min: f64,
    pub tau_max: f64,
    /// Whether τ is in that range.
    pub sensible: bool,
    /// What is wrong with τ, in one or two sentences for the page (empty when sensible).
    pub warning: String,
}

/// Checks τ for the sphere lesson on a sphere of radius `r0` (the page warns before running).
pub fn lesson_tau_advice(r0: f64, tau: f64) -> TauAdvice {
    let f = LESSON_STOP_FRACTION;
    let extinction_time = sphere_extinction_time(r0);
    let stop = extinction_time * (1.0 - f * f);
    let (tau_min, tau_max) = (stop / LESSON_MAX_STEPS, stop / LESSON_MIN_STEPS);
    let steps = lesson_steps_left(r0, tau, 0);
    let range = format!("a sensible τ lies between {tau_min:.1e} and {tau_max:.1e}");
    let warning = if !(tau > 0.0 && tau.is_finite()) {
        format!("τ must be a positive number; {range}.")
    } else if tau >= extinction_time {
        format!(
            "τ = {tau} is at least the whole life of the sphere (it vanishes at t = r0²/4 = \
             {extinction_time}): one step would pass it. {range}."
        )
    } else if tau > tau_max {
        format!(
            "τ = {tau} is too large: the sphere vanishes at t = r0²/4 = {extinction_time}, so \
             the run has only {steps} steps and the linearised flow departs from the exact law; \
             {range}."
        )
    } else if tau < tau_min {
        format!(
            "τ = {tau} is very small: the run would take {steps} steps to reach \
             {:.0} % of the radius; {range}.",
            100.0 * f
        )
    } else {
        String::new()
    };
    TauAdvice {
        tau,
        extinction_time,
        steps,
        tau_min,
        tau_max,
        sensible: warning.is_empty(),
        warning,
    }
}

/// Refuses step number `step + 1` of the sphere lesson if it would reach the extinction time
/// r0²/4: the exact radius does not exist there, and the mesh, shrunk to a point, has no
/// co-volumes left to divide by.
pub fn check_sphere_step(r0: f64, tau: f64, step: u32) -> Result<(), FlowError> {
    let extinction = sphere_extinction_time(r0);
    if (step as f64 + 1.0) * tau >= extinction {
        return Err(FlowError::PastExtinction {
            time: step as f64 * tau,
            tau,
            extinction,
        });
    }
    Ok(())
}

/// Advances `mesh` by one implicit MCF step. On error the mesh is left unchanged.
pub fn mcf_step(
    mesh: &mut HalfedgeMesh,
    settings: &McfSettings,
) -> Result<McfStepReport, FlowError> {
    mcf_step_with(mesh, settings, None, false)
}

/// [`mcf_step`] with a per-vertex mobility: vertex `i` moves with speed `mobility[i]`·2H
/// (`None` = 1 everywhere). A vertex of mobility 0 gets an identity row and stays put: the mesh
/// lesson pins an open mesh's boundary this way (the Dirichlet problem of MCF), since at a
/// boundary vertex the cotangent Laplacian measures the boundary curve's curvature, not H.
/// With `clamp_negative`, negative cotangent weights are clamped to zero (see
/// [`CotanLaplacian::implicit_system`]): robust on any mesh, exact where all angles are acute.
pub fn mcf_step_with(
    mesh: &mut HalfedgeMesh,
    settings: &McfSettings,
    mobility: Option<&[f64]>,
    clamp_negative: bool,
) -> Result<McfStepReport, FlowError> {
    let tau = settings.tau;
    if !(tau > 0.0 && tau.is_finite()) {
        return Err(FlowError::BadTimeStep(tau));
    }
    let old = mesh.positions().to_vec();
    let mut x = old.clone();
    let lap = CotanLaplacian::new(mesh);
    let (covolume_min, covolume_mean, covolume_max) = stats(&lap.covolumes);
    let mut solve = solve_xyz_scaled(
        &lap.implicit_system(mesh, tau, mobility, clamp_negative)?,
        &old,
        &mut x,
        &settings.solver,
    )?;
    let result = (|| {
        for pass in 0..=settings.corrector_passes {
            if pass > 0 {
                let lap = CotanLaplacian::new(mesh);
                let r = solve_xyz_scaled(
                    &lap.implicit_system(mesh, tau, mobility, clamp_negative)?,
                    &old,
                    &mut x,
                    &settings.solver,
                )?;
                solve.iterations = solve.iterations.max(r.iterations);
                solve.relative_residual = solve.relative_residual.max(r.relative_residual);
            }
            if let Some(vertex) = x.iter().position(|p| !p.is_finite()) {
                return Err(FlowError::NonFinite { vertex });
            }
            mesh.positions_mut().copy_from_slice(&x);
        }
        Ok(())
    })();
    if let Err(e) = result {
        mesh.positions_mut().copy_from_slice(&old);
        return Err(e);
    }
    Ok(McfStepReport {
        solve,
        covolume_min,
        covolume_mean,
        covolume_max,
    })
}

/// Min, mean, max of a non-empty slice (zeros for an empty one).
pub fn stats(values: &[f64]) -> (f64, f64, f64) {
    if values.is_empty() {
        return (0.0, 0.0, 0.0);
    }
    let (mut lo, mut hi, mut sum) = (f64::INFINITY, f64::NEG_INFINITY, 0.0);
    for &v in values {
        lo = lo.min(v);
        hi = hi.max(v);
        sum += v;
    }
    (lo, sum / values.len() as f64, hi)
}

/// Per-vertex mean curvature `H = ½|ΔF|`, signed positive where ΔF points against the outward
/// normal direction estimated from the vertex's faces (convex regions positive).
pub fn mean_curvature(mesh: &HalfedgeMesh) -> Vec<f64> {
    let lap = CotanLaplacian::new(mesh);
    let hn = lap.apply(mesh, mesh.positions());
    let mut normals = vec![DVec3::ZERO; mesh.n_vertices()];
    for f in 0..mesh.n_faces() as u32 {
        let (n, area) = mesh.face_normal_area(f);
        for v in mesh.face_vertices(f) {
            normals[v as usize] += area * n;
        }
    }
    hn.iter()
        .zip(&normals)
        .map(|(h, n)| {
            let mag = 0.5 * h.length();
            if h.dot(*n) <= 0.0 {
                mag
            } else {
                -mag
            }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn exact_radius_law() {
        assert_eq!(exact_sphere_radius(1.0, 0.0), 1.0);
        assert!((exact_sphere_radius(1.0, 0.1875) - 0.5).abs() < 1e-15);
        assert!(exact_sphere_radius(1.0, 0.3).is_nan());
    }

    #[test]
    fn lesson_stops_before_extinction() {
        // τ = 5e-4: the radius reaches 15 % at t = 0.244375, i.e. after 489 steps.
        assert_eq!(sphere_extinction_time(2.0), 1.0);
        assert_eq!(lesson_steps_left(1.0, 5e-4, 0), 489);
        assert_eq!(lesson_steps_left(1.0, 5e-4, 480), 9);
        assert_eq!(lesson_steps_left(1.0, 5e-4, 500), 0);
        let t = 489.0 * 5e-4;
        assert!(exact_sphere_radius(1.0, t) <= LESSON_STOP_FRACTION);
        assert!(exact_sphere_radius(1.0, t - 5e-4) > LESSON_STOP_FRACTION);
        // τ = 0.01: 25 steps reach t* = 0.25 exactly; the lesson stops at 24 (r = 0.2), where
        // the exact radius still exists.
        assert_eq!(lesson_steps_left(1.0, 0.01, 0), 24);
        assert!(exact_sphere_radius(1.0, 24.0 * 0.01).is_finite());
        // τ = 1/16: t* = 4τ, so three steps at most.
        assert_eq!(lesson_steps_left(1.0, 0.0625, 0), 3);
        assert_eq!(lesson_steps_left(1.0, 0.3, 0), 0);
        assert_eq!(lesson_steps_left(1.0, f64::NAN, 0), 0);
    }

    #[test]
    fn tau_advice_names_the_collapse() {
        let ok = lesson_tau_advice(1.0, 5e-4);
        assert!(ok.sensible && ok.warning.is_empty(), "{ok:?}");
        assert_eq!(ok.steps, 489);
        assert!(ok.tau_min < 5e-4 && 5e-4 < ok.tau_max);
        let big = lesson_tau_advice(1.0, 0.01);
        assert!(!big.sensible);
        assert!(big.warning.contains("r0²/4 = 0.25") && big.warning.contains("24 steps"));
        let huge = lesson_tau_advice(1.0, 0.5);
        assert!(huge.warning.contains("one step"), "{}", huge.warning);
        let tiny = lesson_tau_advice(1.0, 1e-6);
        assert!(!tiny.sensible && tiny.warning.contains("very small"));
        assert!(!lesson_tau_advice(1.0, -1.0).sensible);
    }

    #[test]
    fn a_step_into_extinction_is_refused() {
        assert!(check_sphere_step(1.0, 0.01, 23).is_ok());
        assert!(matches!(
            check_sphere_step(1.0, 0.01, 24),
            Err(FlowError::PastExtinction { .. })
        ));
    }

    #[test]
    fn rejects_bad_tau_without_touching_mesh() {
        let mut m = crate::geometry::icosphere::icosphere(1, 1.0, DVec3::ZERO).unwrap();
        let before = m.positions().to_vec();
        for tau in [0.0, -1.0, f64::NAN, f64::INFINITY] {
            assert!(matches!(
                mcf_step(
                    &mut m,
                    &McfSettings {
                        tau,
                        ..Default::default()
                    }
                ),
                Err(FlowError::BadTimeStep(_))
            ));
        }
        assert_eq!(m.positions(), &before[..]);
    }
}
