//! `lsw metrics` JSON: the documented keys are present and consistent; `--error-map` /
//! `--target-error-map` (issue 15, item 1) write per-point distances as scalars, checked against
//! an analytic case (native only: the CLI is not part of the wasm build).
#![cfg(not(target_arch = "wasm32"))]

use lsw::cli::metrics::{metrics_json_of, run, MetricsArgs};
use lsw::geometry::icosphere::icosphere;
use lsw::io::{write_path, WriteInput};
use lsw::target::Target;
use lsw::DVec3;

#[test]
fn metrics_json_has_stable_keys() {
    let m = icosphere(3, 1.0, DVec3::ZERO).unwrap();
    let cloud: Vec<DVec3> = m.positions().iter().map(|p| *p * 1.01).collect();
    let target = Target::new(cloud, Vec::new()).unwrap();
    let v = metrics_json_of(m.positions(), &m.triangles(), Some(&target)).unwrap();
    let topo = &v["topology"];
    assert_eq!(topo["closed"], true);
    assert_eq!(topo["manifold"], true);
    assert_eq!(topo["genus"], 0);
    for k in ["kappa", "kappa_reference", "radius_ratio", "min_angle_deg"] {
        for s in ["count", "mean", "median", "p95", "min", "max"] {
            assert!(v["quality"][k][s].is_number(), "quality.{k}.{s}");
        }
    }
    assert!(v["quality"]["kappa_le_1_5"].as_f64().unwrap() == 1.0);
    assert!(v["covolumes"]["area"]["mean"].is_number());
    assert_eq!(v["self_intersections"], 0);
    assert!(v["volume"].as_f64().unwrap() > 4.0);
    let d = &v["distances"];
    for side in ["mesh_to_target", "target_to_mesh"] {
        for s in ["count", "mean", "rms", "p95", "max"] {
            assert!(d["absolute"][side][s].is_number(), "{side}.{s}");
        }
    }
    // All points sit 1 % outside a unit sphere: vertex → point distance is exactly 0.01.
    let abs = d["absolute"]["mesh_to_target"]["max"].as_f64().unwrap();
    assert!((abs - 0.01).abs() < 1e-12);
    let diag = v["target"]["bbox_diagonal"].as_f64().unwrap();
    let pc = d["percent_of_target_diagonal"]["hausdorff"]
        .as_f64()
        .unwrap();
    assert!((pc - 100.0 * d["absolute"]["hausdorff"].as_f64().unwrap() / diag).abs() < 1e-9);
}

#[test]
fn histograms_count_every_face_and_point() {
    use lsw::cli::metrics::metrics_json_with;
    let m = icosphere(2, 1.0, DVec3::ZERO).unwrap();
    let mesh = Target::new(m.positions().to_vec(), m.triangles()).unwrap();
    let cloud: Vec<DVec3> = m.positions().iter().map(|p| *p * 1.05).collect();
    let target = Target::new(cloud, Vec::new()).unwrap();
    let v = metrics_json_with("m", &mesh, Some(("t", &target)), true);
    let total = |k: &str| {
        let h = &v["histograms"][k];
        h["counts"]
            .as_array()
            .unwrap()
            .iter()
            .map(|c| c.as_u64().unwrap())
            .sum::<u64>()
            + h["below"].as_u64().unwrap()
            + h["above"].as_u64().unwrap()
    };
    let nf = m.n_faces() as u64;
    assert_eq!(total("kappa"), nf);
    assert_eq!(total("radius_ratio"), nf);
    assert_eq!(total("min_angle_deg"), nf);
    assert_eq!(total("mesh_to_target_percent"), m.n_vertices() as u64);
    assert_eq!(total("target_to_mesh_percent"), m.n_vertices() as u64);
    assert!(metrics_json_with("m", &mesh, None, false)
        .get("histograms")
        .is_none());
}

