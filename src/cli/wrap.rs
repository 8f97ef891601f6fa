//! `lsw wrap INPUT -o OUTPUT`: the whole pipeline, read → field → start surface → evolve → write.

use crate::flow::{Preset, StepReport, WrapSettings};
use crate::io::{read_path_with, write_path, ReadResult, WriteInput};
use crate::metrics::error_budget::error_budget;
use crate::pipeline::{wrap, Observer, WrapResult};
use serde_json::{json, Value};
use std::path::{Path, PathBuf};

/// Arguments of `lsw wrap`.
#[derive(clap::Args, Debug)]
pub struct WrapArgs {
    /// Input point cloud, mesh or volume (any format of [`crate::io::FORMATS`]).
    #[arg(help = super::input_help("Input point cloud or mesh"))]
    pub input: PathBuf,
    /// Output mesh; the format follows the extension (a writable format of
    /// [`crate::io::FORMATS`]).
    #[arg(short, long, help = super::output_help("Output mesh"))]
    pub output: PathBuf,
    /// Settings preset: one of [`Preset::ALL`].
    #[arg(long, default_value = "full-wrap", help = super::preset_help())]
    pub preset: String,
    /// Step limit (overrides the preset's).
    #[arg(long)]
    pub steps: Option<u32>,
    /// Any setting as key=value (JSON value; dotted keys reach nested settings, e.g.
    /// field.cells_per_min_dimension=60). Repeatable.
    #[arg(long = "set", value_name = "KEY=VALUE")]
    pub set: Vec<String>,
    /// Write per-step statistics (JSON) to this file: settings, start, stop_reason, certificate,
    /// error_budget (where the remaining distance to the target comes from: features, sizing,
    /// not_reached, vertices_off, hausdorff_from; see `metrics::error_budget`), steps.
    #[arg(long)]
    pub stats: Option<PathBuf>,
    /// Start surface: auto (default: the exterior isosurface for closed meshes, an icosphere for
    /// point clouds and open meshes), icosphere or isosurface. Overrides the preset's.
    #[arg(long)]
    pub start: Option<String>,
    /// Write the mesh even when its certificate says it is not valid (or the run diverged). The
    /// exit status is still non-zero.
    #[arg(long)]
    pub keep_invalid: bool,
    /// Volume inputs: iso-value, frame, inside, array, iso-surface output.
    #[command(flatten)]
    pub volume: super::volume::VolumeArgs,
}

/// Applies `key=value` overrides to the settings' JSON form; keys are nested (`flow.tau`) or
/// earlier ones (`tau`, see [`crate::flow::settings::aliases`]); unknown keys are errors.
/// `tuning.version` comes first whatever its place: it picks the row the other values override.
pub fn apply_overrides(
    settings: WrapSettings,
    overrides: &[String],
) -> Result<WrapSettings, String> {
    let mut v = serde_json::to_value(&settings).expect("settings serialise");
    let is_version = |o: &&String| o.split('=').next() == Some("tuning.version");
    for o in overrides.iter().filter(is_version) {
        let raw = o.split_once('=').map_or("", |kv| kv.1);
        let version: Value = serde_json::from_str(raw).unwrap_or(Value::Null);
        let row: crate::flow::settings::Tuning =
            serde_json::from_value(serde_json::json!({ "version": version }))
                .map_err(|e| format!("--set {o}: {e}"))?;
        v["tuning"] = serde_json::to_value(row).expect("tuning serialises");
    }
    for o in overrides.iter().filter(|o| !is_version(o)) {
        let (key, raw) = o
            .split_once('=')
            .ok_or_else(|| format!("--set {o}: expected KEY=VALUE"))?;
        let value: Value =
            serde_json::from_str(raw).unwrap_or_else(|_| Value::String(raw.to_owned()));
        let path = crate::flow::settings::aliases::canonical_key(key);
        let mut slot = &mut v;
        for part in path.split('.') {
            slot = slot
                .as_object_mut()
                .and_then(|m| m.get_mut(part))
                .ok_or_else(|| format!("--set {o}: unknown setting \"{key}\""))?;
        }
        *slot = value;
    }
    serde_json::from_value(v).map_err(|e| format!("--set: {e}"))
}

