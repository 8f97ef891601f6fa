//! glTF 2.0 (JSON) and GLB: reader via the `gltf` crate, and a GLB writer.
//!
//! Reading walks the default scene (or the first, or — without scenes — every root node, or —
//! without nodes — every mesh) and applies node transforms. Triangle, strip and fan primitives
//! become triangles; if there are none, POINTS primitives become a point cloud (lines are
//! skipped). Buffers may be the GLB binary chunk or base64 `data:` URIs; external files are
//! rejected, since a dropped file arrives alone.
//!
//! The `gltf` crate's accessor reader trusts offsets and counts in ways that can overflow on
//! hostile input, so every accessor used is first checked here against the real buffer length
//! (`check_accessor`), and the total instanced output is bounded relative to the input size.

use super::error::{Format, IoError, Location};
use super::{Encoding, RawGeometry};
use ::gltf::accessor::{DataType, Dimensions};
use ::gltf::mesh::Mode;
use glam::{DMat3, DMat4, DVec3};
use std::borrow::Cow;

mod write;

pub use write::write_glb;

/// Node hierarchies deeper than this are rejected (they are cycles or corrupt).
const MAX_DEPTH: usize = 64;
/// Output vertices may exceed the input's bytes by at most this factor (instancing), which
/// bounds memory on hostile files whose nodes instance one mesh millions of times.
const MAX_INSTANCING: usize = 16;

fn gltf_err(format: Format, e: impl std::fmt::Display) -> IoError {
    IoError::Gltf {
        format,
        message: e.to_string(),
    }
}

/// Decodes standard base64 (with optional `=` padding); `None` on a bad character.
fn base64_decode(s: &[u8]) -> Option<Vec<u8>> {
    let val = |c: u8| -> Option<u32> {
        Some(match c {
            b'A'..=b'Z' => c - b'A',
            b'a'..=b'z' => c - b'a' + 26,
            b'0'..=b'9' => c - b'0' + 52,
            b'+' | b'-' => 62,
            b'/' | b'_' => 63,
            _ => return None,
        } as u32)
    };
    let s = s
        .strip_suffix(b"==")
        .or_else(|| s.strip_suffix(b"="))
        .unwrap_or(s);
    let mut out = Vec::with_capacity(s.len() / 4 * 3 + 3);
    for chunk in s.chunks(4) {
        let mut acc = 0u32;
        for (i, &c) in chunk.iter().enumerate() {
            acc |= val(c)? << (18 - 6 * i);
        }
        let bytes = acc.to_be_bytes();
        match chunk.len() {
            4 => out.extend_from_slice(&bytes[1..4]),
            3 => out.extend_from_slice(&bytes[1..3]),
            2 => out.push(bytes[1]),
            _ => return None,
        }
    }
    Some(out)
}

/// Checks that an accessor's bytes lie inside its (available) buffer; returns nothing useful,
/// only an error naming the accessor when they do not.
fn check_accessor(
    format: Format,
    acc: &::gltf::Accessor,
    buffers: &[Option<Cow<[u8]>>],
) -> Result<(), IoError> {
    let bad = |what: String| IoError::Gltf {
        format,
        message: format!("accessor {}: {what}", acc.index()),
    };
    if acc.sparse().is_some() {
        return Err(IoError::Unsupported {
            format,
            what: format!("sparse accessor {}", acc.index()),
        });
    }
    let Some(view) = acc.view() else {
        return Err(bad("has no bufferView".into()));
    };
    if acc.count() == 0 {
        return Err(bad("has count 0".into()));
    }
    let data = match buffers.get(view.buffer().index()) {
        Some(Some(d)) => d,
        _ => {
            return Err(IoError::Unsupported {
                format,
                what: format!(
                    "buffer {} (an external file that is not available; use GLB or embed the buffer as a data: URI)",
                    view.buffer().index()
                ),
            })
        }
    };
    let size = acc.size();
    let stride = view.stride().unwrap_or(size);
    if stride < size {
        return Err(bad(format!(
            "byteStride {stride} is smaller than the element size {size}"
        )));
    }
    let view_end = view.offset().checked_add(view.length());
    let need = (acc.count() as u128 - 1) * stride as u128 + size as u128 + acc.offset() as u128;
    match view_end {
        Some(end) if end <= data.len() && need <= view.length() as u128 => Ok(()),
        _ => Err(bad(format!(
            "needs {need} bytes of bufferView {} (offset {}, length {}), buffer holds {}",
            view.index(),
            view.offset(),
            view.length(),
            data.len()
        ))),
    }
}

