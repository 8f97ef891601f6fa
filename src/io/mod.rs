//! Reading and writing geometry files. Readers: PLY, OBJ, STL, OFF, XYZ/PTS/TXT/CSV, glTF/GLB,
//! legacy VTK polydata, PCD, LAS/LAZ, E57 and PTX (any of them also gzip-compressed); voxel
//! volumes NIfTI-1/2, NRRD, VTI and MetaImage ([`volume`]).
//! Writers ([`write_bytes`]): OBJ, PLY, STL, GLB and VTK.
//!
//! A volume becomes a target through its iso-surface (see [`Target::from_volume`]): the
//! [`ReadResult`] then carries the volume itself in [`ReadResult::volume`], and the target is the
//! closed surface {v = iso} in world millimetres, so the field and the flow need no volume code.
//!
//! One file per format; [`detect()`] sniffs the format from the content (the file name is only a
//! hint). Reading gives a [`Target`] (points, or triangles indexing points). Readers never panic
//! and never allocate more than the input size justifies: header counts are checked against the
//! bytes that follow before any buffer is reserved. Every failure is an [`IoError`] naming the
//! format, the line or byte offset, and what was expected.
//!
//! Readers take `&[u8]` so the browser path can hand over the dropped file's bytes once, with no
//! intermediate copy; [`read_path`] (native only) reads a file and calls [`read_bytes`].

pub mod detect;
pub mod e57;
pub mod error;
pub mod formats;
pub mod gltf;
pub mod las;
pub mod metaimage;
pub mod nifti;
pub mod nrrd;
pub mod obj;
pub mod off;
pub mod pcd;
pub mod ply;
pub mod ptx;
pub mod stl;
pub(crate) mod text;
pub mod volume;
pub mod vti;
pub mod vtk;
pub mod xyz;

pub use detect::detect;
pub use error::{Format, IoError, Location};
pub use formats::{FormatInfo, FormatKind, FORMATS};
pub use volume::{Inside, VolumeOptions, VoxelVolume};

use crate::progress::Progress;
use crate::target::{Target, TargetError};
use glam::DVec3;
use serde::{Deserialize, Serialize};

/// The progress phase of reading a file: the readers of big clouds and meshes (PLY, XYZ, OBJ,
/// STL, PCD, LAS/LAZ, E57, PTX) report the share of their input read, so a file that takes
/// seconds to read shows a percentage too.
pub const READING: &str = "reading";

/// How often, in records, a reader reports its position (reports are thinned further in time).
pub(crate) const REPORT_EVERY: usize = 4096;

/// How the data of a file was encoded.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Encoding {
    /// Text (ASCII / UTF-8), including glTF JSON.
    Ascii,
    /// Binary, little-endian (binary PLY/STL, GLB).
    BinaryLe,
    /// Binary, big-endian (binary PLY only).
    BinaryBe,
}

/// Points and triangles as a reader produced them (before [`Target::new`] checks them).
pub type RawMesh = (Vec<DVec3>, Vec<[u32; 3]>);

/// A reader's output: points, triangles and how the file was encoded.
pub type RawGeometry = (Vec<DVec3>, Vec<[u32; 3]>, Encoding);

/// What [`read_bytes`] returns: the target and how it was stored.
#[derive(Clone, Debug, PartialEq)]
pub struct ReadResult {
    /// The points or mesh read, with its bounding box.
    pub target: Target,
    /// The format detected from the content (and, where ambiguous, the file name).
    pub format: Format,
    /// Text or binary (and byte order).
    pub encoding: Encoding,
    /// For volume formats: the volume and the iso-surface the target was built from.
    pub volume: Option<Box<VolumeRead>>,
    /// For meshes whose indices were mended on reading (see [`Target::repaired`]): what changed.
    pub repairs: Option<crate::mesh::Repairs>,
    /// Points the file itself marks as not measured or not to be used, which were not read.
    pub left_out: Option<LeftOut>,
}

