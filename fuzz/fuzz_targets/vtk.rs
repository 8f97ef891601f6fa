//! Fuzzes the legacy VTK reader: `Ok` or an error, never a panic; on `Ok` the invariants hold.
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    if let Ok(((points, tris), scalars)) = lsw::io::vtk::read(data) {
        assert!(points.iter().all(|p| p.is_finite()));
        assert!(tris.iter().flatten().all(|&i| (i as usize) < points.len()));
        assert!(scalars.iter().all(|(_, s)| s.len() == points.len()));
    }
});
