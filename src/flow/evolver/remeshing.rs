//! Phase 4 of a step, *remesh*: adaptive remeshing with the current edge sizes when the trigger
//! says so (`remesh.trigger`), followed by the divergence guard.

use super::{EvolveError, Evolver, PhaseTimes};
use crate::clock::now_ms;
use crate::flow::guard::check_divergence;
use crate::flow::settings::RemeshTrigger;
use crate::remesh::adaptive::{remesh, RemeshReport, RemeshSettings, CURVED_SPLITS_LAYER};

/// Distance beyond the offset level d₀, in grid cells, up to which remesh splits follow the
/// surface's curvature (see [`RemeshSettings::curved_splits`]).
const CURVED_CELLS: f64 = 2.0;

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
            curved_splits: s.remesh.curved_splits,
            ..RemeshSettings::with_sizes(self.sizes)
        };
        self.sizes_changed = false;
        // Curved splits only near the target (within CURVED_CELLS of the offset level).
        // (The distances are this step's, sampled before the move; none if the count changed.)
        let near = self.d0 + CURVED_CELLS * self.field.cell_size() * self.phi;
        let fresh = self.distances.len() == self.mesh.n_vertices();
        self.mesh.set_vertex_scalar_layer(CURVED_SPLITS_LAYER, 0.0);
        if let (true, Some(layer)) = (fresh, self.mesh.vertex_scalars_mut(CURVED_SPLITS_LAYER)) {
            for (l, &d) in layer.iter_mut().zip(&self.distances) {
                *l = if d <= near { 1.0 } else { 0.0 };
            }
        }
        let report = remesh(&mut self.mesh, &rs);
        self.mesh.remove_vertex_scalar_layer(CURVED_SPLITS_LAYER);
        let report = report?;
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