/// Checks the GLB header and chunk lengths against the data, so a truncated or corrupt
/// container gets an error with a byte offset (the crate's own error has none).
fn check_glb_container(b: &[u8]) -> Result<(), IoError> {
    let f = Format::Glb;
    let u32_at = |o: usize| {
        b.get(o..o + 4)
            .map(|s| u32::from_le_bytes([s[0], s[1], s[2], s[3]]))
    };
    let (Some(version), Some(length)) = (u32_at(4), u32_at(8)) else {
        return Err(IoError::truncated(
            f,
            Location::Byte(b.len()),
            "a 12-byte GLB header",
        ));
    };
    if version != 2 {
        return Err(IoError::Unsupported {
            format: f,
            what: format!("GLB container version {version} (byte 4; only 2 is read)"),
        });
    }
    if (length as usize) > b.len() {
        return Err(IoError::truncated(
            f,
            Location::Byte(b.len()),
            format!("{length} bytes, as the header declares at byte 8"),
        ));
    }
    let mut o = 12;
    let mut first = true;
    while o < length as usize {
        let (Some(len), Some(kind)) = (u32_at(o), u32_at(o + 4)) else {
            return Err(IoError::truncated(
                f,
                Location::Byte(o),
                "an 8-byte chunk header",
            ));
        };
        if first && kind != 0x4E4F_534A {
            return Err(IoError::syntax(
                f,
                Location::Byte(o + 4),
                "the JSON chunk first",
                format!("chunk type 0x{kind:08x}"),
            ));
        }
        let end = o as u64 + 8 + len as u64;
        if end > length as u64 {
            return Err(IoError::truncated(
                f,
                Location::Byte(length as usize),
                format!("a chunk of {len} bytes starting at byte {o}"),
            ));
        }
        o = end as usize;
        first = false;
    }
    if first {
        return Err(IoError::truncated(f, Location::Byte(12), "a JSON chunk"));
    }
    Ok(())
}

/// Reads glTF JSON or GLB.
pub fn read(bytes: &[u8]) -> Result<RawGeometry, IoError> {
    read_with(bytes, &|_| None)
}

/// Loads an external buffer by its (relative) URI; `None` when it cannot.
pub type Resolver<'r> = &'r dyn Fn(&str) -> Option<Vec<u8>>;

/// Reads glTF JSON or GLB, loading external buffers through `resolve` (the native
/// [`super::read_path`] resolves them next to the file; the browser has no such files).
pub fn read_with(bytes: &[u8], resolve: Resolver) -> Result<RawGeometry, IoError> {
    let is_glb = bytes.starts_with(b"glTF");
    let format = if is_glb { Format::Glb } else { Format::Gltf };
    let (doc, bin) = parse_document(bytes, is_glb, format)?;
    let buffers = load_buffers(&doc, bin, resolve, format)?;
    let instances = collect_instances(&doc, bytes.len(), format)?;
    let mut out = Emitted {
        tri_points: Vec::new(),
        tris: Vec::new(),
        cloud: Vec::new(),
        max_points: MAX_INSTANCING * (bytes.len() / 12 + 1),
    };
    for (mesh, world) in &instances {
        for prim in mesh.primitives() {
            emit_primitive(&mut out, mesh, &prim, world, &buffers, format)?;
        }
    }
    let enc = if is_glb {
        Encoding::BinaryLe
    } else {
        Encoding::Ascii
    };
    if out.tris.is_empty() {
        Ok((out.cloud, out.tris, enc))
    } else {
        Ok((out.tri_points, out.tris, enc))
    }
}

/// Buffer contents by buffer index (`None` where a buffer could not be loaded).
type Buffers<'b> = Vec<Option<Cow<'b, [u8]>>>;

/// A validated document and the GLB binary chunk (if any).
type ParsedDoc<'b> = (::gltf::Document, Option<Cow<'b, [u8]>>);

/// Parses the GLB container (if any) and the JSON into a validated document and the GLB binary
/// chunk.
fn parse_document(bytes: &[u8], is_glb: bool, format: Format) -> Result<ParsedDoc<'_>, IoError> {
    if is_glb {
        check_glb_container(bytes)?;
    }
    let (json, bin): (Cow<[u8]>, Option<Cow<[u8]>>) = if is_glb {
        let glb = ::gltf::binary::Glb::from_slice(bytes).map_err(|e| gltf_err(format, e))?;
        (glb.json, glb.bin)
    } else {
        (Cow::Borrowed(bytes), None)
    };
    let root: ::gltf::json::Root = ::gltf::json::deserialize::from_slice(&json).map_err(|e| {
        IoError::syntax(
            format,
            Location::Line(e.line()),
            "valid glTF JSON",
            e.to_string(),
        )
    })?;
    check_attribute_accessors(&root, format)?;
    let doc = ::gltf::Document::from_json(root).map_err(|e| gltf_err(format, e))?;
    Ok((doc, bin))
}

