//! `lsw wrap INPUT -o OUTPUT`: the whole pipeline, read → field → start surface → evolve → write.

use crate::flow::{Evolver, Preset, StepReport, WrapSettings};
use crate::io::{read_path_with, write_path, WriteInput};
use serde_json::{json, Value};
use std::path::PathBuf;

/// Arguments of `lsw wrap`.
#[derive(clap::Args, Debug)]
pub struct WrapArgs {
    /// Input point cloud or mesh (PLY, OBJ, STL, OFF, XYZ/CSV, glTF/GLB).
    pub input: PathBuf,
    /// Output mesh; the format follows the extension (.obj, .ply, .stl, .glb, .vtk).
    #[arg(short, long)]
    pub output: PathBuf,
    /// Settings preset: full-wrap, obstacle, isosurface or mcf.
    #[arg(long, default_value = "full-wrap")]
    pub preset: String,
    /// Step limit (overrides the preset's).
    #[arg(long)]
    pub steps: Option<u32>,
    /// Any setting as key=value (JSON value; dotted keys reach nested settings, e.g.
    /// field.cells_per_min_dimension=60). Repeatable.
    #[arg(long = "set", value_name = "KEY=VALUE")]
    pub set: Vec<String>,
    /// Write per-step statistics (JSON) to this file.
    #[arg(long)]
    pub stats: Option<PathBuf>,
    /// Volume inputs: iso-value, frame, inside, array, iso-surface output.
    #[command(flatten)]
    pub volume: super::volume::VolumeArgs,
}

/// Applies `key=value` overrides to the settings' JSON form; unknown keys are errors.
pub fn apply_overrides(
    settings: WrapSettings,
    overrides: &[String],
) -> Result<WrapSettings, String> {
    let mut v = serde_json::to_value(&settings).expect("settings serialise");
    for o in overrides {
        let (key, raw) = o
            .split_once('=')
            .ok_or_else(|| format!("--set {o}: expected KEY=VALUE"))?;
        let value: Value =
            serde_json::from_str(raw).unwrap_or_else(|_| Value::String(raw.to_owned()));
        let mut slot = &mut v;
        for part in key.split('.') {
            slot = slot
                .as_object_mut()
                .and_then(|m| m.get_mut(part))
                .ok_or_else(|| format!("--set {o}: unknown setting \"{key}\""))?;
        }
        *slot = value;
    }
    serde_json::from_value(v).map_err(|e| format!("--set: {e}"))
}

/// Runs the wrap; JSON keys: input, output, preset, vertices, faces, steps, stopped_early,
/// scale, result_hash, iso_level, times_ms {read, field, start, evolve, write, total}, evolve_ms {normals,
/// assembly, solve, remesh}, distance_mean, distance_max; for volumes also iso (the iso-value
/// wrapped) and volume (see [`super::volume::volume_json`]).
pub fn run(a: &WrapArgs) -> Result<String, String> {
    let t0 = crate::clock::now_ms();
    let preset = Preset::from_name(&a.preset).ok_or_else(|| {
        format!(
            "unknown preset \"{}\" (use full-wrap, obstacle, isosurface or mcf)",
            a.preset
        )
    })?;
    let mut settings = apply_overrides(preset.settings(), &a.set)?;
    if let Some(n) = a.steps {
        settings.steps = n;
    }
    let read = read_path_with(&a.input, &a.volume.options()).map_err(|e| e.to_string())?;
    a.volume.write_isosurface(&read)?;
    let t_read = crate::clock::now_ms();
    let mut ev = Evolver::new(&read.target, settings.clone()).map_err(|e| e.to_string())?;
    let t_setup = crate::clock::now_ms();
    let mut reports: Vec<StepReport> = Vec::new();
    ev.run(|r| reports.push(r.clone()))
        .map_err(|e| e.to_string())?;
    let t_evolve = crate::clock::now_ms();
    let (positions, triangles) = (ev.positions(), ev.triangles());
    let distances = ev.vertex_distances();
    let settings_json = serde_json::to_string(&settings).expect("settings serialise");
    let scalars = [("distance", distances.as_slice())];
    let input = WriteInput {
        positions: &positions,
        triangles: &triangles,
        scalars: &scalars,
        settings_json: Some(&settings_json),
    };
    write_path(&a.output, &input).map_err(|e| e.to_string())?;
    let t_write = crate::clock::now_ms();
    if let Some(path) = &a.stats {
        let text = serde_json::to_string_pretty(&json!({ "settings": settings, "steps": reports }))
            .expect("JSON");
        std::fs::write(path, text).map_err(|e| format!("{}: {e}", path.display()))?;
    }
    let sum = |f: fn(&StepReport) -> f64| reports.iter().map(f).sum::<f64>();
    let last = reports.last();
    let field = ev.field().timings();
    Ok(serde_json::to_string_pretty(&json!({
        "input": a.input.display().to_string(),
        "output": a.output.display().to_string(),
        "preset": preset.name(),
        "vertices": positions.len(),
        "faces": triangles.len(),
        "steps": ev.steps_done(),
        "stopped_early": ev.steps_done() < settings.steps,
        "scale": ev.scale(),
        "result_hash": crate::mesh::fingerprint::mesh_hash(&positions, &triangles),
        "iso_level": ev.iso_level(),
        "distance_mean": last.map_or(0.0, |r| r.distance_mean),
        "distance_max": last.map_or(0.0, |r| r.distance_max),
        "iso": read.volume.as_ref().map(|v| v.iso),
        "volume": read.volume.as_deref().map(super::volume::volume_json),
        "field_ms": field,
        "times_ms": {
            "read": t_read - t0,
            "setup": t_setup - t_read,
            "evolve": t_evolve - t_setup,
            "write": t_write - t_evolve,
            "total": t_write - t0,
        },
        "evolve_ms": {
            "normals": sum(|r| r.times.normals),
            "assembly": sum(|r| r.times.assembly),
            "solve": sum(|r| r.times.solve),
            "remesh": sum(|r| r.times.remesh),
        },
    }))
    .expect("JSON of plain values"))
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
        assert_eq!(s.tau, 0.01);
        assert_eq!(s.field.cells_per_min_dimension, 60);
        assert_eq!(s.start, crate::flow::StartSurface::Isosurface);
        assert!(apply_overrides(WrapSettings::default(), &["nope=1".into()]).is_err());
        assert!(apply_overrides(WrapSettings::default(), &["tau".into()]).is_err());
        assert!(apply_overrides(WrapSettings::default(), &["tau=\"fast\"".into()]).is_err());
    }
}
