//! Phase 8 of a step, *surgery*: every `tuning.surgery.check_every` steps, membranes that meet far
//! from the data are cut and joined by a tube ([`crate::flow::surgery`]), the seam is remeshed,
//! and the operated surface becomes the certified state (roll-backs never undo a surgery).

use super::{Evolver, PhaseTimes};
use crate::clock::now_ms;
use crate::flow::guarded::{guarded, GuardPolicy, Verdict};
use crate::flow::settings::WrapSettings;
use crate::flow::snap::SnapTarget;
use crate::flow::surgery::detect::FacingQuery;
use crate::flow::surgery::{
    drop_empty_components, events, open_handles, SurgeryEvent, SurgeryKind, OPENED_MARGIN,
};
use crate::geometry::spatial::local_spacing::spacing_near;
use crate::mesh::HalfedgeMesh;
use crate::metrics::intersections::count_self_intersections;
use crate::target::Target;
use glam::DVec3;

/// Tunnels are looked for from this share of the step limit on: by then membranes over holes
/// they can reach have met, and the ones left are stuck (cut earlier, while still far from the
/// walls, a tube fits the hole worse; see docs/decisions/0014-surgery-tunnels.md).
const TUNNELS_FROM: f64 = 0.5;

/// Where a cloud's local spacing exceeds this many times its median, surgery reads "far from the
/// data" at the local spacing: `tuning.surgery.empty_spacings` local spacings. (Below, at the median:
/// a random sampling's local medians scatter about it, and an even sampling keeps the global
/// reading.)
const SPARSE: f64 = 1.5;

/// A cloud's median spacing in the stabilised frame, for surgery's reading of local spacing;
/// None for a target without a point spacing or without `tuning.surgery.empty_spacings`.
pub(super) fn cloud_spacing(target: &Target, settings: &WrapSettings, phi: f64) -> Option<f64> {
    if !settings.surgery.enabled || settings.tuning.surgery.empty_spacings <= 0.0 {
        return None;
    }
    let median = phi * target.oracle().spacing()?;
    (median > 0.0).then_some(median)
}

/// The factor (≤ 1) by which surgery reads a distance where the local spacing `local` is sparser
/// than [`SPARSE`] medians: `empty` over `empty_spacings` local spacings, so that a place counts
/// as far from the data only beyond that many local spacings (1 elsewhere).
fn sparse_factor(local: Option<f64>, median: f64, empty: f64, spacings: f64) -> f64 {
    match local {
        Some(l) if l > SPARSE * median => (empty / (spacings * l)).min(1.0),
        _ => 1.0,
    }
}

impl Evolver {
    /// Operates when due and needed; the events of this step (empty when nothing happened).
    pub(super) fn surgery_if_due(&mut self, times: &mut PhaseTimes) -> Vec<SurgeryEvent> {
        let every = self.settings.tuning.surgery.check_every;
        if (self.step % every.max(1) != 0 && !self.surgery_pending) || self.done {
            return Vec::new();
        }
        self.surgery_now(times, false)
    }

    /// The last look, on the step that ends the evolution (before the final fit): membranes
    /// still closing in on each other are cut as they are. The wait for them to settle exists
    /// so that a hole is not cut twice, and there is no later look; without this, membranes
    /// that meet late stay uncut and the wrap loses the handle (see
    /// docs/decisions/0016-surgery-last-look.md). The distances are sampled at the current
    /// surface for the look and kept only if it operated.
    pub(super) fn surgery_last(&mut self, times: &mut PhaseTimes) -> Vec<SurgeryEvent> {
        if !self.settings.surgery.enabled {
            return Vec::new();
        }
        let kept = (self.distances.clone(), self.gradients.clone());
        self.refresh_distances();
        let events = self.surgery_now(times, true);
        if events.is_empty() {
            (self.distances, self.gradients) = kept;
        }
        events
    }

