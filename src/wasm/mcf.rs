//! [`McfSession`]: the mean-curvature-flow lessons. [`McfSession::new`] flows an icosphere, the
//! teaching demo and the pipeline's smoke test, its radius checked against the analytic
//! r(t) = sqrt(r0² − 4t); [`McfSession::from_mesh`] flows a mesh the page loaded (smoothing as a
//! lesson, [`crate::flow::mcf_mesh`]), its area and volume plotted over time.

use super::errors::{ui_error, UiError};
use super::{index_array, scalar_array, to_js, vec3_array};
use crate::flow::mcf::{check_sphere_step, lesson_steps_left, lesson_tau_advice};
use crate::flow::{
    self, exact_sphere_radius, ColourMap, FlowError, McfSettings, MeshFlow, MeshFlowStats,
    LESSON_COLOUR_MAPS,
};
use crate::geometry::icosphere::icosphere;
use crate::geometry::sphere::mean_radius;
use crate::mesh::HalfedgeMesh;
use glam::DVec3;
use js_sys::{Float32Array, Uint32Array};
use serde::Serialize;
use wasm_bindgen::prelude::*;

/// Statistics of the current MCF state, for the UI's plots and labels (`SphereStats` in
/// TypeScript, where `McfStats` is either lesson's).
#[derive(Serialize, Debug, Clone, tsify::Tsify)]
#[serde(rename_all = "camelCase")]
#[tsify(rename = "SphereStats")]
pub struct McfStats {
    /// Which lesson: always "sphere" here ("mesh" for [`MeshLessonStats`]).
    #[tsify(type = "\"sphere\"")]
    pub lesson: &'static str,
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

/// Statistics of the mesh lesson: the core's [`MeshFlowStats`] (camelCase, flattened, `volume`
/// and `volumeRatio` null for an open mesh) with `lesson: "mesh"` and the wall time per step
/// (`MeshStats` in TypeScript).
#[derive(Serialize, Debug, Clone, tsify::Tsify)]
#[serde(rename_all = "camelCase")]
#[tsify(rename = "MeshStats")]
pub struct MeshLessonStats {
    /// Always "mesh".
    #[tsify(type = "\"mesh\"")]
    pub lesson: &'static str,
    #[serde(flatten)]
    pub flow: MeshFlowStats,
    /// Wall time of the last `step(n)` call divided by n, in milliseconds.
    pub ms_per_step: f64,
}

/// What a session flows: the icosphere of the sphere lesson, or a loaded mesh.
enum Lesson {
    Sphere {
        mesh: HalfedgeMesh,
        settings: McfSettings,
        r0: f64,
        stats: McfStats,
    },
    Mesh {
        flow: MeshFlow,
        ms_per_step: f64,
    },
}

/// A mean-curvature-flow session: on an icosphere (the teaching demo and the pipeline's smoke
/// test) or on a loaded mesh (the smoothing lesson).
#[wasm_bindgen]
pub struct McfSession {
    lesson: Lesson,
}

impl McfSession {
    /// The mesh being flowed.
    fn mesh(&self) -> &HalfedgeMesh {
        match &self.lesson {
            Lesson::Sphere { mesh, .. } => mesh,
            Lesson::Mesh { flow, .. } => flow.mesh(),
        }
    }
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
            lesson: "sphere",
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
            lesson: Lesson::Sphere {
                mesh,
                settings: McfSettings {
                    tau,
                    ..Default::default()
                },
                r0: radius,
                stats,
            },
        })
    }

    /// Starts the smoothing lesson on a loaded mesh: `positions` (x0, y0, z0, x1, …) and
    /// `indices` (a0, b0, c0, …) of a manifold triangle mesh, closed or open (its boundary stays
    /// pinned), flowed with time step `tau` given relative to the squared bounding-box diagonal
    /// (τ/D², see [`crate::flow::mcf_mesh`]; `flow::mcf_mesh::MESH_LESSON_TAU` = 5e-5 is the
    /// page's default). Errors (`bad-target`, `bad-parameter`) name what is wrong with the mesh.
    #[wasm_bindgen(js_name = fromMesh)]
    pub fn from_mesh(positions: &[f32], indices: &[u32], tau: f64) -> Result<McfSession, JsValue> {
        let flat: Vec<f64> = positions.iter().map(|&x| x as f64).collect();
        let flow = MeshFlow::from_flat(&flat, indices, tau).map_err(ui_error)?;
        Ok(McfSession {
            lesson: Lesson::Mesh {
                flow,
                ms_per_step: 0.0,
            },
        })
    }

    /// Which lesson this session is: "sphere" or "mesh".
    pub fn lesson(&self) -> String {
        match self.lesson {
            Lesson::Sphere { .. } => "sphere".into(),
            Lesson::Mesh { .. } => "mesh".into(),
        }
    }

    /// Advances `n` steps. Stops with an error (mesh unchanged by the failing step) if a solve
    /// fails or produces a non-finite position, or if a step of the sphere lesson would reach
    /// the sphere's extinction time r0²/4.
    pub fn step(&mut self, n: u32) -> Result<(), JsValue> {
        let t0 = crate::clock::now_ms();
        match &mut self.lesson {
            Lesson::Sphere {
                mesh,
                settings,
                r0,
                stats,
            } => {
                for _ in 0..n {
                    check_sphere_step(*r0, settings.tau, stats.step).map_err(ui_error)?;
                    let rep = flow::mcf_step(mesh, settings).map_err(ui_error)?;
                    stats.step += 1;
                    stats.time = stats.step as f64 * settings.tau;
                    stats.covolume_min = rep.covolume_min;
                    stats.covolume_mean = rep.covolume_mean;
                    stats.covolume_max = rep.covolume_max;
                    stats.solver_iterations = rep.solve.iterations;
                    stats.solver_residual = rep.solve.relative_residual;
                }
                stats.mean_radius = mean_radius(mesh.positions());
                stats.exact_radius = exact_sphere_radius(*r0, stats.time);
                if n > 0 {
                    stats.ms_per_step = (crate::clock::now_ms() - t0) / n as f64;
                }
            }
            Lesson::Mesh { flow, ms_per_step } => {
                for _ in 0..n {
                    flow.step().map_err(ui_error)?;
                }
                if n > 0 {
                    *ms_per_step = (crate::clock::now_ms() - t0) / n as f64;
                }
            }
        }
        Ok(())
    }

    /// Vertex positions as a flat `Float32Array` (x0, y0, z0, x1, …).
    pub fn positions(&self) -> Float32Array {
        vec3_array(self.mesh().positions())
    }

    /// Angle-weighted unit vertex normals as a flat `Float32Array`, for shading.
    pub fn normals(&self) -> Float32Array {
        vec3_array(&crate::geometry::operators::normals::angle_weighted_normals(self.mesh()))
    }

    /// Triangle vertex indices as a flat `Uint32Array`.
    pub fn indices(&self) -> Uint32Array {
        index_array(&self.mesh().triangles())
    }

    /// Per-vertex mean curvature H (1/r on a sphere of radius r).
    #[wasm_bindgen(js_name = meanCurvature)]
    pub fn mean_curvature(&self) -> Float32Array {
        scalar_array(&flow::mcf::mean_curvature(self.mesh()))
    }

    /// Steps the lesson still takes; 0 when it is over. The sphere: up to the radius 15 % of
    /// r0, never into the extinction time (see [`crate::flow::mcf::lesson_steps_left`]). A mesh:
    /// up to t = 0.01·D², or none once its area is below 5 % of the initial
    /// ([`MeshFlow::steps_left`]).
    #[wasm_bindgen(js_name = stepsLeft)]
    pub fn steps_left(&self) -> u32 {
        match &self.lesson {
            Lesson::Sphere {
                settings,
                r0,
                stats,
                ..
            } => lesson_steps_left(*r0, settings.tau, stats.step),
            Lesson::Mesh { flow, .. } => flow.steps_left(),
        }
    }

    /// What this session's τ means for the lesson, before it runs. The sphere: `{tau,
    /// extinctionTime, steps, tauMin, tauMax, sensible, warning}` (see
    /// [`crate::flow::TauAdvice`]); a mesh: `{tau, horizon, steps, tauMin, tauMax, sensible,
    /// warning}` with τ, its range and the horizon relative to D² (see
    /// [`crate::flow::MeshTauAdvice`]).
    #[wasm_bindgen(js_name = tauAdvice)]
    pub fn tau_advice(&self) -> Result<JsValue, JsValue> {
        match &self.lesson {
            Lesson::Sphere { settings, r0, .. } => to_js(&lesson_tau_advice(*r0, settings.tau)),
            Lesson::Mesh { flow, .. } => to_js(&flow.tau_advice()),
        }
    }

    /// A per-vertex scalar of the lesson's colour maps (`lessonColourMaps` in the catalog:
    /// "curvature", "kappa"), in mesh units.
    pub fn scalar(&self, name: &str) -> Result<Float32Array, JsValue> {
        let values = ColourMap::from_name(name).and_then(|m| m.mesh_values(self.mesh()));
        let values = values.ok_or_else(|| {
            UiError::unknown(
                "unknown lesson scalar",
                name,
                &LESSON_COLOUR_MAPS.map(ColourMap::name),
            )
        })?;
        Ok(scalar_array(&values))
    }

    /// Current statistics as a plain JS object: `McfStats` for the sphere, `MeshLessonStats`
    /// for a mesh (told apart by `lesson`).
    pub fn stats(&self) -> Result<JsValue, JsValue> {
        match &self.lesson {
            Lesson::Sphere { stats, .. } => to_js(stats),
            Lesson::Mesh { flow, ms_per_step } => {
                let stats = MeshLessonStats {
                    lesson: "mesh",
                    flow: flow.stats(),
                    ms_per_step: *ms_per_step,
                };
                // Flattened fields serialise as a map: ask for a plain object (and null for
                // an open mesh's volume).
                stats
                    .serialize(&serde_wasm_bindgen::Serializer::json_compatible())
                    .map_err(|e| JsValue::from_str(&e.to_string()))
            }
        }
    }
}
