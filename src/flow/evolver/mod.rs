//! The LSW evolution as a step-wise state machine: `Evolver::new(target, settings)`, then
//! `step()` until `is_done()`. Each step is the semi-implicit scheme of docs/method.md §6.1–6.4:
//! implicit (cotangent) diffusion weighted by ε, explicit advection η·N and tangential
//! redistribution, one matrix for x, y, z; then adaptive remeshing and the size/τ schedule.
//! Work happens in the stabilised frame (see [`super::scaling`]); results come out in the
//! target's units.
//!
//! A step is a sequence of named phases, one file each with its own [`PhaseTimes`] entry:
//! [`forces`] (sample the field: ε, η, tangential) → [`solve`] (assemble and solve) →
//! [`advance`] (move, divergence guard) → [`remeshing`] → [`contact`] (contact guard) →
//! [`schedule`] (sizes, τ, stop rule) → [`fit`] (final fit, last step) → [`surgery`] (topology,
//! every few steps). A new phase is one file and one line in `Evolver::step_once`. After the
//! last step a target that the first pass left partly outside is wrapped again
//! ([`second_pass`]).

mod advance;
mod contact;
mod fit;
pub use super::fit::FitTimes;
mod fit_view;
pub use fit_view::CreaseJob;
use fit_view::PendingCreases;
mod forces;
mod second_pass;
mod setup;
pub use second_pass::{StartedOver, ThirdPass, SECOND_PASS_PHASE};
mod remeshing;
mod schedule;
mod solve;
mod start_choice;
mod surgery;

use super::guard::{ContactReport, Divergence, DivergenceLimits};
use super::mcf::stats;
use super::scaling::written;
use super::settings::{StartSurface, WrapSettings};
use super::snap::SnapTarget;
use super::surgery::SurgeryEvent;
use crate::clock::now_ms;
use crate::field::DistanceField;
use crate::geometry::creases::Creases;
use crate::mesh::HalfedgeMesh;
use crate::parallel::Later;
use crate::progress::Progress;
use crate::remesh::adaptive::RemeshReport;
use crate::remesh::sizing::EdgeSizes;
use crate::target::Target;
use contact::Contact;
use glam::DVec3;
use serde::Serialize;

/// The progress phase of a cloud's crease detection (before the steps).
pub const CREASE_PHASE: &str = "sharp creases";
/// The progress phase of a cloud's stray-point test (before the field).
pub const STRAY_PHASE: &str = "stray points";
/// The progress phase of the start surface.
pub const START_PHASE: &str = "start surface";

pub use super::evolve_error::EvolveError;

/// Wall time of the phases of one step, in milliseconds.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize)]
#[cfg_attr(target_arch = "wasm32", derive(tsify::Tsify))]
pub struct PhaseTimes {
    /// Surface terms (normals, cotangent weights, co-volumes, tangential sums, in one pass
    /// over the faces) and control functions.
    pub normals: f64,
    /// Matrix and right-hand sides.
    pub assembly: f64,
    /// Linear solves (all retries).
    pub solve: f64,
    /// Adaptive remeshing.
    pub remesh: f64,
    /// Divergence and contact guards (self-intersection checks, reverts).
    pub guard: f64,
    /// Final fit (last step only).
    pub fit: f64,
    /// The final fit, part by part.
    pub fit_parts: FitTimes,
    /// Topology surgery (detection, and the cut, glue and remesh when it operates).
    pub surgery: f64,
    /// Steps whose reports went unseen on the way to this one: the step whose contact check
    /// found intersections since the last certified state (it was undone), and the steps redone
    /// from that state before this one. Their whole time, included in `total`.
    pub redone: f64,
    /// The whole step.
    pub total: f64,
}

