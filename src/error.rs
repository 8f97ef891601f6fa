//! What the core's errors mean to a user: [`Explain`] gives every error type a stable code from
//! [`CODES`] and a hint (what to try); the message is the error's `Display`. The wasm facade turns
//! any `E: Explain + Display` into `{code, message, hint}` with one function, and the CLI prints
//! `error: <message>` and `hint: <hint>`.
//!
//! The impls live here, not next to the error types, so the types stay plain `thiserror` enums
//! and the user-facing wording is in one file. The codes and hints are those the app has shown
//! since its first release; lists inside hints (formats, demo shapes) derive from their catalogs.

use crate::demo::DemoError;
use crate::field::FieldError;
use crate::flow::guard::Divergence;
use crate::flow::settings::SettingError;
use crate::flow::{EvolveError, FlowError, MeshMcfError};
use crate::geometry::icosphere::IcosphereError;
use crate::io::formats::join_list;
use crate::io::IoError;
use crate::mesh::{MeshBuildError, ValidationError};
use crate::remesh::adaptive::RemeshError;
use crate::solve::SolveError;
use crate::target::TargetError;
use std::sync::OnceLock;

/// An error a user can act on: a stable code (one of [`CODES`]) and a one-sentence hint.
/// The message is the error's `Display`.
pub trait Explain {
    /// Stable machine code, one of [`CODES`] (the app branches on some, e.g. `internal`).
    fn code(&self) -> &'static str;
    /// What the user can do about it: one sentence.
    fn hint(&self) -> &'static str;
}

/// Every code [`Explain::code`] returns.
///
/// * `bad-parameter` — a setting or argument out of range; `bad-file` — a file LSW cannot read;
/// * `bad-target` — what was read cannot be wrapped (empty, flat, degenerate);
/// * `bad-start` — the isosurface start surface failed; `too-large` — over a memory cap;
/// * `solve-failed`, `diverged` — the numerics failed (the surface is kept at its last good
///   state); `internal` — a bug (the app restarts its worker).
pub const CODES: &[&str] = &[
    "bad-parameter",
    "bad-file",
    "bad-target",
    "bad-start",
    "too-large",
    "solve-failed",
    "diverged",
    "internal",
];

/// The hint for settings out of range or unreadable settings JSON.
pub const SETTINGS_HINT: &str = "Reset the advanced settings or pick a preset.";
/// The hint for a grid over the memory cap.
const TOO_LARGE_HINT: &str = "Lower the grid resolution (cells per minimum dimension).";
/// The hint when the distance field has nothing to measure from.
const FIELD_TARGET_HINT: &str =
    "The target needs points spread in 3D (not empty, not a single point or a flat sheet).";
/// The hint for a target the flow cannot wrap.
const TARGET_HINT: &str = "The target needs at least 4 points spread in 3-D: not a single point, a line or a flat sheet (a thin plate with some thickness is fine).";
/// The hint for a failed start surface.
const START_HINT: &str = "Raise the isosurface level, or use the icosphere start.";
/// The hint for a divergence (the evolver rolls back and stops).
const DIVERGED_HINT: &str = "The surface was rolled back to the last good step. Lower the time step τ, or pick the full-wrap preset.";
/// The hint for a failed or non-finite step of the MCF demo.
const STEP_HINT: &str = "Reduce the time step τ and reset.";
/// The hint for a bug.
const INTERNAL_HINT: &str = "Try another preset; if it persists, report a bug with the share link.";

impl Explain for IcosphereError {
    fn code(&self) -> &'static str {
        "bad-parameter"
    }
    fn hint(&self) -> &'static str {
        "Use a subdivision level from 0 to 7 and a positive radius."
    }
}

impl Explain for SolveError {
    fn code(&self) -> &'static str {
        "solve-failed"
    }
    fn hint(&self) -> &'static str {
        STEP_HINT
    }
}

impl Explain for FlowError {
    fn code(&self) -> &'static str {
        match self {
            FlowError::BadTimeStep(_) => "bad-parameter",
            FlowError::Solve(e) => e.code(),
            FlowError::NonFinite { .. } => "diverged",
            FlowError::PastExtinction { .. } => "bad-parameter",
        }
    }
    fn hint(&self) -> &'static str {
        match self {
            FlowError::BadTimeStep(_) => "Choose a positive time step τ.",
            FlowError::Solve(e) => e.hint(),
            FlowError::NonFinite { .. } => STEP_HINT,
            FlowError::PastExtinction { .. } => {
                "Choose a smaller time step τ: the lesson must stop before the sphere vanishes."
            }
        }
    }
}

