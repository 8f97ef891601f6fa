//! The malformed-input corpus: every case must give a clear, typed error — the right variant,
//! a message naming the format and the place (line or byte) — and never a panic. The cases are
//! generated in code so the same test runs natively and in headless Chromium (wasm tests cannot
//! read files).

use lsw::io::{read_bytes, write_bytes, Format, IoError, WriteInput};
use lsw::DVec3;
use wasm_bindgen_test::*;

wasm_bindgen_test_configure!(run_in_browser);

/// One malformed input: a description, the file name it arrives with, its bytes, the expected
/// error code ([`IoError::code`]) and text the message must contain.
struct Case {
    what: &'static str,
    name: Option<&'static str>,
    bytes: Vec<u8>,
    code: &'static str,
    says: &'static [&'static str],
}

fn case(
    what: &'static str,
    name: Option<&'static str>,
    bytes: impl Into<Vec<u8>>,
    code: &'static str,
    says: &'static [&'static str],
) -> Case {
    Case {
        what,
        name,
        bytes: bytes.into(),
        code,
        says,
    }
}

fn ply_bin_header(nv: usize, nf: usize) -> Vec<u8> {
    format!("ply\nformat binary_little_endian 1.0\nelement vertex {nv}\nproperty float x\nproperty float y\nproperty float z\nelement face {nf}\nproperty list uchar int vertex_indices\nend_header\n").into_bytes()
}

fn f32s(v: &mut Vec<u8>, xs: &[f32]) {
    for x in xs {
        v.extend_from_slice(&x.to_le_bytes());
    }
}

/// A valid small binary PLY triangle (3 vertices, 1 face).
fn ply_triangle() -> Vec<u8> {
    let mut b = ply_bin_header(3, 1);
    f32s(&mut b, &[0., 0., 0., 1., 0., 0., 0., 1., 0.]);
    b.push(3);
    for i in [0i32, 1, 2] {
        b.extend_from_slice(&i.to_le_bytes());
    }
    b
}

/// Deterministic pseudo-random bytes (xorshift), with no text signature.
fn garbage(n: usize) -> Vec<u8> {
    let mut s = 0x9E37_79B9_7F4A_7C15u64;
    (0..n)
        .map(|_| {
            s ^= s << 13;
            s ^= s >> 7;
            s ^= s << 17;
            (s >> 32) as u8 | 0x80
        })
        .collect()
}

fn glb_triangle() -> Vec<u8> {
    let p = [DVec3::ZERO, DVec3::X, DVec3::Y];
    write_bytes(Format::Glb, &WriteInput::new(&p, &[[0, 1, 2]])).unwrap()
}

fn gltf_json(buffer_uri: &str, count: usize) -> Vec<u8> {
    format!(
        r#"{{"asset":{{"version":"2.0"}},"buffers":[{{"byteLength":36,"uri":"{buffer_uri}"}}],
        "bufferViews":[{{"buffer":0,"byteLength":36}}],
        "accessors":[{{"bufferView":0,"componentType":5126,"count":{count},"type":"VEC3","min":[0,0,0],"max":[1,1,0]}}],
        "meshes":[{{"primitives":[{{"attributes":{{"POSITION":0}},"mode":0}}]}}],
        "nodes":[{{"mesh":0}}],"scenes":[{{"nodes":[0]}}],"scene":0}}"#
    )
    .into_bytes()
}

/// 36 bytes (3 float VEC3) as a base64 data URI.
const DATA_URI: &str =
    "data:application/octet-stream;base64,AAAAAAAAAAAAAAAAAACAPwAAAAAAAAAAAAAAAAAAgD8AAAAA";

/// A PTX scan header for a grid of 2 × 1 points (identity pose).
const PTX_HEAD: &str = "2\n1\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n1 0 0 0\n0 1 0 0\n0 0 1 0\n0 0 0 1\n";

const PCD_HEAD: &str =
    "VERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT 1 1 1\nWIDTH 2\nHEIGHT 1\nPOINTS 2\n";

