//! NRRD volumes (`.nrrd` with attached data, `.nhdr` with a detached data file), the "nearly raw
//! raster data" format of Teem, 3D Slicer and pynrrd: a text header of `field: value` lines, a
//! blank line, then the samples (raw, gzip or ASCII).
//!
//! World coordinates: `space directions` and `space origin` give the index → world map in the
//! header's `space`; it is converted to RAS (the NIfTI frame) so the same volume agrees across
//! formats: left-posterior-superior negates x and y, left-anterior-superior negates x;
//! scanner-xyz and 3D-right/left-handed are kept as they are. Without `space directions`,
//! `spacings` (or 1) scale the axes and the origin is 0. Reference: the NRRD format
//! specification, <http://teem.sourceforge.net/nrrd/format.html>.

use super::error::{Format, IoError, Location};
use super::text::{parse_f64, show, trim};
use super::volume::{
    affine, checked_count, decode_samples, inflate_prefix, parse_ascii_samples, parse_sizes,
    Packing, ScalarType, VolumeOptions, VoxelVolume, MAX_INFLATE_RATIO,
};
use super::Encoding;
use glam::DVec3;

const F: Format = Format::Nrrd;

/// True when `bytes` start with the NRRD magic (`NRRD000x`).
pub fn sniff(bytes: &[u8]) -> bool {
    bytes.starts_with(b"NRRD000")
}

/// The sample type of a NRRD `type` name (all the spec's synonyms).
fn scalar_type(name: &str) -> Option<ScalarType> {
    Some(match name {
        "signed char" | "int8" | "int8_t" => ScalarType::I8,
        "uchar" | "unsigned char" | "uint8" | "uint8_t" => ScalarType::U8,
        "short" | "short int" | "signed short" | "signed short int" | "int16" | "int16_t" => {
            ScalarType::I16
        }
        "ushort" | "unsigned short" | "unsigned short int" | "uint16" | "uint16_t" => {
            ScalarType::U16
        }
        "int" | "signed int" | "int32" | "int32_t" => ScalarType::I32,
        "uint" | "unsigned int" | "uint32" | "uint32_t" => ScalarType::U32,
        "longlong"
        | "long long"
        | "long long int"
        | "signed long long"
        | "signed long long int"
        | "int64"
        | "int64_t" => ScalarType::I64,
        "ulonglong" | "unsigned long long" | "unsigned long long int" | "uint64" | "uint64_t" => {
            ScalarType::U64
        }
        "float" => ScalarType::F32,
        "double" => ScalarType::F64,
        _ => return None,
    })
}

/// A parsed header field with the line it came from.
struct Field {
    line: usize,
    value: String,
}

/// The header: fields by lower-cased name (first occurrence wins), and where the data starts.
struct Header {
    fields: Vec<(String, Field)>,
    data_start: usize,
    /// The line after the blank line (for ASCII data errors).
    data_line: usize,
}

impl Header {
    fn get(&self, key: &str) -> Option<&Field> {
        self.fields.iter().find(|(k, _)| k == key).map(|(_, f)| f)
    }

    /// The field `key`, or an error naming it as required.
    fn need(&self, key: &str) -> Result<&Field, IoError> {
        self.get(key).ok_or_else(|| {
            IoError::syntax(
                F,
                Location::Line(1),
                format!("the required field \"{key}\""),
                "a header without it",
            )
        })
    }
}

/// The sample type and the axes: which are spatial, the volume's size and its frame count.
struct Axes {
    ty: ScalarType,
    /// Line of `sizes` (where count errors point).
    sizes_line: usize,
    /// Per-axis `space directions` (`None` entries for non-spatial axes), when given.
    directions: Option<Vec<Option<Vec<f64>>>>,
    spatial: Vec<usize>,
    dims3: [usize; 3],
    frames: usize,
}

