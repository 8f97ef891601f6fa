//! Phase 3 of a step, *move*: the solved positions replace the old ones, the divergence guard
//! checks the result (non-finite or escaped vertices, runaway area or vertex count: roll back to
//! the last certified state and stop), and the step counter advances.

use super::{EvolveError, Evolver, PhaseTimes};
use crate::clock::now_ms;
use crate::flow::guard::{check_divergence, release_held};
use crate::mesh::HalfedgeMesh;
use glam::DVec3;

/// What the move left for the later phases.
pub(super) struct Moved {
    /// The surface before the move, kept when the contact guard checks this step (it redoes the
    /// move from there, putting back the vertices of intersecting faces).
    pub pre: Option<HalfedgeMesh>,
    /// Fraction of vertices that moved less than the stop threshold.
    pub settled_fraction: f64,
}

impl Evolver {
    /// Moves the surface to `x` (from `old`) and checks it for divergence.
    pub(super) fn advance(
        &mut self,
        x: &[DVec3],
        old: &[DVec3],
        times: &mut PhaseTimes,
    ) -> Result<Moved, EvolveError> {
        let t0 = now_ms();
        let g = &self.settings.tuning.guard;
        let guarded = self.guarded_left > 0 || g.check_every <= 1;
        let pre = (guarded && g.contact).then(|| self.mesh.clone());
        release_held(&mut self.mesh);
        let mut settled = 0usize;
        for (i, q) in self.mesh.positions_mut().iter_mut().enumerate() {
            if (x[i] - old[i]).length() < self.settle_threshold {
                settled += 1;
            }
            *q = x[i];
        }
        if let Err(reason) = check_divergence(&self.mesh, &self.limits) {
            return Err(self.roll_back(reason));
        }
        times.guard += now_ms() - t0;
        self.step += 1;
        Ok(Moved {
            pre,
            settled_fraction: settled as f64 / old.len().max(1) as f64,
        })
    }
}
