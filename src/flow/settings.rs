//! Settings of the LSW evolution, with the method's names and defaults (method spec §10.1), and
//! the presets users pick from. Everything (de)serialises with serde so a URL or a JSON file can
//! carry it; unknown keys are rejected by [`WrapSettings::from_json`], missing keys default.

use super::guard::GuardSettings;
use crate::field::FieldSettings;
use crate::remesh::features::FeatureSettings;
use crate::solve::SolverSettings;
use serde::{Deserialize, Serialize};

/// The starting surface.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum StartSurface {
    /// Chosen per target (measured, see the README): the exterior isosurface for targets with a
    /// signed field (closed meshes: it keeps their genus), the icosphere for point clouds and
    /// open meshes (it spans scan holes). Settings still at their full-wrap defaults follow the
    /// chosen start's own defaults ([`WrapSettings::resolved_for`]).
    Auto,
    /// An icosphere around the target's bounding box (genus 0 results).
    Icosphere,
    /// The boundary of the exterior region `d ≥ d_iso` (marching tetrahedra of the field, flooded
    /// from the grid's border) plus one remesh: keeps the genus of closed targets and never seeds
    /// the inner sheet of an unsigned field.
    Isosurface,
}

/// When the adaptive remesher runs.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum RemeshTrigger {
    /// After every step from `remesh_from_step` on (what the reference does in effect).
    Always,
    /// When some vertex's mean κ(J_Δ) exceeds `remesh_max_kappa`, or the schedule has changed
    /// the target edge lengths since the last remesh.
    QualityBand,
}

/// λ_min of the isosurface start when `auto` picks it: half the isosurface preset's 0.4. Measured
/// (quick build, 2026-11-23): spot.obj 5 268 vertices, Hausdorff 1.36 %, mean 0.012 / 0.095 % in
/// 1.1 s (0.4: 1 304 vertices, 2.51 %, 0.038 / 0.239 %; the icosphere full wrap: 1.99 %,
/// 0.058 / 0.16 % in 2.0 s); the half-resolution brain at iso 128: mean distance to the
/// iso-surface 0.52 mm (icosphere: 1.61 mm) in half the time.
pub const AUTO_ISOSURFACE_MIN_EDGE: f64 = 0.2;

/// A named bundle of settings.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Preset {
    /// The paper's bunny settings (D2 = 1 pushes into concavities), d₀ retuned for the exact field.
    FullWrap,
    /// D2 = 0: the surface stops at the first obstacle and bridges concavities.
    Obstacle,
    /// Marching-cubes start for higher-genus targets (spec §10.2).
    Isosurface,
    /// Pure mean-curvature flow of the icosphere (ε ≡ 1, η ≡ 0), for teaching and checking.
    Mcf,
}

impl Preset {
    /// All presets, in menu order.
    pub const ALL: [Preset; 4] = [
        Preset::FullWrap,
        Preset::Obstacle,
        Preset::Isosurface,
        Preset::Mcf,
    ];

    /// The preset's kebab-case name (as on the command line and in URLs).
    pub fn name(self) -> &'static str {
        match self {
            Preset::FullWrap => "full-wrap",
            Preset::Obstacle => "obstacle",
            Preset::Isosurface => "isosurface",
            Preset::Mcf => "mcf",
        }
    }

    /// Parses a kebab-case name.
    pub fn from_name(name: &str) -> Option<Preset> {
        Preset::ALL.into_iter().find(|p| p.name() == name)
    }

    /// The settings of this preset.
    pub fn settings(self) -> WrapSettings {
        let base = WrapSettings::default();
        match self {
            Preset::FullWrap => base,
            Preset::Obstacle => WrapSettings { d2: 0.0, ..base },
            Preset::Isosurface => base.with_isosurface_start(),
            Preset::Mcf => WrapSettings {
                use_target: false,
                remesh: false,
                schedule: vec![],
                steps: 100,
                ..base
            },
        }
    }
}