/// The sample bytes after `line skip`, where they start, and the `byte skip` to apply.
struct Data<'a> {
    bytes: &'a [u8],
    /// Byte offset of `bytes` in its file (for errors).
    at: usize,
    /// Line number of the first data line (for ASCII errors).
    line: usize,
    byte_skip: i64,
}

fn parse_header(bytes: &[u8]) -> Result<Header, IoError> {
    let mut fields = Vec::new();
    let mut pos = 0;
    let mut line = 0;
    loop {
        line += 1;
        let Some(nl) = bytes[pos..].iter().position(|&b| b == b'\n') else {
            // A detached header may end without the blank line.
            let rest = trim(&bytes[pos..]);
            if !rest.is_empty() {
                push_field(&mut fields, rest, line)?;
            }
            return Ok(Header {
                fields,
                data_start: bytes.len(),
                data_line: line + 1,
            });
        };
        let raw = &bytes[pos..pos + nl];
        pos += nl + 1;
        let l = raw.strip_suffix(b"\r").unwrap_or(raw);
        if line == 1 {
            if !sniff(l) {
                return Err(IoError::syntax(
                    F,
                    Location::Line(1),
                    "the magic line NRRD000x",
                    show(&l[..l.len().min(16)]),
                ));
            }
            continue;
        }
        if l.is_empty() {
            return Ok(Header {
                fields,
                data_start: pos,
                data_line: line + 1,
            });
        }
        if l.starts_with(b"#") {
            continue;
        }
        push_field(&mut fields, l, line)?;
    }
}

fn push_field(fields: &mut Vec<(String, Field)>, l: &[u8], line: usize) -> Result<(), IoError> {
    let text = std::str::from_utf8(l).map_err(|_| {
        IoError::syntax(
            F,
            Location::Line(line),
            "a text header line",
            "non-UTF-8 bytes",
        )
    })?;
    // Key/value pairs ("key:=value") are free-form metadata.
    if text.contains(":=") {
        return Ok(());
    }
    let (k, v) = text.split_once(": ").ok_or_else(|| {
        IoError::syntax(
            F,
            Location::Line(line),
            "a \"field: value\" line (or a blank line before the data)",
            show(l),
        )
    })?;
    let key = k.trim().to_ascii_lowercase();
    if !fields.iter().any(|(f, _)| *f == key) {
        fields.push((
            key,
            Field {
                line,
                value: v.trim().to_string(),
            },
        ));
    }
    Ok(())
}

/// Parses a vector "(x,y,z)" (or "none").
fn parse_vector(s: &str, line: usize) -> Result<Option<Vec<f64>>, IoError> {
    let s = s.trim();
    if s == "none" {
        return Ok(None);
    }
    let bad = || IoError::syntax(F, Location::Line(line), "a vector like (1,0,0)", s);
    let inner = s
        .strip_prefix('(')
        .and_then(|s| s.strip_suffix(')'))
        .ok_or_else(bad)?;
    inner
        .split(',')
        .map(|t| parse_f64(t.trim().as_bytes()).filter(|v| v.is_finite()))
        .collect::<Option<Vec<f64>>>()
        .map(Some)
        .ok_or_else(bad)
}

/// Splits "(a,b,c) (d,e,f) none" into its vectors.
fn split_vectors(s: &str) -> Vec<String> {
    let mut out = Vec::new();
    let mut cur = String::new();
    let mut depth = 0;
    for ch in s.chars() {
        match ch {
            '(' => {
                depth += 1;
                cur.push(ch);
            }
            ')' => {
                depth -= 1;
                cur.push(ch);
            }
            c if c.is_whitespace() && depth == 0 => {
                if !cur.is_empty() {
                    out.push(std::mem::take(&mut cur));
                }
            }
            c => cur.push(c),
        }
    }
    if !cur.is_empty() {
        out.push(cur);
    }
    out
}

