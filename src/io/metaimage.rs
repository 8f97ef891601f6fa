//! MetaImage volumes (`.mha` single file, `.mhd` header + data file), ITK's and VTK's plain
//! format: `Key = Value` text lines ending with `ElementDataFile`, then (for `LOCAL`) the samples.
//!
//! World coordinates: `Offset` (alias `Position`, `Origin`) + `TransformMatrix` (alias
//! `Rotation`, `Orientation`) · (`ElementSpacing` ⊙ index), in the file's own world frame, which
//! is kept as written.
//! `TransformMatrix` lists the direction of index axis 0 first, then axis 1, then axis 2 (MetaIO
//! stores the direction matrix column by column, as ITK reads it). `CompressedData = True` means
//! a zlib stream. Reference: the MetaIO documentation of ITK
//! (<https://itk.org/Wiki/ITK/MetaIO/Documentation>).

use super::error::{Format, IoError, Location};
use super::text::{parse_f64, show};
use super::volume::{
    affine, checked_count, decode_samples, inflate_prefix, is_gzip, parse_ascii_samples,
    parse_sizes, Packing, ScalarType, VolumeOptions, VoxelVolume, MAX_INFLATE_RATIO,
};
use super::Encoding;
use glam::DVec3;

const F: Format = Format::MetaImage;

/// The keys a MetaImage header may start with (for sniffing).
const FIRST_KEYS: [&str; 5] = [
    "ObjectType",
    "NDims",
    "Comment",
    "ObjectSubType",
    "TransformType",
];

/// True when the first line is a MetaImage `Key = Value` line with a known first key.
pub fn sniff(bytes: &[u8]) -> bool {
    let line = bytes.split(|&b| b == b'\n').next().unwrap_or(b"");
    let Ok(s) = std::str::from_utf8(&line[..line.len().min(200)]) else {
        return false;
    };
    s.split_once('=')
        .is_some_and(|(k, _)| FIRST_KEYS.contains(&k.trim()))
}

fn scalar_type(name: &str) -> Option<ScalarType> {
    Some(match name {
        "MET_UCHAR" => ScalarType::U8,
        "MET_CHAR" => ScalarType::I8,
        "MET_USHORT" => ScalarType::U16,
        "MET_SHORT" => ScalarType::I16,
        "MET_UINT" | "MET_ULONG" => ScalarType::U32,
        "MET_INT" | "MET_LONG" => ScalarType::I32,
        "MET_ULONG_LONG" => ScalarType::U64,
        "MET_LONG_LONG" => ScalarType::I64,
        "MET_FLOAT" => ScalarType::F32,
        "MET_DOUBLE" => ScalarType::F64,
        _ => return None,
    })
}

struct Field {
    line: usize,
    value: String,
}

/// The header's `Key = Value` fields in file order, and where it ends.
struct Header {
    fields: Vec<(String, Field)>,
    /// Byte offset just after the `ElementDataFile` line.
    data_start: usize,
    /// Line number of the `ElementDataFile` line.
    last_line: usize,
}

impl Header {
    /// The first field named by any of `keys` (tried in order).
    fn get(&self, keys: &[&str]) -> Option<&Field> {
        keys.iter()
            .find_map(|k| self.fields.iter().find(|(f, _)| f == k).map(|(_, v)| v))
    }

    /// The field `key`, or an error naming it as required.
    fn need(&self, key: &str) -> Result<&Field, IoError> {
        self.get(&[key]).ok_or_else(|| {
            IoError::syntax(
                F,
                Location::Line(1),
                format!("the required key {key}"),
                "a header without it",
            )
        })
    }

    /// True when the first field named by `keys` says `True` (any case).
    fn yes(&self, keys: &[&str]) -> bool {
        self.get(keys)
            .is_some_and(|f| f.value.eq_ignore_ascii_case("true"))
    }
}

/// The volume's shape and sample layout as the header gives them.
struct Layout {
    ndims: usize,
    /// Line of `DimSize` (where count errors point).
    sizes_line: usize,
    ty: ScalarType,
    dims3: [usize; 3],
    frames: usize,
    big: bool,
    compressed: bool,
    binary: bool,
}

