//! [`WrapSession`]: a wrap of a dropped file, advanced step by step from the worker, and what the
//! app reads from it between steps (surface, colour-map scalars, report, certificate, κ
//! histogram). Its field view is in [`super::field`], its export in [`super::io`], its volume
//! constructor in [`super::volume`].

use super::errors::{ui_error, UiError};
use super::{index_array, scalar_array, to_js, vec3_array};
use crate::flow::{ColourMap, StartedOver, StepReport, WrapSettings};
use crate::io::Format;
use crate::metrics::certificate::{Certificate, CertificateTarget};
use crate::pipeline::{Verdict, WrapResult, WrapRun};
use crate::progress::Progress;
use crate::target::{Surface, TargetKind};
use js_sys::{Float32Array, Uint32Array};
use serde::Serialize;
use wasm_bindgen::prelude::*;

/// A wrap of a dropped file, advanced step by step from the worker.
#[wasm_bindgen]
pub struct WrapSession {
    pub(super) run: WrapRun,
    pub(super) target: crate::target::Target,
    format: Format,
    /// What reading mended in a mesh's indices (see [`crate::target::Target::repaired`]).
    repairs: Option<crate::mesh::Repairs>,
    /// Points the file marked unusable, not read (see [`crate::io::LeftOut`]).
    left_out: Option<crate::io::LeftOut>,
    /// The settings in force, as JSON (recorded in exported files).
    pub(super) settings_json: String,
    /// Called as `progress(phase, fraction)` during the long phases (the final fit).
    progress: Option<js_sys::Function>,
    last: Option<StepReport>,
    /// The finished wrap's result, certified once.
    finished: std::cell::OnceCell<WrapResult>,
}

impl WrapSession {
    /// The session for what was read (a file or a volume) under `settings_json`.
    /// `progress(phase, fraction)` hears the field build and the start surface now, and the
    /// final fit later.
    pub(crate) fn prepare(
        read: crate::io::ReadResult,
        settings_json: &str,
        progress: Option<js_sys::Function>,
    ) -> Result<WrapSession, JsValue> {
        let settings = WrapSettings::from_json(settings_json).map_err(UiError::settings)?;
        // A volume's voxels go before the evolver is built: the wrap needs only their
        // iso-surface, and the page keeps its own copy for the slices (kept here as well, a
        // large volume's voxels would take memory the wrap needs).
        let crate::io::ReadResult {
            target,
            format,
            repairs,
            volume,
            left_out,
            ..
        } = read;
        drop(volume);
        if let Surface::Points(points) = target.oracle().surface() {
            check_cloud_size(points.len())?;
        }
        let run = with_progress(progress.as_ref(), |p| {
            WrapRun::new(&target, settings.clone(), p)
        })
        .map_err(ui_error)?;
        Ok(WrapSession {
            run,
            target,
            format,
            repairs,
            left_out,
            settings_json: serde_json::to_string(&settings).unwrap_or_default(),
            progress,
            last: None,
            finished: std::cell::OnceCell::new(),
        })
    }
}

impl WrapSession {
    /// The current surface as a result: certified against the target as wrapped (once, when
    /// the wrap is done).
    fn result(&self) -> std::borrow::Cow<'_, WrapResult> {
        match self.finished() {
            Some(r) => std::borrow::Cow::Borrowed(r),
            None => std::borrow::Cow::Owned(self.certify()),
        }
    }

    /// The finished wrap's result, if it is done (certified now if not yet).
    pub(super) fn finished(&self) -> Option<&WrapResult> {
        self.run
            .is_done()
            .then(|| self.finished.get_or_init(|| self.certify()))
    }

    /// The current surface certified against the target as wrapped.
    fn certify(&self) -> WrapResult {
        let against = CertificateTarget::new(self.run.certified_target(&self.target));
        self.run.result(&against)
    }
}

/// What was read (`WrapSession.targetInfo`).
#[derive(Serialize, Debug, Clone, tsify::Tsify)]
#[serde(rename_all = "camelCase")]
pub struct TargetInfo {
    /// The format's short name (see [`Format::name`]).
    pub format: &'static str,
    pub kind: TargetKind,
    pub points: usize,
    pub triangles: usize,
    /// The bounding box's corners and diagonal, in the target's units.
    pub bbox_min: [f64; 3],
    pub bbox_max: [f64; 3],
    pub diagonal: f64,
    /// What reading mended in a mesh's indices (none: nothing).
    pub repairs: Option<crate::mesh::Repairs>,
    /// Points the file marks unusable, which were not read (none: none).
    pub left_out: Option<crate::io::LeftOut>,
}