/// Runs the wrap; JSON keys: input, output, preset, start, written, stop_reason, certificate
/// {valid, closed, manifold, oriented, finite, genus, components, euler_characteristic,
/// self_intersections, degenerate_faces, distance_min, distance_max, problem, target_genus,
/// target_components, target_points_outside, target_points_checked,
/// target_part_outside}, verdict {state (valid, warning or invalid), certified, badge,
/// headline, explanation, warnings, notes} (decided once in the core: see
/// [`crate::pipeline::Verdict`]), warnings (what the certificate shows beside `valid`, in words: a
/// genus or part count unlike the target's, a part of the target outside; also on stderr; see
/// `Certificate::warnings`), contacts,
/// surgery [{step, kind, position, genus_before, genus_after}], isolated_points_left_out (a
/// cloud's stray points, see `tuning.field.outlier_spacings`), specks_left_out (a mesh's small closed
/// parts floating apart, see `geometry::specks`), repairs (what reading mended in a mesh's
/// indices, or null; see `lsw info`), points_left_out ({points, why}: points the file marks
/// unusable that were not read, or null; see `io::LeftOut`), vertices, faces, steps, stopped_early,
/// scale, result_hash, iso_level, started_over (null, or how a target that the first pass left
/// partly outside was wrapped a second time: see `flow::StartedOver`), times_ms {read, field, start, evolve, write, total}, evolve_ms {normals,
/// assembly, solve, remesh, guard, fit, surgery, redone (steps undone and redone after a
/// failed contact check)}, fit_ms (the final fit part by part, see
/// `flow::FitTimes`), distance_mean, distance_max; for volumes also iso (the iso-value
/// wrapped) and volume (see [`super::volume::volume_json`]); error (why, when the wrap was
/// refused: the report is then the [`super::Failure`]'s, printed on stdout all the same).
pub fn run(a: &WrapArgs) -> Result<String, super::Failure> {
    let t0 = crate::clock::now_ms();
    let (preset, settings) = wrap_settings(a)?;
    let read = read_path_with(&a.input, &a.volume.options()).map_err(super::explained)?;
    a.volume.write_isosurface(&read)?;
    let t_read = crate::clock::now_ms();
    let mut observer = Steps::default();
    let w = wrap(&read.target, settings, &mut observer).map_err(super::explained)?;
    let reports = observer.reports;
    let t_evolve = crate::clock::now_ms();
    let failure = failure_of(&w);
    let written = failure.is_none() || a.keep_invalid;
    write_mesh(&a.output, &w, written)?;
    let t_write = crate::clock::now_ms();
    if let Some(path) = &a.stats {
        write_stats(path, &w, &read, &reports)?;
    }
    let clock = Clock {
        t0,
        t_read,
        t_evolve,
        t_write,
    };
    let mut report = report_json(a, preset, &w, &read, &reports, written, clock);
    if let Some(why) = &failure {
        report["error"] = Value::String(why.clone());
    }
    let out = serde_json::to_string_pretty(&report).expect("JSON of plain values");
    finish(out, failure, a.keep_invalid)
}

/// The preset named by `--preset` and its settings with `--set`, `--steps` and `--start`
/// applied.
fn wrap_settings(a: &WrapArgs) -> Result<(Preset, WrapSettings), String> {
    let preset = Preset::from_name(&a.preset).ok_or_else(|| {
        let names = Preset::ALL.map(Preset::name);
        format!("unknown preset \"{}\" (use {})", a.preset, names.join(", "))
    })?;
    let mut settings = apply_overrides(preset.settings(), &a.set)?;
    if let Some(n) = a.steps {
        settings.stop.steps = n;
    }
    if let Some(start) = &a.start {
        settings.start.surface =
            serde_json::from_value(Value::String(start.clone())).map_err(|_| {
                let options = crate::flow::settings::docs::settings_enums()
                    .into_iter()
                    .find(|(k, _)| k == "start.surface")
                    .map(|(_, v)| v.join(", "))
                    .unwrap_or_default();
                format!("unknown start surface \"{start}\" (use {options})")
            })?;
    }
    Ok((preset, settings))
}

