//! After the final fit, *a second pass* for a point cloud or mesh that the first left partly
//! outside (`tuning.flow.cover_gaps`, `tuning.flow.second_pass_d2`). At a sparse cloud's usual d₀ (1.7 median
//! spacings) a tenth of a randomly sampled surface lies farther than d₀ from every point. A
//! closed surface's wrap only sags into those holes, but round the rim of an open single-layer
//! scan the two sides of the wrap can slip through them, meet inside the sheet and leave part
//! of it outside; on denser sheets, and on single-layer meshes, full-wrap's push where the
//! normal lies across the gradient (D₂) can drive the coarse early wrap's edge past the rim. A
//! d₀ that covers the gaps and D₂ = 0 keep the rim, but for every cloud the larger d₀ would also
//! change results that are right, so both are used only where the first pass left part of the
//! target outside: the evolution starts over once from its start surface, and the pass that
//! leaves fewer points outside is the result (see docs/decisions/0019-second-pass.md).
//!
//! D₂ = 0 does not push into concavities (the method's reason for full-wrap), so it can leave a
//! web far off the data. When a second pass that leaves fewer points outside ends more than
//! [`FAR_GROWTH`] times farther from the data than the first, a third pass halfway between the
//! two D₂ runs. The result is the pass that leaves no part outside and ends nearest the data,
//! else the one with the fewest outside; but a pass that leaves a part outside stays the result
//! over one that ends more than [`FAR_GROWTH`] times farther off the data than that part lies
//! out (see [`better`]).

use super::{Checkpoint, Evolver, PhaseTimes, StepReport};
use crate::flow::settings::WrapSettings;
use crate::flow::surgery::SurgeryEvent;
use crate::mesh::HalfedgeMesh;
use crate::metrics::certificate::{
    outside_distances, outside_miss, outside_samples, part_outside, OUTSIDE_TOLERANCE,
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
#[cfg_attr(target_arch = "wasm32", derive(tsify::Tsify))]
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
    /// The farthest vertex's distance to the target (field distance, target units) after the
    /// first and the second pass.
    pub far_before: f64,
    pub far_after: f64,
    /// How far out the part each left outside lies (target units: the distance beyond which at
    /// most [`crate::metrics::certificate::OUTSIDE_SHARE`] of the checked points lie outside;
    /// 0 when no part is outside).
    pub miss_before: f64,
    pub miss_after: f64,
    /// The genus after the first and the second pass (None: not a closed manifold, or the pass
    /// stopped).
    pub genus_before: Option<i64>,
    pub genus_after: Option<i64>,
    /// The third pass, when the second ended far off the data (see the module's doc).
    pub third: Option<ThirdPass>,
}

/// A third pass, with D₂ halfway between the first's and the second's.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
#[cfg_attr(target_arch = "wasm32", derive(tsify::Tsify))]
pub struct ThirdPass {
    pub d2: f64,
    /// Checked points outside, how far out they lie, and the farthest vertex's distance
    /// (target units).
    pub outside: usize,
    pub miss: f64,
    pub far: f64,
    pub genus: Option<i64>,
    /// Whether it is the result.
    pub kept: bool,
}

/// A second pass that leaves fewer points outside but ends more than this many times farther
/// from the data than the first (its farthest vertex) gets a third pass; and a pass that leaves a
/// part outside stays the result over one that ends this many times farther off the data than
/// it misses (see the module's doc).
pub const FAR_GROWTH: f64 = 2.0;

/// A finished pass, kept while the next runs.
struct Pass {
    mesh: HalfedgeMesh,
    d0: f64,
    d2: f64,
    steps: u32,
    surgery_events: Vec<SurgeryEvent>,
    outside: usize,
    /// How far out the part left outside lies ([`outside_miss`], target units; 0: none).
    miss: f64,
    /// Its genus (None when it is not a closed manifold).
    genus: Option<i64>,
    /// The farthest vertex's field distance (target units: its last step's `distance_max`).
    far: f64,
    /// Its last step's report (None for the first pass: the caller's).
    report: Option<StepReport>,
}

