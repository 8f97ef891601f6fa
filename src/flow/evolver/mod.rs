//! The LSW evolution as a step-wise state machine: `Evolver::new(target, settings)`, then
//! `step()` until `is_done()`. Each step is the semi-implicit scheme of method spec §6.1–6.4:
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
mod forces;
mod second_pass;
pub use second_pass::{StartedOver, ThirdPass, SECOND_PASS_PHASE};
mod remeshing;
mod schedule;
mod solve;
mod surgery;

use super::guard::{ContactReport, Divergence, DivergenceLimits};
use super::mcf::stats;
use super::scaling::written;
use super::settings::{StartSurface, WrapSettings};
use super::snap::SnapTarget;
use super::start::{build_start, start_scale, Start};
use super::surgery::SurgeryEvent;
use crate::clock::now_ms;
use crate::field::{DistanceField, FieldError};
use crate::geometry::cloud_creases::detect_cloud_creases;
use crate::geometry::creases::{detect_creases, Creases};
use crate::geometry::icosphere::IcosphereError;
use crate::geometry::spatial::point_grid::PointGrid;
use crate::mesh::{HalfedgeMesh, MeshBuildError, MeshReport};
use crate::parallel::Later;
use crate::progress::Progress;
use crate::remesh::adaptive::{RemeshError, RemeshReport};
use crate::remesh::sizing::EdgeSizes;
use crate::target::Target;
use contact::Contact;
use glam::DVec3;
use serde::Serialize;

/// The progress phase of a cloud's crease detection (before the steps; ~0.4 s natively on
/// 1 M points).
pub const CREASE_PHASE: &str = "sharp creases";
/// The progress phase of a cloud's stray-point test (before the field; ~0.5 s natively on 1 M
/// points).
pub const STRAY_PHASE: &str = "stray points";
/// The progress phase of the start surface.
pub const START_PHASE: &str = "start surface";

/// Grid refinements tried for an isosurface start that lost a closed mesh's topology (see
/// `Evolver::finer_start`).
const FINER_GRIDS: [f64; 2] = [1.5, 2.0];

/// `auto`'s isosurface start `resolved` with the isosurface preset's λ_min instead of its own
/// finer one, unless the user chose λ_min (in `requested`) or the start is not the isosurface.
fn coarser_isosurface_start(
    requested: &WrapSettings,
    resolved: &WrapSettings,
) -> Option<WrapSettings> {
    let preset = WrapSettings::default().with_isosurface_start();
    let chosen =
        requested.remesh.min_edge_multiplier != WrapSettings::default().remesh.min_edge_multiplier;
    let coarser = preset.remesh.min_edge_multiplier > resolved.remesh.min_edge_multiplier;
    (resolved.start.surface == StartSurface::Isosurface && !chosen && coarser).then(|| {
        let mut s = resolved.clone();
        s.remesh.min_edge_multiplier = preset.remesh.min_edge_multiplier;
        s
    })
}

/// Whether `mesh` has the Euler characteristic and the component count of `target`'s triangles
/// (false when those do not form a manifold mesh). From connectivity alone: degenerate faces of
/// an iso-surface do not matter here. `closed`: the target's [`crate::mesh::closed_topology`],
/// computed once per wrap (a sort of its edges: 50 ms on a volume's 575 K faces); a target that
/// is not closed is built as a half-edge mesh.
fn same_topology(mesh: &HalfedgeMesh, target: &Target, closed: Option<&MeshReport>) -> bool {
    let t = mesh.topology();
    let mine = (t.euler_characteristic, t.components);
    match closed {
        Some(t) => (t.euler_characteristic, t.components) == mine,
        None => {
            HalfedgeMesh::from_triangles(target.points.clone(), &target.triangles).is_ok_and(|t| {
                let t = t.topology();
                (t.euler_characteristic, t.components) == mine
            })
        }
    }
}

