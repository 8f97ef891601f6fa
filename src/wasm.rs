//! The `#[wasm_bindgen]` facade: converts core types to typed arrays and errors to
//! `{code, message, hint}` objects. It holds no algorithm; everything here delegates to the core.

use crate::flow::{self, exact_sphere_radius, FlowError, McfSettings};
use crate::geometry::icosphere::{icosphere, IcosphereError};
use crate::geometry::sphere::mean_radius;
use crate::mesh::HalfedgeMesh;
use glam::DVec3;
use js_sys::{Float32Array, Uint32Array};
use serde::Serialize;
use wasm_bindgen::prelude::*;

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
        let flat: Vec<f32> = crate::geometry::normals::angle_weighted_normals(&self.mesh)
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
