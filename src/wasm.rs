//! The `#[wasm_bindgen]` facade: converts core types to typed arrays and errors to
//! `{code, message, hint}` objects. It holds no algorithm; everything here delegates to the core.

use crate::flow::{
    self, exact_sphere_radius, EvolveError, Evolver, FlowError, McfSettings, StepReport,
    WrapSettings,
};
use crate::geometry::icosphere::{icosphere, IcosphereError};
use crate::geometry::sphere::mean_radius;
use crate::io::{Format, IoError, WriteInput};
use crate::mesh::HalfedgeMesh;
use glam::DVec3;
use js_sys::{Float32Array, Uint32Array};
use serde::Serialize;
use wasm_bindgen::prelude::*;

mod volume;
pub use volume::{phantom_volume, VolumeView};

/// An error as the UI sees it: a stable machine code, a sentence, and what to try.
#[derive(Serialize, Debug, Clone, PartialEq)]
pub struct UiError {
    /// Stable identifier (e.g. `bad-parameter`, `solve-failed`).
    pub code: &'static str,
    /// What went wrong, naming the problem.
    pub message: String,
    /// What the user can do about it.
    pub hint: &'static str,
}

impl From<UiError> for JsValue {
    fn from(e: UiError) -> JsValue {
        serde_wasm_bindgen::to_value(&e).unwrap_or_else(|_| JsValue::from_str(&e.message))
    }
}

impl From<IcosphereError> for UiError {
    fn from(e: IcosphereError) -> Self {
        UiError {
            code: "bad-parameter",
            message: e.to_string(),
            hint: "Use a subdivision level from 0 to 7 and a positive radius.",
        }
    }
}

impl From<FlowError> for UiError {
    fn from(e: FlowError) -> Self {
        let (code, hint) = match e {
            FlowError::BadTimeStep(_) => ("bad-parameter", "Choose a positive time step τ."),
            FlowError::Solve(_) => ("solve-failed", "Reduce the time step τ and reset."),
            FlowError::NonFinite { .. } => ("diverged", "Reduce the time step τ and reset."),
        };
        UiError {
            code,
            message: e.to_string(),
            hint,
        }
    }
}

impl From<IoError> for UiError {
    fn from(e: IoError) -> Self {
        let hint = match e {
            IoError::Empty { .. } => "The file is empty: choose another file.",
            IoError::UnknownFormat { .. } => "Use PLY, OBJ, STL, OFF, XYZ/CSV, glTF or GLB, or a NIfTI, NRRD, VTI or MetaImage volume.",
            _ => "The file looks damaged or is not what its name says; re-export it from its source program.",
        };
        UiError {
            code: "bad-file",
            message: e.to_string(),
            hint,
        }
    }
}

impl From<EvolveError> for UiError {
    fn from(e: EvolveError) -> Self {
        let (code, hint) = match e {
            EvolveError::Setting(_) => ("bad-parameter", "Reset the advanced settings or pick a preset."),
            EvolveError::Field(crate::field::FieldError::TooLarge { .. }) => ("too-large", "Lower the grid resolution (cells per minimum dimension)."),
            EvolveError::Field(_) => ("bad-target", "The target needs points spread in 3D (not empty, not a single point or a flat sheet)."),
            EvolveError::EmptyIsosurface { .. } | EvolveError::StartMesh(_) | EvolveError::StartIntersects { .. } => ("bad-start", "Raise the isosurface level, or use the icosphere start."),
            EvolveError::Diverged { .. } | EvolveError::Divergence { .. } => ("diverged", "The surface was rolled back to the last good step. Lower the time step τ, or pick the full-wrap preset."),
            EvolveError::Target(_) => ("bad-target", "The target needs at least 4 points spread in 3-D: not a single point, a line or a flat sheet (a thin plate with some thickness is fine)."),
            _ => ("internal", "Try another preset; if it persists, report a bug with the share link."),
        };
        UiError {
            code,
            message: e.to_string(),
            hint,
        }
    }
}

/// Installs a panic hook that logs Rust panics to the console (they should never happen).
#[wasm_bindgen(start)]
pub fn start() {
    console_error_panic_hook::set_once();
}