/// Points a cloud file marks as unusable and the reader left out: a depth image's pixels without
/// a measurement (PCD), points flagged withheld or classified as noise (LAS), points marked
/// invalid (E57), grid cells without a return (PTX). Reported so that a cloud smaller than its
/// file's count is not a surprise.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[cfg_attr(target_arch = "wasm32", derive(tsify::Tsify))]
pub struct LeftOut {
    /// How many.
    pub points: usize,
    /// Why, as a phrase after the count ("points without a measurement (NaN pixels)").
    pub why: &'static str,
}

impl LeftOut {
    /// `None` for none left out.
    pub(crate) fn of(points: usize, why: &'static str) -> Option<LeftOut> {
        (points > 0).then_some(LeftOut { points, why })
    }

    /// A cloud reader's result: the points it kept, with `left` more left out for `why` (set in
    /// `left_out`), or the error that it left out every point of the file (nothing to wrap).
    pub(crate) fn kept(
        format: Format,
        at: Location,
        points: Vec<DVec3>,
        (left, why): (usize, &'static str),
        left_out: &mut Option<LeftOut>,
    ) -> Result<Vec<DVec3>, IoError> {
        if points.is_empty() && left > 0 {
            return Err(IoError::syntax(
                format,
                at,
                "at least one point to wrap",
                format!("{left} {why} and no other point"),
            ));
        }
        *left_out = LeftOut::of(left, why);
        Ok(points)
    }
}

/// A volume as read, and the level set of it that became the target.
#[derive(Clone, Debug, PartialEq)]
pub struct VolumeRead {
    /// The voxels and their index → world map.
    pub volume: VoxelVolume,
    /// The iso-value of the target surface.
    pub iso: f64,
    /// Where `iso` came from: "option" (given) or "otsu" (Otsu's threshold).
    pub iso_source: &'static str,
    /// Which side of the surface is inside.
    pub inside: Inside,
}

/// Reads a geometry file from memory. `file_name` (optional, any path form) only breaks ties
/// where the content is ambiguous (e.g. a point list vs. an OBJ without keywords).
pub fn read_bytes(bytes: &[u8], file_name: Option<&str>) -> Result<ReadResult, IoError> {
    read_bytes_with(bytes, file_name, &VolumeOptions::default())
}

/// [`read_bytes`] with the options for volume files (frame, iso-value, inside; ignored for
/// meshes and point clouds).
pub fn read_bytes_with(
    bytes: &[u8],
    file_name: Option<&str>,
    opts: &VolumeOptions,
) -> Result<ReadResult, IoError> {
    read_bytes_progress(bytes, file_name, opts, &mut Progress::none())
}

/// [`read_bytes_with`], reporting [`READING`] to `progress`.
pub fn read_bytes_progress(
    bytes: &[u8],
    file_name: Option<&str>,
    opts: &VolumeOptions,
    progress: &mut Progress,
) -> Result<ReadResult, IoError> {
    if let Some((inner, name)) = gunzipped(bytes, file_name)? {
        return read_bytes_progress(&inner, name.as_deref(), opts, progress);
    }
    let format = detect(bytes, file_name)?;
    read_as_progress(bytes, format, opts, progress)
}

/// Inflated bytes and the file name they came under, without `.gz`.
type Inflated = (Vec<u8>, Option<String>);

/// A gzip-compressed mesh or cloud (`scan.ply.gz`, `points.xyz.gz`, …): its inflated bytes and the
/// file name without `.gz`. `None` when `bytes` are not gzip, or are a NIfTI volume (which is
/// stored that way and inflated by its reader as far as the frame it needs). Inflation stops at
/// deflate's worst-case ratio; gzip inside gzip is refused.
fn gunzipped(bytes: &[u8], file_name: Option<&str>) -> Result<Option<Inflated>, IoError> {
    use volume::{inflate_prefix, is_gzip, Packing, MAX_INFLATE_RATIO};
    let lower = file_name.map(str::to_ascii_lowercase);
    let nifti_name = lower.as_deref().is_some_and(|n| {
        n.ends_with(".nii.gz") || n.ends_with(".img.gz") || n.ends_with(".hdr.gz")
    });
    if !is_gzip(bytes) || nifti_name {
        return Ok(None);
    }
    let inner_name = file_name.map(|n| match n.len().checked_sub(3) {
        Some(k) if n.is_char_boundary(k) && n[k..].eq_ignore_ascii_case(".gz") => {
            n[..k].to_string()
        }
        _ => n.to_string(),
    });
    // Errors name the format the inner name says (else the one the content turns out to be).
    let format = inner_name
        .as_deref()
        .and_then(Format::from_file_name)
        .unwrap_or(Format::Nifti);
    let head = inflate_prefix(bytes, Packing::Gzip, 540, false, format, 0)?;
    if nifti::sniff(&head) {
        return Ok(None);
    }
    let most = (bytes.len() as u128 * MAX_INFLATE_RATIO).min(isize::MAX as u128) as usize;
    let inner = inflate_prefix(bytes, Packing::Gzip, most, false, format, 0)?;
    if is_gzip(&inner) {
        return Err(IoError::Unsupported {
            format,
            what: "gzip inside gzip".into(),
        });
    }
    Ok(Some((inner, inner_name)))
}

/// Reads a volume file from memory (NIfTI, NRRD, VTI, MetaImage) without building a target:
/// what the app needs for its histogram and slices. Detached data (`.hdr`/`.img`, `.nhdr`,
/// `.mhd`) is refused here; [`read_volume_path`] reads it natively.
pub fn read_volume_bytes(
    bytes: &[u8],
    file_name: Option<&str>,
    opts: &VolumeOptions,
) -> Result<(VoxelVolume, Format, Encoding), IoError> {
    let format = detect(bytes, file_name)?;
    let (v, e) = read_volume_as(bytes, format, opts, &|_| None)?;
    Ok((v, format, e))
}

/// Dispatches to the volume readers; `resolve` fetches detached data files by relative name.
fn read_volume_as(
    bytes: &[u8],
    format: Format,
    opts: &VolumeOptions,
    resolve: &dyn Fn(&str) -> Option<Vec<u8>>,
) -> Result<(VoxelVolume, Encoding), IoError> {
    if bytes.is_empty() {
        return Err(IoError::Empty {
            format: Some(format),
        });
    }
    if opts.frame > 0 && format == Format::Vti {
        return Err(IoError::Unsupported {
            format,
            what: format!("frame {} (a VTI file holds one volume)", opts.frame),
        });
    }
    match format {
        Format::Nifti => nifti::read(bytes, opts),
        Format::Nrrd => nrrd::read_with(bytes, opts, resolve),
        Format::Vti => vti::read(bytes, opts),
        Format::MetaImage => metaimage::read_with(bytes, opts, resolve),
        f => Err(IoError::Unsupported {
            format: f,
            what: "reading it as a voxel volume".into(),
        }),
    }
}

/// Builds the target of a volume: the closed iso-surface at `opts.iso` (or Otsu's threshold).
pub fn volume_target(
    format: Format,
    volume: VoxelVolume,
    encoding: Encoding,
    opts: &VolumeOptions,
) -> Result<ReadResult, IoError> {
    let (target, iso, iso_source) = volume_surface(format, &volume, opts)?;
    Ok(ReadResult {
        target,
        format,
        encoding,
        volume: Some(Box::new(VolumeRead {
            volume,
            iso,
            iso_source,
            inside: opts.inside,
        })),
        repairs: None,
        left_out: None,
    })
}

/// The target of [`volume_target`] without taking the volume: its iso-surface, the iso-value,
/// and where that came from ("option" or "otsu"). (The app wraps the volume it already holds for
/// its slices, rather than a second copy read from the same bytes.)
pub fn volume_surface(
    format: Format,
    volume: &VoxelVolume,
    opts: &VolumeOptions,
) -> Result<(Target, f64, &'static str), IoError> {
    let (iso, iso_source) = match opts.iso {
        Some(i) => (i, "option"),
        None => match volume.otsu() {
            Some(i) => (i, "otsu"),
            None => {
                return Err(IoError::Target {
                    format,
                    source: TargetError::NoIsosurface {
                        iso: f64::NAN,
                        min: volume.value_range().map_or(f64::NAN, |r| r.0),
                        max: volume.value_range().map_or(f64::NAN, |r| r.1),
                    },
                })
            }
        },
    };
    let target = Target::from_volume(volume, iso, opts.inside)
        .map_err(|source| IoError::Target { format, source })?;
    Ok((target, iso, iso_source))
}

/// Reads `bytes` as the given format, skipping detection.
pub fn read_as(bytes: &[u8], format: Format) -> Result<ReadResult, IoError> {
    read_as_with(bytes, format, &VolumeOptions::default())
}

/// [`read_as`] with volume options.
pub fn read_as_with(
    bytes: &[u8],
    format: Format,
    opts: &VolumeOptions,
) -> Result<ReadResult, IoError> {
    read_as_progress(bytes, format, opts, &mut Progress::none())
}

/// [`read_as_with`], reporting [`READING`] to `progress`.
fn read_as_progress(
    bytes: &[u8],
    format: Format,
    opts: &VolumeOptions,
    progress: &mut Progress,
) -> Result<ReadResult, IoError> {
    if bytes.is_empty() {
        return Err(IoError::Empty {
            format: Some(format),
        });
    }
    if format.is_volume() {
        let (v, e) = read_volume_as(bytes, format, opts, &|_| None)?;
        return volume_target(format, v, e, opts);
    }
    let mut left_out = None;
    let (points, triangles, encoding) = match format {
        Format::Ply => ply::read_progress(bytes, progress)?,
        Format::Obj => obj::read_progress(bytes, progress)?,
        Format::Stl => stl::read_progress(bytes, progress)?,
        Format::Off => off::read(bytes)?,
        Format::Xyz => xyz::read_progress(bytes, progress)?,
        Format::Pcd => pcd::read_counting(bytes, &mut left_out, progress)?,
        Format::Las => las::read_counting(bytes, &mut left_out, progress)?,
        Format::E57 => e57::read_counting(bytes, &mut left_out, progress)?,
        Format::Ptx => ptx::read_counting(bytes, &mut left_out, progress)?,
        Format::Gltf | Format::Glb => gltf::read(bytes)?,
        Format::Vtk => {
            let ((p, t), _) = vtk::read(bytes)?;
            (p, t, Encoding::Ascii)
        }
        Format::Nifti | Format::Nrrd | Format::Vti | Format::MetaImage => {
            unreachable!("volumes returned above")
        }
    };
    progress.report(READING, 1.0);
    finish(format, points, triangles, encoding, left_out)
}

/// Checks a reader's output into a [`Target`].
fn finish(
    format: Format,
    points: Vec<DVec3>,
    triangles: Vec<[u32; 3]>,
    encoding: Encoding,
    left_out: Option<LeftOut>,
) -> Result<ReadResult, IoError> {
    let format = match (format, encoding) {
        (Format::Gltf | Format::Glb, Encoding::Ascii) => Format::Gltf,
        (Format::Gltf | Format::Glb, _) => Format::Glb,
        (f, _) => f,
    };
    let target = Target::new(points, triangles).map_err(|e| match e {
        TargetError::NonFinite { index, x, y, z } => IoError::NonFinite {
            format,
            at: Location::Byte(0),
            index,
            x,
            y,
            z,
        },
        source => IoError::Target { format, source },
    })?;
    let (target, repairs) = target.repaired();
    Ok(ReadResult {
        target,
        format,
        encoding,
        volume: None,
        repairs,
        left_out,
    })
}

/// Reads a geometry file from disk (native only).
#[cfg(not(target_arch = "wasm32"))]
pub fn read_path(path: impl AsRef<std::path::Path>) -> Result<ReadResult, IoError> {
    read_path_with(path, &VolumeOptions::default())
}

/// Reads a volume from disk without building a target, including detached data: a NIfTI
/// `.hdr` with its `.img` (same stem; `.img.gz` too), an `.nhdr` or `.mhd` with the data file it
/// names (relative to the header's folder).
#[cfg(not(target_arch = "wasm32"))]
pub fn read_volume_path(
    path: impl AsRef<std::path::Path>,
    opts: &VolumeOptions,
) -> Result<(VoxelVolume, Format, Encoding), IoError> {
    let path = path.as_ref();
    let bytes = read_file(path)?;
    let format = detect(&bytes, path.to_str())?;
    let (v, e) = read_volume_file(path, &bytes, format, opts)?;
    Ok((v, format, e))
}

#[cfg(not(target_arch = "wasm32"))]
fn read_file(path: &std::path::Path) -> Result<Vec<u8>, IoError> {
    std::fs::read(path).map_err(|e| IoError::Fs {
        path: path.display().to_string(),
        message: e.to_string(),
    })
}

/// The volume readers with detached files resolved next to `path`.
#[cfg(not(target_arch = "wasm32"))]
fn read_volume_file(
    path: &std::path::Path,
    bytes: &[u8],
    format: Format,
    opts: &VolumeOptions,
) -> Result<(VoxelVolume, Encoding), IoError> {
    let dir = path.parent().map(|d| d.to_path_buf()).unwrap_or_default();
    if format == Format::Nifti && nifti::is_pair_header(bytes) {
        let name = path.file_name().and_then(|n| n.to_str()).unwrap_or("");
        let stem = name
            .strip_suffix(".gz")
            .unwrap_or(name)
            .trim_end_matches(|c| c != '.')
            .trim_end_matches('.');
        let candidates = ["img", "IMG", "img.gz"].map(|e| dir.join(format!("{stem}.{e}")));
        let img_path =
            candidates
                .iter()
                .find(|p| p.is_file())
                .ok_or_else(|| IoError::Unsupported {
                    format,
                    what: format!(
                        "a .hdr header without its data file {}",
                        candidates[0].display()
                    ),
                })?;
        let img = read_file(img_path)?;
        return nifti::read_pair(bytes, &img, opts);
    }
    let resolve = |name: &str| -> Option<Vec<u8>> {
        if name.contains("://") {
            return None;
        }
        std::fs::read(dir.join(name)).ok()
    };
    read_volume_as(bytes, format, opts, &resolve)
}

/// [`read_path`] with volume options (frame, iso-value, inside).
#[cfg(not(target_arch = "wasm32"))]
pub fn read_path_with(
    path: impl AsRef<std::path::Path>,
    opts: &VolumeOptions,
) -> Result<ReadResult, IoError> {
    let path = path.as_ref();
    let bytes = read_file(path)?;
    if let Some((inner, name)) = gunzipped(&bytes, path.to_str())? {
        return read_bytes_with(&inner, name.as_deref(), opts);
    }
    let format = detect(&bytes, path.to_str())?;
    if format.is_volume() {
        let (v, e) = read_volume_file(path, &bytes, format, opts)?;
        return volume_target(format, v, e, opts);
    }
    if format == Format::Gltf {
        // External buffers (`"uri": "mesh.bin"`) are read from the glTF file's folder.
        let dir = path.parent().map(|d| d.to_path_buf()).unwrap_or_default();
        let resolve = |uri: &str| -> Option<Vec<u8>> {
            if uri.contains("://") {
                return None;
            }
            std::fs::read(dir.join(uri.replace("%20", " "))).ok()
        };
        let (points, triangles, encoding) = gltf::read_with(&bytes, &resolve)?;
        return finish(format, points, triangles, encoding, None);
    }
    read_as(&bytes, format)
}

/// The input of every writer: a triangle mesh (or, for formats that allow it, bare points when
/// `triangles` is empty), optional named per-vertex scalars, and the settings used to make it.
#[derive(Clone, Copy, Debug, Default)]
pub struct WriteInput<'a> {
    /// Vertex positions.
    pub positions: &'a [DVec3],
    /// Triangles indexing `positions`, counter-clockwise seen from outside.
    pub triangles: &'a [[u32; 3]],
    /// Named per-vertex scalars, each as long as `positions` (PLY and VTK store them; GLB
    /// stores them as `_NAME` attributes; OBJ and STL cannot and ignore them).
    pub scalars: &'a [(&'a str, &'a [f64])],
    /// The settings that produced the mesh, as JSON, recorded where the format has room for it
    /// (PLY/OBJ comments, GLB `asset.extras`, VTK title when short enough; STL has no room).
    pub settings_json: Option<&'a str>,
}