/// Reads a NRRD file; `resolve` fetches a detached `data file` by its name relative to the
/// header (native reading passes one; in memory there is none and detached data is an error).
pub fn read_with(
    bytes: &[u8],
    opts: &VolumeOptions,
    resolve: &dyn Fn(&str) -> Option<Vec<u8>>,
) -> Result<(VoxelVolume, Encoding), IoError> {
    let h = parse_header(bytes)?;
    let ax = parse_axes(&h, opts)?;
    let (flip, frame) = space_frame(&h);
    let (cols, origin) = world_axes(&h, &ax, flip)?;
    // Data location and encoding.
    let enc_f = h.need("encoding")?;
    let encoding = enc_f.value.to_ascii_lowercase();
    let big = match h.get("endian") {
        Some(f) if f.value.eq_ignore_ascii_case("big") => true,
        Some(f) if f.value.eq_ignore_ascii_case("little") => false,
        Some(f) => {
            return Err(IoError::syntax(
                F,
                Location::Line(f.line),
                "endian: little or big",
                &f.value,
            ))
        }
        None => false,
    };
    let owned;
    let (data, data_at, data_line): (&[u8], usize, usize) = match load_detached(&h, resolve)? {
        Some(d) => {
            owned = d;
            (&owned, 0, 1)
        }
        None => (&bytes[h.data_start..], h.data_start, h.data_line),
    };
    let data = skip_data(&h, data, data_at, data_line)?;
    let values = decode_values(&encoding, enc_f.line, &ax, &data, big, opts.frame)?;
    Ok((
        VoxelVolume {
            dims: ax.dims3,
            values,
            index_to_world: affine(cols, origin),
            datatype: ax.ty,
            frame,
            frames: ax.frames,
            frame_index: opts.frame,
        },
        if encoding.starts_with("ascii") || encoding.starts_with("t") {
            Encoding::Ascii
        } else if big {
            Encoding::BinaryBe
        } else {
            Encoding::BinaryLe
        },
    ))
}

/// Reads the type, dimension, sizes and space directions, and checks the requested frame.
fn parse_axes(h: &Header, opts: &VolumeOptions) -> Result<Axes, IoError> {
    let tf = h.need("type")?;
    let ty = scalar_type(&tf.value).ok_or_else(|| IoError::Unsupported {
        format: F,
        what: format!("type \"{}\" (line {})", tf.value, tf.line),
    })?;
    let df = h.need("dimension")?;
    let dim: usize = df
        .value
        .parse()
        .ok()
        .filter(|d| (1..=16).contains(d))
        .ok_or_else(|| {
            IoError::syntax(F, Location::Line(df.line), "a dimension in 1…16", &df.value)
        })?;
    let sf = h.need("sizes")?;
    let sizes = parse_sizes(&sf.value, dim, F, sf.line, format!("{dim} sizes ≥ 1"))?;
    // Spatial axes: those with a space direction (or, without directions, the first three).
    let directions = space_directions(h, dim)?;
    let spatial: Vec<usize> = match &directions {
        Some(d) => (0..dim).filter(|&i| d[i].is_some()).collect(),
        None => (0..dim.min(3)).collect(),
    };
    // Supported: up to three leading spatial axes, then frame axes (time, lists).
    if spatial.len() > 3 || spatial.iter().enumerate().any(|(k, &i)| k != i) {
        return Err(IoError::Unsupported {
            format: F,
            what: "a non-spatial axis before the spatial ones (e.g. vector or RGB samples)".into(),
        });
    }
    let mut dims3 = [1usize; 3];
    for (k, &i) in spatial.iter().enumerate() {
        dims3[k] = sizes[i];
    }
    let frames: usize = sizes[spatial.len()..].iter().product();
    if opts.frame >= frames {
        return Err(IoError::Unsupported {
            format: F,
            what: format!(
                "frame {} (the file holds {frames} volumes; 0-based)",
                opts.frame
            ),
        });
    }
    Ok(Axes {
        ty,
        sizes_line: sf.line,
        directions,
        spatial,
        dims3,
        frames,
    })
}