/// Statistics of the current MCF state, for the UI's plots and labels.
#[derive(Serialize, Debug, Clone)]
#[serde(rename_all = "camelCase")]
pub struct McfStats {
    /// Steps taken since creation.
    pub step: u32,
    /// Flow time t = steps · τ.
    pub time: f64,
    /// Mean distance of vertices from their centroid.
    pub mean_radius: f64,
    /// Analytic radius sqrt(r0² − 4t).
    pub exact_radius: f64,
    /// Co-volume min / mean / max of the last step.
    pub covolume_min: f64,
    pub covolume_mean: f64,
    pub covolume_max: f64,
    /// Solver iterations and relative residual of the last step.
    pub solver_iterations: usize,
    pub solver_residual: f64,
    /// Wall time of the last `step(n)` call divided by n, in milliseconds.
    pub ms_per_step: f64,
    /// Vertex and face counts.
    pub vertices: usize,
    pub faces: usize,
}

/// A mean-curvature-flow session on an icosphere: the teaching demo and the pipeline's smoke test.
#[wasm_bindgen]
pub struct McfSession {
    mesh: HalfedgeMesh,
    settings: McfSettings,
    r0: f64,
    stats: McfStats,
}

#[wasm_bindgen]
impl McfSession {
    /// Creates an icosphere of `level` subdivisions and `radius`, to be flowed with time step `tau`.
    #[wasm_bindgen(constructor)]
    pub fn new(level: u32, radius: f64, tau: f64) -> Result<McfSession, JsValue> {
        let mesh = icosphere(level, radius, DVec3::ZERO).map_err(UiError::from)?;
        if !(tau > 0.0 && tau.is_finite()) {
            return Err(UiError::from(FlowError::BadTimeStep(tau)).into());
        }
        let stats = McfStats {
            step: 0,
            time: 0.0,
            mean_radius: mean_radius(mesh.positions()),
            exact_radius: radius,
            covolume_min: 0.0,
            covolume_mean: 0.0,
            covolume_max: 0.0,
            solver_iterations: 0,
            solver_residual: 0.0,
            ms_per_step: 0.0,
            vertices: mesh.n_vertices(),
            faces: mesh.n_faces(),
        };
        Ok(McfSession {
            mesh,
            settings: McfSettings {
                tau,
                ..Default::default()
            },
            r0: radius,
            stats,
        })
    }

    /// Advances `n` steps. Stops with an error (mesh unchanged by the failing step) if a solve fails
    /// or the sphere has (nearly) vanished.
    pub fn step(&mut self, n: u32) -> Result<(), JsValue> {
        let t0 = crate::clock::now_ms();
        for _ in 0..n {
            let rep = flow::mcf_step(&mut self.mesh, &self.settings).map_err(UiError::from)?;
            self.stats.step += 1;
            self.stats.time = self.stats.step as f64 * self.settings.tau;
            self.stats.covolume_min = rep.covolume_min;
            self.stats.covolume_mean = rep.covolume_mean;
            self.stats.covolume_max = rep.covolume_max;
            self.stats.solver_iterations = rep.solve.iterations;
            self.stats.solver_residual = rep.solve.relative_residual;
        }
        self.stats.mean_radius = mean_radius(self.mesh.positions());
        self.stats.exact_radius = exact_sphere_radius(self.r0, self.stats.time);
        if n > 0 {
            self.stats.ms_per_step = (crate::clock::now_ms() - t0) / n as f64;
        }
        Ok(())
    }

    /// Vertex positions as a flat `Float32Array` (x0, y0, z0, x1, …).
    pub fn positions(&self) -> Float32Array {
        let flat: Vec<f32> = self
            .mesh
            .positions()
            .iter()
            .flat_map(|p| [p.x as f32, p.y as f32, p.z as f32])
            .collect();
        Float32Array::from(flat.as_slice())
    }

    /// Angle-weighted unit vertex normals as a flat `Float32Array`, for shading.
    pub fn normals(&self) -> Float32Array {
        let flat: Vec<f32> =
            crate::geometry::operators::normals::angle_weighted_normals(&self.mesh)
                .iter()
                .flat_map(|p| [p.x as f32, p.y as f32, p.z as f32])
                .collect();
        Float32Array::from(flat.as_slice())
    }

    /// Triangle vertex indices as a flat `Uint32Array`.
    pub fn indices(&self) -> Uint32Array {
        let flat: Vec<u32> = self.mesh.triangles().into_iter().flatten().collect();
        Uint32Array::from(flat.as_slice())
    }