/// Reads a MetaImage; `resolve` fetches a separate `ElementDataFile` by its name relative to the
/// header (none in memory).
pub fn read_with(
    bytes: &[u8],
    opts: &VolumeOptions,
    resolve: &dyn Fn(&str) -> Option<Vec<u8>>,
) -> Result<(VoxelVolume, Encoding), IoError> {
    let h = parse_header(bytes)?;
    let l = parse_layout(&h, opts)?;
    let (cols, origin) = world_axes(&h, l.ndims)?;
    let orientation = h
        .get(&["AnatomicalOrientation"])
        .map(|f| f.value.clone())
        .unwrap_or_else(|| "unspecified".into());
    let frame = format!(
        "MetaImage world frame as written (Offset/ElementSpacing/TransformMatrix; \
         AnatomicalOrientation {orientation})"
    );
    // The data.
    let owned;
    let (data, data_at): (&[u8], usize) = match load_data(&h, resolve)? {
        Some(d) => {
            owned = d;
            (&owned, 0)
        }
        None => (&bytes[h.data_start..], h.data_start),
    };
    let values = read_values(&h, &l, data, data_at, opts.frame)?;
    Ok((
        VoxelVolume {
            dims: l.dims3,
            values,
            index_to_world: affine(cols, origin),
            datatype: l.ty,
            frame,
            frames: l.frames,
            frame_index: opts.frame,
        },
        if !l.binary {
            Encoding::Ascii
        } else if l.big {
            Encoding::BinaryBe
        } else {
            Encoding::BinaryLe
        },
    ))
}

/// Reads the `Key = Value` lines up to and including `ElementDataFile`.
fn parse_header(bytes: &[u8]) -> Result<Header, IoError> {
    let mut fields: Vec<(String, Field)> = Vec::new();
    let mut pos = 0;
    let mut line = 0;
    loop {
        line += 1;
        if pos >= bytes.len() {
            return Err(IoError::truncated(
                F,
                Location::Line(line),
                "the ElementDataFile line that ends the header",
            ));
        }
        let nl = bytes[pos..].iter().position(|&b| b == b'\n');
        let end = nl.map_or(bytes.len(), |n| pos + n);
        let raw = &bytes[pos..end];
        pos = nl.map_or(bytes.len(), |_| end + 1);
        let l = raw.strip_suffix(b"\r").unwrap_or(raw);
        if l.iter().all(|b| b.is_ascii_whitespace()) {
            continue;
        }
        let text = std::str::from_utf8(l).map_err(|_| {
            IoError::syntax(
                F,
                Location::Line(line),
                "a \"Key = Value\" text line",
                "binary data",
            )
        })?;
        let (k, v) = text.split_once('=').ok_or_else(|| {
            IoError::syntax(F, Location::Line(line), "a \"Key = Value\" line", show(l))
        })?;
        let key = k.trim().to_string();
        let value = v.trim().to_string();
        let last = key == "ElementDataFile";
        fields.push((key, Field { line, value }));
        if last {
            return Ok(Header {
                fields,
                data_start: pos,
                last_line: line,
            });
        }
    }
}

/// At least `n` finite numbers from the field `f` (`what` names it in the error).
fn floats(f: &Field, n: usize, what: &str) -> Result<Vec<f64>, IoError> {
    f.value
        .split_whitespace()
        .map(|t| parse_f64(t.as_bytes()).filter(|v| v.is_finite()))
        .collect::<Option<Vec<f64>>>()
        .filter(|v| v.len() >= n)
        .ok_or_else(|| {
            IoError::syntax(
                F,
                Location::Line(f.line),
                format!("{n} numbers ({what})"),
                &f.value,
            )
        })
}

/// Reads the dimensions, sizes, sample type and byte layout, and checks the requested frame.
fn parse_layout(h: &Header, opts: &VolumeOptions) -> Result<Layout, IoError> {
    let nd_f = h.need("NDims")?;
    let ndims: usize = nd_f
        .value
        .parse()
        .ok()
        .filter(|d| (1..=4).contains(d))
        .ok_or_else(|| IoError::syntax(F, Location::Line(nd_f.line), "NDims 1…4", &nd_f.value))?;
    let ds_f = h.need("DimSize")?;
    let sizes = parse_sizes(
        &ds_f.value,
        ndims,
        F,
        ds_f.line,
        format!("{ndims} sizes ≥ 1 (DimSize)"),
    )?;
    let et_f = h.need("ElementType")?;
    let ty = scalar_type(&et_f.value).ok_or_else(|| IoError::Unsupported {
        format: F,
        what: format!("ElementType {} (line {})", et_f.value, et_f.line),
    })?;
    if let Some(f) = h.get(&["ElementNumberOfChannels"]) {
        if f.value != "1" {
            return Err(IoError::Unsupported {
                format: F,
                what: format!(
                    "{} channels per voxel (line {}); LSW reads scalar volumes",
                    f.value, f.line
                ),
            });
        }
    }
    let nsp = ndims.min(3);
    let mut dims3 = [1usize; 3];
    dims3[..nsp].copy_from_slice(&sizes[..nsp]);
    let frames = if ndims == 4 { sizes[3] } else { 1 };
    if opts.frame >= frames {
        return Err(IoError::Unsupported {
            format: F,
            what: format!(
                "frame {} (the file holds {frames} volumes; 0-based)",
                opts.frame
            ),
        });
    }
    Ok(Layout {
        ndims,
        sizes_line: ds_f.line,
        ty,
        dims3,
        frames,
        big: h.yes(&["BinaryDataByteOrderMSB", "ElementByteOrderMSB"]),
        compressed: h.yes(&["CompressedData"]),
        binary: h
            .get(&["BinaryData"])
            .is_none_or(|f| f.value.eq_ignore_ascii_case("true")),
    })
}