/// The current surface certified, with the core's verdict on it (`WrapSession.outcome`; keys
/// in snake_case).
#[derive(Serialize, Debug, Clone, tsify::Tsify)]
pub struct Outcome {
    pub certificate: Certificate,
    pub verdict: Verdict,
    /// Fingerprint of the surface (see [`crate::mesh::fingerprint::mesh_hash`]).
    pub hash: String,
    /// Why the wrap stopped before its rule said so, if it did.
    pub stop_reason: Option<String>,
    /// How a target the first pass left partly outside was wrapped again, if it was.
    pub started_over: Option<StartedOver>,
}

/// The most points a cloud may have in the browser, where wasm32 gives the core 4 GiB of memory
/// at most: a wrap's peak memory grows with the points, and a larger cloud would run out of it
/// part-way (in the stray-point test), so it is refused at once instead.
pub const MAX_CLOUD_POINTS: usize = 16_000_000;

/// Refuses a cloud of more than [`MAX_CLOUD_POINTS`] points (`too-large`, saying how to wrap it).
pub fn check_cloud_size(points: usize) -> Result<(), UiError> {
    if points <= MAX_CLOUD_POINTS {
        return Ok(());
    }
    let millions = |n: usize| format!("{:.1} million", n as f64 / 1e6);
    Err(UiError {
        code: "too-large",
        message: format!(
            "The cloud has {} points: more than the browser can wrap ({} at most in its 4 GiB of memory)",
            millions(points),
            millions(MAX_CLOUD_POINTS)
        ),
        hint: "Thin the cloud (every second point keeps the shape), or wrap it with the native \
               CLI (lsw wrap), which has no such limit."
            .into(),
    })
}

/// Runs `f` with a [`Progress`] that calls the JS function `js(phase, fraction)` (none: silent).
fn with_progress<T>(js: Option<&js_sys::Function>, f: impl FnOnce(&mut Progress) -> T) -> T {
    let Some(js) = js else {
        return f(&mut Progress::none());
    };
    let mut sink = |phase: &str, fraction: f64| {
        // A failing callback must not stop the wrap: its error is the page's to show.
        let _ = js.call2(&JsValue::NULL, &phase.into(), &fraction.into());
    };
    f(&mut Progress::to(&mut sink))
}

#[wasm_bindgen]
impl WrapSession {
    /// Reads `bytes` (format sniffed from content, `file_name` breaks ties) and prepares the
    /// wrap with `settings_json` (a `WrapSettings` JSON object; missing keys default).
    /// `progress(phase, fraction)`, if given, hears the long phases: reading the file, the
    /// distance field and the start surface during construction, the final fit during `step`.
    #[wasm_bindgen(constructor)]
    pub fn new(
        bytes: &[u8],
        file_name: Option<String>,
        settings_json: &str,
        progress: Option<js_sys::Function>,
    ) -> Result<WrapSession, JsValue> {
        let opts = crate::io::VolumeOptions::default();
        let read = with_progress(progress.as_ref(), |p| {
            crate::io::read_bytes_progress(bytes, file_name.as_deref(), &opts, p)
        })
        .map_err(ui_error)?;
        WrapSession::prepare(read, settings_json, progress)
    }

    /// Runs up to `n` steps; returns true when the wrap is done.
    pub fn step(&mut self, n: u32) -> Result<bool, JsValue> {
        for _ in 0..n {
            if self.run.is_done() {
                break;
            }
            let run = &mut self.run;
            let report = with_progress(self.progress.as_ref(), |p| run.step(p));
            self.last = Some(report.map_err(ui_error)?);
        }
        Ok(self.run.is_done())
    }

    /// True when the stopping rule or the step limit has been reached.
    #[wasm_bindgen(js_name = isDone)]
    pub fn is_done(&self) -> bool {
        self.run.is_done()
    }

    /// The last step's report (see `StepReport`), or null before the first step.
    pub fn report(&self) -> Result<JsValue, JsValue> {
        to_js(&self.last)
    }

    /// What was read: format, kind, counts, bounding box, what reading mended and what it left
    /// out (see [`TargetInfo`]).
    #[wasm_bindgen(js_name = targetInfo)]
    pub fn target_info(&self) -> Result<JsValue, JsValue> {
        let t = &self.target;
        to_js(&TargetInfo {
            format: self.format.name(),
            kind: t.kind(),
            points: t.points.len(),
            triangles: t.triangles.len(),
            bbox_min: t.bbox.min.to_array(),
            bbox_max: t.bbox.max.to_array(),
            diagonal: t.bbox.diagonal(),
            repairs: self.repairs,
            left_out: self.left_out,
        })
    }

    /// Target points (or mesh vertices) as a flat `Float32Array`.
    #[wasm_bindgen(js_name = targetPositions)]
    pub fn target_positions(&self) -> Float32Array {
        vec3_array(&self.target.points)
    }

