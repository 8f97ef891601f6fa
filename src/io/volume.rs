//! Voxel volumes, the common output of the NIfTI, NRRD, VTI and MetaImage readers: node values on
//! a regular lattice plus the affine map from voxel indices to world millimetres, so the same
//! volume read from any of the four formats lands in the same place.
//!
//! Also here, because every volume reader needs them: sample decoding (all common integer and
//! float types, either byte order, with a linear scaling), bounded gzip/zlib inflation (a corrupt
//! or hostile stream cannot make a reader allocate more than the header justifies), Otsu's
//! threshold (the default iso-value) and the iso-surface of a volume in world coordinates.

use super::error::{Format, IoError, Location};
use crate::geometry::marching_cubes::{marching_cubes_with, GridNodes};
use crate::target::{Target, TargetError};
use glam::{DMat4, DVec3, DVec4};
use serde::{Deserialize, Serialize};
use std::io::Read;

/// The sample type stored in a volume file (values are converted to `f32` on reading).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum ScalarType {
    /// Unsigned 8-bit integer.
    U8,
    /// Signed 8-bit integer.
    I8,
    /// Unsigned 16-bit integer.
    U16,
    /// Signed 16-bit integer.
    I16,
    /// Unsigned 32-bit integer.
    U32,
    /// Signed 32-bit integer.
    I32,
    /// Unsigned 64-bit integer.
    U64,
    /// Signed 64-bit integer.
    I64,
    /// IEEE 754 single precision.
    F32,
    /// IEEE 754 double precision.
    F64,
}

impl ScalarType {
    /// Bytes per sample.
    pub fn size(self) -> usize {
        match self {
            ScalarType::U8 | ScalarType::I8 => 1,
            ScalarType::U16 | ScalarType::I16 => 2,
            ScalarType::U32 | ScalarType::I32 | ScalarType::F32 => 4,
            ScalarType::U64 | ScalarType::I64 | ScalarType::F64 => 8,
        }
    }

    /// Short name as printed by `lsw info` ("uint8", "int16", "float32", …).
    pub fn name(self) -> &'static str {
        match self {
            ScalarType::U8 => "uint8",
            ScalarType::I8 => "int8",
            ScalarType::U16 => "uint16",
            ScalarType::I16 => "int16",
            ScalarType::U32 => "uint32",
            ScalarType::I32 => "int32",
            ScalarType::U64 => "uint64",
            ScalarType::I64 => "int64",
            ScalarType::F32 => "float32",
            ScalarType::F64 => "float64",
        }
    }

    /// True for the integer types (Otsu then bins one value per bin when the range allows).
    pub fn is_integer(self) -> bool {
        !matches!(self, ScalarType::F32 | ScalarType::F64)
    }
}

/// Which side of the iso-surface is the structure: voxels brighter than the iso-value (a tissue
/// probability map, CT bone) or darker (ventricles in T1, air).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Inside {
    /// Inside where `value > iso` (the default).
    #[default]
    Bright,
    /// Inside where `value < iso`.
    Dark,
}

/// How to read a volume and which surface to take from it.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(default)]
pub struct VolumeOptions {
    /// Which volume of a 4-D file (time series, several components): 0-based; default 0.
    pub frame: usize,
    /// The iso-value of the surface S = {v = iso}, in the file's (scaled) value units;
    /// `None` (the default) takes Otsu's threshold of the histogram.
    pub iso: Option<f64>,
    /// Which side of S is inside; default bright.
    pub inside: Inside,
    /// VTI only: the point array to read; `None` takes the `Scalars` array of `PointData`, or
    /// the first one.
    pub array: Option<String>,
}

/// A scalar volume: `values[ix + nx·(iy + ny·iz)]` at voxel index (ix, iy, iz), which lies at
/// `index_to_world · (ix, iy, iz, 1)` in world millimetres.
#[derive(Clone, Debug, PartialEq)]
pub struct VoxelVolume {
    /// Voxel counts (nx, ny, nz).
    pub dims: [usize; 3],
    /// `nx·ny·nz` values after the file's scaling (NIfTI `scl_slope`/`scl_inter`), x fastest.
    pub values: Vec<f32>,
    /// Affine map from voxel index to world coordinates (mm).
    pub index_to_world: DMat4,
    /// The sample type stored in the file.
    pub datatype: ScalarType,
    /// The world frame, in words (e.g. "RAS (NIfTI sform, code 4)").
    pub frame: String,
    /// Number of volumes in the file (the product of the dimensions beyond the third).
    pub frames: usize,
    /// The volume that was read (0-based).
    pub frame_index: usize,
}