    /// Per-vertex mean curvature H (1/r on a sphere of radius r).
    #[wasm_bindgen(js_name = meanCurvature)]
    pub fn mean_curvature(&self) -> Float32Array {
        let h: Vec<f32> = flow::mcf::mean_curvature(&self.mesh)
            .into_iter()
            .map(|x| x as f32)
            .collect();
        Float32Array::from(h.as_slice())
    }

    /// Current statistics as a plain JS object (see `McfStats`).
    pub fn stats(&self) -> Result<JsValue, JsValue> {
        serde_wasm_bindgen::to_value(&self.stats).map_err(|e| JsValue::from_str(&e.to_string()))
    }
}

/// Flat `Float32Array` of 3-vectors.
fn vec3_array(v: &[DVec3]) -> Float32Array {
    let flat: Vec<f32> = v
        .iter()
        .flat_map(|p| [p.x as f32, p.y as f32, p.z as f32])
        .collect();
    Float32Array::from(flat.as_slice())
}

/// A wrap of a dropped file, advanced step by step from the worker.
#[wasm_bindgen]
pub struct WrapSession {
    evolver: Evolver,
    target: crate::target::Target,
    format: Format,
    settings_json: String,
    last: Option<StepReport>,
}

impl WrapSession {
    /// The session for what was read (a file or a volume) under `settings_json`.
    pub(crate) fn prepare(
        read: crate::io::ReadResult,
        settings_json: &str,
    ) -> Result<WrapSession, JsValue> {
        let settings = WrapSettings::from_json(settings_json).map_err(|e| UiError {
            code: "bad-parameter",
            message: format!("settings: {e}"),
            hint: "Reset the advanced settings or pick a preset.",
        })?;
        let evolver = Evolver::new(&read.target, settings.clone()).map_err(UiError::from)?;
        Ok(WrapSession {
            evolver,
            target: read.target,
            format: read.format,
            settings_json: serde_json::to_string(&settings).unwrap_or_default(),
            last: None,
        })
    }
}

#[wasm_bindgen]
impl WrapSession {
    /// Reads `bytes` (format sniffed from content, `file_name` breaks ties) and prepares the
    /// wrap with `settings_json` (a `WrapSettings` JSON object; missing keys default).
    #[wasm_bindgen(constructor)]
    pub fn new(
        bytes: &[u8],
        file_name: Option<String>,
        settings_json: &str,
    ) -> Result<WrapSession, JsValue> {
        let read = crate::io::read_bytes(bytes, file_name.as_deref()).map_err(UiError::from)?;
        WrapSession::prepare(read, settings_json)
    }

    /// Runs up to `n` steps; returns true when the wrap is done.
    pub fn step(&mut self, n: u32) -> Result<bool, JsValue> {
        for _ in 0..n {
            if self.evolver.is_done() {
                break;
            }
            self.last = Some(self.evolver.step().map_err(UiError::from)?);
        }
        Ok(self.evolver.is_done())
    }

    /// True when the stopping rule or the step limit has been reached.
    #[wasm_bindgen(js_name = isDone)]
    pub fn is_done(&self) -> bool {
        self.evolver.is_done()
    }

    /// The last step's report (see `StepReport`), or null before the first step.
    pub fn report(&self) -> Result<JsValue, JsValue> {
        serde_wasm_bindgen::to_value(&self.last).map_err(|e| JsValue::from_str(&e.to_string()))
    }

    /// What was read: format, kind, counts and bounding box.
    #[wasm_bindgen(js_name = targetInfo)]
    pub fn target_info(&self) -> Result<JsValue, JsValue> {
        let t = &self.target;
        let info = serde_json::json!({
            "format": self.format.name(),
            "kind": t.kind(),
            "points": t.points.len(),
            "triangles": t.triangles.len(),
            "bboxMin": t.bbox.min.to_array(),
            "bboxMax": t.bbox.max.to_array(),
            "diagonal": t.bbox.diagonal(),
        });
        serde_wasm_bindgen::to_value(&info).map_err(|e| JsValue::from_str(&e.to_string()))
    }

    /// Target points (or mesh vertices) as a flat `Float32Array`.
    #[wasm_bindgen(js_name = targetPositions)]
    pub fn target_positions(&self) -> Float32Array {
        vec3_array(&self.target.points)
    }

    /// Target triangles as a flat `Uint32Array` (empty for a point cloud).
    #[wasm_bindgen(js_name = targetIndices)]
    pub fn target_indices(&self) -> Uint32Array {
        let flat: Vec<u32> = self.target.triangles.iter().flatten().copied().collect();
        Uint32Array::from(flat.as_slice())
    }

