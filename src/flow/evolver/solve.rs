//! Phase 2 of a step, *assemble and solve*: the semi-implicit system (I − τ·ε·Δ)x = x⁰ +
//! τ(η·N + tangential) for x, y and z at once (docs/method.md §6.1–6.4). A failed solve is retried
//! with non-negative weights, first at the same τ, then with τ halved each time; after
//! `tuning.flow.max_retries` the surface goes back to the last certified state and the evolution stops.

use super::forces::Forces;
use super::{EvolveError, Evolver, PhaseTimes};
use crate::clock::now_ms;
use crate::mesh::HalfedgeMesh;
use crate::solve::{solve_xyz_scaled, SolveReport};
use glam::DVec3;

/// The new positions and how the solve went.
pub(super) struct Solved {
    pub x: Vec<DVec3>,
    pub report: SolveReport,
    /// Retries this step needed (the first at the same τ, the later ones with τ halved).
    pub retries: u32,
    /// The τ of the solve that succeeded.
    pub tau: f64,
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
        let (solver, max_retries) = (
            self.settings.tuning.solver.clone(),
            self.settings.tuning.flow.max_retries,
        );
        let mut retries = 0;
        let reach = RUNAWAY_EDGES * longest_edge(&self.mesh);
        loop {
            let t0 = now_ms();
            // After a failed solve, retry with non-negative weights: negative cotangent weights
            // of a few near-degenerate triangles are what usually stalls BiCGStab, and halving
            // τ for that (for good: τ is not raised again) can freeze a whole evolution (see
            // docs/decisions/0020-solver-retries.md). τ is halved from the second retry on.
            if retries >= 2 {
                self.tau *= 0.5;
            }
            let tau = self.tau;
            let system = lap.implicit_system(&self.mesh, tau, Some(&f.eps), retries > 0);
            let rhs: Vec<DVec3> = (0..n)
                .map(|i| old[i] + tau * (f.eta[i] * normals[i] + f.tangential[i]))
                .collect();
            let mut x = rhs.clone();
            let t1 = now_ms();
            times.assembly += t1 - t0;
            let result = system
                .and_then(|a| solve_xyz_scaled(&a, &rhs, &mut x, &solver))
                .map_err(|e| e.to_string())
                .and_then(|report| match runaway(old, &rhs, &x, reach) {
                    Some(cause) => Err(cause),
                    None => Ok(report),
                });
            times.solve += now_ms() - t1;
            match result {
                Ok(report) => {
                    return Ok(Solved {
                        x,
                        report,
                        retries,
                        tau,
                    })
                }
                Err(e) if retries >= max_retries => {
                    let err = EvolveError::Diverged {
                        step: self.step + 1,
                        retries,
                        tau,
                        cause: e,
                    };
                    self.restore_checkpoint();
                    self.stop(&err);
                    return Err(err);
                }
                Err(_) => retries += 1,
            }
        }
    }
}

/// How many of the mesh's longest edge lengths a vertex may move beyond its own forces' push in
/// one step (see [`runaway`]).
const RUNAWAY_EDGES: f64 = 2.0;

/// The length of the longest edge of `mesh`.
fn longest_edge(mesh: &HalfedgeMesh) -> f64 {
    let p = mesh.positions();
    (0..mesh.n_edges() as u32)
        .map(|e| (p[mesh.to(2 * e) as usize] - p[mesh.from(2 * e) as usize]).length())
        .fold(0.0, f64::max)
}

/// A solution that moved a vertex farther than the forces' largest push plus `reach` says why,
/// else None. The smoothing alone only pulls a vertex towards its neighbours; with negative
/// cotangent weights around a collapsed vertex the system can be near-singular, and BiCGStab
/// then converges to a solution that throws that vertex across the scene. Such a solve is
/// failed and retried with non-negative weights, whose solutions keep the maximum principle
/// (see docs/decisions/0020-solver-retries.md).
fn runaway(old: &[DVec3], rhs: &[DVec3], x: &[DVec3], reach: f64) -> Option<String> {
    let push = old
        .iter()
        .zip(rhs)
        .map(|(o, r)| (*r - *o).length())
        .fold(0.0, f64::max);
    let (worst, moved) = old
        .iter()
        .zip(x)
        .map(|(o, x)| (*x - *o).length())
        .enumerate()
        .fold(
            (0, 0.0),
            |best, (i, d)| if d > best.1 { (i, d) } else { best },
        );
    (moved > push + reach).then(|| {
        format!(
            "the solution moved vertex {worst} by {moved:.3e}, more than the forces' push \
             {push:.3e} plus {reach:.3e} (a near-singular system)"
        )
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_solution_that_throws_a_vertex_away_is_a_runaway() {
        let old = vec![DVec3::ZERO, DVec3::X, DVec3::Y];
        // The forces push vertex 1 by 0.5; reach 0.1.
        let rhs = vec![DVec3::ZERO, 1.5 * DVec3::X, DVec3::Y];
        let calm = vec![DVec3::new(0.05, 0.0, 0.0), 1.4 * DVec3::X, DVec3::Y];
        assert_eq!(runaway(&old, &rhs, &calm, 0.1), None);
        let thrown = vec![DVec3::ZERO, DVec3::X, DVec3::new(0.0, 1.0, 0.7)];
        let why = runaway(&old, &rhs, &thrown, 0.1).unwrap();
        assert!(why.contains("vertex 2"), "{why}");
    }

    #[test]
    fn the_longest_edge_of_a_tetrahedron() {
        let p = vec![DVec3::ZERO, DVec3::X, DVec3::Y, 3.0 * DVec3::Z];
        let m =
            HalfedgeMesh::from_triangles(p, &[[0, 2, 1], [0, 1, 3], [1, 2, 3], [2, 0, 3]]).unwrap();
        assert_eq!(longest_edge(&m), 10f64.sqrt());
    }
}
