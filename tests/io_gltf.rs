//! glTF specifics: node transforms (composed parent → child, instancing one mesh twice), data-URI
//! buffers, strips and fans, POINTS primitives as point clouds. Runs natively and in Chromium.

use lsw::io::{read_bytes, Format};
use lsw::target::TargetKind;
use lsw::DVec3;
use wasm_bindgen_test::*;

wasm_bindgen_test_configure!(run_in_browser);

fn base64(data: &[u8]) -> String {
    const A: &[u8; 64] = b"ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    let mut s = String::new();
    for c in data.chunks(3) {
        let n = (c[0] as u32) << 16
            | (*c.get(1).unwrap_or(&0) as u32) << 8
            | *c.get(2).unwrap_or(&0) as u32;
        for k in 0..4 {
            if k <= c.len() {
                s.push(A[(n >> (18 - 6 * k) & 63) as usize] as char);
            } else {
                s.push('=');
            }
        }
    }
    s
}

/// A glTF with one buffer (4 float positions of a unit square, then 4 u16 indices) and the
/// given mesh primitives / nodes JSON.
fn doc(primitives: &str, nodes: &str, scenes: &str) -> Vec<u8> {
    let mut b = Vec::new();
    for p in [[0f32, 0., 0.], [1., 0., 0.], [0., 1., 0.], [1., 1., 0.]] {
        for c in p {
            b.extend_from_slice(&c.to_le_bytes());
        }
    }
    for i in [0u16, 1, 2, 3] {
        b.extend_from_slice(&i.to_le_bytes());
    }
    format!(
        r#"{{"asset":{{"version":"2.0"}},
        "buffers":[{{"byteLength":{},"uri":"data:application/octet-stream;base64,{}"}}],
        "bufferViews":[{{"buffer":0,"byteLength":48}},{{"buffer":0,"byteOffset":48,"byteLength":8}}],
        "accessors":[{{"bufferView":0,"componentType":5126,"count":4,"type":"VEC3","min":[0,0,0],"max":[1,1,0]}},
                     {{"bufferView":1,"componentType":5123,"count":4,"type":"SCALAR"}}],
        "meshes":[{{"primitives":[{primitives}]}}]
        {nodes}{scenes}}}"#,
        b.len(),
        base64(&b)
    )
    .into_bytes()
}

#[wasm_bindgen_test(unsupported = test)]
fn node_transforms_compose_and_instance() {
    // Node 0 (translation +10 x) has child node 1 (scale 2) with the mesh; node 2 instances the
    // mesh again untransformed.
    let nodes = r#","nodes":[{"translation":[10,0,0],"children":[1]},{"scale":[2,2,2],"mesh":0},{"mesh":0}]"#;
    let scenes = r#","scenes":[{"nodes":[0,2]}],"scene":0"#;
    let prim = r#"{"attributes":{"POSITION":0},"indices":1,"mode":5}"#; // strip: 2 triangles
    let r = read_bytes(&doc(prim, nodes, scenes), None).unwrap();
    assert_eq!(r.format, Format::Gltf);
    assert_eq!(r.target.points.len(), 8);
    assert_eq!(r.target.triangles.len(), 4);
    let has = |p: DVec3| r.target.points.iter().any(|q| (*q - p).length() < 1e-12);
    assert!(
        has(DVec3::new(12.0, 2.0, 0.0)),
        "parent translation after child scale"
    );
    assert!(has(DVec3::new(1.0, 1.0, 0.0)), "the untransformed instance");
    // Strip orientation alternates as the glTF spec says: (p0,p1,p2), (p1,p3,p2); nodes are
    // visited in document order, so the first instance is the translated one.
    assert_eq!(r.target.triangles[..2], [[0, 1, 2], [1, 3, 2]]);
    assert_eq!(r.target.points[0], DVec3::new(10.0, 0.0, 0.0));
}

#[wasm_bindgen_test(unsupported = test)]
fn fans_without_nodes_and_points_primitives() {
    let fan = r#"{"attributes":{"POSITION":0},"mode":6}"#;
    let r = read_bytes(&doc(fan, "", ""), Some("x.gltf")).unwrap();
    assert_eq!(r.target.triangles, vec![[0, 1, 2], [0, 2, 3]]);
    let pts = r#"{"attributes":{"POSITION":0},"mode":0}"#;
    let r = read_bytes(&doc(pts, "", ""), None).unwrap();
    assert_eq!(r.target.kind(), TargetKind::Points);
    assert_eq!(r.target.points.len(), 4);
    // Triangles win over points when both exist; lines are skipped.
    let both = r#"{"attributes":{"POSITION":0},"mode":0},{"attributes":{"POSITION":0},"indices":1,"mode":1},{"attributes":{"POSITION":0},"indices":1,"mode":4}"#;
    let e = read_bytes(&doc(both, "", ""), None).unwrap_err();
    assert!(e.to_string().contains("multiple of 3"), "{e}");
}

#[wasm_bindgen_test(unsupported = test)]
fn node_cycles_are_rejected() {
    let nodes = r#","nodes":[{"children":[1]},{"children":[0],"mesh":0}]"#;
    let scenes = r#","scenes":[{"nodes":[0]}]"#;
    let prim = r#"{"attributes":{"POSITION":0},"mode":0}"#;
    let e = read_bytes(&doc(prim, nodes, scenes), None).unwrap_err();
    assert!(e.to_string().contains("gltf"), "{e}");
}

/// `read_path` loads external buffers from the glTF file's folder; `read_bytes` cannot and says so.
#[cfg(not(target_arch = "wasm32"))]
#[test]
fn read_path_resolves_external_buffers() {
    let dir = std::env::temp_dir().join(format!("lsw_io_gltf_{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let inline = String::from_utf8(doc(
        r#"{"attributes":{"POSITION":0},"indices":1,"mode":5}"#,
        "",
        "",
    ))
    .unwrap();
    let start = inline.find("data:").unwrap();
    let end = start + inline[start..].find('"').unwrap();
    let b64 = &inline[start + "data:application/octet-stream;base64,".len()..end];
    let mut bin = Vec::new();
    for p in [[0f32, 0., 0.], [1., 0., 0.], [0., 1., 0.], [1., 1., 0.]] {
        for c in p {
            bin.extend_from_slice(&c.to_le_bytes());
        }
    }
    for i in [0u16, 1, 2, 3] {
        bin.extend_from_slice(&i.to_le_bytes());
    }
    assert_eq!(base64(&bin), b64);
    let external = format!("{}mesh data.bin{}", &inline[..start], &inline[end..]);
    std::fs::write(dir.join("mesh data.bin"), &bin).unwrap();
    std::fs::write(dir.join("scene.gltf"), &external).unwrap();
    let r = lsw::io::read_path(dir.join("scene.gltf")).unwrap();
    assert_eq!((r.target.points.len(), r.target.triangles.len()), (4, 2));
    let e = read_bytes(external.as_bytes(), Some("scene.gltf")).unwrap_err();
    assert_eq!(e.code(), "io_unsupported");
    std::fs::remove_dir_all(&dir).ok();
}