/// A LAS 1.4 (or LAZ) file of 50 points.
fn las_file(laz: bool) -> Vec<u8> {
    let mut b = las::Builder::from((1, 4));
    b.point_format.is_compressed = laz;
    let header = b.into_header().unwrap();
    let mut w = las::Writer::new(std::io::Cursor::new(Vec::new()), header).unwrap();
    for i in 0..50 {
        let t = i as f64 * 0.3;
        let p = las::Point {
            x: lsw::fmath::cos(t),
            y: lsw::fmath::sin(t),
            z: t,
            ..Default::default()
        };
        w.write_point(p).unwrap();
    }
    w.close().unwrap();
    w.into_inner().unwrap().into_inner()
}

/// An E57 file of one scan of 20 Cartesian points.
fn e57_file() -> Vec<u8> {
    use e57::{Record, RecordValue};
    let mut out = std::io::Cursor::new(Vec::new());
    let mut w = e57::E57Writer::new(&mut out, "corpus").unwrap();
    let xyz = vec![
        Record::CARTESIAN_X_F64,
        Record::CARTESIAN_Y_F64,
        Record::CARTESIAN_Z_F64,
    ];
    let mut scan = w.add_pointcloud("scan", xyz).unwrap();
    for i in 0..20 {
        let t = i as f64 * 0.3;
        let v = [lsw::fmath::cos(t), lsw::fmath::sin(t), t].map(RecordValue::Double);
        scan.add_point(v.to_vec()).unwrap();
    }
    scan.finalize().unwrap();
    w.finalize().unwrap();
    drop(w);
    out.into_inner()
}

