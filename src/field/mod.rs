//! The distance field that drives the flow: exact near the target, fast everywhere, signed when
//! it can be [docs/method.md §2; project decision 1].
//!
//! Pipeline of [`DistanceField::new`], one file per step:
//! [`grid`] (lattice layout) → [`band`] (exact distances within `k` cells) → [`fast_sweep`]
//! (Zhao's eikonal solver outside the band) → [`sign`] (meshes only) → [`gradient`]
//! (`−∇d/|∇d|`), queried through [`sample`] (trilinear, clamped into the box).
//!
//! Precision: values are **f64** (8 bytes per node): the band is exact to rounding, which the
//! tests check to 1e-9 relative, and the flow subtracts d₀ from values of order c. The gradient is
//! a unit vector stored as **3×f32** (12 bytes per node), see [`gradient`]. With the 1-byte band
//! flag a field holds 21 bytes per node. While building, the sweep works on an f32 copy (it is
//! memory-bound, and its O(c) error dwarfs f32 rounding) with 1 byte of state per node, and mesh
//! targets keep a 4-byte nearest-triangle index per node.
//!
//! Isosurfaces ([`DistanceField::isosurface`]) come from
//! [`crate::geometry::marching_cubes`]: closed, manifold, oriented, welded.

pub mod band;
pub mod exterior;
pub mod fast_sweep;
pub mod gradient;
pub mod grid;
pub mod sample;
pub mod sign;
pub mod slice;
pub mod vtk;

pub use grid::Grid;
pub use sign::Signedness;

use crate::geometry::aabb::Aabb;
use crate::progress::Progress;
use crate::target::{Surface, Target};
use glam::DVec3;
use serde::{Deserialize, Serialize};

/// Whether to sign a mesh field.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize, Default)]
#[serde(rename_all = "snake_case")]
pub enum SignMode {
    /// Signed for closed (or nearly closed) consistently oriented meshes, unsigned otherwise.
    #[default]
    Auto,
    /// Always the unsigned distance.
    Unsigned,
}

/// Settings of the distance field. All lengths are relative to the target's bounding box.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default)]
pub struct FieldSettings {
    /// Cells per minimum bounding-box dimension N: the cell size is `c = β_min/N`, β_min the
    /// smallest (non-flat) side of the target's bounding box, or of its principal box where
    /// that is much tighter (a target lying turned: [`grid::reference_length_of`]). Range
    /// 2–4096; default 40 (the paper's "40 voxels per minimum dimension").
    pub cells_per_min_dimension: u32,
    /// Volume expansion factor ζ: the box is grown by `ζ·β_min` on every side. Unit: β_min.
    /// Range 0–10; default 1.0.
    pub expansion: f64,
    /// The room in cells the surface needs, where that is less than `ζ·β_min` (an isosurface
    /// start lies a level and a band off the target, where an icosphere needs the room round the
    /// box): the `ζ·β_min` margin is trimmed by whole steps of [`TRIM_CELLS`] while this much
    /// is left. Range 1–64; default `None` (ζ·β_min).
    pub margin_cells: Option<f64>,
    /// Width k of the exact near band, in cells: every node within `k·c` of the target gets its
    /// exact distance and is frozen for sweeping. Range 1–16; default 3.
    pub band_cells: f64,
    /// Optional truncation: distances are capped at `truncation·β_min` (values never exceed it).
    /// Unit: β_min. Range > 0; default `None` (no cap, as in all the paper's experiments).
    pub truncation: Option<f64>,
    /// Signing of mesh fields; point clouds are always unsigned. Default [`SignMode::Auto`].
    pub sign: SignMode,
    /// Cap on fast-sweeping passes (one ordering each; 8 make a full cycle). Range ≥ 1;
    /// default 64.
    pub max_sweep_passes: u32,
    /// Sweeping stops after the first pass (from the 8th on) in which no value dropped by more
    /// than `sweep_tolerance·c`; 0 means "until no value changes at all". Unit: cells.
    /// Range 0–1; default 1e-4 (the scheme's own error is O(c), so a tighter tolerance gains
    /// nothing).
    pub sweep_tolerance: f64,
    /// Memory cap in bytes for the finished field (21 bytes per node, see the module docs); a
    /// larger grid is refused with [`FieldError::TooLarge`]. Default 1 GiB.
    pub memory_cap_bytes: u64,
    /// Point clouds only: the cell is at least this many median nearest-neighbour spacings, so a
    /// sparse cloud gets a grid coarse enough that the offset surface d = d₀ cannot slip between
    /// its points (then it would wrap each point on its own and the vertex count would run away).
    /// 0 turns it off. Range 0–10; default 2 (dense scans are below it and keep N cells per
    /// β_min; only sparse clouds get a coarser grid).
    pub min_cell_spacings: f64,
    /// Point clouds only: a point is a stray return, left out of the field, the start and the
    /// fit, when fewer than 6 points (itself included) lie within this many median spacings of
    /// it and its nearest points are not as sparse as it is (a region sampled more sparsely than
    /// the rest keeps its points; see [`crate::geometry::spatial::isolated::stray_points`]); at
    /// most a tenth of the cloud is left out (more is a sparse scan, not strays). 0 keeps every
    /// point. Range 0–100; default 6.
    pub outlier_spacings: f64,
    /// A target lying turned away from the axes gets the grid of its principal box: β_min is the
    /// smaller of the axis-aligned box's and this many times the principal box's (see
    /// [`grid::reference_length_of`]). 0 keeps the method's axis-aligned box (share links
    /// without this key decode to 0). Range 0 or 1–100; default 1.25.
    pub principal_slack: f64,
    /// Point clouds only: nodes deeper than this many cells inside a region the cloud encloses
    /// (the inside of a solid sampled all round: not linked to the grid's border by nodes one
    /// cell farther still from every point, see [`sign::negate_enclosed`]) get a negative
    /// distance. A wrap vertex that slips past a sharp rim into such a part is then held and
    /// regrown instead of driven on through it by the full-wrap term (which would cut a thin
    /// frame's corners and open false handles). Parts thinner than twice this, and clouds with
    /// wide gaps, stay unsigned. 0 keeps the field unsigned (share links without this key
    /// decode to 0). Range 0 or 1–16; default 2.
    pub enclosed_cells: f64,
}

