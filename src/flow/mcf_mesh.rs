//! Mean-curvature flow of a mesh the user loaded: the smoothing lesson.
//!
//! The sphere lesson ([`super::mcf`]) checks the scheme against an exact law; this one applies
//! the same implicit step, `(I − τΔ) F^{n+1} = F^n` ([`mcf_step_with`]), to any manifold
//! triangle mesh, closed or open, and watches what MCF does to it: noise and small bumps go
//! first (their curvature is largest), then the shape rounds and shrinks. There is no exact law
//! for a general mesh; what is known is that MCF is the gradient flow of area, so the area falls
//! monotonically — the lesson plots it (and the enclosed volume of a closed mesh) over time.
//!
//! **τ is relative to the mesh's size.** MCF is a diffusion: time has units of length², and
//! scaling a mesh by s scales the time any feature takes to smooth out by s² (a sphere of radius
//! r vanishes at r²/4). The lesson therefore takes τ as a fraction of D², D the bounding-box
//! diagonal, and flows with τ·D²: the same τ/D² does the same amount of smoothing per step on a
//! model in metres or a scan in millimetres, and the linear system `I + (τ/A_i)·L` — whose
//! conditioning depends on τ over the co-volumes A_i ∝ (edge length)² — is unchanged by scale.
//!
//! An open mesh's boundary is pinned (mobility 0, see [`mcf_step_with`]): at a boundary vertex
//! the cotangent Laplacian measures the boundary curve's curvature, not H, and a free boundary
//! would shrink into the hole. The flow then smooths the surface spanning the fixed boundary
//! towards a minimal surface, whose area it approaches from above.

use super::mcf::{
    mcf_step_with, stats, McfSettings, McfStepReport, LESSON_MAX_STEPS, LESSON_MIN_STEPS,
};
use super::FlowError;
use crate::mesh::{HalfedgeMesh, MeshBuildError};
use glam::DVec3;
use serde::Serialize;

/// The lesson ends at flow time t = `MESH_LESSON_HORIZON`·D². A sphere just inside its
/// bounding box (D² = 12 r²) has then shrunk to 90 % of its radius (it vanishes at D²/48 ≈
/// 0.021 D²); on a scan, noise and small features are gone long before, so a longer lesson
/// shows mostly a shrinking blob.
pub const MESH_LESSON_HORIZON: f64 = 0.004;

/// … or earlier, when the area falls below this fraction of the initial area: the mesh has
/// (nearly) collapsed, its triangles are needles and the flow shows the mesh, not the law.
pub const MESH_LESSON_STOP_AREA: f64 = 0.05;

/// … or when the largest |H| exceeds this many times 1/h, h = √(mean co-volume) the mesh's own
/// spacing: a mesh resolves curvature up to about 1/h, so beyond it triangles have collapsed to
/// needles (where a thin part pinches MCF forms a singularity, which a fixed mesh cannot pass),
/// and H and the solve measure the needles, not the flow.
pub const MESH_LESSON_COLLAPSE: f64 = 100.0;

/// The default relative time step τ/D²: 200 steps to the horizon.
pub const MESH_LESSON_TAU: f64 = 2e-5;

/// An entry of the app's lesson menu (the catalog's `lessons`).
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
#[serde(rename_all = "camelCase")]
pub struct LessonInfo {
    /// Stable name: "mcf" (the sphere, also the gallery id `demo:mcf`) or "mcf-mesh".
    pub name: &'static str,
    /// Button label.
    pub label: &'static str,
    /// What it shows, for the button's tooltip.
    pub title: &'static str,
    /// Whether it flows the loaded mesh (offered only while a mesh, not a point cloud or a
    /// volume, is loaded).
    pub needs_mesh: bool,
}

/// The MCF lessons, in menu order.
pub const LESSONS: [LessonInfo; 2] = [
    LessonInfo {
        name: "mcf",
        label: "MCF sphere",
        title: "Mean-curvature flow of a sphere against the exact law",
        needs_mesh: false,
    },
    LessonInfo {
        name: "mcf-mesh",
        label: "MCF on the loaded mesh",
        title: "Mean-curvature flow of the mesh you loaded: smoothing as a lesson (area and volume over time; an open mesh keeps its boundary)",
        needs_mesh: true,
    },
];