/// What one step did. Distances are in the target's units; co-volumes in the stabilised frame
/// (where the method expects their mean to shrink from τ/σ towards τ).
#[derive(Clone, Debug, PartialEq, Serialize)]
#[cfg_attr(target_arch = "wasm32", derive(tsify::Tsify))]
pub struct StepReport {
    /// Steps completed (1 after the first).
    pub step: u32,
    /// Vertex and face counts after the step (and remesh).
    pub vertices: usize,
    pub faces: usize,
    /// τ used by this step (after any retries).
    pub tau: f64,
    /// Retries (τ halvings) this step needed.
    pub retries: u32,
    /// Solver iterations (worst of x, y, z) and true relative residual.
    pub solver_iterations: usize,
    pub solver_residual: f64,
    /// Co-volume (mixed Voronoi area) min / mean / max before the step, stabilised frame.
    pub covolume_min: f64,
    pub covolume_mean: f64,
    pub covolume_max: f64,
    /// Mean and max |d| over vertices after the step (field distance, target units).
    pub distance_mean: f64,
    pub distance_max: f64,
    /// Fraction of vertices that moved less than the stop threshold in this step.
    pub settled_fraction: f64,
    /// Genus of the surface after the step, summed over its components (from its counts: it is
    /// closed, so E = 3F/2 and Σ genus = components − χ/2).
    pub genus: i64,
    /// The remesher's report, if it ran.
    pub remesh: Option<RemeshReport>,
    /// Vertices moved by the final fit onto the target (only in the last step).
    pub fitted: Option<usize>,
    /// What the contact guard did after the move (pairs found, vertices put back).
    pub contacts: ContactReport,
    /// Vertices held by the contact guard during this step (advection off).
    pub held: usize,
    /// True when this step's remesh was undone because it left intersecting faces.
    pub remesh_reverted: bool,
    /// Topology changes made at the end of this step.
    pub surgery: Vec<SurgeryEvent>,
    /// Per-phase wall times.
    pub times: PhaseTimes,
    /// True when the stopping rule or the step limit has been reached.
    pub done: bool,
}

/// The evolving surface and everything the step needs.
pub struct Evolver {
    settings: WrapSettings,
    mesh: HalfedgeMesh,
    field: DistanceField,
    center: DVec3,
    phi: f64,
    d0: f64,
    tau: f64,
    d1: f64,
    sizes: EdgeSizes,
    step: u32,
    done: bool,
    /// Per-step displacement threshold for the stopping rule (stabilised frame).
    settle_threshold: f64,
    /// Per-vertex field distance (stabilised frame), refreshed after each step.
    distances: Vec<f64>,
    /// Per-vertex −∇d/|∇d| at the same positions.
    gradients: Vec<DVec3>,
    /// The target for the final fit (stabilised frame).
    fit_target: Option<SnapTarget>,
    /// The target's sharp creases for the final fit (stabilised frame): from dihedral angles
    /// on a mesh, from plane fits on a cloud; None with `fit.crease_angle_deg` = 0.
    creases: Option<Creases>,
    /// The creases while they are still being found (natively, beside the steps) or left to
    /// the fit (wasm): they become `creases` when the fit starts.
    pending_creases: Option<PendingCreases>,
    /// Stray points of the cloud left out of the wrap (see [`Target::without_isolated_points`]).
    isolated_points: usize,
    /// Specks of the mesh left out of the wrap (see [`Target::without_specks`]).
    specks: usize,
    /// The mesh without its specks, where it had any: what the wrap is certified against.
    despecked: Option<Target>,
    /// The schedule changed the target edge lengths since the last remesh.
    sizes_changed: bool,
    /// The start surface actually built.
    start: StartSurface,
    /// The region, area and vertex count beyond which a step counts as diverged.
    limits: DivergenceLimits,
    /// Why the evolution stopped before its rule said so (divergence, solver failure).
    stop_reason: Option<String>,
    /// The last state the contact guard certified free of self-intersections.
    checkpoint: Checkpoint,
    /// Steps left in which the contact guard checks every step (after a roll-back).
    guarded_left: u32,
    /// Surgery's "far from the data" distance (stabilised frame).
    empty_distance: f64,
    /// A cloud's median spacing (stabilised frame), for surgery's reading of "far" where the
    /// cloud is sampled sparsely, over the fit's grid (see `surgery::SPARSE`); None for a mesh.
    cloud_spacing: Option<f64>,
    /// Half of `surgery.close_gaps` diagonals (stabilised frame): a tunnel narrower than this
    /// stays closed.
    close_gap_distance: f64,
    /// The target's genus where it is known (a closed one-part mesh's): no neck cut takes the
    /// surface below it.
    least_genus: Option<i64>,
    /// Every topology change so far.
    surgery_events: Vec<SurgeryEvent>,
    /// The tunnels opened so far (middle, farthest wall; stabilised frame): nothing pairs there.
    tunnels_opened: Vec<(DVec3, f64)>,
    /// Vertices paired with a facing sheet at surgery's last look.
    surgery_paired: usize,
    /// The last look found the surface intersecting itself: look again at the next step.
    surgery_pending: bool,
    /// The second pass, for when the first leaves part of the target outside, while it may still
    /// come ([`second_pass`]).
    second_pass: Option<Box<second_pass::SecondPass>>,
    /// Why and how the evolution started over, when it did.
    started_over: Option<second_pass::StartedOver>,
}