    /// Operates when needed; `last`: no later look will come (see [`Evolver::surgery_last`]).
    fn surgery_now(&mut self, times: &mut PhaseTimes, last: bool) -> Vec<SurgeryEvent> {
        let s = &self.settings.tuning.surgery;
        if !self.settings.surgery.enabled {
            return Vec::new();
        }
        let t0 = now_ms();
        let (phi, center) = (self.phi, self.center);
        // A hole once opened is left alone: its ball reaches the cut's rim plus the width of the
        // membrane left around it (at most `empty` from the data), with a margin.
        let opened = self
            .surgery_events
            .iter()
            .map(|e| {
                let c = phi * (DVec3::from_array(e.position) - center);
                (c, phi * e.radius + OPENED_MARGIN * self.empty_distance)
            })
            .chain(
                self.tunnels_opened
                    .iter()
                    .map(|&(c, r)| (c, r + OPENED_MARGIN * self.empty_distance)),
            )
            .collect();
        let query = FacingQuery {
            empty: self.empty_distance,
            gap_ratio: s.gap_ratio,
            opened,
            min_width: self.close_gap_distance,
            least_genus: self.least_genus,
            tunnel_ratio: if self.step as f64 >= TUNNELS_FROM * self.settings.stop.steps as f64 {
                s.tunnel_ratio
            } else {
                0.0
            },
        };
        // (Settled: the count of paired vertices compared with "no limit".)
        let previous = if last {
            usize::MAX
        } else {
            self.surgery_paired
        };
        // On a cloud sampled sparsely in places, a tube needs its hole to be empty at the local
        // spacing (see `surgery::SPARSE`).
        let (empty, spacings) = (self.empty_distance, s.empty_spacings);
        // (Over the fit's grid: a cloud without a fit reads the global spacing only.)
        let local = match (&self.fit_target, self.cloud_spacing) {
            (Some(SnapTarget::Points(grid)), Some(median)) => Some((grid, median)),
            _ => None,
        };
        let sparse = |p| {
            local.map_or(1.0, |(grid, median)| {
                sparse_factor(spacing_near(grid, p), median, empty, spacings)
            })
        };
        let field = &self.field;
        let look = open_handles(
            &self.mesh,
            &self.distances,
            &|p| field.sample(p),
            &sparse,
            &query,
            s.min_vertices,
            previous,
        );
        // A look on a surface that intersects itself (it moved since the contact guard's last
        // check) can certify nothing: the next step looks again.
        self.surgery_pending = look.intersecting;
        if !look.intersecting {
            self.surgery_paired = look.paired;
        }
        let Some(op) = look.operated else {
            times.surgery += now_ms() - t0;
            return Vec::new();
        };
        // A tunnel with a tube through it is opened all across (the tube may be narrower).
        for &(c, r) in &look.tunnels {
            if op.tubes.iter().any(|t| t.position.distance(c) <= r) {
                self.tunnels_opened.push((c, r));
            }
        }
        let mut out = events(&op, self.step, phi, |p| p / phi + center);
        self.remesh_tubes(op.mesh, times);
        self.refresh_distances();
        // A pinch may leave a bubble around nothing: drop it.
        if let Some((kept, centroid)) =
            drop_empty_components(&self.mesh, &self.distances, self.empty_distance)
        {
            let before = self.mesh.validate().map(|r| (r.genus, r.components));
            let after = kept.validate().map(|r| (r.genus, r.components));
            if let (Ok((g0, c0)), Ok((g1, c1))) = (before, after) {
                self.mesh = kept;
                self.refresh_distances();
                out.push(SurgeryEvent {
                    step: self.step,
                    kind: SurgeryKind::Drop,
                    position: (centroid / phi + center).to_array(),
                    radius: 0.0,
                    genus_before: g0,
                    genus_after: g1,
                    components_before: c0,
                    components_after: c1,
                });
            }
        }
        self.save_checkpoint();
        self.surgery_events.extend(out.iter().cloned());
        times.surgery += now_ms() - t0;
        out
    }

    /// The tubes' faces are as long as the loops' edges and as tall as the gap: remeshes the
    /// `operated` surface, keeping it unremeshed if the remesh leaves intersecting faces.
    fn remesh_tubes(&mut self, operated: HalfedgeMesh, times: &mut PhaseTimes) {
        self.mesh = operated.clone();
        guarded(
            &mut (self, times),
            &mut [],
            GuardPolicy::ONCE,
            |(ev, times), _| ev.remesh_phase(times, None).is_ok(),
            |(ev, _), _| {
                let pairs = count_self_intersections(ev.mesh.positions(), &ev.mesh.triangles());
                Verdict::clean_if(pairs == 0)
            },
            |(ev, _)| ev.mesh = operated,
        );
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn only_a_sampling_sparser_than_its_median_shrinks_distances() {
        // empty = 3 median spacings of 0.01.
        let f = |local| sparse_factor(local, 0.01, 0.03, 3.0);
        assert_eq!(f(None), 1.0);
        assert_eq!(f(Some(0.012)), 1.0);
        assert_eq!(f(Some(0.015)), 1.0);
        assert!((f(Some(0.03)) - 1.0 / 3.0).abs() < 1e-12);
        // A global empty set by the grid (larger than 3 spacings) shrinks less.
        assert!((sparse_factor(Some(0.03), 0.01, 0.06, 3.0) - 2.0 / 3.0).abs() < 1e-12);
    }
}