impl VoxelVolume {
    /// World position of a (possibly fractional) voxel index.
    pub fn world(&self, index: DVec3) -> DVec3 {
        self.index_to_world.transform_point3(index)
    }

    /// Voxel size along each index axis in mm (lengths of the affine's columns).
    pub fn voxel_size(&self) -> [f64; 3] {
        [
            self.index_to_world.x_axis.truncate().length(),
            self.index_to_world.y_axis.truncate().length(),
            self.index_to_world.z_axis.truncate().length(),
        ]
    }

    /// Smallest and largest finite value (`None` when there is none).
    pub fn value_range(&self) -> Option<(f64, f64)> {
        let mut r: Option<(f32, f32)> = None;
        for &v in self.values.iter().filter(|v| v.is_finite()) {
            r = Some(match r {
                None => (v, v),
                Some((lo, hi)) => (lo.min(v), hi.max(v)),
            });
        }
        r.map(|(lo, hi)| (lo as f64, hi as f64))
    }

    /// Otsu's threshold of the values (see [`otsu_threshold`]).
    pub fn otsu(&self) -> Option<f64> {
        otsu_threshold(&self.values, self.datatype.is_integer())
    }

    /// The affine as rows (row-major 4×4), as printed in JSON.
    pub fn affine_rows(&self) -> [[f64; 4]; 4] {
        let m = self.index_to_world.transpose();
        [
            m.x_axis.to_array(),
            m.y_axis.to_array(),
            m.z_axis.to_array(),
            m.w_axis.to_array(),
        ]
    }

    /// The surface S = {v = iso} of the piecewise-linear interpolant of the voxels, closed: the
    /// volume is padded by one voxel of "outside" value, so a structure touching the border is
    /// capped there rather than left open. Marching tetrahedra in index space
    /// ([`crate::geometry::marching_cubes`]: no ambiguous cases, always manifold), then mapped
    /// through the affine; triangles are counter-clockwise seen from outside (reversed when the
    /// affine mirrors, e.g. a radiological-order NIfTI). Non-finite values count as outside.
    pub fn isosurface(&self, iso: f64, inside: Inside) -> (Vec<DVec3>, Vec<[u32; 3]>) {
        let [nx, ny, nz] = self.dims;
        let (px, py, pz) = (nx + 2, ny + 2, nz + 2);
        // g < 0 inside; the marching code treats nodes with g < 0 as inside.
        let sign = match inside {
            Inside::Bright => -1.0,
            Inside::Dark => 1.0,
        };
        // The volume padded by one voxel of outside (1) and offset by the iso-value, read where
        // the marching needs it rather than written out (at 8 bytes a voxel, gigabytes for a
        // large volume).
        let value = |ix: usize, iy: usize, iz: usize| -> f64 {
            let pad = |i: usize, n: usize| i == 0 || i > n;
            if pad(ix, nx) || pad(iy, ny) || pad(iz, nz) {
                return 1.0;
            }
            let v = self.values[(ix - 1) + nx * ((iy - 1) + ny * (iz - 1))];
            if v.is_finite() {
                sign * (v as f64 - iso)
            } else {
                1.0
            }
        };
        let nodes = GridNodes {
            first: [0; 3],
            origin: DVec3::splat(-1.0),
            cell: 1.0,
            dims: [px, py, pz],
        };
        let (mut positions, mut triangles) = marching_cubes_with(&nodes, value, 0.0);
        for p in &mut positions {
            *p = self.world(*p);
        }
        if self.index_to_world.determinant() < 0.0 {
            for t in &mut triangles {
                t.swap(1, 2);
            }
        }
        (positions, triangles)
    }

    /// One axis-aligned slice of values (axis 0, 1 or 2 at `index`), row-major in the two other
    /// axes (the lower-numbered axis fastest); empty when out of range. For the app's slice views.
    pub fn slice(&self, axis: usize, index: usize) -> Vec<f32> {
        let [nx, ny, nz] = self.dims;
        let at = |x: usize, y: usize, z: usize| self.values[x + nx * (y + ny * z)];
        match axis {
            0 if index < nx => (0..nz)
                .flat_map(|z| (0..ny).map(move |y| (y, z)))
                .map(|(y, z)| at(index, y, z))
                .collect(),
            1 if index < ny => (0..nz)
                .flat_map(|z| (0..nx).map(move |x| (x, z)))
                .map(|(x, z)| at(x, index, z))
                .collect(),
            2 if index < nz => self.values[nx * ny * index..nx * ny * (index + 1)].to_vec(),
            _ => Vec::new(),
        }
    }
}

