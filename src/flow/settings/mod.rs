//! Settings of a wrap, nested by stage (start, field, flow, remesh, fit, guard, surgery, solver,
//! stop), with the method's names and defaults (docs/method.md §10.1), and the presets users pick
//! from.
//! Everything (de)serialises with serde so a URL or a JSON file can carry it; unknown keys are
//! rejected by [`WrapSettings::from_json`], missing keys default, and the flat keys of the first
//! releases are still read ([`aliases`]).

pub mod aliases;
pub mod docs;
mod stages;
pub mod tuning;

pub use stages::{
    FieldParams, FitSettings, FlowSettings, RemeshTrigger, RemeshingSettings, StartSettings,
    StartSurface, StopSettings, SurgerySettings,
};
pub use tuning::{FieldTuning, Tuning};

use crate::field::FieldSettings;
use serde::{Deserialize, Serialize};

/// λ_min of the isosurface start when `auto` picks it: half the isosurface preset's 0.4, fine
/// enough that the automatic start fits closer than the icosphere full wrap without its cost
/// (see docs/decisions/).
pub const AUTO_ISOSURFACE_MIN_EDGE: f64 = 0.2;

/// A named bundle of settings.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Preset {
    /// The paper's settings (D2 = 1 pushes into concavities), d₀ retuned for the exact field.
    FullWrap,
    /// D2 = 0: the surface stops at the first obstacle and bridges concavities.
    Obstacle,
    /// Marching-cubes start for higher-genus targets (docs/method.md §10.2).
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

    /// The preset's name in menus.
    pub fn label(self) -> &'static str {
        match self {
            Preset::FullWrap => "full-wrap",
            Preset::Obstacle => "obstacle",
            Preset::Isosurface => "isosurface start",
            Preset::Mcf => "MCF (ignore target)",
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
            Preset::Obstacle => {
                let mut s = base;
                s.flow.d2 = 0.0;
                s
            }
            Preset::Isosurface => base.with_isosurface_start(),
            Preset::Mcf => {
                let mut s = base;
                s.flow.use_target = false;
                s.flow.schedule = vec![];
                s.remesh.enabled = false;
                s.stop.steps = 100;
                s
            }
        }
    }
}

/// Every setting of a wrap: the method's parameters and the user's controls by stage, and the
/// tuning table's values apart ([`Tuning`]). Lengths are relative to the target (cells of the
/// distance grid, or multiples of the start surface).
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct WrapSettings {
    /// The start surface: icosphere, isosurface of the field, or chosen per target.
    pub start: StartSettings,
    /// The distance field: grid, near band, sign.
    pub field: FieldParams,
    /// The evolution: time step, curvature and advection controls, size schedule.
    pub flow: FlowSettings,
    /// Adaptive remeshing: when, how often, edge sizes, features.
    pub remesh: RemeshingSettings,
    /// The final fit onto the target.
    pub fit: FitSettings,
    /// Topology surgery: handles open where two membranes meet in empty space.
    pub surgery: SurgerySettings,
    /// When the evolution ends.
    pub stop: StopSettings,
    /// The heuristics and constants, from a version of the tuning table (docs/decisions/).
    pub tuning: Tuning,
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

/// The finest icosphere start of a wrap (see [`WrapSettings::check`]).
pub const MAX_WRAP_ICOSPHERE_LEVEL: u32 = 3;

/// The allowed range of a numeric setting: one table read by [`WrapSettings::check`], the app's
/// Expert panel (limits and tooltips) and the CLI's error messages.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct SettingRange {
    /// The setting's key (nested form).
    pub key: &'static str,
    /// Lower and upper limit (infinite when unbounded).
    pub min: f64,
    pub max: f64,
    /// Whether the lower limit itself is excluded.
    pub min_open: bool,
    /// The range as shown to users.
    pub text: &'static str,
}

impl SettingRange {
    const fn new(
        key: &'static str,
        min: f64,
        max: f64,
        min_open: bool,
        text: &'static str,
    ) -> Self {
        Self {
            key,
            min,
            max,
            min_open,
            text,
        }
    }

    /// Whether `v` is finite and in the range.
    pub fn contains(&self, v: f64) -> bool {
        v.is_finite()
            && (if self.min_open {
                v > self.min
            } else {
                v >= self.min
            })
            && v <= self.max
    }
}

