//! Phase 7 of a step, *final fit* (last step only): the settled surface, at the offset level set
//! d = d₀, moves onto the target along its normals (plane fits to the cloud or closest points on
//! the mesh, [`crate::flow::snap`]), each pass through the contact guard. On a mesh target, the
//! passes after the first also refine where target vertices are still missed
//! ([`crate::flow::error_sizing`]) and move wrap vertices onto them ([`crate::flow::reach`]).

use super::{Evolver, PhaseTimes};
use crate::clock::now_ms;
use crate::progress::Progress;

/// The progress phase of the final fit.
pub const FIT_PHASE: &str = "final fit";
use crate::flow::crease_fit::snap_to_creases;
use crate::flow::error_sizing::{crease_caps, error_caps, wrap_faces, BEVEL_TOL_DEG};
use crate::flow::guard::{freeze_where_intersecting, resolve_contacts, REMESH_TRIES};
use crate::flow::reach::{reach_into_misses, settle_flap_tips};
use crate::flow::scaling::{round_as_written, written};
use crate::flow::snap::{snap_to_closest, snap_to_target, SnapParams, SnapTarget};
use crate::geometry::creases::Creases;
use crate::geometry::operators::normals::angle_weighted_normals;
use crate::geometry::spatial::bvh::TriangleBvh;
use crate::mesh::HalfedgeMesh;
use crate::metrics::creases::CREASE_OFFSET;
use crate::metrics::intersections::{count_self_intersections, self_intersecting_pairs};
use crate::remesh::adaptive::{
    remesh, remesh_capped, remesh_with_features, RemeshError, RemeshSettings,
};
use crate::remesh::features::Features;
use crate::remesh::slivers::{remove_slivers, SliverReport, SliverSettings};
use glam::DVec3;
use serde::Serialize;

impl Evolver {
    /// The final fit when the evolution has just ended; vertices moved.
    pub(super) fn fit_if_done(
        &mut self,
        times: &mut PhaseTimes,
        progress: &mut Progress,
    ) -> Option<usize> {
        if !self.done {
            return None;
        }
        let t0 = now_ms();
        if let Some(pending) = self.pending_creases.take() {
            // Found beside the steps (natively): the fit waits here for what is left of that;
            // or left to the fit (wasm) and found now.
            let report = pending.takes_time();
            if report {
                progress.report(super::CREASE_PHASE, 0.0);
            }
            self.creases = pending.get(&mut |f| progress.report(super::CREASE_PHASE, f));
            if report {
                progress.report(super::CREASE_PHASE, 1.0);
            }
        }
        let mut parts = FitTimes::default();
        let fitted = self.final_fit(progress, &mut parts);
        // The fit was the last use of the target's tree (no step follows a done one): freed
        // before the certificate builds its own (a 640³ volume's 9.7 M triangles: ≈ 0.8 GB, the
        // difference between done and out of memory in the browser).
        if !self.second_pass_may_follow() {
            self.fit_target = None;
        }
        times.fit = now_ms() - t0;
        parts.other = times.fit - parts.named();
        times.fit_parts = parts;
        fitted
    }