/// The mesh lesson (MCF on a loaded mesh): a mesh it cannot flow, or a failed step.
impl Explain for MeshMcfError {
    fn code(&self) -> &'static str {
        match self {
            MeshMcfError::Empty { .. }
            | MeshMcfError::Ragged { .. }
            | MeshMcfError::NonFinite { .. }
            | MeshMcfError::NotManifold(_)
            | MeshMcfError::NoExtent { .. } => "bad-target",
            MeshMcfError::BadTimeStep(_) => "bad-parameter",
            MeshMcfError::Step { source, .. } => source.code(),
        }
    }
    fn hint(&self) -> &'static str {
        match self {
            MeshMcfError::Empty { .. } | MeshMcfError::Ragged { .. } => {
                "Load a triangle mesh first (a point cloud or a volume has no triangles to flow)."
            }
            MeshMcfError::NonFinite { .. } | MeshMcfError::NoExtent { .. } => {
                "The mesh needs finite coordinates spread in space: clean it, or load another."
            }
            MeshMcfError::NotManifold(_) => {
                "MCF needs a manifold, consistently oriented mesh: repair it, or wrap it and flow the result."
            }
            MeshMcfError::BadTimeStep(_) => "Choose a positive time step τ/D².",
            MeshMcfError::Step { .. } => {
                "The mesh was kept at its last good step. Reduce the time step τ/D² and reset."
            }
        }
    }
}

/// The app's codes and hints for files: every reading failure is `bad-file`. (`IoError` also
/// has inherent `code()`/`hint()` with finer `io_*` codes, used by the IO tests; call
/// `Explain::code(&e)` to get these.)
impl Explain for IoError {
    fn code(&self) -> &'static str {
        "bad-file"
    }
    fn hint(&self) -> &'static str {
        match self {
            IoError::Empty { .. } => "The file is empty: choose another file.",
            IoError::UnknownFormat { .. } => crate::io::formats::use_formats_hint(),
            IoError::Fs { .. } => "Check the path and the file permissions.",
            IoError::NotWritable { .. } => crate::io::formats::name_output_hint(),
            _ => "The file looks damaged or is not what its name says; re-export it from its source program.",
        }
    }
}

impl Explain for SettingError {
    fn code(&self) -> &'static str {
        "bad-parameter"
    }
    fn hint(&self) -> &'static str {
        SETTINGS_HINT
    }
}

impl Explain for FieldError {
    fn code(&self) -> &'static str {
        match self {
            FieldError::TooLarge { .. } => "too-large",
            FieldError::InvalidSetting { .. } => "bad-parameter",
            FieldError::EmptyTarget
            | FieldError::DegenerateTarget
            | FieldError::NonFinite { .. }
            | FieldError::BadTriangle { .. } => "bad-target",
        }
    }
    fn hint(&self) -> &'static str {
        match self {
            FieldError::TooLarge { .. } => TOO_LARGE_HINT,
            FieldError::InvalidSetting { .. } => "Use a value in the range the message gives.",
            FieldError::EmptyTarget
            | FieldError::DegenerateTarget
            | FieldError::NonFinite { .. }
            | FieldError::BadTriangle { .. } => FIELD_TARGET_HINT,
        }
    }
}

impl Explain for TargetError {
    fn code(&self) -> &'static str {
        "bad-target"
    }
    fn hint(&self) -> &'static str {
        match self {
            TargetError::NoIsosurface { .. } => {
                "Choose an iso-value strictly between the volume's minimum and maximum."
            }
            TargetError::Empty
            | TargetError::NonFinite { .. }
            | TargetError::IndexOutOfRange { .. }
            | TargetError::TooFewPoints { .. }
            | TargetError::Collinear { .. }
            | TargetError::Coplanar { .. }
            | TargetError::ZeroArea { .. } => TARGET_HINT,
            TargetError::SparseCloud { .. } => {
                "Give a denser scan of the object (a mesh with few vertices is fine)."
            }
            TargetError::FarFromOrigin { .. } => {
                "Translate the input near the origin (subtract its centre) and wrap it again."
            }
        }
    }
}