/// The ranges [`WrapSettings::check`] enforces, in the order it checks them.
pub const RANGES: &[SettingRange] = &[
    SettingRange::new("start.icosphere_level", 0.0, 7.0, false, "0–7"),
    SettingRange::new("start.icosphere_radius_factor", 0.1, 10.0, false, "0.1–10"),
    SettingRange::new("flow.tau", 0.0, 10.0, true, "(0, 10]"),
    SettingRange::new("stop.steps", 0.0, 100_000.0, false, "0–100000"),
    SettingRange::new("flow.c2", 0.0, f64::INFINITY, true, "> 0"),
    SettingRange::new("flow.tangential_weight", 0.0, 1.0, false, "0–1"),
    SettingRange::new("flow.iso_level_factor", 0.0, 10.0, false, "0–10"),
    SettingRange::new("tuning.flow.cover_gaps", 1.0, 4.0, false, "1–4"),
    SettingRange::new(
        "tuning.flow.second_pass_d2",
        0.0,
        f64::INFINITY,
        false,
        "≥ 0",
    ),
    SettingRange::new("tuning.flow.deflate_far", 0.0, 100.0, false, "0–100"),
    SettingRange::new("flow.shrink_factor", 0.0, 10.0, true, "(0, 10]"),
    SettingRange::new("flow.decay", 0.0, 1.0, true, "(0, 1]"),
    SettingRange::new("remesh.min_edge_multiplier", 0.0, 10.0, true, "(0, 10]"),
    SettingRange::new("tuning.remesh.every", 1.0, 1000.0, false, "1–1000"),
    SettingRange::new("stop.fraction", 0.0, 1.0, true, "(0, 1]"),
    SettingRange::new("start.isosurface_resampling", 0.5, 8.0, false, "0.5–8"),
    SettingRange::new("tuning.start.part_gap", 0.0, 1.0, false, "0–1"),
    SettingRange::new("flow.c1", 0.0, f64::INFINITY, false, "≥ 0"),
    SettingRange::new("flow.d1", 0.0, f64::INFINITY, false, "≥ 0"),
    SettingRange::new("flow.d2", 0.0, f64::INFINITY, false, "≥ 0"),
    SettingRange::new("tuning.flow.regrow_depth", 0.0, 100.0, false, "0–100"),
    SettingRange::new("tuning.flow.regrow_cells", 0.0, 1000.0, false, "0–1000"),
    SettingRange::new("tuning.flow.regrow_edges", 0.0, 100.0, false, "0–100"),
    SettingRange::new("tuning.fit.max_points", 6.0, 1e6, false, "6–1000000"),
    SettingRange::new("fit.crease_angle_deg", 0.0, 180.0, false, "0–180"),
    SettingRange::new("tuning.fit.refine_error_cells", 0.0, 1e6, false, "≥ 0"),
    SettingRange::new("tuning.fit.refine_passes", 0.0, 10.0, false, "0–10"),
    SettingRange::new("tuning.fit.volume_refine_passes", 0.0, 10.0, false, "0–10"),
    SettingRange::new("tuning.fit.refine_max_vertices", 100.0, 1e9, false, "≥ 100"),
    SettingRange::new("tuning.surgery.check_every", 1.0, 1e6, false, "≥ 1"),
    SettingRange::new("tuning.surgery.empty_cells", 0.0, 1e6, false, "≥ 0"),
    SettingRange::new("tuning.surgery.empty_spacings", 0.0, 1e6, false, "≥ 0"),
    SettingRange::new("tuning.surgery.gap_ratio", 0.0, 1.0, true, "(0, 1]"),
    SettingRange::new("tuning.surgery.tunnel_ratio", 0.0, 1e6, false, "≥ 0"),
    SettingRange::new("tuning.surgery.min_vertices", 3.0, 1e9, false, "≥ 3"),
    SettingRange::new("surgery.close_gaps", 0.0, 1.0, false, "0–1"),
];

impl WrapSettings {
    /// These settings with the isosurface start and its parameters (docs/method.md §10.2): 20
    /// steps of τ = 0.05, C1 = D1 = 1/(1 − e⁻⁴) (the reference's
    /// `PreComputeAdvectionDiffusionParams(2.0)`), no size schedule, λ_min = 0.4, 3 remesh
    /// iterations from step 1.
    pub fn with_isosurface_start(mut self) -> Self {
        let c = 1.0 / (1.0 - crate::fmath::exp(-4.0f64));
        self.start.surface = StartSurface::Isosurface;
        self.stop.steps = 20;
        self.flow.tau = 0.05;
        self.flow.c1 = c;
        self.flow.d1 = c;
        self.flow.iso_level_factor = 1.0;
        self.flow.schedule = vec![];
        self.remesh.min_edge_multiplier = 0.4;
        self.remesh.iterations = 3;
        self.remesh.from_step = 1;
        self
    }