    /// Surface positions (target units).
    pub fn positions(&self) -> Float32Array {
        vec3_array(&self.evolver.positions())
    }

    /// Angle-weighted unit vertex normals.
    pub fn normals(&self) -> Float32Array {
        vec3_array(
            &crate::geometry::operators::normals::angle_weighted_normals(self.evolver.mesh()),
        )
    }

    /// Surface triangles as a flat `Uint32Array`.
    pub fn indices(&self) -> Uint32Array {
        let flat: Vec<u32> = self.evolver.triangles().into_iter().flatten().collect();
        Uint32Array::from(flat.as_slice())
    }

    /// A per-vertex scalar for colouring: "distance" (target units), "curvature" (mean
    /// curvature, 1/target units), "kappa" (vertex-averaged κ(J_Δ)), "covolume" (stabilised
    /// frame) or "features" (1 for feature vertices).
    pub fn scalar(&self, name: &str) -> Result<Float32Array, JsValue> {
        let mesh = self.evolver.mesh();
        let values: Vec<f64> = match name {
            "distance" => self.evolver.vertex_distances(),
            "curvature" => flow::mcf::mean_curvature(mesh)
                .into_iter()
                .map(|h| h * self.evolver.scale())
                .collect(),
            "kappa" => crate::metrics::quality::vertex_kappa(mesh),
            "covolume" => crate::geometry::operators::CotanLaplacian::new(mesh).covolumes,
            "features" => {
                let f =
                    crate::remesh::features::detect(mesh, &self.evolver.settings().remesh.features);
                f.vertices.into_iter().map(|b| b as u8 as f64).collect()
            }
            other => {
                return Err(UiError {
                    code: "bad-parameter",
                    message: format!("unknown scalar \"{other}\""),
                    hint: "Use distance, curvature, kappa, covolume or features.",
                }
                .into())
            }
        };
        let flat: Vec<f32> = values.into_iter().map(|x| x as f32).collect();
        Ok(Float32Array::from(flat.as_slice()))
    }

    /// The result as a file: "obj", "ply", "stl", "glb" or "vtk" (PLY, GLB and VTK carry the
    /// per-vertex distance; PLY, OBJ, GLB and VTK record the settings).
    pub fn export(&self, format: &str) -> Result<js_sys::Uint8Array, JsValue> {
        let fmt = Format::from_extension(format).ok_or_else(|| UiError {
            code: "bad-parameter",
            message: format!("cannot export as \"{format}\""),
            hint: "Choose OBJ, PLY, STL, GLB or VTK.",
        })?;
        let (positions, triangles) = (self.evolver.positions(), self.evolver.triangles());
        let distance = self.evolver.vertex_distances();
        let curvature: Vec<f64> = flow::mcf::mean_curvature(self.evolver.mesh())
            .into_iter()
            .map(|h| h * self.evolver.scale())
            .collect();
        let kappa = crate::metrics::quality::vertex_kappa(self.evolver.mesh());
        let scalars = [
            ("distance", distance.as_slice()),
            ("mean_curvature", curvature.as_slice()),
            ("kappa", kappa.as_slice()),
        ];
        let input = WriteInput {
            positions: &positions,
            triangles: &triangles,
            scalars: &scalars,
            settings_json: Some(&self.settings_json),
        };
        let bytes = crate::io::write_bytes(fmt, &input).map_err(UiError::from)?;
        Ok(js_sys::Uint8Array::from(bytes.as_slice()))
    }

    /// The certificate of the current surface against the target (see
    /// [`crate::metrics::certificate::Certificate`]; keys in snake_case).
    pub fn certificate(&self) -> Result<JsValue, JsValue> {
        let c = crate::metrics::certificate::certify(
            &self.evolver.positions(),
            &self.evolver.triangles(),
            Some(&self.target),
        );
        serde_wasm_bindgen::to_value(&c).map_err(|e| JsValue::from_str(&e.to_string()))
    }

    /// The step limit in force (the start's own when `auto` resolved to the isosurface start).
    #[wasm_bindgen(js_name = stepLimit)]
    pub fn step_limit(&self) -> u32 {
        self.evolver.settings().stop.steps
    }

    /// Why the wrap stopped before its rule said so (divergence, solver failure), or null.
    #[wasm_bindgen(js_name = stopReason)]
    pub fn stop_reason(&self) -> Option<String> {
        self.evolver.stop_reason().map(str::to_owned)
    }