/// What the evolution needs to resume from a certified state.
#[derive(Clone)]
struct Checkpoint {
    mesh: HalfedgeMesh,
    tau: f64,
    d1: f64,
    sizes: EdgeSizes,
    step: u32,
    sizes_changed: bool,
}

/// What the phases of one step report, gathered for [`StepReport`].
struct StepParts<'a> {
    tau: f64,
    solved: &'a solve::Solved,
    covolumes: (f64, f64, f64),
    settled_fraction: f64,
    held: usize,
    remesh: Option<RemeshReport>,
    fitted: Option<usize>,
    contacts: ContactReport,
    remesh_reverted: bool,
    surgery: Vec<SurgeryEvent>,
}

impl Evolver {
    /// Samples d and −∇d at every vertex (the step reads both at these positions).
    fn refresh_distances(&mut self) {
        let (field, pos) = (&self.field, self.mesh.positions());
        (self.distances, self.gradients) =
            crate::parallel::map(pos.len(), |i| field.sample_with_gradient(pos[i]))
                .into_iter()
                .unzip();
    }

    /// A cloud's crease detection while it is left to the final fit (in wasm; None natively,
    /// where it runs beside the steps, and once found): another worker may run it meanwhile and
    /// bring the result to [`Evolver::supply_creases`], sparing the fit that time.
    pub fn crease_job(&self) -> Option<CreaseJob> {
        match self.pending_creases.as_ref()? {
            PendingCreases::Deferred(job) => Some(job.clone()),
            PendingCreases::Later(_) => None,
        }
    }

    /// Takes the result of [`Evolver::crease_job`]'s job; false (and nothing changes) when the
    /// creases are no longer pending (the fit found them already) or were never left to it.
    pub fn supply_creases(&mut self, creases: Option<Creases>) -> bool {
        if !matches!(self.pending_creases, Some(PendingCreases::Deferred(_))) {
            return false;
        }
        self.pending_creases = Some(PendingCreases::Later(Later::ready(creases)));
        true
    }

    /// True when the step limit or the stopping rule has been reached.
    pub fn is_done(&self) -> bool {
        self.done
    }

    /// Steps completed.
    pub fn steps_done(&self) -> u32 {
        self.step
    }

    /// The settings in use (τ and D1 there are the initial values).
    pub fn settings(&self) -> &WrapSettings {
        &self.settings
    }

    /// The stabilisation factor φ.
    pub fn scale(&self) -> f64 {
        self.phi
    }

    /// d₀ in the target's units.
    pub fn iso_level(&self) -> f64 {
        self.d0 / self.phi
    }

    /// The distance field (in the stabilised frame).
    pub fn field(&self) -> &DistanceField {
        &self.field
    }

    /// The evolving mesh in the stabilised frame.
    pub fn mesh(&self) -> &HalfedgeMesh {
        &self.mesh
    }

    /// Vertex positions in the target's units, rounded to f32 as every output format stores
    /// them: what is certified, hashed and shown is exactly what is written.
    pub fn positions(&self) -> Vec<DVec3> {
        self.mesh
            .positions()
            .iter()
            .map(|&p| written(p, self.phi, self.center))
            .collect()
    }

