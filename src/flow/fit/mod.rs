//! The final fit (docs/method.md §11.5), run once on the settled surface after the last step:
//! the surface at the offset level set d = d₀ moves onto the target along its normals (plane
//! fits to the cloud or closest points on the mesh, [`crate::flow::snap`]), each pass through
//! the contact guard. On a mesh target the passes after the first also refine where target
//! vertices are still missed ([`error_sizing`]) and move wrap vertices onto them ([`reach`]).
//!
//! [`fit`] is a loop over passes, each a sequence of named steps: the moves and the reach
//! ([`moves`]) → the contacts they made put back → the crease snap ([`crease_fit`]) → the error
//! sizing ([`sizing`]) → the remesh, its check, its retries and the fall-back when it is lost
//! ([`remesh_step`]). Then a mesh target's last round of moves ([`last_round`]), the tidy of
//! the slivers, and the roll back to the settled surface if what is left is not valid. Each
//! step's edits are checked for intersections where the certificate checks them ([`checks`]).

mod checks;
pub mod crease_fit;
pub mod error_sizing;
mod last_round;
mod moves;
pub mod reach;
mod remesh_step;
mod sizing;

use super::guard::GuardSettings;
use super::settings::WrapSettings;
use super::snap::{SnapParams, SnapTarget};
use crate::clock::now_ms;
use crate::field::sign::Signedness;
use crate::geometry::creases::Creases;
use crate::mesh::HalfedgeMesh;
use crate::metrics::creases::CREASE_OFFSET;
use crate::progress::Progress;
use crate::remesh::adaptive::RemeshSettings;
use crate::remesh::sizing::EdgeSizes;
use checks::{intersects_as_written, tidy_slivers};
use glam::DVec3;
use serde::Serialize;

/// The progress phase of the final fit.
pub const FIT_PHASE: &str = "final fit";

/// What the fit is asked to do, derived once from the wrap's settings ([`FitOptions::new`]).
/// Lengths are in the stabilised frame.
#[derive(Clone, Debug, PartialEq)]
pub struct FitOptions {
    /// The moves onto the target: the plane fits' radius and points, the longest move
    /// (`fit.radius_cells`, `fit.max_move_cells`, `tuned.max_points`).
    pub snap: SnapParams,
    /// Passes, each of moves and a remesh (`fit.passes`).
    pub passes: u32,
    /// Most extra passes while a mesh target's vertices are still missed
    /// (`tuned.refine_passes`); only with the error sizing on.
    pub refine_passes: u32,
    /// How far off the wrap a target vertex counts as missed (`tuned.refine_error_cells`); 0
    /// turns the error sizing off.
    pub refine_tol: f64,
    /// The error sizing's vertex budget (`tuned.refine_max_vertices`): no new caps past it, and
    /// an extra pass whose remesh grows the wrap past it is the last.
    pub budget: usize,
    /// Reach into the concavities the moves bridge (`tuned.reach`; mesh targets with the error
    /// sizing).
    pub reach: bool,
    /// The contact guard (`tuning.guard.contact`): no pass may leave faces intersecting.
    pub contact: bool,
    /// The guard's settings, for putting back the moves that make faces meet.
    pub guard: GuardSettings,
    /// Each pass ends with a remesh (`remesh.enabled`).
    pub remeshing: bool,
    /// A pass's remesh: one iteration, projected onto the surface before it, with the step's
    /// sizes and features and a bound on the splits per vertex.
    pub remesh: RemeshSettings,
    /// The first pass's remesh when the step that ended the run left its remesh to the fit (the
    /// sizes changed since the last remesh): as many iterations as a step's remesh, or the
    /// triangles come out worse. None when the sizes did not change.
    pub first_remesh: Option<RemeshSettings>,
    /// The shortest edge the error sizing's caps may ask for (the sizes' l_min).
    pub min_edge: f64,
    /// The target has an inside (a signed field): a reach tests its way for it, and the last
    /// round moves every vertex still off the target onto its closest point.
    pub closed: bool,
    /// How far off a closed mesh target a vertex may stay after the last round.
    pub settled: f64,
    /// The stabilised frame's scale φ, for the positions as written.
    pub phi: f64,
    /// The stabilised frame's centre (in the target's units).
    pub center: DVec3,
}