    /// The start surface actually used ("icosphere" or "isosurface").
    #[wasm_bindgen(js_name = startSurface)]
    pub fn start_surface(&self) -> String {
        serde_json::to_value(self.evolver.start_surface())
            .ok()
            .and_then(|v| v.as_str().map(str::to_owned))
            .unwrap_or_default()
    }

    /// Fingerprint of the current surface (see [`crate::mesh::fingerprint::mesh_hash`]).
    #[wasm_bindgen(js_name = resultHash)]
    pub fn result_hash(&self) -> String {
        crate::mesh::fingerprint::mesh_hash(&self.evolver.positions(), &self.evolver.triangles())
    }
}

/// The default settings of a preset ("full-wrap", "obstacle", "isosurface", "mcf") as JSON.
#[wasm_bindgen(js_name = presetSettings)]
pub fn preset_settings(name: &str) -> Result<String, JsValue> {
    let p = flow::Preset::from_name(name).ok_or_else(|| UiError {
        code: "bad-parameter",
        message: format!("unknown preset \"{name}\""),
        hint: "Use full-wrap, obstacle, isosurface or mcf.",
    })?;
    Ok(serde_json::to_string(&p.settings()).unwrap_or_default())
}

// ---------------------------------------------------------------------------------------------
// Demo gallery, control curves and settings documentation for the browser app (issue 7).

impl From<crate::demo::DemoError> for UiError {
    fn from(e: crate::demo::DemoError) -> Self {
        let hint = match e {
            crate::demo::DemoError::UnknownShape(_) => "Use noisy-sphere, genus2 or box-soup.",
            crate::demo::DemoError::BadMesh(_) => "Pass a triangle mesh with non-degenerate faces.",
        };
        UiError {
            code: "bad-parameter",
            message: e.to_string(),
            hint,
        }
    }
}

/// Flat f32 triples → points (a trailing partial triple is ignored).
fn points_from_flat(flat: &[f32]) -> Vec<DVec3> {
    flat.chunks_exact(3)
        .map(|c| DVec3::new(c[0] as f64, c[1] as f64, c[2] as f64))
        .collect()
}

/// PLY bytes of points (+ triangles), as the worker feeds to `WrapSession::new`.
fn ply_bytes(points: &[DVec3], triangles: &[[u32; 3]]) -> Result<js_sys::Uint8Array, JsValue> {
    let bytes = crate::io::write_bytes(Format::Ply, &WriteInput::new(points, triangles))
        .map_err(UiError::from)?;
    Ok(js_sys::Uint8Array::from(bytes.as_slice()))
}

/// A procedural demo shape ("noisy-sphere", "genus2", "box-soup") as PLY bytes.
#[wasm_bindgen(js_name = demoShape)]
pub fn demo_shape(name: &str) -> Result<js_sys::Uint8Array, JsValue> {
    let (points, triangles) = crate::demo::shape(name).map_err(UiError::from)?;
    ply_bytes(&points, &triangles)
}

/// A mesh given as flat positions and triangle indices, as PLY bytes; with `samples > 0`, a
/// point cloud (no normals) of that many points sampled uniformly by area (seeded).
#[wasm_bindgen(js_name = demoMesh)]
pub fn demo_mesh(
    positions: &[f32],
    indices: &[u32],
    samples: u32,
    seed: u32,
) -> Result<js_sys::Uint8Array, JsValue> {
    let points = points_from_flat(positions);
    let triangles: Vec<[u32; 3]> = indices
        .chunks_exact(3)
        .map(|c| [c[0], c[1], c[2]])
        .collect();
    if samples > 0 {
        let cloud = crate::demo::sample_mesh(&points, &triangles, samples as usize, seed as u64)
            .map_err(UiError::from)?;
        ply_bytes(&cloud, &[])
    } else {
        ply_bytes(&points, &triangles)
    }
}

