//! Phase 2 of a step, *assemble and solve*: the semi-implicit system (I − τ·ε·Δ)x = x⁰ +
//! τ(η·N + tangential) for x, y and z at once (method spec §6.1–6.4). A failed solve is retried
//! with τ halved and non-negative weights; after `flow.max_retries` the surface goes back to the
//! last certified state and the evolution stops.

use super::forces::Forces;
use super::{EvolveError, Evolver, PhaseTimes};
use crate::clock::now_ms;
use crate::solve::{solve_xyz_scaled, SolveReport};
use glam::DVec3;

/// The new positions and how the solve went.
pub(super) struct Solved {
    pub x: Vec<DVec3>,
    pub report: SolveReport,
    /// τ halvings this step needed.
    pub retries: u32,
}

impl Evolver {
    /// Solves for the new positions from `old` (the positions the forces were computed at).
    pub(super) fn solve(
        &mut self,
        f: &Forces,
        old: &[DVec3],
        times: &mut PhaseTimes,
    ) -> Result<Solved, EvolveError> {
        let n = old.len();
        let lap = &f.terms.laplacian;
        let normals = &f.terms.normals;
        let (solver, max_retries) = (self.settings.solver.clone(), self.settings.flow.max_retries);
        let mut retries = 0;
        loop {
            let t0 = now_ms();
            let tau = self.tau;
            // After a failed solve, retry with a smaller τ and non-negative weights.
            let system = lap.implicit_system(&self.mesh, tau, Some(&f.eps), retries > 0);
            let rhs: Vec<DVec3> = (0..n)
                .map(|i| old[i] + tau * (f.eta[i] * normals[i] + f.tangential[i]))
                .collect();
            let mut x = rhs.clone();
            let t1 = now_ms();
            times.assembly += t1 - t0;
            let result = system.and_then(|a| solve_xyz_scaled(&a, &rhs, &mut x, &solver));
            times.solve += now_ms() - t1;
            match result {
                Ok(report) => return Ok(Solved { x, report, retries }),
                Err(e) if retries >= max_retries => {
                    let err = EvolveError::Diverged {
                        step: self.step + 1,
                        retries,
                        tau,
                        cause: e.to_string(),
                    };
                    self.restore_checkpoint();
                    self.stop(&err);
                    return Err(err);
                }
                Err(_) => {
                    retries += 1;
                    self.tau *= 0.5;
                }
            }
        }
    }
}