impl Default for FieldSettings {
    fn default() -> Self {
        Self {
            cells_per_min_dimension: 40,
            expansion: 1.0,
            margin_cells: None,
            band_cells: 3.0,
            truncation: None,
            sign: SignMode::Auto,
            max_sweep_passes: 64,
            sweep_tolerance: 1e-4,
            memory_cap_bytes: 1 << 30,
            min_cell_spacings: 2.0,
            outlier_spacings: 6.0,
            principal_slack: grid::TURNED_SLACK,
            enclosed_cells: 2.0,
        }
    }
}

/// The step by which a margin is trimmed (see [`FieldSettings::margin_cells`]), in cells: a
/// multiple of the cell and of the isosurface start's 1.5-cell resampling, so both lattices keep
/// their nodes where the untrimmed box has them and the start is the one that box gives.
pub const TRIM_CELLS: f64 = 3.0;

impl FieldSettings {
    /// How far the box is grown on every side, for reference length `beta` (see
    /// [`Self::margin_cells`]).
    pub fn margin(&self, beta: f64) -> f64 {
        let wide = self.expansion * beta;
        let Some(room) = self.margin_cells else {
            return wide;
        };
        let c = beta / self.cells_per_min_dimension as f64;
        let steps = ((wide / c - room) / TRIM_CELLS).floor().max(0.0);
        wide - steps * TRIM_CELLS * c
    }

    /// Checks every field's range.
    pub fn check(&self) -> Result<(), FieldError> {
        let bad = |name: &'static str, value: f64, range: &'static str| {
            Err(FieldError::InvalidSetting { name, value, range })
        };
        if !(2..=4096).contains(&self.cells_per_min_dimension) {
            return bad(
                "cells_per_min_dimension",
                self.cells_per_min_dimension as f64,
                "2–4096",
            );
        }
        if !(0.0..=10.0).contains(&self.expansion) {
            return bad("expansion", self.expansion, "0–10");
        }
        if let Some(k) = self.margin_cells.filter(|k| !(1.0..=64.0).contains(k)) {
            return bad("margin_cells", k, "1–64");
        }
        if !(1.0..=16.0).contains(&self.band_cells) {
            return bad("band_cells", self.band_cells, "1–16");
        }
        if let Some(t) = self.truncation {
            if t <= 0.0 || !t.is_finite() {
                return bad("truncation", t, "> 0");
            }
        }
        if !(0.0..=1.0).contains(&self.sweep_tolerance) {
            return bad("sweep_tolerance", self.sweep_tolerance, "0–1");
        }
        if self.max_sweep_passes == 0 {
            return bad("max_sweep_passes", 0.0, "≥ 1");
        }
        if !(0.0..=10.0).contains(&self.min_cell_spacings) {
            return bad("min_cell_spacings", self.min_cell_spacings, "0–10");
        }
        if !(0.0..=100.0).contains(&self.outlier_spacings) {
            return bad("outlier_spacings", self.outlier_spacings, "0–100");
        }
        if !(self.principal_slack == 0.0 || (1.0..=100.0).contains(&self.principal_slack)) {
            return bad("principal_slack", self.principal_slack, "0 or 1–100");
        }
        if !(self.enclosed_cells == 0.0 || (1.0..=16.0).contains(&self.enclosed_cells)) {
            return bad("enclosed_cells", self.enclosed_cells, "0 or 1–16");
        }
        Ok(())
    }
}

