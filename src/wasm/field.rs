//! Viewing the distance field of a [`WrapSession`]: a plane of nodes or an
//! isosurface, in the target's units (see [`crate::field::slice::FieldView`]).

use super::errors::UiError;
use super::{index_array, set_key, vec3_array, WrapSession};
use crate::field::slice::FieldView;
use js_sys::Float32Array;
use wasm_bindgen::prelude::*;

impl WrapSession {
    /// The session's field (built in the stabilised frame) seen in the target's units.
    fn field_view(&self) -> FieldView<'_> {
        FieldView::new(
            self.run.evolver().field(),
            self.target.bbox.center(),
            self.run.evolver().scale(),
        )
    }
}

#[wasm_bindgen]
impl WrapSession {
    /// The plane of field nodes normal to `axis` (0 = x, 1 = y, 2 = z) nearest to the fraction
    /// `t` ∈ [0, 1] along that axis: `{axis, index, width, height, coordinate, corners, values}`;
    /// `corners` (Float32Array of 4 positions: (u₀,v₀), (u₁,v₀), (u₁,v₁), (u₀,v₁)) and the
    /// plane's `coordinate` are in target units, `values` (Float32Array, u fastest, see
    /// [`crate::field::slice`]) are distances in target units.
    #[wasm_bindgen(js_name = fieldSlice)]
    pub fn field_slice(&self, axis: u32, t: f64) -> Result<js_sys::Object, JsValue> {
        let plane = self.field_view().plane(axis as usize, t).ok_or_else(|| {
            UiError::bad_parameter(
                format!("no field slice for axis {axis} at {t}"),
                "Use axis 0, 1 or 2 (x, y, z) and a position between 0 and 1.",
            )
        })?;
        let values: Vec<f32> = plane.values.iter().map(|&d| d as f32).collect();
        let obj = js_sys::Object::new();
        set_key(&obj, "axis", &JsValue::from(plane.axis as u32))?;
        set_key(&obj, "index", &JsValue::from(plane.index as u32))?;
        set_key(&obj, "width", &JsValue::from(plane.width as u32))?;
        set_key(&obj, "height", &JsValue::from(plane.height as u32))?;
        set_key(
            &obj,
            "coordinate",
            &JsValue::from(plane.corners[0][plane.axis]),
        )?;
        set_key(&obj, "corners", &vec3_array(&plane.corners))?;
        set_key(&obj, "values", &Float32Array::from(values.as_slice()))?;
        Ok(obj)
    }

    /// The isosurface d = `level` of the field (target units; for unsigned fields at least half
    /// a cell): `{level, positions, indices}` with positions in target units.
    #[wasm_bindgen(js_name = fieldIsosurface)]
    pub fn field_isosurface(&self, level: f64) -> Result<js_sys::Object, JsValue> {
        let iso = self.field_view().isosurface(level).ok_or_else(|| {
            UiError::bad_parameter(
                format!("isosurface level {level} is not a number"),
                "Give a finite level in the target's units.",
            )
        })?;
        let obj = js_sys::Object::new();
        set_key(&obj, "level", &JsValue::from(iso.level))?;
        set_key(&obj, "positions", &vec3_array(&iso.positions))?;
        set_key(&obj, "indices", &index_array(&iso.triangles))?;
        Ok(obj)
    }
}
