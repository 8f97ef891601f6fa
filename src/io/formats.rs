//! The catalog of file formats: one [`FormatInfo`] per [`Format`] — its name, label, file-name
//! extensions, what it holds, and whether LSW reads and writes it.
//!
//! This is the one list: [`Format::name`], [`Format::from_extension`], [`Format::is_volume`],
//! [`Format::WRITABLE`], the "supported formats" sentences of errors and hints, the CLI's help,
//! the app's catalog (`catalog()` in the wasm facade) and the README check (`tests/catalog.rs`)
//! all derive from [`FORMATS`].

use serde::Serialize;
use std::fmt;
use std::sync::OnceLock;

/// A file format known to `io` (for reading, writing or both).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Format {
    /// Stanford PLY (ASCII, binary little- or big-endian).
    Ply,
    /// Wavefront OBJ.
    Obj,
    /// STL (ASCII or binary).
    Stl,
    /// Object File Format (OFF, COFF, NOFF, CNOFF).
    Off,
    /// Plain point lists: XYZ, PTS, TXT, CSV.
    Xyz,
    /// glTF 2.0 JSON (embedded or data-URI buffers).
    Gltf,
    /// glTF 2.0 binary container.
    Glb,
    /// Legacy VTK polydata (ASCII).
    Vtk,
    /// Point Cloud Library PCD (ASCII, binary, binary_compressed).
    Pcd,
    /// ASPRS LAS lidar points, or LASzip-compressed LAZ.
    Las,
    /// ASTM E57 laser-scan exchange file (every scan, in the common frame).
    E57,
    /// Leica PTX text export of terrestrial scans (every scan, in the common frame).
    Ptx,
    /// NIfTI-1 or NIfTI-2 volume (`.nii`, `.nii.gz`, `.hdr`/`.img`).
    Nifti,
    /// NRRD volume (`.nrrd` attached, `.nhdr` detached).
    Nrrd,
    /// VTK XML ImageData volume (`.vti`).
    Vti,
    /// MetaImage volume (`.mha`, `.mhd` + raw).
    MetaImage,
}

impl Format {
    /// The formats `io::write_bytes` can write (those marked `write` in
    /// [`FORMATS`]).
    pub const WRITABLE: [Format; 5] = WRITABLE;

    /// True for the voxel-volume formats (NIfTI, NRRD, VTI, MetaImage).
    pub fn is_volume(self) -> bool {
        self.info().kind == FormatKind::Volume
    }

    /// Short lower-case name, as printed by `lsw info` and used in error messages.
    pub fn name(self) -> &'static str {
        self.info().name
    }

    /// The format a file extension (without dot, any case) usually means, if any.
    pub fn from_extension(ext: &str) -> Option<Format> {
        let ext = ext.to_ascii_lowercase();
        FORMATS
            .iter()
            .find(|i| i.extensions.contains(&ext.as_str()))
            .map(|i| i.format)
    }
}

impl fmt::Display for Format {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// What a file of a format holds once read.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum FormatKind {
    /// Triangles only (STL).
    Mesh,
    /// Points only (XYZ lists).
    Cloud,
    /// A mesh, or a point cloud when the file has no faces (PLY, OBJ, OFF, glTF, VTK).
    MeshOrCloud,
    /// A voxel volume, wrapped through its iso-surface (NIfTI, NRRD, VTI, MetaImage).
    Volume,
}

/// One format of the catalog.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
pub struct FormatInfo {
    /// The format itself (not serialised: `name` identifies it).
    #[serde(skip)]
    pub format: Format,
    /// Short lower-case name (`lsw info`'s `format`, error messages, the app's export menu).
    pub name: &'static str,
    /// Name for people ("PLY", "glTF", "NIfTI").
    pub label: &'static str,
    /// File-name extensions, lower case and without the dot, the usual one first. A compound
    /// extension (`nii.gz`) matches the end of a file name.
    pub extensions: &'static [&'static str],
    /// What a file holds once read.
    pub kind: FormatKind,
    /// LSW reads it ([`crate::io::read_bytes`]).
    pub read: bool,
    /// LSW writes it ([`crate::io::write_bytes`]).
    pub write: bool,
}

const fn entry(
    format: Format,
    name: &'static str,
    label: &'static str,
    extensions: &'static [&'static str],
    kind: FormatKind,
    write: bool,
) -> FormatInfo {
    FormatInfo {
        format,
        name,
        label,
        extensions,
        kind,
        read: true,
        write,
    }
}