/// A histogram of finite values over `[min, max]` in equal bins.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Histogram {
    /// Lower edge of the first bin.
    pub min: f64,
    /// Upper edge of the last bin.
    pub max: f64,
    /// Counts per bin.
    pub counts: Vec<u64>,
}

/// The histogram of the finite values in `bins` equal bins (at least 1), or `None` when no value
/// is finite.
pub fn histogram(values: &[f32], bins: usize) -> Option<Histogram> {
    let bins = bins.max(1);
    let (mut lo, mut hi) = (f32::INFINITY, f32::NEG_INFINITY);
    for &v in values.iter().filter(|v| v.is_finite()) {
        lo = lo.min(v);
        hi = hi.max(v);
    }
    if lo > hi {
        return None;
    }
    let (lo, hi) = (lo as f64, hi as f64);
    let w = if hi > lo {
        (hi - lo) / bins as f64
    } else {
        1.0
    };
    let mut counts = vec![0u64; bins];
    for &v in values.iter().filter(|v| v.is_finite()) {
        let k = (((v as f64 - lo) / w) as usize).min(bins - 1);
        counts[k] += 1;
    }
    Some(Histogram {
        min: lo,
        max: if hi > lo { hi } else { lo + w },
        counts,
    })
}

/// Otsu's threshold: the value that splits the histogram into two classes of maximal
/// between-class variance (N. Otsu, IEEE Trans. SMC 9(1), 1979). Integer data whose range spans
/// at most 65 536 values get one bin per value and a threshold halfway between two values (so
/// `v > t` is unambiguous); other data 1024 bins. Where several splits tie (empty bins between two
/// peaks) the middle one is taken, so a 0/255 mask gives 127.5 rather than 0.5. `None` when fewer
/// than two distinct finite values exist.
pub fn otsu_threshold(values: &[f32], integer: bool) -> Option<f64> {
    let (mut lo, mut hi) = (f32::INFINITY, f32::NEG_INFINITY);
    for &v in values.iter().filter(|v| v.is_finite()) {
        lo = lo.min(v);
        hi = hi.max(v);
    }
    if lo >= hi {
        return None;
    }
    let (lo, hi) = (lo as f64, hi as f64);
    let integral = integer && hi - lo < 65_536.0;
    let bins = if integral {
        (hi - lo) as usize + 1
    } else {
        1024
    };
    let w = if integral {
        1.0
    } else {
        (hi - lo) / bins as f64
    };
    let mut counts = vec![0u64; bins];
    for &v in values.iter().filter(|v| v.is_finite()) {
        let k = if integral {
            (v as f64 - lo).round() as usize
        } else {
            ((v as f64 - lo) / w) as usize
        };
        counts[k.min(bins - 1)] += 1;
    }
    let centre = |k: usize| {
        if integral {
            lo + k as f64
        } else {
            lo + (k as f64 + 0.5) * w
        }
    };
    let total: f64 = counts.iter().map(|&c| c as f64).sum();
    let sum_all: f64 = counts
        .iter()
        .enumerate()
        .map(|(k, &c)| c as f64 * centre(k))
        .sum();
    // Between-class variance for the split after bin k, k = 0 … bins − 2.
    let mut sigma = Vec::with_capacity(bins - 1);
    let (mut w0, mut s0) = (0.0, 0.0);
    for (k, &c) in counts.iter().enumerate().take(bins - 1) {
        w0 += c as f64;
        s0 += c as f64 * centre(k);
        let w1 = total - w0;
        sigma.push(if w0 > 0.0 && w1 > 0.0 {
            let d = s0 / w0 - (sum_all - s0) / w1;
            w0 * w1 * d * d
        } else {
            0.0
        });
    }
    let best = sigma.iter().cloned().fold(0.0f64, f64::max);
    let tol = best * 1e-12;
    let first = sigma.iter().position(|&s| s >= best - tol)?;
    let last = first
        + sigma[first..]
            .iter()
            .take_while(|&&s| s >= best - tol)
            .count()
        - 1;
    let k = (first + last) / 2;
    Some(if integral {
        lo + k as f64 + 0.5
    } else {
        lo + (k + 1) as f64 * w
    })
}

