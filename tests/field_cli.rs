//! `lsw sdf`: JSON keys and the VTK file (native only; reads `LSW_SHARED_DATA`).
#![cfg(not(target_arch = "wasm32"))]

#[path = "common/field_data.rs"]
mod field_data;

use lsw::cli::sdf::{run, SdfArgs};

#[test]
#[cfg_attr(
    not(shared_data),
    ignore = "needs the shared test data (LSW_SHARED_DATA)"
)]
fn sdf_prints_json_and_writes_vtk() {
    let dir = field_data::data_dir("sdf_prints_json_and_writes_vtk");
    let out = std::env::temp_dir().join(format!("lsw_field_cli_{}.vtk", std::process::id()));
    let args = SdfArgs {
        input: dir.join("spot.obj"),
        cells: 20,
        expand: 0.5,
        band: 2.0,
        truncate: None,
        unsigned: false,
        enclosed: 2.0,
        out: Some(out.clone()),
        volume: Default::default(),
    };
    let text = run(&args).unwrap();
    println!("{text}");
    let v: serde_json::Value = serde_json::from_str(&text).unwrap();
    assert_eq!(v["signedness"], "signed");
    assert_eq!(v["signed"], true);
    let dims: Vec<u64> = v["dims"]
        .as_array()
        .unwrap()
        .iter()
        .map(|d| d.as_u64().unwrap())
        .collect();
    let nodes: u64 = dims.iter().product();
    assert_eq!(v["nodes"].as_u64().unwrap(), nodes);
    assert!(v["min"].as_f64().unwrap() < 0.0 && v["max"].as_f64().unwrap() > 0.0);
    for k in [
        "read", "band", "sweep", "sign", "gradient", "field", "write",
    ] {
        assert!(v["times_ms"][k].as_f64().unwrap() >= 0.0, "{k}");
    }
    let bytes = std::fs::read(&out).unwrap();
    std::fs::remove_file(&out).ok();
    let head = String::from_utf8_lossy(&bytes[..300]);
    assert!(head.contains("DATASET STRUCTURED_POINTS"));
    assert!(head.contains(&format!("DIMENSIONS {} {} {}", dims[0], dims[1], dims[2])));
    // Header + 8 bytes distance + 1 byte band + 12 bytes gradient per node.
    assert!(bytes.len() as u64 > 21 * nodes && (bytes.len() as u64) < 21 * nodes + 1024);

    // Unsigned on request; a missing file is a clear error.
    let v: serde_json::Value = serde_json::from_str(
        &run(&SdfArgs {
            unsigned: true,
            out: None,
            ..args
        })
        .unwrap(),
    )
    .unwrap();
    assert_eq!(v["signedness"], "unsigned");
    let err = run(&SdfArgs {
        input: dir.join("no_such_file.ply"),
        cells: 20,
        expand: 1.0,
        band: 3.0,
        truncate: None,
        unsigned: false,
        enclosed: 2.0,
        out: None,
        volume: Default::default(),
    })
    .unwrap_err();
    assert!(err.contains("no_such_file"), "{err}");
}
