//! The volume part of the facade: a [`VolumeView`] of dropped volume bytes for the app's
//! histogram, slices and marching-cubes preview; [`WrapSession::with_volume`] to wrap a chosen
//! iso-value and frame; the procedural phantom as NIfTI bytes. Conversions only; the work is in
//! [`crate::io::volume`].

use super::errors::{ui_error, UiError};
use super::{index_array, set_key, to_js, vec3_array, WrapSession};
use crate::io::{Format, Inside, VolumeOptions, VoxelVolume};
use js_sys::{Float32Array, Float64Array};
use serde::Serialize;
use wasm_bindgen::prelude::*;

fn options(iso: Option<f64>, frame: u32, dark: bool) -> VolumeOptions {
    VolumeOptions {
        frame: frame as usize,
        iso,
        inside: if dark { Inside::Dark } else { Inside::Bright },
        array: None,
    }
}

/// A voxel volume's facts (`VolumeView.info`).
#[derive(Serialize, Debug, Clone, tsify::Tsify)]
#[serde(rename_all = "camelCase")]
pub struct VolumeInfo {
    /// The format's short name (see [`Format::name`]).
    pub format: &'static str,
    /// Voxel counts (nx, ny, nz) and the voxel size in mm.
    pub dims: [usize; 3],
    pub voxel_size: [f64; 3],
    /// The sample type stored in the file.
    pub datatype: &'static str,
    /// The range of the values (0, 0 when none is finite).
    pub min: f64,
    pub max: f64,
    /// The world frame, in words.
    pub frame: String,
    /// The volume read (0-based) of the file's `frames`.
    pub frame_index: usize,
    pub frames: usize,
    /// Otsu's threshold, when the values have one.
    pub otsu: Option<f64>,
    /// Index → world (mm), 16 numbers, row-major.
    pub affine: Vec<f64>,
}

/// A voxel volume read from bytes (NIfTI, NRRD, VTI, MetaImage), kept for viewing.
#[wasm_bindgen]
pub struct VolumeView {
    volume: VoxelVolume,
    format: Format,
    encoding: crate::io::Encoding,
}

#[wasm_bindgen]
impl VolumeView {
    /// Reads volume bytes (`file_name` breaks format ties); `frame` picks a volume of a 4-D file.
    #[wasm_bindgen(constructor)]
    pub fn new(bytes: &[u8], file_name: Option<String>, frame: u32) -> Result<VolumeView, JsValue> {
        let (volume, format, encoding) =
            crate::io::read_volume_bytes(bytes, file_name.as_deref(), &options(None, frame, false))
                .map_err(ui_error)?;
        Ok(VolumeView {
            volume,
            format,
            encoding,
        })
    }

    /// The volume's facts (see [`VolumeInfo`]).
    pub fn info(&self) -> Result<JsValue, JsValue> {
        let v = &self.volume;
        let (min, max) = v.value_range().unwrap_or((0.0, 0.0));
        to_js(&VolumeInfo {
            format: self.format.name(),
            dims: v.dims,
            voxel_size: v.voxel_size(),
            datatype: v.datatype.name(),
            min,
            max,
            frame: v.frame.clone(),
            frame_index: v.frame_index,
            frames: v.frames,
            otsu: v.otsu(),
            affine: v.affine_rows().concat(),
        })
    }

    /// `{min, max, counts}` with `counts` a Float64Array of `bins` equal bins.
    pub fn histogram(&self, bins: u32) -> Result<js_sys::Object, JsValue> {
        let h =
            crate::io::volume::histogram(&self.volume.values, bins as usize).ok_or_else(|| {
                UiError {
                    code: "bad-file",
                    message: "the volume has no finite value".into(),
                    hint: "The volume holds only NaN or infinite values.".into(),
                }
            })?;
        let counts: Vec<f64> = h.counts.iter().map(|&c| c as f64).collect();
        let obj = js_sys::Object::new();
        set_key(&obj, "min", &JsValue::from(h.min))?;
        set_key(&obj, "max", &JsValue::from(h.max))?;
        set_key(&obj, "counts", &Float64Array::from(counts.as_slice()))?;
        Ok(obj)
    }

    /// The slice of voxel values normal to index axis `axis` (0, 1, 2) at `index`, the lower
    /// remaining axis fastest (empty when out of range).
    pub fn slice(&self, axis: u32, index: u32) -> Float32Array {
        Float32Array::from(self.volume.slice(axis as usize, index as usize).as_slice())
    }

    /// The marching-cubes preview of {v = iso}: `{positions, indices}` in world mm.
    pub fn isosurface(&self, iso: f64, dark: bool) -> Result<js_sys::Object, JsValue> {
        let inside = if dark { Inside::Dark } else { Inside::Bright };
        let (pos, tris) = self.volume.isosurface(iso, inside);
        let obj = js_sys::Object::new();
        set_key(&obj, "positions", &vec3_array(&pos))?;
        set_key(&obj, "indices", &index_array(&tris))?;
        Ok(obj)
    }
}

#[wasm_bindgen]
impl WrapSession {
    /// Like the constructor, for volume bytes: wraps the iso-surface at `iso` (Otsu's threshold
    /// when undefined) of volume `frame`, inside darker than `iso` when `dark`; `progress` as
    /// in the constructor.
    #[wasm_bindgen(js_name = withVolume)]
    pub fn with_volume(
        bytes: &[u8],
        file_name: Option<String>,
        settings_json: &str,
        iso: Option<f64>,
        frame: u32,
        dark: bool,
        progress: Option<js_sys::Function>,
    ) -> Result<WrapSession, JsValue> {
        let read =
            crate::io::read_bytes_with(bytes, file_name.as_deref(), &options(iso, frame, dark))
                .map_err(ui_error)?;
        WrapSession::prepare(read, settings_json, progress)
    }

    /// [`WrapSession::with_volume`] for the volume `view` already holds (its frame): no second
    /// read of the bytes and no second copy of the voxels (a large volume's second copy would
    /// take memory the browser's 4 GiB cannot spare). The same target, so the same wrap.
    #[wasm_bindgen(js_name = fromVolumeView)]
    pub fn from_volume_view(
        view: &VolumeView,
        settings_json: &str,
        iso: Option<f64>,
        dark: bool,
        progress: Option<js_sys::Function>,
    ) -> Result<WrapSession, JsValue> {
        let opts = options(iso, view.volume.frame_index as u32, dark);
        let (target, _, _) =
            crate::io::volume_surface(view.format, &view.volume, &opts).map_err(ui_error)?;
        let read = crate::io::ReadResult {
            target,
            format: view.format,
            encoding: view.encoding,
            volume: None,
            repairs: None,
            left_out: None,
        };
        WrapSession::prepare(read, settings_json, progress)
    }
}

/// The procedural head phantom (see [`crate::demo::phantom`]) with `n` voxels along x, as NIfTI
/// bytes, so the gallery entry goes through the same reader as a dropped file.
#[wasm_bindgen(js_name = phantomVolume)]
pub fn phantom_volume(n: u32) -> js_sys::Uint8Array {
    let v = crate::demo::phantom::phantom_volume(n as usize);
    js_sys::Uint8Array::from(crate::io::nifti::write(&v).as_slice())
}