/// The `space directions` field, one entry per axis (`None` for "none"), when present.
fn space_directions(h: &Header, dim: usize) -> Result<Option<Vec<Option<Vec<f64>>>>, IoError> {
    let Some(f) = h.get("space directions") else {
        return Ok(None);
    };
    let v = split_vectors(&f.value)
        .iter()
        .map(|s| parse_vector(s, f.line))
        .collect::<Result<Vec<_>, _>>()?;
    if v.len() != dim {
        return Err(IoError::syntax(
            F,
            Location::Line(f.line),
            format!("{dim} space directions (one per axis, \"none\" for non-spatial)"),
            &f.value,
        ));
    }
    Ok(Some(v))
}

/// The sign flips that take the header's `space` to RAS, and the frame's description.
fn space_frame(h: &Header) -> (DVec3, String) {
    let space = h.get("space").map(|f| f.value.to_ascii_lowercase());
    match space.as_deref() {
        None => (
            DVec3::ONE,
            "NRRD index space scaled by spacings (no space field)".to_string(),
        ),
        Some("right-anterior-superior" | "ras" | "right-anterior-superior-time" | "ras-time") => (
            DVec3::ONE,
            "RAS (NRRD space right-anterior-superior)".to_string(),
        ),
        Some("left-anterior-superior" | "las" | "left-anterior-superior-time" | "las-time") => (
            DVec3::new(-1.0, 1.0, 1.0),
            "RAS (converted from NRRD space left-anterior-superior: x negated)".to_string(),
        ),
        Some("left-posterior-superior" | "lps" | "left-posterior-superior-time" | "lps-time") => (
            DVec3::new(-1.0, -1.0, 1.0),
            "RAS (converted from NRRD space left-posterior-superior: x and y negated)".to_string(),
        ),
        Some(s) => (DVec3::ONE, format!("NRRD space {s} (kept as is)")),
    }
}

/// The index → world columns and origin (from space directions and origin, else spacings).
fn world_axes(h: &Header, ax: &Axes, flip: DVec3) -> Result<([DVec3; 3], DVec3), IoError> {
    let mut cols = [DVec3::X, DVec3::Y, DVec3::Z];
    let mut origin = DVec3::ZERO;
    if let Some(d) = &ax.directions {
        for (k, &i) in ax.spatial.iter().enumerate() {
            let v = d[i].as_ref().expect("spatial axis");
            let mut c = DVec3::ZERO;
            for (j, x) in v.iter().take(3).enumerate() {
                c[j] = *x;
            }
            cols[k] = c * flip;
        }
        if let Some(f) = h.get("space origin") {
            let v = parse_vector(&f.value, f.line)?.unwrap_or_default();
            for (j, x) in v.iter().take(3).enumerate() {
                origin[j] = *x;
            }
            origin *= flip;
        }
    } else if let Some(f) = h.get("spacings") {
        for (k, t) in f.value.split_whitespace().take(3).enumerate() {
            if let Some(s) = parse_f64(t.as_bytes()).filter(|s| s.is_finite() && *s != 0.0) {
                cols[k] *= s;
            }
        }
    }
    Ok((cols, origin))
}

/// The detached data file's bytes, or `None` when the data is attached.
fn load_detached(
    h: &Header,
    resolve: &dyn Fn(&str) -> Option<Vec<u8>>,
) -> Result<Option<Vec<u8>>, IoError> {
    let Some(f) = h.get("data file").or_else(|| h.get("datafile")) else {
        return Ok(None);
    };
    let name = f.value.trim();
    if name.starts_with("LIST") || name.split_whitespace().count() > 1 {
        return Err(IoError::Unsupported {
            format: F,
            what: format!("data file lists or patterns (line {})", f.line),
        });
    }
    resolve(name).map(Some).ok_or_else(|| IoError::Unsupported {
        format: F,
        what: format!(
            "the detached data file \"{name}\" (line {}) could not be read; keep it next \
             to the header, or use an attached .nrrd",
            f.line
        ),
    })
}