/// Converts raw samples to `f32` as `raw·slope + inter` (computed in f64). `bytes` holds exactly
/// `n·ty.size()` bytes in the given byte order.
pub(crate) fn decode_samples(
    bytes: &[u8],
    ty: ScalarType,
    big_endian: bool,
    slope: f64,
    inter: f64,
) -> Vec<f32> {
    macro_rules! conv {
        ($t:ty, $n:expr) => {
            bytes
                .chunks_exact($n)
                .map(|c| {
                    let a: [u8; $n] = c.try_into().expect("chunk size");
                    let raw = if big_endian {
                        <$t>::from_be_bytes(a)
                    } else {
                        <$t>::from_le_bytes(a)
                    };
                    raw as f64
                })
                .map(|r| (r * slope + inter) as f32)
                .collect()
        };
    }
    match ty {
        ScalarType::U8 => bytes
            .iter()
            .map(|&b| (b as f64 * slope + inter) as f32)
            .collect(),
        ScalarType::I8 => bytes
            .iter()
            .map(|&b| (b as i8 as f64 * slope + inter) as f32)
            .collect(),
        ScalarType::U16 => conv!(u16, 2),
        ScalarType::I16 => conv!(i16, 2),
        ScalarType::U32 => conv!(u32, 4),
        ScalarType::I32 => conv!(i32, 4),
        ScalarType::U64 => conv!(u64, 8),
        ScalarType::I64 => conv!(i64, 8),
        ScalarType::F32 => conv!(f32, 4),
        ScalarType::F64 => conv!(f64, 8),
    }
}

/// Parses whitespace-separated numbers (ASCII-encoded NRRD, MetaImage and VTI data): exactly `n`
/// are expected; `line0` is the line of the first byte (for errors).
pub(crate) fn parse_ascii_samples(
    text: &[u8],
    n: usize,
    format: Format,
    line0: usize,
    slope: f64,
    inter: f64,
) -> Result<Vec<f32>, IoError> {
    let mut t = super::text::Tokens::new(text, 0, line0, false);
    let mut out = Vec::with_capacity(n.min(text.len() / 2 + 1));
    for i in 0..n {
        let tok = t.next_token().ok_or_else(|| {
            IoError::truncated(
                format,
                Location::Line(t.line()),
                format!("{n} values, found {i}"),
            )
        })?;
        let v = super::text::parse_f64(tok).ok_or_else(|| {
            IoError::syntax(
                format,
                Location::Line(t.line()),
                "a number",
                super::text::show(tok),
            )
        })?;
        out.push((v * slope + inter) as f32);
    }
    Ok(out)
}

/// A text header's list of exactly `n` voxel counts (each ≥ 1), at `line`; every product of them
/// fits in usize (also on 32-bit wasm). `expected` names the field in the error.
pub(crate) fn parse_sizes(
    text: &str,
    n: usize,
    format: Format,
    line: usize,
    expected: String,
) -> Result<Vec<usize>, IoError> {
    let sizes = text
        .split_whitespace()
        .map(|t| t.parse::<usize>().ok().filter(|&s| s >= 1))
        .collect::<Option<Vec<_>>>()
        .filter(|v| v.len() == n)
        .ok_or_else(|| IoError::syntax(format, Location::Line(line), expected, text))?;
    checked_count(&sizes, 1, usize::MAX / 16, 1, format, Location::Line(line))?;
    Ok(sizes)
}

/// The number of voxels `dims` describe, refusing overflow and anything larger than
/// `available` bytes could hold at `bytes_each` (× `max_ratio` for compressed data: deflate
/// cannot expand more than about 1032:1).
pub(crate) fn checked_count(
    dims: &[usize],
    bytes_each: usize,
    available: usize,
    max_ratio: u128,
    format: Format,
    at: Location,
) -> Result<usize, IoError> {
    let count: u128 = dims
        .iter()
        .try_fold(1u128, |a, &d| a.checked_mul(d as u128))
        .unwrap_or(u128::MAX);
    let needed = count.saturating_mul(bytes_each as u128);
    if needed > (available as u128).saturating_mul(max_ratio) || count > usize::MAX as u128 / 8 {
        return Err(IoError::CountTooLarge {
            format,
            at,
            element: "voxels".into(),
            count: count.min(u64::MAX as u128) as u64,
            available,
            needed,
        });
    }
    Ok(count as usize)
}

/// Deflate's worst-case expansion is about 1032:1; a header promising more is corrupt.
pub(crate) const MAX_INFLATE_RATIO: u128 = 1100;

