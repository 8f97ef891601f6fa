//! Results as files: a session's surface ([`WrapSession::export`], with the colour maps that
//! are exported and the settings) and a mesh the page kept ([`export_mesh`]).

use super::errors::{ui_error, UiError};
use super::{points_from_flat, triangles_from_flat, WrapSession};
use crate::io::{formats, Format, WriteInput};
use js_sys::Uint8Array;
use wasm_bindgen::prelude::*;

/// The writable format `name` ("obj", "ply", "stl", "glb", "vtk"; see [`formats::FORMATS`]).
fn export_format(name: &str) -> Result<Format, UiError> {
    Format::from_extension(name)
        .filter(|f| f.info().write)
        .ok_or_else(|| {
            UiError::bad_parameter(
                format!("cannot export as \"{name}\""),
                format!("Choose {}.", formats::writable_labels()),
            )
        })
}

/// `input` written as `format`, as bytes for the page.
pub(super) fn file_bytes(format: Format, input: &WriteInput) -> Result<Uint8Array, JsValue> {
    let bytes = crate::io::write_bytes(format, input).map_err(ui_error)?;
    Ok(Uint8Array::from(bytes.as_slice()))
}

#[wasm_bindgen]
impl WrapSession {
    /// The result as a file: "obj", "ply", "stl", "glb" or "vtk" (PLY, GLB and VTK carry the
    /// exported colour maps — distance, mean curvature, κ — per vertex; PLY, OBJ, GLB and VTK
    /// record the settings).
    pub fn export(&self, format: &str) -> Result<Uint8Array, JsValue> {
        let fmt = export_format(format)?;
        let (positions, triangles) = (
            self.run.evolver().positions(),
            self.run.evolver().triangles(),
        );
        let values = self.run.export_scalars(self.finished());
        let scalars: Vec<(&str, &[f64])> = values.iter().map(|(n, v)| (*n, v.as_slice())).collect();
        file_bytes(
            fmt,
            &WriteInput {
                positions: &positions,
                triangles: &triangles,
                scalars: &scalars,
                settings_json: Some(&self.settings_json),
            },
        )
    }
}

/// A mesh held by the page (flat positions and indices) written as "obj", "ply", "stl", "glb" or
/// "vtk": exports a kept result after its session is gone.
#[wasm_bindgen(js_name = exportMesh)]
pub fn export_mesh(
    positions: &[f32],
    indices: &[u32],
    format: &str,
) -> Result<Uint8Array, JsValue> {
    let fmt = export_format(format)?;
    let (points, triangles) = (points_from_flat(positions), triangles_from_flat(indices));
    file_bytes(fmt, &WriteInput::new(&points, &triangles))
}