/// Why a wrap could not start or continue.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum EvolveError {
    /// A setting is out of range. Fix: see the named setting's documentation.
    #[error(transparent)]
    Setting(#[from] super::settings::SettingError),
    /// The target cannot be wrapped (too few points, flat, zero area): see the variant.
    #[error(transparent)]
    Target(#[from] crate::target::TargetError),
    /// The distance field could not be built (empty or degenerate target, too fine a grid).
    #[error("distance field: {0}")]
    Field(#[from] FieldError),
    /// The icosphere could not be built.
    #[error(transparent)]
    Icosphere(#[from] IcosphereError),
    /// The marching-cubes start surface is empty: no grid node lies below d_iso.
    #[error("the isosurface d = {iso:.4} is empty; raise start.isosurface_level_cells")]
    EmptyIsosurface { iso: f64 },
    /// The isosurface start intersects itself after its remesh: its exterior leaked into narrow
    /// channels (typically through gaps in a point cloud). Fix: use the icosphere start (or auto).
    #[error("the isosurface start is not usable here: after remeshing, {pairs} pairs of its faces intersect (start genus {genus}; the exterior leaked through gaps in the input); use --start icosphere or auto")]
    StartIntersects { pairs: usize, genus: i64 },
    /// The marching-cubes start surface is not a manifold mesh.
    #[error("the isosurface start is not a manifold mesh: {0}")]
    StartMesh(#[from] MeshBuildError),
    /// The remesher refused its sizes.
    #[error(transparent)]
    Remesh(#[from] RemeshError),
    /// The step showed a sign of divergence; the surface was rolled back to the last state the
    /// contact guard certified (`previous`) and the evolution stopped. Fix: a smaller τ, or
    /// report the input.
    #[error("the evolution diverged at step {step} ({reason}); rolled back to step {previous}")]
    Divergence {
        step: u32,
        previous: u32,
        reason: Divergence,
    },
    /// A step's solve failed even after `retries` retries (non-negative weights, then τ halved;
    /// `tau` is the last one tried): the surface is the last certified one and the evolution
    /// stopped.
    #[error("the solve diverged at step {step} after {retries} retries (τ {tau:.3e} at the last): {cause}")]
    Diverged {
        step: u32,
        retries: u32,
        tau: f64,
        cause: String,
    },
}

/// Wall time of the phases of one step, in milliseconds.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize)]
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

/// A cloud's creases before the final fit.
enum PendingCreases {
    /// Being found beside the steps (natively), or known.
    Later(Later<Option<Creases>>),
    /// Left to the fit (wasm, one thread), unless [`Evolver::supply_creases`] brings them
    /// first.
    Deferred(CreaseJob),
}

impl PendingCreases {
    /// Whether getting them takes time here: found now, or waited for.
    fn takes_time(&self) -> bool {
        !matches!(self, PendingCreases::Later(l) if !l.elsewhere())
    }

    /// The creases, found here if they were left to the fit (`done` hears the fraction).
    fn get(self, done: &mut dyn FnMut(f64)) -> Option<Creases> {
        match self {
            PendingCreases::Later(later) => later.get(),
            PendingCreases::Deferred(job) => job.run(done),
        }
    }
}

/// A cloud's crease detection as a job for another worker (see [`Evolver::crease_job`]): the
/// fit's grid of the target's points (stabilised frame), the fit radius and the crease angle
/// (radians).
#[derive(Clone)]
pub struct CreaseJob {
    grid: std::sync::Arc<PointGrid>,
    /// The points in input order when the job was rebuilt elsewhere (else taken from the grid).
    input: Option<std::sync::Arc<Vec<DVec3>>>,
    pub radius: f64,
    pub angle: f64,
}

impl CreaseJob {
    /// What crosses to the other worker: the points in the grid's cell order and each one's
    /// index among the target's points (read straight out of the grid: a copy in input order
    /// cost the browser's worker 0.36 s at 2 M points).
    pub fn cell_order(&self) -> (&[DVec3], &[u32]) {
        self.grid.cell_ordered()
    }

    /// The job again from [`CreaseJob::cell_order`]'s lists (in the other worker), its grid
    /// built as the fit builds its own, so the same; None unless `order` numbers `points`.
    pub fn from_cell_order(
        points: Vec<DVec3>,
        order: &[u32],
        radius: f64,
        angle: f64,
    ) -> Option<Self> {
        if points.len() != order.len() {
            return None;
        }
        let (mut input, mut seen) = (vec![DVec3::ZERO; points.len()], vec![false; points.len()]);
        for (&i, p) in order.iter().zip(points) {
            let i = i as usize;
            if std::mem::replace(seen.get_mut(i)?, true) {
                return None;
            }
            input[i] = p;
        }
        Some(CreaseJob {
            grid: std::sync::Arc::new(PointGrid::new(&input, radius)),
            input: Some(std::sync::Arc::new(input)),
            radius,
            angle,
        })
    }

    /// The creases the fit would find (`done` hears the fraction).
    pub fn run(&self, done: &mut dyn FnMut(f64)) -> Option<Creases> {
        let from_grid;
        let points = match &self.input {
            Some(input) => input.as_slice(),
            None => {
                from_grid = self.grid.points_in_input_order();
                &from_grid
            }
        };
        let c = detect_cloud_creases(points, &self.grid, self.radius, self.angle, done);
        (!c.is_empty()).then_some(c)
    }
}

/// What the fit's view of the target (its creases, and the tree or grid the fit projects onto)
/// is built from: equal keys build equal things.
#[derive(Clone, Copy, Debug, PartialEq)]
struct FitKey {
    /// The stabilisation factor of the frame they are built in.
    phi: f64,
    /// The fit's neighbourhood radius (stabilised frame).
    fit_radius: f64,
    /// The crease angle (radians); None: no crease detection (none on a volume's iso-surface:
    /// see `Target::sampled`).
    crease_angle: Option<f64>,
    /// Whether there is a final fit.
    fits: bool,
}

impl FitKey {
    /// The key of `settings` for a field of cells of size `cell` and a start scaled by `phi`.
    fn new(settings: &WrapSettings, target: &Target, cell: f64, phi: f64) -> Self {
        let fits = settings.fit.enabled && settings.flow.use_target;
        Self {
            phi,
            fit_radius: settings.fit.radius_cells * cell * phi,
            crease_angle: (fits && !target.sampled && settings.fit.crease_angle_deg > 0.0)
                .then(|| settings.fit.crease_angle_deg.to_radians()),
            fits,
        }
    }

    /// The target's points in the stabilised frame.
    fn framed(&self, target: &Target, center: DVec3) -> Vec<DVec3> {
        target
            .points
            .iter()
            .map(|&p| self.phi * (p - center))
            .collect()
    }

    /// The fit target of `target` (None without a fit).
    fn fit_target(&self, target: &Target, center: DVec3) -> Option<SnapTarget> {
        self.fits
            .then(|| SnapTarget::new(target, center, self.phi, self.fit_radius))
    }

    /// `(fit target, creases)`, each on a thread of its own natively; a cloud's creases are
    /// found later, on its fit grid (None here).
    fn build(&self, target: &Target, center: DVec3) -> (Option<SnapTarget>, Option<Creases>) {
        let mesh = !target.triangles.is_empty();
        let (creases, fit_target) = crate::parallel::beside(
            || {
                self.crease_angle.filter(|_| mesh).map(|angle| {
                    detect_creases(&self.framed(target, center), &target.triangles, angle)
                })
            },
            || self.fit_target(target, center),
        );
        (fit_target, creases)
    }
}

impl Evolver {
    /// Builds the distance field and the start surface, scaled into the stabilised frame.
    pub fn new(target: &Target, settings: WrapSettings) -> Result<Self, EvolveError> {
        Self::new_with_progress(target, settings, &mut Progress::none())
    }

    /// [`Evolver::new`], reporting the field build and the start surface to `progress`.
    pub fn new_with_progress(
        target: &Target,
        settings: WrapSettings,
        progress: &mut Progress,
    ) -> Result<Self, EvolveError> {
        settings.check()?;
        target.check_wrappable()?;
        // A scan's stray points are left out of everything built from the target below.
        let cloud = target.triangles.is_empty() && settings.field.outlier_spacings > 0.0;
        if cloud {
            progress.report(STRAY_PHASE, 0.0);
            // (Its first part, remembered for the test below: a third of it on 1 M points.)
            crate::geometry::spatial::spacing::median_spacing(&target.points);
            progress.report(STRAY_PHASE, 0.3);
        }
        let cleaned = target.without_isolated_points(settings.field.outlier_spacings);
        if cloud {
            progress.report(STRAY_PHASE, 1.0);
        }
        let (target, isolated_points) = match &cleaned {
            Some((t, n)) => {
                t.check_wrappable()?;
                (t, *n)
            }
            None => (target, 0),
        };
        // A mesh's specks likewise, at the cell of the grid its whole box would get.
        let despecked = match target.triangles.is_empty() {
            true => None,
            false => DistanceField::planned_cell_size(target, &settings.field)
                .and_then(|cell| target.without_specks(cell)),
        };
        let (target, specks) = match &despecked {
            Some((t, n)) => {
                t.check_wrappable()?;
                (t, *n)
            }
            None => (target, 0),
        };
        // A mesh's creases and the fit's tree over it (a cloud's fit grid) depend on the field
        // and the start only through the cell size and φ, both known from the settings: they are
        // built on other threads while the field and the start are (bust: 255 ms of setup), for
        // the start the settings ask for, and again below in the rare case of another start.
        // (The field's grid is laid out once, for both.)
        let plan = DistanceField::plan(target, &settings.field);
        let planned = plan.as_ref().ok().map(|p| {
            let cell = p.cell_size();
            // (A cloud's field is never signed; a mesh's is where it is closed, the usual case.)
            let guess = settings.clone().resolved_for(!target.triangles.is_empty());
            FitKey::new(&guess, target, cell, start_scale(target, cell, &guess))
        });
        let center = target.bbox.center();
        let (prebuilt, start) = crate::parallel::beside(
            || planned.map(|k| (k, k.build(target, center))),
            || -> Result<_, EvolveError> {
                let field = DistanceField::new_planned(target, &settings.field, plan?, progress)?;
                let mut resolved = settings.clone().resolved_for(field.is_signed());
                progress.report(START_PHASE, 0.0);
                // The target's topology where it is closed: for the start's checks and
                // surgery's least genus.
                let closed = crate::mesh::closed_topology(target.points.len(), &target.triangles);
                let start = Self::build_start_with_fallback(
                    target,
                    closed.as_ref(),
                    &field,
                    &settings,
                    &mut resolved,
                )?;
                if let Some(finer) = Self::finer_start(
                    target,
                    closed.as_ref(),
                    &settings,
                    &resolved,
                    &start,
                    progress,
                ) {
                    return Ok((finer, closed));
                }
                Ok(((field, start, resolved), closed))
            },
        );
        let ((field, start, mut settings), closed) = start?;
        let c = field.cell_size();
        progress.report(START_PHASE, 1.0);
        if target.sampled {
            settings = settings.resolved_for_volume();
        }
        let (mesh, phi, sizes) = (start.mesh, start.phi, start.sizes);
        let limits = divergence_limits(target, &mesh, phi, center, &settings);
        // In place: a scaled copy kept the unscaled field alive to the end of this function (a
        // bunny cloud's 2.1 M nodes: 45 MB twice).
        let mut field = field;
        field.scale_uniform(center, phi);
        let key = FitKey::new(&settings, target, c, phi);
        let (fit_target, creases) = if target.triangles.is_empty() {
            // A cloud's creases are seen at the scale of the fit's plane fits, on the fit's own
            // grid. A smooth cloud's fit stays exactly as without crease detection. (Its grid
            // was built beside the field when the key was foreseen: 1 M points, 0.15 s.)
            let fit_target = match prebuilt {
                Some((made, (built, _))) if made == key => built,
                _ => key.fit_target(target, center),
            };
            // Only the final fit needs them: natively they are found beside the steps, whose
            // sequential parts leave a core idle (1 M points: 0.25 s of setup, both cores busy).
            // In the browser (one thread) they are left to the fit, and a helper worker may
            // find them meanwhile (see `crease_job`).
            let creases = match (&fit_target, key.crease_angle) {
                (Some(SnapTarget::Points(grid)), Some(angle)) => {
                    let job = CreaseJob {
                        grid: std::sync::Arc::clone(grid),
                        input: None,
                        radius: key.fit_radius,
                        angle,
                    };
                    if cfg!(target_arch = "wasm32") {
                        PendingCreases::Deferred(job)
                    } else {
                        PendingCreases::Later(crate::parallel::later(
                            move |done: &mut dyn FnMut(f64)| job.run(done),
                            &mut |f| progress.report(CREASE_PHASE, f),
                        ))
                    }
                }
                _ => PendingCreases::Later(Later::ready(None)),
            };
            (fit_target, creases)
        } else {
            let (fit_target, creases) = match prebuilt {
                Some((made, built)) if made == key => built,
                _ => key.build(target, center),
            };
            (fit_target, PendingCreases::Later(Later::ready(creases)))
        };
        let d0 = settings.flow.iso_level_factor * 0.5 * 3f64.sqrt() * c * phi;
        let empty_distance = phi * empty_distance(target, c, &settings);
        let cloud_spacing = surgery::cloud_spacing(target, &settings, phi);
        let close_gap_distance = phi * close_gap_distance(target, &settings);
        let least_genus = closed.filter(|t| t.components == 1).map(|t| t.genus);
        let pass = second_pass::SecondPass::new(
            target,
            &settings,
            (d0, phi, center),
            fit_target.is_some(),
        );
        let mut ev = Evolver {
            tau: settings.flow.tau,
            d1: settings.flow.d1,
            settle_threshold: settings.stop.displacement_cells * c * phi,
            settings,
            mesh,
            field,
            center,
            phi,
            d0,
            sizes,
            step: 0,
            done: false,
            distances: vec![],
            gradients: vec![],
            fit_target,
            creases: None,
            pending_creases: Some(creases),
            isolated_points,
            specks,
            despecked: despecked.map(|(t, _)| t),
            sizes_changed: true,
            start: start.kind,
            limits,
            stop_reason: None,
            checkpoint: Checkpoint {
                mesh: HalfedgeMesh::default(),
                tau: 0.0,
                d1: 0.0,
                sizes,
                step: 0,
                sizes_changed: true,
            },
            guarded_left: 0,
            empty_distance,
            cloud_spacing,
            close_gap_distance,
            least_genus,
            surgery_events: Vec::new(),
            tunnels_opened: Vec::new(),
            surgery_paired: 0,
            surgery_pending: false,
            second_pass: pass,
            started_over: None,
        };
        ev.save_checkpoint();
        let start = ev.checkpoint.clone();
        if let Some(pass) = ev.second_pass.as_mut() {
            pass.starting(start);
        }
        ev.refresh_distances();
        ev.done = ev.settings.stop.steps == 0;
        Ok(ev)
    }

    /// The start of `settings` (resolved), falling back as `auto` promises: its isosurface
    /// start is tried again with the isosurface preset's coarser edges (a voxel plate with nine
    /// holes intersected after the finer remesh, not after this one: genus 9 with 20 K vertices
    /// in 13 s, against the icosphere's 95 K in 25 s); where the exterior leaked into gaps of the
    /// target (noisy volumes, sparse clouds) the icosphere, which cannot leak, takes over; the
    /// same when the start of a mesh of one closed part has another topology than the mesh.
    /// `settings` becomes those of the start built.
    fn build_start_with_fallback(
        target: &Target,
        closed: Option<&MeshReport>,
        field: &DistanceField,
        requested: &WrapSettings,
        settings: &mut WrapSettings,
    ) -> Result<Start, EvolveError> {
        let auto = requested.start.surface == StartSurface::Auto;
        let built = build_start(target, field, settings);
        // A mesh of one closed part has a genus the wrap must keep, and a Lagrangian surface
        // keeps its start's: an offset that joins two parts lying close (a creature's leg and
        // ear, turned so that the grid is coarser) starts with handles the target lacks. (Not
        // a volume's iso-surface: its genus is the noise's, and the icosphere took 2–4× the
        // time for no better genus on the noisy-volume sweep.)
        let wrong_topology = |start: &Start| {
            settings.start.surface == StartSurface::Isosurface
                && !target.sampled
                && closed.is_some_and(|t| t.components == 1)
                && !same_topology(&start.mesh, target, closed)
        };
        match built {
            Ok(start) if auto && wrong_topology(&start) => {
                Self::fall_back(target, closed, field, requested, settings)
            }
            Err(EvolveError::StartIntersects { .. }) if auto => {
                Self::fall_back(target, closed, field, requested, settings)
            }
            other => other,
        }
    }

    /// `auto` on a closed one-part mesh (or a volume's one-part iso-surface) whose isosurface
    /// start lost the target's topology or met itself (an offset of ~1 cell closes a bore under
    /// ~4 cells wide, and the icosphere then wraps over it): the isosurface start on grids
    /// [`FINER_GRIDS`] times finer, the first with the target's topology, with its field and
    /// settings. `None` when the start taken is not that fallback, or no finer grid helps (or
    /// fits the field's memory cap). (A noisy volume's iso-surface rarely matches: five of the 18
    /// of `benches/noisy/sweep.sh` try both grids in vain, 1.3–1.9 s each.)
    ///
    /// A volume's iso-surface of one closed part whose isosurface `start` has another topology
    /// tries the first of them too, and keeps `start` when it does not match (see
    /// `build_start_with_fallback`: no icosphere for volumes). A knot of voxels whose strands
    /// pass 6 voxels apart started with two of its crossings joined and three specks of
    /// tetrahedra, and ended so: genus 2 in 4 parts for genus 1; its start 1.5× finer has the
    /// knot's topology.
    fn finer_start(
        target: &Target,
        closed: Option<&MeshReport>,
        requested: &WrapSettings,
        resolved: &WrapSettings,
        start: &Start,
        progress: &mut Progress,
    ) -> Option<(DistanceField, Start, WrapSettings)> {
        let auto = requested.start.surface == StartSurface::Auto;
        let fell_back = resolved.start.surface == StartSurface::Icosphere;
        let volume_off = || {
            target.sampled
                && resolved.start.surface == StartSurface::Isosurface
                && !same_topology(&start.mesh, target, closed)
        };
        let one_part = closed.is_some_and(|t| t.components == 1);
        if !(auto && one_part && (fell_back || volume_off())) {
            return None;
        }
        // (A volume's own start only 1.5× finer: past its voxels a finer grid rarely changes
        // the iso-surface's topology, and three of the noisy volumes tried both in vain, 1.7 s.)
        let grids = match fell_back {
            true => &FINER_GRIDS[..],
            false => &FINER_GRIDS[..1],
        };
        grids.iter().find_map(|&k| {
            let mut s = requested.clone();
            let n = s.field.cells_per_min_dimension as f64;
            s.field.cells_per_min_dimension = (k * n).round() as u32;
            let field = DistanceField::new_with_progress(target, &s.field, progress).ok()?;
            let resolved = s.clone().resolved_for(field.is_signed());
            (resolved.start.surface == StartSurface::Isosurface).then_some(())?;
            let start = build_start(target, &field, &resolved).ok()?;
            same_topology(&start.mesh, target, closed).then_some((field, start, resolved))
        })
    }

    /// `auto`'s way on from an isosurface start it cannot use: the coarser isosurface start, if
    /// it has the target's topology, else the icosphere.
    fn fall_back(
        target: &Target,
        closed: Option<&MeshReport>,
        field: &DistanceField,
        requested: &WrapSettings,
        settings: &mut WrapSettings,
    ) -> Result<Start, EvolveError> {
        let coarser = coarser_isosurface_start(requested, settings);
        match coarser.map(|s| (build_start(target, field, &s), s)) {
            // Only with the target's own topology: two linked voxel tori gave a clean coarse
            // start of 5 components (the offsets merge where they link).
            Some((Ok(start), s)) if same_topology(&start.mesh, target, closed) => {
                *settings = s;
                Ok(start)
            }
            _ => {
                *settings = requested.clone().resolved_for(false);
                build_start(target, field, settings)
            }
        }
    }

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

    /// Per-vertex field distance d in the target's units.
    pub fn vertex_distances(&self) -> Vec<f64> {
        self.distances.iter().map(|d| d / self.phi).collect()
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
    /// The contact guard checks every `guard.check_every` steps (and always before the final
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
        // first pass remeshes to the same sizes anyway: remeshing first spent a sixth of the
        // bunny's time on a surface that the fit's moves then distort, and most clouds' results
        // came out closer (cube cloud's Hausdorff 0.70 → 0.39 %, spotPts_4's 6.1 → 5.5 %; a
        // thin plate's 5.2 → 5.4 %, benches/RESULTS.md). A mesh's fit sizes its edges by where it still misses the target, which
        // needs the fine surface from its first pass (without it the bust's sockets kept a 95th
        // percentile 0.72 of that with no error sizing, against under 0.6).
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

/// Surgery's "far from the data" distance in the target's units: `surgery.empty_cells` cells,
/// on a point cloud at least `surgery.empty_spacings` median point spacings, and at least half
/// of `surgery.close_gaps` diagonals (a hole of that width has its centre that far from the
/// data). 0 when surgery is off: the spacing costs a tree over the points.
fn empty_distance(target: &Target, cell: f64, settings: &WrapSettings) -> f64 {
    let s = &settings.surgery;
    if !s.enabled {
        return 0.0;
    }
    let spacing = if target.triangles.is_empty() {
        crate::geometry::spatial::spacing::median_spacing(&target.points)
    } else {
        0.0
    };
    (s.empty_cells * cell)
        .max(s.empty_spacings * spacing)
        .max(close_gap_distance(target, settings))
}

/// Half of `surgery.close_gaps` target diagonals, in the target's units: a hole of that width
/// has its centre that far from the data.
fn close_gap_distance(target: &Target, settings: &WrapSettings) -> f64 {
    0.5 * settings.surgery.close_gaps * target.bbox.size().length()
}

/// The divergence guard's limits in the stabilised frame: the box of the start surface and the
/// target grown by `escape_diagonals` target diagonals; the area of the start surface plus the
/// target box's, times `max_area_growth`; `max_vertices`.
fn divergence_limits(
    target: &Target,
    start: &HalfedgeMesh,
    phi: f64,
    center: DVec3,
    settings: &WrapSettings,
) -> DivergenceLimits {
    let g = &settings.guard;
    let tb = &target.bbox;
    let (mut min, mut max) = (phi * (tb.min - center), phi * (tb.max - center));
    for p in start.positions() {
        min = min.min(*p);
        max = max.max(*p);
    }
    let margin = g.escape_diagonals * phi * tb.size().length().max(f64::MIN_POSITIVE);
    let s = phi * tb.size();
    let box_area = 2.0 * (s.x * s.y + s.y * s.z + s.z * s.x);
    DivergenceLimits {
        min: min - DVec3::splat(margin),
        max: max + DVec3::splat(margin),
        max_area: g.max_area_growth * (start.surface_area() + box_area),
        max_vertices: g.max_vertices,
    }
}