/// Rejects a primitive attribute that refers to a missing accessor.
fn check_attribute_accessors(root: &::gltf::json::Root, format: Format) -> Result<(), IoError> {
    // gltf-json 1.4.1's validation indexes `accessors[POSITION]` before checking the index and
    // panics on a dangling one; check it here first.
    for (m, mesh) in root.meshes.iter().enumerate() {
        for (p, prim) in mesh.primitives.iter().enumerate() {
            for (sem, acc) in &prim.attributes {
                if acc.value() >= root.accessors.len() {
                    return Err(gltf_err(
                        format,
                        format!(
                            "meshes[{m}].primitives[{p}].attributes[\"{}\"] refers to accessor {}, but there are {}",
                            match sem {
                                ::gltf::json::validation::Checked::Valid(s) => s.to_string(),
                                _ => "?".into(),
                            },
                            acc.value(),
                            root.accessors.len()
                        ),
                    ));
                }
            }
        }
    }
    Ok(())
}

/// Loads every buffer: the GLB binary chunk, a base64 `data:` URI, or an external file through
/// `resolve`.
fn load_buffers<'b>(
    doc: &::gltf::Document,
    mut bin: Option<Cow<'b, [u8]>>,
    resolve: Resolver,
    format: Format,
) -> Result<Buffers<'b>, IoError> {
    let mut buffers: Buffers<'b> = Vec::new();
    for b in doc.buffers() {
        buffers.push(match b.source() {
            ::gltf::buffer::Source::Bin => bin.take(),
            ::gltf::buffer::Source::Uri(uri) if uri.starts_with("data:") => {
                let (_, data) = uri.split_once(";base64,").ok_or_else(|| {
                    gltf_err(
                        format,
                        format!("buffer {}: data URI is not base64", b.index()),
                    )
                })?;
                Some(Cow::Owned(base64_decode(data.as_bytes()).ok_or_else(
                    || gltf_err(format, format!("buffer {}: invalid base64", b.index())),
                )?))
            }
            ::gltf::buffer::Source::Uri(uri) => resolve(uri).map(Cow::Owned),
        });
    }
    Ok(buffers)
}

/// The (mesh, world matrix) instances to emit, walking the node hierarchy from its roots in
/// document order; the walk is bounded by `input_len`.
fn collect_instances(
    doc: &::gltf::Document,
    input_len: usize,
    format: Format,
) -> Result<Vec<(::gltf::Mesh<'_>, DMat4)>, IoError> {
    let mut instances: Vec<(::gltf::Mesh, DMat4)> = Vec::new();
    let roots: Vec<::gltf::Node> = match doc.default_scene().or_else(|| doc.scenes().next()) {
        Some(s) => s.nodes().collect(),
        None => {
            let mut is_child = vec![false; doc.nodes().len()];
            for n in doc.nodes() {
                for c in n.children() {
                    is_child[c.index()] = true;
                }
            }
            doc.nodes().filter(|n| !is_child[n.index()]).collect()
        }
    };
    if doc.nodes().len() == 0 {
        instances.extend(doc.meshes().map(|m| (m, DMat4::IDENTITY)));
    }
    let mut stack: Vec<(::gltf::Node, DMat4, usize)> = roots
        .into_iter()
        .rev()
        .map(|n| (n, DMat4::IDENTITY, 0))
        .collect();
    let mut visits = 0usize;
    while let Some((node, parent, depth)) = stack.pop() {
        visits += 1;
        if depth > MAX_DEPTH || visits > 1 + input_len {
            return Err(gltf_err(
                format,
                format!(
                    "node hierarchy too deep or too large at node {} (a cycle?)",
                    node.index()
                ),
            ));
        }
        let m = node.transform().matrix().map(|c| c.map(|x| x as f64));
        let world = parent * DMat4::from_cols_array_2d(&m);
        if let Some(mesh) = node.mesh() {
            instances.push((mesh, world));
        }
        // Bound the work and the stack by the input size: a small file whose nodes list the
        // same child many times would otherwise expand exponentially.
        if visits + stack.len() + node.children().len() > 1 + input_len {
            return Err(gltf_err(
                format,
                format!(
                    "node hierarchy too large at node {} (a cycle or shared subtrees?)",
                    node.index()
                ),
            ));
        }
        // Reversed so nodes pop (and are emitted) in document order.
        let children: Vec<_> = node.children().collect();
        stack.extend(children.into_iter().rev().map(|c| (c, world, depth + 1)));
    }
    Ok(instances)
}