/// Why a distance field could not be built.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum FieldError {
    /// The target has no points. Fix: load a file with at least one vertex.
    #[error("the target is empty: a distance field needs at least one point")]
    EmptyTarget,
    /// All points coincide (a single point, or copies of one): there is no bounding box to size
    /// the grid from. Fix: give a target with extent.
    #[error("all target points coincide: the bounding box has no extent to size the grid from")]
    DegenerateTarget,
    /// A coordinate is NaN or infinite. Fix: clean the input.
    #[error("target point {index} has a non-finite coordinate")]
    NonFinite { index: usize },
    /// A triangle refers to a missing vertex. Fix: repair the file's face list.
    #[error("triangle {triangle} refers to a vertex that does not exist")]
    BadTriangle { triangle: usize },
    /// A setting is out of its range. Fix: use a value in the range given.
    #[error("setting {name} = {value} is out of range ({range})")]
    InvalidSetting {
        name: &'static str,
        value: f64,
        range: &'static str,
    },
    /// The grid would need more memory than the cap. Fix: lower the cells per minimum
    /// dimension to at most `cells_that_fit`, or raise the cap.
    #[error(
        "a {}×{}×{} grid needs {} MiB, over the memory cap of {} MiB; \
         at most {cells_that_fit} cells per minimum dimension fit",
        dims[0], dims[1], dims[2], bytes / (1 << 20), cap_bytes / (1 << 20)
    )]
    TooLarge {
        dims: [usize; 3],
        bytes: u64,
        cap_bytes: u64,
        cells_that_fit: u32,
    },
}

/// A field's grid laid out for a checked target (see [`DistanceField::plan`]).
#[derive(Clone, Debug)]
pub struct FieldPlan {
    grid: Grid,
    beta: f64,
}

impl FieldPlan {
    /// The cell size the field will have.
    pub fn cell_size(&self) -> f64 {
        self.grid.cell
    }
}

/// Milliseconds spent in each phase of [`DistanceField::new`].
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct FieldTimings {
    /// Exact near band.
    pub band_ms: f64,
    /// Fast sweeping.
    pub sweep_ms: f64,
    /// Sign (flood fill and pseudo-normals; natively beside the sweep, so the phases overlap);
    /// 0 for unsigned fields.
    pub sign_ms: f64,
    /// Normalised negative gradient.
    pub gradient_ms: f64,
    /// Everything, including allocation.
    pub total_ms: f64,
}

/// A distance field on a regular grid with its normalised negative gradient.
#[derive(Clone, Debug)]
pub struct DistanceField {
    grid: Grid,
    values: Vec<f64>,
    gradient: Vec<[f32; 3]>,
    band: Vec<bool>,
    signedness: Signedness,
    /// Nodes made negative inside a cloud's enclosed solids ([`FieldSettings::enclosed_cells`]).
    enclosed: usize,
    sweep: fast_sweep::SweepReport,
    timings: FieldTimings,
}

impl DistanceField {
    /// Builds the field of `target` (point cloud or triangles) under `settings`.
    pub fn new(target: &Target, settings: &FieldSettings) -> Result<Self, FieldError> {
        Self::new_with_progress(target, settings, &mut Progress::none())
    }

