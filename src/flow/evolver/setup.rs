//! Setting a wrap up, stage by stage: the target as wrapped (without a cloud's stray points and a
//! mesh's specks), the distance field and the start surface (with the fit's view of the target
//! built beside them), the fit's view in the stabilised frame, and the evolver's initial state.

use super::fit_view::{CreaseJob, FitKey, PendingCreases};
use super::{second_pass, start_choice, surgery, Checkpoint, EvolveError, Evolver};
use super::{CREASE_PHASE, START_PHASE, STRAY_PHASE};
use crate::field::DistanceField;
use crate::flow::guard::DivergenceLimits;
use crate::flow::settings::{StartSurface, WrapSettings};
use crate::flow::snap::SnapTarget;
use crate::flow::start::{start_scale, Start};
use crate::geometry::creases::Creases;
use crate::mesh::{HalfedgeMesh, MeshReport};
use crate::parallel::Later;
use crate::progress::Progress;
use crate::target::{CreaseSource, Target};
use glam::DVec3;

/// The field, the start and the settings of that start, with the target's closed topology.
type FieldAndStart = ((DistanceField, Start, WrapSettings), Option<MeshReport>);
/// The fit's view of the target built beside the field, with the key it was built for.
type Prebuilt = Option<(FitKey, (Option<SnapTarget>, Option<Creases>))>;

impl Evolver {
    /// Builds the distance field and the start surface, scaled into the stabilised frame.
    pub fn new(target: &Target, settings: WrapSettings) -> Result<Self, EvolveError> {
        Self::new_with_progress(target, settings, &mut Progress::none())
    }

    /// [`Evolver::new`], reporting the field build and the start surface to `progress`.
    pub fn new_with_progress(
        target: &Target,
        settings: WrapSettings,
        progress: &mut Progress,
    ) -> Result<Self, EvolveError> {
        settings.check()?;
        target.check_wrappable()?;
        let cleaned = without_strays(target, &settings, progress)?;
        let (target, isolated_points) = match &cleaned {
            Some((t, n)) => (t, *n),
            None => (target, 0),
        };
        let despecked = without_specks(target, &settings)?;
        let (target, specks) = match &despecked {
            Some((t, n)) => (t, *n),
            None => (target, 0),
        };
        let (prebuilt, start) = field_and_start(target, &settings, progress);
        let ((field, start, mut settings), closed) = start?;
        progress.report(START_PHASE, 1.0);
        if !target.oracle().refine_passes_help() {
            settings.tuning.fit.refine_passes = settings.tuning.fit.volume_refine_passes;
        }
        let center = target.bbox.center();
        let key = FitKey::new(&settings, target, field.cell_size(), start.phi);
        let (fit_target, creases) = fit_view(target, key, center, prebuilt, progress);
        let mut ev = Evolver::assemble(target, settings, field, start, closed, fit_target);
        ev.pending_creases = Some(creases);
        ev.isolated_points = isolated_points;
        ev.specks = specks;
        ev.despecked = despecked.map(|(t, _)| t);
        ev.save_checkpoint();
        let start = ev.checkpoint.clone();
        if let Some(pass) = ev.second_pass.as_mut() {
            pass.starting(start);
        }
        ev.refresh_distances();
        ev.done = ev.settings.stop.steps == 0;
        Ok(ev)
    }