/// A mesh held by the page (flat positions and indices) written as "obj", "ply", "stl", "glb" or
/// "vtk": exports a kept result after its session is gone.
#[wasm_bindgen(js_name = exportMesh)]
pub fn export_mesh(
    positions: &[f32],
    indices: &[u32],
    format: &str,
) -> Result<js_sys::Uint8Array, JsValue> {
    let fmt = Format::from_extension(format).ok_or_else(|| UiError {
        code: "bad-parameter",
        message: format!("cannot export as \"{format}\""),
        hint: "Choose OBJ, PLY, STL, GLB or VTK.",
    })?;
    let points = points_from_flat(positions);
    let triangles: Vec<[u32; 3]> = indices
        .chunks_exact(3)
        .map(|c| [c[0], c[1], c[2]])
        .collect();
    let bytes = crate::io::write_bytes(fmt, &WriteInput::new(&points, &triangles))
        .map_err(UiError::from)?;
    Ok(js_sys::Uint8Array::from(bytes.as_slice()))
}

/// ε(δ) and η(δ) (cos θ = 1 and 0) of the settings in `settings_json`, sampled at `n` points:
/// `{delta, epsilon, eta_facing, eta_side}`.
#[wasm_bindgen(js_name = controlCurves)]
pub fn control_curves(settings_json: &str, n: u32) -> Result<JsValue, JsValue> {
    let settings = WrapSettings::from_json(settings_json).map_err(|e| UiError {
        code: "bad-parameter",
        message: format!("settings: {e}"),
        hint: "Reset the advanced settings or pick a preset.",
    })?;
    let curves = crate::demo::control_curves(&settings, n as usize);
    serde_wasm_bindgen::to_value(&curves).map_err(|e| JsValue::from_str(&e.to_string()))
}

/// The doc comment of every settings field, as a JSON object keyed by the field's path in the
/// settings JSON (`tau`, `field.band_cells`, …).
#[wasm_bindgen(js_name = settingsDocs)]
pub fn settings_docs() -> String {
    let map: serde_json::Map<String, serde_json::Value> =
        crate::flow::settings::docs::settings_docs()
            .into_iter()
            .map(|(k, v)| (k, serde_json::Value::String(v)))
            .collect();
    serde_json::Value::Object(map).to_string()
}

/// The options of every enum-valued settings field, as a JSON object keyed by the field's path.
#[wasm_bindgen(js_name = settingsEnums)]
pub fn settings_enums() -> String {
    let map: serde_json::Map<String, serde_json::Value> =
        crate::flow::settings::docs::settings_enums()
            .into_iter()
            .map(|(k, v)| (k, serde_json::Value::from(v)))
            .collect();
    serde_json::Value::Object(map).to_string()
}

/// The old flat settings keys (down to the leaves) with their current nested keys, as a JSON
/// object: share links made before the settings were nested still decode.
#[wasm_bindgen(js_name = settingAliases)]
pub fn setting_aliases() -> String {
    let map: serde_json::Map<String, serde_json::Value> =
        crate::flow::settings::aliases::leaf_aliases()
            .into_iter()
            .map(|(k, v)| (k, serde_json::Value::String(v)))
            .collect();
    serde_json::Value::Object(map).to_string()
}

#[wasm_bindgen]
impl WrapSession {
    /// Histogram of the per-triangle κ(J_Δ) (equilateral = 1) of the current surface over
    /// [1, `hi`) in `bins` bins: `{lo, hi, counts, below, above}`.
    #[wasm_bindgen(js_name = kappaHistogram)]
    pub fn kappa_histogram(&self, bins: u32, hi: f64) -> Result<JsValue, JsValue> {
        let (p, t) = (self.evolver.positions(), self.evolver.triangles());
        let k: Vec<f64> = t
            .iter()
            .map(|f| {
                crate::metrics::quality::kappa(p[f[0] as usize], p[f[1] as usize], p[f[2] as usize])
            })
            .collect();
        let hi = if hi > 1.0 && hi.is_finite() { hi } else { 3.0 };
        let h =
            crate::metrics::histogram::Histogram::new(&k, 1.0, hi, bins.clamp(1, 1000) as usize);
        serde_wasm_bindgen::to_value(&h).map_err(|e| JsValue::from_str(&e.to_string()))
    }
}

// ---------------------------------------------------------------------------------------------
// Viewing the distance field in the app (issue 4): a plane of nodes or an isosurface.

/// Sets `key` on `obj` (a fresh plain object, so this cannot fail in practice).
fn set_key(obj: &js_sys::Object, key: &str, value: &JsValue) -> Result<(), JsValue> {
    js_sys::Reflect::set(obj, &JsValue::from_str(key), value).map(|_| ())
}

