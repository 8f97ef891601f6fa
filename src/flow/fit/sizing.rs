//! The error sizing step of a fit pass on a mesh target: caps on the edge length where target
//! vertices are still missed ([`error_caps`]) and where creases are still bevelled
//! ([`crease_caps`]), kept in a vertex layer for the pass's remesh.
//!
//! The caps live in a vertex layer, so the edits carry them to later passes and the curvature
//! sizing does not coarsen a refined region again. The last pass sets no new caps: only a
//! next pass's moves would put the new vertices on the target.

use super::error_sizing::{crease_caps, error_caps, wrap_faces, BEVEL_TOL_DEG};
use super::{Fit, CAP_LAYER, NO_CAP};

/// Caps, and the target samples that missed (when the error caps found any).
type NewCaps = (Option<Vec<f64>>, Option<Vec<u32>>);

impl Fit<'_, '_> {
    /// Pass `pass`'s caps on the edge length for its remesh (the layer's, lowered where the
    /// target is still missed or bevelled); None without the error sizing. Decides whether an
    /// extra pass has something to do (`missed`, `stalled`); `reached` is what the pass's reach
    /// moved.
    pub(super) fn size_by_error(&mut self, pass: u32, reached: usize) -> Option<Vec<f64>> {
        let samples = self.refine?;
        self.mesh.garbage_collect();
        let floor = self.opt.min_edge;
        let last = pass + 1 >= self.most;
        let wrap = (!last).then(|| wrap_faces(self.mesh));
        let (check, tol) = (&self.state.check, self.opt.refine_tol);
        let errors = wrap
            .as_ref()
            .and_then(|w| error_caps(self.mesh, w, samples, check, tol, floor));
        let bevels = match (self.creases, &wrap) {
            (Some(creases), Some(w)) => {
                let tol = BEVEL_TOL_DEG.to_radians();
                crease_caps(self.mesh, w, creases, self.crease_offset, tol, floor)
            }
            _ => None,
        };
        let left = (
            errors.as_ref().map_or(0, |(_, m)| m.len()),
            bevels.as_deref().map_or(0, capped),
        );
        let before = self.state.left_before;
        self.state.stalled =
            pass >= self.opt.passes && reached == 0 && left.0 >= before.0 && left.1 >= before.1;
        self.state.left_before = left;
        let (new, misses) = merged(errors, bevels);
        let budget = self.opt.budget;
        let new = new.filter(|caps| self.mesh.n_vertices() + 4 * capped(caps) <= budget);
        self.state.missed = new.is_some();
        Some(self.lower_caps(new, misses))
    }

    /// The cap layer (made where missing) lowered to `new`, and the samples to check next set
    /// to the `misses` that came with it; returns the layer.
    fn lower_caps(&mut self, new: Option<Vec<f64>>, misses: Option<Vec<u32>>) -> Vec<f64> {
        if self.mesh.vertex_scalars(CAP_LAYER).is_none() {
            self.mesh.set_vertex_scalar_layer(CAP_LAYER, NO_CAP);
        }
        let layer = self.mesh.vertex_scalars_mut(CAP_LAYER).unwrap_or_default();
        if let Some(new) = new {
            for (l, c) in layer.iter_mut().zip(new) {
                *l = l.min(c);
            }
            if let Some(misses) = misses {
                self.state.check = misses;
            }
        }
        layer.to_vec()
    }
}

/// How many vertices `caps` caps.
fn capped(caps: &[f64]) -> usize {
    caps.iter().filter(|c| c.is_finite()).count()
}

/// The error caps (with their misses) and the bevel caps as one: the lower of the two.
fn merged(errors: Option<(Vec<f64>, Vec<u32>)>, bevels: Option<Vec<f64>>) -> NewCaps {
    match (errors, bevels) {
        (Some((mut e, m)), Some(b)) => {
            for (x, y) in e.iter_mut().zip(b) {
                *x = x.min(y);
            }
            (Some(e), Some(m))
        }
        (Some((e, m)), None) => (Some(e), Some(m)),
        (None, b) => (b, None),
    }
}