impl<'a> WriteInput<'a> {
    /// A mesh without scalars or settings.
    pub fn new(positions: &'a [DVec3], triangles: &'a [[u32; 3]]) -> Self {
        Self {
            positions,
            triangles,
            ..Default::default()
        }
    }

    /// Checks indices, scalar lengths and finiteness.
    pub(crate) fn check(&self, format: Format) -> Result<(), IoError> {
        let bad = |what: String| Err(IoError::InvalidInput { format, what });
        let n = self.positions.len();
        if n > i32::MAX as usize {
            return bad(format!("{n} vertices exceed the 2^31 index limit"));
        }
        if let Some(i) = self.positions.iter().position(|p| !p.is_finite()) {
            return bad(format!("vertex {i} has a non-finite coordinate"));
        }
        for (t, tri) in self.triangles.iter().enumerate() {
            if let Some(v) = tri.iter().find(|&&v| v as usize >= n) {
                return bad(format!(
                    "triangle {t} refers to vertex {v}, but there are {n} vertices"
                ));
            }
        }
        for (name, s) in self.scalars {
            if s.len() != n {
                return bad(format!(
                    "scalar \"{name}\" has {} values for {n} vertices",
                    s.len()
                ));
            }
        }
        Ok(())
    }

    /// The settings as one-line JSON (validated), if any.
    pub(crate) fn settings_compact(&self, format: Format) -> Result<Option<String>, IoError> {
        self.settings_value(format)
            .map(|v| v.map(|v| serde_json::to_string(&v).expect("JSON value")))
    }

