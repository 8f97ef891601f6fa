//! Fuzzes format detection plus every reader behind `read_bytes`, with and without a file name.
#![no_main]

use libfuzzer_sys::fuzz_target;

const NAMES: [Option<&str>; 9] = [
    None,
    Some("a.ply"),
    Some("a.obj"),
    Some("a.stl"),
    Some("a.off"),
    Some("a.xyz"),
    Some("a.gltf"),
    Some("a.glb"),
    Some("a.vtk"),
];

fuzz_target!(|data: &[u8]| {
    let (name, data) = match data.split_first() {
        Some((&k, rest)) => (NAMES[k as usize % NAMES.len()], rest),
        None => (None, data),
    };
    if let Ok(r) = lsw::io::read_bytes(data, name) {
        let t = r.target;
        assert!(!t.points.is_empty());
        assert!(t.points.iter().all(|p| p.is_finite()));
    }
});
