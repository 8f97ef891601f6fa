//! The catalog's lists for the page (see [`crate::catalog`]), and a preset's settings.

use super::errors::UiError;
use crate::flow::Preset;
use wasm_bindgen::prelude::*;

/// The doc comment of every settings field, as a JSON object keyed by the field's path in the
/// settings JSON (`flow.tau`, `field.band_cells`, …).
#[wasm_bindgen(js_name = settingsDocs)]
pub fn settings_docs() -> String {
    crate::catalog::settings_docs()
}

/// The options of every enum-valued settings field, as a JSON object keyed by the field's path.
#[wasm_bindgen(js_name = settingsEnums)]
pub fn settings_enums() -> String {
    crate::catalog::settings_enums()
}

/// The old flat settings keys (down to the leaves) with their current nested keys, as a JSON
/// object: share links made before the settings were nested still decode.
#[wasm_bindgen(js_name = settingAliases)]
pub fn setting_aliases() -> String {
    crate::catalog::setting_aliases()
}

/// The catalog of the app's lists as a JSON string (see [`crate::catalog::catalog_json`]; the TypeScript type is
/// `Catalog` in `www/src/protocol.ts`).
#[wasm_bindgen(js_name = catalog)]
pub fn catalog() -> String {
    crate::catalog::catalog_json().to_string()
}

/// The default settings of a preset ("full-wrap", "obstacle", "isosurface", "mcf") as JSON.
#[wasm_bindgen(js_name = presetSettings)]
pub fn preset_settings(name: &str) -> Result<String, JsValue> {
    let p = Preset::from_name(name)
        .ok_or_else(|| UiError::unknown("unknown preset", name, &Preset::ALL.map(Preset::name)))?;
    Ok(serde_json::to_string(&p.settings()).unwrap_or_default())
}

/// The legend's range `[lo, hi]` for `values` of the colour map called `name` (see
/// [`crate::flow::ColourMap::display_range`]): the page colours by it and shows it, and decides
/// nothing about it.
#[wasm_bindgen(js_name = colourRange)]
pub fn colour_range(name: &str, values: &[f32]) -> Result<Vec<f64>, JsValue> {
    let map = crate::flow::ColourMap::from_name(name).ok_or_else(|| {
        let names: Vec<&str> = crate::flow::ColourMap::all().map(|m| m.name()).collect();
        UiError::unknown("unknown colour map", name, &names)
    })?;
    let values: Vec<f64> = values.iter().map(|&v| f64::from(v)).collect();
    Ok(map.display_range(&values).to_vec())
}
