//! The GLB writer: one mesh with positions, normals, indices and one float attribute per scalar.

use crate::io::error::{Format, IoError};
use crate::io::WriteInput;
use glam::DVec3;
use serde_json::json;

/// Area-weighted vertex normals (unit length; +Z where undefined).
fn vertex_normals(p: &[DVec3], t: &[[u32; 3]]) -> Vec<DVec3> {
    let mut n = vec![DVec3::ZERO; p.len()];
    for tri in t {
        let [a, b, c] = tri.map(|i| p[i as usize]);
        let fn_ = (b - a).cross(c - a);
        for &i in tri {
            n[i as usize] += fn_;
        }
    }
    n.into_iter()
        .map(|v| v.try_normalize().unwrap_or(DVec3::Z))
        .collect()
}

/// Writes GLB: one mesh with POSITION, NORMAL (area-weighted), u32 indices, and one float
/// `_NAME` attribute per scalar; bare points (no triangles) become a POINTS primitive.
/// `asset.generator` names the LSW version and `asset.extras.lsw_settings` holds the settings.
pub fn write_glb(input: &WriteInput) -> Result<Vec<u8>, IoError> {
    let f = Format::Glb;
    input.check(f)?;
    if input.positions.is_empty() {
        return Err(IoError::InvalidInput {
            format: f,
            what: "no vertices".into(),
        });
    }
    let n = input.positions.len();
    let mut bin: Vec<u8> = Vec::new();
    let mut views = Vec::new();
    let mut accessors = Vec::new();
    let mut push_view = |bin: &mut Vec<u8>, data: &[u8], target: u32| -> usize {
        let off = bin.len();
        bin.extend_from_slice(data);
        while bin.len() % 4 != 0 {
            bin.push(0);
        }
        views.push(
            json!({"buffer": 0, "byteOffset": off, "byteLength": data.len(), "target": target}),
        );
        views.len() - 1
    };
    let f32s = |v: &mut Vec<u8>, x: f64| v.extend_from_slice(&(x as f32).to_le_bytes());
    let vec3 = |vals: &[DVec3]| {
        let mut d = Vec::with_capacity(12 * vals.len());
        let (mut lo, mut hi) = ([f32::MAX; 3], [f32::MIN; 3]);
        for p in vals {
            for k in 0..3 {
                let c = p[k] as f32;
                lo[k] = lo[k].min(c);
                hi[k] = hi[k].max(c);
                f32s(&mut d, p[k]);
            }
        }
        (d, lo, hi)
    };
    let (d, lo, hi) = vec3(input.positions);
    let v = push_view(&mut bin, &d, 34962);
    accessors.push(json!({"bufferView": v, "componentType": 5126, "count": n, "type": "VEC3", "min": lo, "max": hi}));
    let mut attributes = serde_json::Map::new();
    attributes.insert("POSITION".into(), json!(0));
    if !input.triangles.is_empty() {
        let (d, _, _) = vec3(&vertex_normals(input.positions, input.triangles));
        let v = push_view(&mut bin, &d, 34962);
        accessors.push(json!({"bufferView": v, "componentType": 5126, "count": n, "type": "VEC3"}));
        attributes.insert("NORMAL".into(), json!(accessors.len() - 1));
    }
    for (name, s) in input.scalars {
        let mut d = Vec::with_capacity(4 * n);
        for &x in *s {
            f32s(&mut d, x);
        }
        let v = push_view(&mut bin, &d, 34962);
        accessors
            .push(json!({"bufferView": v, "componentType": 5126, "count": n, "type": "SCALAR"}));
        attributes.insert(
            format!("_{}", crate::io::ply::header_name(name)),
            json!(accessors.len() - 1),
        );
    }
    let mut prim = json!({"attributes": attributes, "mode": 0});
    if !input.triangles.is_empty() {
        let mut d = Vec::with_capacity(12 * input.triangles.len());
        for t in input.triangles {
            for &i in t {
                d.extend_from_slice(&i.to_le_bytes());
            }
        }
        let v = push_view(&mut bin, &d, 34963);
        accessors.push(json!({"bufferView": v, "componentType": 5125, "count": 3 * input.triangles.len(), "type": "SCALAR"}));
        prim["indices"] = json!(accessors.len() - 1);
        prim["mode"] = json!(4);
    }
    let mut asset = json!({"version": "2.0", "generator": format!("LSW {}", crate::VERSION)});
    if let Some(s) = input.settings_value(f)? {
        asset["extras"] = json!({ "lsw_settings": s });
    }
    let doc = json!({
        "asset": asset,
        "scene": 0,
        "scenes": [{"nodes": [0]}],
        "nodes": [{"mesh": 0}],
        "meshes": [{"primitives": [prim]}],
        "buffers": [{"byteLength": bin.len()}],
        "bufferViews": views,
        "accessors": accessors,
    });
    let mut js = serde_json::to_vec(&doc).expect("JSON value");
    while js.len() % 4 != 0 {
        js.push(b' ');
    }
    let total = 12 + 8 + js.len() + 8 + bin.len();
    let mut out = Vec::with_capacity(total);
    out.extend_from_slice(b"glTF");
    out.extend_from_slice(&2u32.to_le_bytes());
    out.extend_from_slice(&(total as u32).to_le_bytes());
    out.extend_from_slice(&(js.len() as u32).to_le_bytes());
    out.extend_from_slice(b"JSON");
    out.extend_from_slice(&js);
    out.extend_from_slice(&(bin.len() as u32).to_le_bytes());
    out.extend_from_slice(b"BIN\0");
    out.extend_from_slice(&bin);
    Ok(out)
}
