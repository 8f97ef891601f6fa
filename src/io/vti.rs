//! VTK XML ImageData volumes (`.vti`): an XML document whose `DataArray`s are ASCII, inline
//! base64 (optionally zlib-compressed in blocks) or in an `<AppendedData>` section (raw bytes or
//! base64), which is not XML at all, so this reader scans tags itself rather than using an XML
//! parser.
//!
//! World coordinates: `Origin + Direction · (Spacing ⊙ index)` with `Direction` row-major and the
//! index counted from the extent's lower corner, in the file's own frame (kept as written). The
//! array read is the one
//! named by [`VolumeOptions::array`], else `PointData`'s active `Scalars`, else the first point
//! array. Binary blocks follow VTK's layout: a header of `UInt32` or `UInt64` values (the byte
//! count; or, compressed, block count, block size, last block size and the compressed sizes),
//! then the data. Reference: "VTK File Formats" in the VTK User's Guide.

use super::error::{Format, IoError, Location};
use super::text::{parse_f64, show};
use super::volume::{
    affine, checked_count, decode_samples, inflate_prefix, parse_ascii_samples, Packing,
    ScalarType, VolumeOptions, VoxelVolume,
};
use super::Encoding;
use base64::Engine as _;
use glam::DVec3;

const F: Format = Format::Vti;

/// True when the document is VTK XML of type ImageData.
pub fn sniff(bytes: &[u8]) -> bool {
    let head = &bytes[..bytes.len().min(1024)];
    let s = String::from_utf8_lossy(head);
    s.contains("<VTKFile") && s.contains("ImageData")
}

/// A start tag with its attributes.
struct Tag<'a> {
    /// Offset of '<'.
    start: usize,
    /// Offset just after '>'.
    end: usize,
    attrs: Vec<(&'a str, &'a str)>,
    self_closing: bool,
}

impl<'a> Tag<'a> {
    fn attr(&self, name: &str) -> Option<&'a str> {
        self.attrs.iter().find(|(k, _)| *k == name).map(|(_, v)| *v)
    }
}

/// Finds the next start tag `<name …>` in `b[from..limit]`.
fn find_tag<'a>(
    b: &'a [u8],
    from: usize,
    limit: usize,
    name: &str,
) -> Result<Option<Tag<'a>>, IoError> {
    let pat = format!("<{name}");
    let mut i = from;
    while i < limit {
        let Some(p) = find(&b[i..limit], pat.as_bytes()) else {
            return Ok(None);
        };
        let start = i + p;
        let after = start + pat.len();
        match b.get(after) {
            Some(c) if c.is_ascii_whitespace() || *c == b'>' || *c == b'/' => {}
            _ => {
                i = after;
                continue;
            }
        }
        let close = find(&b[after..limit], b">").ok_or_else(|| {
            IoError::truncated(
                F,
                Location::Byte(limit),
                format!("the end of the <{name}> tag"),
            )
        })?;
        let inner = &b[after..after + close];
        let self_closing = inner.ends_with(b"/");
        let text = std::str::from_utf8(inner).map_err(|_| {
            IoError::syntax(F, Location::Byte(after), "UTF-8 attributes", "binary data")
        })?;
        return Ok(Some(Tag {
            start,
            end: after + close + 1,
            attrs: parse_attrs(text),
            self_closing,
        }));
    }
    Ok(None)
}

/// `name="value"` pairs (single or double quotes).
fn parse_attrs(s: &str) -> Vec<(&str, &str)> {
    let mut out = Vec::new();
    let mut rest = s;
    while let Some(eq) = rest.find('=') {
        let name = rest[..eq].trim();
        let after = rest[eq + 1..].trim_start();
        let Some(q) = after.chars().next().filter(|c| *c == '"' || *c == '\'') else {
            break;
        };
        let Some(len) = after[1..].find(q) else {
            break;
        };
        out.push((name, &after[1..1 + len]));
        rest = &after[1 + len + 1..];
    }
    out
}

fn find(hay: &[u8], needle: &[u8]) -> Option<usize> {
    hay.windows(needle.len()).position(|w| w == needle)
}

fn scalar_type(name: &str) -> Option<ScalarType> {
    Some(match name {
        "Int8" | "Char" => ScalarType::I8,
        "UInt8" | "UChar" => ScalarType::U8,
        "Int16" => ScalarType::I16,
        "UInt16" => ScalarType::U16,
        "Int32" => ScalarType::I32,
        "UInt32" => ScalarType::U32,
        "Int64" => ScalarType::I64,
        "UInt64" => ScalarType::U64,
        "Float32" => ScalarType::F32,
        "Float64" => ScalarType::F64,
        _ => return None,
    })
}

