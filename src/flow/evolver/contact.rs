//! Phase 5 of a step, *contact guard*: every `tuning.guard.check_every` steps (each step after a
//! roll-back until a stretch of them makes no contact, and always before the final fit) the
//! surface is checked for intersecting faces.
//! With the pre-move surface at hand, the move is redone putting back the vertices of the
//! intersecting faces; without it, the evolution goes back to the last certified state and
//! redoes the steps from there, checking each.

use super::{EvolveError, Evolver, PhaseTimes};
use crate::clock::now_ms;
use crate::flow::guard::{release_held, resolve_contacts, ContactReport};
use crate::mesh::HalfedgeMesh;
use crate::metrics::intersections::count_self_intersections;
use glam::DVec3;

/// What the contact guard did.
pub(super) enum Contact {
    /// The surface is certified free of intersections (or was not checked this step): the
    /// guard's report and whether a remesh was undone.
    Checked(ContactReport, bool),
    /// Intersections and no pre-move surface: back at the last certified state, which the
    /// failed step `from` had left.
    RolledBack { from: u32 },
}

impl Evolver {
    /// Checks the moved (and remeshed: `remeshed`) surface when due; `ends` says this step ends
    /// the evolution, so the check cannot wait.
    pub(super) fn contact_guard(
        &mut self,
        pre: Option<HalfedgeMesh>,
        x: &[DVec3],
        old: &[DVec3],
        remeshed: bool,
        ends: bool,
        times: &mut PhaseTimes,
    ) -> Result<Contact, EvolveError> {
        let g = &self.settings.tuning.guard;
        let due = pre.is_some() || ends || self.step >= self.checkpoint.step + g.check_every;
        if !(g.contact && due) {
            return Ok(Contact::Checked(ContactReport::default(), false));
        }
        let (window, until_clear) = (2 * g.check_every.max(1), g.guarded_until_clear);
        match self.contact_phase(pre, x, old, remeshed, times)? {
            Some((report, reverted)) => {
                // A guarded step that still made contact starts the contact-free stretch anew.
                let renew = until_clear && self.guarded_left > 0 && report.pairs > 0;
                self.guarded_left = match renew {
                    true => window,
                    false => self.guarded_left.saturating_sub(1),
                };
                self.save_checkpoint();
                Ok(Contact::Checked(report, reverted))
            }
            None => {
                let from = self.step;
                self.restore_checkpoint();
                self.guarded_left = window;
                Ok(Contact::RolledBack { from })
            }
        }
    }

    /// The contact guard: if the moved (and remeshed) surface has intersecting faces and the
    /// surface before the step (`pre`) is at hand, go back to it, apply the move `x` there, put
    /// back the vertices of the intersecting faces ([`resolve_contacts`]) and remesh again —
    /// undoing that remesh if it intersects. Returns the guard's report and whether a remesh was
    /// undone, or `None` when there are intersections and no `pre` (the caller rolls back).
    fn contact_phase(
        &mut self,
        pre: Option<HalfedgeMesh>,
        x: &[DVec3],
        old: &[DVec3],
        remesh_due: bool,
        times: &mut PhaseTimes,
    ) -> Result<Option<(ContactReport, bool)>, EvolveError> {
        let t0 = now_ms();
        let pairs = count_self_intersections(self.mesh.positions(), &self.mesh.triangles());
        times.guard += now_ms() - t0;
        if pairs == 0 {
            return Ok(Some((
                ContactReport {
                    rounds: 1,
                    ..Default::default()
                },
                false,
            )));
        }
        let Some(pre) = pre else {
            return Ok(None);
        };
        let t0 = now_ms();
        self.mesh = pre;
        release_held(&mut self.mesh);
        self.mesh.positions_mut().copy_from_slice(x);
        let report = resolve_contacts(&mut self.mesh, old, &self.settings.tuning.guard);
        times.guard += now_ms() - t0;
        let mut reverted = false;
        if remesh_due {
            // Where the remesh makes faces intersect (two membranes pressed together across a
            // hole) it is done again around them, not undone everywhere: undone, the surface
            // would keep its coarse edges from step to step and never grow the vertices its
            // membranes need to be cut (see docs/decisions/0021-contact-guard.md).
            let before = self.mesh.clone();
            self.remesh_phase(times, None)?;
            reverted = !self.remesh_around_intersections(&before, times)?;
        }
        Ok(Some((report, reverted)))
    }
}