fn corpus() -> Vec<Case> {
    let tri = ply_triangle();
    let glb = glb_triangle();
    let mut cases = vec![
        case("empty file", None, "", "io_empty", &["empty"]),
        case("0-byte GLB", Some("scan.glb"), "", "io_empty", &["glb", "0 bytes"]),
        case("whitespace only", Some("a.xyz"), " \n\n\t\n", "io_syntax", &["xyz", "line 1"]),
        // --- PLY ---
        case("truncated binary PLY (cut inside the vertices)", Some("t.ply"), tri[..tri.len() - 30].to_vec(), "io_count_too_large", &["ply", "vertex", "bytes follow"]),
        case("truncated binary PLY (cut inside the face list)", Some("t.ply"), tri[..tri.len() - 3].to_vec(), "io_truncated", &["ply", "byte", "list items"]),
        case("PLY header lies about the vertex count", None, {
            let mut b = ply_bin_header(1_000_000_000, 0);
            f32s(&mut b, &[1., 2., 3.]);
            b
        }, "io_count_too_large", &["ply", "line 3", "1000000000"]),
        case("ASCII PLY header lies about the face count", None,
            "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\nelement face 99999\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n",
            "io_count_too_large", &["ply", "face", "99999"]),
        case("PLY without end_header", None, "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\n", "io_truncated", &["ply", "end_header"]),
        case("PLY with an unknown format", None, "ply\nformat binary_middle_endian 1.0\nend_header\n", "io_syntax", &["ply", "line 2", "binary_middle_endian"]),
        case("PLY with an unknown property type", None, "ply\nformat ascii 1.0\nelement vertex 1\nproperty float128 x\nend_header\n", "io_syntax", &["ply", "line 4", "float128"]),
        case("PLY vertex without z", None, "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\nend_header\n1 2\n", "io_syntax", &["ply", "line 3", "a property z"]),
        case("binary PLY face index out of range", None, {
            let mut b = tri.clone();
            let n = b.len();
            b[n - 4..].copy_from_slice(&7i32.to_le_bytes());
            b
        }, "io_index_out_of_range", &["ply", "byte", "vertex 7", "3 vertices"]),
        case("ASCII PLY negative face index", None,
            "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n3 0 -1 2\n",
            "io_index_out_of_range", &["ply", "line 13", "-1"]),
        case("ASCII PLY with NaN", None,
            "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\nend_header\n0 0 0\n1 nan 0\n0 1 0\n",
            "io_non_finite", &["ply", "line 9", "vertex 1"]),
        case("binary PLY with +inf", None, {
            let mut b = tri.clone();
            let o = b.len() - 13 - 12 * 3 + 12 * 2 + 8; // z of vertex 2
            b[o..o + 4].copy_from_slice(&f32::INFINITY.to_le_bytes());
            b
        }, "io_non_finite", &["ply", "byte", "vertex 2", "inf"]),
        case("ASCII PLY with a word for a number", None,
            "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\nproperty float z\nend_header\n0 zero 0\n",
            "io_syntax", &["ply", "line 8", "zero"]),
        case("ASCII PLY face with two vertices", None,
            "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n2 0 1\n",
            "io_syntax", &["ply", "line 13", "at least 3"]),
        case("binary garbage named .ply", Some("scan.ply"), garbage(500), "io_syntax", &["ply", "line 1", "\"ply\""]),
        // --- OBJ ---
        case("OBJ face index out of range", None, "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 4\n", "io_index_out_of_range", &["obj", "line 4", "vertex 4"]),
        case("OBJ face index 0", None, "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 0 1 2\n", "io_index_out_of_range", &["obj", "line 4"]),
        case("OBJ negative index before the first vertex", None, "v 0 0 0\nf -1 -2 -3\n", "io_index_out_of_range", &["obj", "line 2", "-2"]),
        case("OBJ v with two coordinates", None, "v 0 0 0\nv 1 2\n", "io_syntax", &["obj", "line 2", "three coordinates"]),
        case("OBJ with inf", None, "v 0 0 0\nv 1 inf 0\n", "io_non_finite", &["obj", "line 2", "vertex 1"]),
        case("OBJ face with a bad index", None, "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 x/1\n", "io_syntax", &["obj", "line 4", "x/1"]),
        case("OBJ with only comments", Some("a.obj"), "# nothing\n# here\n", "io_target", &["obj", "empty"]),
        case("binary garbage named .obj", Some("a.obj"), garbage(300), "io_syntax", &["obj", "byte 0", "text"]),
        case("binary garbage named .xyz", Some("a.xyz"), garbage(300), "io_syntax", &["xyz", "byte 0", "text"]),
        case("binary garbage without a name", None, garbage(300), "io_unknown_format", &["unrecognised"]),
        // --- STL ---
        case("binary STL whose count exceeds the file", Some("a.stl"), {
            let mut b = vec![0u8; 80];
            b.extend_from_slice(&100u32.to_le_bytes());
            b.extend_from_slice(&[0u8; 50]);
            b
        }, "io_count_too_large", &["stl", "byte 80", "100 triangles"]),
        case("STL shorter than its header", Some("a.stl"), vec![1u8; 40], "io_truncated", &["stl", "84-byte"]),
        case("ASCII STL cut inside a facet", None, "solid x\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\n", "io_truncated", &["stl", "line 6", "endfacet"]),
        case("ASCII STL with NaN", None, "solid x\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex NaN 0 0\nvertex 0 1 0\nendloop\nendfacet\nendsolid\n", "io_non_finite", &["stl", "line 5"]),
        case("ASCII STL with a stray keyword", None, "solid x\nfacet normal 0 0 1\nouter loop\nvertx 0 0 0\n", "io_syntax", &["stl", "line 4", "vertx"]),
        // --- OFF ---
        case("OFF counts exceed the file", None, "OFF\n100000 1 0\n0 0 0\n", "io_count_too_large", &["off", "line 2", "100000"]),
        case("OFF with a missing vertex", None, "OFF\n3 0 0\n0 0 0\n1 0 0\n", "io_truncated", &["off", "vertex 2 of 3"]),
        case("OFF face index out of range", None, "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 3\n", "io_index_out_of_range", &["off", "line 6", "vertex 3"]),
        case("OFF 4D variant", None, "4OFF\n1 0 0\n0 0 0 0\n", "io_unsupported", &["off", "4OFF"]),
        // --- XYZ ---
        case("XYZ with NaN", Some("p.xyz"), "1 2 3\n4 NaN 6\n", "io_non_finite", &["xyz", "line 2", "vertex 1"]),
        case("XYZ with a broken row", Some("p.csv"), "x,y,z\n1,2,3\n4,5\n", "io_syntax", &["xyz", "line 3", "end of line"]),
        case("XYZ with only a header", Some("p.txt"), "x y z\n", "io_syntax", &["xyz", "three numbers"]),
        // --- glTF / GLB ---
        case("glTF that is not JSON", Some("a.gltf"), "{ \"asset\": ", "io_syntax", &["gltf", "line 1", "JSON"]),
        case("glTF with an external buffer", None, gltf_json("mesh.bin", 3), "io_unsupported", &["gltf", "external"]),
        case("glTF accessor past the end of its buffer", None, gltf_json(DATA_URI, 4), "io_gltf", &["gltf", "accessor 0"]),
        case("GLB whose length field exceeds the file", None, b"glTF\x02\0\0\0\xff\xff\0\0garbage".to_vec(), "io_truncated", &["glb", "byte 19", "65535 bytes"]),
        case("GLB of version 1", Some("a.glb"), b"glTF\x01\0\0\0\x14\0\0\0\0\0\0\0JSON".to_vec(), "io_unsupported", &["glb", "version 1"]),
        case("truncated GLB", Some("a.glb"), glb[..glb.len() / 2].to_vec(), "io_truncated", &["glb", "byte"]),
        case("GLB whose JSON chunk is cut", None, {
            let mut b = glb.clone();
            b[12..16].copy_from_slice(&100_000u32.to_le_bytes());
            b
        }, "io_truncated", &["glb", "chunk of 100000 bytes"]),
        case("glTF POSITION naming a missing accessor (fuzzing find)", None, {
            String::from_utf8(gltf_json(DATA_URI, 3)).unwrap().replace("\"POSITION\":0", "\"POSITION\":5")
        }, "io_gltf", &["gltf", "accessor 5"]),
        // --- VTK ---
        case("binary legacy VTK", None, "# vtk DataFile Version 3.0\nx\nBINARY\nDATASET POLYDATA\n", "io_unsupported", &["vtk", "binary"]),
        case("VTK POINTS count exceeds the file", None, "# vtk DataFile Version 3.0\nx\nASCII\nDATASET POLYDATA\nPOINTS 5000000 float\n0 0 0\n", "io_count_too_large", &["vtk", "line 5", "5000000"]),
        case("VTK polygon index out of range", None, "# vtk DataFile Version 3.0\nx\nASCII\nDATASET POLYDATA\nPOINTS 3 float\n0 0 0 1 0 0 0 1 0\nPOLYGONS 1 4\n3 0 1 9\n", "io_index_out_of_range", &["vtk", "line 8", "vertex 9"]),
        case("VTK with a second POINTS section (fuzzing find)", None, "# vtk DataFile Version 3.0\nx\nASCII\nDATASET POLYDATA\nPOINTS 1 float\n0 0 0\nPOINTS 1 float\n1 1 1\n", "io_syntax", &["vtk", "line 7", "single POINTS"]),
        // --- PCD ---
        case("PCD without a DATA line", Some("a.pcd"), PCD_HEAD, "io_truncated", &["pcd", "DATA"]),
        case("binary PCD whose count exceeds the file", None, format!("{PCD_HEAD}DATA binary\n\0\0\0\0").replace("POINTS 2", "POINTS 9000000000"), "io_count_too_large", &["pcd", "9000000000 points"]),
        case("PCD without a z field", None, format!("{PCD_HEAD}DATA ascii\n1 2 3\n4 5 6\n").replace("x y z", "x y w"), "io_syntax", &["pcd", "fields x, y and z"]),
        case("PCD with x as a 16-bit float", None, format!("{PCD_HEAD}DATA ascii\n1 2 3\n4 5 6\n").replace("SIZE 4", "SIZE 2"), "io_syntax", &["pcd", "line 4", "TYPE F SIZE 2"]),
        case("ASCII PCD with a missing point", None, format!("{PCD_HEAD}DATA ascii\n1 2 3\n"), "io_truncated", &["pcd", "2 points", "found 1"]),
        case("ASCII PCD with a word for a number", None, format!("{PCD_HEAD}DATA ascii\n1 2 3\n4 five 6\n"), "io_syntax", &["pcd", "line 11", "\"five\""]),
        case("PCD whose points are all NaN", None, format!("{PCD_HEAD}DATA ascii\nnan nan nan\nnan nan nan\n"), "io_syntax", &["pcd", "2 points without a measurement (nan pixels) and no other point"]),
        case("compressed PCD with a corrupt back-reference", None, {
            let mut b = format!("{PCD_HEAD}DATA binary_compressed\n").into_bytes();
            b.extend(3u32.to_le_bytes());
            b.extend(24u32.to_le_bytes());
            b.extend([0x3f, 0xff, 0xff]); // a reference before the start of the output
            b
        }, "io_decompress", &["pcd", "lzf"]),
        // --- LAS / LAZ ---
        case("LAS cut inside its header", Some("a.las"), las_file(false)[..150].to_vec(), "io_truncated", &["las", "header"]),
        case("LAS cut inside its points", None, { let b = las_file(false); b[..b.len() - 10].to_vec() }, "io_truncated", &["las", "point records"]),
        case("LAZ cut inside its points", None, { let b = las_file(true); b[..b.len() - 40].to_vec() }, "io_truncated", &["las", "chunk table"]),
        case("LAS whose count exceeds the file", None, {
            let mut b = las_file(false);
            b[107..111].copy_from_slice(&u32::MAX.to_le_bytes()); // legacy count
            b[247..255].copy_from_slice(&(1u64 << 40).to_le_bytes()); // LAS 1.4 count
            b
        }, "io_count_too_large", &["las", "points"]),
        case("LAZ whose chunk table claims 4 × 10⁹ chunks (fuzzing find)", None, {
            let mut b = las_file(true);
            let start = u32::from_le_bytes(b[96..100].try_into().unwrap()) as usize;
            let table = i64::from_le_bytes(b[start..start + 8].try_into().unwrap()) as usize;
            b[table + 4..table + 8].copy_from_slice(&u32::MAX.to_le_bytes());
            b
        }, "io_count_too_large", &["las", "4294967295 LASzip chunks"]),
        case("LAZ whose point count overflows 64 bits of bytes (fuzzing find)", None, {
            let mut b = las_file(true);
            b[107..111].copy_from_slice(&0u32.to_le_bytes()); // legacy count 0: the 1.4 one counts
            b[247..255].copy_from_slice(&(1u64 << 62).to_le_bytes());
            b
        }, "io_count_too_large", &["las", "4611686018427387904 points"]),
        case("binary garbage named .laz", Some("a.laz"), garbage(400), "io_syntax", &["las", "LASF"]),
        // --- E57 ---
        case("E57 cut inside a page", Some("a.e57"), e57_file()[..1500].to_vec(), "io_truncated", &["e57", "whole number of pages"]),
        case("E57 with a flipped byte (checksum)", None, { let mut b = e57_file(); b[100] ^= 1; b }, "io_syntax", &["e57", "byte 0"]),
        case("binary garbage named .e57", Some("a.e57"), garbage(2048), "io_syntax", &["e57", "header"]),
        // --- PTX ---
        case("PTX cut inside its points", Some("a.ptx"), PTX_HEAD.to_string() + "1 2 3 0\n", "io_truncated", &["ptx", "2 points of scan 0", "found 1"]),
        case("PTX with a matrix row of three numbers", None, PTX_HEAD.replace("0 0 1 0\n", "0 0 1\n"), "io_syntax", &["ptx", "line 9", "4 × 4"]),
        case("PTX with a word for a coordinate", None, PTX_HEAD.to_string() + "1 2 3 0\n1 x 3 0\n", "io_syntax", &["ptx", "line 12", "\"1 x 3 0\""]),
        // --- unknown ---
        case("plain prose", None, "hello world\nthis is not geometry\n", "io_unknown_format", &["unrecognised", "hello"]),
    ];
    // The GLB sanity: the untruncated file reads.
    assert!(read_bytes(&glb, None).is_ok());
    for laz in [false, true] {
        assert_eq!(
            read_bytes(&las_file(laz), None)
                .unwrap()
                .target
                .points
                .len(),
            50
        );
    }
    cases.retain(|c| !c.what.is_empty());
    cases
}

