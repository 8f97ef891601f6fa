//! The wrap as one pipeline that returns a value: prepare the target, build the field and the
//! start ([`crate::flow::Evolver::new_with_progress`]), evolve step by step (the final fit and
//! any further pass are the last step's), certify, and decide the [`Verdict`] once. The CLI calls
//! [`wrap`]; the browser's worker advances a [`WrapRun`] a few steps at a time (so it can draw and
//! cancel between them) and ends it with [`WrapRun::result`]. Both only render the result.

pub mod verdict;

pub use verdict::{LeftOut, Verdict, VerdictState};

use crate::clock::now_ms;
use crate::field::FieldTimings;
use crate::flow::surgery::SurgeryEvent;
use crate::flow::{
    ColourMap, EvolveError, Evolver, StartSurface, StartedOver, StepReport, WrapSettings,
};
use crate::metrics::certificate::{certify_measuring, Certificate, CertificateTarget};
use crate::progress::Progress;
use crate::target::Target;
use glam::DVec3;

/// What a caller hears while a wrap runs. Every method has a default that ignores it.
pub trait Observer {
    /// A long phase (reading, the field, the start, the final fit) is `fraction` (0–1) done.
    fn progress(&mut self, _phase: &str, _fraction: f64) {}
    /// A step ended with `report`.
    fn step(&mut self, _report: &StepReport) {}
}

/// An observer that ignores everything.
impl Observer for () {}

/// A finished wrap: the mesh, what certifies it, what happened on the way, and the verdict.
#[derive(Clone, Debug)]
pub struct WrapResult {
    /// The surface, in the target's units.
    pub positions: Vec<DVec3>,
    pub triangles: Vec<[u32; 3]>,
    /// Each vertex's exact distance to the target, from the certificate (to the nearest point of
    /// a cloud, the closest point of a mesh; target units).
    pub distances: Vec<f64>,
    pub certificate: Certificate,
    /// Decided once, from the certificate and the run: see [`Verdict::of`].
    pub verdict: Verdict,
    /// Fingerprint of the mesh (see [`crate::mesh::fingerprint::mesh_hash`]).
    pub hash: String,
    /// Why the run stopped before its rule said so (divergence, solver failure), if it did.
    pub stop_reason: Option<String>,
    /// The settings in force at the end (the start's own where `auto` chose it).
    pub settings: WrapSettings,
    /// The start surface used.
    pub start: StartSurface,
    /// Steps taken.
    pub steps: u32,
    /// Handles opened and closed by surgery.
    pub surgery: Vec<SurgeryEvent>,
    /// How a target the first pass left partly outside was wrapped again, if it was.
    pub started_over: Option<StartedOver>,
    /// What was left out of the target before wrapping it.
    pub left_out: LeftOut,
    /// The stabilisation scale φ, d₀ (target units), the field's cell (target units) and the
    /// field's construction times.
    pub scale: f64,
    pub iso_level: f64,
    pub cell_size: f64,
    pub field_ms: FieldTimings,
    /// Milliseconds per stage.
    pub times: StageTimes,
}

/// Milliseconds spent in each stage of a wrap.
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize)]
pub struct StageTimes {
    /// Strays and specks, the field and the start surface.
    pub setup: f64,
    /// Every step, the final fit and any further pass included.
    pub evolve: f64,
    /// The certificate and the verdict.
    pub certify: f64,
}

/// A wrap under way: built by [`WrapRun::new`], advanced by [`WrapRun::step`] until
/// [`WrapRun::is_done`], ended by [`WrapRun::result`].
pub struct WrapRun {
    evolver: Evolver,
    times: StageTimes,
}

impl WrapRun {
    /// Checks the settings and the target, and builds the field and the start surface.
    pub fn new(
        target: &Target,
        settings: WrapSettings,
        progress: &mut Progress,
    ) -> Result<WrapRun, EvolveError> {
        let t0 = now_ms();
        let evolver = Evolver::new_with_progress(target, settings, progress)?;
        let times = StageTimes {
            setup: now_ms() - t0,
            ..StageTimes::default()
        };
        Ok(WrapRun { evolver, times })
    }

    /// One step (the last one also fits and, where the target was left partly outside, passes
    /// again). On error the surface is the last certified one and the run is over.
    pub fn step(&mut self, progress: &mut Progress) -> Result<StepReport, EvolveError> {
        let t0 = now_ms();
        let step = self.evolver.step_with_progress(progress);
        self.times.evolve += now_ms() - t0;
        step
    }

    /// True when the stopping rule or the step limit has been reached (or a step failed).
    pub fn is_done(&self) -> bool {
        self.evolver.is_done()
    }

