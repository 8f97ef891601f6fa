//! Surface evolution: the discrete operators and the semi-implicit time steps.

pub mod colour;
pub mod controls;
pub mod detail;
pub mod evolve_error;
pub mod evolver;
pub mod fit;
pub mod guard;
pub(crate) mod guarded;
pub mod mcf;
pub mod mcf_mesh;
pub mod regrow;
pub mod scaling;
pub mod settings;
pub mod snap;
pub mod start;
pub mod surface_terms;
pub mod surgery;
pub mod tangential;

pub use colour::{ColourMap, ColourMapInfo, COLOUR_MAPS, LESSON_COLOUR_MAPS};
pub use evolver::{
    CreaseJob, EvolveError, Evolver, PhaseTimes, StartedOver, StepReport, ThirdPass,
};
pub use fit::{FitOptions, FitReport, FitTimes};
pub use mcf::{exact_sphere_radius, mcf_step, McfSettings, McfStepReport, TauAdvice};
pub use mcf_mesh::{LessonInfo, MeshFlow, MeshFlowStats, MeshMcfError, MeshTauAdvice, LESSONS};
pub use settings::{
    FitSettings, FlowSettings, Preset, RemeshTrigger, RemeshingSettings, StartSettings,
    StartSurface, StopSettings, WrapSettings,
};

use crate::solve::SolveError;

/// Why a flow step failed.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum FlowError {
    /// The time step is not a positive finite number.
    #[error("time step τ must be positive and finite, got {0}")]
    BadTimeStep(f64),
    /// The linear solve failed (the step was not applied).
    #[error("linear solve failed: {0}")]
    Solve(#[from] SolveError),
    /// The new positions contain NaN or infinity (the step was not applied).
    #[error("the step produced a non-finite position at vertex {vertex}")]
    NonFinite { vertex: usize },
    /// A step of the sphere lesson would reach the sphere's extinction time r0²/4, where the
    /// exact radius r(t) = sqrt(r0² − 4t) no longer exists.
    #[error(
        "the sphere vanishes at t = r0²/4 = {extinction}: a step of τ = {tau} from t = {time} \
         would reach it"
    )]
    PastExtinction {
        time: f64,
        tau: f64,
        extinction: f64,
    },
}