    /// The evolver's state at step 0 on `start` (field scaled into the stabilised frame here).
    fn assemble(
        target: &Target,
        settings: WrapSettings,
        mut field: DistanceField,
        start: Start,
        closed: Option<MeshReport>,
        fit_target: Option<SnapTarget>,
    ) -> Evolver {
        let c = field.cell_size();
        let center = target.bbox.center();
        let (mesh, phi, sizes) = (start.mesh, start.phi, start.sizes);
        let limits = divergence_limits(target, &mesh, phi, center, &settings);
        // In place: a scaled copy would keep the unscaled field alive to the end of setup.
        field.scale_uniform(center, phi);
        let d0 = settings.flow.iso_level_factor * 0.5 * 3f64.sqrt() * c * phi;
        let pass = second_pass::SecondPass::new(
            target,
            &settings,
            (d0, phi, center),
            fit_target.is_some(),
        );
        Evolver {
            tau: settings.flow.tau,
            d1: settings.flow.d1,
            settle_threshold: settings.stop.displacement_cells * c * phi,
            empty_distance: phi * empty_distance(target, c, &settings),
            cloud_spacing: surgery::cloud_spacing(target, &settings, phi),
            close_gap_distance: phi * close_gap_distance(target, &settings),
            least_genus: closed.filter(|t| t.components == 1).map(|t| t.genus),
            settings,
            mesh,
            field,
            center,
            phi,
            d0,
            sizes,
            step: 0,
            done: false,
            distances: vec![],
            gradients: vec![],
            fit_target,
            creases: None,
            pending_creases: None,
            isolated_points: 0,
            specks: 0,
            despecked: None,
            sizes_changed: true,
            start: start.kind,
            limits,
            stop_reason: None,
            checkpoint: Checkpoint {
                mesh: HalfedgeMesh::default(),
                tau: 0.0,
                d1: 0.0,
                sizes,
                step: 0,
                sizes_changed: true,
            },
            guarded_left: 0,
            surgery_events: Vec::new(),
            tunnels_opened: Vec::new(),
            surgery_paired: 0,
            surgery_pending: false,
            second_pass: pass,
            started_over: None,
        }
    }
}

/// A cloud without its stray points (left out of everything built from the target), with their
/// count; None when none were left out or the test is off.
fn without_strays(
    target: &Target,
    settings: &WrapSettings,
    progress: &mut Progress,
) -> Result<Option<(Target, usize)>, EvolveError> {
    let oracle = target.oracle();
    let strays = oracle.removes_strays() && settings.tuning.field.outlier_spacings > 0.0;
    if strays {
        progress.report(STRAY_PHASE, 0.0);
        // The spacing first, remembered for the test: a part of its cost worth a report.
        oracle.spacing();
        progress.report(STRAY_PHASE, 0.3);
    }
    let cleaned = target.without_isolated_points(settings.tuning.field.outlier_spacings);
    if strays {
        progress.report(STRAY_PHASE, 1.0);
    }
    if let Some((t, _)) = &cleaned {
        t.check_wrappable()?;
    }
    Ok(cleaned)
}

/// A mesh without its specks (small closed parts floating apart, at the cell of the grid its
/// whole box would get), with their count; None for a cloud or a mesh without any.
fn without_specks(
    target: &Target,
    settings: &WrapSettings,
) -> Result<Option<(Target, usize)>, EvolveError> {
    let despecked = match target.oracle().removes_specks() {
        false => None,
        true => DistanceField::planned_cell_size(target, &settings.field_options())
            .and_then(|cell| target.without_specks(cell)),
    };
    if let Some((t, _)) = &despecked {
        t.check_wrappable()?;
    }
    Ok(despecked)
}

/// The field and the start `auto` settles on (see [`start_choice`]), with the fit's view of the
/// target built beside them for the start the settings ask for: it depends on the field and
/// the start only through the cell size and φ, both known from the settings and the field's plan.
fn field_and_start(
    target: &Target,
    settings: &WrapSettings,
    progress: &mut Progress,
) -> (Prebuilt, Result<FieldAndStart, EvolveError>) {
    // (A field is signed where the target has an inside and is closed, the usual case.)
    let inside = target.oracle().has_inside();
    let guess = settings.clone().resolved_for(inside);
    let options = match (inside, guess.start.surface) {
        (true, StartSurface::Isosurface) => guess.isosurface_field_options(),
        _ => settings.field_options(),
    };
    let plan = DistanceField::plan(target, &options);
    let planned = plan.as_ref().ok().map(|p| {
        let cell = p.cell_size();
        FitKey::new(&guess, target, cell, start_scale(target, cell, &guess))
    });
    let center = target.bbox.center();
    crate::parallel::beside(
        || planned.map(|k| (k, k.build(target, center))),
        || -> Result<_, EvolveError> {
            let field = DistanceField::new_planned(target, &options, plan?, progress)?;
            let mut resolved = settings.clone().resolved_for(field.is_signed());
            progress.report(START_PHASE, 0.0);
            // The target's topology where it is closed: for the start's checks and surgery's
            // least genus.
            let closed = target.oracle().topology();
            let start = start_choice::build_start_with_fallback(
                target,
                closed.as_ref(),
                &field,
                settings,
                &mut resolved,
            )?;
            let finer = start_choice::finer_start(
                target,
                closed.as_ref(),
                settings,
                &resolved,
                &start,
                progress,
            );
            // An icosphere (the fallback) lies round the box, in room an isosurface's field lacks.
            let field = match (finer, options.margin_cells, resolved.start.surface) {
                (Some(finer), ..) => return Ok((finer, closed)),
                (None, Some(_), StartSurface::Icosphere) => {
                    DistanceField::new_with_progress(target, &settings.field_options(), progress)?
                }
                (None, ..) => field,
            };
            Ok(((field, start, resolved), closed))
        },
    )
}

