//! Why a wrap could not start or continue: the one error of the evolution, its start and its
//! steps (a module of its own so that the start surface and the evolver both name it).

use crate::field::FieldError;
use crate::flow::guard::Divergence;
use crate::geometry::icosphere::IcosphereError;
use crate::mesh::MeshBuildError;
use crate::remesh::adaptive::RemeshError;

/// Why a wrap could not start or continue.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum EvolveError {
    /// A setting is out of range. Fix: see the named setting's documentation.
    #[error(transparent)]
    Setting(#[from] crate::flow::settings::SettingError),
    /// The target cannot be wrapped (too few points, flat, zero area): see the variant.
    #[error(transparent)]
    Target(#[from] crate::target::TargetError),
    /// The distance field could not be built (empty or degenerate target, too fine a grid).
    #[error("distance field: {0}")]
    Field(#[from] FieldError),
    /// The icosphere could not be built.
    #[error(transparent)]
    Icosphere(#[from] IcosphereError),
    /// The marching-cubes start surface is empty: no grid node lies below d_iso.
    #[error("the isosurface d = {iso:.4} is empty; raise start.isosurface_level_cells")]
    EmptyIsosurface { iso: f64 },
    /// The isosurface start intersects itself after its remesh: its exterior leaked into narrow
    /// channels (typically through gaps in a point cloud). Fix: use the icosphere start (or auto).
    #[error("the isosurface start is not usable here: after remeshing, {pairs} pairs of its faces intersect (start genus {genus}; the exterior leaked through gaps in the input); use --start icosphere or auto")]
    StartIntersects { pairs: usize, genus: i64 },
    /// The marching-cubes start surface is not a manifold mesh.
    #[error("the isosurface start is not a manifold mesh: {0}")]
    StartMesh(#[from] MeshBuildError),
    /// The remesher refused its sizes.
    #[error(transparent)]
    Remesh(#[from] RemeshError),
    /// The step showed a sign of divergence; the surface was rolled back to the last state the
    /// contact guard certified (`previous`) and the evolution stopped. Fix: a smaller τ, or
    /// report the input.
    #[error("the evolution diverged at step {step} ({reason}); rolled back to step {previous}")]
    Divergence {
        step: u32,
        previous: u32,
        reason: Divergence,
    },
    /// A step's solve failed even after `retries` retries (non-negative weights, then τ halved;
    /// `tau` is the last one tried): the surface is the last certified one and the evolution
    /// stopped.
    #[error("the solve diverged at step {step} after {retries} retries (τ {tau:.3e} at the last): {cause}")]
    Diverged {
        step: u32,
        retries: u32,
        tau: f64,
        cause: String,
    },
}