    /// Target triangles as a flat `Uint32Array` (empty for a point cloud).
    #[wasm_bindgen(js_name = targetIndices)]
    pub fn target_indices(&self) -> Uint32Array {
        index_array(&self.target.triangles)
    }

    /// Surface positions (target units).
    pub fn positions(&self) -> Float32Array {
        vec3_array(&self.run.evolver().positions())
    }

    /// Angle-weighted unit vertex normals.
    pub fn normals(&self) -> Float32Array {
        vec3_array(
            &crate::geometry::operators::normals::angle_weighted_normals(self.run.evolver().mesh()),
        )
    }

    /// Surface triangles as a flat `Uint32Array`.
    pub fn indices(&self) -> Uint32Array {
        index_array(&self.run.evolver().triangles())
    }

    /// A per-vertex scalar for colouring, by the name of a colour map of the catalog (see
    /// [`crate::flow::colour`]): "distance" (target units), "curvature" (mean curvature,
    /// 1/target units), "kappa" (vertex-averaged κ(J_Δ)), "covolume" (stabilised frame) or
    /// "features" (1 for feature vertices).
    pub fn scalar(&self, name: &str) -> Result<Float32Array, JsValue> {
        let map = ColourMap::from_name(name).ok_or_else(|| {
            let names: Vec<&str> = ColourMap::all().map(ColourMap::name).collect();
            UiError::unknown("unknown scalar", name, &names)
        })?;
        Ok(scalar_array(&self.run.colour(map, self.finished())))
    }

    /// The certificate of the current surface against the target (see
    /// [`crate::metrics::certificate::Certificate`]; keys in snake_case).
    pub fn certificate(&self) -> Result<JsValue, JsValue> {
        to_js(&self.result().certificate)
    }

    /// The current surface certified, with the core's verdict on it (see [`Outcome`] and
    /// [`crate::pipeline::Verdict`]). The page shows the verdict as it is.
    pub fn outcome(&self) -> Result<JsValue, JsValue> {
        let r = self.result().into_owned();
        to_js(&Outcome {
            certificate: r.certificate,
            verdict: r.verdict,
            hash: r.hash,
            stop_reason: r.stop_reason,
            started_over: r.started_over,
        })
    }

    /// Histogram of the per-triangle κ(J_Δ) (equilateral = 1) of the current surface over
    /// [1, `hi`) in `bins` bins: `{lo, hi, counts, below, above}` (see
    /// [`crate::metrics::histogram::kappa_histogram`]).
    #[wasm_bindgen(js_name = kappaHistogram)]
    pub fn kappa_histogram(&self, bins: u32, hi: f64) -> Result<JsValue, JsValue> {
        to_js(&crate::metrics::histogram::kappa_histogram(
            &self.run.evolver().positions(),
            &self.run.evolver().triangles(),
            bins as usize,
            hi,
        ))
    }

    /// The step limit in force (the start's own when `auto` resolved to the isosurface start).
    #[wasm_bindgen(js_name = stepLimit)]
    pub fn step_limit(&self) -> u32 {
        self.run.evolver().settings().stop.steps
    }

    /// Why the wrap stopped before its rule said so (divergence, solver failure), or null.
    #[wasm_bindgen(js_name = stopReason)]
    pub fn stop_reason(&self) -> Option<String> {
        self.run.evolver().stop_reason().map(str::to_owned)
    }

    /// How many stray points of a cloud the wrap left out (`tuning.field.outlier_spacings`).
    #[wasm_bindgen(js_name = isolatedPoints)]
    pub fn isolated_points(&self) -> u32 {
        self.run.evolver().isolated_points() as u32
    }

    /// Null, or how a target that the first pass left partly outside was wrapped a second time
    /// (see `flow::StartedOver`).
    #[wasm_bindgen(js_name = startedOver)]
    pub fn started_over(&self) -> Result<JsValue, JsValue> {
        to_js(&self.run.evolver().started_over())
    }

    /// How many specks of a mesh (small closed parts floating apart) the wrap left out.
    #[wasm_bindgen(js_name = specksLeftOut)]
    pub fn specks_left_out(&self) -> u32 {
        self.run.evolver().specks() as u32
    }

    /// The start surface actually used ("icosphere" or "isosurface").
    #[wasm_bindgen(js_name = startSurface)]
    pub fn start_surface(&self) -> String {
        serde_json::to_value(self.run.evolver().start_surface())
            .ok()
            .and_then(|v| v.as_str().map(str::to_owned))
            .unwrap_or_default()
    }

    /// Fingerprint of the current surface (see [`crate::mesh::fingerprint::mesh_hash`]).
    #[wasm_bindgen(js_name = resultHash)]
    pub fn result_hash(&self) -> String {
        crate::mesh::fingerprint::mesh_hash(
            &self.run.evolver().positions(),
            &self.run.evolver().triangles(),
        )
    }
}