    /// Moves the settled surface onto the target (see [`crate::flow::snap`]); returns vertices moved.
    /// Each pass's moves go through the contact guard, and a remesh that would leave
    /// intersecting faces is undone.
    fn final_fit(&mut self, progress: &mut Progress, ft: &mut FitTimes) -> Option<usize> {
        let target = self.fit_target.as_ref()?;
        let c = self.field.cell_size();
        let params = SnapParams {
            radius: self.settings.fit.radius_cells * c,
            max_move: self.settings.fit.max_move_cells * c,
            min_points: 6,
            max_points: self.settings.fit.max_points,
        };
        // The fit must never make things worse: keep the settled surface if it breaks validity.
        let backup = self.mesh.clone();
        let mut moved = 0;
        let rs = RemeshSettings {
            iterations: 1,
            use_projection: true,
            smoothing_iterations: self.settings.remesh.smoothing_iterations,
            features: self.settings.remesh.features.clone(),
            max_splits_per_vertex: Some(FIT_SPLITS_PER_VERTEX),
            ..RemeshSettings::with_sizes(self.sizes)
        };
        // The first pass's remesh also refines to the last sizes when the ending step left that
        // to it (clouds, see `step_once`): as many iterations as a step's remesh then, or the
        // triangles come out worse (bunny: mean radius ratio 0.951 against 0.960).
        let first_rs = RemeshSettings {
            iterations: self.settings.remesh.iterations,
            ..rs.clone()
        };
        let mut rs_now = if self.sizes_changed { &first_rs } else { &rs };
        let (contact, remeshing) = (self.settings.guard.contact, self.settings.remesh.enabled);
        // Error-adaptive sizing (mesh targets): extra passes while some target vertex misses.
        let refine_tol = self.settings.fit.refine_error_cells * c;
        // Where a crease is still bevelled is read as the crease metric reads it.
        let crease_offset = match target {
            SnapTarget::Triangles(bvh) => {
                let (lo, hi) = bvh.bvh().bounds();
                CREASE_OFFSET * (hi - lo).length()
            }
            SnapTarget::Points(_) => 0.0,
        };
        let refine = match target {
            SnapTarget::Triangles(bvh) if remeshing && refine_tol > 0.0 => Some(bvh.positions()),
            _ => None,
        };
        // Target samples still to check: all at first, then the previous pass's misses.
        let mut check: Vec<u32> = match refine {
            Some(samples) => (0..samples.len() as u32).collect(),
            None => vec![],
        };
        let passes = self.settings.fit.passes;
        let most = passes
            + if refine.is_some() {
                self.settings.fit.refine_passes
            } else {
                0
            };
        // Each pass: moves (half of it), remesh, check.
        let mut at = |pass: u32, part: f64| {
            progress.report(FIT_PHASE, (pass as f64 + part) / most.max(1) as f64)
        };
        let mut creases_placed = false;
        // How many passes in a row lost their remesh to intersections: their caps never became
        // edges, and an extra pass after two such would most likely lose its own again
        // (sphere-cut: every one of its seven passes, 27 s of fit for nothing).
        let mut remeshes_lost = 0;
        // An extra pass whose remesh grew the wrap past the vertex budget (the caps are only
        // part of the growth) keeps its moves without it, and is the last (DoubleWedge: 81 870
        // vertices after its seventh pass, from 80 276 before the fit).
        let mut over_budget = false;
        // What a pass left to refine (target samples still missed, wrap vertices beside bevelled
        // creases); an extra pass that left no less than the one before and reached nothing is
        // the last (fish: the same 22 unreachable misses through seven passes; now three).
        let (mut left_before, mut stalled) = ((usize::MAX, usize::MAX), false);
        let cloud = matches!(target, SnapTarget::Points(_));
        // The moves onto the target (a cloud's near its crease lines onto their faces' planes).
        let creases = self.creases.as_ref();
        let snap = |mesh: &mut HalfedgeMesh, normals: &[DVec3], progress: &mut dyn FnMut(f64)| {
            snap_to_target(mesh, normals, target, &params, creases, progress)
        };
        let mut missed = true;
        let budget = self.settings.fit.refine_max_vertices;
        // Reaching into concavities tests its way for the target's inside when it has one.
        let closed = self.field.signedness() == crate::field::sign::Signedness::Signed;
        let (mut reached_any, mut reached_last) = (false, false);
        // Whether the surface is known to be free of intersections as written: the settled
        // surface (the contact guard checked it before the fit) and every pass's end but the
        // redo's (see the end of the fit).
        let mut certified = true;
        let mut sw = Laps(now_ms());
        for pass in 0..most {
            // (A pass after a reach puts the dents' new vertices on the target.)
            let spent = remeshes_lost >= 2 || over_budget || stalled;
            if pass >= passes && ((!missed && !reached_last) || spent) {
                break;
            }
            at(pass, 0.0);
            sw.lap();
            // The surface here is certified; keep it to redo the pass with the guard if needed.
            let clean = contact.then(|| self.mesh.clone());
            let start_of_pass = self.creases.is_some().then(|| self.mesh.clone());
            let normals = angle_weighted_normals(&self.mesh);
            moved = snap(&mut self.mesh, &normals, &mut |f| at(pass, 0.5 * f));
            // Into the concavities the moves bridge, once the first pass has found the misses.
            let reach_now = self.settings.fit.reach && pass > 0 && pass + 1 < most;
            // Without the reach when its dents leave the creases no intersection-free snap.
            let unreached =
                (reach_now && creases_placed && refine.is_some()).then(|| self.mesh.clone());
            let mut reached = 0;
            if let (Some(samples), SnapTarget::Triangles(bvh), true) = (refine, target, reach_now) {
                let (tol, reach) = (refine_tol, params.max_move);
                reached =
                    reach_into_misses(&mut self.mesh, bvh, samples, &check, tol, reach, closed);
            }
            ft.moves += sw.lap();
            let (mut snap_moves, mut features, mut refused) = (None, None, false);
            for undo_reach in [false, true] {
                if undo_reach {
                    match (&unreached, refused && reached > 0) {
                        (Some(m), true) => self.mesh = m.clone(),
                        _ => break,
                    }
                    reached = 0;
                }
                // The moves, kept for a redo of the pass (the snap only moves vertices).
                snap_moves = clean.is_some().then(|| self.mesh.positions().to_vec());
                // Undo the moves that made faces intersect before anything else: the crease
                // snap and the remesh below are checked for intersections, and would otherwise be
                // blamed for them (every crease try refused; the pass redone after its remesh,
                // which cost the bunny a fifth of its fit).
                // After a reach, as written, and the crease snap checked so too: the pass's
                // remesh is checked that way, and a reach's dents left touching here intersected
                // there after the rounding, beyond what the remesh's retries can freeze away
                // (the bust's fourth pass, lost with the rest of the fit). (Elsewhere the checks
                // in the stabilised frame refuse fewer crease moves: cube-hole and cad-part at
                // five grid sizes kept 2 850 of their 2 850 crease edges, as written 2 825.)
                let as_written = reached > 0;
                if let Some(clean) = &clean {
                    let (guard, phi, center) = (&self.settings.guard, self.phi, self.center);
                    if !as_written {
                        resolve_contacts(&mut self.mesh, clean.positions(), guard);
                    } else {
                        let old = clean.positions();
                        resolve_contacts_as_written(&mut self.mesh, old, guard, phi, center);
                    }
                }
                ft.contacts += sw.lap();
                // Sharp creases: vertices onto them, edges along them, kept by the remesh.
                features = match &self.creases {
                    None => None,
                    Some(c) => snap_creases_checked(
                        &mut self.mesh,
                        c,
                        params.max_move,
                        (cloud || as_written).then_some(&|m: &mut HalfedgeMesh| {
                            round_as_written(m, self.phi, self.center)
                        }),
                        match target {
                            SnapTarget::Triangles(bvh) => Some(bvh),
                            SnapTarget::Points(_) => None,
                        },
                    ),
                };
                ft.creases += sw.lap();
                refused = self.creases.is_some() && features.is_none();
                if !refused {
                    break;
                }
            }
            reached_last = reached > 0;
            reached_any |= reached_last;
            moved += reached;
            // An earlier pass placed the creases: keep this pass's moves without a remesh (they
            // leave vertices on a crease where they are), or else the earlier surface, rather
            // than round the creases off again.
            if refused && creases_placed {
                round_as_written(&mut self.mesh, self.phi, self.center);
                if contact && intersects_as_written(&self.mesh, self.phi, self.center) {
                    if let Some(m) = start_of_pass {
                        self.mesh = m;
                    }
                } else {
                    certified = true;
                }
                break;
            }
            // Even out the triangles the moves distorted, staying on the fitted surface; with
            // shorter edges where it still misses the target.
            // The caps live in a vertex layer, so the edits carry them to later passes and the
            // curvature sizing does not coarsen a refined region again. (No new caps in the
            // last pass: the next pass's moves must put the new vertices on the target.)
            ft.checks += sw.lap();
            let caps = refine.map(|samples| {
                self.mesh.garbage_collect();
                let floor = self.sizes.min_edge_length;
                let last = pass + 1 >= most;
                let wrap = (!last).then(|| wrap_faces(&self.mesh));
                let errors = wrap
                    .as_ref()
                    .and_then(|w| error_caps(&self.mesh, w, samples, &check, refine_tol, floor));
                let bevels = match (&self.creases, &wrap) {
                    (Some(creases), Some(w)) => {
                        let tol = BEVEL_TOL_DEG.to_radians();
                        crease_caps(&self.mesh, w, creases, crease_offset, tol, floor)
                    }
                    _ => None,
                };
                let count = |caps: &[f64]| caps.iter().filter(|c| c.is_finite()).count();
                let left = (
                    errors.as_ref().map_or(0, |(_, m)| m.len()),
                    bevels.as_deref().map_or(0, count),
                );
                stalled = pass >= passes
                    && reached == 0
                    && left.0 >= left_before.0
                    && left.1 >= left_before.1;
                left_before = left;
                let (new, misses) = match (errors, bevels) {
                    (Some((mut e, m)), Some(b)) => {
                        for (x, y) in e.iter_mut().zip(b) {
                            *x = x.min(y);
                        }
                        (Some(e), Some(m))
                    }
                    (Some((e, m)), None) => (Some(e), Some(m)),
                    (None, b) => (b, None),
                };
                let new = new.filter(|caps| self.mesh.n_vertices() + 4 * count(caps) <= budget);
                missed = new.is_some();
                if self.mesh.vertex_scalars(CAP_LAYER).is_none() {
                    self.mesh.set_vertex_scalar_layer(CAP_LAYER, NO_CAP);
                }
                let layer = self.mesh.vertex_scalars_mut(CAP_LAYER).unwrap_or_default();
                if let Some(new) = new {
                    for (l, c) in layer.iter_mut().zip(new) {
                        *l = l.min(c);
                    }
                    if let Some(misses) = misses {
                        check = misses;
                    }
                }
                layer.to_vec()
            });
            ft.sizing += sw.lap();
            let (phi, center) = (self.phi, self.center);
            // False when the remesh ran away (see `FIT_SPLITS_PER_VERTEX`), leaving the mesh
            // part-way: the caller puts the surface before it back.
            let remesh_now = |mesh: &mut HalfedgeMesh, features: Option<&Features>| {
                let done = match (features, &caps) {
                    (f, Some(caps)) => remesh_capped(mesh, rs_now, f, caps),
                    (Some(f), None) => remesh_with_features(mesh, rs_now, f),
                    (None, None) => remesh(mesh, rs_now),
                };
                round_as_written(mesh, phi, center);
                !matches!(done, Err(RemeshError::Runaway { .. }))
            };
            // The moves (and the crease snap) left this surface intersection-free: if the remesh
            // breaks that, keep the surface without the remesh rather than lose the moves.
            let unremeshed = remeshing.then(|| self.mesh.clone());
            let n_before = self.mesh.n_vertices();
            let mut ran_away = false;
            if remeshing {
                ran_away = !remesh_now(&mut self.mesh, features.as_ref());
            } else {
                round_as_written(&mut self.mesh, phi, center);
            }
            at(pass, 0.75);
            ft.remesh += sw.lap();
            let Some(clean) = clean else {
                if let (true, Some(m)) = (ran_away, unremeshed) {
                    self.mesh = m;
                    round_as_written(&mut self.mesh, phi, center);
                }
                rs_now = &rs;
                continue;
            };
            let intersects = |m: &HalfedgeMesh| intersects_as_written(m, phi, center);
            // On a mesh target, a remesh that makes faces intersect is tried again with the
            // region of those faces left as it was, rather than lost everywhere (the bust's
            // passes after a reach lost every remesh to a few faces in its mouth slit). (A
            // cloud's fit gained nothing by it: spotPts_4's mean target → wrap 0.50 → 0.55 %.)
            let lost = ran_away
                || match (&unremeshed, cloud) {
                    (Some(before), false) => {
                        let mut frozen = vec![false; before.n_vertices()];
                        let mut lost = true;
                        for tries_left in (0..=REMESH_TRIES).rev() {
                            match freeze_where_intersecting(
                                &self.mesh,
                                before,
                                |p| written(p, phi, center),
                                &mut frozen,
                            ) {
                                None => lost = false,
                                Some(true) if tries_left > 0 => {
                                    let mut f =
                                        features.clone().unwrap_or_else(|| Features::none(before));
                                    f.frozen.clone_from(&frozen);
                                    self.mesh = before.clone();
                                    if remesh_now(&mut self.mesh, Some(&f)) {
                                        continue;
                                    }
                                }
                                Some(_) => {}
                            }
                            break;
                        }
                        lost
                    }
                    _ => intersects(&self.mesh),
                };
            ft.checks += sw.lap();
            over_budget = pass >= passes && self.mesh.n_vertices() > budget.max(n_before);
            let lost = lost || over_budget;
            rs_now = &rs;
            if lost {
                remeshes_lost += 1;
            } else {
                remeshes_lost = 0;
                creases_placed |= features.is_some();
                certified = true;
                continue;
            }
            if let Some(mut m) = unremeshed {
                round_as_written(&mut m, self.phi, self.center);
                if !intersects(&m) {
                    self.mesh = m;
                    creases_placed |= features.is_some();
                    certified = true;
                    continue;
                }
            }
            // An earlier pass placed the creases and passed this check: keep its surface.
            if let (true, Some(m)) = (creases_placed, start_of_pass) {
                self.mesh = m;
                break;
            }
            // Redo the pass: the same moves, then put back those that make faces intersect,
            // then a remesh that is undone if it intersects.
            let before = clean.positions().to_vec();
            self.mesh = clean;
            // (Its contacts are put back as written, but a move put back onto the pass's start
            // can still meet as written where that start only passed the check in the
            // stabilised frame.)
            certified = false;
            if let Some(moves) = &snap_moves {
                self.mesh.positions_mut().copy_from_slice(moves);
            }
            let (guard, phi, center) = (&self.settings.guard, self.phi, self.center);
            resolve_contacts_as_written(&mut self.mesh, &before, guard, phi, center);
            round_as_written(&mut self.mesh, self.phi, self.center);
            if remeshing {
                let unremeshed = self.mesh.clone();
                let done = remesh(&mut self.mesh, &rs);
                round_as_written(&mut self.mesh, self.phi, self.center);
                if done.is_err() || intersects_as_written(&self.mesh, self.phi, self.center) {
                    self.mesh = unremeshed;
                }
            }
        }
        // Every pass ends with a remesh, whose new and smoothed vertices lie on the surface
        // before it, not on the target: a mesh target gets one more round of moves without a
        // remesh (cad-part's Hausdorff 0.26 → 0.08 %, cube-hole's rim creases 137 → 139 of 140
        // within 10°). After a reach it also settles the tips of flaps left in concavities; on a
        // closed target every vertex still off it goes to its closest point.
        sw.lap();
        if let SnapTarget::Triangles(bvh) = target {
            // (Its slivers first: a folded one holds its neighbours' moves back.)
            tidy_slivers(&mut self.mesh, contact, self.phi, self.center);
            let clean = self.mesh.clone();
            let normals = angle_weighted_normals(&self.mesh);
            snap(&mut self.mesh, &normals, &mut |_| {});
            // (On a closed target the second move covers the flap tips too.)
            if closed {
                snap_to_closest(&mut self.mesh, bvh, SETTLED_CELLS * c, params.max_move);
            } else if reached_any {
                settle_flap_tips(&mut self.mesh, bvh, refine_tol, params.max_move);
            }
            if contact {
                // As written: snapped faces that lie in one target plane are exactly coplanar
                // there, and only there do the ones that overlap show (cube-hole: 5 pairs).
                let (guard, phi, center) = (&self.settings.guard, self.phi, self.center);
                let wanted = self.mesh.positions().to_vec();
                resolve_contacts_as_written(&mut self.mesh, clean.positions(), guard, phi, center);
                partial_moves(
                    &mut self.mesh,
                    clean.positions(),
                    &wanted,
                    guard,
                    phi,
                    center,
                );
            }
            round_as_written(&mut self.mesh, self.phi, self.center);
            if contact && intersects_as_written(&self.mesh, self.phi, self.center) {
                self.mesh = clean;
            } else if contact {
                certified = true;
            }
        }
        ft.last_round += sw.lap();
        tidy_slivers(&mut self.mesh, contact, self.phi, self.center);
        ft.tidy += sw.lap();
        self.mesh.remove_vertex_scalar_layer(CAP_LAYER);
        at(most, 0.0);
        // A surface the passes left intersecting (a redone pass whose put-back moves still
        // intersect as written: cube-hole with 3 % of its faces dropped kept 12 pairs and was
        // refused) gives way to the settled one, valid if less close.
        let intersecting =
            contact && !certified && intersects_as_written(&self.mesh, self.phi, self.center);
        if intersecting || self.mesh.validate().is_err() {
            self.mesh = backup;
            return Some(0);
        }
        Some(moved)
    }
}

