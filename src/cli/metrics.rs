//! `lsw metrics MESH [--target TARGET]`: quality and accuracy of a mesh, as JSON.
//!
//! JSON keys (stable; add, never rename):
//! * `file`, `vertices`, `faces`, `bbox_diagonal`
//! * `topology`: `closed`, `manifold`, `oriented`, `euler_characteristic`, `genus`,
//!   `components` (the last three `null` unless the mesh is a valid closed manifold),
//!   `boundary_edges`, `problem` (first broken invariant, or `null`)
//! * `quality`: `kappa` (κ(J_Δ), equilateral = 1), `kappa_le_1_5` (fraction of faces),
//!   `kappa_reference` (the reference's variant, equilateral = 2/√3), `kappa_reference_le_1_5`,
//!   `radius_ratio` (2·r_in/r_circ), `min_angle_deg` — each summary has
//!   `count, mean, median, p95, min, max`
//! * `covolumes`: `area` (summary of the mixed Voronoi areas), `relative_std`, `max_over_min`
//!   (`null` if the mesh is not manifold)
//! * `volume` (signed enclosed volume), `self_intersections` (pairs of faces that meet other
//!   than in their shared vertices or edge, by exact predicates; folded neighbours count too)
//! * `certificate`: {`valid`, `closed`, `manifold`, `oriented`, `finite`, `genus`,
//!   `components`, `euler_characteristic`, `self_intersections`, `degenerate_faces`,
//!   `distance_min`, `distance_max` (vertex → target, with `--target`), `problem`,
//!   `target_genus`, `target_components` (a one-part closed mesh target's),
//!   `target_points_outside` of `target_points_checked` (target points the wrap left outside,
//!   farther than 1 % of the diagonal, with `--target`), `target_part_outside` (more than
//!   0.5 % of them)} (see
//!   [`crate::metrics::certificate`]), `certificate_ms`
//! * with `--histograms`: `histograms` (see [`metrics_json_with`])
//! * `--error-map FILE` / `--target-error-map FILE` (with `--target`) write the mesh / the target
//!   with per-vertex scalars `error` and `error_percent` (distance to the other, the JSON's
//!   `distances` point by point), to find where the remaining error sits.
//! * with `--target`: `target` {`file`, `kind`, `points`, `faces`, `bbox_diagonal`, `volume`,
//!   `volume_ratio`} (volumes only for mesh targets) and `distances` {`absolute`,
//!   `percent_of_target_diagonal`}, each {`mesh_to_target`, `target_to_mesh`: `count, mean, rms,
//!   p95, max`; `hausdorff`}. Mesh vertices are measured to the target's triangles (or nearest
//!   point for a cloud); target points to the mesh's triangles.
//! * with a mesh `--target`: `creases` (`null` when it has none) {`edges`, `within_tolerance`,
//!   `mean_error_deg`, `max_error_deg`, `worst_at`}: the target's crease edges (faces turning by
//!   more than 40°) and how far the mesh's dihedral angle beside each is from the target's
//!   (see [`crate::metrics::creases`]; within tolerance = within 10°).

use crate::geometry::creases::detect_creases;
use crate::io::read_path;
use crate::mesh::{HalfedgeMesh, ValidationError};
use crate::metrics::certificate::certify;
use crate::metrics::creases::{crease_fidelity, CREASE_ANGLE_DEG, CREASE_OFFSET};
use crate::metrics::distance::{two_sided_distance_values, DistanceStats, TwoSidedDistances};
use crate::metrics::histogram::Histogram;
use crate::metrics::quality::{covolume_stats, face_quality, quality_stats, CovolumeStats};
use crate::metrics::volume::enclosed_volume;
use crate::target::{CreaseSource, Surface, Target};
use glam::DVec3;
use serde_json::{json, Value};
use std::path::PathBuf;

/// Arguments of `lsw metrics`.
#[derive(clap::Args, Debug)]
pub struct MetricsArgs {
    /// The mesh to measure (any format of [`crate::io::FORMATS`]).
    #[arg(help = super::input_help("The mesh to measure"))]
    pub mesh: PathBuf,
    /// A target (point cloud or mesh) to measure distances to, both ways.
    #[arg(long)]
    pub target: Option<PathBuf>,
    /// Also print histograms (κ, 2·r_in/r_circ, smallest angle; distances with --target).
    #[arg(long)]
    pub histograms: bool,
    /// With --target: write the mesh with each vertex's distance to the target as per-vertex
    /// scalars `error` (target units) and `error_percent` (% of the target's diagonal), where the
    /// result misses the target (.ply or .vtk keep the scalars; ParaView colours by them).
    #[arg(long, requires = "target")]
    pub error_map: Option<PathBuf>,
    /// With --target: write the target (its mesh, or its points) with each point's distance to
    /// the mesh as the same scalars: where the mesh fails to reach the target.
    #[arg(long, requires = "target")]
    pub target_error_map: Option<PathBuf>,
}

