//! Every file in the shared test-data folder (`LSW_SHARED_DATA`) reads with the right format,
//! kind and counts, and the closed meshes have the Euler characteristic of their genus.
//! Native only (reads files); ignored when the build had no `LSW_SHARED_DATA`.
#![cfg(not(target_arch = "wasm32"))]

use lsw::io::{read_path, Format};
use lsw::target::TargetKind;

/// (file, format, kind, vertices, triangles, Euler characteristic of the closed mesh if closed).
type Expected = (&'static str, Format, TargetKind, usize, usize, Option<i64>);

const EXPECTED: &[Expected] = &[
    (
        "bunnyPts_3.ply",
        Format::Ply,
        TargetKind::Points,
        11_988,
        0,
        None,
    ),
    (
        "bunnyPts_Minimal.ply",
        Format::Ply,
        TargetKind::Points,
        20,
        0,
        None,
    ),
    (
        "spotPts_4.ply",
        Format::Ply,
        TargetKind::Points,
        1_307,
        0,
        None,
    ),
    // 5 holes in the base: not closed.
    (
        "bunny.ply",
        Format::Ply,
        TargetKind::Mesh,
        35_947,
        69_451,
        None,
    ),
    (
        "bunnyLSW150_FullWrap.obj",
        Format::Obj,
        TargetKind::Mesh,
        42_629,
        85_254,
        Some(2),
    ),
    (
        "spot.obj",
        Format::Obj,
        TargetKind::Mesh,
        2_930,
        5_856,
        Some(2),
    ),
    (
        "1Torus.obj",
        Format::Obj,
        TargetKind::Mesh,
        536,
        1_072,
        Some(0),
    ),
    (
        "2Torus.obj",
        Format::Obj,
        TargetKind::Mesh,
        2_467,
        4_938,
        Some(-2),
    ),
    (
        "3Torus.obj",
        Format::Obj,
        TargetKind::Mesh,
        1_914,
        3_836,
        Some(-4),
    ),
    // 24 quads (fan-triangulated) on 26 vertices: a cube-sphere.
    (
        "CubeSphere.obj",
        Format::Obj,
        TargetKind::Mesh,
        26,
        48,
        Some(2),
    ),
    // 48 corners welded to 10 vertices; two wedges sharing an edge (non-manifold), mended on
    // reading into two closed wedges: the edge's 2 vertices split, 12 in all.
    (
        "DoubleWedge.stl",
        Format::Stl,
        TargetKind::Mesh,
        12,
        16,
        None,
    ),
];

/// The shared test-data folder (the tests reading it are ignored without it).
fn shared_dir() -> std::path::PathBuf {
    std::env::var_os("LSW_SHARED_DATA")
        .expect("LSW_SHARED_DATA (the build had it)")
        .into()
}

fn euler(points: usize, tris: &[[u32; 3]]) -> i64 {
    points as i64 - lsw::mesh::edge_counts(tris).edges as i64 + tris.len() as i64
}

#[test]
#[cfg_attr(
    not(shared_data),
    ignore = "needs the shared test data (LSW_SHARED_DATA)"
)]
fn every_shared_file_reads_with_the_right_kind_and_counts() {
    let dir = shared_dir();
    let mut seen = 0;
    let mut entries: Vec<_> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .collect();
    entries.sort();
    for path in entries {
        let name = path.file_name().unwrap().to_str().unwrap().to_string();
        // Voxel volumes are checked by tests/io_volume.rs.
        if name.ends_with(".md")
            || [".nii", ".nii.gz", ".nrrd", ".vti", ".mha"]
                .iter()
                .any(|e| name.ends_with(e))
        {
            continue;
        }
        let &(_, format, kind, nv, nf, chi) = EXPECTED
            .iter()
            .find(|e| e.0 == name)
            .unwrap_or_else(|| panic!("{name}: new data file; add its expected counts here"));
        let t0 = std::time::Instant::now();
        let r = read_path(&path).unwrap_or_else(|e| panic!("{name}: {e}"));
        let ms = t0.elapsed().as_secs_f64() * 1e3;
        println!(
            "{name}: {} {:?} {} V {} F ({ms:.1} ms)",
            r.format,
            r.target.kind(),
            r.target.points.len(),
            r.target.triangles.len()
        );
        assert_eq!(r.format, format, "{name}");
        assert_eq!(r.target.kind(), kind, "{name}");
        assert_eq!(r.target.points.len(), nv, "{name}");
        assert_eq!(r.target.triangles.len(), nf, "{name}");
        assert!(r.target.bbox.diagonal() > 0.0, "{name}");
        if let Some(chi) = chi {
            assert_eq!(euler(nv, &r.target.triangles), chi, "{name}");
        }
        // The format is found from the content alone too.
        let bytes = std::fs::read(&path).unwrap();
        assert_eq!(
            lsw::io::read_bytes(&bytes, None).unwrap().target,
            r.target,
            "{name}"
        );
        seen += 1;
    }
    assert_eq!(
        seen,
        EXPECTED.len(),
        "some expected files are missing from {dir:?}"
    );
}