/// Flips the caps and collapses the needles that moves onto crease lines left since the last
/// remesh (see [`crate::remesh::slivers`]). With the contact guard on, where that makes faces
/// intersect as written it is tried again with those regions left alone, as a pass's remesh is
/// (sphere-cut: 217 edits made its doubled sheet intersect).
fn tidy_slivers(mesh: &mut HalfedgeMesh, contact: bool, phi: f64, center: DVec3) {
    let mut frozen = vec![false; mesh.n_vertices()];
    for _ in 0..=REMESH_TRIES {
        let mut tidied = mesh.clone();
        let report = remove_slivers(&mut tidied, &SliverSettings::default(), &frozen);
        if report == SliverReport::default() {
            return;
        }
        if !contact {
            *mesh = tidied;
            return;
        }
        match freeze_where_intersecting(&tidied, mesh, |p| written(p, phi, center), &mut frozen) {
            None => {
                *mesh = tidied;
                return;
            }
            Some(true) => {}
            Some(false) => return,
        }
    }
}

/// Where the final fit's time goes, in milliseconds (summed over its passes).
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize)]
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
    fn named(&self) -> f64 {
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

/// Fractions of a reverted move tried again, in turn (see [`partial_moves`]).
const PARTIAL_MOVES: [f64; 3] = [0.5, 0.25, 0.125];

/// After [`resolve_contacts_as_written`] put vertices back from their `wanted` positions to
/// `old`, moves them part of the way again — half, then a quarter, an eighth — each time
/// keeping what intersects nothing: a flap tip whose move onto the target crosses a face still
/// ends closer to it (a turned bust's last round put 41 vertices back, 1.39 % of the diagonal
/// off the target).
fn partial_moves(
    mesh: &mut HalfedgeMesh,
    old: &[DVec3],
    wanted: &[DVec3],
    guard: &crate::flow::guard::GuardSettings,
    phi: f64,
    center: DVec3,
) {
    let reach = |v: usize| (wanted[v] - old[v]).length();
    let from_old = |mesh: &HalfedgeMesh, v: usize| (mesh.positions()[v] - old[v]).length();
    // Put back: nearer where it was than where it went (positions come back through the written
    // frame, so not bit for bit).
    let mut pending: Vec<bool> = (0..wanted.len())
        .map(|v| reach(v) > 0.0 && from_old(mesh, v) < 0.5 * reach(v))
        .collect();
    for frac in PARTIAL_MOVES {
        if !pending.contains(&true) {
            return;
        }
        let now = mesh.positions().to_vec();
        for (v, p) in mesh.positions_mut().iter_mut().enumerate() {
            if pending[v] {
                *p = old[v] + frac * (wanted[v] - old[v]);
            }
        }
        resolve_contacts_as_written(mesh, &now, guard, phi, center);
        for (v, pending) in pending.iter_mut().enumerate() {
            if *pending && from_old(mesh, v) > 0.5 * frac * reach(v) {
                *pending = false;
            }
        }
    }
}

/// [`resolve_contacts`] on the positions as written (see [`intersects_as_written`]); `mesh` is
/// left at its written positions, mapped back into the stabilised frame (`phi`, `center`).
fn resolve_contacts_as_written(
    mesh: &mut HalfedgeMesh,
    old: &[DVec3],
    guard: &crate::flow::guard::GuardSettings,
    phi: f64,
    center: DVec3,
) {
    let mut w = mesh.clone();
    for p in w.positions_mut() {
        *p = written(*p, phi, center);
    }
    let old: Vec<DVec3> = old.iter().map(|&p| written(p, phi, center)).collect();
    resolve_contacts(&mut w, &old, guard);
    for (p, q) in mesh.positions_mut().iter_mut().zip(w.positions()) {
        *p = (*q - center) * phi;
    }
}

/// Splits per vertex at most in a fit's remesh (see `RemeshSettings::max_splits_per_vertex`):
/// a regular pass splits under twice per vertex (the open bunny's refinement 1.8), while plane
/// fits over a 20-point cloud crumpled the wrap into a million splits per remesh, each undone.
const FIT_SPLITS_PER_VERTEX: f64 = 4.0;

/// How far off a closed mesh target (in cells) a vertex may stay after the fit's last round.
const SETTLED_CELLS: f64 = 0.02;

/// The vertex layer of the error-adaptive caps on the edge length (see `flow::error_sizing`).
const CAP_LAYER: &str = "fit_cap";
/// "No cap" in [`CAP_LAYER`]: finite, because a split vertex gets the mean of its ends' values.
const NO_CAP: f64 = 1e300;

/// True when faces of `m` intersect as written (in the target's frame, rounded to f32): the
/// certificate's check. The same check in the stabilised frame can differ where faces nearly
/// touch (the frame's scaling rounds), and a fit that passed it was certified invalid (a bust
/// whose flap tips moved onto the target: 4 pairs).
fn intersects_as_written(m: &HalfedgeMesh, phi: f64, center: DVec3) -> bool {
    let written: Vec<DVec3> = m
        .positions()
        .iter()
        .map(|&p| written(p, phi, center))
        .collect();
    count_self_intersections(&written, &m.triangles()) > 0
}

/// [`snap_to_creases`] kept intersection-free: a try that makes faces intersect is undone and
/// redone without the vertices of those faces and their neighbours, a few times at most; then
/// the mesh is as it came and the answer is None.
///
/// With `round`, the check is of the positions as written. A cloud's crease lines are many
/// short pieces found point by point, and the wrap over a cloud is finer than a mesh target's
/// fit: a vertex often lands on a line between two others already on it, touching their faces,
/// which the f32 rounding turns into a crossing that the pass's own check then refuses whole
/// (a cube cloud kept no crease). A mesh's snap is checked as computed, as before.
fn snap_creases_checked(
    mesh: &mut HalfedgeMesh,
    creases: &Creases,
    reach: f64,
    round: Option<&dyn Fn(&mut HalfedgeMesh)>,
    triangles: Option<&TriangleBvh>,
) -> Option<Features> {
    mesh.garbage_collect();
    let before = mesh.clone();
    let mut banned = vec![false; before.n_vertices()];
    for _ in 0..CREASE_TRIES {
        let (features, _) = snap_to_creases(mesh, creases, reach, &banned, triangles);
        if let Some(round) = round {
            round(mesh);
        }
        let tris = mesh.triangles();
        let pairs = self_intersecting_pairs(mesh.positions(), &tris);
        if pairs.is_empty() {
            return Some(features);
        }
        for (f, g) in pairs {
            for v in tris[f as usize].into_iter().chain(tris[g as usize]) {
                banned[v as usize] = true;
                for u in before.neighbors(v) {
                    banned[u as usize] = true;
                }
            }
        }
        *mesh = before.clone();
    }
    None
}

/// Tries of the crease snap per fit pass (see [`snap_creases_checked`]).
const CREASE_TRIES: usize = 3;

#[cfg(test)]
mod tests {
    use super::*;
    use crate::flow::guard::GuardSettings;
    use crate::geometry::icosphere::icosphere;
    use crate::metrics::intersections::count_self_intersections;

    #[test]
    fn a_move_put_back_for_crossing_a_face_is_made_part_of_the_way() {
        let mut m = icosphere(2, 1.0, DVec3::ZERO).unwrap();
        let (phi, center) = (1.0, DVec3::ZERO);
        round_as_written(&mut m, phi, center);
        let old = m.positions().to_vec();
        // Vertex 0 wanted through the far side of the sphere: its fan would cross it.
        let mut wanted = old.clone();
        wanted[0] = -1.3 * old[0];
        wanted[1] = 0.99 * old[1];
        m.positions_mut().copy_from_slice(&wanted);
        let guard = GuardSettings::default();
        resolve_contacts_as_written(&mut m, &old, &guard, phi, center);
        assert_eq!(m.position(0), old[0], "the whole move is put back");
        partial_moves(&mut m, &old, &wanted, &guard, phi, center);
        let p = m.positions().to_vec();
        assert_eq!(count_self_intersections(&p, &m.triangles()), 0);
        // Half way (−0.15 p₀, inside) crosses nothing; a vertex the guard kept stays.
        let half = old[0] + 0.5 * (wanted[0] - old[0]);
        assert!((p[0] - half).length() < 1e-6, "{:?} vs {half:?}", p[0]);
        assert!((p[1] - wanted[1]).length() < 1e-6);
    }
}
