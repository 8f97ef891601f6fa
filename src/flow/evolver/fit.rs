//! Phase 7 of a step, *final fit* (last step only): the settled surface, at the offset level set
//! d = d₀, moves onto the target along its normals (plane fits to the cloud or closest points on
//! the mesh, [`crate::flow::snap`]), each pass through the contact guard.

use super::{round_as_written, Evolver, PhaseTimes};
use crate::clock::now_ms;
use crate::progress::Progress;

/// The progress phase of the final fit.
pub const FIT_PHASE: &str = "final fit";
use crate::flow::crease_fit::snap_to_creases;
use crate::flow::guard::resolve_contacts;
use crate::flow::snap::{snap_to_target, SnapParams};
use crate::geometry::creases::Creases;
use crate::geometry::operators::normals::angle_weighted_normals;
use crate::mesh::HalfedgeMesh;
use crate::metrics::intersections::{count_self_intersections, self_intersecting_pairs};
use crate::remesh::adaptive::{remesh, remesh_with_features, RemeshSettings};
use crate::remesh::features::Features;

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
        let fitted = self.final_fit(progress);
        times.fit = now_ms() - t0;
        fitted
    }

    /// Moves the settled surface onto the target (see [`crate::flow::snap`]); returns vertices moved.
    /// Each pass's moves go through the contact guard, and a remesh that would leave
    /// intersecting faces is undone.
    fn final_fit(&mut self, progress: &mut Progress) -> Option<usize> {
        let target = self.fit_target.as_ref()?;
        let c = self.field.cell_size();
        let params = SnapParams {
            radius: self.settings.fit.radius_cells * c,
            max_move: self.settings.fit.max_move_cells * c,
            min_points: 6,
            max_points: self.settings.fit.max_points,
        };
        // The fit must never make things worse: keep the settled surface if it breaks validity.
        let backup = self.mesh.clone();
        let mut moved = 0;
        let rs = RemeshSettings {
            iterations: 1,
            use_projection: true,
            smoothing_iterations: self.settings.remesh.smoothing_iterations,
            features: self.settings.remesh.features.clone(),
            ..RemeshSettings::with_sizes(self.sizes)
        };
        let (contact, remeshing) = (self.settings.guard.contact, self.settings.remesh.enabled);
        let passes = self.settings.fit.passes.max(1) as f64;
        // Each pass: moves (half of it), remesh, check.
        let mut at =
            |pass: u32, part: f64| progress.report(FIT_PHASE, (pass as f64 + part) / passes);
        let mut creases_placed = false;
        for pass in 0..self.settings.fit.passes {
            at(pass, 0.0);
            // The surface here is certified; keep it to redo the pass with the guard if needed.
            let clean = contact.then(|| self.mesh.clone());
            let start_of_pass = self.creases.is_some().then(|| self.mesh.clone());
            let normals = angle_weighted_normals(&self.mesh);
            moved = snap_to_target(&mut self.mesh, &normals, target, &params, &mut |f| {
                at(pass, 0.5 * f)
            });
            // Sharp creases: vertices onto them, edges along them, kept by the remesh.
            let features = match &self.creases {
                None => None,
                Some(c) => match snap_creases_checked(&mut self.mesh, c, params.max_move) {
                    Some(f) => Some(f),
                    // An earlier pass placed the creases: keep its surface rather than round
                    // them off again.
                    None if creases_placed => {
                        if let Some(m) = start_of_pass {
                            self.mesh = m;
                        }
                        break;
                    }
                    None => None,
                },
            };
            // The crease snap left this surface intersection-free: if the remesh breaks that,
            // keep the surface without the remesh rather than lose the creases.
            let snapped = (features.is_some() && remeshing).then(|| self.mesh.clone());
            // Even out the triangles the moves distorted, staying on the fitted surface.
            if remeshing {
                let _ = match &features {
                    Some(f) => remesh_with_features(&mut self.mesh, &rs, f),
                    None => remesh(&mut self.mesh, &rs),
                };
            }
            round_as_written(&mut self.mesh, self.phi, self.center);
            at(pass, 0.75);
            let Some(clean) = clean else { continue };
            let intersects =
                |m: &HalfedgeMesh| count_self_intersections(m.positions(), &m.triangles()) > 0;
            if !intersects(&self.mesh) {
                creases_placed |= features.is_some();
                continue;
            }
            if let Some(mut m) = snapped {
                round_as_written(&mut m, self.phi, self.center);
                if !intersects(&m) {
                    self.mesh = m;
                    creases_placed = true;
                    continue;
                }
            }
            // An earlier pass placed the creases and passed this check: keep its surface.
            if let (true, Some(m)) = (creases_placed, start_of_pass) {
                self.mesh = m;
                break;
            }
            // Redo the pass: the same moves, then put back those that make faces intersect,
            // then a remesh that is undone if it intersects.
            let before = clean.positions().to_vec();
            self.mesh = clean;
            // (Silent: the pass's progress has already gone past the moves.)
            moved = snap_to_target(&mut self.mesh, &normals, target, &params, &mut |_| {});
            resolve_contacts(&mut self.mesh, &before, &self.settings.guard);
            round_as_written(&mut self.mesh, self.phi, self.center);
            if remeshing {
                let unremeshed = self.mesh.clone();
                let _ = remesh(&mut self.mesh, &rs);
                round_as_written(&mut self.mesh, self.phi, self.center);
                if count_self_intersections(self.mesh.positions(), &self.mesh.triangles()) > 0 {
                    self.mesh = unremeshed;
                }
            }
        }
        at(self.settings.fit.passes, 0.0);
        if self.mesh.validate().is_err() {
            self.mesh = backup;
            return Some(0);
        }
        Some(moved)
    }
}

/// [`snap_to_creases`] kept intersection-free: a try that makes faces intersect is undone and
/// redone without the vertices of those faces and their neighbours, a few times at most; then
/// the mesh is as it came and the answer is None.
fn snap_creases_checked(
    mesh: &mut HalfedgeMesh,
    creases: &Creases,
    reach: f64,
) -> Option<Features> {
    mesh.garbage_collect();
    let before = mesh.clone();
    let mut banned = vec![false; before.n_vertices()];
    for _ in 0..CREASE_TRIES {
        let (features, _) = snap_to_creases(mesh, creases, reach, &banned);
        let tris = mesh.triangles();
        let pairs = self_intersecting_pairs(mesh.positions(), &tris);
        if pairs.is_empty() {
            return Some(features);
        }
        for (f, g) in pairs {
            for v in tris[f as usize].into_iter().chain(tris[g as usize]) {
                banned[v as usize] = true;
                for u in before.neighbors(v) {
                    banned[u as usize] = true;
                }
            }
        }
        *mesh = before.clone();
    }
    None
}

/// Tries of the crease snap per fit pass (see [`snap_creases_checked`]).
const CREASE_TRIES: usize = 3;
