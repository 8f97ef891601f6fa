//! The native command-line interface (`lsw SUBCOMMAND …`). Each subcommand lives in its own file
//! and returns the JSON it prints, so tests can call it without spawning a process.
//!
//! Subcommand names, flags and JSON keys are a public interface: add, never rename.

pub mod demo;
pub mod info;
pub mod mcf;
pub mod metrics;
pub mod sdf;
pub mod volume;
pub mod wrap;

use crate::error::Explain;
use clap::{Parser, Subcommand};
use std::fmt::Display;

/// LSW — Lagrangian Shrink-Wrapping: watertight meshes from point clouds, meshes and volumes.
#[derive(Parser, Debug)]
#[command(name = "lsw", version, about)]
pub struct Cli {
    #[command(subcommand)]
    pub command: Command,
}

/// The subcommands.
#[derive(Subcommand, Debug)]
pub enum Command {
    /// Mean-curvature flow of an icosphere, checked against r(t) = sqrt(r0² − 4t).
    Mcf(mcf::McfArgs),
    /// Builds the distance field of a point cloud or mesh; prints grid, signedness, range and
    /// per-phase times as JSON; `--out field.vtk` writes it for ParaView.
    Sdf(sdf::SdfArgs),
    /// Reads a geometry file and prints its format, kind, counts, bounding box and topology.
    Info(info::InfoArgs),
    /// Quality (κ, 2·r_in/r_circ, angles, co-volumes), topology, volume, self-intersections and,
    /// with --target, exact two-sided distances of a mesh, as JSON.
    Metrics(metrics::MetricsArgs),
    /// Wraps a point cloud or mesh: read → distance field → start surface → evolve → write.
    Wrap(wrap::WrapArgs),
    /// The deterministic test shapes: `--list` prints their names and descriptions as JSON;
    /// `NAME -o FILE` writes one (format from the extension; PLY for point clouds).
    Demo(demo::DemoArgs),
}

/// A core error as the CLI reports it: the message, then `hint: …` (what to try) on the next
/// line; `lsw` prints it after `error: ` on stderr.
pub fn explained<E: Explain + Display>(e: E) -> String {
    format!("{e}\nhint: {}", e.hint())
}

/// The help of an input-file argument: `what`, then the formats LSW reads (from the catalog,
/// [`crate::io::FORMATS`]).
pub fn input_help(what: &str) -> String {
    let (geometry, volumes) = crate::io::formats::readable_labels();
    format!(
        "{what}: {}; or a volume: {}",
        geometry.join(", "),
        volumes.join(", ")
    )
}

/// The help of an output-mesh argument: `what`, then the extensions LSW writes.
pub fn output_help(what: &str) -> String {
    format!(
        "{what}; the format follows the extension ({})",
        crate::io::formats::writable_extensions()
    )
}

/// The help of `--preset`: the preset names, from [`crate::flow::Preset::ALL`].
pub fn preset_help() -> String {
    let names = crate::flow::Preset::ALL.map(crate::flow::Preset::name);
    format!(
        "Settings preset: {}",
        crate::io::formats::join_list(&names, "or")
    )
}

/// A command that failed: the message for stderr and, where the command still has one, the JSON
/// report for stdout (a refused `wrap`'s certificate and `stop_reason`, so that a script looping
/// over scans records why with `> report.json`).
#[derive(Debug)]
pub struct Failure {
    pub message: String,
    pub report: Option<String>,
}

impl From<String> for Failure {
    fn from(message: String) -> Self {
        Self {
            message,
            report: None,
        }
    }
}

/// Runs a parsed command line; `Ok` holds the JSON text to print.
pub fn run(cli: Cli) -> Result<String, Failure> {
    match cli.command {
        Command::Mcf(a) => Ok(mcf::run(&a)?),
        Command::Sdf(a) => Ok(sdf::run(&a)?),
        Command::Info(a) => Ok(info::run(&a)?),
        Command::Metrics(a) => Ok(metrics::run(&a)?),
        Command::Wrap(a) => wrap::run(&a),
        Command::Demo(a) => Ok(demo::run(&a)?),
    }
}
