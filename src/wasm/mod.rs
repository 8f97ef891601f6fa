//! The `#[wasm_bindgen]` facade: converts typed arrays to core types and back, and core errors
//! to `{code, message, hint}` objects. It holds no algorithm; everything here delegates to the
//! core. By concern:
//!
//! * [`errors`] — [`UiError`] and the one conversion from any core error ([`ui_error`]);
//! * [`session`] — [`WrapSession`], a wrap advanced step by step from the worker; [`field`] its
//!   view of the distance field, [`io`] its result as a file (and [`export_mesh`]),
//!   [`creases`] a cloud's crease detection in a helper worker ([`cloud_creases`]);
//! * [`mcf`] — [`McfSession`], the mean-curvature-flow lesson;
//! * [`demo`] — gallery shapes and meshes, control curves;
//! * [`catalog`] — the lists the app offers ([`catalog()`]), the presets' settings and the
//!   settings' docs, options and old keys;
//! * [`volume`] — [`VolumeView`] and wrapping volumes.
//!
//! The exported names, `js_name`s and return shapes are the app's interface (`www/src/worker.ts`,
//! `www/src/protocol.ts`): add, never rename.

pub mod catalog;
pub mod creases;
pub mod demo;
pub mod errors;
pub mod field;
pub mod io;
pub mod mcf;
pub mod session;
pub mod volume;

pub use catalog::{catalog, preset_settings, setting_aliases, settings_docs, settings_enums};
pub use creases::cloud_creases;
pub use demo::{control_curves, demo_mesh, demo_shape};
pub use errors::{ui_error, UiError};
pub use io::export_mesh;
pub use mcf::{McfSession, McfStats, MeshLessonStats};
pub use session::WrapSession;
pub use volume::{phantom_volume, VolumeView};

use glam::DVec3;
use js_sys::{Float32Array, Uint32Array};
use wasm_bindgen::prelude::*;

/// Installs a panic hook that logs Rust panics to the console (they should never happen).
#[wasm_bindgen(start)]
pub fn start() {
    console_error_panic_hook::set_once();
}

/// Flat `Float32Array` of 3-vectors (x0, y0, z0, x1, …).
fn vec3_array(v: &[DVec3]) -> Float32Array {
    let flat: Vec<f32> = v
        .iter()
        .flat_map(|p| [p.x as f32, p.y as f32, p.z as f32])
        .collect();
    Float32Array::from(flat.as_slice())
}

/// Flat `Uint32Array` of triangles (a0, b0, c0, a1, …).
fn index_array(triangles: &[[u32; 3]]) -> Uint32Array {
    Uint32Array::from(triangles.as_flattened())
}

/// Flat `Float32Array` of scalars.
fn scalar_array(values: &[f64]) -> Float32Array {
    let flat: Vec<f32> = values.iter().map(|&x| x as f32).collect();
    Float32Array::from(flat.as_slice())
}

/// Flat f32 triples → points (a trailing partial triple is ignored).
fn points_from_flat(flat: &[f32]) -> Vec<DVec3> {
    flat.chunks_exact(3)
        .map(|c| DVec3::new(c[0] as f64, c[1] as f64, c[2] as f64))
        .collect()
}

/// Flat u32 triples → triangles (a trailing partial triple is ignored).
fn triangles_from_flat(flat: &[u32]) -> Vec<[u32; 3]> {
    flat.chunks_exact(3).map(|c| [c[0], c[1], c[2]]).collect()
}

/// Sets `key` on `obj` (a fresh plain object, so this cannot fail in practice).
fn set_key(obj: &js_sys::Object, key: &str, value: &JsValue) -> Result<(), JsValue> {
    js_sys::Reflect::set(obj, &JsValue::from_str(key), value).map(|_| ())
}

/// `value` as a plain JS object (serde field names).
fn to_js<T: serde::Serialize + ?Sized>(value: &T) -> Result<JsValue, JsValue> {
    serde_wasm_bindgen::to_value(value).map_err(|e| JsValue::from_str(&e.to_string()))
}
