//! The fit's view of the target, built beside the field: the tree or grid the fit projects
//! onto ([`FitKey`]), and a cloud's creases while they are still being found ([`PendingCreases`],
//! [`CreaseJob`] for another worker).

use crate::flow::settings::WrapSettings;
use crate::flow::snap::SnapTarget;
use crate::geometry::cloud_creases::detect_cloud_creases;
use crate::geometry::creases::{detect_creases, Creases};
use crate::geometry::spatial::point_grid::PointGrid;
use crate::parallel::Later;
use crate::target::{CreaseSource, Target};
use glam::DVec3;

/// A cloud's creases before the final fit.
pub(super) enum PendingCreases {
    /// Being found beside the steps (natively), or known.
    Later(Later<Option<Creases>>),
    /// Left to the fit (wasm, one thread), unless [`super::Evolver::supply_creases`] brings them
    /// first.
    Deferred(CreaseJob),
}

impl PendingCreases {
    /// Whether getting them takes time here: found now, or waited for.
    pub(super) fn takes_time(&self) -> bool {
        !matches!(self, PendingCreases::Later(l) if !l.elsewhere())
    }

    /// The creases, found here if they were left to the fit (`done` hears the fraction).
    pub(super) fn get(self, done: &mut dyn FnMut(f64)) -> Option<Creases> {
        match self {
            PendingCreases::Later(later) => later.get(),
            PendingCreases::Deferred(job) => job.run(done),
        }
    }
}

/// A cloud's crease detection as a job for another worker (see [`super::Evolver::crease_job`]): the
/// fit's grid of the target's points (stabilised frame), the fit radius and the crease angle
/// (radians).
#[derive(Clone)]
pub struct CreaseJob {
    pub(super) grid: std::sync::Arc<PointGrid>,
    /// The points in input order when the job was rebuilt elsewhere (else taken from the grid).
    pub(super) input: Option<std::sync::Arc<Vec<DVec3>>>,
    pub radius: f64,
    pub angle: f64,
}

impl CreaseJob {
    /// What crosses to the other worker: the points in the grid's cell order and each one's
    /// index among the target's points, read straight out of the grid (a copy in input order
    /// would cost the sending worker time on a large cloud).
    pub fn cell_order(&self) -> (&[DVec3], &[u32]) {
        self.grid.cell_ordered()
    }

    /// The job again from [`CreaseJob::cell_order`]'s lists (in the other worker), its grid
    /// built as the fit builds its own, so the same; None unless `order` numbers `points`.
    pub fn from_cell_order(
        points: Vec<DVec3>,
        order: &[u32],
        radius: f64,
        angle: f64,
    ) -> Option<Self> {
        if points.len() != order.len() {
            return None;
        }
        let (mut input, mut seen) = (vec![DVec3::ZERO; points.len()], vec![false; points.len()]);
        for (&i, p) in order.iter().zip(points) {
            let i = i as usize;
            if std::mem::replace(seen.get_mut(i)?, true) {
                return None;
            }
            input[i] = p;
        }
        Some(CreaseJob {
            grid: std::sync::Arc::new(PointGrid::new(&input, radius)),
            input: Some(std::sync::Arc::new(input)),
            radius,
            angle,
        })
    }

    /// The creases the fit would find (`done` hears the fraction).
    pub fn run(&self, done: &mut dyn FnMut(f64)) -> Option<Creases> {
        let from_grid;
        let points = match &self.input {
            Some(input) => input.as_slice(),
            None => {
                from_grid = self.grid.points_in_input_order();
                &from_grid
            }
        };
        let c = detect_cloud_creases(points, &self.grid, self.radius, self.angle, done);
        (!c.is_empty()).then_some(c)
    }
}

/// What the fit's view of the target (its creases, and the tree or grid the fit projects onto)
/// is built from: equal keys build equal things.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct FitKey {
    /// The stabilisation factor of the frame they are built in.
    pub(super) phi: f64,
    /// The fit's neighbourhood radius (stabilised frame).
    pub(super) fit_radius: f64,
    /// The crease angle (radians); None: no crease detection (none where the target's oracle
    /// finds no creases).
    pub(super) crease_angle: Option<f64>,
    /// Whether there is a final fit.
    pub(super) fits: bool,
}

impl FitKey {
    /// The key of `settings` for a field of cells of size `cell` and a start scaled by `phi`.
    pub(super) fn new(settings: &WrapSettings, target: &Target, cell: f64, phi: f64) -> Self {
        let fits = settings.fit.enabled && settings.flow.use_target;
        Self {
            phi,
            fit_radius: settings.fit.radius_cells * cell * phi,
            crease_angle: (fits
                && target.oracle().creases().is_some()
                && settings.fit.crease_angle_deg > 0.0)
                .then(|| settings.fit.crease_angle_deg.to_radians()),
            fits,
        }
    }

    /// The target's points in the stabilised frame.
    pub(super) fn framed(&self, target: &Target, center: DVec3) -> Vec<DVec3> {
        target
            .points
            .iter()
            .map(|&p| self.phi * (p - center))
            .collect()
    }

    /// The fit target of `target` (None without a fit).
    pub(super) fn fit_target(&self, target: &Target, center: DVec3) -> Option<SnapTarget> {
        self.fits
            .then(|| SnapTarget::new(target, center, self.phi, self.fit_radius))
    }

    /// `(fit target, creases)`, each on a thread of its own natively; a cloud's creases are
    /// found later, on its fit grid (None here).
    pub(super) fn build(
        &self,
        target: &Target,
        center: DVec3,
    ) -> (Option<SnapTarget>, Option<Creases>) {
        let dihedral = target.oracle().creases() == Some(CreaseSource::Dihedral);
        let (creases, fit_target) = crate::parallel::beside(
            || {
                self.crease_angle.filter(|_| dihedral).map(|angle| {
                    detect_creases(&self.framed(target, center), &target.triangles, angle)
                })
            },
            || self.fit_target(target, center),
        );
        (fit_target, creases)
    }
}