/// The index → world columns (direction times spacing) and the origin.
fn world_axes(h: &Header, ndims: usize) -> Result<([DVec3; 3], DVec3), IoError> {
    let nsp = ndims.min(3);
    let mut spacing = [1.0f64; 3];
    if let Some(f) = h.get(&["ElementSpacing", "ElementSize"]) {
        let v = floats(f, ndims, "ElementSpacing")?;
        spacing[..nsp].copy_from_slice(&v[..nsp]);
    }
    let mut origin = DVec3::ZERO;
    if let Some(f) = h.get(&["Offset", "Position", "Origin"]) {
        let v = floats(f, ndims, "Offset")?;
        for (j, x) in v.iter().take(nsp).enumerate() {
            origin[j] = *x;
        }
    }
    let mut dirs = [DVec3::X, DVec3::Y, DVec3::Z];
    if let Some(f) = h.get(&["TransformMatrix", "Rotation", "Orientation"]) {
        let v = floats(f, ndims * ndims, "TransformMatrix")?;
        for (k, d) in dirs.iter_mut().enumerate().take(nsp) {
            let mut c = DVec3::ZERO;
            for j in 0..nsp {
                c[j] = v[k * ndims + j];
            }
            *d = c;
        }
    }
    Ok(([0, 1, 2].map(|k| dirs[k] * spacing[k]), origin))
}

/// The separate data file's bytes, or `None` when the data is `LOCAL` (after the header).
fn load_data(
    h: &Header,
    resolve: &dyn Fn(&str) -> Option<Vec<u8>>,
) -> Result<Option<Vec<u8>>, IoError> {
    let df = h.need("ElementDataFile")?;
    if df.value == "LOCAL" {
        return Ok(None);
    }
    if df.value.starts_with("LIST") || df.value.contains('%') {
        return Err(IoError::Unsupported {
            format: F,
            what: format!("ElementDataFile lists or patterns (line {})", df.line),
        });
    }
    resolve(&df.value)
        .map(Some)
        .ok_or_else(|| IoError::Unsupported {
            format: F,
            what: format!(
                "the data file \"{}\" (line {}) could not be read; keep it next to the .mhd, or \
                 use a single-file .mha",
                df.value, df.line
            ),
        })
}

/// Decodes the samples of frame `frame` from `data` (ASCII, compressed or raw with `HeaderSize`).
fn read_values(
    h: &Header,
    l: &Layout,
    data: &[u8],
    data_at: usize,
    frame: usize,
) -> Result<Vec<f32>, IoError> {
    let ty = l.ty;
    let header_size: i64 = match h.get(&["HeaderSize"]) {
        Some(f) => f.value.parse().map_err(|_| {
            IoError::syntax(
                F,
                Location::Line(f.line),
                "HeaderSize (bytes, or -1)",
                &f.value,
            )
        })?,
        None => 0,
    };
    let at = Location::Line(l.sizes_line);
    let all = [l.dims3[0], l.dims3[1], l.dims3[2], l.frames];
    let n: usize = l.dims3.iter().product();
    let first = frame * n;
    if !l.binary {
        checked_count(&all, 2, data.len() + 1, 1, F, at)?;
        let v = parse_ascii_samples(data, first + n, F, h.last_line + 1, 1.0, 0.0)?;
        return Ok(v[first..].to_vec());
    }
    if l.compressed {
        checked_count(&all, ty.size(), data.len(), MAX_INFLATE_RATIO, F, at)?;
        let packing = if is_gzip(data) {
            Packing::Gzip
        } else {
            Packing::Zlib
        };
        let want = (first + n) * ty.size();
        let raw = inflate_prefix(data, packing, want, true, F, data_at)?;
        return Ok(decode_samples(
            &raw[first * ty.size()..want],
            ty,
            l.big,
            1.0,
            0.0,
        ));
    }
    let total = checked_count(&all, ty.size(), data.len(), 1, F, at)? * ty.size();
    let skip = if header_size == -1 {
        data.len() - total
    } else {
        usize::try_from(header_size).unwrap_or(usize::MAX)
    };
    let begin = skip.saturating_add(first * ty.size());
    let end = begin.saturating_add(n * ty.size());
    if end > data.len() {
        return Err(IoError::truncated(
            F,
            Location::Byte(data_at + data.len()),
            format!("{} bytes of samples", n * ty.size()),
        ));
    }
    Ok(decode_samples(&data[begin..end], ty, l.big, 1.0, 0.0))
}

/// Reads a single-file MetaImage (`.mha`) from memory.
pub fn read(bytes: &[u8], opts: &VolumeOptions) -> Result<(VoxelVolume, Encoding), IoError> {
    read_with(bytes, opts, &|_| None)
}