/// Which compressed container a stream is in.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Packing {
    /// gzip (RFC 1952), possibly several members.
    Gzip,
    /// zlib (RFC 1950).
    Zlib,
}

/// Inflates the first `want` bytes of a gzip or zlib stream starting at byte `at` of the file.
/// With `exact`, fewer bytes are an [`IoError::Truncated`]; otherwise what there is is returned.
pub(crate) fn inflate_prefix(
    data: &[u8],
    packing: Packing,
    want: usize,
    exact: bool,
    format: Format,
    at: usize,
) -> Result<Vec<u8>, IoError> {
    let mut out = Vec::with_capacity(want.min(data.len().saturating_mul(8)).min(1 << 30));
    let res = match packing {
        Packing::Gzip => flate2::read::MultiGzDecoder::new(data)
            .take(want as u64)
            .read_to_end(&mut out),
        Packing::Zlib => flate2::read::ZlibDecoder::new(data)
            .take(want as u64)
            .read_to_end(&mut out),
    };
    let kind = match packing {
        Packing::Gzip => "gzip",
        Packing::Zlib => "zlib",
    };
    match res {
        Err(e) if e.kind() == std::io::ErrorKind::UnexpectedEof => {
            return Err(IoError::truncated(
                format,
                Location::Byte(at + data.len()),
                format!("{want} bytes of {kind}-compressed data, the stream ends early"),
            ))
        }
        Err(e) => {
            return Err(IoError::Decompress {
                format,
                at: Location::Byte(at),
                message: format!("{kind}: {e}"),
            })
        }
        Ok(_) => {}
    }
    if exact && out.len() < want {
        return Err(IoError::truncated(
            format,
            Location::Byte(at + data.len()),
            format!(
                "{want} bytes of {kind}-compressed data, found {}",
                out.len()
            ),
        ));
    }
    Ok(out)
}

/// True when `bytes` start with the gzip magic number.
pub(crate) fn is_gzip(bytes: &[u8]) -> bool {
    bytes.starts_with(&[0x1f, 0x8b])
}

/// An affine from a 3×3 linear part (columns = world directions of the index axes, already
/// scaled by the voxel size) and a translation.
pub(crate) fn affine(cols: [DVec3; 3], origin: DVec3) -> DMat4 {
    DMat4::from_cols(
        cols[0].extend(0.0),
        cols[1].extend(0.0),
        cols[2].extend(0.0),
        DVec4::new(origin.x, origin.y, origin.z, 1.0),
    )
}

/// A volume's target is built here, where volumes are read: the target knows nothing of files.
impl Target {
    /// The target of a voxel volume: the closed surface S = {v = iso} (see
    /// [`VoxelVolume::isosurface`]) in world millimetres, as a triangle mesh. The whole pipeline
    /// (signed distance field, start surface, flow, metrics) then works on volumes unchanged; the
    /// triangles are exact to the piecewise-linear interpolant, so the field near S is exact too.
    pub fn from_volume(
        volume: &VoxelVolume,
        iso: f64,
        inside: Inside,
    ) -> Result<Self, TargetError> {
        let (points, triangles) = volume.isosurface(iso, inside);
        if triangles.is_empty() {
            let (min, max) = volume.value_range().unwrap_or((f64::NAN, f64::NAN));
            return Err(TargetError::NoIsosurface { iso, min, max });
        }
        Self::iso_surface(points, triangles)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn otsu_splits_two_peaks_and_mid_plateau() {
        let mut v = vec![0.0f32; 100];
        v.extend(vec![255.0f32; 50]);
        assert_eq!(otsu_threshold(&v, true), Some(127.5));
        let mut w: Vec<f32> = (0..100).map(|i| 10.0 + (i % 5) as f32).collect();
        w.extend((0..100).map(|i| 100.0 + (i % 7) as f32));
        let t = otsu_threshold(&w, false).unwrap();
        assert!(t > 14.0 && t < 100.0, "{t}");
        assert_eq!(otsu_threshold(&[3.0, 3.0], true), None);
    }

    #[test]
    fn samples_decode_both_orders_with_scaling() {
        let le = [0x01, 0x02, 0xff, 0xff];
        assert_eq!(
            decode_samples(&le, ScalarType::I16, false, 2.0, 1.0),
            vec![1027.0, -1.0]
        );
        assert_eq!(
            decode_samples(&le, ScalarType::U16, true, 1.0, 0.0),
            vec![258.0, 65535.0]
        );
    }
}