/// Runs `lsw metrics`.
pub fn run(a: &MetricsArgs) -> Result<String, String> {
    let mesh =
        read_path(&a.mesh).map_err(|e| format!("{}: {}", a.mesh.display(), super::explained(e)))?;
    let target = match &a.target {
        Some(p) => Some((
            p.display().to_string(),
            read_path(p)
                .map_err(|e| format!("{}: {}", p.display(), super::explained(e)))?
                .target,
        )),
        None => None,
    };
    let v = metrics_json_with(
        &a.mesh.display().to_string(),
        &mesh.target,
        target.as_ref().map(|(n, t)| (n.as_str(), t)),
        a.histograms,
    );
    if let (Some((_, tg)), true) = (
        &target,
        a.error_map.is_some() || a.target_error_map.is_some(),
    ) {
        write_error_maps(a, &mesh.target, tg)?;
    }
    serde_json::to_string_pretty(&v).map_err(|e| e.to_string())
}

/// Writes `--error-map` (mesh vertices → target) and `--target-error-map` (target points →
/// mesh), each with the scalars `error` and `error_percent`.
fn write_error_maps(a: &MetricsArgs, mesh: &Target, target: &Target) -> Result<(), String> {
    let (there, back) =
        two_sided_distance_values(&mesh.points, &mesh.triangles, target.oracle().surface());
    let diagonal = target.bbox.diagonal().max(f64::MIN_POSITIVE);
    let write = |path: &PathBuf, shape: &Target, d: &[f64]| {
        let percent: Vec<f64> = d.iter().map(|x| 100.0 * x / diagonal).collect();
        let scalars = [("error", d), ("error_percent", percent.as_slice())];
        let input = crate::io::WriteInput {
            scalars: &scalars,
            ..crate::io::WriteInput::new(&shape.points, &shape.triangles)
        };
        crate::io::write_path(path, &input)
            .map_err(|e| format!("{}: {}", path.display(), super::explained(e)))
    };
    if let Some(path) = &a.error_map {
        write(path, mesh, &there)?;
    }
    if let Some(path) = &a.target_error_map {
        write(path, target, &back)?;
    }
    Ok(())
}

/// The JSON of `lsw metrics` for a mesh and an optional `(file name, target)`.
pub fn metrics_json(file: &str, mesh: &Target, target: Option<(&str, &Target)>) -> Value {
    metrics_json_with(file, mesh, target, false)
}

/// [`metrics_json`], with `histograms` adding the key `histograms`: `kappa` (20 bins over
/// [1, 2)), `radius_ratio` (20 over [0, 1)), `min_angle_deg` (12 over [0, 60)) and, with a
/// target, `mesh_to_target_percent` / `target_to_mesh_percent` (20 bins from 0 to the largest
/// distance, in % of the target's diagonal). Each is {lo, hi, counts, below, above}.
pub fn metrics_json_with(
    file: &str,
    mesh: &Target,
    target: Option<(&str, &Target)>,
    histograms: bool,
) -> Value {
    let (p, t) = (&mesh.points, &mesh.triangles);
    let (mut out, volume) = mesh_json(file, mesh, target.map(|(_, tg)| tg));
    let mut hist = serde_json::Map::new();
    if histograms {
        quality_histograms(p, t, &mut hist);
    }
    if let Some((tfile, tg)) = target {
        let o = out.as_object_mut().expect("object");
        target_json(
            o,
            p,
            t,
            volume,
            (tfile, tg),
            histograms.then_some(&mut hist),
        );
    }
    if histograms {
        out.as_object_mut()
            .expect("object")
            .insert("histograms".into(), Value::Object(hist));
    }
    out
}

/// The metrics of the mesh alone (counts, topology, quality, covolumes, volume, certificate),
/// and its enclosed volume.
fn mesh_json(file: &str, mesh: &Target, target: Option<&Target>) -> (Value, f64) {
    let (p, t) = (&mesh.points, &mesh.triangles);
    let (topology, covol) = topology_json(p, t);
    let volume = enclosed_volume(p, t);
    let t_si = crate::clock::now_ms();
    let certificate = certify(p, t, target);
    let self_intersections = certificate.self_intersections;
    let si_ms = crate::clock::now_ms() - t_si;
    let out = json!({
        "file": file,
        "vertices": p.len(),
        "faces": t.len(),
        "bbox_diagonal": mesh.bbox.diagonal(),
        "topology": topology,
        "quality": quality_stats(p, t),
        "covolumes": covol,
        "volume": volume,
        "self_intersections": self_intersections,
        "certificate": certificate,
        "certificate_ms": si_ms,
    });
    (out, volume)
}