#[test]
fn error_maps_hold_each_points_distance() {
    let dir = std::env::temp_dir().join(format!("lsw_metrics_cli_{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    // Target: the unit sphere (a fine icosphere); mesh: a sphere of radius 1.1 around it.
    let target = icosphere(5, 1.0, DVec3::ZERO).unwrap();
    let mesh = icosphere(3, 1.1, DVec3::ZERO).unwrap();
    let (tp, tt) = (target.positions().to_vec(), target.triangles());
    let (mp, mt) = (mesh.positions().to_vec(), mesh.triangles());
    write_path(dir.join("target.ply"), &WriteInput::new(&tp, &tt)).unwrap();
    write_path(dir.join("mesh.ply"), &WriteInput::new(&mp, &mt)).unwrap();
    let args = MetricsArgs {
        mesh: dir.join("mesh.ply"),
        target: Some(dir.join("target.ply")),
        histograms: false,
        error_map: Some(dir.join("err.vtk")),
        target_error_map: Some(dir.join("terr.vtk")),
    };
    let json: serde_json::Value = serde_json::from_str(&run(&args).unwrap()).unwrap();
    let diagonal = json["target"]["bbox_diagonal"].as_f64().unwrap();
    for (file, count, lo, hi) in [
        // Mesh vertices lie 0.1 outside the unit sphere, a little more from its flat faces.
        ("err.vtk", mp.len(), 0.1, 0.1 + 2e-3),
        // Target vertices are 0.1 inside the coarser sphere's vertices, less to its faces.
        ("terr.vtk", tp.len(), 0.1 - 0.02, 0.1 + 1e-6),
    ] {
        let bytes = std::fs::read(dir.join(file)).unwrap();
        let ((points, _), scalars) = lsw::io::vtk::read(&bytes).unwrap();
        assert_eq!(points.len(), count, "{file}");
        let get = |name: &str| &scalars.iter().find(|(n, _)| n == name).unwrap().1;
        let (err, pct) = (get("error"), get("error_percent"));
        assert_eq!(err.len(), count, "{file}");
        for (e, p) in err.iter().zip(pct) {
            assert!(
                (lo - 1e-6..=hi).contains(e),
                "{file}: distance {e} outside [{lo}, {hi}]"
            );
            assert!(
                (p - 100.0 * e / diagonal).abs() < 1e-9,
                "{file}: {p} % vs {e}"
            );
        }
    }
    std::fs::remove_dir_all(&dir).ok();
}

/// `creases` (issue 15): a cube measured against itself reproduces all 12·4 crease edges; a
/// cloud target has no creases (`null`).
#[test]
fn creases_are_measured_for_mesh_targets_only() {
    let (p, t) = lsw::demo::shapes::grid_box(DVec3::ONE, [4, 4, 4]);
    let cube = Target::new(p.clone(), t.clone()).unwrap();
    let v = metrics_json_of(&p, &t, Some(&cube)).unwrap();
    let c = &v["creases"];
    assert_eq!(c["edges"], 48);
    assert_eq!(c["within_tolerance"], 48);
    assert!(c["max_error_deg"].as_f64().unwrap() < 1e-6);
    let cloud = Target::new(p.clone(), Vec::new()).unwrap();
    let v = metrics_json_of(&p, &t, Some(&cloud)).unwrap();
    assert!(v["creases"].is_null());
}

/// `lsw wrap --stats` carries the error budget (issue 15, item 4): its classes, and the class
/// holding the Hausdorff distance, which is the largest of the classes' maxima.
#[test]
fn wrap_stats_carry_the_error_budget() {
    let dir = std::env::temp_dir().join(format!("lsw-budget-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let stats = dir.join("s.json");
    let (p, t) = lsw::demo::shapes::grid_box(DVec3::ONE, [4, 4, 4]);
    wrap_cli(&dir, &p, &t, &["--stats", stats.to_str().unwrap()]);
    let s: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&stats).unwrap()).unwrap();
    let b = &s["error_budget"];
    let mut largest = (String::new(), 0.0f64);
    for k in ["features", "sizing", "not_reached", "vertices_off"] {
        for f in ["count", "mean", "max", "mean_percent", "max_percent"] {
            assert!(b[k][f].is_number(), "{k}.{f}");
        }
        let m = b[k]["max_percent"].as_f64().unwrap();
        if m > largest.1 {
            largest = (k.to_string(), m);
        }
    }
    assert_eq!(b["hausdorff_from"], largest.0.as_str());
    assert!((b["hausdorff_percent"].as_f64().unwrap() - largest.1).abs() < 1e-12);
    // The cube's 98 target vertices: its 8 corners and the edge vertices are features.
    assert!(b["features"]["count"].as_u64().unwrap() >= 8);
    std::fs::remove_dir_all(&dir).ok();
}

/// `lsw wrap` says in `warnings` what its certificate shows beside `valid`: here a wrap stopped
/// after three steps, still the icosphere's genus 0 round a genus-1 torus, is valid and says so.
#[test]
fn wrap_warns_of_a_genus_unlike_the_targets() {
    let dir = std::env::temp_dir().join(format!("lsw-warn-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let (p, t) = lsw::demo::shapes::generate("torus-g1").unwrap();
    let v = wrap_cli(&dir, &p, &t, &["--start", "icosphere", "--steps", "3"]);
    assert_eq!(v["certificate"]["valid"], true);
    assert_eq!(
        v["warnings"],
        serde_json::json!(["the target has genus 1 in 1 part(s) and the wrap genus 0 in 1"])
    );
    let _ = std::fs::remove_dir_all(&dir);
}

/// Writes the mesh `(p, t)` to DIR/in.obj and runs `lsw wrap` on it (output DIR/w.ply, a
/// 16-cell grid) with `extra` arguments; its JSON report.
fn wrap_cli(
    dir: &std::path::Path,
    p: &[DVec3],
    t: &[[u32; 3]],
    extra: &[&str],
) -> serde_json::Value {
    use clap::Parser;
    let (input, out) = (dir.join("in.obj"), dir.join("w.ply"));
    write_path(&input, &WriteInput::new(p, t)).unwrap();
    let (input, out) = (input.to_str().unwrap(), out.to_str().unwrap());
    let mut args = vec!["lsw", "wrap", input, "-o", out];
    args.extend(["--set", "field.cells_per_min_dimension=16"]);
    args.extend_from_slice(extra);
    let cli = lsw::cli::Cli::try_parse_from(args).unwrap();
    serde_json::from_str(&lsw::cli::run(cli).unwrap()).unwrap()
}
