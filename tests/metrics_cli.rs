//! `lsw metrics --error-map / --target-error-map` (issue 15, item 1): per-point distances written
//! as scalars, checked against an analytic case. Native only (files).
#![cfg(not(target_arch = "wasm32"))]

use glam::DVec3;
use lsw::cli::metrics::{run, MetricsArgs};
use lsw::geometry::icosphere::icosphere;
use lsw::io::{write_path, WriteInput};

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
