//! After the final fit, *a second pass* for a point cloud or mesh that the first left partly
//! outside (`flow.cover_gaps`, `flow.second_pass_d2`). At a sparse cloud's usual d₀ (1.7 median
//! spacings) a tenth of a randomly sampled surface lies farther than d₀ from every point. A
//! closed surface's wrap only sags into those holes, but round the rim of an open single-layer
//! scan the two sides of the wrap slipped through them, met inside the sheet and left a fifth of
//! it outside; on denser sheets, and on single-layer meshes, full-wrap's push where the normal
//! lies across the gradient (D₂) drove the coarse early wrap's edge past the rim. A d₀ that
//! covers the gaps and D₂ = 0 keep the rim; used for every cloud the larger d₀ also changed
//! results that were right (genus sweep: one handle lost, a 3 000-point plate 23 s instead of
//! 1 s), so both are used only where the first pass left part of the target outside: the
//! evolution starts over once from its start surface, and the pass that leaves fewer points
//! outside is the result.

use super::{Checkpoint, Evolver, PhaseTimes, StepReport};
use crate::flow::settings::WrapSettings;
use crate::flow::surgery::SurgeryEvent;
use crate::mesh::HalfedgeMesh;
use crate::metrics::certificate::{
    outside_samples, part_outside, points_outside, OUTSIDE_TOLERANCE,
};
use crate::progress::Progress;
use crate::target::Target;
use glam::DVec3;
use serde::Serialize;

/// The progress phase of the second pass.
pub const SECOND_PASS_PHASE: &str = "second pass (part outside)";

/// What a second pass needs: its d₀, the start to go back to, and the points to check.
pub(super) struct SecondPass {
    /// d₀ of the second pass (stabilised frame).
    d0: f64,
    /// The state before the first step.
    start: Option<Checkpoint>,
    /// Target points checked for lying outside (stabilised frame), and how far out counts.
    samples: Vec<DVec3>,
    tolerance: f64,
}

/// Why and how the evolution started over.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct StartedOver {
    /// Checked points the first pass left outside (see [`crate::metrics::certificate`]).
    pub outside_before: usize,
    /// … and the second pass.
    pub outside_after: usize,
    pub checked: usize,
    /// d₀ of the first and the second pass, in the target's units.
    pub iso_level_before: f64,
    pub iso_level_after: f64,
    /// Whether the second pass is the result (it left fewer points outside).
    pub kept: bool,
}

/// The first pass, kept while the second runs.
struct FirstPass {
    mesh: HalfedgeMesh,
    d0: f64,
    d2: f64,
    steps: u32,
    surgery_events: Vec<SurgeryEvent>,
    outside: usize,
}

impl SecondPass {
    /// The second pass of a wrap of `target` whose d₀ is `d0` (stabilised frame, scale `phi`
    /// about `center`; `fits`: there is a final fit), with D₂ = `flow.second_pass_d2`; a cloud's
    /// with d₀ grown to its gap spacing ([`crate::geometry::spatial::spacing::gap_spacing`])
    /// where that is larger, at most `flow.cover_gaps` times. `None` for a volume's iso-surface
    /// (a second pass of a 640³ volume would take another minute), with `flow.cover_gaps` = 1,
    /// and where it would repeat the first.
    /// Its start is set by [`Self::starting`].
    pub(super) fn new(
        target: &Target,
        settings: &WrapSettings,
        (d0, phi, center): (f64, f64, DVec3),
        fits: bool,
    ) -> Option<Box<Self>> {
        let grow = settings.flow.cover_gaps;
        if target.sampled || grow <= 1.0 || !fits {
            return None;
        }
        let gap = match target.triangles.is_empty() {
            true => phi * crate::geometry::spatial::spacing::gap_spacing(&target.points),
            false => 0.0, // (A mesh's field has no gaps.)
        };
        let second = d0.max(gap.min(grow * d0));
        // (The same d₀ and D₂ would only repeat the first pass: the obstacle preset on a mesh.)
        if second == d0 && settings.flow.d2 == settings.flow.second_pass_d2 {
            return None;
        }
        Some(Box::new(SecondPass {
            d0: second,
            start: None,
            samples: outside_samples(target)
                .into_iter()
                .map(|p| (p - center) * phi)
                .collect(),
            tolerance: OUTSIDE_TOLERANCE * target.bbox.diagonal() * phi,
        }))
    }

    /// Sets the state to begin again from (the evolver's before its first step).
    pub(super) fn starting(&mut self, start: Checkpoint) {
        self.start = Some(start);
    }

