//! Phase 6 of a step, *schedule*: at the steps listed in `flow.schedule`, edge sizes shrink by
//! λ_dec, τ by λ_dec² and D1 grows by 1/λ_dec (docs/method.md §6.6), taking effect next step.

use super::Evolver;
use crate::remesh::sizing::decayed;

impl Evolver {
    /// Applies the schedule after step `self.step`.
    pub(super) fn schedule(&mut self) {
        if self.settings.flow.schedule.contains(&self.step) {
            let decay = self.settings.flow.decay;
            self.sizes = decayed(self.sizes, decay);
            self.sizes_changed = true;
            self.tau *= decay * decay;
            self.d1 /= decay;
        }
    }

    /// Whether the step just taken ends the evolution: the step limit, or — once the schedule is
    /// over — the stopping rule on the settled fraction. The schedule is step-indexed, so this is
    /// known before the contact guard (a roll-back simply redoes the step); sizes decayed at
    /// step t take effect in step t + 1, so the rule stops only after that step.
    pub(super) fn ends(&self, settled_fraction: f64) -> bool {
        let s = &self.settings;
        let schedule_over = s.flow.schedule.iter().all(|&t| t < self.step);
        self.step >= s.stop.steps || (schedule_over && settled_fraction >= s.stop.fraction)
    }
}