    /// Triangles (counter-clockwise, outward).
    pub fn triangles(&self) -> Vec<[u32; 3]> {
        self.mesh.triangles()
    }

    /// Per-vertex distance to the target as the field samples it, |d| in the target's units (the
    /// exact one is the certificate's: `WrapResult::distances`).
    pub fn vertex_distances(&self) -> Vec<f64> {
        self.distances.iter().map(|d| d.abs() / self.phi).collect()
    }

    /// The start surface actually built (`Auto` resolved).
    pub fn start_surface(&self) -> StartSurface {
        self.start
    }

    /// How many stray points of the cloud the wrap left out (0 for meshes).
    pub fn isolated_points(&self) -> usize {
        self.isolated_points
    }

    /// How many specks of the mesh (small closed parts floating apart) the wrap left out (0 for
    /// clouds; see [`crate::geometry::specks`]).
    pub fn specks(&self) -> usize {
        self.specks
    }

    /// The mesh as wrapped where that is not the target given: without its specks (see
    /// [`Self::specks`]). The certificate's side of the target is this one, so that the specks
    /// left out do not count as part of the target lying outside the wrap.
    pub fn despecked_target(&self) -> Option<&Target> {
        self.despecked.as_ref()
    }

    /// Every topology change so far, in order.
    pub fn surgery_events(&self) -> &[SurgeryEvent] {
        &self.surgery_events
    }

    /// Why the evolution stopped early (divergence, solver failure), if it did.
    pub fn stop_reason(&self) -> Option<&str> {
        self.stop_reason.as_deref()
    }

    /// One LSW step: surface terms → assemble and solve → divergence guard → remesh → contact
    /// guard → schedule → (last step) final fit. On error the surface is the last certified one
    /// and the evolution is over (see [`Evolver::stop_reason`]).
    ///
    /// The contact guard checks every `tuning.guard.check_every` steps (and always before the final
    /// fit). When a check fails, the evolution goes back to the last certified state and redoes
    /// the steps from there checking each one, resolving contacts locally; the report returned
    /// is the requested step's.
    pub fn step(&mut self) -> Result<StepReport, EvolveError> {
        self.step_with_progress(&mut Progress::none())
    }

    /// [`Evolver::step`], reporting the final fit (the last step's long part) to `progress`.
    pub fn step_with_progress(
        &mut self,
        progress: &mut Progress,
    ) -> Result<StepReport, EvolveError> {
        let wanted = self.step + 1;
        // Surgery done in steps that were redone is still done: its events go with the report.
        let mut events = Vec::new();
        let mut redone = 0.0;
        loop {
            let mut r = self.step_once(progress)?;
            events.append(&mut r.surgery);
            if self.step >= wanted || self.done {
                r.surgery = events;
                r.times.redone = redone;
                r.times.total += redone;
                return Ok(match self.done {
                    true => self.second_pass_if_outside(r, progress),
                    false => r,
                });
            }
            redone += r.times.total;
        }
    }

    /// Saves the current state as certified.
    fn save_checkpoint(&mut self) {
        self.checkpoint = Checkpoint {
            mesh: self.mesh.clone(),
            tau: self.tau,
            d1: self.d1,
            sizes: self.sizes,
            step: self.step,
            sizes_changed: self.sizes_changed,
        };
    }

    /// Returns to the last certified state.
    fn restore_checkpoint(&mut self) {
        let c = self.checkpoint.clone();
        self.mesh = c.mesh;
        self.tau = c.tau;
        self.d1 = c.d1;
        self.sizes = c.sizes;
        self.step = c.step;
        self.sizes_changed = c.sizes_changed;
        self.done = false;
        self.refresh_distances();
    }