#[test]
#[cfg_attr(
    not(shared_data),
    ignore = "needs the shared test data (LSW_SHARED_DATA)"
)]
fn bunny_bbox_diagonals_match_the_readme() {
    let dir = shared_dir();
    let d = read_path(dir.join("bunnyPts_3.ply"))
        .unwrap()
        .target
        .bbox
        .diagonal();
    assert!((d - 0.24996).abs() < 1e-5, "{d}");
    let d = read_path(dir.join("bunny.ply"))
        .unwrap()
        .target
        .bbox
        .diagonal();
    assert!((d - 0.25025).abs() < 1e-5, "{d}");
}

#[test]
#[cfg_attr(
    not(shared_data),
    ignore = "needs the shared test data (LSW_SHARED_DATA)"
)]
fn info_cli_reports_topology() {
    let dir = shared_dir();
    let run = |f: &str| {
        let a = lsw::cli::info::InfoArgs {
            file: dir.join(f),
            volume: Default::default(),
        };
        let s = lsw::cli::info::run(&a).unwrap();
        serde_json::from_str::<serde_json::Value>(&s).unwrap()
    };
    let v = run("2Torus.obj");
    assert_eq!(v["kind"], "mesh");
    assert_eq!(v["closed"], true);
    assert_eq!(v["manifold"], true);
    assert_eq!(v["euler_characteristic"], -2);
    let v = run("bunny.ply");
    assert_eq!(v["closed"], false);
    assert_eq!(v["vertices"], 35_947);
    let v = run("bunnyPts_3.ply");
    assert_eq!(v["kind"], "points");
    assert!(v.get("closed").is_none());
    // Two wedges on one edge: mended on reading (see `mesh::repair`), and said so.
    let v = run("DoubleWedge.stl");
    assert_eq!((&v["manifold"], &v["closed"]), (&true.into(), &true.into()));
    assert_eq!(v["repairs"]["split_vertices"], 2);
    assert_eq!(run("bunny.ply")["repairs"], serde_json::Value::Null);
    let e = lsw::cli::info::run(&lsw::cli::info::InfoArgs {
        file: dir.join("README.md"),
        volume: Default::default(),
    })
    .unwrap_err();
    assert!(e.contains("unrecognised"), "{e}");
}

/// `lsw info` exits non-zero with the reader's message on bad input, and prints JSON otherwise.
#[test]
fn info_binary_exit_codes() {
    let dir = std::env::temp_dir().join(format!("lsw_io_info_{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let bad = dir.join("broken.ply");
    std::fs::write(
        &bad,
        "ply\nformat ascii 1.0\nelement vertex 5000\nproperty float x\nend_header\n",
    )
    .unwrap();
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_lsw"))
        .arg("info")
        .arg(&bad)
        .output()
        .unwrap();
    assert!(!out.status.success());
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("ply: line 3"), "{err}");
    let good = dir.join("tri.off");
    std::fs::write(&good, "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n").unwrap();
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_lsw"))
        .arg("info")
        .arg(&good)
        .output()
        .unwrap();
    assert!(out.status.success());
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(v["format"], "off");
    assert_eq!(v["closed"], false);
    assert_eq!(v["euler_characteristic"], 1);
    std::fs::remove_dir_all(&dir).ok();
}