/// Applies `line skip` to the data file and reads `byte skip` (applied when decoding).
fn skip_data<'a>(
    h: &Header,
    mut data: &'a [u8],
    mut data_at: usize,
    line: usize,
) -> Result<Data<'a>, IoError> {
    if let Some(f) = h.get("line skip").or_else(|| h.get("lineskip")) {
        let n: usize = f
            .value
            .parse()
            .map_err(|_| IoError::syntax(F, Location::Line(f.line), "a line count", &f.value))?;
        for _ in 0..n {
            let nl = data.iter().position(|&b| b == b'\n').ok_or_else(|| {
                IoError::truncated(F, Location::Byte(data_at + data.len()), "the skipped lines")
            })?;
            data = &data[nl + 1..];
            data_at += nl + 1;
        }
    }
    let byte_skip: i64 = match h.get("byte skip").or_else(|| h.get("byteskip")) {
        Some(f) => f.value.parse().map_err(|_| {
            IoError::syntax(F, Location::Line(f.line), "a byte count or -1", &f.value)
        })?,
        None => 0,
    };
    Ok(Data {
        bytes: data,
        at: data_at,
        line,
        byte_skip,
    })
}

/// Decodes the samples of frame `frame` in the lower-cased `encoding` (raw, gzip/zlib, ASCII).
fn decode_values(
    encoding: &str,
    enc_line: usize,
    ax: &Axes,
    d: &Data,
    big: bool,
    frame: usize,
) -> Result<Vec<f32>, IoError> {
    let (ty, dims3, data) = (ax.ty, ax.dims3, d.bytes);
    let at = Location::Line(ax.sizes_line);
    let all = [dims3[0], dims3[1], dims3[2], ax.frames];
    let start_sample = frame * dims3.iter().product::<usize>();
    let n = dims3.iter().product::<usize>();
    Ok(match encoding {
        "raw" => {
            let total = checked_count(&all, ty.size(), data.len(), 1, F, at)? * ty.size();
            let skip = if d.byte_skip == -1 {
                data.len() - total
            } else {
                usize::try_from(d.byte_skip).unwrap_or(usize::MAX)
            };
            let begin = skip.saturating_add(start_sample * ty.size());
            let end = begin.saturating_add(n * ty.size());
            if end > data.len() {
                return Err(IoError::truncated(
                    F,
                    Location::Byte(d.at + data.len()),
                    format!("{} bytes of raw samples", n * ty.size()),
                ));
            }
            decode_samples(&data[begin..end], ty, big, 1.0, 0.0)
        }
        "gzip" | "gz" | "zlib" => {
            let packing = if encoding == "zlib" {
                Packing::Zlib
            } else {
                Packing::Gzip
            };
            checked_count(&all, ty.size(), data.len(), MAX_INFLATE_RATIO, F, at)?;
            let skip = usize::try_from(d.byte_skip.max(0)).unwrap_or(usize::MAX);
            let begin = skip.saturating_add(start_sample * ty.size());
            let want = begin + n * ty.size();
            let raw = inflate_prefix(data, packing, want, true, F, d.at)?;
            decode_samples(&raw[begin..want], ty, big, 1.0, 0.0)
        }
        "ascii" | "text" | "txt" => {
            checked_count(&all, 2, data.len() + 1, 1, F, at)?;
            let v = parse_ascii_samples(data, start_sample + n, F, d.line, 1.0, 0.0)?;
            v[start_sample..].to_vec()
        }
        other => {
            return Err(IoError::Unsupported {
                format: F,
                what: format!("encoding \"{other}\" (line {enc_line}); use raw, gzip or ascii"),
            })
        }
    })
}

/// Reads an attached NRRD from memory (a detached data file is an error here).
pub fn read(bytes: &[u8], opts: &VolumeOptions) -> Result<(VoxelVolume, Encoding), IoError> {
    read_with(bytes, opts, &|_| None)
}