impl FitOptions {
    /// The options of a wrap's fit: `settings`, the last step's `sizes` (and whether they
    /// `changed` since the last remesh), the field's `cell` size and `signedness`, and the
    /// stabilised frame (`phi`, `center`).
    pub fn new(
        settings: &WrapSettings,
        sizes: EdgeSizes,
        changed: bool,
        cell: f64,
        signedness: Signedness,
        phi: f64,
        center: DVec3,
    ) -> Self {
        let (fit, tuned) = (&settings.fit, &settings.tuning.fit);
        let remesh = RemeshSettings {
            iterations: 1,
            use_projection: true,
            smoothing_iterations: settings.remesh.smoothing_iterations,
            features: settings.tuning.remesh.features.clone(),
            max_splits_per_vertex: Some(FIT_SPLITS_PER_VERTEX),
            ..RemeshSettings::with_sizes(sizes)
        };
        let first_remesh = changed.then(|| RemeshSettings {
            iterations: settings.remesh.iterations,
            ..remesh.clone()
        });
        FitOptions {
            snap: SnapParams {
                radius: fit.radius_cells * cell,
                max_move: fit.max_move_cells * cell,
                min_points: 6,
                max_points: tuned.max_points,
                moving_least_squares: tuned.moving_least_squares,
            },
            passes: fit.passes,
            refine_passes: tuned.refine_passes,
            refine_tol: tuned.refine_error_cells * cell,
            budget: tuned.refine_max_vertices,
            reach: tuned.reach,
            contact: settings.tuning.guard.contact,
            guard: settings.tuning.guard.clone(),
            remeshing: settings.remesh.enabled,
            remesh,
            first_remesh,
            min_edge: sizes.min_edge_length,
            closed: signedness == Signedness::Signed,
            settled: SETTLED_CELLS * cell,
            phi,
            center,
        }
    }

    /// The remesh of pass `pass`.
    fn pass_remesh(&self, pass: u32) -> &RemeshSettings {
        match (pass, &self.first_remesh) {
            (0, Some(first)) => first,
            _ => &self.remesh,
        }
    }
}

/// What the final fit did.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize)]
pub struct FitReport {
    /// Vertices the last pass moved onto the target (its moves and its reach); 0 when the fit
    /// was rolled back.
    pub moved: usize,
    /// Passes begun.
    pub passes: u32,
    /// Where the time went (`other` is the caller's to fill in).
    pub times: FitTimes,
    /// The fit left the surface intersecting or invalid, and the settled surface was put back.
    pub rolled_back: bool,
    /// A pass placed the target's creases (vertices on them, edges along them) and kept them.
    pub creases_placed: bool,
}

/// Where the final fit's time goes, in milliseconds (summed over its passes).
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize)]
#[cfg_attr(target_arch = "wasm32", derive(tsify::Tsify))]
pub struct FitTimes {
    /// Moves onto the target (plane fits or closest points) and reaches into concavities.
    pub moves: f64,
    /// The contact guard putting back moves that make faces meet.
    pub contacts: f64,
    /// Vertices onto the target's creases and edges along them, checked.
    pub creases: f64,
    /// Error-adaptive and crease sizing: the caps on the edge length where the target is missed.
    pub sizing: f64,
    /// The passes' remeshes.
    pub remesh: f64,
    /// Intersection checks after the moves and the remesh, with the remesh's retries.
    pub checks: f64,
    /// A mesh target's last round of moves without a remesh.
    pub last_round: f64,
    /// The slivers tidied at the end (see [`crate::remesh::slivers`]).
    pub tidy: f64,
    /// The rest: copies, normals, passes redone.
    pub other: f64,
}

impl FitTimes {
    /// Everything but `other`.
    pub fn named(&self) -> f64 {
        self.moves
            + self.contacts
            + self.creases
            + self.sizing
            + self.remesh
            + self.checks
            + self.last_round
            + self.tidy
    }
}