/// The isosurface level in the scaled frame for `level` in target units: clamped to at least
/// half a cell for unsigned fields (their zero set is the target itself, not a surface).
fn field_iso_level(level: f64, phi: f64, cell_scaled: f64, signed: bool) -> Result<f64, UiError> {
    if !level.is_finite() {
        return Err(UiError {
            code: "bad-parameter",
            message: format!("isosurface level {level} is not a number"),
            hint: "Give a finite level in the target's units.",
        });
    }
    let scaled = level * phi;
    Ok(if signed {
        scaled
    } else {
        scaled.max(0.5 * cell_scaled)
    })
}

#[wasm_bindgen]
impl WrapSession {
    /// The plane of field nodes normal to `axis` (0 = x, 1 = y, 2 = z) nearest to the fraction
    /// `t` ∈ [0, 1] along that axis: `{axis, index, width, height, coordinate, corners, values}`;
    /// `corners` (Float32Array of 4 positions: (u₀,v₀), (u₁,v₀), (u₁,v₁), (u₀,v₁)) and the
    /// plane's `coordinate` are in target units, `values` (Float32Array, u fastest, see
    /// [`crate::field::slice`]) are distances in target units.
    #[wasm_bindgen(js_name = fieldSlice)]
    pub fn field_slice(&self, axis: u32, t: f64) -> Result<js_sys::Object, JsValue> {
        let field = self.evolver.field();
        let plane =
            crate::field::slice::node_plane(field, axis as usize, t).ok_or_else(|| UiError {
                code: "bad-parameter",
                message: format!("no field slice for axis {axis} at {t}"),
                hint: "Use axis 0, 1 or 2 (x, y, z) and a position between 0 and 1.",
            })?;
        let (phi, center) = (self.evolver.scale(), self.target.bbox.center());
        let corners: Vec<DVec3> = plane.corners.iter().map(|&p| p / phi + center).collect();
        let values: Vec<f32> = plane.values.iter().map(|&d| (d / phi) as f32).collect();
        let obj = js_sys::Object::new();
        set_key(&obj, "axis", &JsValue::from(plane.axis as u32))?;
        set_key(&obj, "index", &JsValue::from(plane.index as u32))?;
        set_key(&obj, "width", &JsValue::from(plane.width as u32))?;
        set_key(&obj, "height", &JsValue::from(plane.height as u32))?;
        set_key(&obj, "coordinate", &JsValue::from(corners[0][plane.axis]))?;
        set_key(&obj, "corners", &vec3_array(&corners))?;
        set_key(&obj, "values", &Float32Array::from(values.as_slice()))?;
        Ok(obj)
    }

    /// The isosurface d = `level` of the field (target units; for unsigned fields at least half
    /// a cell): `{level, positions, indices}` with positions in target units.
    #[wasm_bindgen(js_name = fieldIsosurface)]
    pub fn field_isosurface(&self, level: f64) -> Result<js_sys::Object, JsValue> {
        let field = self.evolver.field();
        let phi = self.evolver.scale();
        let iso = field_iso_level(level, phi, field.cell_size(), field.is_signed())?;
        let (pos, tris) = field.isosurface(iso);
        let center = self.target.bbox.center();
        let pos: Vec<DVec3> = pos.into_iter().map(|p| p / phi + center).collect();
        let flat: Vec<u32> = tris.into_iter().flatten().collect();
        let obj = js_sys::Object::new();
        set_key(&obj, "level", &JsValue::from(iso / phi))?;
        set_key(&obj, "positions", &vec3_array(&pos))?;
        set_key(&obj, "indices", &Uint32Array::from(flat.as_slice()))?;
        Ok(obj)
    }
}

#[cfg(test)]
mod field_view_tests {
    use super::field_iso_level;

    #[test]
    fn iso_level_is_scaled_and_clamped_for_unsigned_fields() {
        // φ = 2, scaled cell 0.1: half a cell is 0.05 scaled.
        assert_eq!(field_iso_level(0.0, 2.0, 0.1, false).unwrap(), 0.05);
        assert_eq!(field_iso_level(0.3, 2.0, 0.1, false).unwrap(), 0.6);
        assert_eq!(field_iso_level(-1.0, 2.0, 0.1, false).unwrap(), 0.05);
        // Signed fields keep zero and negative levels.
        assert_eq!(field_iso_level(0.0, 2.0, 0.1, true).unwrap(), 0.0);
        assert_eq!(field_iso_level(-0.25, 2.0, 0.1, true).unwrap(), -0.5);
        assert!(field_iso_level(f64::NAN, 2.0, 0.1, false).is_err());
    }
}