impl Explain for Divergence {
    fn code(&self) -> &'static str {
        "diverged"
    }
    fn hint(&self) -> &'static str {
        DIVERGED_HINT
    }
}

/// A triangle list that is not a manifold surface (a start surface, or a mesh to measure).
impl Explain for MeshBuildError {
    fn code(&self) -> &'static str {
        "bad-target"
    }
    fn hint(&self) -> &'static str {
        "The triangles do not form a manifold, consistently oriented surface: repair the mesh, or wrap it to get one."
    }
}

/// A mesh that fails [`crate::mesh::HalfedgeMesh::validate`].
impl Explain for ValidationError {
    fn code(&self) -> &'static str {
        "bad-target"
    }
    fn hint(&self) -> &'static str {
        "The mesh is not a closed, manifold surface with finite, non-degenerate faces: wrap it to get one."
    }
}

/// The remesher's refusals are caller bugs (the flow passes it sizes it computed).
impl Explain for RemeshError {
    fn code(&self) -> &'static str {
        "internal"
    }
    fn hint(&self) -> &'static str {
        INTERNAL_HINT
    }
}

impl Explain for EvolveError {
    fn code(&self) -> &'static str {
        match self {
            EvolveError::Setting(e) => e.code(),
            EvolveError::Target(e) => e.code(),
            EvolveError::Field(e) => e.code(),
            EvolveError::EmptyIsosurface { .. }
            | EvolveError::StartMesh(_)
            | EvolveError::StartIntersects { .. } => "bad-start",
            EvolveError::Divergence { .. } | EvolveError::Diverged { .. } => "diverged",
            EvolveError::Icosphere(_) | EvolveError::Remesh(_) => "internal",
        }
    }
    fn hint(&self) -> &'static str {
        match self {
            EvolveError::Setting(e) => e.hint(),
            EvolveError::Target(e) => e.hint(),
            EvolveError::Field(e) => e.hint(),
            EvolveError::EmptyIsosurface { .. }
            | EvolveError::StartMesh(_)
            | EvolveError::StartIntersects { .. } => START_HINT,
            EvolveError::Divergence { .. } | EvolveError::Diverged { .. } => DIVERGED_HINT,
            EvolveError::Icosphere(_) | EvolveError::Remesh(_) => INTERNAL_HINT,
        }
    }
}