/// Moves the settled `mesh` onto `target` (stabilised frame), keeping edges along its `creases`;
/// its passes and parts report to `progress` as [`FIT_PHASE`]. A fit that leaves the surface
/// intersecting or invalid gives way to the settled surface (`rolled_back`).
pub fn fit(
    mesh: &mut HalfedgeMesh,
    target: &SnapTarget,
    creases: Option<&Creases>,
    options: &FitOptions,
    progress: &mut Progress,
) -> FitReport {
    // The fit must never make things worse: keep the settled surface if it breaks validity.
    let backup = mesh.clone();
    let mut fit = Fit::new(mesh, target, creases, options, progress);
    fit.passes();
    fit.last_round();
    fit.tidy();
    let rolled_back = fit.roll_back_if_invalid(backup);
    FitReport {
        moved: if rolled_back { 0 } else { fit.state.moved },
        passes: fit.state.passes,
        times: fit.times,
        rolled_back,
        creases_placed: fit.state.creases_placed,
    }
}

/// One fit under way: what it works on, and what its passes carry from one to the next.
struct Fit<'a, 'p> {
    mesh: &'a mut HalfedgeMesh,
    target: &'a SnapTarget,
    creases: Option<&'a Creases>,
    opt: &'a FitOptions,
    /// The mesh target's vertices, checked by the error sizing and reached for; None on a
    /// cloud or with the sizing (or the remesh) off.
    refine: Option<&'a [DVec3]>,
    /// Passes at most: `passes`, and `refine_passes` more with the error sizing.
    most: u32,
    /// Where a crease still counts as bevelled, read as the crease metric reads it.
    crease_offset: f64,
    at: FitProgress<'a, 'p>,
    sw: Laps,
    times: FitTimes,
    state: FitState,
}

/// What the passes carry from one to the next.
struct FitState {
    /// Target samples still to check: all at first, then the previous pass's misses.
    check: Vec<u32>,
    /// Vertices the last pass moved.
    moved: usize,
    /// Passes begun.
    passes: u32,
    /// A pass placed the creases and kept them: a later one whose crease snap is refused keeps
    /// its moves without a remesh, or the earlier surface, rather than round them off again.
    creases_placed: bool,
    /// Passes in a row that lost their remesh to intersections: their caps never became edges,
    /// and an extra pass after two such would most likely lose its own again.
    remeshes_lost: u32,
    /// An extra pass's remesh grew the wrap past the vertex budget (the caps are only part of
    /// the growth): it keeps its moves without the remesh, and is the last.
    over_budget: bool,
    /// What the last pass left to refine: target samples still missed, crease edges still
    /// bevelled.
    left_before: (usize, usize),
    /// An extra pass left no less to refine than the one before and reached nothing: it is the
    /// last.
    stalled: bool,
    /// The last pass's sizing set new caps: an extra pass has vertices to put into the misses.
    missed: bool,
    /// Some pass reached into a concavity: the last round settles the flap tips left there.
    reached_any: bool,
    /// The last pass reached: the next one puts the dents' new vertices on the target.
    reached_last: bool,
    /// The surface is known to be free of intersections as written: the settled surface (the
    /// contact guard checked it before the fit) and every pass's end but a redone one's.
    certified: bool,
}

impl<'a, 'p> Fit<'a, 'p> {
    fn new(
        mesh: &'a mut HalfedgeMesh,
        target: &'a SnapTarget,
        creases: Option<&'a Creases>,
        opt: &'a FitOptions,
        progress: &'a mut Progress<'p>,
    ) -> Self {
        let crease_offset = match target {
            SnapTarget::Triangles(bvh) => {
                let (lo, hi) = bvh.bvh().bounds();
                CREASE_OFFSET * (hi - lo).length()
            }
            SnapTarget::Points(_) => 0.0,
        };
        let refine = match target {
            SnapTarget::Triangles(bvh) if opt.remeshing && opt.refine_tol > 0.0 => {
                Some(bvh.positions())
            }
            _ => None,
        };
        let check = match refine {
            Some(samples) => (0..samples.len() as u32).collect(),
            None => vec![],
        };
        let most = opt.passes
            + if refine.is_some() {
                opt.refine_passes
            } else {
                0
            };
        let state = FitState {
            check,
            moved: 0,
            passes: 0,
            creases_placed: false,
            remeshes_lost: 0,
            over_budget: false,
            left_before: (usize::MAX, usize::MAX),
            stalled: false,
            missed: true,
            reached_any: false,
            reached_last: false,
            certified: true,
        };
        Fit {
            mesh,
            target,
            creases,
            opt,
            refine,
            most,
            crease_offset,
            at: FitProgress { progress, most },
            sw: Laps(now_ms()),
            times: FitTimes::default(),
            state,
        }
    }