/// Decodes base64 that may be several independently padded pieces one after another (VTK writes
/// the compression header and the data as separate base64 streams).
fn decode_base64(text: &[u8], at: usize) -> Result<Vec<u8>, IoError> {
    let clean: Vec<u8> = text
        .iter()
        .filter(|b| !b.is_ascii_whitespace())
        .copied()
        .collect();
    let mut out = Vec::with_capacity(clean.len() / 4 * 3 + 3);
    let mut i = 0;
    while i < clean.len() {
        let mut j = i;
        while j < clean.len() && clean[j] != b'=' {
            j += 1;
        }
        while j < clean.len() && clean[j] == b'=' {
            j += 1;
        }
        base64::engine::general_purpose::STANDARD
            .decode_vec(&clean[i..j], &mut out)
            .map_err(|e| {
                IoError::syntax(
                    F,
                    Location::Byte(at),
                    "base64 data",
                    format!("invalid base64 ({e})"),
                )
            })?;
        i = j;
    }
    Ok(out)
}

/// Reads one header integer (UInt32 or UInt64) at `k`.
fn header_int(d: &[u8], k: usize, wide: bool, big: bool, at: usize) -> Result<u64, IoError> {
    let w = if wide { 8 } else { 4 };
    let s = d
        .get(k * w..(k + 1) * w)
        .ok_or_else(|| IoError::truncated(F, Location::Byte(at), "the binary block header"))?;
    Ok(match (wide, big) {
        (false, false) => u32::from_le_bytes(s.try_into().expect("4")) as u64,
        (false, true) => u32::from_be_bytes(s.try_into().expect("4")) as u64,
        (true, false) => u64::from_le_bytes(s.try_into().expect("8")),
        (true, true) => u64::from_be_bytes(s.try_into().expect("8")),
    })
}

/// The sample bytes of a binary array whose block (header + data) starts at `d[0]`.
fn unpack(
    d: &[u8],
    want: usize,
    wide: bool,
    big: bool,
    compressed: bool,
    at: usize,
) -> Result<Vec<u8>, IoError> {
    let w = if wide { 8 } else { 4 };
    if !compressed {
        let count = header_int(d, 0, wide, big, at)? as usize;
        if count < want {
            return Err(IoError::syntax(
                F,
                Location::Byte(at),
                format!("{want} bytes of samples (the extent's voxel count)"),
                format!("a block of {count} bytes"),
            ));
        }
        return d.get(w..w + want).map(|s| s.to_vec()).ok_or_else(|| {
            IoError::truncated(F, Location::Byte(at), format!("{want} bytes of samples"))
        });
    }
    let nb = header_int(d, 0, wide, big, at)? as usize;
    let bs = header_int(d, 1, wide, big, at)? as usize;
    let lbs = header_int(d, 2, wide, big, at)? as usize;
    if nb > d.len() / w {
        return Err(IoError::CountTooLarge {
            format: F,
            at: Location::Byte(at),
            element: "compressed blocks".into(),
            count: nb as u64,
            available: d.len(),
            needed: (nb as u128 + 3) * w as u128,
        });
    }
    let total = if nb == 0 {
        0
    } else {
        (nb - 1)
            .saturating_mul(bs)
            .saturating_add(if lbs == 0 { bs } else { lbs })
    };
    if total < want {
        return Err(IoError::syntax(
            F,
            Location::Byte(at),
            format!("{want} bytes of samples (the extent's voxel count)"),
            format!("compressed blocks holding {total} bytes"),
        ));
    }
    let mut out = Vec::with_capacity(want.min(d.len().saturating_mul(1100)));
    let mut pos = (3 + nb) * w;
    for b in 0..nb {
        let cs = header_int(d, 3 + b, wide, big, at)? as usize;
        let block = d.get(pos..pos.saturating_add(cs)).ok_or_else(|| {
            IoError::truncated(
                F,
                Location::Byte(at),
                format!("compressed block {b} of {nb}"),
            )
        })?;
        let size = if b + 1 == nb && lbs != 0 { lbs } else { bs };
        let need = size.min(want - out.len());
        out.extend(inflate_prefix(block, Packing::Zlib, need, true, F, at)?);
        pos += cs;
        if out.len() >= want {
            break;
        }
    }
    Ok(out)
}