/// Why the MCF of a given mesh could not start, or a step of it failed.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum MeshMcfError {
    /// No vertices or no triangles. Fix: load a mesh (a point cloud has no triangles to flow).
    #[error("the mesh is empty ({vertices} vertices, {triangles} triangles): MCF needs triangles")]
    Empty { vertices: usize, triangles: usize },
    /// A flat array whose length is not a multiple of 3 (x, y, z or a, b, c per entry).
    #[error("{what} has {len} numbers, not a multiple of 3")]
    Ragged { what: &'static str, len: usize },
    /// A coordinate is NaN or infinite. Fix: clean the input; the index names the first bad vertex.
    #[error("vertex {vertex} has a non-finite coordinate")]
    NonFinite { vertex: usize },
    /// The triangles are not a manifold, consistently oriented surface (an edge with three
    /// faces, a bow-tie vertex, an index out of range, a repeated vertex). Fix: repair the mesh,
    /// or wrap it (the wrap's result is always manifold).
    #[error("the triangles are not a manifold surface: {0}")]
    NotManifold(#[from] MeshBuildError),
    /// All vertices coincide: the bounding box has no diagonal to measure τ against.
    #[error("the mesh has no extent (bounding-box diagonal {diagonal:e})")]
    NoExtent { diagonal: f64 },
    /// The relative time step τ/D² is not a positive finite number.
    #[error("time step τ/D² must be positive and finite, got {0}")]
    BadTimeStep(f64),
    /// A step failed (the solve, or a non-finite position): the mesh is left as it was before
    /// that step. Fix: a smaller τ/D².
    #[error("MCF step {step} (from t = {time:.3e}) failed: {source}")]
    Step {
        step: u32,
        time: f64,
        #[source]
        source: FlowError,
    },
}

/// Statistics of the current state of a mesh lesson (serialised camelCase for the page).
#[derive(Clone, Debug, PartialEq, Serialize)]
#[serde(rename_all = "camelCase")]
#[cfg_attr(target_arch = "wasm32", derive(tsify::Tsify))]
// Sent through the JSON-compatible serialiser (`wasm::mcf::McfSession::stats`): `None` arrives
// as null, and the TypeScript type must say so.
#[cfg_attr(target_arch = "wasm32", tsify(missing_as_null))]
pub struct MeshFlowStats {
    /// Steps taken.
    pub step: u32,
    /// Flow time t = step·τ, in squared mesh units.
    pub time: f64,
    /// t/D²: the time the plot shows (the horizon is [`MESH_LESSON_HORIZON`]).
    pub relative_time: f64,
    /// The step τ = (τ/D²)·D² in squared mesh units.
    pub tau: f64,
    /// Bounding-box diagonal D of the input.
    pub diagonal: f64,
    /// Surface area, and its ratio to the initial area.
    pub area: f64,
    pub area_ratio: f64,
    /// Enclosed (signed) volume and its ratio to the initial one; `None` for an open mesh.
    pub volume: Option<f64>,
    pub volume_ratio: Option<f64>,
    /// Mean and largest |H| over the moving (interior) vertices, 1/mesh units.
    pub mean_abs_h: f64,
    pub max_abs_h: f64,
    /// Co-volume min / mean / max before the last step (0 before the first).
    pub covolume_min: f64,
    pub covolume_mean: f64,
    pub covolume_max: f64,
    /// Solver iterations and relative residual of the last step.
    pub solver_iterations: usize,
    pub solver_residual: f64,
    /// Counts: vertices, faces, pinned boundary vertices.
    pub vertices: usize,
    pub faces: usize,
    pub boundary_vertices: usize,
    /// Whether the mesh is closed (no boundary), i.e. encloses a volume.
    pub closed: bool,
    /// Why the lesson stopped before its horizon, in a sentence for the page; `None` while it
    /// runs or once it reached the horizon.
    pub stopped_early: Option<String>,
}

/// What a relative time step τ/D² means for the mesh lesson, worked out before it runs.
#[derive(Clone, Debug, PartialEq, Serialize)]
#[serde(rename_all = "camelCase")]
#[cfg_attr(target_arch = "wasm32", derive(tsify::Tsify))]
pub struct MeshTauAdvice {
    /// The τ/D² asked about.
    pub tau: f64,
    /// The lesson's end, t/D² ([`MESH_LESSON_HORIZON`]).
    pub horizon: f64,
    /// Steps to the horizon.
    pub steps: u32,
    /// The sensible range of τ/D²: between [`LESSON_MAX_STEPS`] and [`LESSON_MIN_STEPS`] steps.
    pub tau_min: f64,
    pub tau_max: f64,
    /// Whether τ/D² is in that range.
    pub sensible: bool,
    /// What is wrong with τ/D², in one or two sentences for the page (empty when sensible).
    pub warning: String,
}

/// Steps of relative size `tau` to the horizon: the first n with n·τ ≥ horizon; 0 when τ is
/// not a positive finite number.
pub fn mesh_lesson_steps(tau: f64) -> u32 {
    if !(tau > 0.0 && tau.is_finite()) {
        return 0;
    }
    (MESH_LESSON_HORIZON / tau).ceil().min(u32::MAX as f64) as u32
}

/// Checks τ/D² for the mesh lesson (the page warns before running).
pub fn mesh_tau_advice(tau: f64) -> MeshTauAdvice {
    let horizon = MESH_LESSON_HORIZON;
    let (tau_min, tau_max) = (horizon / LESSON_MAX_STEPS, horizon / LESSON_MIN_STEPS);
    let steps = mesh_lesson_steps(tau);
    let range = format!("a sensible τ/D² lies between {tau_min:.1e} and {tau_max:.1e}");
    let warning = if !(tau > 0.0 && tau.is_finite()) {
        format!("τ/D² must be a positive number; {range}.")
    } else if tau >= horizon {
        format!(
            "τ/D² = {tau} is at least the whole lesson (it ends at t = {horizon}·D²): one step \
             would jump past all of the smoothing. {range}."
        )
    } else if tau > tau_max {
        format!(
            "τ/D² = {tau} is too large: the lesson reaches t = {horizon}·D² in only {steps} \
             steps, each smoothing away many triangles' worth of detail at once; {range}."
        )
    } else if tau < tau_min {
        format!("τ/D² = {tau} is very small: the lesson would take {steps} steps; {range}.")
    } else {
        String::new()
    };
    MeshTauAdvice {
        tau,
        horizon,
        steps,
        tau_min,
        tau_max,
        sensible: warning.is_empty(),
        warning,
    }
}

/// A mean-curvature flow of a given mesh, step by step (the state of the mesh lesson).
#[derive(Clone, Debug)]
pub struct MeshFlow {
    mesh: HalfedgeMesh,
    /// τ in squared mesh units (the relative τ/D² times D²).
    settings: McfSettings,
    tau_relative: f64,
    diagonal: f64,
    /// 0 at boundary vertices (pinned), 1 elsewhere; `None` for a closed mesh.
    mobility: Option<Vec<f64>>,
    boundary_vertices: usize,
    area0: f64,
    /// The largest |H| over the moving vertices times √(mean co-volume) after the step that
    /// collapsed a thin part (and was undone); `None` while none has.
    pinched: Option<f64>,
    volume0: Option<f64>,
    area: f64,
    step: u32,
    last: Option<McfStepReport>,
}

impl MeshFlow {
    /// Starts from flat arrays (x0, y0, z0, x1, … and a0, b0, c0, a1, …), as the page sends them.
    /// See [`MeshFlow::new`].
    pub fn from_flat(
        positions: &[f64],
        indices: &[u32],
        tau_relative: f64,
    ) -> Result<Self, MeshMcfError> {
        for (what, len) in [
            ("the position array", positions.len()),
            ("the index array", indices.len()),
        ] {
            if len % 3 != 0 {
                return Err(MeshMcfError::Ragged { what, len });
            }
        }
        let points: Vec<DVec3> = positions
            .chunks_exact(3)
            .map(|c| DVec3::new(c[0], c[1], c[2]))
            .collect();
        let triangles: Vec<[u32; 3]> = indices
            .chunks_exact(3)
            .map(|c| [c[0], c[1], c[2]])
            .collect();
        Self::new(points, &triangles, tau_relative)
    }

    /// Validates the mesh (non-empty, finite, a manifold triangle mesh with some extent) and
    /// τ/D², and prepares the flow with τ = (τ/D²)·D². Vertices no triangle uses are dropped
    /// (files often carry some; they have no neighbours to flow with).
    pub fn new(
        positions: Vec<DVec3>,
        triangles: &[[u32; 3]],
        tau_relative: f64,
    ) -> Result<Self, MeshMcfError> {
        if positions.is_empty() || triangles.is_empty() {
            return Err(MeshMcfError::Empty {
                vertices: positions.len(),
                triangles: triangles.len(),
            });
        }
        if let Some(vertex) = positions.iter().position(|p| !p.is_finite()) {
            return Err(MeshMcfError::NonFinite { vertex });
        }
        if !(tau_relative > 0.0 && tau_relative.is_finite()) {
            return Err(MeshMcfError::BadTimeStep(tau_relative));
        }
        let (positions, triangles) = drop_unused(positions, triangles)?;
        let mesh = HalfedgeMesh::from_triangles(positions, &triangles)?;
        check_vertex_fans(&mesh)?;
        let (lo, hi) = mesh.bounds();
        let diagonal = (hi - lo).length();
        if !(diagonal > 0.0 && diagonal.is_finite()) {
            return Err(MeshMcfError::NoExtent { diagonal });
        }
        let boundary: Vec<bool> = (0..mesh.n_vertices() as u32)
            .map(|v| mesh.is_boundary_vertex(v))
            .collect();
        let boundary_vertices = boundary.iter().filter(|&&b| b).count();
        let mobility = (boundary_vertices > 0).then(|| {
            boundary
                .iter()
                .map(|&b| if b { 0.0 } else { 1.0 })
                .collect()
        });
        let area0 = mesh.surface_area();
        let volume0 = (boundary_vertices == 0).then(|| mesh.signed_volume());
        Ok(Self {
            settings: McfSettings {
                tau: tau_relative * diagonal * diagonal,
                ..Default::default()
            },
            tau_relative,
            diagonal,
            mobility,
            boundary_vertices,
            area0,
            pinched: None,
            volume0,
            area: area0,
            step: 0,
            last: None,
            mesh,
        })
    }

    /// One implicit MCF step of τ = (τ/D²)·D², the boundary pinned, negative cotangent weights
    /// clamped to zero. On error, or where the step collapses a thin part (which ends the
    /// lesson: [`MeshFlow::stopped_early`]), the mesh is left as it was.
    ///
    /// The clamp makes every step a convex combination of the old positions (the system is an
    /// M-matrix with unit row sums: a discrete maximum principle), so no loaded mesh can blow up.
    /// Without it, meshes with sliver and obtuse triangles do: their area can grow manyfold
    /// within the lesson (the ±19.1 cotangent clamp likely leaves the operator indefinite on
    /// slivers). On an acute mesh such as the icosphere it changes nothing. Should
    /// the corrector pass's solve fail on a (nearly) collapsed mesh, the step is retried with the
    /// plain semi-implicit scheme, whose clamped system is strictly diagonally dominant.
    pub fn step(&mut self) -> Result<&McfStepReport, MeshMcfError> {
        let before = self.mesh.positions().to_vec();
        let mobility = self.mobility.as_deref();
        let report = match mcf_step_with(&mut self.mesh, &self.settings, mobility, true) {
            Err(FlowError::Solve(_)) if self.settings.corrector_passes > 0 => {
                let plain = McfSettings {
                    corrector_passes: 0,
                    ..self.settings.clone()
                };
                mcf_step_with(&mut self.mesh, &plain, mobility, true)
            }
            r => r,
        }
        .map_err(|source| MeshMcfError::Step {
            step: self.step + 1,
            time: self.time(),
            source,
        })?;
        let (_, max_abs_h) = self.abs_h();
        let sharpest = max_abs_h * report.covolume_mean.sqrt();
        if sharpest > MESH_LESSON_COLLAPSE {
            // The step collapsed a thin part: the lesson ends on the mesh before it (whose
            // co-volumes the report gives), not on needles.
            self.mesh.positions_mut().copy_from_slice(&before);
            self.pinched = Some(sharpest);
        } else {
            self.step += 1;
            self.area = self.mesh.surface_area();
        }
        Ok(self.last.insert(report))
    }

    /// Flow time t = steps·τ (squared mesh units).
    pub fn time(&self) -> f64 {
        self.step as f64 * self.settings.tau
    }

    /// Steps the lesson still takes: to the horizon t = [`MESH_LESSON_HORIZON`]·D², and none once
    /// it stopped early ([`MeshFlow::stopped_early`]).
    pub fn steps_left(&self) -> u32 {
        if self.collapsed() || self.pinched.is_some() {
            return 0;
        }
        mesh_lesson_steps(self.tau_relative).saturating_sub(self.step)
    }

    /// Why the lesson ends before its horizon: the area fell below [`MESH_LESSON_STOP_AREA`] of
    /// the start's, or the next step would have collapsed a thin part (|H| past
    /// [`MESH_LESSON_COLLAPSE`] over the mesh's spacing).
    pub fn stopped_early(&self) -> Option<String> {
        let at = format!(
            "at t = {:.3e}·D² (step {})",
            self.relative_time(),
            self.step
        );
        if self.collapsed() {
            return Some(format!(
                "Stopped {at}: the mesh has nearly collapsed (area {:.1} % of the start).",
                100.0 * self.area / self.area0
            ));
        }
        self.pinched.map(|sharpest| {
            format!(
                "Stopped {at}: the next step collapsed triangles to needles (|H| {sharpest:.0} \
                 times what the mesh's spacing resolves). A mesh of fixed connectivity cannot \
                 flow on from there: thin parts pinch and triangles degenerate."
            )
        })
    }

    /// Whether the area has fallen below [`MESH_LESSON_STOP_AREA`] of the start's.
    fn collapsed(&self) -> bool {
        self.area < MESH_LESSON_STOP_AREA * self.area0
    }

    /// Mean and largest |H| over the moving (interior) vertices.
    fn abs_h(&self) -> (f64, f64) {
        let h = super::mcf::mean_curvature(&self.mesh);
        let moving: Vec<f64> = h
            .iter()
            .enumerate()
            .filter(|(i, _)| self.mobility.as_ref().is_none_or(|m| m[*i] > 0.0))
            .map(|(_, x)| x.abs())
            .collect();
        let (_, mean, max) = stats(&moving);
        (mean, max)
    }

    /// t/D².
    fn relative_time(&self) -> f64 {
        self.time() / (self.diagonal * self.diagonal)
    }

    /// What this lesson's τ/D² means for it.
    pub fn tau_advice(&self) -> MeshTauAdvice {
        mesh_tau_advice(self.tau_relative)
    }

    /// The mesh as it is now.
    pub fn mesh(&self) -> &HalfedgeMesh {
        &self.mesh
    }

    /// The current statistics (O(mesh size): computes H).
    pub fn stats(&self) -> MeshFlowStats {
        let (mean_abs_h, max_abs_h) = self.abs_h();
        let volume = self.volume0.map(|_| self.mesh.signed_volume());
        let (covolume_min, covolume_mean, covolume_max, solver_iterations, solver_residual) =
            self.last.as_ref().map_or((0.0, 0.0, 0.0, 0, 0.0), |r| {
                (
                    r.covolume_min,
                    r.covolume_mean,
                    r.covolume_max,
                    r.solve.iterations,
                    r.solve.relative_residual,
                )
            });
        let time = self.time();
        MeshFlowStats {
            step: self.step,
            time,
            relative_time: self.relative_time(),
            tau: self.settings.tau,
            diagonal: self.diagonal,
            area: self.area,
            area_ratio: self.area / self.area0,
            volume,
            volume_ratio: volume.zip(self.volume0).map(|(v, v0)| v / v0),
            mean_abs_h,
            max_abs_h,
            covolume_min,
            covolume_mean,
            covolume_max,
            solver_iterations,
            solver_residual,
            vertices: self.mesh.n_vertices(),
            faces: self.mesh.n_faces(),
            boundary_vertices: self.boundary_vertices,
            closed: self.volume0.is_some(),
            stopped_early: self.stopped_early(),
        }
    }
}

/// Drops the vertices no triangle uses (renumbering the rest in order); indices out of range
/// are reported as [`MeshBuildError::IndexOutOfRange`].
fn drop_unused(
    positions: Vec<DVec3>,
    triangles: &[[u32; 3]],
) -> Result<(Vec<DVec3>, Vec<[u32; 3]>), MeshBuildError> {
    let count = positions.len();
    let mut new_index = vec![u32::MAX; count];
    for (face, t) in triangles.iter().enumerate() {
        for &vertex in t {
            let slot =
                new_index
                    .get_mut(vertex as usize)
                    .ok_or(MeshBuildError::IndexOutOfRange {
                        face,
                        vertex,
                        count,
                    })?;
            *slot = 0;
        }
    }
    let mut kept = Vec::with_capacity(count);
    for (i, p) in positions.into_iter().enumerate() {
        if new_index[i] == 0 {
            new_index[i] = kept.len() as u32;
            kept.push(p);
        }
    }
    let triangles = triangles
        .iter()
        .map(|t| t.map(|v| new_index[v as usize]))
        .collect();
    Ok((kept, triangles))
}

/// Refuses a vertex whose triangles form more than one fan (two sheets touching at a point):
/// [`HalfedgeMesh::from_triangles`] catches this only where the fans have boundaries.
fn check_vertex_fans(mesh: &HalfedgeMesh) -> Result<(), MeshBuildError> {
    let mut total = vec![0usize; mesh.n_vertices()];
    for h in 0..mesh.n_halfedges() as u32 {
        total[mesh.from(h) as usize] += 1;
    }
    for (v, &n) in total.iter().enumerate() {
        if mesh.outgoing(v as u32).count() != n {
            return Err(MeshBuildError::NonManifoldVertex { vertex: v as u32 });
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::flow::exact_sphere_radius;
    use crate::geometry::icosphere::icosphere;
    use crate::geometry::sphere::mean_radius;

    /// A level-`level` unit icosphere with deterministic radial bumps of relative size `amp`.
    fn bumpy(level: u32, amp: f64) -> (Vec<DVec3>, Vec<[u32; 3]>) {
        let m = icosphere(level, 1.0, DVec3::ZERO).unwrap();
        let p = m
            .positions()
            .iter()
            .enumerate()
            .map(|(i, p)| {
                let s = (crate::fmath::sin(i as f64 * 12.9898) * 43758.5453).fract();
                *p * (1.0 + amp * s)
            })
            .collect();
        (p, m.triangles())
    }

    #[test]
    fn loaded_icosphere_follows_the_sphere_law() {
        // The same bound as tests/mcf_sphere.rs: 1 % to t = 0.2 at τ ≈ 1e-3 (in r0² units).
        let m = icosphere(4, 1.0, DVec3::ZERO).unwrap();
        let (lo, hi) = m.bounds();
        let d2 = (hi - lo).length_squared();
        let mut flow = MeshFlow::new(m.positions().to_vec(), &m.triangles(), 1e-3 / d2).unwrap();
        let tau = flow.stats().tau;
        assert!((tau - 1e-3).abs() < 1e-15, "τ = {tau}");
        assert!(flow.stats().closed && flow.stats().boundary_vertices == 0);
        let mut worst = 0.0f64;
        while flow.time() < 0.2 - 1e-12 {
            flow.step().unwrap();
            flow.mesh().validate().unwrap();
            let exact = exact_sphere_radius(1.0, flow.time());
            let err = (mean_radius(flow.mesh().positions()) - exact).abs() / exact;
            assert!(
                err < 0.01,
                "step {}: radius off by {:.3} %",
                flow.step,
                100.0 * err
            );
            worst = worst.max(err);
        }
        // Area and volume follow 4πr², 4πr³/3 (to the mesh's discretisation).
        let s = flow.stats();
        let r = exact_sphere_radius(1.0, s.time);
        assert!((s.area_ratio - r * r).abs() < 0.02, "{s:?}");
        assert!((s.volume_ratio.unwrap() - r * r * r).abs() < 0.03, "{s:?}");
        // |H| ≈ 1/r.
        assert!((s.mean_abs_h * r - 1.0).abs() < 0.02, "{s:?}");
        println!(
            "loaded icosphere: worst radius error {:.3} %",
            100.0 * worst
        );
    }

    #[test]
    fn bumpy_mesh_area_decreases_monotonically() {
        let (p, t) = bumpy(3, 0.1);
        let mut flow = MeshFlow::new(p, &t, MESH_LESSON_TAU).unwrap();
        let h0 = flow.stats().max_abs_h;
        let mut area = flow.stats().area;
        let n = flow.steps_left();
        assert_eq!(n, 200);
        for _ in 0..n {
            flow.step().unwrap();
            let a = flow.stats().area;
            assert!(a < area, "area rose at step {}: {area} → {a}", flow.step);
            area = a;
        }
        assert_eq!(flow.steps_left(), 0);
        let s = flow.stats();
        // The bumps are gone: |H| is nearly uniform, far below the bumps' peak.
        println!("max |H| {h0} → {} (mean {})", s.max_abs_h, s.mean_abs_h);
        assert!(s.max_abs_h < 0.25 * h0, "max |H| {} from {h0}", s.max_abs_h);
        assert!(s.max_abs_h < 1.2 * s.mean_abs_h, "{s:?}");
        assert!((s.relative_time - MESH_LESSON_HORIZON).abs() < 1e-12);
        assert_eq!(s.stopped_early, None);
    }

    /// A dumbbell's neck (radius 0.06) pinches long before the lesson's horizon, at about the
    /// time a cylinder of its radius vanishes (r² = r0² − 2t: t = r0²/2): the lesson stops
    /// there and says why, every position finite.
    #[test]
    fn a_pinching_neck_stops_the_lesson_and_says_why() {
        let (p, t) = crate::demo::shapes::dumbbell(0.35, 0.06, 0.6);
        let mut flow = MeshFlow::new(p, &t, MESH_LESSON_TAU).unwrap();
        let all = flow.steps_left();
        while flow.steps_left() > 0 {
            flow.step().unwrap();
        }
        let s = flow.stats();
        let why = s
            .stopped_early
            .clone()
            .expect("the lesson ran to its horizon");
        println!("{why} ({} of {all} steps, t = {})", s.step, s.time);
        assert!(why.contains("collapsed triangles"), "{why}");
        // The lesson ends on the mesh before the collapse, not on the needles.
        assert!(
            s.max_abs_h * s.covolume_mean.sqrt() < MESH_LESSON_COLLAPSE,
            "{s:?}"
        );
        let pinch = 0.5 * 0.06 * 0.06;
        assert!(
            (0.5 * pinch..3.0 * pinch).contains(&s.time),
            "t = {}",
            s.time
        );
        assert!(flow.mesh().positions().iter().all(|p| p.is_finite()));
    }

    #[test]
    fn open_mesh_keeps_its_boundary_and_loses_area() {
        // The upper half of a bumpy sphere: the rim is pinned, the cap flattens towards the disc.
        let (p, t) = bumpy(3, 0.05);
        let t: Vec<[u32; 3]> = t
            .into_iter()
            .filter(|f| f.iter().all(|&v| p[v as usize].z > -1e-9))
            .collect();
        let mut flow = MeshFlow::new(p, &t, 2e-4).unwrap();
        let s0 = flow.stats();
        assert!(
            !s0.closed && s0.volume.is_none() && s0.boundary_vertices > 0,
            "{s0:?}"
        );
        let boundary: Vec<(usize, DVec3)> = (0..flow.mesh().n_vertices() as u32)
            .filter(|&v| flow.mesh().is_boundary_vertex(v))
            .map(|v| (v as usize, flow.mesh().position(v)))
            .collect();
        let mut area = s0.area;
        while flow.steps_left() > 0 {
            flow.step().unwrap();
            assert!(flow.stats().area < area);
            area = flow.stats().area;
        }
        for (v, p) in boundary {
            assert_eq!(flow.mesh().positions()[v], p, "boundary vertex {v} moved");
        }
        assert!(area < 0.9 * s0.area, "{area} of {}", s0.area);
    }

    #[test]
    fn same_relative_tau_same_flow_at_any_scale() {
        let (p, t) = bumpy(2, 0.1);
        let big: Vec<DVec3> = p.iter().map(|x| *x * 1000.0).collect();
        let mut a = MeshFlow::new(p, &t, MESH_LESSON_TAU).unwrap();
        let mut b = MeshFlow::new(big, &t, MESH_LESSON_TAU).unwrap();
        for _ in 0..20 {
            a.step().unwrap();
            b.step().unwrap();
        }
        let (sa, sb) = (a.stats(), b.stats());
        assert!(
            (sa.area_ratio - sb.area_ratio).abs() < 1e-6,
            "{sa:?} {sb:?}"
        );
        assert!((sa.relative_time - sb.relative_time).abs() < 1e-15);
    }

    #[test]
    fn bad_meshes_are_typed_errors() {
        let (p, t) = bumpy(1, 0.0);
        let e = |p: Vec<DVec3>, t: &[[u32; 3]]| MeshFlow::new(p, t, 1e-4).err().unwrap();
        assert!(matches!(e(vec![], &[]), MeshMcfError::Empty { .. }));
        assert!(matches!(e(p.clone(), &[]), MeshMcfError::Empty { .. }));
        let mut nan = p.clone();
        nan[3].y = f64::NAN;
        assert!(matches!(e(nan, &t), MeshMcfError::NonFinite { vertex: 3 }));
        // A third triangle on one edge.
        let mut three = t.clone();
        let [a, b, _] = t[0];
        three.push([a, b, p.len() as u32 - 1]);
        assert!(matches!(
            e(p.clone(), &three),
            MeshMcfError::NotManifold(MeshBuildError::NonManifoldEdge { .. })
        ));
        // Two closed spheres sharing one vertex (a pinch): no boundary, two fans.
        let (q, u) = bumpy(1, 0.0);
        let n = p.len() as u32;
        let mut both: Vec<DVec3> = p.clone();
        both.extend(q.iter().map(|x| *x + DVec3::new(2.0, 0.0, 0.0)));
        let mut tris = t.clone();
        // Glue: the second sphere's vertex nearest the first uses the first's vertex index.
        let glue_a = (0..n)
            .max_by(|&i, &j| p[i as usize].x.total_cmp(&p[j as usize].x))
            .unwrap();
        let glue_b = (0..q.len() as u32)
            .min_by(|&i, &j| q[i as usize].x.total_cmp(&q[j as usize].x))
            .unwrap();
        tris.extend(
            u.iter()
                .map(|f| f.map(|v| if v == glue_b { glue_a } else { v + n })),
        );
        assert!(matches!(
            e(both, &tris),
            MeshMcfError::NotManifold(MeshBuildError::NonManifoldVertex { .. })
        ));
        assert!(matches!(
            e(p.clone(), &[[0, 1, 99]]),
            MeshMcfError::NotManifold(MeshBuildError::IndexOutOfRange { vertex: 99, .. })
        ));
        let point = vec![DVec3::ONE; 3];
        assert!(matches!(
            MeshFlow::new(point, &[[0, 1, 2]], 1e-4).err().unwrap(),
            MeshMcfError::NoExtent { .. }
        ));
        for tau in [0.0, -1.0, f64::NAN] {
            assert!(matches!(
                MeshFlow::new(p.clone(), &t, tau).err().unwrap(),
                MeshMcfError::BadTimeStep(_)
            ));
        }
        assert!(matches!(
            MeshFlow::from_flat(&[0.0; 4], &[0, 1, 2], 1e-4)
                .err()
                .unwrap(),
            MeshMcfError::Ragged { .. }
        ));
    }

    #[test]
    fn unused_vertices_are_dropped() {
        let (mut p, t) = bumpy(1, 0.0);
        let n = p.len();
        p.push(DVec3::splat(50.0)); // far away, referenced by nothing: must not set D
        let flow = MeshFlow::new(p, &t, 1e-4).unwrap();
        assert_eq!(flow.mesh().n_vertices(), n);
        assert!(flow.stats().diagonal < 4.0);
    }

    #[test]
    fn tau_advice_range() {
        let ok = mesh_tau_advice(MESH_LESSON_TAU);
        assert!(ok.sensible && ok.steps == 200, "{ok:?}");
        assert!(!mesh_tau_advice(1e-3).sensible);
        assert!(mesh_tau_advice(0.02).warning.contains("one step"));
        assert!(mesh_tau_advice(1e-8).warning.contains("very small"));
        assert!(!mesh_tau_advice(f64::NAN).sensible);
        assert_eq!(mesh_lesson_steps(-1.0), 0);
    }
}