    /// The grid the field of `target` is built on (a cloud's cells no finer than
    /// `min_cell_spacings` of its point spacings), and its reference length β_min.
    fn grid_for(target: &Target, settings: &FieldSettings) -> Result<(Grid, f64), FieldError> {
        // Recomputed rather than trusted: `Target`'s fields are public.
        let bbox = Aabb::from_points(&target.points);
        let beta = grid::reference_length_of(&target.points, settings.principal_slack);
        let mut grid = Grid::for_box(&bbox, beta, settings)?;
        let spacing = (settings.min_cell_spacings > 0.0).then(|| target.oracle().spacing());
        if let Some(spacing) = spacing.flatten() {
            let floor = settings.min_cell_spacings * spacing;
            if grid.cell < floor {
                let n = ((beta / floor).floor() as u32).clamp(2, settings.cells_per_min_dimension);
                let coarse = FieldSettings {
                    cells_per_min_dimension: n,
                    ..settings.clone()
                };
                grid = Grid::for_box(&bbox, beta, &coarse)?;
            }
        }
        Ok((grid, beta))
    }

    /// The cell size the field of `target` will have, known before it is built (None where the
    /// build would fail). (A cloud's follows its point spacing, which is remembered for the build
    /// on this thread.)
    pub fn planned_cell_size(target: &Target, settings: &FieldSettings) -> Option<f64> {
        Self::plan(target, settings).ok().map(|p| p.cell_size())
    }

    /// Checks `target` and `settings` and lays out the grid the field will have, for
    /// [`DistanceField::new_planned`]: a caller that needs the cell size before the field (the
    /// evolver, to build the fit's grid beside it) lays it out once (the principal box of a
    /// million points is six passes over them).
    pub fn plan(target: &Target, settings: &FieldSettings) -> Result<FieldPlan, FieldError> {
        settings.check()?;
        if target.points.is_empty() {
            return Err(FieldError::EmptyTarget);
        }
        if let Some(index) = target.points.iter().position(|p| !p.is_finite()) {
            return Err(FieldError::NonFinite { index });
        }
        let n = target.points.len();
        if let Some(triangle) = target
            .triangles
            .iter()
            .position(|t| t.iter().any(|&v| v as usize >= n))
        {
            return Err(FieldError::BadTriangle { triangle });
        }
        let (grid, beta) = Self::grid_for(target, settings)?;
        Ok(FieldPlan { grid, beta })
    }

    /// [`DistanceField::new`], reporting the near band (the long part on big inputs) per item and
    /// the sweep, sign and gradient as they finish.
    pub fn new_with_progress(
        target: &Target,
        settings: &FieldSettings,
        progress: &mut Progress,
    ) -> Result<Self, FieldError> {
        let plan = Self::plan(target, settings)?;
        Self::new_planned(target, settings, plan, progress)
    }

    /// [`DistanceField::new_with_progress`] on the grid `plan` laid out for this `target` and
    /// these `settings`.
    pub fn new_planned(
        target: &Target,
        settings: &FieldSettings,
        plan: FieldPlan,
        progress: &mut Progress,
    ) -> Result<Self, FieldError> {
        let t0 = crate::clock::now_ms();
        let FieldPlan { grid, beta } = plan;
        let init = settings.truncation.map_or(f64::INFINITY, |t| t * beta);

        let t1 = crate::clock::now_ms();
        let oracle = target.oracle();
        // (The band's own reports come after each batch: its start is announced here.)
        progress.report(band::PHASE, 0.0);
        let (cells, by_nodes) = (settings.band_cells, band::NODE_QUERY_TRIANGLES);
        let b = match oracle.surface() {
            Surface::Triangles { points, triangles } if triangles.len() >= by_nodes => {
                band::triangles_band_by_nodes(&grid, points, triangles, cells, init, progress)
            }
            Surface::Triangles { points, triangles } => {
                band::triangles_band(&grid, points, triangles, cells, init, progress)
            }
            Surface::Points(points) => band::points_band(&grid, points, cells, init, progress),
        };
        let band::Band {
            mut values,
            frozen,
            nearest_triangle,
        } = b;
        let t2 = crate::clock::now_ms();
        progress.report("distance field: sweeps", 0.0);
        // The sign reads only the band and the mesh: worked out beside the sweep, which fills
        // in the values away from the band on one thread.
        let ((signedness, inside, sign_ms), sweep) = crate::parallel::beside(
            || {
                let t = crate::clock::now_ms();
                let (kind, inside) = match (&nearest_triangle, settings.sign) {
                    (Some(nearest), SignMode::Auto) => sign::mesh_inside(
                        &grid,
                        &frozen,
                        nearest,
                        &target.points,
                        &target.triangles,
                    ),
                    _ => (Signedness::Unsigned, None),
                };
                (kind, inside, crate::clock::now_ms() - t)
            },
            || {
                fast_sweep::fast_sweep(
                    &grid,
                    &mut values,
                    &frozen,
                    settings.max_sweep_passes,
                    settings.sweep_tolerance,
                    &mut |f| progress.report("distance field: sweeps", f),
                )
            },
        );
        let t3 = crate::clock::now_ms();
        sign::negate_inside(&mut values, inside.as_deref());
        let enclosed = if oracle.has_inside() || settings.enclosed_cells == 0.0 {
            0
        } else {
            sign::negate_enclosed(&grid, &mut values, settings.enclosed_cells * grid.cell)
        };
        drop(nearest_triangle);
        let t4 = crate::clock::now_ms();
        progress.report("distance field: sweeps", 1.0);
        let gradient = gradient::normalized_negative_gradient(&grid, &values);
        let t5 = crate::clock::now_ms();
        Ok(Self {
            grid,
            values,
            gradient,
            band: frozen,
            signedness,
            enclosed,
            sweep,
            timings: FieldTimings {
                band_ms: t2 - t1,
                sweep_ms: t3 - t2,
                sign_ms: sign_ms + (t4 - t3),
                gradient_ms: t5 - t4,
                total_ms: t5 - t0,
            },
        })
    }