/// How the binary blocks are laid out: byte order, header integer width, zlib compression.
#[derive(Clone, Copy)]
struct BlockLayout {
    big: bool,
    wide: bool,
    compressed: bool,
}

/// The `<ImageData>` grid: its tag, voxel counts and the index → world columns and origin.
struct Grid<'a> {
    image: Tag<'a>,
    dims: [usize; 3],
    cols: [DVec3; 3],
    origin: DVec3,
}

/// Reads a `.vti` document.
pub fn read(bytes: &[u8], opts: &VolumeOptions) -> Result<(VoxelVolume, Encoding), IoError> {
    let appended = find(bytes, b"<AppendedData");
    let limit = appended.unwrap_or(bytes.len());
    let file = find_tag(bytes, 0, limit, "VTKFile")?
        .ok_or_else(|| IoError::syntax(F, Location::Byte(0), "a <VTKFile> element", "none"))?;
    let layout = block_layout(&file)?;
    let grid = read_grid(bytes, file.end, limit)?;
    let (pd, arrays) = point_arrays(bytes, grid.image.end, limit)?;
    let arr = pick_array(&pd, &arrays, opts)?;
    let ty_name = arr.attr("type").unwrap_or("");
    let ty = scalar_type(ty_name).ok_or_else(|| IoError::Unsupported {
        format: F,
        what: format!("DataArray type \"{ty_name}\" (byte {})", arr.start),
    })?;
    if let Some(nc) = arr.attr("NumberOfComponents") {
        if nc != "1" {
            return Err(IoError::Unsupported {
                format: F,
                what: format!(
                    "{nc} components per point (array \"{}\"); LSW reads scalar volumes",
                    arr.attr("Name").unwrap_or("")
                ),
            });
        }
    }
    let dims = grid.dims;
    let n = checked_count(
        &dims,
        1,
        usize::MAX / 16,
        1,
        F,
        Location::Byte(grid.image.start),
    )?;
    let src = Source {
        bytes,
        limit,
        appended,
        dims,
        layout,
    };
    let (values, encoding) = read_values(&src, arr, ty, n)?;
    Ok((
        VoxelVolume {
            dims,
            values,
            index_to_world: affine(grid.cols, grid.origin),
            datatype: ty,
            frame: "VTK world frame as written (Origin/Spacing/Direction)".into(),
            frames: 1,
            frame_index: 0,
        },
        encoding,
    ))
}

/// Reads `byte_order`, `header_type` and `compressor` from the `<VTKFile>` tag, checking the type.
fn block_layout(file: &Tag) -> Result<BlockLayout, IoError> {
    if file.attr("type") != Some("ImageData") {
        return Err(IoError::Unsupported {
            format: F,
            what: format!(
                "VTK XML type \"{}\"; LSW reads ImageData volumes",
                file.attr("type").unwrap_or("")
            ),
        });
    }
    let big = file.attr("byte_order") == Some("BigEndian");
    let wide = match file.attr("header_type") {
        None | Some("UInt32") => false,
        Some("UInt64") => true,
        Some(other) => {
            return Err(IoError::syntax(
                F,
                Location::Byte(file.start),
                "header_type UInt32 or UInt64",
                other,
            ))
        }
    };
    let compressed = match file.attr("compressor") {
        None | Some("") => false,
        Some("vtkZLibDataCompressor") => true,
        Some(other) => {
            return Err(IoError::Unsupported {
                format: F,
                what: format!("compressor {other} (LSW reads zlib-compressed or raw data)"),
            })
        }
    };
    Ok(BlockLayout {
        big,
        wide,
        compressed,
    })
}

/// The attribute `name` of `tag` as `n` finite numbers (or `default` when it is absent).
fn tag_numbers(
    tag: &Tag,
    name: &str,
    n: usize,
    default: Option<Vec<f64>>,
) -> Result<Vec<f64>, IoError> {
    match tag.attr(name) {
        None => default.ok_or_else(|| {
            IoError::syntax(
                F,
                Location::Byte(tag.start),
                format!("the attribute {name}"),
                "none",
            )
        }),
        Some(s) => s
            .split_whitespace()
            .map(|t| parse_f64(t.as_bytes()).filter(|v| v.is_finite()))
            .collect::<Option<Vec<_>>>()
            .filter(|v| v.len() == n)
            .ok_or_else(|| {
                IoError::syntax(
                    F,
                    Location::Byte(tag.start),
                    format!("{n} numbers in {name}"),
                    s,
                )
            }),
    }
}