impl SecondPass {
    /// The second pass of a wrap of `target` whose d₀ is `d0` (stabilised frame, scale `phi`
    /// about `center`; `fits`: there is a final fit), with D₂ = `tuning.flow.second_pass_d2`; a
    /// sampling's with d₀ grown to its gap spacing (the oracle's `gap_spacing`) where that is
    /// larger, at most `tuning.flow.cover_gaps` times. `None` where the oracle says a second pass does
    /// not pay (a volume's iso-surface), with `tuning.flow.cover_gaps` = 1, and where it would repeat
    /// the first.
    /// Its start is set by [`Self::starting`].
    pub(super) fn new(
        target: &Target,
        settings: &WrapSettings,
        (d0, phi, center): (f64, f64, DVec3),
        fits: bool,
    ) -> Option<Box<Self>> {
        let grow = settings.tuning.flow.cover_gaps;
        let oracle = target.oracle();
        if !oracle.second_pass_pays() || grow <= 1.0 || !fits {
            return None;
        }
        let gap = oracle.gap_spacing().map_or(0.0, |g| phi * g);
        let second = d0.max(gap.min(grow * d0));
        // (The same d₀ and D₂ would only repeat the first pass: the obstacle preset on a mesh.)
        if second == d0 && settings.flow.d2 == settings.tuning.flow.second_pass_d2 {
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

    /// Checked points outside `mesh`, and how far out the part outside lies ([`outside_miss`],
    /// in the stabilised frame).
    fn outside(&self, mesh: &HalfedgeMesh) -> (usize, f64) {
        let d = outside_distances(
            mesh.positions(),
            &mesh.triangles(),
            &self.samples,
            self.tolerance,
        );
        (d.len(), outside_miss(&d, self.samples.len()))
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
    /// `progress`), and a third where the second ended far off the data (see the module's doc);
    /// returns the report of the last step of the pass that is the result (times: the first
    /// pass's last step and every later pass's steps; surgery: the result's events), or `last`
    /// when the first pass stays the result.
    pub(super) fn second_pass_if_outside(
        &mut self,
        last: StepReport,
        progress: &mut Progress,
    ) -> StepReport {
        let Some(pass) = self.second_pass.take().filter(|p| p.start.is_some()) else {
            return last;
        };
        let (outside, miss) = pass.outside(&self.mesh);
        if self.stop_reason.is_some() || !part_outside(outside, pass.samples.len()) {
            // (As after a fit with no second pass: see `fit_if_done`.)
            self.fit_target = None;
            return last;
        }
        let checked = pass.samples.len();
        let first = Pass {
            mesh: self.mesh.clone(),
            d0: self.d0,
            d2: self.settings.flow.d2,
            steps: self.step,
            surgery_events: std::mem::take(&mut self.surgery_events),
            outside,
            miss: miss / self.phi,
            genus: genus_of(&self.mesh),
            far: last.distance_max,
            report: None,
        };
        let mut times = last.times;
        let d2 = self.settings.tuning.flow.second_pass_d2;
        let second = self.run_pass(&pass, d2, progress, &mut times);
        // (A second pass that leaves fewer points outside but ends far off the data.)
        let far_off = second.as_ref().is_some_and(|s| {
            let fewer = !part_outside(s.outside, checked) || s.outside < first.outside;
            fewer && s.far > FAR_GROWTH * first.far
        });
        let third = match far_off {
            true => self.run_pass(&pass, 0.5 * (first.d2 + d2), progress, &mut times),
            false => None,
        };
        let second_kept = second.as_ref().is_some_and(|s| better(s, &first, checked));
        let third_kept = third.as_ref().is_some_and(|t| {
            let best = second.as_ref().filter(|_| second_kept).unwrap_or(&first);
            better(t, best, checked)
        });
        self.started_over = Some(StartedOver {
            outside_before: first.outside,
            outside_after: second.as_ref().map_or(checked, |s| s.outside),
            checked,
            iso_level_before: first.d0 / self.phi,
            iso_level_after: pass.d0 / self.phi,
            kept: second_kept && !third_kept,
            far_before: first.far,
            far_after: second.as_ref().map_or(f64::INFINITY, |s| s.far),
            miss_before: first.miss,
            miss_after: second.as_ref().map_or(f64::INFINITY, |s| s.miss),
            genus_before: first.genus,
            genus_after: second.as_ref().and_then(|s| s.genus),
            third: third.as_ref().map(|t| ThirdPass {
                d2: t.d2,
                outside: t.outside,
                miss: t.miss,
                far: t.far,
                genus: t.genus,
                kept: third_kept,
            }),
        });
        self.fit_target = None;
        let result = match (third, second) {
            (Some(t), _) if third_kept => t,
            (_, Some(s)) if second_kept => s,
            _ => first,
        };
        // The pass kept: its surface, d₀, D₂, step count and events.
        self.mesh = result.mesh;
        self.d0 = result.d0;
        self.settings.flow.d2 = result.d2;
        self.step = result.steps;
        self.stop_reason = None;
        self.done = true;
        self.refresh_distances();
        let mut r = match result.report {
            Some(mut r) => {
                r.surgery.clone_from(&result.surgery_events);
                r
            }
            None => last,
        };
        self.surgery_events = result.surgery_events;
        r.times = times;
        r
    }

    /// One more pass from the start with the second pass's d₀ and D₂ = `d2` (its steps reported
    /// to `progress`, their times added to `times`); None when it stopped early.
    fn run_pass(
        &mut self,
        pass: &SecondPass,
        d2: f64,
        progress: &mut Progress,
        times: &mut PhaseTimes,
    ) -> Option<Pass> {
        self.begin_again(pass, d2);
        let (mut events, mut report) = (Vec::new(), None);
        progress.report(SECOND_PASS_PHASE, 0.0);
        let limit = self.settings.stop.steps.max(1) as f64;
        while !self.done {
            match self.step_with_progress(progress) {
                Ok(r) => {
                    progress.report(SECOND_PASS_PHASE, r.step as f64 / limit);
                    add_times(times, &r.times);
                    events.extend(r.surgery.iter().cloned());
                    report = Some(r);
                }
                Err(_) => break,
            }
        }
        progress.report(SECOND_PASS_PHASE, 1.0);
        let report = report.filter(|_| self.stop_reason.is_none())?;
        let (outside, miss) = pass.outside(&self.mesh);
        Some(Pass {
            mesh: self.mesh.clone(),
            d0: self.d0,
            d2,
            steps: self.step,
            surgery_events: events,
            outside,
            miss: miss / self.phi,
            genus: genus_of(&self.mesh),
            far: report.distance_max,
            report: Some(report),
        })
    }

    /// Back to the state before the first step, with the second pass's d₀ and D₂ = `d2`.
    fn begin_again(&mut self, pass: &SecondPass, d2: f64) {
        self.d0 = pass.d0;
        self.settings.flow.d2 = d2;
        if let Some(start) = &pass.start {
            self.checkpoint = start.clone();
        }
        self.restore_checkpoint();
        // (A pass's surgery is its own: events switch the deflation on, see `forces`.)
        self.surgery_events.clear();
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

/// Whether pass `a` is a better result than `b` (of `checked` points): leaving no part of the
/// target outside unless it ends more than [`FAR_GROWTH`] times farther off the data than the
/// other misses it (its farthest vertex against the other's, or how far out the other's part
/// outside lies, whichever is larger), then nearer the data; or, where both leave a part
/// outside, fewer outside. A pass with fewer handles than `b` is never better: a later pass's
/// larger d₀ closes holes as narrow as itself, and the surgery's handles are checked ones. The
/// [`FAR_GROWTH`] margin keeps a first pass that leaves a rim's tips a little outside over a
/// later one that covers them but ends far off the data.
fn better(a: &Pass, b: &Pass, checked: usize) -> bool {
    let misses = |p: &Pass| p.far.max(p.miss);
    if let (Some(ga), Some(gb)) = (a.genus, b.genus) {
        if ga < gb {
            return false;
        }
    }
    match (
        part_outside(a.outside, checked),
        part_outside(b.outside, checked),
    ) {
        (false, true) => a.far <= FAR_GROWTH * misses(b),
        (true, false) => FAR_GROWTH * misses(a) < b.far,
        (false, false) => a.far < b.far,
        (true, true) => a.outside < b.outside,
    }
}

/// The genus of a closed manifold `mesh`, None otherwise.
fn genus_of(mesh: &HalfedgeMesh) -> Option<i64> {
    mesh.validate().ok().map(|r| r.genus)
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::icosphere::icosphere;

    fn pass(outside: usize, miss: f64, far: f64) -> Pass {
        Pass {
            mesh: icosphere(0, 1.0, DVec3::ZERO).unwrap(),
            d0: 0.01,
            d2: 1.0,
            steps: 100,
            surgery_events: Vec::new(),
            outside,
            miss,
            genus: Some(0),
            far,
            report: None,
        }
    }

    #[test]
    fn a_pass_with_nothing_outside_wins_unless_it_ends_much_farther_off() {
        // Of 10 000 checked points, more than 50 outside are a part.
        let checked = 10_000;
        // A first pass that leaves a rim's tips 0.049 out, a later one that covers them but
        // ends 0.113 off the data.
        let first = pass(188, 0.049, 0.029);
        assert!(!better(&pass(0, 0.0, 0.113), &first, checked));
        assert!(better(&first, &pass(0, 0.0, 0.113), checked));
        // A later pass that ends as near the data as the first.
        let band = pass(174, 0.055, 0.037);
        assert!(better(&pass(0, 0.0, 0.038), &band, checked));
        assert!(!better(&band, &pass(0, 0.0, 0.038), checked));
        // Within twice the miss, nothing outside wins; both clean or both outside: as before.
        assert!(better(&pass(0, 0.0, 0.09), &first, checked));
        assert!(better(&pass(0, 0.0, 0.02), &pass(0, 0.0, 0.03), checked));
        assert!(better(
            &pass(100, 0.05, 0.9),
            &pass(200, 0.01, 0.01),
            checked
        ));
        // A pass with fewer handles never wins (genus 3 with a rim outside against genus 2
        // with nothing outside); with more, as above.
        let plate = Pass {
            genus: Some(3),
            ..pass(351, 0.027, 0.018)
        };
        let closed_a_hole = Pass {
            genus: Some(2),
            ..pass(2, 0.0, 0.028)
        };
        assert!(!better(&closed_a_hole, &plate, checked));
        let opened_one = Pass {
            genus: Some(4),
            ..pass(2, 0.0, 0.028)
        };
        assert!(better(&opened_one, &plate, checked));
    }
}
