//! The first steps of a fit pass: the moves onto the target, the reach into the concavities
//! they bridge, the contacts they made put back, and the crease snap, with the reach undone
//! when it leaves the creases no intersection-free snap.

use super::checks::{intersects_as_written, resolve_contacts_as_written, snap_creases_checked};
use super::reach::reach_into_misses;
use super::Fit;
use crate::flow::guard::resolve_contacts;
use crate::flow::guarded::{guarded, GuardPolicy, Verdict};
use crate::flow::scaling::round_as_written;
use crate::flow::snap::{snap_to_target, SnapTarget};
use crate::geometry::creases::Creases;
use crate::geometry::operators::normals::angle_weighted_normals;
use crate::mesh::HalfedgeMesh;
use crate::remesh::features::Features;
use glam::DVec3;

/// One pass under way: its snapshots and what its steps found.
pub(super) struct Pass {
    /// The pass's index (from 0).
    pub index: u32,
    /// The surface at the pass's start (certified) when the contact guard is on: a pass redone
    /// starts from it.
    pub clean: Option<HalfedgeMesh>,
    /// The same when the target has creases: kept instead of a later surface that would round
    /// placed creases off.
    pub start: Option<HalfedgeMesh>,
    /// The surface after the moves, before the reach, where the reach may have to be undone
    /// (creases placed by an earlier pass).
    pub unreached: Option<HalfedgeMesh>,
    /// The positions after the moves (and the reach) with the contact guard on, for a redo.
    pub snap_moves: Option<Vec<DVec3>>,
    /// Vertices the reach moved (0 when it was undone).
    pub reached: usize,
    /// The wrap's features along the creases the snap placed.
    pub features: Option<Features>,
    /// The target has creases and their snap was refused (every try intersected).
    pub refused: bool,
}

impl Fit<'_, '_> {
    /// Pass `pass`'s moves onto the target and, after the first pass, its reach into the
    /// concavities the moves bridge; the pass's snapshots are taken first.
    pub(super) fn moves(&mut self, pass: u32) -> Pass {
        let opt = self.opt;
        // The surface here is certified; keep it to redo the pass with the guard if needed.
        let clean = opt.contact.then(|| self.mesh.clone());
        let start = self.creases.is_some().then(|| self.mesh.clone());
        let normals = angle_weighted_normals(self.mesh);
        let at = &mut self.at;
        self.state.moved = snap_to_target(
            self.mesh,
            &normals,
            self.target,
            &opt.snap,
            self.creases,
            &mut |f| at.report(pass, 0.5 * f),
        );
        // Into the concavities the moves bridge, once the first pass has found the misses.
        let reach_now = opt.reach && pass > 0 && pass + 1 < self.most;
        // Without the reach when its dents leave the creases no intersection-free snap.
        let unreached = (reach_now && self.state.creases_placed && self.refine.is_some())
            .then(|| self.mesh.clone());
        let mut reached = 0;
        if let (Some(samples), SnapTarget::Triangles(bvh), true) =
            (self.refine, self.target, reach_now)
        {
            let (tol, reach, closed) = (opt.refine_tol, opt.snap.max_move, opt.closed);
            let check = &self.state.check;
            reached = reach_into_misses(self.mesh, bvh, samples, check, tol, reach, closed);
        }
        self.times.moves += self.sw.lap();
        Pass {
            index: pass,
            clean,
            start,
            unreached,
            snap_moves: None,
            reached,
            features: None,
            refused: false,
        }
    }

    /// The contacts the moves made put back, then the crease snap; when the snap is refused
    /// after a reach that can be undone, both again without the reach.
    pub(super) fn contacts_and_creases(&mut self, p: &mut Pass) {
        for undo_reach in [false, true] {
            if undo_reach {
                match (&p.unreached, p.refused && p.reached > 0) {
                    (Some(m), true) => *self.mesh = m.clone(),
                    _ => break,
                }
                p.reached = 0;
            }
            // The moves, kept for a redo of the pass (the snap only moves vertices).
            p.snap_moves = p.clean.is_some().then(|| self.mesh.positions().to_vec());
            // After a reach the contacts and the crease snap are checked as written, as the
            // pass's remesh is: dents left touching in the stabilised frame can intersect after
            // the rounding, beyond what the remesh's retries can freeze away. Elsewhere the
            // checks in the stabilised frame refuse fewer crease moves.
            let as_written = p.reached > 0;
            self.put_back_contacts(p.clean.as_ref(), as_written);
            self.times.contacts += self.sw.lap();
            p.features = match self.creases {
                None => None,
                Some(c) => self.snap_creases(c, as_written),
            };
            self.times.creases += self.sw.lap();
            p.refused = self.creases.is_some() && p.features.is_none();
            if !p.refused {
                break;
            }
        }
    }

    /// Undoes the moves that made faces intersect (against the pass's `clean` start) before
    /// anything else: the crease snap and the remesh are checked for intersections, and would
    /// otherwise be blamed for them.
    fn put_back_contacts(&mut self, clean: Option<&HalfedgeMesh>, as_written: bool) {
        let Some(clean) = clean else {
            return;
        };
        let (guard, phi, center) = (&self.opt.guard, self.opt.phi, self.opt.center);
        if !as_written {
            resolve_contacts(self.mesh, clean.positions(), guard);
        } else {
            let old = clean.positions();
            resolve_contacts_as_written(self.mesh, old, guard, phi, center);
        }
    }

    /// Sharp creases: vertices onto them, edges along them, kept by the remesh; checked as
    /// written on a cloud or after a reach (see [`snap_creases_checked`]).
    fn snap_creases(&mut self, creases: &Creases, as_written: bool) -> Option<Features> {
        let (phi, center) = (self.opt.phi, self.opt.center);
        let cloud = matches!(self.target, SnapTarget::Points(_));
        let round = |m: &mut HalfedgeMesh| round_as_written(m, phi, center);
        let triangles = match self.target {
            SnapTarget::Triangles(bvh) => Some(bvh),
            SnapTarget::Points(_) => None,
        };
        snap_creases_checked(
            self.mesh,
            creases,
            self.opt.snap.max_move,
            (cloud || as_written).then_some(&round),
            triangles,
        )
    }

    /// Counts the pass's reach: into `moved`, and for the passes that follow.
    pub(super) fn count_reach(&mut self, reached: usize) {
        self.state.reached_last = reached > 0;
        self.state.reached_any |= self.state.reached_last;
        self.state.moved += reached;
    }

    /// The crease snap was refused after an earlier pass placed the creases: keeps this pass's
    /// moves without a remesh (they leave vertices on a crease where they are), or else the
    /// pass's `start`, rather than round the creases off again.
    pub(super) fn keep_moves_unremeshed(&mut self, start: Option<HalfedgeMesh>) {
        let (contact, phi, center) = (self.opt.contact, self.opt.phi, self.opt.center);
        let outcome = guarded(
            &mut *self.mesh,
            &mut [],
            GuardPolicy::ONCE,
            |m, _| {
                round_as_written(m, phi, center);
                true
            },
            |m, _| Verdict::clean_if(!(contact && intersects_as_written(m, phi, center))),
            |m| {
                if let Some(start) = start {
                    *m = start;
                }
            },
        );
        self.state.certified |= outcome.clean;
    }
}