    /// One pass through the phases, each in its own file with its own timing entry.
    fn step_once(&mut self, progress: &mut Progress) -> Result<StepReport, EvolveError> {
        let t_start = now_ms();
        let mut times = PhaseTimes::default();
        let forces = self.forces(&mut times);
        let old = self.mesh.positions().to_vec();
        let solved = self.solve(&forces, &old, &mut times)?;
        let tau_used = solved.tau;
        let moved = self.advance(&solved.x, &old, &mut times)?;
        let ends = self.ends(moved.settled_fraction);
        // On a cloud, the step that ends the run leaves the remesh to the final fit, whose
        // first pass remeshes to the same sizes anyway: a remesh here would cost time on a
        // surface that the fit's moves then distort. A mesh's fit sizes its edges by where it
        // still misses the target, which needs the fine surface from this remesh (see
        // docs/decisions/0022-fit-error-sizing.md).
        let fits = ends && matches!(self.fit_target, Some(SnapTarget::Points(_)));
        let remesh = match fits {
            true => None,
            false => self.remesh_if_due(&mut times)?,
        };
        let contact = self.contact_guard(
            moved.pre,
            &solved.x,
            &old,
            remesh.is_some(),
            ends,
            &mut times,
        )?;
        let mut parts = StepParts {
            tau: tau_used,
            solved: &solved,
            covolumes: stats(&forces.terms.laplacian.covolumes),
            settled_fraction: moved.settled_fraction,
            held: forces.held,
            remesh: None,
            fitted: None,
            contacts: ContactReport::default(),
            remesh_reverted: false,
            surgery: Vec::new(),
        };
        match contact {
            Contact::Checked(contacts, remesh_reverted) => {
                (parts.contacts, parts.remesh_reverted) = (contacts, remesh_reverted);
            }
            Contact::RolledBack { from } => {
                // Intersections since the last certified state: the steps are redone from there.
                parts.tau = self.tau;
                parts.contacts.rolled_back_from = from;
                times.total = now_ms() - t_start;
                return Ok(self.report(parts, times));
            }
        }
        self.schedule();
        self.done = ends;
        let last_cut = match ends {
            true => self.surgery_last(&mut times),
            false => Vec::new(),
        };
        parts.fitted = self.fit_if_done(&mut times, progress);
        parts.remesh = remesh;
        self.refresh_distances();
        parts.surgery = self.surgery_if_due(&mut times);
        parts.surgery.splice(0..0, last_cut);
        times.total = now_ms() - t_start;
        Ok(self.report(parts, times))
    }

    /// The report of the step just taken (distances at the current surface).
    fn report(&self, p: StepParts, times: PhaseTimes) -> StepReport {
        let (mut dmean, mut dmax) = (0.0, 0.0f64);
        for d in &self.distances {
            dmean += d.abs();
            dmax = dmax.max(d.abs());
        }
        dmean /= self.distances.len().max(1) as f64;
        let (covolume_min, covolume_mean, covolume_max) = p.covolumes;
        StepReport {
            step: self.step,
            vertices: self.mesh.n_vertices(),
            faces: self.mesh.n_faces(),
            tau: p.tau,
            retries: p.solved.retries,
            solver_iterations: p.solved.report.iterations,
            solver_residual: p.solved.report.relative_residual,
            covolume_min,
            covolume_mean,
            covolume_max,
            distance_mean: dmean / self.phi,
            distance_max: dmax / self.phi,
            settled_fraction: p.settled_fraction,
            genus: self.mesh.count_components() as i64
                - (self.mesh.n_vertices() as i64 - self.mesh.n_faces() as i64 / 2) / 2,
            remesh: p.remesh,
            fitted: p.fitted,
            contacts: p.contacts,
            held: p.held,
            remesh_reverted: p.remesh_reverted,
            surgery: p.surgery,
            times,
            done: self.done,
        }
    }

    /// Ends the evolution with `err` as the reason.
    fn stop(&mut self, err: &EvolveError) {
        self.done = true;
        self.stop_reason = Some(err.to_string());
    }

    /// Restores the last certified surface and ends the evolution.
    fn roll_back(&mut self, reason: Divergence) -> EvolveError {
        let step = self.step + 1;
        self.restore_checkpoint();
        let err = EvolveError::Divergence {
            step,
            previous: self.step,
            reason,
        };
        self.stop(&err);
        err
    }

    /// Runs until done, calling `on_step` after each step.
    pub fn run(&mut self, mut on_step: impl FnMut(&StepReport)) -> Result<(), EvolveError> {
        while !self.done {
            let r = self.step()?;
            on_step(&r);
        }
        Ok(())
    }
}
