//! Phase 1 of a step, *sample the field*: the surface terms (normals, cotangent Laplacian,
//! co-volumes, tangential sums in one pass over the faces) and, at every vertex, the controls
//! ε(δ) and η(δ, cos θ) of the sampled distance d and gradient (docs/method.md §4–§5).

use super::{Evolver, PhaseTimes};
use crate::clock::now_ms;
use crate::flow::controls::Controls;
use crate::flow::guard::held_mask;
use crate::flow::regrow::{outward_to_offset, Regrow};
use crate::flow::surface_terms::SurfaceTerms;
use crate::flow::surgery::SurgeryKind;
use glam::DVec3;

/// What the solve needs from the current surface.
pub(super) struct Forces {
    /// Normals, Laplacian and co-volumes of the surface before the step.
    pub terms: SurfaceTerms,
    /// Curvature weight ε per vertex (1 everywhere without a target).
    pub eps: Vec<f64>,
    /// Normal speed η per vertex (0 where held by the contact guard).
    pub eta: Vec<f64>,
    /// Tangential redistribution per vertex (weight ω·ε).
    pub tangential: Vec<DVec3>,
    /// Vertices the contact guard holds this step.
    pub held: usize,
}

impl Evolver {
    /// ε, η and the tangential term at every vertex.
    pub(super) fn forces(&self, times: &mut PhaseTimes) -> Forces {
        let t0 = now_ms();
        let n = self.mesh.n_vertices();
        let s = &self.settings;
        let controls = Controls {
            c1: s.flow.c1,
            c2: s.flow.c2,
            d1: self.d1,
            d2: s.flow.d2,
            mcf_positive_support: s.flow.mcf_positive_support,
            advection_positive_support: s.flow.advection_positive_support,
        };
        let terms = SurfaceTerms::new(&self.mesh);
        let normals = &terms.normals;
        let held = held_mask(&self.mesh);
        let (mut eps, mut eta) = (vec![1.0; n], vec![0.0; n]);
        let cell = self.field.cell_size();
        let regrow = Regrow {
            d0: self.d0,
            min_depth: s.tuning.flow.regrow_depth * self.d0,
            reach: s.tuning.flow.regrow_cells * cell,
            spacing: 0.5 * cell,
        };
        let regrows = s.tuning.flow.regrow_depth > 0.0 && s.tuning.flow.regrow_edges > 0.0;
        // Beyond this distance, a surface with the data in front of it deflates (see
        // `FlowSettings::deflate_far`), once the surgery has cut: before that the surface is
        // the shrinking start, and a part of it far from the data that faces the data has
        // slipped through a gap in a sparse wall, where deflating would drive it on into the
        // inside.
        let operated = self
            .surgery_events
            .iter()
            .any(|e| e.kind != SurgeryKind::Drop);
        let deflate_beyond = match s.tuning.flow.deflate_far {
            k if k > 0.0 && operated => k * self.empty_distance,
            _ => f64::INFINITY,
        };
        if s.flow.use_target {
            for i in 0..n {
                let delta = self.distances[i] - self.d0;
                eps[i] = controls.epsilon(delta);
                let advects = eps[i] != 0.0 || !s.flow.advection_positive_support || delta >= 0.0;
                if advects && !held[i] {
                    let cos = self.gradients[i].dot(normals[i]);
                    let cos = match self.distances[i] > deflate_beyond {
                        true => -cos.abs(),
                        false => cos,
                    };
                    eta[i] = controls.eta(delta, cos);
                }
                // A held-still vertex on a chord through a thin part moves out (its row is the
                // identity, so this η is its whole move).
                if regrows && eps[i] == 0.0 && !held[i] && delta < 0.0 {
                    let p = self.mesh.position(i as u32);
                    let sample = |q| self.field.sample(q);
                    let d = self.distances[i];
                    if let Some(along) = outward_to_offset(sample, p, d, normals[i], &regrow) {
                        let most =
                            s.tuning.flow.regrow_edges * self.mesh.mean_edge_length(i as u32);
                        eta[i] = along.min(most) / self.tau;
                    }
                }
            }
        }
        let tangential: Vec<DVec3> = (0..n)
            .map(|v| terms.tangential(v, s.flow.tangential_weight * eps[v]))
            .collect();
        times.normals = now_ms() - t0;
        Forces {
            terms,
            eps,
            eta,
            tangential,
            held: held.iter().filter(|&&h| h).count(),
        }
    }
}
