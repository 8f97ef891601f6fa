//! The wasm facade as the worker uses it, in headless Chromium (wasm only; natively this file
//! has no tests): the catalog's lists are the ones the session accepts, and core errors arrive
//! as `{code, message, hint}` objects with a code from `lsw::error::CODES`.

#![cfg(target_arch = "wasm32")]

use lsw::wasm::{
    catalog, cloud_creases, export_mesh, preset_settings, McfSession, VolumeView, WrapSession,
};
use wasm_bindgen::JsValue;
use wasm_bindgen_test::*;

wasm_bindgen_test_configure!(run_in_browser);

fn get(o: &JsValue, key: &str) -> JsValue {
    js_sys::Reflect::get(o, &JsValue::from_str(key)).unwrap()
}

/// The error object's code (checked to be one of the fixed set) and hint.
fn code_and_hint(e: JsValue) -> (String, String) {
    let code = get(&e, "code").as_string().unwrap();
    assert!(lsw::error::CODES.contains(&code.as_str()), "{code}");
    assert!(!get(&e, "message").as_string().unwrap().is_empty());
    (code, get(&e, "hint").as_string().unwrap())
}

#[wasm_bindgen_test]
fn catalog_lists_what_the_session_accepts() {
    let c: serde_json::Value = serde_json::from_str(&catalog()).unwrap();
    let bytes = lsw::wasm::demo_shape("genus2").unwrap().to_vec();
    let mut s =
        WrapSession::new(&bytes, Some("genus2.ply".into()), r#"{"steps": 2}"#, None).unwrap();
    s.step(1).unwrap();
    let n = s.positions().length() / 3;
    for m in c["colourMaps"].as_array().unwrap() {
        let name = m["name"].as_str().unwrap();
        assert_eq!(s.scalar(name).unwrap().length(), n, "{name}");
    }
    for f in c["exportFormats"].as_array().unwrap() {
        let name = f.as_str().unwrap();
        assert!(s.export(name).unwrap().length() > 0, "{name}");
        let (p, i) = (s.positions().to_vec(), s.indices().to_vec());
        assert!(export_mesh(&p, &i, name).unwrap().length() > 0, "{name}");
    }
    for p in c["presets"].as_array().unwrap() {
        assert!(preset_settings(p.as_str().unwrap()).is_ok());
    }
    let (code, hint) = code_and_hint(s.scalar("nope").unwrap_err());
    assert_eq!(code, "bad-parameter");
    assert!(
        hint.contains("distance") && hint.contains("features"),
        "{hint}"
    );
    let (code, hint) = code_and_hint(s.export("off").unwrap_err());
    assert_eq!(code, "bad-parameter");
    assert!(hint.contains("GLB"), "{hint}");
    let h = s.kappa_histogram(10, 3.0).unwrap();
    assert_eq!(js_sys::Array::from(&get(&h, "counts")).length(), 10);
    assert!(s.field_slice(3, 0.5).is_err());
    let iso = s.field_isosurface(0.0).unwrap();
    assert!(js_sys::Float32Array::from(get(&iso, "positions")).length() > 0);
}

/// A cloud too large for the browser's memory is refused at once, saying how to wrap it
/// (building one here would take the 4 GB it lacks, so the check is called as the session does).
#[wasm_bindgen_test]
fn a_cloud_too_large_for_the_browser_is_refused_with_a_way_out() {
    use lsw::wasm::session::{check_cloud_size, MAX_CLOUD_POINTS};
    assert!(check_cloud_size(MAX_CLOUD_POINTS).is_ok());
    let (code, hint) = code_and_hint(check_cloud_size(20_000_000).unwrap_err().into());
    assert_eq!(code, "too-large");
    assert!(hint.contains("lsw wrap"), "{hint}");
}

/// The app wraps a volume from the copy of its voxels that the page's view holds: the same
/// surface, step for step, as from a second read of the bytes.
#[wasm_bindgen_test]
fn a_volume_wraps_the_same_from_its_view_as_from_its_bytes() {
    let bytes = lsw::wasm::phantom_volume(40).to_vec();
    let view = VolumeView::new(&bytes, Some("phantom.nii".into()), 0).unwrap();
    let settings = r#"{"steps": 6}"#;
    let name = Some("phantom.nii".to_string());
    let mut read = WrapSession::with_volume(&bytes, name, settings, None, 0, false, None).unwrap();
    let mut held = WrapSession::from_volume_view(&view, settings, None, false, None).unwrap();
    assert_eq!(
        read.target_positions().to_vec(),
        held.target_positions().to_vec()
    );
    read.step(6).unwrap();
    held.step(6).unwrap();
    assert!(read.positions().length() > 0);
    assert_eq!(read.positions().to_vec(), held.positions().to_vec());
    assert_eq!(read.result_hash(), held.result_hash());
}

/// A cloud's crease job goes out as numbers and its result comes back once: the page's helper
/// worker calls `cloudCreases` on what `creaseJob` gives, the session takes it with
/// `setCreases`; anything else is refused with a `bad-parameter` error.
#[wasm_bindgen_test]
fn a_crease_job_goes_out_and_its_result_comes_back_once() {
    let bytes = lsw::wasm::demo_shape("noisy-sphere").unwrap().to_vec();
    let mut s = WrapSession::new(&bytes, None, r#"{"steps": 2}"#, None).unwrap();
    let job = s
        .crease_job()
        .expect("a cloud's creases are left to the fit");
    let creases = cloud_creases(&job).unwrap().to_vec();
    // A sphere has none.
    assert_eq!(creases, vec![0.0, 0.0]);
    assert_eq!(
        code_and_hint(s.set_creases(&[1.0]).unwrap_err()).0,
        "bad-parameter"
    );
    assert!(s.set_creases(&creases).unwrap());
    assert!(s.crease_job().is_none());
    assert!(!s.set_creases(&creases).unwrap());
    // (radius, angle, count, points in cell order, their indices)
    let one = [0.1, 0.7, 1.0, 0.0, 0.0, 0.0, 0.0];
    assert_eq!(
        cloud_creases(&js_sys::Float64Array::from(&one[..]))
            .unwrap()
            .to_vec(),
        [0.0, 0.0]
    );
    for bad in [
        &[][..],
        &one[..6],
        &[0.1, 0.7, 1.5, 0.0, 0.0, 0.0, 0.0],
        &[0.1, f64::NAN, 1.0, 0.0, 0.0, 0.0, 0.0],
        &[0.1, 0.7, 1.0, 0.0, f64::INFINITY, 0.0, 0.0],
        &[0.1, 0.7, 1.0, 0.0, 0.0, 0.0, 1.0],
        &[0.0, 0.7, 1.0, 0.0, 0.0, 0.0, 0.0],
    ] {
        assert_eq!(
            code_and_hint(cloud_creases(&js_sys::Float64Array::from(bad)).unwrap_err()).0,
            "bad-parameter"
        );
    }
    // A mesh's creases come with the target: no job.
    let bytes = lsw::wasm::demo_shape("genus2").unwrap().to_vec();
    let s = WrapSession::new(&bytes, Some("genus2.ply".into()), "{}", None).unwrap();
    assert!(s.crease_job().is_none());
}

#[wasm_bindgen_test]
fn core_errors_arrive_with_code_and_hint() {
    let e = WrapSession::new(b"hello\n", None, "{}", None)
        .err()
        .unwrap();
    let (code, hint) = code_and_hint(e);
    assert_eq!(code, "bad-file");
    assert!(hint.contains("MetaImage"), "{hint}");
    let e = McfSession::new(3, 1.0, -1.0).err().unwrap();
    assert_eq!(code_and_hint(e).0, "bad-parameter");
    let e = McfSession::new(9, 1.0, 1e-4).err().unwrap();
    assert_eq!(code_and_hint(e).0, "bad-parameter");
    let e = lsw::wasm::demo_shape("nope").unwrap_err();
    assert_eq!(code_and_hint(e).1, "Use noisy-sphere, genus2 or box-soup.");
    let e = preset_settings("nope").unwrap_err();
    assert!(code_and_hint(e).1.contains("full-wrap"));
    let bytes = lsw::wasm::demo_shape("noisy-sphere").unwrap().to_vec();
    let e = WrapSession::new(&bytes, None, r#"{"tau": "fast"}"#, None)
        .err()
        .unwrap();
    assert_eq!(code_and_hint(e).0, "bad-parameter");
}

#[wasm_bindgen_test]
fn the_lesson_colours_by_its_maps_and_stops_before_the_sphere_vanishes() {
    let c: serde_json::Value = serde_json::from_str(&catalog()).unwrap();
    let mut m = McfSession::new(3, 1.0, 0.01).unwrap();
    let n = m.positions().length() / 3;
    for name in c["lessonColourMaps"].as_array().unwrap() {
        let name = name.as_str().unwrap();
        assert_eq!(m.scalar(name).unwrap().length(), n, "{name}");
    }
    assert_eq!(
        code_and_hint(m.scalar("distance").unwrap_err()).0,
        "bad-parameter"
    );
    let advice = m.tau_advice().unwrap();
    assert_eq!(get(&advice, "sensible").as_bool(), Some(false));
    assert!(get(&advice, "warning")
        .as_string()
        .unwrap()
        .contains("r0²/4"));
    // τ = 0.01: 25 steps would reach t* = 0.25; the lesson takes 24 and then refuses.
    assert_eq!(m.steps_left(), 24);
    m.step(24).unwrap();
    assert_eq!(m.steps_left(), 0);
    let (code, hint) = code_and_hint(m.step(1).unwrap_err());
    assert_eq!(code, "bad-parameter");
    assert!(hint.contains("smaller time step"), "{hint}");
}

#[wasm_bindgen_test]
fn the_mesh_lesson_flows_a_loaded_mesh_and_refuses_bad_ones() {
    // An icosphere handed over as flat arrays, as the worker hands over a loaded mesh.
    let m = lsw::geometry::icosphere::icosphere(3, 1.0, lsw::DVec3::ZERO).unwrap();
    let p: Vec<f32> = m
        .positions()
        .iter()
        .flat_map(|v| [v.x as f32, v.y as f32, v.z as f32])
        .collect();
    let i: Vec<u32> = m.triangles().concat();
    let mut s = McfSession::from_mesh(&p, &i, 2e-5).unwrap();
    assert_eq!(s.lesson(), "mesh");
    assert_eq!(s.steps_left(), 200);
    let advice = s.tau_advice().unwrap();
    assert_eq!(get(&advice, "sensible").as_bool(), Some(true));
    assert_eq!(get(&advice, "horizon").as_f64(), Some(0.004));
    let c: serde_json::Value = serde_json::from_str(&catalog()).unwrap();
    for name in c["lessonColourMaps"].as_array().unwrap() {
        let name = name.as_str().unwrap();
        assert_eq!(
            s.scalar(name).unwrap().length() as usize,
            p.len() / 3,
            "{name}"
        );
    }
    let area = |s: &McfSession| get(&s.stats().unwrap(), "areaRatio").as_f64().unwrap();
    let mut last = area(&s);
    assert_eq!(last, 1.0);
    for _ in 0..10 {
        s.step(5).unwrap();
        let a = area(&s);
        assert!(a < last, "area ratio {last} → {a}");
        last = a;
    }
    let st = s.stats().unwrap();
    assert_eq!(get(&st, "lesson").as_string().unwrap(), "mesh");
    assert_eq!(get(&st, "step").as_f64(), Some(50.0));
    assert!(get(&st, "volumeRatio").as_f64().unwrap() < 1.0);
    assert!(get(&st, "meanAbsH").as_f64().unwrap() > 1.0);
    assert_eq!(s.steps_left(), 150);
    // Open meshes have no volume: null, not undefined.
    let half: Vec<u32> = m
        .triangles()
        .into_iter()
        .filter(|t| t.iter().all(|&v| m.position(v).z > -1e-9))
        .flatten()
        .collect();
    let open = McfSession::from_mesh(&p, &half, 5e-5).unwrap();
    assert!(get(&open.stats().unwrap(), "volume").is_null());
    // Bad input: typed errors with a code and a hint, never a panic.
    let e = McfSession::from_mesh(&[], &[], 5e-5).err().unwrap();
    assert_eq!(code_and_hint(e).0, "bad-target");
    let mut nan = p.clone();
    nan[4] = f32::NAN;
    let e = McfSession::from_mesh(&nan, &i, 5e-5).err().unwrap();
    assert_eq!(code_and_hint(e).0, "bad-target");
    let mut three = i.clone();
    three.extend([i[0], i[1], 5]);
    let (code, hint) = code_and_hint(McfSession::from_mesh(&p, &three, 5e-5).err().unwrap());
    assert_eq!(code, "bad-target");
    assert!(hint.contains("manifold"), "{hint}");
    let e = McfSession::from_mesh(&p, &i, -1.0).err().unwrap();
    assert_eq!(code_and_hint(e).0, "bad-parameter");
}
