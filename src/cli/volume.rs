//! The volume flags shared by `lsw info`, `lsw sdf` and `lsw wrap` (`--iso`, `--frame`,
//! `--dark-inside`, `--isosurface-out`), and the `volume` block of their JSON. Kept in one file so
//! the subcommands only flatten the flags in and add one JSON key.

use crate::io::{Inside, ReadResult, VolumeOptions, VolumeRead, WriteInput};
use serde_json::{json, Value};
use std::path::PathBuf;

/// Flags for voxel-volume inputs (NIfTI, NRRD, VTI, MetaImage); ignored for meshes and clouds.
#[derive(clap::Args, Debug, Clone, Default)]
pub struct VolumeArgs {
    /// Iso-value of the surface to wrap, in the volume's value units (default: Otsu's threshold).
    #[arg(long)]
    pub iso: Option<f64>,
    /// Which volume of a 4-D file (0-based).
    #[arg(long, default_value_t = 0)]
    pub frame: usize,
    /// The structure is darker than the iso-value (default: brighter).
    #[arg(long)]
    pub dark_inside: bool,
    /// Point array of a VTI file (default: the active scalars, else the first).
    #[arg(long)]
    pub array: Option<String>,
    /// Write the volume's iso-surface (the target mesh, world mm) to this mesh file.
    #[arg(long)]
    pub isosurface_out: Option<PathBuf>,
}

impl VolumeArgs {
    /// The reader options these flags ask for.
    pub fn options(&self) -> VolumeOptions {
        VolumeOptions {
            frame: self.frame,
            iso: self.iso,
            inside: if self.dark_inside {
                Inside::Dark
            } else {
                Inside::Bright
            },
            array: self.array.clone(),
        }
    }

    /// Writes the iso-surface if `--isosurface-out` was given and the input is a volume.
    pub fn write_isosurface(&self, read: &ReadResult) -> Result<(), String> {
        if let (Some(path), Some(_)) = (&self.isosurface_out, &read.volume) {
            let t = &read.target;
            crate::io::write_path(path, &WriteInput::new(&t.points, &t.triangles))
                .map_err(super::explained)?;
        }
        Ok(())
    }
}

/// The `volume` JSON block: dims, voxel_size (mm), datatype, value_range [min, max], frame (the
/// world frame in words), frame_index, frames, affine (row-major 4×4, index → world mm), iso,
/// iso_source ("otsu" or "option"), otsu, inside ("bright" or "dark").
pub fn volume_json(v: &VolumeRead) -> Value {
    let vol = &v.volume;
    json!({
        "dims": vol.dims,
        "voxel_size": vol.voxel_size(),
        "datatype": vol.datatype.name(),
        "value_range": vol.value_range().map(|(a, b)| [a, b]),
        "frame": vol.frame,
        "frame_index": vol.frame_index,
        "frames": vol.frames,
        "affine": vol.affine_rows(),
        "iso": v.iso,
        "iso_source": v.iso_source,
        "otsu": vol.otsu(),
        "inside": v.inside,
    })
}
