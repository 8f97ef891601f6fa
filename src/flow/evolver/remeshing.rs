//! Phase 4 of a step, *remesh*: adaptive remeshing with the current edge sizes when the trigger
//! says so (`remesh.trigger`), followed by the divergence guard.

use super::{EvolveError, Evolver, PhaseTimes};
use crate::clock::now_ms;
use crate::flow::guard::{check_divergence, freeze_where_intersecting, REMESH_TRIES};
use crate::flow::guarded::{guarded_edit, GuardPolicy};
use crate::flow::settings::RemeshTrigger;
use crate::mesh::HalfedgeMesh;
use crate::remesh::adaptive::{
    remesh, remesh_with_features, RemeshReport, RemeshSettings, CURVED_SPLITS_LAYER,
};
use crate::remesh::features::{FeatureDetector, Features};

/// Distance beyond the offset level d₀, in grid cells, up to which remesh splits follow the
/// surface's curvature (see [`RemeshSettings::curved_splits`]). The field is already in the
/// stabilised frame, so its cell is not scaled by φ again (that would make this reach depend
/// on the input's units). Farther reaches lose handles and merge parts lying close (see
/// docs/decisions/0010-curved-splits.md).
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
        let report = self.remesh_phase(times, None)?;
        if let Err(reason) = check_divergence(&self.mesh, &self.limits) {
            self.step -= 1;
            return Err(self.roll_back(reason));
        }
        Ok(Some(report))
    }

    /// Adaptive remeshing with the current sizes; `frozen` vertices (indexed like the mesh) are
    /// left as they are, with their edges (ignored with a feature detector on: its features
    /// would be lost).
    pub(super) fn remesh_phase(
        &mut self,
        times: &mut PhaseTimes,
        frozen: Option<&[bool]>,
    ) -> Result<RemeshReport, EvolveError> {
        let t0 = now_ms();
        let s = &self.settings;
        let rs = RemeshSettings {
            iterations: s.remesh.iterations,
            smoothing_iterations: s.remesh.smoothing_iterations,
            features: s.tuning.remesh.features.clone(),
            curved_splits: s.tuning.remesh.curved_splits,
            ..RemeshSettings::with_sizes(self.sizes)
        };
        self.sizes_changed = false;
        // Curved splits only near the target (within CURVED_CELLS of the offset level).
        // (The distances are this step's, sampled before the move; none if the count changed.)
        let near = self.d0 + CURVED_CELLS * self.field.cell_size();
        let fresh = self.distances.len() == self.mesh.n_vertices();
        self.mesh.set_vertex_scalar_layer(CURVED_SPLITS_LAYER, 0.0);
        if let (true, Some(layer)) = (fresh, self.mesh.vertex_scalars_mut(CURVED_SPLITS_LAYER)) {
            for (l, &d) in layer.iter_mut().zip(&self.distances) {
                *l = if d <= near { 1.0 } else { 0.0 };
            }
        }
        let report = match frozen {
            Some(f) if rs.features.detector == FeatureDetector::Off => {
                let mut features = Features::none(&self.mesh);
                features.frozen = f.to_vec();
                remesh_with_features(&mut self.mesh, &rs, &features)
            }
            _ => remesh(&mut self.mesh, &rs),
        };
        self.mesh.remove_vertex_scalar_layer(CURVED_SPLITS_LAYER);
        let report = report?;
        times.remesh += now_ms() - t0;
        Ok(report)
    }

    /// Remeshes (see [`Evolver::remesh_phase`]) the surface `before`, already remeshed into
    /// the current one, again where that made faces intersect: a [`guarded_edit`] of up to
    /// [`REMESH_TRIES`] more remeshes with those regions frozen. True when the surface is now
    /// free of intersections; false (with `before` restored) when that failed. The checks count
    /// as the guard's time, the remeshes as the remesh's.
    pub(super) fn remesh_around_intersections(
        &mut self,
        before: &HalfedgeMesh,
        times: &mut PhaseTimes,
    ) -> Result<bool, EvolveError> {
        let mut frozen = vec![false; before.n_vertices()];
        let policy = GuardPolicy {
            tries: REMESH_TRIES + 1,
            applied: true,
        };
        let outcome = guarded_edit(
            &mut (self, times),
            &mut frozen,
            policy,
            |(ev, times), frozen| {
                ev.mesh = before.clone();
                ev.remesh_phase(times, Some(frozen)).map(|_| true)
            },
            |(ev, times), frozen| {
                let t0 = now_ms();
                let verdict = freeze_where_intersecting(&ev.mesh, before, |p| p, frozen);
                times.guard += now_ms() - t0;
                verdict
            },
            |(ev, _)| ev.mesh = before.clone(),
        )?;
        Ok(outcome.clean)
    }

    fn quality_left_band(&self) -> bool {
        crate::remesh::trigger::needs_remesh(&self.mesh, self.settings.tuning.remesh.max_kappa)
    }

    fn needs_remesh(&self) -> bool {
        match self.settings.remesh.trigger {
            RemeshTrigger::Always => true,
            RemeshTrigger::QualityBand => self.sizes_changed || self.quality_left_band(),
            RemeshTrigger::Auto => {
                // The step number, not a counter: a rolled-back step replays the same decision.
                self.sizes_changed
                    || self.step % self.settings.tuning.remesh.every.max(1) == 0
                    || self.quality_left_band()
            }
        }
    }
}