/// Every format, in the order of [`Format`]'s variants (so `FORMATS[format as usize]` is its
/// entry; a unit test checks it).
pub const FORMATS: &[FormatInfo] = {
    use FormatKind::*;
    &[
        entry(Format::Ply, "ply", "PLY", &["ply"], MeshOrCloud, true),
        entry(Format::Obj, "obj", "OBJ", &["obj"], MeshOrCloud, true),
        entry(Format::Stl, "stl", "STL", &["stl"], Mesh, true),
        entry(Format::Off, "off", "OFF", &["off"], MeshOrCloud, false),
        entry(
            Format::Xyz,
            "xyz",
            "XYZ",
            &["xyz", "pts", "txt", "csv", "asc", "pcd_ascii"],
            Cloud,
            false,
        ),
        entry(Format::Gltf, "gltf", "glTF", &["gltf"], MeshOrCloud, false),
        entry(Format::Glb, "glb", "GLB", &["glb"], MeshOrCloud, true),
        entry(Format::Vtk, "vtk", "VTK", &["vtk"], MeshOrCloud, true),
        entry(Format::Pcd, "pcd", "PCD", &["pcd"], Cloud, false),
        entry(Format::Las, "las", "LAS/LAZ", &["las", "laz"], Cloud, false),
        entry(Format::E57, "e57", "E57", &["e57"], Cloud, false),
        entry(Format::Ptx, "ptx", "PTX", &["ptx"], Cloud, false),
        entry(
            Format::Nifti,
            "nifti",
            "NIfTI",
            &["nii", "nii.gz", "hdr"],
            Volume,
            false,
        ),
        entry(
            Format::Nrrd,
            "nrrd",
            "NRRD",
            &["nrrd", "nhdr"],
            Volume,
            false,
        ),
        entry(Format::Vti, "vti", "VTI", &["vti"], Volume, false),
        entry(
            Format::MetaImage,
            "metaimage",
            "MetaImage",
            &["mha", "mhd"],
            Volume,
            false,
        ),
    ]
};

/// The formats with `write` set, in catalog order; `N` must be their count (checked when
/// compiling).
const fn writable<const N: usize>() -> [Format; N] {
    let mut out = [Format::Ply; N];
    let (mut i, mut k) = (0, 0);
    while i < FORMATS.len() {
        if FORMATS[i].write {
            assert!(k < N, "more writable formats than Format::WRITABLE holds");
            out[k] = FORMATS[i].format;
            k += 1;
        }
        i += 1;
    }
    assert!(k == N, "fewer writable formats than Format::WRITABLE holds");
    out
}

/// See [`Format::WRITABLE`].
pub(crate) const WRITABLE: [Format; 5] = writable();

impl Format {
    /// This format's catalog entry.
    pub fn info(self) -> &'static FormatInfo {
        &FORMATS[self as usize]
    }

    /// Every format, in catalog order.
    pub fn all() -> impl Iterator<Item = Format> {
        FORMATS.iter().map(|i| i.format)
    }

    /// The format whose extension ends `file_name` (any case, any path form), preferring the
    /// longest match so `brain.nii.gz` is NIfTI.
    pub fn from_file_name(file_name: &str) -> Option<Format> {
        let name = file_name.to_ascii_lowercase();
        let base = name.rsplit(['/', '\\']).next().unwrap_or(&name);
        FORMATS
            .iter()
            .flat_map(|i| i.extensions.iter().map(move |e| (i.format, *e)))
            .filter(|(_, e)| {
                base.strip_suffix(e)
                    .and_then(|stem| stem.strip_suffix('.'))
                    .is_some_and(|stem| !stem.is_empty())
            })
            .max_by_key(|(_, e)| e.len())
            .map(|(f, _)| f)
    }
}

/// Items joined for a sentence: "a, b, c or d" (`last` is "or" or "and").
pub fn join_list(items: &[&str], last: &str) -> String {
    match items {
        [] => String::new(),
        [one] => (*one).to_owned(),
        [init @ .., tail] => format!("{} {last} {tail}", init.join(", ")),
    }
}

/// The labels of the formats LSW reads: (meshes and clouds, volumes), in catalog order.
pub fn readable_labels() -> (Vec<&'static str>, Vec<&'static str>) {
    let read = FORMATS.iter().filter(|i| i.read);
    let (volumes, geometry): (Vec<_>, Vec<_>) = read.partition(|i| i.kind == FormatKind::Volume);
    let labels = |v: Vec<&FormatInfo>| v.into_iter().map(|i| i.label).collect();
    (labels(geometry), labels(volumes))
}

/// "PLY, OBJ, …, VTK; volumes NIfTI, …, MetaImage": the formats LSW reads, for messages.
pub fn supported_formats() -> &'static str {
    static TEXT: OnceLock<String> = OnceLock::new();
    TEXT.get_or_init(|| {
        let (geometry, volumes) = readable_labels();
        format!("{}; volumes {}", geometry.join(", "), volumes.join(", "))
    })
}

