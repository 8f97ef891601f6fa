//! The last step of a fit pass: the remesh, which evens out the triangles the moves distorted
//! (staying on the fitted surface, with shorter edges where the caps ask), and its check. A
//! remesh that makes faces intersect is tried again with those regions left alone; one that is
//! still lost gives way to the surface without it, or to an earlier pass's, or the pass is
//! redone with the guard.

use super::checks::{intersects_as_written, resolve_contacts_as_written};
use super::moves::Pass;
use super::Fit;
use crate::flow::guard::{freeze_where_intersecting, REMESH_TRIES};
use crate::flow::guarded::{guarded, GuardPolicy, Verdict};
use crate::flow::scaling::{round_as_written, written};
use crate::mesh::HalfedgeMesh;
use crate::remesh::adaptive::{
    remesh, remesh_capped, remesh_with_features, RemeshError, RemeshSettings,
};
use crate::remesh::features::Features;
use glam::DVec3;

impl Fit<'_, '_> {
    /// Pass `p`'s remesh with `caps` and its check; false when the fit keeps an earlier pass's
    /// surface and stops.
    pub(super) fn remesh_step(&mut self, p: Pass, caps: Option<&[f64]>) -> bool {
        let opt = self.opt;
        let (pass, rs) = (p.index, opt.pass_remesh(p.index));
        let (phi, center) = (opt.phi, opt.center);
        // The moves (and the crease snap) left this surface intersection-free: if the remesh
        // breaks that, keep the surface without the remesh rather than lose the moves.
        let unremeshed = opt.remeshing.then(|| self.mesh.clone());
        let n_before = self.mesh.n_vertices();
        let mut ran_away = false;
        if opt.remeshing {
            ran_away = !remesh_once(self.mesh, rs, p.features.as_ref(), caps, phi, center);
        } else {
            round_as_written(self.mesh, phi, center);
        }
        self.at.report(pass, 0.75);
        self.times.remesh += self.sw.lap();
        let Some(clean) = p.clean else {
            if let (true, Some(m)) = (ran_away, unremeshed) {
                *self.mesh = m;
                round_as_written(self.mesh, phi, center);
            }
            return true;
        };
        let features = p.features.as_ref();
        let lost = ran_away || self.remesh_lost(unremeshed.as_ref(), features, caps, rs);
        self.times.checks += self.sw.lap();
        self.state.over_budget =
            pass >= opt.passes && self.mesh.n_vertices() > opt.budget.max(n_before);
        if !(lost || self.state.over_budget) {
            self.state.remeshes_lost = 0;
            self.state.creases_placed |= p.features.is_some();
            self.state.certified = true;
            return true;
        }
        self.state.remeshes_lost += 1;
        let placed = p.features.is_some();
        self.fall_back(clean, unremeshed, p.start, p.snap_moves, placed)
    }

    /// Whether the remesh from `unremeshed` left faces intersecting as written. On a mesh
    /// target it is first tried again with the region of those faces left as it was (a guarded
    /// edit), rather than lost everywhere (a cloud's fit gains nothing by that).
    fn remesh_lost(
        &mut self,
        unremeshed: Option<&HalfedgeMesh>,
        features: Option<&Features>,
        caps: Option<&[f64]>,
        rs: &RemeshSettings,
    ) -> bool {
        let (phi, center) = (self.opt.phi, self.opt.center);
        let cloud = matches!(self.target, crate::flow::snap::SnapTarget::Points(_));
        let before = match (unremeshed, cloud) {
            (Some(before), false) => before,
            _ => return intersects_as_written(self.mesh, phi, center),
        };
        let mut frozen = vec![false; before.n_vertices()];
        let policy = GuardPolicy {
            tries: REMESH_TRIES + 1,
            applied: true,
        };
        let outcome = guarded(
            &mut *self.mesh,
            &mut frozen,
            policy,
            |mesh, frozen| {
                let mut f = features.cloned().unwrap_or_else(|| Features::none(before));
                f.frozen = frozen.to_vec();
                *mesh = before.clone();
                remesh_once(mesh, rs, Some(&f), caps, phi, center)
            },
            |mesh, frozen| {
                freeze_where_intersecting(mesh, before, |p| written(p, phi, center), frozen)
            },
            // Lost: the caller falls back.
            |_| {},
        );
        !outcome.clean
    }

    /// The pass's remesh is lost: keeps the surface without it where that is free of
    /// intersections as written; else an earlier pass's surface with its placed creases (the
    /// pass's `start`: false, the fit stops there); else redoes the pass from `clean`. `placed`:
    /// the pass's crease snap placed its creases.
    fn fall_back(
        &mut self,
        clean: HalfedgeMesh,
        unremeshed: Option<HalfedgeMesh>,
        start: Option<HalfedgeMesh>,
        moves: Option<Vec<DVec3>>,
        placed: bool,
    ) -> bool {
        let (phi, center) = (self.opt.phi, self.opt.center);
        if let Some(mut m) = unremeshed {
            round_as_written(&mut m, phi, center);
            if !intersects_as_written(&m, phi, center) {
                *self.mesh = m;
                self.state.creases_placed |= placed;
                self.state.certified = true;
                return true;
            }
        }
        // An earlier pass placed the creases and passed this check: keep its surface.
        if let (true, Some(m)) = (self.state.creases_placed, start) {
            *self.mesh = m;
            return false;
        }
        self.redo(clean, moves);
        true
    }

    /// Redoes the pass from `clean`: the same `moves`, then those that make faces intersect
    /// put back, then a remesh that is undone if it intersects. The result is not certified:
    /// its contacts are put back as written, but a move put back onto the pass's start can
    /// still meet as written where that start only passed the check in the stabilised frame.
    fn redo(&mut self, clean: HalfedgeMesh, moves: Option<Vec<DVec3>>) {
        let (phi, center) = (self.opt.phi, self.opt.center);
        let before = clean.positions().to_vec();
        *self.mesh = clean;
        self.state.certified = false;
        if let Some(moves) = &moves {
            self.mesh.positions_mut().copy_from_slice(moves);
        }
        resolve_contacts_as_written(self.mesh, &before, &self.opt.guard, phi, center);
        round_as_written(self.mesh, phi, center);
        if self.opt.remeshing {
            let unremeshed = self.mesh.clone();
            let rs = &self.opt.remesh;
            guarded(
                &mut *self.mesh,
                &mut [],
                GuardPolicy::ONCE,
                |m, _| {
                    let done = remesh(m, rs);
                    round_as_written(m, phi, center);
                    done.is_ok()
                },
                |m, _| Verdict::clean_if(!intersects_as_written(m, phi, center)),
                |m| *m = unremeshed,
            );
        }
    }
}

/// One remesh of a fit pass (capped where `caps` say, keeping the creases' `features`), its
/// result rounded as written. False when it ran away (see `FIT_SPLITS_PER_VERTEX`), leaving
/// the mesh part-way: the caller puts the surface before it back.
fn remesh_once(
    mesh: &mut HalfedgeMesh,
    rs: &RemeshSettings,
    features: Option<&Features>,
    caps: Option<&[f64]>,
    phi: f64,
    center: DVec3,
) -> bool {
    let done = match (features, caps) {
        (f, Some(caps)) => remesh_capped(mesh, rs, f, caps),
        (Some(f), None) => remesh_with_features(mesh, rs, f),
        (None, None) => remesh(mesh, rs),
    };
    round_as_written(mesh, phi, center);
    !matches!(done, Err(RemeshError::Runaway { .. }))
}