    /// The evolution, for what a viewer draws between steps.
    pub fn evolver(&self) -> &Evolver {
        &self.evolver
    }

    /// The evolution, for handing it work done elsewhere (a cloud's creases).
    pub fn evolver_mut(&mut self) -> &mut Evolver {
        &mut self.evolver
    }

    /// Colour map `map` on the current surface: its distances are `result`'s exact ones where
    /// the surface is the one `result` certified, the field's while the wrap runs; its flagged
    /// vertices those of `result`'s certificate.
    pub fn colour(&self, map: ColourMap, result: Option<&WrapResult>) -> Vec<f64> {
        let n = self.evolver.mesh().n_vertices();
        match result {
            Some(r) if map == ColourMap::Distance && r.distances.len() == n => r.distances.clone(),
            Some(r) if map == ColourMap::Flagged => {
                let mut v = vec![0.0; n];
                let flagged = r.certificate.faithfulness.as_ref();
                for &i in flagged.map_or(&[][..], |f| &f.flagged_vertices[..]) {
                    if let Some(x) = v.get_mut(i as usize) {
                        *x = 1.0;
                    }
                }
                v
            }
            _ => map.values(&self.evolver),
        }
    }

    /// The per-vertex scalars a written result records (see [`crate::flow::colour::export_scalars`]),
    /// with the distances of [`WrapRun::colour`].
    pub fn export_scalars(&self, result: Option<&WrapResult>) -> Vec<(&'static str, Vec<f64>)> {
        crate::flow::colour::export_scalars_with(|map| self.colour(map, result))
    }

    /// The target the result is certified against: `target` without the specks the run left
    /// out (those are reported, not wrapped).
    pub fn certified_target<'a>(&'a self, target: &'a Target) -> &'a Target {
        self.evolver.despecked_target().unwrap_or(target)
    }

    /// The current surface certified against `against` (built from
    /// [`WrapRun::certified_target`]), with its verdict.
    pub fn result(&self, against: &CertificateTarget) -> WrapResult {
        let t0 = now_ms();
        let ev = &self.evolver;
        let (positions, triangles) = (ev.positions(), ev.triangles());
        let (certificate, exact) = certify_measuring(&positions, &triangles, Some(against));
        let left_out = LeftOut {
            strays: ev.isolated_points(),
            specks: ev.specks(),
        };
        let started_over = ev.started_over();
        let verdict = Verdict::of(
            &certificate,
            ev.stop_reason(),
            started_over.as_ref(),
            left_out,
        );
        WrapResult {
            distances: exact.unwrap_or_else(|| ev.vertex_distances()),
            hash: crate::mesh::fingerprint::mesh_hash(&positions, &triangles),
            positions,
            triangles,
            certificate,
            verdict,
            stop_reason: ev.stop_reason().map(str::to_owned),
            settings: ev.settings().clone(),
            start: ev.start_surface(),
            steps: ev.steps_done(),
            surgery: ev.surgery_events().to_vec(),
            started_over,
            left_out,
            scale: ev.scale(),
            iso_level: ev.iso_level(),
            cell_size: ev.field().cell_size() / ev.scale(),
            field_ms: ev.field().timings(),
            times: StageTimes {
                certify: now_ms() - t0,
                ..self.times
            },
        }
    }
}

/// Wraps `target` with `settings`, telling `observer` of progress and of every step. A step that
/// fails ends the run with the last certified surface, and the result says so (`stop_reason`,
/// an invalid verdict); only a wrap that cannot start is an error.
pub fn wrap(
    target: &Target,
    settings: WrapSettings,
    observer: &mut impl Observer,
) -> Result<WrapResult, EvolveError> {
    let mut run = {
        let mut sink = |phase: &str, f: f64| observer.progress(phase, f);
        WrapRun::new(target, settings, &mut Progress::to(&mut sink))?
    };
    // The certificate's side of the target (a tree, its topology) is built beside the steps,
    // on the core their sequential parts leave idle.
    // (A copy only where specks were left out: the steps borrow the run meanwhile.)
    let despecked = run.evolver().despecked_target().cloned();
    let wrapped = despecked.as_ref().unwrap_or(target);
    let (against, ()) = crate::parallel::beside(
        || CertificateTarget::new(wrapped),
        || {
            while !run.is_done() {
                let step = {
                    let mut sink = |phase: &str, f: f64| observer.progress(phase, f);
                    run.step(&mut Progress::to(&mut sink))
                };
                match step {
                    Ok(report) => observer.step(&report),
                    Err(_) => break,
                }
            }
        },
    );
    Ok(run.result(&against))
}