#[wasm_bindgen_test(unsupported = test)]
fn every_malformed_input_gives_a_clear_typed_error() {
    let cases = corpus();
    assert!(cases.len() >= 25, "the corpus must hold at least 25 cases");
    let mut failures = Vec::new();
    for c in &cases {
        match read_bytes(&c.bytes, c.name) {
            Ok(r) => failures.push(format!(
                "{}: read OK as {} ({} points)",
                c.what,
                r.format,
                r.target.points.len()
            )),
            Err(e) => {
                let msg = e.to_string();
                assert!(!e.hint().is_empty());
                println!("{:<50} {msg}", c.what);
                if e.code() != c.code {
                    failures.push(format!(
                        "{}: code {} (expected {}): {msg}",
                        c.what,
                        e.code(),
                        c.code
                    ));
                }
                for s in c.says {
                    if !msg.to_lowercase().contains(&s.to_lowercase()) {
                        failures.push(format!("{}: message lacks {s:?}: {msg}", c.what));
                    }
                }
            }
        }
    }
    assert!(
        failures.is_empty(),
        "{} of {} cases failed:\n{}",
        failures.len(),
        cases.len(),
        failures.join("\n")
    );
    println!("{} corpus cases gave the expected errors", cases.len());
}

/// A tetrahedron with a scalar layer, written in every writable format.
fn tetrahedron_files(settings_json: &str) -> Vec<(Format, Vec<u8>)> {
    let p = [DVec3::ZERO, DVec3::X, DVec3::Y, DVec3::Z];
    let t = [[0, 2, 1], [0, 1, 3], [1, 2, 3], [0, 3, 2]];
    let d = [1.0, 2.0, 3.0, 4.0];
    let s = [("d", &d[..])];
    let input = WriteInput {
        positions: &p,
        triangles: &t,
        scalars: &s,
        settings_json: Some(settings_json),
    };
    Format::WRITABLE
        .into_iter()
        .map(|f| (f, write_bytes(f, &input).unwrap()))
        .collect()
}

