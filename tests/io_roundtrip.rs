//! Every writer round-trips through its reader: same counts, positions within float precision,
//! the same triangles (by corner positions, since STL renumbers welded vertices), scalars where
//! the format stores them, and the LSW version + settings in the metadata. Runs natively and in
//! headless Chromium.

use lsw::geometry::icosphere::icosphere;
use lsw::io::{read_bytes, write_bytes, Format, IoError, WriteInput};
use lsw::DVec3;
use wasm_bindgen_test::*;

wasm_bindgen_test_configure!(run_in_browser);

const SETTINGS: &str = r#"{ "tau": 0.001, "preset": "bunny" }"#;

fn sphere() -> (Vec<DVec3>, Vec<[u32; 3]>) {
    let m = icosphere(2, 1.5, DVec3::new(0.25, -1.0, 3.0)).unwrap();
    (m.positions().to_vec(), m.triangles())
}

fn ext(f: Format) -> &'static str {
    match f {
        Format::Glb => "glb",
        Format::Obj => "obj",
        Format::Ply => "ply",
        Format::Stl => "stl",
        _ => "vtk",
    }
}

/// Checks positions (f32 precision) and triangles by their corner positions.
fn same_mesh(f: Format, a: (&[DVec3], &[[u32; 3]]), b: (&[DVec3], &[[u32; 3]])) {
    assert_eq!(a.0.len(), b.0.len(), "{f}: vertex count");
    assert_eq!(a.1.len(), b.1.len(), "{f}: triangle count");
    let close =
        |p: DVec3, q: DVec3| (p - q).abs().max_element() <= 1e-6 * (1.0 + p.abs().max_element());
    if f != Format::Stl {
        for (i, (p, q)) in a.0.iter().zip(b.0).enumerate() {
            assert!(close(*p, *q), "{f}: vertex {i}: {p} vs {q}");
        }
    }
    for (t, (s, u)) in a.1.iter().zip(b.1).enumerate() {
        for k in 0..3 {
            let (p, q) = (a.0[s[k] as usize], b.0[u[k] as usize]);
            assert!(close(p, q), "{f}: triangle {t} corner {k}");
        }
    }
}

#[wasm_bindgen_test(unsupported = test)]
fn every_writer_round_trips_a_mesh() {
    let (p, t) = sphere();
    let dist: Vec<f64> = p.iter().map(|q| q.length()).collect();
    let flag: Vec<f64> = (0..p.len()).map(|i| (i % 3) as f64).collect();
    let scalars = [("distance", &dist[..]), ("feature flag", &flag[..])];
    let input = WriteInput {
        positions: &p,
        triangles: &t,
        scalars: &scalars,
        settings_json: Some(SETTINGS),
    };
    for f in Format::WRITABLE {
        let bytes = write_bytes(f, &input).unwrap();
        let name = format!("out.{}", ext(f));
        let r = read_bytes(&bytes, Some(&name)).unwrap_or_else(|e| panic!("{f}: {e}"));
        assert_eq!(r.format, f);
        // Detection by content alone agrees.
        assert_eq!(read_bytes(&bytes, None).unwrap().format, f);
        same_mesh(f, (&p, &t), (&r.target.points, &r.target.triangles));
        let text = String::from_utf8_lossy(&bytes);
        assert!(
            text.contains(&format!("LSW {}", lsw::VERSION)),
            "{f}: version"
        );
        if f != Format::Stl {
            assert!(text.contains("\"preset\":\"bunny\""), "{f}: settings");
        }
    }
}

#[wasm_bindgen_test(unsupported = test)]
fn scalars_round_trip_in_ply_and_vtk() {
    let (p, t) = sphere();
    let dist: Vec<f64> = p.iter().map(|q| q.length() - 1.0).collect();
    let scalars = [("distance", &dist[..])];
    let input = WriteInput {
        positions: &p,
        triangles: &t,
        scalars: &scalars,
        settings_json: None,
    };
    let ply = write_bytes(Format::Ply, &input).unwrap();
    let back = lsw::io::ply::read_vertex_property(&ply, "distance").unwrap();
    assert_eq!(back.len(), p.len());
    assert!(back.iter().zip(&dist).all(|(a, b)| (a - b).abs() < 1e-6));
    let vtk = write_bytes(Format::Vtk, &input).unwrap();
    let (_, s) = lsw::io::vtk::read(&vtk).unwrap();
    assert_eq!(s.len(), 1);
    assert_eq!(s[0].0, "distance");
    assert_eq!(
        s[0].1, dist,
        "VTK writes shortest round-trip decimals: exact"
    );
}

