//! Fuzzes the LAS/LAZ reader (the `las` and `laz` crates behind it): it must return `Ok` or an
//! error, never panic, hang or over-allocate, and on `Ok` its points are finite.
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    if let Ok((points, tris, _)) = lsw::io::las::read(data) {
        assert!(points.iter().all(|p| p.is_finite()));
        assert!(tris.is_empty());
    }
});