    /// Distance at `p` by trilinear interpolation; `p` is clamped into [`DistanceField::bbox`].
    #[inline]
    pub fn sample(&self, p: DVec3) -> f64 {
        sample::trilinear(&self.grid, &self.values, p)
    }

    /// Normalised negative gradient `−∇d/|∇d|` at `p`, trilinearly interpolated from the nodes
    /// (not renormalised, norm ≤ 1); `p` is clamped into the box.
    #[inline]
    pub fn sample_gradient(&self, p: DVec3) -> DVec3 {
        sample::trilinear_vec(&self.grid, &self.gradient, p)
    }

    /// [`Self::sample`] and [`Self::sample_gradient`] at once (one cell lookup); both values are
    /// the same values as from the separate calls.
    #[inline]
    pub fn sample_with_gradient(&self, p: DVec3) -> (f64, DVec3) {
        sample::trilinear_both(&self.grid, &self.values, &self.gradient, p)
    }

    /// Cell size c (node spacing).
    pub fn cell_size(&self) -> f64 {
        self.grid.cell
    }

    /// The box spanned by the nodes.
    pub fn bbox(&self) -> Aabb {
        self.grid.bbox()
    }

    /// Node counts (nx, ny, nz).
    pub fn dims(&self) -> [usize; 3] {
        self.grid.dims
    }

    /// The lattice (origin, cell size, dims).
    pub fn grid(&self) -> &Grid {
        &self.grid
    }

    /// Node values, index `ix + nx·(iy + ny·iz)` (see [`Grid`]).
    pub fn values(&self) -> &[f64] {
        &self.values
    }

    /// Node gradients `−∇d/|∇d|` (zero where undefined), same order as [`DistanceField::values`].
    pub fn gradients(&self) -> &[[f32; 3]] {
        &self.gradient
    }

    /// True for nodes of the exact near band (value = exact distance, up to the sign).
    pub fn band_mask(&self) -> &[bool] {
        &self.band
    }

    /// True when the field is signed (negative inside).
    pub fn is_signed(&self) -> bool {
        self.signedness != Signedness::Unsigned
    }

    /// How many nodes deep inside a cloud's enclosed solids are negative (0 for meshes).
    pub fn enclosed_nodes(&self) -> usize {
        self.enclosed
    }

    /// Which kind of field this is.
    pub fn signedness(&self) -> Signedness {
        self.signedness
    }

    /// How fast sweeping ended.
    pub fn sweep_report(&self) -> fast_sweep::SweepReport {
        self.sweep
    }

    /// Time per phase of construction.
    pub fn timings(&self) -> FieldTimings {
        self.timings
    }

