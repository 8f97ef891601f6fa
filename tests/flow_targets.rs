//! The evolution on real scans and volumes from `LSW_SHARED_DATA` (native only; ignored when the
//! build had none), and the tangential term on a distorted sphere.

#![cfg(not(target_arch = "wasm32"))]

use lsw::flow::tangential::tangential_velocity;
use lsw::flow::{Evolver, Preset, WrapSettings};
use lsw::geometry::icosphere::icosphere;
use lsw::geometry::operators::normals::angle_weighted_normals;
use lsw::geometry::operators::CotanLaplacian;
use lsw::metrics::distance::two_sided_distances;
use lsw::DVec3;

/// A file of the shared test data (the tests reading it are ignored without it).
fn shared(name: &str) -> std::path::PathBuf {
    let dir = std::env::var("LSW_SHARED_DATA").expect("LSW_SHARED_DATA (the build had it)");
    std::path::Path::new(&dir).join(name)
}

#[test]
#[cfg_attr(
    not(shared_data),
    ignore = "needs the shared test data (LSW_SHARED_DATA)"
)]
#[cfg_attr(
    shared_data,
    ignore = "corpus tier (whole wraps): cargo test -- --ignored"
)]
fn full_wrap_gets_closer_than_obstacle_on_spot() {
    let path = shared("spotPts_4.ply");
    let target = lsw::io::read_path(&path).unwrap().target;
    let diag = target.bbox.diagonal();
    let mut means = vec![];
    for preset in [Preset::Obstacle, Preset::FullWrap] {
        let mut settings = {
            let mut w = preset.settings();
            w.stop.steps = 100;
            w.flow.schedule = vec![3, 10, 20, 50];
            w
        };
        // The paper's grid (40 cells per β_min), not the coarser one the defaults give this
        // sparse cloud: on it the concavities are resolved well enough to compare.
        settings.tuning.field.min_cell_spacings = 0.0;
        // The flows alone: on that grid full-wrap's first pass leaves 120 of the 1 307 points
        // outside, and the second pass (D₂ = 0, `flow.cover_gaps`) would take over.
        settings.tuning.flow.cover_gaps = 1.0;
        let mut ev = Evolver::new(&target, settings).unwrap();
        ev.run(|_| {}).unwrap();
        let report = ev.mesh().validate().unwrap();
        assert_eq!(report.genus, 0);
        let d = two_sided_distances(&ev.positions(), &ev.triangles(), &target.points, &[]);
        println!(
            "{}: {} vertices, mesh→cloud mean {:.3} % max {:.3} %, cloud→mesh mean {:.3} % max {:.3} % of the diagonal",
            preset.name(),
            report.vertices,
            100.0 * d.mesh_to_target.mean / diag,
            100.0 * d.mesh_to_target.max / diag,
            100.0 * d.target_to_mesh.mean / diag,
            100.0 * d.target_to_mesh.max / diag
        );
        means.push(d.target_to_mesh.mean);
    }
    // Full-wrap pushes into the concavities (between the legs, under the belly) that obstacle
    // bridges: the cloud's mean distance to the surface must drop clearly.
    assert!(
        means[1] < 0.8 * means[0],
        "full-wrap {} vs obstacle {}",
        means[1],
        means[0]
    );
}

/// The bunny bar of the remeshing issue with slightly looser limits (the benchmark in
/// benches/RESULTS.md holds the tight ones): default settings on bunnyPts_3, scored against the
/// scanned mesh bunny.ply.
#[test]
#[cfg_attr(
    not(shared_data),
    ignore = "needs the shared test data (LSW_SHARED_DATA)"
)]
#[cfg_attr(
    shared_data,
    ignore = "corpus tier (whole wraps): cargo test -- --ignored"
)]
fn bunny_wrap_meets_the_bar() {
    let (cloud, reference) = (shared("bunnyPts_3.ply"), shared("bunny.ply"));
    let target = lsw::io::read_path(&cloud).unwrap().target;
    let mesh = lsw::io::read_path(&reference).unwrap().target;
    let mut ev = Evolver::new(&target, WrapSettings::default()).unwrap();
    ev.run(|_| {}).unwrap();
    let report = ev.mesh().validate().unwrap();
    assert_eq!((report.genus, report.components), (0, 1));
    let (pos, tris) = (ev.positions(), ev.triangles());
    let json = lsw::cli::metrics::metrics_json_of(&pos, &tris, Some(&mesh)).unwrap();
    let pct = &json["distances"]["percent_of_target_diagonal"];
    let q = &json["quality"];
    let f = |v: &serde_json::Value| v.as_f64().unwrap();
    println!(
        "bunny: {} V; mean result→mesh {:.3} %, mesh→result {:.3} %, Hausdorff {:.3} %; 2r/R mean {:.4}; κ ≤ 1.5: {:.3} %; volume ratio {:.3}; self-intersections {}",
        pos.len(),
        f(&pct["mesh_to_target"]["mean"]),
        f(&pct["target_to_mesh"]["mean"]),
        f(&pct["hausdorff"]),
        f(&q["radius_ratio"]["mean"]),
        100.0 * f(&q["kappa_le_1_5"]),
        f(&json["target"]["volume_ratio"]),
        json["self_intersections"]
    );
    assert!(pos.len() <= 45_000);
    // Issue 15's bunny-cloud bar: mean ≤ 0.15 % both ways (0.144 / 0.117 with the cloud fit's
    // quadric lift; 0.177 / 0.155 with the plane alone).
    assert!(f(&pct["mesh_to_target"]["mean"]) <= 0.15);
    assert!(f(&pct["target_to_mesh"]["mean"]) <= 0.15);
    // Two holes in the scan's base are wider than 2 % of the diagonal: a flat cap over them is
    // already 3.1 % and 3.4 % from the scan (see benches/RESULTS.md), so 2 % cannot be met by a
    // closed, single-walled surface.
    assert!(f(&pct["hausdorff"]) <= 4.5);
    assert!(f(&q["radius_ratio"]["mean"]) >= 0.955);
    assert!(f(&q["kappa_le_1_5"]) >= 0.99);
    assert!(f(&json["target"]["volume_ratio"]) <= 1.12);
    assert_eq!(json["self_intersections"], 0);
}