impl Explain for DemoError {
    fn code(&self) -> &'static str {
        "bad-parameter"
    }
    fn hint(&self) -> &'static str {
        match self {
            DemoError::UnknownShape(_) => {
                static TEXT: OnceLock<String> = OnceLock::new();
                TEXT.get_or_init(|| format!("Use {}.", join_list(&crate::demo::SHAPES, "or")))
            }
            DemoError::BadMesh(_) => "Pass a triangle mesh with non-degenerate faces.",
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::io::{Format, Location};
    use std::fmt::Display;

    /// Checks one sample per variant: a code from [`CODES`], a sentence as hint, a message.
    /// `variant` must be an exhaustive match (no `_`) naming the variant, so a new variant does
    /// not compile until it has a sample here.
    fn check<E: Explain + Display>(samples: &[E], variant: fn(&E) -> &'static str) {
        let mut seen = std::collections::BTreeSet::new();
        for e in samples {
            let name = variant(e);
            assert!(seen.insert(name), "two samples of {name}");
            assert!(CODES.contains(&e.code()), "{name}: code {}", e.code());
            let hint = e.hint();
            assert!(
                hint.len() > 10 && hint.ends_with('.'),
                "{name}: hint {hint:?}"
            );
            assert!(!e.to_string().is_empty(), "{name}: no message");
        }
    }

    #[test]
    fn every_variant_has_a_known_code_and_a_hint() {
        use EvolveError as V;
        let setting = || SettingError {
            name: "tau",
            value: -1.0,
            range: "> 0",
        };
        check(
            &[
                IcosphereError::LevelTooHigh(9),
                IcosphereError::BadRadius(0.0),
            ],
            |e| match e {
                IcosphereError::LevelTooHigh(_) => "LevelTooHigh",
                IcosphereError::BadRadius(_) => "BadRadius",
            },
        );
        let solve = [
            SolveError::Dimension {
                rows: 1,
                cols: 1,
                len: 2,
            },
            SolveError::BadDiagonal { row: 0 },
            SolveError::Breakdown {
                iterations: 3,
                residual: 1.0,
            },
            SolveError::NotConverged {
                iterations: 3,
                residual: 1.0,
                tolerance: 1e-9,
            },
            SolveError::NonFinite { iterations: 1 },
        ];
        check(&solve, |e| match e {
            SolveError::Dimension { .. } => "Dimension",
            SolveError::BadDiagonal { .. } => "BadDiagonal",
            SolveError::Breakdown { .. } => "Breakdown",
            SolveError::NotConverged { .. } => "NotConverged",
            SolveError::NonFinite { .. } => "NonFinite",
        });
        check(
            &[
                FlowError::BadTimeStep(0.0),
                FlowError::Solve(SolveError::BadDiagonal { row: 1 }),
                FlowError::NonFinite { vertex: 1 },
                FlowError::PastExtinction {
                    time: 0.24,
                    tau: 0.01,
                    extinction: 0.25,
                },
            ],
            |e| match e {
                FlowError::BadTimeStep(_) => "BadTimeStep",
                FlowError::Solve(_) => "Solve",
                FlowError::NonFinite { .. } => "NonFinite",
                FlowError::PastExtinction { .. } => "PastExtinction",
            },
        );
        check(
            &[
                MeshMcfError::Empty {
                    vertices: 0,
                    triangles: 0,
                },
                MeshMcfError::Ragged {
                    what: "the index array",
                    len: 4,
                },
                MeshMcfError::NonFinite { vertex: 2 },
                MeshMcfError::NotManifold(MeshBuildError::NonManifoldVertex { vertex: 1 }),
                MeshMcfError::NoExtent { diagonal: 0.0 },
                MeshMcfError::BadTimeStep(-1.0),
                MeshMcfError::Step {
                    step: 3,
                    time: 0.1,
                    source: FlowError::NonFinite { vertex: 1 },
                },
            ],
            |e| match e {
                MeshMcfError::Empty { .. } => "Empty",
                MeshMcfError::Ragged { .. } => "Ragged",
                MeshMcfError::NonFinite { .. } => "NonFinite",
                MeshMcfError::NotManifold(_) => "NotManifold",
                MeshMcfError::NoExtent { .. } => "NoExtent",
                MeshMcfError::BadTimeStep(_) => "BadTimeStep",
                MeshMcfError::Step { .. } => "Step",
            },
        );
        let (f, at) = (Format::Ply, Location::Line(3));
        let s = || String::from("x");
        let io = [
            IoError::Empty { format: None },
            IoError::UnknownFormat { reason: s() },
            IoError::syntax(f, at, "a number", "x"),
            IoError::truncated(f, at, "3 vertices"),
            IoError::CountTooLarge {
                format: f,
                at,
                element: s(),
                count: 9,
                available: 1,
                needed: 9,
            },
            IoError::IndexOutOfRange {
                format: f,
                at,
                face: 0,
                index: 7,
                count: 3,
            },
            IoError::NonFinite {
                format: f,
                at,
                index: 0,
                x: f64::NAN,
                y: 0.0,
                z: 0.0,
            },
            IoError::Unsupported {
                format: f,
                what: s(),
            },
            IoError::Gltf {
                format: Format::Gltf,
                message: s(),
            },
            IoError::Target {
                format: f,
                source: TargetError::Empty,
            },
            IoError::Decompress {
                format: Format::Nifti,
                at: Location::Byte(0),
                message: s(),
            },
            IoError::Fs {
                path: s(),
                message: s(),
            },
            IoError::InvalidInput {
                format: f,
                what: s(),
            },
            IoError::NotWritable { what: s() },
        ];
        check(&io, |e| match e {
            IoError::Empty { .. } => "Empty",
            IoError::UnknownFormat { .. } => "UnknownFormat",
            IoError::Syntax { .. } => "Syntax",
            IoError::Truncated { .. } => "Truncated",
            IoError::CountTooLarge { .. } => "CountTooLarge",
            IoError::IndexOutOfRange { .. } => "IndexOutOfRange",
            IoError::NonFinite { .. } => "NonFinite",
            IoError::Unsupported { .. } => "Unsupported",
            IoError::Gltf { .. } => "Gltf",
            IoError::Target { .. } => "Target",
            IoError::Decompress { .. } => "Decompress",
            IoError::Fs { .. } => "Fs",
            IoError::InvalidInput { .. } => "InvalidInput",
            IoError::NotWritable { .. } => "NotWritable",
        });
        check(&[setting()], |_| "SettingError");
        let field = [
            FieldError::EmptyTarget,
            FieldError::DegenerateTarget,
            FieldError::NonFinite { index: 0 },
            FieldError::BadTriangle { triangle: 0 },
            FieldError::InvalidSetting {
                name: "band_cells",
                value: -1.0,
                range: "> 0",
            },
            FieldError::TooLarge {
                dims: [9, 9, 9],
                bytes: 1 << 40,
                cap_bytes: 1 << 30,
                cells_that_fit: 100,
            },
        ];
        check(&field, |e| match e {
            FieldError::EmptyTarget => "EmptyTarget",
            FieldError::DegenerateTarget => "DegenerateTarget",
            FieldError::NonFinite { .. } => "NonFinite",
            FieldError::BadTriangle { .. } => "BadTriangle",
            FieldError::InvalidSetting { .. } => "InvalidSetting",
            FieldError::TooLarge { .. } => "TooLarge",
        });
        let target = [
            TargetError::Empty,
            TargetError::NonFinite {
                index: 0,
                x: f64::NAN,
                y: 0.0,
                z: 0.0,
            },
            TargetError::IndexOutOfRange {
                triangle: 0,
                vertex: 9,
                count: 3,
            },
            TargetError::TooFewPoints {
                distinct: 2,
                total: 2,
            },
            TargetError::SparseCloud {
                distinct: 8,
                total: 8,
                least: 20,
            },
            TargetError::Collinear { count: 5 },
            TargetError::Coplanar {
                count: 5,
                thickness: 0.0,
                size: 1.0,
            },
            TargetError::ZeroArea { faces: 2 },
            TargetError::FarFromOrigin {
                distance: 1e4,
                size: 1e-4,
                step: 1e-3,
            },
            TargetError::NoIsosurface {
                iso: 9.0,
                min: 0.0,
                max: 1.0,
            },
        ];
        check(&target, |e| match e {
            TargetError::Empty => "Empty",
            TargetError::NonFinite { .. } => "NonFinite",
            TargetError::IndexOutOfRange { .. } => "IndexOutOfRange",
            TargetError::TooFewPoints { .. } => "TooFewPoints",
            TargetError::SparseCloud { .. } => "SparseCloud",
            TargetError::Collinear { .. } => "Collinear",
            TargetError::Coplanar { .. } => "Coplanar",
            TargetError::ZeroArea { .. } => "ZeroArea",
            TargetError::FarFromOrigin { .. } => "FarFromOrigin",
            TargetError::NoIsosurface { .. } => "NoIsosurface",
        });
        let divergence = [
            Divergence::NonFinite { vertex: 0 },
            Divergence::Escaped {
                vertex: 0,
                distance: 9.0,
            },
            Divergence::AreaRunaway {
                area: 9.0,
                limit: 1.0,
            },
            Divergence::VertexRunaway { count: 9 },
        ];
        check(&divergence, |e| match e {
            Divergence::NonFinite { .. } => "NonFinite",
            Divergence::Escaped { .. } => "Escaped",
            Divergence::AreaRunaway { .. } => "AreaRunaway",
            Divergence::VertexRunaway { .. } => "VertexRunaway",
        });
        let build = [
            MeshBuildError::IndexOutOfRange {
                face: 0,
                vertex: 9,
                count: 3,
            },
            MeshBuildError::RepeatedVertex {
                face: 0,
                a: 1,
                b: 1,
                c: 2,
            },
            MeshBuildError::NonManifoldEdge {
                face: 1,
                from: 0,
                to: 1,
            },
            MeshBuildError::NonManifoldVertex { vertex: 0 },
            MeshBuildError::TooLarge,
        ];
        check(&build, |e| match e {
            MeshBuildError::IndexOutOfRange { .. } => "IndexOutOfRange",
            MeshBuildError::RepeatedVertex { .. } => "RepeatedVertex",
            MeshBuildError::NonManifoldEdge { .. } => "NonManifoldEdge",
            MeshBuildError::NonManifoldVertex { .. } => "NonManifoldVertex",
            MeshBuildError::TooLarge => "TooLarge",
        });
        let validation = [
            ValidationError::Empty,
            ValidationError::Boundary {
                halfedge: 0,
                from: 0,
                to: 1,
            },
            ValidationError::BrokenLink {
                halfedge: 0,
                what: "next",
            },
            ValidationError::IsolatedVertex { vertex: 0 },
            ValidationError::NonManifoldVertex {
                vertex: 0,
                ring: 3,
                total: 6,
            },
            ValidationError::NonFinite { vertex: 0 },
            ValidationError::DegenerateFace { face: 0, area: 0.0 },
        ];
        check(&validation, |e| match e {
            ValidationError::Empty => "Empty",
            ValidationError::Boundary { .. } => "Boundary",
            ValidationError::BrokenLink { .. } => "BrokenLink",
            ValidationError::IsolatedVertex { .. } => "IsolatedVertex",
            ValidationError::NonManifoldVertex { .. } => "NonManifoldVertex",
            ValidationError::NonFinite { .. } => "NonFinite",
            ValidationError::DegenerateFace { .. } => "DegenerateFace",
        });
        let remesh = [
            RemeshError::InvalidSizes {
                min: 1.0,
                max: 0.5,
                eps: 0.1,
            },
            RemeshError::Empty,
            RemeshError::Runaway {
                splits: 9,
                vertices: 1,
            },
        ];
        check(&remesh, |e| match e {
            RemeshError::InvalidSizes { .. } => "InvalidSizes",
            RemeshError::Empty => "Empty",
            RemeshError::Runaway { .. } => "Runaway",
        });
        let evolve = [
            V::Setting(setting()),
            V::Target(TargetError::Collinear { count: 5 }),
            V::Field(FieldError::EmptyTarget),
            V::Icosphere(IcosphereError::LevelTooHigh(9)),
            V::EmptyIsosurface { iso: 0.1 },
            V::StartIntersects { pairs: 3, genus: 2 },
            V::StartMesh(MeshBuildError::TooLarge),
            V::Remesh(RemeshError::Empty),
            V::Divergence {
                step: 3,
                previous: 2,
                reason: Divergence::VertexRunaway { count: 9 },
            },
            V::Diverged {
                step: 3,
                retries: 4,
                tau: 1e-3,
                cause: s(),
            },
        ];
        check(&evolve, |e| match e {
            V::Setting(_) => "Setting",
            V::Target(_) => "Target",
            V::Field(_) => "Field",
            V::Icosphere(_) => "Icosphere",
            V::EmptyIsosurface { .. } => "EmptyIsosurface",
            V::StartIntersects { .. } => "StartIntersects",
            V::StartMesh(_) => "StartMesh",
            V::Remesh(_) => "Remesh",
            V::Divergence { .. } => "Divergence",
            V::Diverged { .. } => "Diverged",
        });
        check(
            &[DemoError::UnknownShape(s()), DemoError::BadMesh(s())],
            |e| match e {
                DemoError::UnknownShape(_) => "UnknownShape",
                DemoError::BadMesh(_) => "BadMesh",
            },
        );
    }

    /// The codes and hints the app relies on, for the cases it branches on or that users see
    /// most.
    #[test]
    fn codes_and_hints_kept_from_the_facade() {
        let too_large = EvolveError::Field(FieldError::TooLarge {
            dims: [1, 1, 1],
            bytes: 2,
            cap_bytes: 1,
            cells_that_fit: 1,
        });
        assert_eq!(too_large.code(), "too-large");
        assert_eq!(EvolveError::Remesh(RemeshError::Empty).code(), "internal");
        assert_eq!(
            Explain::hint(&IoError::UnknownFormat { reason: "?".into() }),
            "Use PLY, OBJ, STL, OFF, XYZ, glTF, GLB, VTK, PCD, LAS/LAZ, E57 or PTX, or a NIfTI, NRRD, VTI or MetaImage volume."
        );
        assert_eq!(Explain::code(&IoError::Empty { format: None }), "bad-file");
        assert_eq!(
            DemoError::UnknownShape("x".into()).hint(),
            "Use noisy-sphere, genus2 or box-soup."
        );
        assert_eq!(FlowError::BadTimeStep(0.0).code(), "bad-parameter");
    }
}
