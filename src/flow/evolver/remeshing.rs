//! Phase 4 of a step, *remesh*: adaptive remeshing with the current edge sizes when the trigger
//! says so (`remesh.trigger`), followed by the divergence guard.

use super::{EvolveError, Evolver, PhaseTimes};
use crate::clock::now_ms;
use crate::flow::guard::check_divergence;
use crate::flow::settings::RemeshTrigger;
use crate::remesh::adaptive::{remesh, RemeshReport, RemeshSettings};

impl Evolver {
    /// Remeshes if due; `None` when it was not.
    pub(super) fn remesh_if_due(
        &mut self,
        times: &mut PhaseTimes,
    ) -> Result<Option<RemeshReport>, EvolveError> {
        let r = &self.settings.remesh;
        if !(r.enabled && self.step >= r.from_step && self.needs_remesh()) {
            return Ok(None);
        }
        let report = self.remesh_phase(times)?;
        if let Err(reason) = check_divergence(&self.mesh, &self.limits) {
            self.step -= 1;
            return Err(self.roll_back(reason));
        }
        Ok(Some(report))
    }

    /// Adaptive remeshing with the current sizes.
    pub(super) fn remesh_phase(
        &mut self,
        times: &mut PhaseTimes,
    ) -> Result<RemeshReport, EvolveError> {
        let t0 = now_ms();
        let s = &self.settings;
        let rs = RemeshSettings {
            iterations: s.remesh.iterations,
            smoothing_iterations: s.remesh.smoothing_iterations,
            features: s.remesh.features.clone(),
            ..RemeshSettings::with_sizes(self.sizes)
        };
        self.sizes_changed = false;
        let report = remesh(&mut self.mesh, &rs)?;
        times.remesh += now_ms() - t0;
        Ok(report)
    }

    fn quality_left_band(&self) -> bool {
        crate::remesh::trigger::needs_remesh(&self.mesh, self.settings.remesh.max_kappa)
    }

    fn needs_remesh(&self) -> bool {
        match self.settings.remesh.trigger {
            RemeshTrigger::Always => true,
            RemeshTrigger::QualityBand => self.sizes_changed || self.quality_left_band(),
            RemeshTrigger::Auto => {
                // The step number, not a counter: a rolled-back step replays the same decision.
                self.sizes_changed
                    || self.step % self.settings.remesh.every.max(1) == 0
                    || self.quality_left_band()
            }
        }
    }
}