/// Every prefix of valid files (truncation at every byte) gives `Ok` or an error, never a panic.
#[wasm_bindgen_test(unsupported = test)]
fn every_truncation_of_valid_files_is_handled() {
    for (f, bytes) in tetrahedron_files("{}") {
        let mut errors = 0;
        for n in 0..bytes.len() {
            if let Err(e) = read_bytes(&bytes[..n], Some("cut.bin")) {
                assert!(!e.to_string().is_empty());
                errors += 1;
            }
        }
        assert!(errors > 0, "{f}");
    }
    // An error is a value the caller can match on.
    assert!(matches!(
        read_bytes(b"", None),
        Err(IoError::Empty { format: None })
    ));
}

/// Writes fuzzing seeds (every corpus case and every writer's output) into
/// `$LSW_FUZZ_SEEDS/<target>/` when that variable is set: `LSW_FUZZ_SEEDS=fuzz/corpus cargo
/// test --test io_corpus write_fuzz_seeds`. Does nothing otherwise.
#[cfg(not(target_arch = "wasm32"))]
#[test]
fn write_fuzz_seeds() {
    let Some(dir) = std::env::var_os("LSW_FUZZ_SEEDS") else {
        return;
    };
    let dir = std::path::PathBuf::from(dir);
    let target_of = |bytes: &[u8], name: Option<&str>| match lsw::io::detect(bytes, name) {
        Ok(f) => f.name(),
        Err(_) => "read_bytes",
    };
    let mut seeds: Vec<(String, Vec<u8>, &str)> = Vec::new();
    for (i, c) in corpus().into_iter().enumerate() {
        let t = target_of(&c.bytes, c.name);
        seeds.push((format!("case{i}"), c.bytes, t));
    }
    let p = [DVec3::ZERO, DVec3::X, DVec3::Y, DVec3::Z];
    for (f, b) in tetrahedron_files("{\"a\":1}") {
        seeds.push((
            format!("written_{f}"),
            b.clone(),
            if f == Format::Glb { "gltf" } else { f.name() },
        ));
        let pts = write_bytes(f, &WriteInput::new(&p, &[])).unwrap_or_default();
        seeds.push((
            format!("written_points_{f}"),
            pts,
            if f == Format::Glb { "gltf" } else { f.name() },
        ));
    }
    seeds.push((
        "off".into(),
        b"OFF\n4 2 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n3 0 1 2\n4 0 1 2 3\n".to_vec(),
        "off",
    ));
    seeds.push(("xyz".into(), b"x,y,z\n1,2,3,4\n5 6 7\n".to_vec(), "xyz"));
    seeds.push(("gltf".into(), gltf_json(DATA_URI, 3), "gltf"));
    seeds.push(("las".into(), las_file(false), "las"));
    seeds.push(("laz".into(), las_file(true), "las"));
    seeds.push(("e57".into(), e57_file(), "e57"));
    let ptx = PTX_HEAD.to_string() + "1 2 3 0.5 10 20 30\n0 0 0 0 0 0 0\n";
    seeds.push(("ptx".into(), ptx.into_bytes(), "ptx"));
    seeds.push((
        "pcd_ascii".into(),
        format!("{PCD_HEAD}DATA ascii\n1 2 3\nnan 0 0\n").into_bytes(),
        "pcd",
    ));
    let mut compressed = format!("{PCD_HEAD}DATA binary_compressed\n").into_bytes();
    // x = [1, 4], y = [2, 5], z = [3, 6] as f32 in one LZF literal run of 24 bytes.
    let packed = [
        23u8, 0, 0, 128, 63, 0, 0, 128, 64, 0, 0, 0, 64, 0, 0, 160, 64, 0, 0, 64, 64, 0, 0, 192, 64,
    ];
    compressed.extend((packed.len() as u32).to_le_bytes());
    compressed.extend(24u32.to_le_bytes());
    compressed.extend(packed);
    assert_eq!(
        read_bytes(&compressed, None).unwrap().target.points.len(),
        2
    );
    seeds.push(("pcd_compressed".into(), compressed, "pcd"));
    for (name, bytes, t) in seeds {
        let t = if t == "glb" { "gltf" } else { t };
        for sub in [t, "read_bytes"] {
            let d = dir.join(sub);
            std::fs::create_dir_all(&d).unwrap();
            std::fs::write(d.join(&name), &bytes).unwrap();
        }
    }
}

