//! The start surface, scaled into the stabilised frame (docs/method.md §3, §5): an icosphere around
//! the target, or the boundary of the field's exterior region `d ≥ d_iso` plus one remesh.
//!
//! Both are free of self-intersections by construction (a remesh that would break that is
//! dropped), so the contact guard of every later step starts from a clean surface.

use super::evolve_error::EvolveError;
use super::scaling;
use super::settings::{StartSurface, WrapSettings};
use crate::field::DistanceField;
use crate::geometry::aabb::Aabb;
use crate::geometry::icosphere::icosphere;
use crate::geometry::spatial::parts::parts_apart;
use crate::mesh::HalfedgeMesh;
use crate::metrics::intersections::count_self_intersections;
use crate::remesh::adaptive::{remesh, RemeshSettings};
use crate::remesh::sizing::{icosphere_sizes, isosurface_sizes, EdgeSizes};
use crate::target::Target;
use glam::DVec3;

/// The isosurface start on a point cloud sits at least this many median point spacings out.
pub const ISO_SPACINGS: f64 = 3.0;

/// A start surface in the stabilised frame.
pub struct Start {
    /// The surface (centred on the target's box centre, scaled by `phi`).
    pub mesh: HalfedgeMesh,
    /// The stabilisation factor φ.
    pub phi: f64,
    /// Target edge lengths for the remesher (stabilised frame).
    pub sizes: EdgeSizes,
    /// The start actually built (never `Auto`).
    pub kind: StartSurface,
}

/// The icosphere start's radius: around the target's box.
fn icosphere_radius(target: &Target, settings: &WrapSettings) -> f64 {
    let size = target.bbox.size();
    let (bmin, bmax) = (size.min_element(), size.max_element());
    settings.start.icosphere_radius_factor * 0.4 * (bmin + 1.5 * bmax)
}

/// One icosphere per part of a point cloud whose parts lie apart (centre and radius, target units:
/// [`PART_ROOM`] times the farthest point of the part from its box's centre), or `None` for one
/// around the whole target. A single sphere shrinking onto two objects set apart leaves a neck
/// between them that must pinch in empty space, and a ragged neck often cannot be cut, so the wrap
/// stays one part. Parts are [`parts_apart`] at `tuning.start.part_gap` of the diagonal; each must hold
/// [`PART_POINTS`] points and the spheres must not overlap, else one sphere as the method has it.
fn spheres_apart(target: &Target, settings: &WrapSettings) -> Option<Vec<(DVec3, f64)>> {
    let share = settings.tuning.start.part_gap;
    if !target.oracle().splits_start_by_parts() || share <= 0.0 {
        return None;
    }
    let points = &target.points;
    let gap = share * target.bbox.size().length();
    let (labels, parts) = parts_apart(points, gap)?;
    if !(2..=MOST_PARTS).contains(&parts) {
        return None;
    }
    let mut boxes = vec![Aabb::EMPTY; parts];
    let mut counts = vec![0usize; parts];
    for (p, &l) in points.iter().zip(&labels) {
        boxes[l as usize] = boxes[l as usize].grow(*p);
        counts[l as usize] += 1;
    }
    if counts.iter().any(|&c| c < PART_POINTS) {
        return None;
    }
    let mut reach = vec![0.0f64; parts];
    for (p, &l) in points.iter().zip(&labels) {
        let l = l as usize;
        reach[l] = reach[l].max(p.distance(boxes[l].center()));
    }
    let factor = settings.start.icosphere_radius_factor * PART_ROOM;
    let spheres: Vec<(DVec3, f64)> = boxes
        .iter()
        .zip(&reach)
        .map(|(b, &r)| (b.center(), factor * r))
        .collect();
    let apart = spheres.iter().enumerate().all(|(i, &(a, ra))| {
        spheres[i + 1..]
            .iter()
            .all(|&(b, rb)| a.distance(b) > SPHERE_ROOM * (ra + rb))
    });
    (apart && spheres.iter().all(|&(_, r)| r > 0.0)).then_some(spheres)
}

/// Each part holds at least this many points (as many as the smallest cloud a wrap takes, see
/// `target::MIN_CLOUD_POINTS`; fewer: one sphere as the method has it).
pub const PART_POINTS: usize = crate::target::MIN_CLOUD_POINTS;
/// At most this many parts get a sphere each.
pub const MOST_PARTS: usize = 16;
/// A part's sphere reaches this many times its farthest point (an icosphere's faces dip inside
/// its vertices' sphere, and a start with room costs a few steps at most).
pub const PART_ROOM: f64 = 1.2;
/// The spheres' centres are farther apart than this times the sum of their radii.
const SPHERE_ROOM: f64 = 1.05;

