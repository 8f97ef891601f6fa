//! Phase 7 of a step, *final fit* (last step only): the creases still being found are waited
//! for, then the settled surface is fitted onto the target ([`crate::flow::fit`]) and the
//! target's tree freed when no second pass may need it.

use super::{Evolver, PhaseTimes};
use crate::clock::now_ms;
use crate::flow::fit::{fit, FitOptions, FitTimes};
use crate::progress::Progress;

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
        let fitted = match &self.fit_target {
            Some(target) => {
                let options = FitOptions::new(
                    &self.settings,
                    self.sizes,
                    self.sizes_changed,
                    self.field.cell_size(),
                    self.field.signedness(),
                    self.phi,
                    self.center,
                );
                let creases = self.creases.as_ref();
                let report = fit(&mut self.mesh, target, creases, &options, progress);
                parts = report.times;
                Some(report.moved)
            }
            None => None,
        };
        // The fit was the last use of the target's tree (no step follows a done one): freed
        // before the certificate builds its own, so that the two are never held at once (on a
        // large volume in the browser, that is the difference between done and out of memory).
        if !self.second_pass_may_follow() {
            self.fit_target = None;
        }
        times.fit = now_ms() - t0;
        parts.other = times.fit - parts.named();
        times.fit_parts = parts;
        fitted
    }
}