/// Finds `<ImageData>` after `from` and reads its extent, origin, spacing and direction.
fn read_grid(bytes: &[u8], from: usize, limit: usize) -> Result<Grid<'_>, IoError> {
    let image = find_tag(bytes, from, limit, "ImageData")?.ok_or_else(|| {
        IoError::syntax(F, Location::Byte(from), "an <ImageData> element", "none")
    })?;
    let ext = tag_numbers(&image, "WholeExtent", 6, None)?;
    if ext.iter().any(|e| e.fract() != 0.0 || e.abs() > 1e12)
        || (0..3).any(|k| ext[2 * k + 1] < ext[2 * k])
    {
        return Err(IoError::syntax(
            F,
            Location::Byte(image.start),
            "a WholeExtent of integer pairs lo ≤ hi",
            image.attr("WholeExtent").unwrap_or(""),
        ));
    }
    let dims = [0, 1, 2].map(|k| ((ext[2 * k + 1] - ext[2 * k]) as usize).saturating_add(1));
    let origin = tag_numbers(&image, "Origin", 3, Some(vec![0.0; 3]))?;
    let spacing = tag_numbers(&image, "Spacing", 3, Some(vec![1.0; 3]))?;
    let dir = tag_numbers(
        &image,
        "Direction",
        9,
        Some(vec![1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0]),
    )?;
    let cols = [0, 1, 2].map(|k| DVec3::new(dir[k], dir[3 + k], dir[6 + k]) * spacing[k]);
    let o = DVec3::from_slice(&origin) + cols[0] * ext[0] + cols[1] * ext[2] + cols[2] * ext[4];
    Ok(Grid {
        image,
        dims,
        cols,
        origin: o,
    })
}

/// Finds the single `<Piece>` after `from` and its `<PointData>`; returns that tag and its arrays.
fn point_arrays(
    bytes: &[u8],
    from: usize,
    limit: usize,
) -> Result<(Tag<'_>, Vec<Tag<'_>>), IoError> {
    let piece = find_tag(bytes, from, limit, "Piece")?
        .ok_or_else(|| IoError::syntax(F, Location::Byte(from), "a <Piece> element", "none"))?;
    if find_tag(bytes, piece.end, limit, "Piece")?.is_some() {
        return Err(IoError::Unsupported {
            format: F,
            what: "ImageData with several pieces".into(),
        });
    }
    let pd = find_tag(bytes, piece.end, limit, "PointData")?.ok_or_else(|| {
        IoError::syntax(
            F,
            Location::Byte(piece.end),
            "a <PointData> element with the values",
            "none",
        )
    })?;
    let pd_end = if pd.self_closing {
        pd.end
    } else {
        find(&bytes[pd.end..limit], b"</PointData").map_or(limit, |p| pd.end + p)
    };
    let mut arrays = Vec::new();
    let mut at = pd.end;
    while let Some(t) = find_tag(bytes, at, pd_end, "DataArray")? {
        at = t.end;
        arrays.push(t);
    }
    Ok((pd, arrays))
}

/// The array named by the options, else the active `Scalars`, else the first one.
fn pick_array<'t, 'a>(
    pd: &Tag,
    arrays: &'t [Tag<'a>],
    opts: &VolumeOptions,
) -> Result<&'t Tag<'a>, IoError> {
    let wanted = opts.array.as_deref().or(pd.attr("Scalars"));
    match wanted {
        Some(name) => arrays
            .iter()
            .find(|a| a.attr("Name") == Some(name))
            .ok_or_else(|| {
                let names: Vec<&str> = arrays.iter().filter_map(|a| a.attr("Name")).collect();
                IoError::syntax(
                    F,
                    Location::Byte(pd.start),
                    format!("a point array named \"{name}\""),
                    format!("arrays {names:?}"),
                )
            }),
        None => arrays.first().ok_or_else(|| {
            IoError::syntax(F, Location::Byte(pd.start), "a point DataArray", "none")
        }),
    }
}

/// The document and what the array's data reading needs to know about it.
struct Source<'a> {
    bytes: &'a [u8],
    /// End of the XML part (the `<AppendedData>` offset, else the length).
    limit: usize,
    appended: Option<usize>,
    dims: [usize; 3],
    layout: BlockLayout,
}