/// The stabilisation factor φ of the start [`build_start`] builds under `settings` on a field
/// of cells of size `cell` (known before either is built, so that what the fit needs in the
/// stabilised frame can be built beside them).
pub fn start_scale(target: &Target, cell: f64, settings: &WrapSettings) -> f64 {
    let (tau, shrink) = (settings.flow.tau, settings.flow.shrink_factor);
    match settings.start.surface {
        StartSurface::Auto | StartSurface::Icosphere => scaling::icosphere_scale(
            tau,
            shrink,
            icosphere_radius(target, settings),
            settings.start.icosphere_level,
        ),
        StartSurface::Isosurface => {
            let c_r = settings.start.isosurface_resampling * cell;
            scaling::isosurface_scale(tau, shrink, c_r)
        }
    }
}

/// Builds the start surface of `settings.start` (`Auto` counts as icosphere: resolve it first
/// with [`WrapSettings::resolved_for`]); `field` is in the target's frame.
pub fn build_start(
    target: &Target,
    field: &DistanceField,
    settings: &WrapSettings,
) -> Result<Start, EvolveError> {
    let center = target.bbox.center();
    let c = field.cell_size();
    match settings.start.surface {
        StartSurface::Auto | StartSurface::Icosphere => {
            let r = icosphere_radius(target, settings);
            let phi = start_scale(target, field.cell_size(), settings);
            let level = settings.start.icosphere_level;
            let mesh = match spheres_apart(target, settings) {
                Some(spheres) => {
                    let (mut p, mut t) = (Vec::new(), Vec::new());
                    for (c, rk) in spheres {
                        let m = icosphere(level, phi * rk, phi * (c - center))?;
                        let o = p.len() as u32;
                        t.extend(m.triangles().into_iter().map(|f| f.map(|v| v + o)));
                        p.extend_from_slice(m.positions());
                    }
                    HalfedgeMesh::from_triangles(p, &t)?
                }
                None => icosphere(level, phi * r, DVec3::ZERO)?,
            };
            let sizes = icosphere_sizes(
                settings.remesh.min_edge_multiplier,
                phi * r,
                settings.start.icosphere_level,
            );
            Ok(Start {
                mesh,
                phi,
                sizes,
                kind: StartSurface::Icosphere,
            })
        }
        StartSurface::Isosurface => {
            let d0 = settings.flow.iso_level_factor * 0.5 * 3f64.sqrt() * c;
            let mut iso = settings.start.isosurface_level_cells * c;
            if iso <= d0 {
                iso = 1.1 * d0;
            }
            // Unsigned, the exterior must not leak through the gaps between a sampling's points,
            // which reach about three median spacings in a random sampling.
            if let (false, Some(spacing)) = (field.is_signed(), target.oracle().spacing()) {
                iso = iso.max(ISO_SPACINGS * spacing);
            }
            let c_r = settings.start.isosurface_resampling * c;
            let (pos, tris) =
                field.exterior_isosurface_resampled(iso, settings.start.isosurface_resampling);
            if tris.is_empty() {
                return Err(EvolveError::EmptyIsosurface { iso });
            }
            let phi = start_scale(target, field.cell_size(), settings);
            let scaled: Vec<DVec3> = pos.into_iter().map(|p| phi * (p - center)).collect();
            let mut mesh = HalfedgeMesh::from_triangles(scaled, &tris)?;
            let sizes = isosurface_sizes(settings.remesh.min_edge_multiplier, c_r, phi);
            // One remesh with back-projection onto the marching-cubes surface (docs/method.md
            // §5.3). If it leaves intersecting faces the start is refused: the raw
            // marching-tetrahedra surface is full of slivers on which the flow is not stable (it
            // blows up within a few steps), and this happens where the exterior leaked into
            // narrow channels.
            let rs = RemeshSettings {
                iterations: 1,
                use_projection: true,
                smoothing_iterations: settings.remesh.smoothing_iterations,
                features: settings.tuning.remesh.features.clone(),
                ..RemeshSettings::with_sizes(sizes)
            };
            remesh(&mut mesh, &rs)?;
            let pairs = count_self_intersections(mesh.positions(), &mesh.triangles());
            if settings.tuning.guard.contact && pairs > 0 {
                let genus = mesh.validate().map(|r| r.genus).unwrap_or(-1);
                return Err(EvolveError::StartIntersects { pairs, genus });
            }
            Ok(Start {
                mesh,
                phi,
                sizes,
                kind: StartSurface::Isosurface,
            })
        }
    }
}
