//! Fuzzes the E57 reader behind its checksums: every page of an E57 file carries a CRC, so
//! mutated files rarely get past the first page (the `e57` target). Here the input edits the XML
//! section of a valid file of two scans (Cartesian scaled integers with an invalid-state column;
//! spherical floats with a pose), and the file is written with correct checksums around it:
//! counts, offsets, types, limits and poses reach the reader. Each 3 input bytes set one XML
//! byte (2 bytes of position, 1 of value). The reader must return `Ok` or an error, never panic,
//! hang or over-allocate, and on `Ok` its points are finite.
#![no_main]

use e57::{Record, RecordDataType, RecordName, RecordValue};
use libfuzzer_sys::fuzz_target;
use std::io::Cursor;

fn file(edit: &[u8]) -> Option<Vec<u8>> {
    let mut out = Cursor::new(Vec::new());
    let mut w = e57::E57Writer::new(&mut out, "fuzz").ok()?;
    let scaled = |name| Record {
        name,
        data_type: RecordDataType::ScaledInteger { min: -1000, max: 1000, scale: 0.01, offset: 0.5 },
    };
    let proto = vec![
        scaled(RecordName::CartesianX),
        scaled(RecordName::CartesianY),
        scaled(RecordName::CartesianZ),
        Record::CARTESIAN_INVALID_STATE,
    ];
    let mut a = w.add_pointcloud("a", proto).ok()?;
    for i in 0..40i64 {
        let v = |c: i64| RecordValue::ScaledInteger(c);
        a.add_point(vec![v(i), v(-i), v(i * 3 % 7), RecordValue::Integer(i % 3)]).ok()?;
    }
    a.finalize().ok()?;
    let proto = vec![
        Record::SPHERICAL_AZIMUTH_F64,
        Record::SPHERICAL_ELEVATION_F32,
        Record::SPHERICAL_RANGE_F64,
    ];
    let mut b = w.add_pointcloud("b", proto).ok()?;
    b.set_transform(Some(e57::Transform::default()));
    for i in 0..30 {
        let t = i as f64 * 0.2;
        b.add_point(vec![RecordValue::Double(t), RecordValue::Single(0.1), RecordValue::Double(1.0 + t)])
            .ok()?;
    }
    b.finalize().ok()?;
    let edit = edit.to_vec();
    w.finalize_customized_xml(move |xml| {
        let mut x = xml.into_bytes();
        for e in edit.chunks_exact(3) {
            let at = u16::from_le_bytes([e[0], e[1]]) as usize % x.len().max(1);
            x[at] = e[2];
        }
        Ok(String::from_utf8_lossy(&x).into_owned())
    })
    .ok()?;
    drop(w);
    Some(out.into_inner())
}

fuzz_target!(|data: &[u8]| {
    if let Some(bytes) = file(data) {
        if let Ok((points, tris, _)) = lsw::io::e57::read(&bytes) {
            assert!(points.iter().all(|p| p.is_finite()));
            assert!(tris.is_empty());
        }
    }
});