/// The geometry gathered from the primitives so far.
struct Emitted {
    /// Vertices of triangle primitives.
    tri_points: Vec<DVec3>,
    tris: Vec<[u32; 3]>,
    /// Vertices of POINTS primitives.
    cloud: Vec<DVec3>,
    /// Bound on the vertices (and half the index count) of either kind.
    max_points: usize,
}

/// Adds one primitive of a mesh instance placed by `world` (lines are skipped).
fn emit_primitive(
    out: &mut Emitted,
    mesh: &::gltf::Mesh,
    prim: &::gltf::Primitive,
    world: &DMat4,
    buffers: &[Option<Cow<[u8]>>],
    format: Format,
) -> Result<(), IoError> {
    let mode = prim.mode();
    let is_tri = matches!(
        mode,
        Mode::Triangles | Mode::TriangleStrip | Mode::TriangleFan
    );
    if !is_tri && mode != Mode::Points {
        return Ok(());
    }
    let pos = position_accessor(mesh, prim, buffers, format)?;
    let points = if is_tri {
        &mut out.tri_points
    } else {
        &mut out.cloud
    };
    if points.len() + pos.count() > out.max_points {
        return Err(gltf_err(
            format,
            "instanced geometry is too large for the file size",
        ));
    }
    let base = points.len();
    let get = |b: ::gltf::Buffer| buffers.get(b.index()).and_then(|d| d.as_deref());
    let reader = prim.reader(get);
    let positions = reader
        .read_positions()
        .ok_or_else(|| gltf_err(format, "unreadable POSITION data"))?;
    push_points(points, positions, world, format)?;
    if !is_tri {
        return Ok(());
    }
    let n = pos.count();
    let idx: Vec<u32> = match prim.indices() {
        Some(acc) => {
            check_index_accessor(format, &acc, buffers)?;
            reader
                .read_indices()
                .ok_or_else(|| gltf_err(format, "unreadable index data"))?
                .into_u32()
                .collect()
        }
        None => (0..n as u32).collect(),
    };
    if let Some(&bad) = idx.iter().find(|&&i| i as usize >= n) {
        return Err(IoError::IndexOutOfRange {
            format,
            at: Location::Byte(0),
            face: out.tris.len(),
            index: bad as i64,
            count: n,
        });
    }
    if out.tris.len() + idx.len() > 2 * out.max_points {
        return Err(gltf_err(
            format,
            "instanced geometry is too large for the file size",
        ));
    }
    let first = out.tris.len();
    push_triangles(&mut out.tris, mode, &idx, base as u32, mesh, prim, format)?;
    // A mirroring node (negative determinant) reverses the winding (glTF 2.0 §3.7.2.1):
    // its faces are turned back, or a mirrored half of a model points inwards.
    if DMat3::from_mat4(*world).determinant() < 0.0 {
        out.tris[first..].iter_mut().for_each(|t| t.swap(1, 2));
    }
    Ok(())
}

/// The primitive's POSITION accessor, checked to be float VEC3 inside its buffer.
fn position_accessor<'d>(
    mesh: &::gltf::Mesh,
    prim: &::gltf::Primitive<'d>,
    buffers: &[Option<Cow<[u8]>>],
    format: Format,
) -> Result<::gltf::Accessor<'d>, IoError> {
    let Some(pos) = prim.get(&::gltf::Semantic::Positions) else {
        return Err(gltf_err(
            format,
            format!(
                "mesh {} primitive {} has no POSITION",
                mesh.index(),
                prim.index()
            ),
        ));
    };
    if pos.data_type() != DataType::F32 || pos.dimensions() != Dimensions::Vec3 {
        return Err(IoError::Unsupported {
            format,
            what: format!("POSITION accessor {} that is not float VEC3", pos.index()),
        });
    }
    check_accessor(format, &pos, buffers)?;
    Ok(pos)
}

/// Transforms `positions` by `world` onto `out`, rejecting non-finite results.
fn push_points(
    out: &mut Vec<DVec3>,
    positions: impl Iterator<Item = [f32; 3]>,
    world: &DMat4,
    format: Format,
) -> Result<(), IoError> {
    for p in positions {
        let q = world.transform_point3(DVec3::from_array(p.map(|c| c as f64)));
        if !q.is_finite() {
            return Err(IoError::NonFinite {
                format,
                at: Location::Byte(0),
                index: out.len(),
                x: q.x,
                y: q.y,
                z: q.z,
            });
        }
        out.push(q);
    }
    Ok(())
}