/// A small, noisy MRI volume (nibabel's NIfTI-2 test image, 32×20×12 voxels) through the CLI with
/// the defaults. Its evolution makes near-degenerate triangles whose negative cotangent weights
/// stall the solver step after step; it used to end diverged with no mesh written (τ halved for
/// good at each retry, down a thousandfold, and the curved splits' reach in the input's units).
/// It must come out valid, with τ not frozen.
#[test]
#[cfg_attr(
    not(shared_data),
    ignore = "needs the shared test data (LSW_SHARED_DATA)"
)]
#[cfg_attr(
    shared_data,
    ignore = "corpus tier (whole wraps): cargo test -- --ignored"
)]
fn a_noisy_volume_wraps_valid() {
    let path = shared("example_nifti2.nii.gz");
    assert!(path.exists(), "{path:?} is missing");
    let dir = std::env::temp_dir().join(format!("lsw_noisy_volume_{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let (out, stats) = (dir.join("wrap.ply"), dir.join("stats.json"));
    let run = std::process::Command::new(env!("CARGO_BIN_EXE_lsw"))
        .arg("wrap")
        .arg(&path)
        .arg("-o")
        .arg(&out)
        .arg("--stats")
        .arg(&stats)
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&run.stderr);
    assert!(run.status.success(), "lsw wrap failed: {err}");
    let json: serde_json::Value = serde_json::from_slice(&run.stdout).unwrap();
    let c = &json["certificate"];
    println!(
        "example_nifti2: valid {}, genus {}, {} self-intersections",
        c["valid"], c["genus"], c["self_intersections"]
    );
    assert_eq!(c["valid"], true, "{c}");
    assert_eq!(c["self_intersections"], 0);
    assert!(out.exists());
    // τ only falls by the schedule and by real failures, not once per retried step.
    let steps: serde_json::Value = serde_json::from_slice(&std::fs::read(&stats).unwrap()).unwrap();
    let steps = steps["steps"].as_array().unwrap();
    let retried = steps.iter().filter(|s| s["retries"].as_u64() > Some(0));
    let last = steps.last().unwrap()["tau"].as_f64().unwrap();
    println!("{} steps retried; last τ {last:e}", retried.count());
    assert!(last > 1e-4, "τ fell to {last:e}");
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn tangential_term_evens_out_covolumes_on_a_distorted_sphere() {
    let mut mesh = icosphere(3, 1.0, DVec3::ZERO).unwrap();
    // Squeeze the northern hemisphere's vertices towards the pole along the sphere.
    for p in mesh.positions_mut() {
        if p.z > 0.0 {
            *p = DVec3::new(0.6 * p.x, 0.6 * p.y, p.z).normalize();
        }
    }
    let spread = |m: &lsw::mesh::HalfedgeMesh| {
        let a = CotanLaplacian::new(m).covolumes;
        let mean = a.iter().sum::<f64>() / a.len() as f64;
        (a.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / a.len() as f64).sqrt() / mean
    };
    let before = spread(&mesh);
    let mut previous = before;
    for round in 0..50 {
        let normals = angle_weighted_normals(&mesh);
        let v: Vec<DVec3> = (0..mesh.n_vertices() as u32)
            .map(|i| tangential_velocity(&mesh, i, normals[i as usize], 1.0))
            .collect();
        for (p, d) in mesh.positions_mut().iter_mut().zip(&v) {
            *p = (*p + 0.05 * *d).normalize();
        }
        let now = spread(&mesh);
        assert!(
            now <= previous * 1.001,
            "round {round}: spread grew {previous} → {now}"
        );
        previous = now;
    }
    let after = spread(&mesh);
    println!("co-volume relative spread: {before:.3} → {after:.3}");
    assert!(after < 0.9 * before, "{before} → {after}");
    mesh.validate().unwrap();
}