/// Why the wrap counts as failed (it stopped early, or its result is not certified), if it does.
fn failure_of(w: &WrapResult) -> Option<String> {
    match (&w.stop_reason, w.verdict.certified) {
        (Some(why), _) => Some(format!("the wrap stopped early: {why}")),
        (None, false) => Some(format!(
            "the result is not valid: {}",
            w.certificate
                .problem
                .as_deref()
                .unwrap_or("unknown problem")
        )),
        (None, true) => None,
    }
}

/// Writes the mesh with its distances and settings to `output` when `write` says so.
fn write_mesh(output: &Path, w: &WrapResult, write: bool) -> Result<(), String> {
    let settings_json = serde_json::to_string(&w.settings).expect("settings serialise");
    let scalars = [("distance", w.distances.as_slice())];
    let input = WriteInput {
        positions: &w.positions,
        triangles: &w.triangles,
        scalars: &scalars,
        settings_json: Some(&settings_json),
    };
    if write {
        write_path(output, &input).map_err(super::explained)?;
    }
    Ok(())
}

/// Writes the `--stats` JSON: settings (the parameters, and the tuning under `tuning` with its
/// `version`), what each parameter means, start, certificate, verdict, error budget and steps.
fn write_stats(
    path: &Path,
    w: &WrapResult,
    read: &ReadResult,
    reports: &[StepReport],
) -> Result<(), String> {
    let text = serde_json::to_string_pretty(&json!({
        "settings": w.settings,
        "settings_help": crate::flow::settings::docs::parameter_docs()
            .into_iter()
            .map(|(k, doc)| (k, Value::String(doc)))
            .collect::<serde_json::Map<_, _>>(),
        "start": w.start,
        "stop_reason": w.stop_reason,
        "isolated_points_left_out": w.left_out.strays,
        "specks_left_out": w.left_out.specks,
        "certificate": w.certificate,
        "verdict": w.verdict,
        "error_budget": error_budget(
            &w.positions,
            &w.triangles,
            &read.target,
            w.cell_size,
            w.settings.fit.crease_angle_deg,
        ),
        "steps": reports,
    }))
    .expect("JSON");
    std::fs::write(path, text).map_err(|e| format!("{}: {e}", path.display()))
}

/// The clock readings of a run: start, after reading, after the wrap, after writing.
struct Clock {
    t0: f64,
    t_read: f64,
    t_evolve: f64,
    t_write: f64,
}

/// The report printed on stdout (see [`run`] for its keys).
fn report_json(
    a: &WrapArgs,
    preset: Preset,
    w: &WrapResult,
    read: &ReadResult,
    reports: &[StepReport],
    written: bool,
    clock: Clock,
) -> Value {
    let Clock {
        t0,
        t_read,
        t_evolve,
        t_write,
    } = clock;
    let sum = |f: fn(&StepReport) -> f64| reports.iter().map(f).sum::<f64>();
    let last = reports.last();
    json!({
        "input": a.input.display().to_string(),
        "output": a.output.display().to_string(),
        "preset": preset.name(),
        "start": w.start,
        "written": written,
        "stop_reason": w.stop_reason,
        "certificate": w.certificate,
        "verdict": w.verdict,
        "warnings": w.verdict.warnings,
        "contacts": {
            "steps_with_contact": reports.iter().filter(|r| r.contacts.pairs > 0).count(),
            "pairs_resolved": reports.iter().map(|r| r.contacts.pairs).sum::<usize>(),
            "remesh_reverted": reports.iter().filter(|r| r.remesh_reverted).count(),
        },
        "surgery": w.surgery,
        "isolated_points_left_out": w.left_out.strays,
        "specks_left_out": w.left_out.specks,
        "repairs": read.repairs,
        "points_left_out": read.left_out,
        "vertices": w.positions.len(),
        "faces": w.triangles.len(),
        "steps": w.steps,
        "stopped_early": w.steps < w.settings.stop.steps,
        "scale": w.scale,
        "result_hash": w.hash,
        "iso_level": w.iso_level,
        "started_over": w.started_over,
        "distance_mean": last.map_or(0.0, |r| r.distance_mean),
        "distance_max": last.map_or(0.0, |r| r.distance_max),
        "iso": read.volume.as_ref().map(|v| v.iso),
        "volume": read.volume.as_deref().map(super::volume::volume_json),
        "field_ms": w.field_ms,
        "times_ms": {
            "read": t_read - t0,
            "setup": w.times.setup,
            "evolve": w.times.evolve,
            "certify": t_evolve - t_read - w.times.setup - w.times.evolve,
            "write": t_write - t_evolve,
            "total": t_write - t0,
        },
        "evolve_ms": {
            "normals": sum(|r| r.times.normals),
            "assembly": sum(|r| r.times.assembly),
            "solve": sum(|r| r.times.solve),
            "remesh": sum(|r| r.times.remesh),
            "guard": sum(|r| r.times.guard),
            "fit": sum(|r| r.times.fit),
            "surgery": sum(|r| r.times.surgery),
            "redone": sum(|r| r.times.redone),
        },
        "fit_ms": last.map(|r| r.times.fit_parts),
    })
}