/// Checks that an index accessor is an unsigned scalar lying inside its buffer.
fn check_index_accessor(
    format: Format,
    acc: &::gltf::Accessor,
    buffers: &[Option<Cow<[u8]>>],
) -> Result<(), IoError> {
    if acc.dimensions() != Dimensions::Scalar
        || !matches!(
            acc.data_type(),
            DataType::U8 | DataType::U16 | DataType::U32
        )
    {
        return Err(gltf_err(
            format,
            format!("index accessor {} is not an unsigned scalar", acc.index()),
        ));
    }
    check_accessor(format, acc, buffers)
}

/// Turns the indices of a triangle list, strip or fan (offset by `b`) into triangles.
fn push_triangles(
    tris: &mut Vec<[u32; 3]>,
    mode: Mode,
    idx: &[u32],
    b: u32,
    mesh: &::gltf::Mesh,
    prim: &::gltf::Primitive,
    format: Format,
) -> Result<(), IoError> {
    match mode {
        Mode::Triangles => {
            if idx.len() % 3 != 0 {
                return Err(gltf_err(
                    format,
                    format!(
                        "mesh {} primitive {}: {} indices is not a multiple of 3",
                        mesh.index(),
                        prim.index(),
                        idx.len()
                    ),
                ));
            }
            tris.extend(idx.chunks_exact(3).map(|t| [b + t[0], b + t[1], b + t[2]]));
        }
        Mode::TriangleStrip => {
            for k in 0..idx.len().saturating_sub(2) {
                let (i, j) = if k % 2 == 0 {
                    (k + 1, k + 2)
                } else {
                    (k + 2, k + 1)
                };
                tris.push([b + idx[k], b + idx[i], b + idx[j]]);
            }
        }
        _ => {
            for k in 1..idx.len().saturating_sub(1) {
                tris.push([b + idx[0], b + idx[k], b + idx[k + 1]]);
            }
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::io::WriteInput;

    /// `glb` with its JSON chunk rewritten by `edit`.
    fn with_json(glb: &[u8], edit: impl Fn(String) -> String) -> Vec<u8> {
        let json_len = u32::from_le_bytes(glb[12..16].try_into().unwrap()) as usize;
        let mut js = edit(String::from_utf8(glb[20..20 + json_len].to_vec()).unwrap()).into_bytes();
        while js.len() % 4 != 0 {
            js.push(b' ');
        }
        let bin = &glb[20 + json_len..];
        let total = 20 + js.len() + bin.len();
        let mut out = b"glTF".to_vec();
        out.extend_from_slice(&2u32.to_le_bytes());
        out.extend_from_slice(&(total as u32).to_le_bytes());
        out.extend_from_slice(&(js.len() as u32).to_le_bytes());
        out.extend_from_slice(b"JSON");
        out.extend_from_slice(&js);
        out.extend_from_slice(bin);
        out
    }

    #[test]
    fn a_mirroring_node_keeps_the_faces_outwards() {
        let s = crate::geometry::icosphere::icosphere(1, 1.0, DVec3::new(2.0, 0.0, 0.0)).unwrap();
        let (p, t) = (s.positions().to_vec(), s.triangles());
        let glb = write_glb(&WriteInput {
            positions: &p,
            triangles: &t,
            scalars: &[],
            settings_json: None,
        })
        .unwrap();
        let volume = |p: &[DVec3], t: &[[u32; 3]]| -> f64 {
            t.iter()
                .map(|f| {
                    let [a, b, c] = f.map(|v| p[v as usize]);
                    a.dot(b.cross(c)) / 6.0
                })
                .sum()
        };
        let (p0, t0, _) = read(&glb).unwrap();
        let v0 = volume(&p0, &t0);
        assert!(v0 > 0.0);
        for node in [
            r#"{"mesh":0,"scale":[-1,1,1]}"#,
            r#"{"mesh":0,"scale":[-1,-1,-1]}"#,
        ] {
            let mirrored = with_json(&glb, |j| j.replace(r#"{"mesh":0}"#, node));
            let (p1, t1, _) = read(&mirrored).unwrap();
            assert!(p1[0].x < 0.0, "{node}: not mirrored");
            assert!((volume(&p1, &t1) - v0).abs() < 1e-9 * v0, "{node}");
        }
    }

    #[test]
    fn base64() {
        assert_eq!(base64_decode(b"TWFu").unwrap(), b"Man");
        assert_eq!(base64_decode(b"TWE=").unwrap(), b"Ma");
        assert_eq!(base64_decode(b"TQ==").unwrap(), b"M");
        assert!(base64_decode(b"T!==").is_none());
    }
}
