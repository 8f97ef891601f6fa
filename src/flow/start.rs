//! The start surface, scaled into the stabilised frame (spec §3, §5): an icosphere around the
//! target, or the boundary of the field's exterior region `d ≥ d_iso` plus one remesh.
//!
//! Both are free of self-intersections by construction (a remesh that would break that is
//! dropped), so the contact guard of every later step starts from a clean surface.

use super::evolver::EvolveError;
use super::scaling;
use super::settings::{StartSurface, WrapSettings};
use crate::field::DistanceField;
use crate::geometry::icosphere::icosphere;
use crate::geometry::spatial::spacing::median_spacing;
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
            let mesh = icosphere(settings.start.icosphere_level, phi * r, DVec3::ZERO)?;
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
            if !field.is_signed() && target.triangles.is_empty() {
                // A cloud: the exterior must not leak through the gaps between its points, which
                // reach about three median spacings in a random sampling.
                iso = iso.max(ISO_SPACINGS * median_spacing(&target.points));
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
            // One remesh with back-projection onto the marching-cubes surface (spec §5.3). If it
            // leaves intersecting faces the start is refused: the raw marching-tetrahedra surface
            // is full of slivers on which the flow is not stable (measured: it blows up within a
            // few steps), and this happens where the exterior leaked into narrow channels.
            let rs = RemeshSettings {
                iterations: 1,
                use_projection: true,
                smoothing_iterations: settings.remesh.smoothing_iterations,
                features: settings.remesh.features.clone(),
                ..RemeshSettings::with_sizes(sizes)
            };
            remesh(&mut mesh, &rs)?;
            let pairs = count_self_intersections(mesh.positions(), &mesh.triangles());
            if settings.guard.contact && pairs > 0 {
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