/// Inputs the fuzzers found (fuzz/README.md), kept as they were found: each is a clear error now,
/// where the las and laz crates panicked or asked for gigabytes, and PTX's grid size overflowed.
#[wasm_bindgen_test(unsupported = test)]
fn fuzzing_finds_are_clear_errors() {
    let finds: [(&str, &[u8], &str, &str); 8] = [
        (
            "las-chunk-count.laz",
            include_bytes!("fuzz-finds/las-chunk-count.laz"),
            "io_count_too_large",
            "LASzip chunks",
        ),
        (
            "las-chunk-table-short.laz",
            include_bytes!("fuzz-finds/las-chunk-table-short.laz"),
            "io_syntax",
            "chunk table for the header's 50 points",
        ),
        (
            "las-count-overflow.las",
            include_bytes!("fuzz-finds/las-count-overflow.las"),
            "io_count_too_large",
            "points",
        ),
        (
            "las-evlr-length.las",
            include_bytes!("fuzz-finds/las-evlr-length.las"),
            "io_count_too_large",
            "extended VLR",
        ),
        (
            "las-no-laszip-items.laz",
            include_bytes!("fuzz-finds/las-no-laszip-items.laz"),
            "io_syntax",
            "lists none",
        ),
        (
            "las-no-laszip-items-2.laz",
            include_bytes!("fuzz-finds/las-no-laszip-items-2.laz"),
            "io_syntax",
            "lists none",
        ),
        (
            "las-record-length.laz",
            include_bytes!("fuzz-finds/las-record-length.laz"),
            "io_truncated",
            "point records",
        ),
        (
            "ptx-grid-overflow.ptx",
            include_bytes!("fuzz-finds/ptx-grid-overflow.ptx"),
            "io_count_too_large",
            "grid cells",
        ),
    ];
    for (name, bytes, code, says) in finds {
        let e = read_bytes(bytes, Some(name)).map(|r| r.format).unwrap_err();
        assert_eq!(e.code(), code, "{name}: {e}");
        assert!(e.to_string().contains(says), "{name}: {e}");
    }
}

/// Corrupt LAZ data that panics inside the laz crate's arithmetic decoder (a fuzzing find no
/// header check can foresee): natively the reader catches it and says the data is corrupt. In
/// wasm a panic cannot be caught (the app reports the worker's trap), so this runs natively only.
#[cfg(not(target_arch = "wasm32"))]
#[test]
fn a_laz_decoder_panic_is_a_clear_error_natively() {
    let bytes = include_bytes!("fuzz-finds/las-decoder-panic.laz");
    let e = read_bytes(bytes, Some("las-decoder-panic.laz"))
        .map(|r| r.format)
        .unwrap_err();
    assert_eq!(e.code(), "io_decompress", "{e}");
    assert!(e.to_string().contains("LASzip decoder"), "{e}");
}
