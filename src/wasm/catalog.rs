//! The lists the app offers, exported once from their Rust sources: file formats
//! ([`crate::io::formats::FORMATS`]), colour maps ([`crate::flow::colour::COLOUR_MAPS`]),
//! presets ([`crate::flow::Preset::ALL`]) and export formats; and a preset's settings.

use super::errors::UiError;
use crate::flow::{Preset, COLOUR_MAPS};
use crate::io::{Format, FORMATS};
use wasm_bindgen::prelude::*;

/// The catalog as JSON: `{formats, colourMaps, presets, exportFormats}`.
///
/// * `formats`: `[{name, label, extensions, kind, read, write}]` — every format LSW knows;
///   `kind` is "mesh", "cloud", "mesh-or-cloud" or "volume"; extensions without the dot, the
///   usual one first (`nii.gz` is one extension).
/// * `colourMaps`: `[{name, label, legend, unit, exportName}]` — the names `scalar()` takes;
///   `exportName` is the per-vertex property name in exported files, or null.
/// * `presets`: preset names in menu order (see `presetSettings`).
/// * `exportFormats`: names of the formats `export` and `exportMesh` write.
pub fn catalog_json() -> serde_json::Value {
    serde_json::json!({
        "formats": FORMATS,
        "colourMaps": COLOUR_MAPS,
        "presets": Preset::ALL.map(Preset::name),
        "exportFormats": Format::WRITABLE.map(Format::name),
    })
}

/// The catalog of the app's lists as a JSON string (see [`catalog_json`]; the TypeScript type is
/// `Catalog` in `www/src/protocol.ts`).
#[wasm_bindgen(js_name = catalog)]
pub fn catalog() -> String {
    catalog_json().to_string()
}

/// The default settings of a preset ("full-wrap", "obstacle", "isosurface", "mcf") as JSON.
#[wasm_bindgen(js_name = presetSettings)]
pub fn preset_settings(name: &str) -> Result<String, JsValue> {
    let p = Preset::from_name(name)
        .ok_or_else(|| UiError::unknown("unknown preset", name, &Preset::ALL.map(Preset::name)))?;
    Ok(serde_json::to_string(&p.settings()).unwrap_or_default())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn catalog_lists_every_format_map_and_preset() {
        let c = catalog_json();
        let formats = c["formats"].as_array().unwrap();
        assert_eq!(formats.len(), FORMATS.len());
        assert_eq!(formats[0]["name"], "ply");
        assert_eq!(formats[0]["kind"], "mesh-or-cloud");
        let nifti = formats.iter().find(|f| f["name"] == "nifti").unwrap();
        assert_eq!(nifti["extensions"][1], "nii.gz");
        assert_eq!(
            (nifti["read"].as_bool(), nifti["write"].as_bool()),
            (Some(true), Some(false))
        );
        let maps: Vec<&str> = c["colourMaps"]
            .as_array()
            .unwrap()
            .iter()
            .map(|m| m["name"].as_str().unwrap())
            .collect();
        assert_eq!(
            maps,
            ["distance", "curvature", "kappa", "covolume", "features"]
        );
        assert_eq!(c["colourMaps"][1]["exportName"], "mean_curvature");
        assert_eq!(c["presets"][0], "full-wrap");
        assert_eq!(c["presets"].as_array().unwrap().len(), Preset::ALL.len());
        assert_eq!(
            c["exportFormats"],
            serde_json::json!(["ply", "obj", "stl", "glb", "vtk"])
        );
    }
}
