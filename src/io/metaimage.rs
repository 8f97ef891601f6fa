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

/// Reads a MetaImage; `resolve` fetches a separate `ElementDataFile` by its name relative to the
/// header (none in memory).
pub fn read_with(
    bytes: &[u8],
    opts: &VolumeOptions,
    resolve: &dyn Fn(&str) -> Option<Vec<u8>>,
) -> Result<(VoxelVolume, Encoding), IoError> {
    let mut fields: Vec<(String, Field)> = Vec::new();
    let mut pos = 0;
    let mut line = 0;
    let data_start = loop {
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
            break pos;
        }
    };
    let get = |keys: &[&str]| {
        keys.iter()
            .find_map(|k| fields.iter().find(|(f, _)| f == k).map(|(_, v)| v))
    };
    let need = |key: &str| {
        get(&[key]).ok_or_else(|| {
            IoError::syntax(
                F,
                Location::Line(1),
                format!("the required key {key}"),
                "a header without it",
            )
        })
    };
    let floats = |f: &Field, n: usize, what: &str| -> Result<Vec<f64>, IoError> {
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
    };
    let nd_f = need("NDims")?;
    let ndims: usize = nd_f
        .value
        .parse()
        .ok()
        .filter(|d| (1..=4).contains(d))
        .ok_or_else(|| IoError::syntax(F, Location::Line(nd_f.line), "NDims 1…4", &nd_f.value))?;
    let ds_f = need("DimSize")?;
    let sizes = parse_sizes(
        &ds_f.value,
        ndims,
        F,
        ds_f.line,
        format!("{ndims} sizes ≥ 1 (DimSize)"),
    )?;
    let et_f = need("ElementType")?;
    let ty = scalar_type(&et_f.value).ok_or_else(|| IoError::Unsupported {
        format: F,
        what: format!("ElementType {} (line {})", et_f.value, et_f.line),
    })?;
    if let Some(f) = get(&["ElementNumberOfChannels"]) {
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
    let yes = |keys: &[&str]| get(keys).is_some_and(|f| f.value.eq_ignore_ascii_case("true"));
    let big = yes(&["BinaryDataByteOrderMSB", "ElementByteOrderMSB"]);
    let compressed = yes(&["CompressedData"]);
    let binary = get(&["BinaryData"]).is_none_or(|f| f.value.eq_ignore_ascii_case("true"));
    let mut spacing = [1.0f64; 3];
    if let Some(f) = get(&["ElementSpacing", "ElementSize"]) {
        let v = floats(f, ndims, "ElementSpacing")?;
        spacing[..nsp].copy_from_slice(&v[..nsp]);
    }
    let mut origin = DVec3::ZERO;
    if let Some(f) = get(&["Offset", "Position", "Origin"]) {
        let v = floats(f, ndims, "Offset")?;
        for (j, x) in v.iter().take(nsp).enumerate() {
            origin[j] = *x;
        }
    }
    let mut dirs = [DVec3::X, DVec3::Y, DVec3::Z];
    if let Some(f) = get(&["TransformMatrix", "Rotation", "Orientation"]) {
        let v = floats(f, ndims * ndims, "TransformMatrix")?;
        for (k, d) in dirs.iter_mut().enumerate().take(nsp) {
            let mut c = DVec3::ZERO;
            for j in 0..nsp {
                c[j] = v[k * ndims + j];
            }
            *d = c;
        }
    }
    let cols = [0, 1, 2].map(|k| dirs[k] * spacing[k]);
    let orientation = get(&["AnatomicalOrientation"])
        .map(|f| f.value.clone())
        .unwrap_or_else(|| "unspecified".into());
    let frame = format!(
        "MetaImage world frame as written (Offset/ElementSpacing/TransformMatrix; \
         AnatomicalOrientation {orientation})"
    );
    // The data.
    let df = need("ElementDataFile")?;
    let owned;
    let (data, data_at): (&[u8], usize) = if df.value == "LOCAL" {
        (&bytes[data_start..], data_start)
    } else {
        if df.value.starts_with("LIST") || df.value.contains('%') {
            return Err(IoError::Unsupported {
                format: F,
                what: format!("ElementDataFile lists or patterns (line {})", df.line),
            });
        }
        owned = resolve(&df.value).ok_or_else(|| IoError::Unsupported {
            format: F,
            what: format!(
                "the data file \"{}\" (line {}) could not be read; keep it next to the .mhd, or \
                 use a single-file .mha",
                df.value, df.line
            ),
        })?;
        (&owned, 0)
    };
    let header_size: i64 = match get(&["HeaderSize"]) {
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
    let all = [dims3[0], dims3[1], dims3[2], frames];
    let n: usize = dims3.iter().product();
    let first = opts.frame * n;
    let values = if !binary {
        checked_count(&all, 2, data.len() + 1, 1, F, Location::Line(ds_f.line))?;
        let v = parse_ascii_samples(data, first + n, F, line + 1, 1.0, 0.0)?;
        v[first..].to_vec()
    } else if compressed {
        checked_count(
            &all,
            ty.size(),
            data.len(),
            MAX_INFLATE_RATIO,
            F,
            Location::Line(ds_f.line),
        )?;
        let packing = if is_gzip(data) {
            Packing::Gzip
        } else {
            Packing::Zlib
        };
        let want = (first + n) * ty.size();
        let raw = inflate_prefix(data, packing, want, true, F, data_at)?;
        decode_samples(&raw[first * ty.size()..want], ty, big, 1.0, 0.0)
    } else {
        let total = checked_count(&all, ty.size(), data.len(), 1, F, Location::Line(ds_f.line))?
            * ty.size();
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
        decode_samples(&data[begin..end], ty, big, 1.0, 0.0)
    };
    Ok((
        VoxelVolume {
            dims: dims3,
            values,
            index_to_world: affine(cols, origin),
            datatype: ty,
            frame,
            frames,
            frame_index: opts.frame,
        },
        if !binary {
            Encoding::Ascii
        } else if big {
            Encoding::BinaryBe
        } else {
            Encoding::BinaryLe
        },
    ))
}

/// Reads a single-file MetaImage (`.mha`) from memory.
pub fn read(bytes: &[u8], opts: &VolumeOptions) -> Result<(VoxelVolume, Encoding), IoError> {
    read_with(bytes, opts, &|_| None)
}