    /// Smallest and largest node value.
    pub fn min_max(&self) -> (f64, f64) {
        self.values
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &v| {
                (a.min(v), b.max(v))
            })
    }

    /// Maps the field into a uniformly scaled frame `x' = φ·(x − center)`: the grid moves and
    /// shrinks/grows with it and distances are multiplied by φ (> 0); gradients, being unit
    /// directions, are unchanged. This is the stabilised frame of the flow [docs/method.md §3.2].
    pub fn scale_uniform(&mut self, center: DVec3, phi: f64) {
        assert!(
            phi > 0.0 && phi.is_finite(),
            "scale factor must be positive"
        );
        self.grid.origin = phi * (self.grid.origin - center);
        self.grid.cell *= phi;
        for v in &mut self.values {
            *v *= phi;
        }
    }

    /// The isosurface `d = iso` (closed, oriented, welded; see
    /// [`crate::geometry::marching_cubes`]) as positions and counter-clockwise triangles.
    pub fn isosurface(&self, iso: f64) -> (Vec<DVec3>, Vec<[u32; 3]>) {
        let view = crate::geometry::marching_cubes::ScalarGridView {
            first: [0; 3],
            origin: self.grid.origin,
            cell: self.grid.cell,
            dims: self.grid.dims,
            values: &self.values,
        };
        crate::geometry::marching_cubes::marching_cubes(&view, iso)
    }

    /// The isosurface `d = iso` extracted on a lattice of cell size `factor·c` over the same box,
    /// with values resampled trilinearly [docs/method.md §5.3 step 1]; `factor = 1` is
    /// [`DistanceField::isosurface`]. `factor` > 1 gives fewer, larger triangles. `factor` is
    /// clamped to 0.5–16 (below 0.5 the resampled grid would hold over 8× the nodes); a
    /// non-finite factor counts as 1.
    pub fn isosurface_resampled(&self, iso: f64, factor: f64) -> (Vec<DVec3>, Vec<[u32; 3]>) {
        self.with_resampled(factor, iso, |view| {
            crate::geometry::marching_cubes::marching_cubes(view, iso)
        })
    }

    /// Like [`DistanceField::isosurface_resampled`], but only the boundary of the exterior region
    /// `{d ≥ iso}` connected to the grid's border (see [`exterior`]): never an inner sheet.
    pub fn exterior_isosurface_resampled(
        &self,
        iso: f64,
        factor: f64,
    ) -> (Vec<DVec3>, Vec<[u32; 3]>) {
        self.with_resampled(factor, iso, |view| exterior::exterior_isosurface(view, iso))
    }

    /// Calls `f` on the field's values resampled at cell size `factor·c` (see
    /// [`DistanceField::isosurface_resampled`] for the clamp), for the level set `d = iso`.
    ///
    /// Only the window of the resampled lattice around the nodes below `iso` is sampled (the
    /// icosphere's padded box is mostly far from the target). The window keeps the lattice's origin
    /// (see [`ScalarGridView::first`](crate::geometry::marching_cubes::ScalarGridView)), and every
    /// node outside it is ≥ `iso` and linked to the border, so the (exterior) isosurface is the
    /// same, bit for bit, as over the whole lattice.
    fn with_resampled<R>(
        &self,
        factor: f64,
        iso: f64,
        f: impl FnOnce(&crate::geometry::marching_cubes::ScalarGridView) -> R,
    ) -> R {
        let factor = if factor.is_finite() {
            factor.clamp(0.5, 16.0)
        } else {
            1.0
        };
        if factor == 1.0 {
            return f(&crate::geometry::marching_cubes::ScalarGridView {
                first: [0; 3],
                origin: self.grid.origin,
                cell: self.grid.cell,
                dims: self.grid.dims,
                values: &self.values,
            });
        }
        let g = Grid::covering(self.bbox(), factor * self.grid.cell);
        let sample_window = |first: [usize; 3], dims: [usize; 3]| -> Vec<f64> {
            let n = dims[0] * dims[1] * dims[2];
            (0..n)
                .map(|i| {
                    let (x, y, z) = (i % dims[0], i / dims[0] % dims[1], i / (dims[0] * dims[1]));
                    self.sample(g.node_position(x + first[0], y + first[1], z + first[2]))
                })
                .collect()
        };
        let window = self.window_below(iso, &g).and_then(|(first, dims)| {
            let values = sample_window(first, dims);
            // The bound on the window's border holds up to rounding in the interpolation: if it
            // did not hold, the whole lattice.
            window_border_at_or_above(&values, dims, iso).then_some((first, dims, values))
        });
        let (first, dims, values) =
            window.unwrap_or_else(|| ([0; 3], g.dims, sample_window([0; 3], g.dims)));
        f(&crate::geometry::marching_cubes::ScalarGridView {
            first,
            origin: g.origin,
            cell: g.cell,
            dims,
            values: &values,
        })
    }

    /// The window (first node, node counts) of lattice `g` outside which every resampled value
    /// is ≥ `iso`: the cells around field nodes below `iso` (a hair above it, against rounding in
    /// the interpolation), one node more on every side. None when it reaches the lattice's border
    /// or no node is below `iso`.
    fn window_below(&self, iso: f64, g: &Grid) -> Option<([usize; 3], [usize; 3])> {
        let bound = iso + 1e-6 * self.grid.cell;
        let (mut lo, mut hi) = ([usize::MAX; 3], [0usize; 3]);
        for (i, &v) in self.values.iter().enumerate() {
            if v < bound || v.is_nan() {
                let c = self.grid.coords(i);
                for k in 0..3 {
                    lo[k] = lo[k].min(c[k]);
                    hi[k] = hi[k].max(c[k]);
                }
            }
        }
        if lo[0] == usize::MAX {
            return None;
        }
        let (c, r) = (self.grid.cell, g.cell);
        let mut first = [0; 3];
        let mut dims = [0; 3];
        for k in 0..3 {
            // Field cells touching such a node span nodes lo − 1 ..= hi + 1; the resampled nodes
            // within, plus one on each side (the border, all ≥ iso).
            let a = ((lo[k] as f64 - 1.0) * c / r).floor() - 1.0;
            let b = ((hi[k] as f64 + 1.0) * c / r).ceil() + 1.0;
            if a < 1.0 || b > (g.dims[k] - 2) as f64 {
                return None;
            }
            first[k] = a as usize;
            dims[k] = (b - a) as usize + 1;
        }
        Some((first, dims))
    }

    /// A copy of the field in the scaled frame (see [`DistanceField::scale_uniform`]).
    pub fn scaled(&self, center: DVec3, phi: f64) -> Self {
        let mut f = self.clone();
        f.scale_uniform(center, phi);
        f
    }
}