#[wasm_bindgen_test(unsupported = test)]
fn point_clouds_round_trip() {
    let (p, _) = sphere();
    let input = WriteInput::new(&p, &[]);
    for f in [Format::Obj, Format::Ply, Format::Glb, Format::Vtk] {
        let bytes = write_bytes(f, &input).unwrap();
        let r = read_bytes(&bytes, None).unwrap_or_else(|e| panic!("{f}: {e}"));
        assert_eq!(r.target.kind(), lsw::target::TargetKind::Points, "{f}");
        same_mesh(f, (&p, &[]), (&r.target.points, &r.target.triangles));
    }
}

/// A whole-file gzip of any mesh or cloud (`scan.ply.gz`) reads as what it holds, named by the
/// inner extension; a damaged one is an error naming that format, not a NIfTI's.
#[wasm_bindgen_test(unsupported = test)]
fn gzip_compressed_files_read_as_what_they_hold() {
    use std::io::Write;
    let (p, t) = sphere();
    for f in Format::WRITABLE {
        let bytes = write_bytes(f, &WriteInput::new(&p, &t)).unwrap();
        let mut gz = flate2::write::GzEncoder::new(Vec::new(), flate2::Compression::fast());
        gz.write_all(&bytes).unwrap();
        let gz = gz.finish().unwrap();
        let name = format!("scan.{}.gz", ext(f));
        for hint in [Some(name.as_str()), None] {
            let r = read_bytes(&gz, hint).unwrap_or_else(|e| panic!("{f} {hint:?}: {e}"));
            assert_eq!(r.format, f);
            same_mesh(f, (&p, &t), (&r.target.points, &r.target.triangles));
        }
        let cut = &gz[..gz.len() / 2];
        let e = read_bytes(cut, Some(&name)).unwrap_err();
        assert!(e.to_string().starts_with(f.name()), "{f}: {e}");
    }
}

#[wasm_bindgen_test(unsupported = test)]
fn glb_has_normals_and_settings_in_asset_extras() {
    let (p, t) = sphere();
    let bytes = write_bytes(
        Format::Glb,
        &WriteInput {
            settings_json: Some(SETTINGS),
            ..WriteInput::new(&p, &t)
        },
    )
    .unwrap();
    let json_len = u32::from_le_bytes(bytes[12..16].try_into().unwrap()) as usize;
    let v: serde_json::Value = serde_json::from_slice(&bytes[20..20 + json_len]).unwrap();
    assert_eq!(v["asset"]["extras"]["lsw_settings"]["preset"], "bunny");
    assert!(v["asset"]["generator"]
        .as_str()
        .unwrap()
        .contains(lsw::VERSION));
    assert!(v["meshes"][0]["primitives"][0]["attributes"]["NORMAL"].is_number());
}

#[wasm_bindgen_test(unsupported = test)]
fn writers_reject_inconsistent_input() {
    let (p, t) = sphere();
    let short = [0.0; 3];
    let bad_scalars = [("d", &short[..])];
    let bad_tri = [[0, 1, p.len() as u32]];
    let nan = [DVec3::new(f64::NAN, 0.0, 0.0)];
    for f in Format::WRITABLE {
        let e = write_bytes(
            f,
            &WriteInput {
                scalars: &bad_scalars,
                ..WriteInput::new(&p, &t)
            },
        );
        assert!(matches!(e, Err(IoError::InvalidInput { .. })), "{f}: {e:?}");
        let e = write_bytes(f, &WriteInput::new(&p, &bad_tri));
        assert!(matches!(e, Err(IoError::InvalidInput { .. })), "{f}: {e:?}");
        let e = write_bytes(f, &WriteInput::new(&nan, &[]));
        assert!(matches!(e, Err(IoError::InvalidInput { .. })), "{f}: {e:?}");
        let e = write_bytes(
            f,
            &WriteInput {
                settings_json: Some("{oops"),
                ..WriteInput::new(&p, &t)
            },
        );
        if f != Format::Stl {
            assert!(matches!(e, Err(IoError::InvalidInput { .. })), "{f}: {e:?}");
        }
    }
    // A format LSW reads but does not write: said so, with the formats it writes (not "the file
    // looks damaged", the hint every other file error has).
    let e = write_bytes(Format::Xyz, &WriteInput::new(&p, &t)).unwrap_err();
    assert!(matches!(e, IoError::NotWritable { .. }), "{e:?}");
    assert_eq!(
        e.to_string(),
        "cannot write XYZ files: LSW writes .ply, .obj, .stl, .glb or .vtk"
    );
    assert_eq!(e.code(), "io_not_writable");
    let hint = lsw::error::Explain::hint(&e);
    assert_eq!(hint, "Name the output .ply, .obj, .stl, .glb or .vtk.");
}
