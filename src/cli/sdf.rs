//! `lsw sdf INPUT`: builds the distance field of a point cloud or mesh and prints its layout,
//! signedness, value range and per-phase times as JSON; `--out` writes it as VTK for ParaView.

use crate::field::{DistanceField, FieldSettings, SignMode};
use serde_json::json;
use std::path::PathBuf;

/// Arguments of `lsw sdf`.
#[derive(clap::Args, Debug)]
pub struct SdfArgs {
    /// The target file: a point cloud, a mesh or a volume (any format of [`crate::io::FORMATS`]).
    #[arg(help = super::input_help("The target file (a point cloud or a mesh)"))]
    pub input: PathBuf,
    /// Cells per minimum bounding-box dimension (cell size = smallest side / N; the principal
    /// box's side where that is much tighter, for a target lying turned).
    #[arg(long, default_value_t = 40)]
    pub cells: u32,
    /// Expansion factor ζ: the box grows by ζ × the smallest side on every side.
    #[arg(long, default_value_t = 1.0)]
    pub expand: f64,
    /// Width of the exact near band, in cells.
    #[arg(long, default_value_t = 3.0)]
    pub band: f64,
    /// Optional truncation distance, as a fraction of the smallest side.
    #[arg(long)]
    pub truncate: Option<f64>,
    /// Produce an unsigned field even for a closed mesh (and a cloud's enclosed solids).
    #[arg(long)]
    pub unsigned: bool,
    /// Point clouds: nodes deeper than this many cells inside a solid the cloud samples all
    /// round are negative (0: unsigned everywhere).
    #[arg(long, default_value_t = 2.0)]
    pub enclosed: f64,
    /// Write the field (distance, band flag, gradient) as a legacy VTK structured-points file.
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Volume inputs: iso-value, frame, inside, array, iso-surface output.
    #[command(flatten)]
    pub volume: super::volume::VolumeArgs,
}

/// Runs `lsw sdf`. JSON keys: input, kind, points, triangles, dims, nodes, cell_size, origin,
/// bbox {min, max}, signedness, signed, enclosed_nodes (a cloud's nodes negative deep inside
/// the solids it encloses), min, max, band_nodes, sweep {passes, converged},
/// memory_bytes, times_ms {read, band, sweep, sign, gradient, field, write}, out.
pub fn run(a: &SdfArgs) -> Result<String, String> {
    let t0 = crate::clock::now_ms();
    let read =
        crate::io::read_path_with(&a.input, &a.volume.options()).map_err(super::explained)?;
    a.volume.write_isosurface(&read)?;
    let volume = read.volume.as_deref().map(super::volume::volume_json);
    let target = read.target;
    let t1 = crate::clock::now_ms();
    let settings = FieldSettings {
        cells_per_min_dimension: a.cells,
        expansion: a.expand,
        margin_cells: None,
        band_cells: a.band,
        truncation: a.truncate,
        sign: if a.unsigned {
            SignMode::Unsigned
        } else {
            SignMode::Auto
        },
        enclosed_cells: if a.unsigned { 0.0 } else { a.enclosed },
        ..Default::default()
    };
    let f = DistanceField::new(&target, &settings).map_err(super::explained)?;
    let t2 = crate::clock::now_ms();
    if let Some(out) = &a.out {
        std::fs::write(out, crate::field::vtk::structured_points(&f))
            .map_err(|e| format!("{}: {e}", out.display()))?;
    }
    let t3 = crate::clock::now_ms();
    let (lo, hi) = f.min_max();
    let tm = f.timings();
    let sw = f.sweep_report();
    let bb = f.bbox();
    Ok(serde_json::to_string_pretty(&json!({
        "input": a.input.display().to_string(),
        "kind": target.kind(),
        "points": target.points.len(),
        "triangles": target.triangles.len(),
        "dims": f.dims(),
        "nodes": f.grid().node_count(),
        "cell_size": f.cell_size(),
        "origin": f.grid().origin.to_array(),
        "bbox": { "min": bb.min.to_array(), "max": bb.max.to_array() },
        "signedness": f.signedness(),
        "signed": f.is_signed(),
        "enclosed_nodes": f.enclosed_nodes(),
        "min": lo,
        "max": hi,
        "band_nodes": f.band_mask().iter().filter(|&&b| b).count(),
        "sweep": { "passes": sw.passes, "converged": sw.converged },
        "memory_bytes": f.grid().node_count() as u64 * crate::field::grid::BYTES_PER_NODE,
        "times_ms": {
            "read": t1 - t0,
            "band": tm.band_ms,
            "sweep": tm.sweep_ms,
            "sign": tm.sign_ms,
            "gradient": tm.gradient_ms,
            "field": tm.total_ms,
            "write": t3 - t2,
        },
        "out": a.out.as_ref().map(|p| p.display().to_string()),
        "volume": volume,
    }))
    .expect("JSON of plain values"))
}