/// Every setting of a wrap. Lengths a user sets are relative to the target (cells of the
/// distance grid, or multiples of the start surface); τ, C1, C2, D1 act in the stabilised frame
/// (spec §3), which is what makes them scale-free.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct WrapSettings {
    /// Start surface. Default auto.
    pub start: StartSurface,
    /// Icosphere subdivision level s (0–7). Default 2 (162 vertices).
    pub icosphere_level: u32,
    /// Icosphere radius as a multiple of the paper's rule `r = 0.4·(β_min + 1.5·β_max)`
    /// (β = bounding-box sides). Range 0.1–10; default 1.
    pub icosphere_radius_factor: f64,
    /// Initial time step τ (stabilised frame). Range (0, 10]; default 0.07.
    pub tau: f64,
    /// Step limit N_t. Default 146 (the reference's bunny run).
    pub steps: u32,
    /// C1: strength of the curvature term ε(δ) = C1·(1 − exp(−δ²/C2)). Default 1.
    pub c1: f64,
    /// C2: width of ε's cut-off near the target (squared stabilised length). Default 1.
    pub c2: f64,
    /// D1: strength of the advection η = D1·δ·(cos θ − D2·sin θ). Default 2.
    pub d1: f64,
    /// D2: full-wrap push into concavities (0 = obstacle). Default 1.
    pub d2: f64,
    /// ω: tangential redistribution weight, ρ = ω·ε. Range 0–1; default 0.05.
    pub tangential_weight: f64,
    /// ε⁺: no curvature motion where δ = d − d₀ < 0. Default true.
    pub mcf_positive_support: bool,
    /// η⁺: no advection where δ < 0. Default true.
    pub advection_positive_support: bool,
    /// d₀ as a multiple of half the voxel diagonal (√3/2·c_G): the surface settles where the
    /// field equals d₀. Range 0–10; default 1.0 (the reference used 2.0 on a field that
    /// overestimates distances ×1.7; our field is exact near the target).
    pub iso_level_factor: f64,
    /// σ: the stabilisation scales the start so its mean co-volume is τ/σ. Default 0.2.
    pub shrink_factor: f64,
    /// Steps after which sizes shrink by λ_dec, τ by λ_dec² and D1 grows by 1/λ_dec.
    /// Default [3, 10, 20, 50, 100, 120, 140, 145].
    pub schedule: Vec<u32>,
    /// λ_dec, the schedule's decay factor. Range (0, 1]; default 0.7.
    pub decay: f64,
    /// False: ignore the target (ε ≡ 1, η ≡ 0), i.e. pure MCF. Default true.
    pub use_target: bool,
    /// Adaptive remeshing on. Default true.
    pub remesh: bool,
    /// First step after which remeshing may run. Default 4 (the fresh icosphere needs none).
    pub remesh_from_step: u32,
    /// When to remesh. Default always (from `remesh_from_step`). Measured on the bunny: the
    /// quality band alone remeshes 18 times instead of 143 (remesh time 0.12 s vs 0.85 s) and ends
    /// closer to the scan, but lets slivers live long enough to stall the solver on spot; with
    /// the schedule also triggering it remeshes after every size change and matches `always`.
    pub remesh_trigger: RemeshTrigger,
    /// Vertex-averaged κ(J_Δ) (equilateral = 1) above which [`RemeshTrigger::QualityBand`]
    /// remeshes. Default 1.5.
    pub remesh_max_kappa: f64,
    /// λ_min: l_min as a fraction of the start surface's edge (icosphere) or of √2·c (isosurface).
    /// Default 0.14.
    pub min_edge_multiplier: f64,
    /// Remeshing outer iterations per call. Default 2.
    pub remesh_iterations: u32,
    /// Tangential smoothing passes per remeshing iteration. Default 5.
    pub smoothing_iterations: u32,
    /// Feature detection in the remesher (re-detected each call). Default off.
    pub features: FeatureSettings,
    /// Isosurface start: d_iso in cells of the distance grid (raised to 1.1·d₀ if below d₀).
    /// Default 1.5.
    pub isosurface_level_cells: f64,
    /// Isosurface start: marching-cubes cell size as a multiple of the field's. Range 0.5–8;
    /// default 1.5.
    pub isosurface_resampling: f64,
    /// Stop early when this fraction of vertices moved less than `stop_displacement_cells` in the
    /// last step (only after the last schedule step). Range (0, 1]; default 0.98.
    pub stop_fraction: f64,
    /// Stop threshold on per-step displacement, in cells of the distance grid. Default 0.002
    /// (the approach to d₀ is exponential at a few % per step, so this leaves ≈ 0.05 cells).
    pub stop_displacement_cells: f64,
    /// Final fit: when the evolution ends, move the surface from the offset level set d = d₀ onto
    /// the target along the normals (plane fits to the cloud, or closest points on a mesh).
    /// Default true.
    pub final_fit: bool,
    /// Final fit: neighbourhood radius of the plane fit, in cells. Default 2.
    pub fit_radius_cells: f64,
    /// Final fit: longest move of a vertex, in cells (longer moves, e.g. across a hole in the
    /// scan, are refused). Default 2.5.
    pub fit_max_move_cells: f64,
    /// Final fit: passes (normals are recomputed between passes). Default 2.
    pub fit_passes: u32,
    /// Times a failed step is retried with τ halved before giving up. Default 4.
    pub max_retries: u32,
    /// Guards: contact (no self-intersection) and divergence.
    pub guard: GuardSettings,
    /// Distance-field settings.
    pub field: FieldSettings,
    /// Linear-solver settings.
    pub solver: SolverSettings,
}