    /// The settings parsed as JSON, if any.
    pub(crate) fn settings_value(
        &self,
        format: Format,
    ) -> Result<Option<serde_json::Value>, IoError> {
        match self.settings_json {
            None => Ok(None),
            Some(s) => serde_json::from_str(s)
                .map(Some)
                .map_err(|e| IoError::InvalidInput {
                    format,
                    what: format!("settings are not valid JSON: {e}"),
                }),
        }
    }
}

/// Writes a mesh in `format` (OBJ, PLY, STL, GLB or VTK) to bytes.
pub fn write_bytes(format: Format, input: &WriteInput) -> Result<Vec<u8>, IoError> {
    match format {
        Format::Obj => obj::write(input),
        Format::Ply => ply::write(input),
        Format::Stl => stl::write(input),
        Format::Glb => gltf::write_glb(input),
        Format::Vtk => vtk::write(input),
        f => Err(IoError::NotWritable {
            what: format!("{} files", f.info().label),
        }),
    }
}

/// Writes a mesh to a file, choosing the format from the extension (native only).
#[cfg(not(target_arch = "wasm32"))]
pub fn write_path(path: impl AsRef<std::path::Path>, input: &WriteInput) -> Result<(), IoError> {
    let path = path.as_ref();
    let format = path
        .extension()
        .and_then(|e| e.to_str())
        .and_then(Format::from_extension)
        .ok_or_else(|| IoError::NotWritable {
            what: path.display().to_string(),
        })?;
    let bytes = write_bytes(format, input)?;
    std::fs::write(path, bytes).map_err(|e| IoError::Fs {
        path: path.display().to_string(),
        message: e.to_string(),
    })
}
