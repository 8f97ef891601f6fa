//! Fuzzes the obj reader: it must return `Ok` or an error, never panic, hang or over-allocate,
//! and on `Ok` its output must satisfy the `Target` invariants.
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    if let Ok((points, tris, _)) = lsw::io::obj::read(data) {
        assert!(points.iter().all(|p| p.is_finite()));
        assert!(tris.iter().flatten().all(|&i| (i as usize) < points.len()));
    }
});