/// The fit's target and a cloud's creases for the start taken: what was built beside the field
/// when its key is this one's, else built now. A cloud's creases are found on the fit's grid:
/// natively beside the steps, in wasm left to the fit (or a helper worker, see
/// [`Evolver::crease_job`]).
fn fit_view(
    target: &Target,
    key: FitKey,
    center: DVec3,
    prebuilt: Prebuilt,
    progress: &mut Progress,
) -> (Option<SnapTarget>, PendingCreases) {
    // Creases from plane fits are found on the fit's grid, later; the others with the fit target.
    if target.oracle().creases() != Some(CreaseSource::PlaneFits) {
        let (fit_target, creases) = match prebuilt {
            Some((made, built)) if made == key => built,
            _ => key.build(target, center),
        };
        return (fit_target, PendingCreases::Later(Later::ready(creases)));
    }
    let fit_target = match prebuilt {
        Some((made, (built, _))) if made == key => built,
        _ => key.fit_target(target, center),
    };
    let creases = match (&fit_target, key.crease_angle) {
        (Some(SnapTarget::Points(grid)), Some(angle)) => {
            let job = CreaseJob {
                grid: std::sync::Arc::clone(grid),
                input: None,
                radius: key.fit_radius,
                angle,
            };
            if cfg!(target_arch = "wasm32") {
                PendingCreases::Deferred(job)
            } else {
                PendingCreases::Later(crate::parallel::later(
                    move |done: &mut dyn FnMut(f64)| job.run(done),
                    &mut |f| progress.report(CREASE_PHASE, f),
                ))
            }
        }
        _ => PendingCreases::Later(Later::ready(None)),
    };
    (fit_target, creases)
}
/// Surgery's "far from the data" distance in the target's units: `tuning.surgery.empty_cells` cells,
/// on a point cloud at least `tuning.surgery.empty_spacings` median point spacings, and at least half
/// of `surgery.close_gaps` diagonals (a hole of that width has its centre that far from the
/// data). 0 when surgery is off: the spacing costs a tree over the points.
fn empty_distance(target: &Target, cell: f64, settings: &WrapSettings) -> f64 {
    let (s, tuned) = (&settings.surgery, &settings.tuning.surgery);
    if !s.enabled {
        return 0.0;
    }
    let spacing = target.oracle().spacing().unwrap_or(0.0);
    (tuned.empty_cells * cell)
        .max(tuned.empty_spacings * spacing)
        .max(close_gap_distance(target, settings))
}

/// Half of `surgery.close_gaps` target diagonals, in the target's units: a hole of that width
/// has its centre that far from the data.
fn close_gap_distance(target: &Target, settings: &WrapSettings) -> f64 {
    0.5 * settings.surgery.close_gaps * target.bbox.size().length()
}

/// The divergence guard's limits in the stabilised frame: the box of the start surface and the
/// target grown by `escape_diagonals` target diagonals; the area of the start surface plus the
/// target box's, times `max_area_growth`; `max_vertices`.
fn divergence_limits(
    target: &Target,
    start: &HalfedgeMesh,
    phi: f64,
    center: DVec3,
    settings: &WrapSettings,
) -> DivergenceLimits {
    let g = &settings.tuning.guard;
    let tb = &target.bbox;
    let (mut min, mut max) = (phi * (tb.min - center), phi * (tb.max - center));
    for p in start.positions() {
        min = min.min(*p);
        max = max.max(*p);
    }
    let margin = g.escape_diagonals * phi * tb.size().length().max(f64::MIN_POSITIVE);
    let s = phi * tb.size();
    let box_area = 2.0 * (s.x * s.y + s.y * s.z + s.z * s.x);
    DivergenceLimits {
        min: min - DVec3::splat(margin),
        max: max + DVec3::splat(margin),
        max_area: g.max_area_growth * (start.surface_area() + box_area),
        max_vertices: g.max_vertices,
    }
}