/// The `topology` object of the mesh and, when it is manifold, its covolume statistics.
fn topology_json(p: &[DVec3], t: &[[u32; 3]]) -> (Value, Option<CovolumeStats>) {
    let nb = crate::mesh::edge_counts(t).boundary;
    let built = HalfedgeMesh::from_triangles(p.to_vec(), t);
    let (manifold, oriented, problem, report, covol) = match &built {
        Err(e) => (false, false, Some(e.to_string()), None, None),
        Ok(m) => {
            let v = m.validate();
            let manifold = !matches!(v, Err(ValidationError::NonManifoldVertex { .. }));
            let cv = manifold.then(|| covolume_stats(m));
            match v {
                Ok(r) => (true, true, None, Some(r), cv),
                Err(e) => (manifold, true, Some(e.to_string()), None, cv),
            }
        }
    };
    let topology = json!({
        "closed": nb == 0 && built.is_ok(),
        "manifold": manifold,
        "oriented": oriented,
        "boundary_edges": nb,
        "euler_characteristic": report.map(|r| r.euler_characteristic),
        "genus": report.map(|r| r.genus),
        "components": report.map(|r| r.components),
        "problem": problem,
    });
    (topology, covol)
}

/// Adds the histograms of the face quality: `kappa`, `radius_ratio` and `min_angle_deg`.
fn quality_histograms(p: &[DVec3], t: &[[u32; 3]], hist: &mut serde_json::Map<String, Value>) {
    let q = face_quality(p, t);
    hist.insert(
        "kappa".into(),
        json!(Histogram::new(&q.kappa, 1.0, 2.0, 20)),
    );
    hist.insert(
        "radius_ratio".into(),
        json!(Histogram::new(&q.radius_ratio, 0.0, 1.0 + 1e-12, 20)),
    );
    hist.insert(
        "min_angle_deg".into(),
        json!(Histogram::new(&q.min_angle_deg, 0.0, 60.0 + 1e-9, 12)),
    );
}

/// Adds the keys that compare with the target `(file, target)`: `target`, `creases` and
/// `distances`, and with `hist` the two distance histograms.
fn target_json(
    o: &mut serde_json::Map<String, Value>,
    p: &[DVec3],
    t: &[[u32; 3]],
    volume: f64,
    (tfile, tg): (&str, &Target),
    hist: Option<&mut serde_json::Map<String, Value>>,
) {
    let diag = tg.bbox.diagonal();
    let (there, back) = two_sided_distance_values(p, t, tg.oracle().surface());
    let (a, b) = (
        DistanceStats::from_distances(&there),
        DistanceStats::from_distances(&back),
    );
    let d = TwoSidedDistances {
        mesh_to_target: a,
        target_to_mesh: b,
        hausdorff: a.max.max(b.max),
    };
    if let Some(hist) = hist {
        let pct = |v: &[f64]| v.iter().map(|x| 100.0 * x / diag).collect::<Vec<f64>>();
        hist.insert(
            "mesh_to_target_percent".into(),
            json!(Histogram::auto(&pct(&there), 20)),
        );
        hist.insert(
            "target_to_mesh_percent".into(),
            json!(Histogram::auto(&pct(&back), 20)),
        );
    }
    let oracle = tg.oracle();
    let tvol = match oracle.surface() {
        Surface::Triangles { points, triangles } => Some(enclosed_volume(points, triangles)),
        Surface::Points(_) => None,
    };
    o.insert(
        "target".into(),
        json!({
            "file": tfile,
            "kind": tg.kind(),
            "points": tg.points.len(),
            "faces": tg.triangles.len(),
            "bbox_diagonal": diag,
            "volume": tvol,
            "volume_ratio": tvol.map(|tv| volume / tv),
        }),
    );
    let creases = (oracle.creases() == Some(CreaseSource::Dihedral)).then(|| {
        let c = detect_creases(&tg.points, &tg.triangles, CREASE_ANGLE_DEG.to_radians());
        crease_fidelity(p, t, &c, CREASE_OFFSET * diag)
    });
    o.insert("creases".into(), json!(creases.flatten()));
    o.insert(
        "distances".into(),
        json!({
            "absolute": d,
            "percent_of_target_diagonal": d.percent_of(diag),
        }),
    );
}

/// Convenience for tests and `lsw wrap --stats`: the metrics JSON of in-memory data.
pub fn metrics_json_of(
    positions: &[DVec3],
    triangles: &[[u32; 3]],
    target: Option<&Target>,
) -> Result<Value, String> {
    let m = Target::new(positions.to_vec(), triangles.to_vec()).map_err(|e| e.to_string())?;
    Ok(metrics_json(
        "<memory>",
        &m,
        target.map(|t| ("<memory>", t)),
    ))
}