impl Default for WrapSettings {
    fn default() -> Self {
        Self {
            start: StartSurface::Auto,
            icosphere_level: 2,
            icosphere_radius_factor: 1.0,
            tau: 0.07,
            steps: 146,
            c1: 1.0,
            c2: 1.0,
            d1: 2.0,
            d2: 1.0,
            tangential_weight: 0.05,
            mcf_positive_support: true,
            advection_positive_support: true,
            iso_level_factor: 1.0,
            shrink_factor: 0.2,
            schedule: vec![3, 10, 20, 50, 100, 120, 140, 145],
            decay: 0.7,
            use_target: true,
            remesh: true,
            remesh_from_step: 4,
            remesh_trigger: RemeshTrigger::Always,
            remesh_max_kappa: 1.5,
            min_edge_multiplier: 0.14,
            remesh_iterations: 2,
            smoothing_iterations: 5,
            features: FeatureSettings::default(),
            isosurface_level_cells: 1.5,
            isosurface_resampling: 1.5,
            stop_fraction: 0.98,
            stop_displacement_cells: 0.002,
            final_fit: true,
            fit_radius_cells: 2.0,
            fit_max_move_cells: 2.5,
            fit_passes: 2,
            max_retries: 4,
            guard: GuardSettings::default(),
            field: FieldSettings::default(),
            solver: SolverSettings::default(),
        }
    }
}

/// A setting out of its range.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("setting {name} = {value} is out of range ({range})")]
pub struct SettingError {
    /// The setting's name.
    pub name: &'static str,
    /// The offending value.
    pub value: f64,
    /// The allowed range.
    pub range: &'static str,
}

impl WrapSettings {
    /// These settings with the isosurface start and its parameters (spec §10.2): 20 steps of
    /// τ = 0.05, C1 = D1 = 1/(1 − e⁻⁴) (the reference's `PreComputeAdvectionDiffusionParams(2.0)`),
    /// no size schedule, λ_min = 0.4, 3 remesh iterations from step 1.
    pub fn with_isosurface_start(self) -> Self {
        let c = 1.0 / (1.0 - (-4.0f64).exp());
        WrapSettings {
            start: StartSurface::Isosurface,
            steps: 20,
            tau: 0.05,
            c1: c,
            d1: c,
            iso_level_factor: 1.0,
            schedule: vec![],
            min_edge_multiplier: 0.4,
            remesh_iterations: 3,
            remesh_from_step: 1,
            ..self
        }
    }

    /// Resolves [`StartSurface::Auto`] for a target whose field is signed (`signed`) or not: the
    /// start becomes isosurface or icosphere. With the isosurface start (chosen or resolved),
    /// every parameter the isosurface start has its own default for takes that default if it is
    /// still at the full-wrap default (a value the user changed is kept).
    pub fn resolved_for(self, signed: bool) -> Self {
        match self.start {
            StartSurface::Icosphere => return self,
            StartSurface::Auto if !signed => {
                return WrapSettings {
                    start: StartSurface::Icosphere,
                    ..self
                }
            }
            // Auto on a signed field, or an explicit isosurface start: the isosurface start's
            // own defaults (its sizes are relative to the grid cell, so the full-wrap schedule
            // would shrink them to millions of vertices).
            _ => {}
        }
        let (d, mut iso) = (
            WrapSettings::default(),
            WrapSettings::default().with_isosurface_start(),
        );
        if self.start == StartSurface::Auto {
            iso.min_edge_multiplier = AUTO_ISOSURFACE_MIN_EDGE;
        }
        let pick = |mine: f64, def: f64, theirs: f64| if mine == def { theirs } else { mine };
        WrapSettings {
            start: StartSurface::Isosurface,
            steps: if self.steps == d.steps {
                iso.steps
            } else {
                self.steps
            },
            tau: pick(self.tau, d.tau, iso.tau),
            c1: pick(self.c1, d.c1, iso.c1),
            d1: pick(self.d1, d.d1, iso.d1),
            iso_level_factor: pick(
                self.iso_level_factor,
                d.iso_level_factor,
                iso.iso_level_factor,
            ),
            schedule: if self.schedule == d.schedule {
                iso.schedule.clone()
            } else {
                self.schedule.clone()
            },
            min_edge_multiplier: pick(
                self.min_edge_multiplier,
                d.min_edge_multiplier,
                iso.min_edge_multiplier,
            ),
            remesh_iterations: if self.remesh_iterations == d.remesh_iterations {
                iso.remesh_iterations
            } else {
                self.remesh_iterations
            },
            remesh_from_step: if self.remesh_from_step == d.remesh_from_step {
                iso.remesh_from_step
            } else {
                self.remesh_from_step
            },
            ..self
        }
    }