/// True when every node on the border of a `dims` block of `values` is ≥ `iso`.
fn window_border_at_or_above(values: &[f64], dims: [usize; 3], iso: f64) -> bool {
    let [nx, ny, nz] = dims;
    (0..values.len()).all(|i| {
        let (x, y, z) = (i % nx, i / nx % ny, i / (nx * ny));
        let border = x == 0 || y == 0 || z == 0 || x + 1 == nx || y + 1 == ny || z + 1 == nz;
        !border || values[i] >= iso
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::marching_cubes::{marching_cubes, ScalarGridView};

    /// The start's isosurface over the window around the target is the one over the whole
    /// resampled lattice, bit for bit (a closed mesh, signed, and a cloud, unsigned).
    #[test]
    fn the_windowed_isosurface_is_the_whole_lattices() {
        let (torus, tris) = crate::demo::shape("torus-g2").unwrap();
        let cloud = crate::demo::shape("torus-g1-cloud").unwrap().0;
        for target in [
            Target::new(torus, tris).unwrap(),
            Target::new(cloud, vec![]).unwrap(),
        ] {
            let field = DistanceField::new(&target, &FieldSettings::default()).unwrap();
            let (iso, factor) = (1.5 * field.cell_size(), 1.5);
            let g = Grid::covering(field.bbox(), factor * field.cell_size());
            let (first, dims) = field.window_below(iso, &g).expect("a window");
            assert!(
                dims[0] * dims[1] * dims[2] < g.node_count() / 2,
                "{dims:?} of {:?}",
                g.dims
            );
            assert!(first.iter().all(|&f| f > 0));
            let all: Vec<f64> = (0..g.node_count())
                .map(|i| field.sample(g.position_of(i)))
                .collect();
            let view = ScalarGridView {
                first: [0; 3],
                origin: g.origin,
                cell: g.cell,
                dims: g.dims,
                values: &all,
            };
            let whole = exterior::exterior_isosurface(&view, iso);
            assert!(!whole.1.is_empty());
            assert_eq!(field.exterior_isosurface_resampled(iso, factor), whole);
            assert_eq!(
                field.isosurface_resampled(iso, factor),
                marching_cubes(&view, iso)
            );
        }
    }
}
