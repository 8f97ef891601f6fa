//! Fuzzes the PTX reader (scan headers with 4 × 4 matrices, grids of point lines): it must return
//! `Ok` or an error, never panic, hang or over-allocate, and on `Ok` its points are finite.
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    if let Ok((points, tris, _)) = lsw::io::ptx::read(data) {
        assert!(points.iter().all(|p| p.is_finite()));
        assert!(tris.is_empty());
    }
});