    /// The passes, until the last or until an extra one has nothing left to do: moves and
    /// reach → contacts and crease snap → error sizing → remesh and its check.
    fn passes(&mut self) {
        for pass in 0..self.most {
            if self.spent(pass) {
                break;
            }
            self.state.passes += 1;
            self.at.report(pass, 0.0);
            self.sw.lap();
            let mut p = self.moves(pass);
            self.contacts_and_creases(&mut p);
            self.count_reach(p.reached);
            if p.refused && self.state.creases_placed {
                self.keep_moves_unremeshed(p.start);
                break;
            }
            self.times.checks += self.sw.lap();
            let caps = self.size_by_error(pass, p.reached);
            self.times.sizing += self.sw.lap();
            if !self.remesh_step(p, caps.as_deref()) {
                break;
            }
        }
    }

    /// Whether the extra pass `pass` is not worth running: nothing left missed and no dents to
    /// fill, or the passes lose their remeshes, outgrew the budget or stalled.
    fn spent(&self, pass: u32) -> bool {
        let s = &self.state;
        // (A pass after a reach puts the dents' new vertices on the target.)
        let spent = s.remeshes_lost >= 2 || s.over_budget || s.stalled;
        pass >= self.opt.passes && ((!s.missed && !s.reached_last) || spent)
    }

    /// The tidy after the passes and the last round: slivers, then the caps' layer.
    fn tidy(&mut self) {
        let (contact, phi, center) = (self.opt.contact, self.opt.phi, self.opt.center);
        tidy_slivers(self.mesh, contact, phi, center);
        self.times.tidy += self.sw.lap();
        self.mesh.remove_vertex_scalar_layer(CAP_LAYER);
        self.at.report(self.most, 0.0);
    }

    /// Puts `backup` back when the passes left the surface intersecting (a redone pass whose
    /// put-back moves still intersect as written) or invalid: the settled surface is valid if
    /// less close. True when it did.
    fn roll_back_if_invalid(&mut self, backup: HalfedgeMesh) -> bool {
        let (phi, center) = (self.opt.phi, self.opt.center);
        let intersecting = self.opt.contact
            && !self.state.certified
            && intersects_as_written(self.mesh, phi, center);
        if intersecting || self.mesh.validate().is_err() {
            *self.mesh = backup;
            return true;
        }
        false
    }
}

/// The fit's progress: pass `pass` and a part of it, out of `most` passes.
struct FitProgress<'a, 'p> {
    progress: &'a mut Progress<'p>,
    most: u32,
}

impl FitProgress<'_, '_> {
    fn report(&mut self, pass: u32, part: f64) {
        let fraction = (pass as f64 + part) / self.most.max(1) as f64;
        self.progress.report(FIT_PHASE, fraction);
    }
}

/// A stopwatch read in laps.
struct Laps(f64);

impl Laps {
    /// Milliseconds since the last lap (or the start).
    fn lap(&mut self) -> f64 {
        let now = now_ms();
        let d = now - self.0;
        self.0 = now;
        d
    }
}

/// Splits per vertex at most in a fit's remesh (see `RemeshSettings::max_splits_per_vertex`):
/// a regular pass splits under twice per vertex, while plane fits over a sparse cloud can
/// crumple the wrap into a runaway of splits, each undone.
const FIT_SPLITS_PER_VERTEX: f64 = 4.0;

/// How far off a closed mesh target (in cells) a vertex may stay after the fit's last round.
const SETTLED_CELLS: f64 = 0.02;

/// The vertex layer of the error-adaptive caps on the edge length (see [`error_sizing`]).
const CAP_LAYER: &str = "fit_cap";
/// "No cap" in [`CAP_LAYER`]: finite, because a split vertex gets the mean of its ends' values.
const NO_CAP: f64 = 1e300;