/// The result of [`run`]: the report, or on failure the message (with the report after it on
/// stderr) and the report for stdout.
fn finish(
    out: String,
    failure: Option<String>,
    keep_invalid: bool,
) -> Result<String, super::Failure> {
    match failure {
        None => Ok(out),
        // The report goes to stdout as on success, and also after the message on stderr.
        Some(why) => Err(super::Failure {
            message: format!(
                "{why}; {}\n{out}",
                if keep_invalid {
                    "the mesh was written anyway (--keep-invalid)"
                } else {
                    "no mesh was written (--keep-invalid writes it anyway)"
                }
            ),
            report: Some(out),
        }),
    }
}

/// Keeps every step's report for `--stats` and the phase sums.
#[derive(Default)]
struct Steps {
    reports: Vec<StepReport>,
}

impl Observer for Steps {
    fn step(&mut self, report: &StepReport) {
        self.reports.push(report.clone());
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn overrides_reach_nested_settings_and_reject_unknown_keys() {
        let s = apply_overrides(
            WrapSettings::default(),
            &[
                "tau=0.01".into(),
                "field.cells_per_min_dimension=60".into(),
                "start=\"isosurface\"".into(),
            ],
        )
        .unwrap();
        assert_eq!(s.flow.tau, 0.01);
        assert_eq!(s.field.cells_per_min_dimension, 60);
        assert_eq!(s.start.surface, crate::flow::StartSurface::Isosurface);
        let s = apply_overrides(
            WrapSettings::default(),
            &[
                "flow.d2=0".into(),
                "remesh_iterations=3".into(),
                "features.detector=both".into(),
                "stop.steps=7".into(),
            ],
        )
        .unwrap();
        assert_eq!(s.flow.d2, 0.0);
        assert_eq!(s.remesh.iterations, 3);
        assert_eq!(
            s.tuning.remesh.features.detector,
            crate::remesh::FeatureDetector::Both
        );
        assert_eq!(s.stop.steps, 7);
        // A tuned value at its stage's earlier key; a tuning version picks its row first.
        let s = apply_overrides(
            WrapSettings::default(),
            &["flow.regrow_depth=0.5".into(), "tuning.version=1".into()],
        )
        .unwrap();
        let one = crate::flow::settings::Tuning::at(1).unwrap();
        assert_eq!(s.tuning.flow.regrow_depth, 0.5);
        assert_eq!(s.tuning.surgery.tunnel_ratio, one.surgery.tunnel_ratio);
        assert_eq!(s.tuning.version, 1);
        assert!(apply_overrides(WrapSettings::default(), &["tuning.version=7".into()]).is_err());
        assert!(apply_overrides(WrapSettings::default(), &["nope=1".into()]).is_err());
        assert!(apply_overrides(WrapSettings::default(), &["tau".into()]).is_err());
        assert!(apply_overrides(WrapSettings::default(), &["tau=\"fast\"".into()]).is_err());
    }
}