    /// Checked points outside `mesh`.
    fn outside(&self, mesh: &HalfedgeMesh) -> usize {
        points_outside(
            mesh.positions(),
            &mesh.triangles(),
            &self.samples,
            self.tolerance,
        )
    }
}

impl Evolver {
    /// Whether the fit's view of the target is still needed after the final fit: a second pass
    /// may follow.
    pub(super) fn second_pass_may_follow(&self) -> bool {
        self.second_pass.is_some()
    }

    /// Called with the report of a step that ended the evolution: when part of the target lies
    /// outside and a second pass is possible, runs it from the start (its steps reported to
    /// `progress`) and returns the report of its last step (times: both passes' last steps and
    /// every step of the second; surgery: the second pass's events), or `last` when the first
    /// pass stays the result.
    pub(super) fn second_pass_if_outside(
        &mut self,
        last: StepReport,
        progress: &mut Progress,
    ) -> StepReport {
        let Some(pass) = self.second_pass.take().filter(|p| p.start.is_some()) else {
            return last;
        };
        let outside = pass.outside(&self.mesh);
        if self.stop_reason.is_some() || !part_outside(outside, pass.samples.len()) {
            self.fit_target = None; // (as after a fit with no second pass: see `fit_if_done`)
            return last;
        }
        let first = FirstPass {
            mesh: self.mesh.clone(),
            d0: self.d0,
            d2: self.settings.flow.d2,
            steps: self.step,
            surgery_events: std::mem::take(&mut self.surgery_events),
            outside,
        };
        self.begin_again(&pass);
        let (mut times, mut events) = (last.times, Vec::new());
        let mut report = None;
        progress.report(SECOND_PASS_PHASE, 0.0);
        let limit = self.settings.stop.steps.max(1) as f64;
        while !self.done {
            match self.step_with_progress(progress) {
                Ok(r) => {
                    progress.report(SECOND_PASS_PHASE, r.step as f64 / limit);
                    add_times(&mut times, &r.times);
                    events.extend(r.surgery.iter().cloned());
                    report = Some(r);
                }
                Err(_) => break,
            }
        }
        progress.report(SECOND_PASS_PHASE, 1.0);
        let after = match (&self.stop_reason, &report) {
            (None, Some(_)) => pass.outside(&self.mesh),
            _ => usize::MAX,
        };
        let kept = after < first.outside;
        self.started_over = Some(StartedOver {
            outside_before: first.outside,
            outside_after: after.min(pass.samples.len()),
            checked: pass.samples.len(),
            iso_level_before: first.d0 / self.phi,
            iso_level_after: pass.d0 / self.phi,
            kept,
        });
        self.fit_target = None;
        match (kept, report) {
            (true, Some(mut r)) => {
                r.times = times;
                r.surgery = events;
                r
            }
            _ => {
                // The first pass stays: its surface, d₀, D₂, step count and events.
                self.mesh = first.mesh;
                self.d0 = first.d0;
                self.settings.flow.d2 = first.d2;
                self.step = first.steps;
                self.surgery_events = first.surgery_events;
                self.stop_reason = None;
                self.done = true;
                self.refresh_distances();
                let mut r = last;
                r.times = times;
                r
            }
        }
    }

    /// Back to the state before the first step, with the second pass's d₀ and D₂.
    fn begin_again(&mut self, pass: &SecondPass) {
        self.d0 = pass.d0;
        self.settings.flow.d2 = self.settings.flow.second_pass_d2;
        if let Some(start) = &pass.start {
            self.checkpoint = start.clone();
        }
        self.restore_checkpoint();
        self.guarded_left = 0;
        self.tunnels_opened.clear();
        self.surgery_paired = 0;
        self.surgery_pending = false;
        self.done = self.settings.stop.steps == 0;
    }

    /// Why and how the evolution started over (see [`StartedOver`]), when it did.
    pub fn started_over(&self) -> Option<StartedOver> {
        self.started_over
    }
}

/// `sum += add`, phase by phase (the fit's parts are the last fit's).
fn add_times(sum: &mut PhaseTimes, add: &PhaseTimes) {
    sum.normals += add.normals;
    sum.assembly += add.assembly;
    sum.solve += add.solve;
    sum.remesh += add.remesh;
    sum.guard += add.guard;
    sum.fit += add.fit;
    sum.fit_parts = add.fit_parts;
    sum.surgery += add.surgery;
    sum.total += add.total;
}
