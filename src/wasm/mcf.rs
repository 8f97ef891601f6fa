//! [`McfSession`]: mean-curvature flow of an icosphere, the teaching demo and the pipeline's smoke
//! test; its radius is checked against the analytic r(t) = sqrt(r0² − 4t).

use super::errors::{ui_error, UiError};
use super::{index_array, scalar_array, to_js, vec3_array};
use crate::flow::mcf::{check_sphere_step, lesson_steps_left, lesson_tau_advice};
use crate::flow::{
    self, exact_sphere_radius, ColourMap, FlowError, McfSettings, LESSON_COLOUR_MAPS,
};
use crate::geometry::icosphere::icosphere;
use crate::geometry::sphere::mean_radius;
use crate::mesh::HalfedgeMesh;
use glam::DVec3;
use js_sys::{Float32Array, Uint32Array};
use serde::Serialize;
use wasm_bindgen::prelude::*;

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
        let mesh = icosphere(level, radius, DVec3::ZERO).map_err(ui_error)?;
        if !(tau > 0.0 && tau.is_finite()) {
            return Err(ui_error(FlowError::BadTimeStep(tau)));
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

    /// Advances `n` steps. Stops with an error (mesh unchanged by the failing step) if a solve
    /// fails or a step would reach the sphere's extinction time r0²/4.
    pub fn step(&mut self, n: u32) -> Result<(), JsValue> {
        let t0 = crate::clock::now_ms();
        for _ in 0..n {
            check_sphere_step(self.r0, self.settings.tau, self.stats.step).map_err(ui_error)?;
            let rep = flow::mcf_step(&mut self.mesh, &self.settings).map_err(ui_error)?;
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
        vec3_array(self.mesh.positions())
    }

    /// Angle-weighted unit vertex normals as a flat `Float32Array`, for shading.
    pub fn normals(&self) -> Float32Array {
        vec3_array(&crate::geometry::operators::normals::angle_weighted_normals(&self.mesh))
    }

    /// Triangle vertex indices as a flat `Uint32Array`.
    pub fn indices(&self) -> Uint32Array {
        index_array(&self.mesh.triangles())
    }

    /// Per-vertex mean curvature H (1/r on a sphere of radius r).
    #[wasm_bindgen(js_name = meanCurvature)]
    pub fn mean_curvature(&self) -> Float32Array {
        scalar_array(&flow::mcf::mean_curvature(&self.mesh))
    }

    /// Steps the lesson still takes: up to the radius 15 % of r0, never into the extinction
    /// time (see [`crate::flow::mcf::lesson_steps_left`]); 0 when it is over.
    #[wasm_bindgen(js_name = stepsLeft)]
    pub fn steps_left(&self) -> u32 {
        lesson_steps_left(self.r0, self.settings.tau, self.stats.step)
    }

    /// What this session's τ means for the lesson, before it runs: `{tau, extinctionTime,
    /// steps, tauMin, tauMax, sensible, warning}` (see [`crate::flow::TauAdvice`]).
    #[wasm_bindgen(js_name = tauAdvice)]
    pub fn tau_advice(&self) -> Result<JsValue, JsValue> {
        to_js(&lesson_tau_advice(self.r0, self.settings.tau))
    }

    /// A per-vertex scalar of the lesson's colour maps (`lessonColourMaps` in the catalog:
    /// "curvature", "kappa"), in mesh units.
    pub fn scalar(&self, name: &str) -> Result<Float32Array, JsValue> {
        let values = ColourMap::from_name(name).and_then(|m| m.mesh_values(&self.mesh));
        let values = values.ok_or_else(|| {
            UiError::unknown(
                "unknown lesson scalar",
                name,
                &LESSON_COLOUR_MAPS.map(ColourMap::name),
            )
        })?;
        Ok(scalar_array(&values))
    }

    /// Current statistics as a plain JS object (see `McfStats`).
    pub fn stats(&self) -> Result<JsValue, JsValue> {
        to_js(&self.stats)
    }
}