    /// Resolves [`StartSurface::Auto`] for a target whose field is signed (`signed`) or not: the
    /// start becomes isosurface or icosphere. With the isosurface start (chosen or resolved),
    /// every parameter the isosurface start has its own default for takes that default if it is
    /// still at the full-wrap default (a value the user changed is kept).
    pub fn resolved_for(mut self, signed: bool) -> Self {
        match self.start.surface {
            StartSurface::Icosphere => return self,
            StartSurface::Auto if !signed => {
                self.start.surface = StartSurface::Icosphere;
                return self;
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
        if self.start.surface == StartSurface::Auto {
            iso.remesh.min_edge_multiplier = AUTO_ISOSURFACE_MIN_EDGE;
        }
        fn pick<T: PartialEq>(mine: &mut T, def: T, theirs: T) {
            if *mine == def {
                *mine = theirs;
            }
        }
        self.start.surface = StartSurface::Isosurface;
        pick(&mut self.stop.steps, d.stop.steps, iso.stop.steps);
        pick(&mut self.flow.tau, d.flow.tau, iso.flow.tau);
        pick(&mut self.flow.c1, d.flow.c1, iso.flow.c1);
        pick(&mut self.flow.d1, d.flow.d1, iso.flow.d1);
        pick(
            &mut self.flow.iso_level_factor,
            d.flow.iso_level_factor,
            iso.flow.iso_level_factor,
        );
        pick(&mut self.flow.schedule, d.flow.schedule, iso.flow.schedule);
        pick(
            &mut self.remesh.min_edge_multiplier,
            d.remesh.min_edge_multiplier,
            iso.remesh.min_edge_multiplier,
        );
        pick(
            &mut self.remesh.iterations,
            d.remesh.iterations,
            iso.remesh.iterations,
        );
        pick(
            &mut self.remesh.from_step,
            d.remesh.from_step,
            iso.remesh.from_step,
        );
        self
    }

    /// The distance field's options: its parameters and its tuning.
    pub fn field_options(&self) -> FieldSettings {
        let (p, t) = (&self.field, &self.tuning.field);
        FieldSettings {
            cells_per_min_dimension: p.cells_per_min_dimension,
            expansion: p.expansion,
            margin_cells: None,
            band_cells: p.band_cells,
            truncation: t.truncation,
            sign: p.sign,
            max_sweep_passes: t.max_sweep_passes,
            sweep_tolerance: t.sweep_tolerance,
            memory_cap_bytes: p.memory_cap_bytes,
            min_cell_spacings: t.min_cell_spacings,
            outlier_spacings: t.outlier_spacings,
            principal_slack: t.principal_slack,
            enclosed_cells: t.enclosed_cells,
        }
    }

    /// [`Self::field_options`] for a wrap that starts from an isosurface of a target with an
    /// inside: with `tuning.field.isosurface_margin`, the box keeps of the ζ·β_min an icosphere
    /// needs only the room that start needs — its level or the band, whichever is wider, and 2
    /// cells for the exterior's flood and the gradient (see [`FieldSettings::margin_cells`]).
    pub fn isosurface_field_options(&self) -> FieldSettings {
        let d0_cells = self.flow.iso_level_factor * 0.5 * 3f64.sqrt();
        let level = self.start.isosurface_level_cells.max(1.1 * d0_cells);
        FieldSettings {
            margin_cells: self
                .tuning
                .field
                .isosurface_margin
                .then(|| (level.max(self.field.band_cells) + 2.0).min(64.0)),
            ..self.field_options()
        }
    }

    /// Checks every setting of [`RANGES`] (the field and solver settings are checked where they
    /// are used), in the table's order.
    pub fn check(&self) -> Result<(), SettingError> {
        let json = serde_json::to_value(self).unwrap_or_default();
        for r in RANGES {
            let value = r
                .key
                .split('.')
                .try_fold(&json, |v, k| v.get(k))
                .and_then(serde_json::Value::as_f64)
                .unwrap_or(f64::NAN);
            if !r.contains(value) {
                return Err(SettingError {
                    name: r.key,
                    value,
                    range: r.text,
                });
            }
        }
        // A wrap's edge sizes follow its icosphere start's edges, so each level quadruples its
        // vertices, and the run time grows faster still. Flow without a target (MCF) may go
        // finer.
        let level = self.start.icosphere_level;
        if self.flow.use_target
            && self.start.surface != StartSurface::Isosurface
            && level > MAX_WRAP_ICOSPHERE_LEVEL
        {
            return Err(SettingError {
                name: "start.icosphere_level",
                value: level as f64,
                range: "0–3 for a wrap's icosphere start, 0–7 for flow alone",
            });
        }
        Ok(())
    }

    /// Parses settings from JSON, nested or with the old flat keys ([`aliases`]); missing keys
    /// take their defaults, unknown keys are an error.
    pub fn from_json(json: &str) -> Result<Self, serde_json::Error> {
        Self::from_value(serde_json::from_str(json)?)
    }

    /// [`Self::from_json`] on a parsed value.
    pub fn from_value(value: serde_json::Value) -> Result<Self, serde_json::Error> {
        serde_json::from_value(aliases::migrate(value))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// With `tuning.field.isosurface_margin`, an isosurface start's field grows by the start's
    /// room (the band's 3 cells, wider than the 1.5-cell level, and 2 more); without it, and for
    /// the icosphere's options, by ζ·β_min.
    #[test]
    fn an_isosurface_start_gets_the_room_it_needs() {
        let mut s = WrapSettings::default();
        assert_eq!(s.isosurface_field_options().margin_cells, None);
        s.tuning.field.isosurface_margin = true;
        assert_eq!(s.isosurface_field_options().margin_cells, Some(5.0));
        assert_eq!(s.field_options().margin_cells, None);
        let mut wide_level = s.clone();
        wide_level.start.isosurface_level_cells = 6.0;
        assert_eq!(
            wide_level.isosurface_field_options().margin_cells,
            Some(8.0)
        );
        let mut old = s.clone();
        old.tuning = Tuning::at(1).unwrap();
        assert_eq!(old.isosurface_field_options().margin_cells, None);
    }

    /// A wrap's icosphere start finer than level 3 is refused by name (its vertex count would
    /// run away); flow without a target and an isosurface start take any level of the table.
    #[test]
    fn a_wrap_refuses_an_icosphere_start_that_would_run_away() {
        let mut s = WrapSettings::default();
        s.start.icosphere_level = MAX_WRAP_ICOSPHERE_LEVEL;
        assert!(s.check().is_ok());
        s.start.icosphere_level = MAX_WRAP_ICOSPHERE_LEVEL + 1;
        let e = s.check().unwrap_err();
        assert_eq!((e.name, e.value), ("start.icosphere_level", 4.0));
        s.start.surface = StartSurface::Isosurface;
        assert!(s.check().is_ok());
        s.start.surface = StartSurface::Icosphere;
        s.flow.use_target = false;
        s.start.icosphere_level = 7;
        assert!(s.check().is_ok());
    }

    /// The parameters stay few: a rule for a class of inputs belongs in the tuning table.
    #[test]
    fn at_most_forty_parameters_outside_the_tuning_table() {
        fn leaves(v: &serde_json::Value) -> usize {
            v.as_object().map_or(1, |m| m.values().map(leaves).sum())
        }
        let mut json = serde_json::to_value(WrapSettings::default()).unwrap();
        let tuning = json.as_object_mut().unwrap().remove("tuning").unwrap();
        let n = leaves(&json);
        assert!(n <= 40, "{n} parameters");
        assert!(
            leaves(&tuning) > n / 2,
            "the tuning table is where the rest went"
        );
    }

    #[test]
    fn the_field_options_are_the_field_modules_defaults() {
        assert_eq!(
            WrapSettings::default().field_options(),
            FieldSettings::default()
        );
    }

    #[test]
    fn auto_start_resolves_by_signedness_and_keeps_user_values() {
        let auto = WrapSettings::default();
        assert_eq!(auto.start.surface, StartSurface::Auto);
        let cloud = auto.clone().resolved_for(false);
        assert_eq!(cloud.start.surface, StartSurface::Icosphere);
        assert_eq!(cloud.stop.steps, auto.stop.steps);
        let closed = auto.clone().resolved_for(true);
        assert_eq!(closed, {
            let mut w = WrapSettings::default().with_isosurface_start();
            w.remesh.min_edge_multiplier = AUTO_ISOSURFACE_MIN_EDGE;
            w
        });
        // An explicit isosurface start gets the same defaults; a changed τ survives.
        let mine = {
            let mut w = WrapSettings::default();
            w.start.surface = StartSurface::Isosurface;
            w.flow.tau = 0.01;
            w
        }
        .resolved_for(false);
        assert_eq!(
            (mine.flow.tau, mine.stop.steps, mine.flow.schedule.len()),
            (0.01, 20, 0)
        );
        let ico = {
            let mut w = WrapSettings::default();
            w.start.surface = StartSurface::Icosphere;
            w
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
        assert_eq!(Preset::Obstacle.settings().flow.d2, 0.0);
        assert!(
            WrapSettings::from_json(r#"{"tau": 0.01}"#)
                .unwrap()
                .flow
                .tau
                == 0.01
        );
        assert!(WrapSettings::from_json(r#"{"bogus": 1}"#).is_err());
        let bad = {
            let mut w = WrapSettings::default();
            w.flow.tau = -1.0;
            w
        };
        assert_eq!(bad.check().unwrap_err().name, "flow.tau");
        // Every range names a numeric setting; its limits are in or out as documented.
        let json = serde_json::to_value(WrapSettings::default()).unwrap();
        for r in RANGES {
            let v = r.key.split('.').try_fold(&json, |v, k| v.get(k));
            assert!(v.and_then(|v| v.as_f64()).is_some(), "{}", r.key);
            assert_eq!(r.contains(r.min), !r.min_open, "{}", r.key);
            assert!(
                !r.contains(f64::NAN) && !r.contains(r.min - 1.0),
                "{}",
                r.key
            );
        }
        let mut c2 = WrapSettings::default();
        c2.flow.c2 = f64::INFINITY;
        assert_eq!(c2.check().unwrap_err().name, "flow.c2");
    }

    /// Settings JSON saved by the flat-settings releases (every old key, non-default values)
    /// decodes to the same settings as its nested form.
    #[test]
    fn old_flat_settings_json_still_decodes() {
        let old = r#"{"start": "isosurface", "icosphere_level": 3, "icosphere_radius_factor": 1.2,
            "tau": 0.05, "steps": 30, "c1": 1.5, "c2": 2.0, "d1": 3.0, "d2": 0.0,
            "tangential_weight": 0.1, "mcf_positive_support": false,
            "advection_positive_support": false, "iso_level_factor": 2.0, "shrink_factor": 0.3,
            "schedule": [2, 4], "decay": 0.5, "use_target": true, "remesh": false,
            "remesh_from_step": 2, "remesh_trigger": "quality_band", "remesh_max_kappa": 1.7,
            "min_edge_multiplier": 0.2, "remesh_iterations": 3, "smoothing_iterations": 4,
            "features": {"detector": "both"}, "isosurface_level_cells": 2.5,
            "isosurface_resampling": 2.0, "stop_fraction": 0.9, "stop_displacement_cells": 0.01,
            "final_fit": false, "fit_radius_cells": 3.0, "fit_max_move_cells": 4.0,
            "fit_passes": 1, "max_retries": 2, "guard": {"check_every": 4},
            "field": {"band_cells": 4.0}, "solver": {"max_iterations": 50}}"#;
        let s = WrapSettings::from_json(old).unwrap();
        let mut tuning = Tuning::default();
        tuning.flow.max_retries = 2;
        tuning.remesh.max_kappa = 1.7;
        tuning.remesh.features.detector = crate::remesh::FeatureDetector::Both;
        tuning.guard.check_every = 4;
        tuning.solver.max_iterations = 50;
        let want = WrapSettings {
            start: StartSettings {
                surface: StartSurface::Isosurface,
                icosphere_level: 3,
                icosphere_radius_factor: 1.2,
                isosurface_level_cells: 2.5,
                isosurface_resampling: 2.0,
            },
            flow: FlowSettings {
                use_target: true,
                tau: 0.05,
                c1: 1.5,
                c2: 2.0,
                d1: 3.0,
                d2: 0.0,
                tangential_weight: 0.1,
                mcf_positive_support: false,
                advection_positive_support: false,
                iso_level_factor: 2.0,
                shrink_factor: 0.3,
                schedule: vec![2, 4],
                decay: 0.5,
            },
            remesh: RemeshingSettings {
                enabled: false,
                from_step: 2,
                trigger: RemeshTrigger::QualityBand,
                min_edge_multiplier: 0.2,
                iterations: 3,
                smoothing_iterations: 4,
            },
            fit: FitSettings {
                enabled: false,
                radius_cells: 3.0,
                max_move_cells: 4.0,
                passes: 1,
                crease_angle_deg: 40.0,
            },
            stop: StopSettings {
                steps: 30,
                fraction: 0.9,
                displacement_cells: 0.01,
            },
            surgery: SurgerySettings::default(),
            field: FieldParams {
                band_cells: 4.0,
                ..Default::default()
            },
            tuning,
        };
        assert_eq!(s, want);
        // The nested form round-trips, and the old keys cover every leaf they name.
        let json = serde_json::to_string(&want).unwrap();
        assert_eq!(WrapSettings::from_json(&json).unwrap(), want);
        assert_eq!(aliases::ALIASES.len(), 34);
    }
}