/// "Export the geometry as PLY, …, GLB or VTK, or a volume as NIfTI, …, VTI or MetaImage.":
/// [`IoError::hint`](super::IoError::hint) for an unknown format.
pub fn export_as_hint() -> &'static str {
    static TEXT: OnceLock<String> = OnceLock::new();
    TEXT.get_or_init(|| {
        let (geometry, volumes) = readable_labels();
        format!(
            "Export the geometry as {}, or a volume as {}.",
            join_list(&geometry, "or"),
            join_list(&volumes, "or")
        )
    })
}

/// "Use PLY, …, GLB or VTK, or a NIfTI, …, VTI or MetaImage volume.": the app's hint for an
/// unknown format (see [`crate::error`]).
pub fn use_formats_hint() -> &'static str {
    static TEXT: OnceLock<String> = OnceLock::new();
    TEXT.get_or_init(|| {
        let (geometry, volumes) = readable_labels();
        format!(
            "Use {}, or a {} volume.",
            join_list(&geometry, "or"),
            join_list(&volumes, "or")
        )
    })
}

/// The extensions of the formats LSW writes, dotted: ".ply, .obj, .stl, .glb or .vtk".
pub fn writable_extensions() -> &'static str {
    static TEXT: OnceLock<String> = OnceLock::new();
    TEXT.get_or_init(|| {
        let exts: Vec<String> = FORMATS
            .iter()
            .filter(|i| i.write)
            .map(|i| format!(".{}", i.extensions[0]))
            .collect();
        join_list(&exts.iter().map(String::as_str).collect::<Vec<_>>(), "or")
    })
}

/// "Name the output .ply, .obj, .stl, .glb or .vtk.": the hint for an output LSW cannot write.
pub fn name_output_hint() -> &'static str {
    static TEXT: OnceLock<String> = OnceLock::new();
    TEXT.get_or_init(|| format!("Name the output {}.", writable_extensions()))
}

/// The labels of the formats LSW writes: "PLY, OBJ, STL, GLB or VTK".
pub fn writable_labels() -> &'static str {
    static TEXT: OnceLock<String> = OnceLock::new();
    TEXT.get_or_init(|| {
        let labels: Vec<&str> = FORMATS
            .iter()
            .filter(|i| i.write)
            .map(|i| i.label)
            .collect();
        join_list(&labels, "or")
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::io::detect::{detect, extension};
    use crate::io::IoError;

    #[test]
    fn entries_are_in_variant_order_and_names_match_serde() {
        for (i, info) in FORMATS.iter().enumerate() {
            assert_eq!(info.format as usize, i, "{}", info.name);
            assert_eq!(info.format.info(), info);
            assert_eq!(serde_json::to_value(info.format).unwrap(), info.name);
            assert!(!info.extensions.is_empty() && !info.label.is_empty());
        }
        assert_eq!(Format::all().count(), FORMATS.len());
    }

    /// Every extension leads back to its format: through `from_extension` (for the last
    /// dotted part), `from_file_name` and the sniffer's tie-break on an empty file.
    #[test]
    fn every_extension_round_trips_through_detection() {
        for info in FORMATS {
            for ext in info.extensions {
                let file = format!("dir.v2/Scan.{}", ext.to_ascii_uppercase());
                assert_eq!(Format::from_file_name(&file), Some(info.format), "{file}");
                if !ext.contains('.') {
                    assert_eq!(Format::from_extension(ext), Some(info.format), "{ext}");
                    assert_eq!(extension(&file).as_deref(), Some(*ext));
                }
                assert_eq!(
                    detect(b"", Some(&file)),
                    Err(IoError::Empty {
                        format: Some(info.format)
                    }),
                    "{file}"
                );
            }
        }
        assert_eq!(Format::from_extension("gz"), None);
        assert_eq!(Format::from_file_name(".ply"), None);
        assert_eq!(Format::from_file_name("ply"), None);
        assert_eq!(Format::from_file_name("a.gz"), None);
    }

    #[test]
    fn derived_lists() {
        assert_eq!(
            Format::WRITABLE,
            [
                Format::Ply,
                Format::Obj,
                Format::Stl,
                Format::Glb,
                Format::Vtk
            ]
        );
        assert_eq!(writable_labels(), "PLY, OBJ, STL, GLB or VTK");
        assert_eq!(writable_extensions(), ".ply, .obj, .stl, .glb or .vtk");
        assert_eq!(
            supported_formats(),
            "PLY, OBJ, STL, OFF, XYZ, glTF, GLB, VTK, PCD, LAS/LAZ, E57, PTX; volumes NIfTI, NRRD, VTI, MetaImage"
        );
        assert!(Format::Nrrd.is_volume() && !Format::Xyz.is_volume());
        assert_eq!(join_list(&["a"], "or"), "a");
        assert_eq!(join_list(&["a", "b", "c"], "or"), "a, b or c");
    }
}
