//! The demo gallery, control curves and settings documentation for the browser app.
//! Gallery data comes back as PLY bytes, so it goes through the same reader as a dropped file.

use super::errors::{ui_error, UiError};
use super::io::file_bytes;
use super::{points_from_flat, to_js, triangles_from_flat};
use crate::flow::WrapSettings;
use crate::io::{Format, WriteInput};
use glam::DVec3;
use js_sys::Uint8Array;
use wasm_bindgen::prelude::*;

/// PLY bytes of points (+ triangles), as the worker feeds to `WrapSession::new`.
fn ply_bytes(points: &[DVec3], triangles: &[[u32; 3]]) -> Result<Uint8Array, JsValue> {
    file_bytes(Format::Ply, &WriteInput::new(points, triangles))
}

/// A procedural demo shape ("noisy-sphere", "genus2", "box-soup") as PLY bytes.
#[wasm_bindgen(js_name = demoShape)]
pub fn demo_shape(name: &str) -> Result<Uint8Array, JsValue> {
    let (points, triangles) = crate::demo::shape(name).map_err(ui_error)?;
    ply_bytes(&points, &triangles)
}

/// A mesh given as flat positions and triangle indices, as PLY bytes; with `samples > 0`, a
/// point cloud (no normals) of that many points sampled uniformly by area (seeded).
#[wasm_bindgen(js_name = demoMesh)]
pub fn demo_mesh(
    positions: &[f32],
    indices: &[u32],
    samples: u32,
    seed: u32,
) -> Result<Uint8Array, JsValue> {
    let (points, triangles) = (points_from_flat(positions), triangles_from_flat(indices));
    if samples > 0 {
        let cloud = crate::demo::sample_mesh(&points, &triangles, samples as usize, seed as u64)
            .map_err(ui_error)?;
        ply_bytes(&cloud, &[])
    } else {
        ply_bytes(&points, &triangles)
    }
}

/// ε(δ) and η(δ) (cos θ = 1 and 0) of the settings in `settings_json`, sampled at `n` points:
/// `{delta, epsilon, eta_facing, eta_side}`.
#[wasm_bindgen(js_name = controlCurves)]
pub fn control_curves(settings_json: &str, n: u32) -> Result<JsValue, JsValue> {
    let settings = WrapSettings::from_json(settings_json).map_err(UiError::settings)?;
    to_js(&crate::demo::control_curves(&settings, n as usize))
}
