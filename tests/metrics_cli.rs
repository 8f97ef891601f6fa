//! `lsw metrics` JSON: the documented keys are present and consistent (native only: the CLI is
//! not part of the wasm build).
#![cfg(not(target_arch = "wasm32"))]

use lsw::cli::metrics::metrics_json_of;
use lsw::geometry::icosphere::icosphere;
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