    /// Checks ranges (the field and solver settings are checked where they are used).
    pub fn check(&self) -> Result<(), SettingError> {
        let checks: [(&'static str, f64, bool, &'static str); 12] = [
            (
                "icosphere_level",
                self.icosphere_level as f64,
                self.icosphere_level <= 7,
                "0–7",
            ),
            (
                "icosphere_radius_factor",
                self.icosphere_radius_factor,
                (0.1..=10.0).contains(&self.icosphere_radius_factor),
                "0.1–10",
            ),
            (
                "tau",
                self.tau,
                self.tau > 0.0 && self.tau <= 10.0,
                "(0, 10]",
            ),
            (
                "steps",
                self.steps as f64,
                self.steps <= 100_000,
                "0–100000",
            ),
            ("c2", self.c2, self.c2 > 0.0 && self.c2.is_finite(), "> 0"),
            (
                "tangential_weight",
                self.tangential_weight,
                (0.0..=1.0).contains(&self.tangential_weight),
                "0–1",
            ),
            (
                "iso_level_factor",
                self.iso_level_factor,
                (0.0..=10.0).contains(&self.iso_level_factor),
                "0–10",
            ),
            (
                "shrink_factor",
                self.shrink_factor,
                self.shrink_factor > 0.0 && self.shrink_factor <= 10.0,
                "(0, 10]",
            ),
            (
                "decay",
                self.decay,
                self.decay > 0.0 && self.decay <= 1.0,
                "(0, 1]",
            ),
            (
                "min_edge_multiplier",
                self.min_edge_multiplier,
                self.min_edge_multiplier > 0.0 && self.min_edge_multiplier <= 10.0,
                "(0, 10]",
            ),
            (
                "stop_fraction",
                self.stop_fraction,
                self.stop_fraction > 0.0 && self.stop_fraction <= 1.0,
                "(0, 1]",
            ),
            (
                "isosurface_resampling",
                self.isosurface_resampling,
                (0.5..=8.0).contains(&self.isosurface_resampling),
                "0.5–8",
            ),
        ];
        for (name, value, ok, range) in checks {
            if !ok || !value.is_finite() {
                return Err(SettingError { name, value, range });
            }
        }
        for (name, value) in [("c1", self.c1), ("d1", self.d1), ("d2", self.d2)] {
            if !(value >= 0.0 && value.is_finite()) {
                return Err(SettingError {
                    name,
                    value,
                    range: "≥ 0",
                });
            }
        }
        Ok(())
    }

    /// Parses settings from JSON; missing keys take their defaults, unknown keys are an error.
    pub fn from_json(json: &str) -> Result<Self, serde_json::Error> {
        serde_json::from_str(json)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn auto_start_resolves_by_signedness_and_keeps_user_values() {
        let auto = WrapSettings::default();
        assert_eq!(auto.start, StartSurface::Auto);
        let cloud = auto.clone().resolved_for(false);
        assert_eq!(cloud.start, StartSurface::Icosphere);
        assert_eq!(cloud.steps, auto.steps);
        let closed = auto.clone().resolved_for(true);
        assert_eq!(
            closed,
            WrapSettings {
                min_edge_multiplier: AUTO_ISOSURFACE_MIN_EDGE,
                ..WrapSettings::default().with_isosurface_start()
            }
        );
        // An explicit isosurface start gets the same defaults; a changed τ survives.
        let mine = WrapSettings {
            start: StartSurface::Isosurface,
            tau: 0.01,
            ..Default::default()
        }
        .resolved_for(false);
        assert_eq!((mine.tau, mine.steps, mine.schedule.len()), (0.01, 20, 0));
        let ico = WrapSettings {
            start: StartSurface::Icosphere,
            ..Default::default()
        };
        assert_eq!(ico.clone().resolved_for(true), ico);
    }

    #[test]
    fn presets_round_trip_and_check() {
        for p in Preset::ALL {
            let s = p.settings();
            s.check().unwrap();
            let json = serde_json::to_string(&s).unwrap();
            assert_eq!(WrapSettings::from_json(&json).unwrap(), s);
            assert_eq!(Preset::from_name(p.name()), Some(p));
        }
        assert_eq!(Preset::Obstacle.settings().d2, 0.0);
        assert!(WrapSettings::from_json(r#"{"tau": 0.01}"#).unwrap().tau == 0.01);
        assert!(WrapSettings::from_json(r#"{"bogus": 1}"#).is_err());
        let bad = WrapSettings {
            tau: -1.0,
            ..Default::default()
        };
        assert_eq!(bad.check().unwrap_err().name, "tau");
    }
}