impl Source<'_> {
    /// The text between a `<DataArray>` tag and its `</DataArray>` (empty when self-closing).
    fn content(&self, t: &Tag) -> Result<&[u8], IoError> {
        if t.self_closing {
            return Ok(&[]);
        }
        let end = find(&self.bytes[t.end..self.limit], b"</DataArray")
            .ok_or_else(|| IoError::truncated(F, Location::Byte(self.limit), "</DataArray>"))?;
        Ok(&self.bytes[t.end..t.end + end])
    }
}

/// Reads the `n` samples of `arr` in its `format` (ascii, inline binary or appended).
fn read_values(
    src: &Source,
    arr: &Tag,
    ty: ScalarType,
    n: usize,
) -> Result<(Vec<f32>, Encoding), IoError> {
    let BlockLayout {
        big,
        wide,
        compressed,
    } = src.layout;
    let dims = src.dims;
    let want = n * ty.size();
    let format = arr.attr("format").unwrap_or("ascii");
    Ok(match format {
        "ascii" => {
            let text = src.content(arr)?;
            checked_count(&dims, 2, text.len() + 1, 1, F, Location::Byte(arr.start))?;
            let line0 = src.bytes[..arr.end].iter().filter(|&&b| b == b'\n').count() + 1;
            (
                parse_ascii_samples(text, n, F, line0, 1.0, 0.0)?,
                Encoding::Ascii,
            )
        }
        "binary" => {
            let text = src.content(arr)?;
            checked_count(
                &dims,
                ty.size(),
                text.len(),
                1100,
                F,
                Location::Byte(arr.start),
            )?;
            let d = decode_base64(text, arr.end)?;
            let raw = unpack(&d, want, wide, big, compressed, arr.end)?;
            (
                decode_samples(&raw, ty, big, 1.0, 0.0),
                binary_encoding(big),
            )
        }
        "appended" => {
            let raw = appended_raw(src, arr, ty, want)?;
            (
                decode_samples(&raw, ty, big, 1.0, 0.0),
                binary_encoding(big),
            )
        }
        other => {
            return Err(IoError::syntax(
                F,
                Location::Byte(arr.start),
                "format ascii, binary or appended",
                show(other.as_bytes()),
            ))
        }
    })
}

/// The `want` sample bytes of `arr` from the `<AppendedData>` section (raw or base64).
fn appended_raw(src: &Source, arr: &Tag, ty: ScalarType, want: usize) -> Result<Vec<u8>, IoError> {
    let BlockLayout {
        big,
        wide,
        compressed,
    } = src.layout;
    let bytes = src.bytes;
    let app_at = src.appended.ok_or_else(|| {
        IoError::syntax(
            F,
            Location::Byte(arr.start),
            "an <AppendedData> section",
            "none",
        )
    })?;
    let app = find_tag(bytes, app_at, bytes.len(), "AppendedData")?
        .ok_or_else(|| IoError::truncated(F, Location::Byte(app_at), "the <AppendedData> tag"))?;
    let underscore = bytes[app.end..]
        .iter()
        .position(|&b| b == b'_')
        .ok_or_else(|| {
            IoError::truncated(
                F,
                Location::Byte(app.end),
                "the '_' that starts appended data",
            )
        })?;
    let base = app.end + underscore + 1;
    let off_s = arr.attr("offset").unwrap_or("0");
    let off: usize = off_s
        .trim()
        .parse()
        .map_err(|_| IoError::syntax(F, Location::Byte(arr.start), "a byte offset", off_s))?;
    let start = base
        .checked_add(off)
        .filter(|&s| s <= bytes.len())
        .ok_or_else(|| {
            IoError::truncated(
                F,
                Location::Byte(bytes.len()),
                format!("appended data at offset {off}"),
            )
        })?;
    let d = &bytes[start..];
    if app.attr("encoding") == Some("base64") {
        let stop = d.iter().position(|&b| b == b'<').unwrap_or(d.len());
        let decoded = decode_base64(&d[..stop], start)?;
        unpack(&decoded, want, wide, big, compressed, start)
    } else {
        checked_count(
            &src.dims,
            ty.size(),
            d.len(),
            1100,
            F,
            Location::Byte(arr.start),
        )?;
        unpack(d, want, wide, big, compressed, start)
    }
}

fn binary_encoding(big: bool) -> Encoding {
    if big {
        Encoding::BinaryBe
    } else {
        Encoding::BinaryLe
    }
}
