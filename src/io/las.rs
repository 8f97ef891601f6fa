//! LAS 1.0–1.4 and LAZ (LASzip-compressed LAS): the ASPRS lidar format, also what many
//! terrestrial and handheld scanners export. The points' x, y, z are read (scaled and offset as
//! the header says), except those the file itself rules out: points flagged withheld (the format
//! says to treat them as deleted) and points classified as noise (class 7, "low point (noise)",
//! and 18, "high noise"), which a scanner's or an operator's cleaning marked. Every other class
//! (ground included) is wrapped; intensity, colour and returns are ignored.
//!
//! Read through the `las` crate (with `laz` for LAZ, both pure Rust): LAZ is an arithmetic-coded
//! format with a dozen point layouts and versions, which is no place for a hand-written decoder.
//! The crate reads from an owned cursor, so the file's bytes are copied once (LAS is ≈ 30 bytes
//! a point, LAZ ≈ 7); the points are decoded in chunks, so a header that overstates its count
//! costs no more memory than the points that are there.

use super::error::{Format, IoError, Location};
use super::{Encoding, LeftOut, RawGeometry, READING};
use crate::progress::Progress;
use glam::DVec3;
use std::io::Cursor;

const F: Format = Format::Las;

/// Bytes of point records decoded at a time: the crate reserves a chunk's records before
/// decoding them, and a record may be up to 64 KiB long (extra bytes), so the chunk is counted
/// in bytes (counted in records, a corrupt file could ask for gigabytes).
const CHUNK_BYTES: u64 = 1 << 22;

/// True when `bytes` start with LAS's file signature (LAZ files have it too).
pub fn sniff(bytes: &[u8]) -> bool {
    bytes.starts_with(b"LASF")
}

/// The crate's error as ours: a file cut short is truncated, LASzip's own errors are corrupt
/// compressed data, the rest (signature, version, header fields) is the file's syntax.
fn error(e: las::Error, bytes: &[u8], what: &str) -> IoError {
    match e {
        las::Error::Io(io) | las::Error::LasZipError(laz::LasZipError::IoError(io))
            if io.kind() == std::io::ErrorKind::UnexpectedEof =>
        {
            IoError::truncated(F, Location::Byte(bytes.len()), what)
        }
        las::Error::LasZipError(z) => IoError::Decompress {
            format: F,
            at: Location::Byte(0),
            message: z.to_string(),
        },
        e => IoError::syntax(F, Location::Byte(0), what, e.to_string()),
    }
}

/// Little-endian reads at byte offsets of the file, `None` past its end.
fn u32_at(bytes: &[u8], o: usize) -> Option<u32> {
    let b = bytes.get(o..o.checked_add(4)?)?;
    <[u8; 4]>::try_from(b).ok().map(u32::from_le_bytes)
}

fn u64_at(bytes: &[u8], o: usize) -> Option<u64> {
    let b = bytes.get(o..o.checked_add(8)?)?;
    <[u8; 8]>::try_from(b).ok().map(u64::from_le_bytes)
}

/// Refuses counts the file cannot hold before the crate sees them (each would be a panic or a
/// reservation of gigabytes in the crate):
/// - the point count times the record length, which the crate computes, must fit 64 bits, and
///   an uncompressed file must hold that many bytes;
/// - the first extended VLR's 64-bit length, reserved before reading it, must fit;
/// - a LAZ chunk table's count, reserved before reading the table, must not exceed the
///   file's bytes (each chunk takes at least one).
///
/// Fields as the public header stores them: offset to the point data at byte 96, point format
/// at 104, record length at 105, legacy point count at 107; LAS 1.4's 64-bit count at 247 (used
/// when the legacy one is 0, as the crate does). A file cut before its points is left for the
/// crate to refuse: it says where.
fn check_counts(bytes: &[u8]) -> Result<(), IoError> {
    let too_large = |at: usize, element: &str, count: u64, needed: u128| IoError::CountTooLarge {
        format: F,
        at: Location::Byte(at),
        element: element.into(),
        count,
        available: bytes.len(),
        needed,
    };
    let (Some(&format), Some(&[lo, hi]), Some(legacy), Some(start)) = (
        bytes.get(104),
        bytes.get(105..107),
        u32_at(bytes, 107),
        u32_at(bytes, 96).map(u64::from),
    ) else {
        return Ok(());
    };
    let record = u16::from_le_bytes([lo, hi]) as u128;
    let minor = bytes.get(25).copied().unwrap_or(0);
    let count = match u64_at(bytes, 247) {
        Some(n) if minor >= 4 && legacy == 0 => n,
        _ => legacy as u64,
    };
    // Bit 7 of the point format marks LASzip data (as the las crate reads it).
    let compressed = format & 0x80 != 0;
    let needed = count as u128 * record;
    if needed > u64::MAX as u128 {
        return Err(too_large(107, "points", count, needed));
    }
    // LAS 1.4's first extended VLR (the one the crate reads): it reserves the record's length,
    // a 64-bit field, before reading it. Its header is 60 bytes, the length at byte 20 of it.
    if let (true, Some(first), Some(n)) = (minor >= 4, u64_at(bytes, 235), u32_at(bytes, 243)) {
        let length = usize::try_from(first)
            .ok()
            .and_then(|f| u64_at(bytes, f.checked_add(20)?).map(|l| (f, l)));
        if let (true, Some((at, length))) = (first > 0 && n > 0, length) {
            let needed = at as u128 + 60 + length as u128;
            if needed > bytes.len() as u128 {
                return Err(too_large(
                    at + 20,
                    "bytes of an extended VLR",
                    length,
                    needed,
                ));
            }
        }
    }
    if start > bytes.len() as u64 {
        return Ok(());
    }
    if !compressed && needed > bytes.len() as u128 {
        return Err(too_large(107, "points", count, needed));
    }
    if !compressed {
        return Ok(());
    }
    // The chunk table's offset is at the start of the point data, or, where the writer could
    // not seek back, in the file's last 8 bytes; each chunk takes at least a byte of the file.
    // (An offset past what `usize` holds, in wasm's 32 bits, is past the file: the crate says so.)
    let offset = |t: u64| {
        usize::try_from(t)
            .ok()
            .filter(|_| t > start && t < i64::MAX as u64)
    };
    let table = match u64_at(bytes, start as usize) {
        Some(t) if offset(t).is_some() => t as usize,
        Some(_) => match u64_at(bytes, bytes.len().saturating_sub(8)).and_then(offset) {
            Some(t) => t,
            None => return check_laszip(bytes, start, count),
        },
        None => return check_laszip(bytes, start, count),
    };
    match u32_at(bytes, table.saturating_add(4)) {
        Some(chunks) if chunks as usize > bytes.len() => Err(too_large(
            table + 4,
            "LASzip chunks",
            chunks as u64,
            chunks as u128,
        )),
        _ => check_laszip(bytes, start, count),
    }
}

/// The LASzip VLR's data (user "laszip encoded", record 22204), found as the crate finds it:
/// VLRs follow the header (its stated size at byte 94, but never before the end of the fields
/// of its version: 227, 235 or 375 bytes; their number at byte 100), each a 54-byte header (its
/// data length at byte 20) and its data.
fn laszip_vlr(bytes: &[u8]) -> Option<&[u8]> {
    let size = bytes.get(94..96)?;
    let fields = match (*bytes.get(24)?, *bytes.get(25)?) {
        v if v <= (1, 2) => 227,
        (1, 3) => 235,
        _ => 375,
    };
    let mut at = (u16::from_le_bytes([size[0], size[1]]) as usize).max(fields);
    for _ in 0..u32_at(bytes, 100)? {
        let head = bytes.get(at..at.checked_add(54)?)?;
        let len = u16::from_le_bytes([head[20], head[21]]) as usize;
        let data = bytes.get(at + 54..at + 54 + len)?;
        if head[2..18].starts_with(b"laszip encoded") && head[18..20] == 22204u16.to_le_bytes() {
            return Some(data);
        }
        at += 54 + len;
    }
    None
}

/// Refuses a LASzip description the laz crate would panic on (a panic is a crash
/// of the CLI and a trap in the browser): one with no items (the crate `expect`s one), and, for
/// variable-size chunks, a chunk table that holds fewer points than the header counts (the
/// crate indexes the table past its end). What the crate cannot parse is left for it to report.
fn check_laszip(bytes: &[u8], start: u64, count: u64) -> Result<(), IoError> {
    let Some(laz_vlr) = laszip_vlr(bytes).and_then(|d| laz::LazVlr::from_buffer(d).ok()) else {
        return Ok(());
    };
    if laz_vlr.items().is_empty() {
        return Err(IoError::syntax(
            F,
            Location::Byte(0),
            "a LASzip record that lists the point's fields",
            "one that lists none",
        ));
    }
    if !laz_vlr.uses_variable_size_chunks() {
        return Ok(());
    }
    let mut data = Cursor::new(bytes);
    data.set_position(start);
    let Ok(table) = laz::laszip::ChunkTable::read_from(&mut data, &laz_vlr) else {
        return Ok(());
    };
    let held = table
        .as_ref()
        .iter()
        .fold(0u64, |n, e| n.saturating_add(e.point_count));
    if held < count {
        return Err(IoError::syntax(
            F,
            Location::Byte(start as usize),
            format!("a LASzip chunk table for the header's {count} points"),
            format!("one for {held}"),
        ));
    }
    Ok(())
}

/// True for a point the file rules out: flagged withheld, or classified as noise (7 or 18).
/// The withheld flag is bit 7 of byte 15 in the legacy formats 0–5 and bit 2 of byte 15 in the
/// extended formats 6–10.
#[inline]
fn ruled_out(class: u8, record: &[u8], extended: bool) -> bool {
    let withheld = match record.get(15) {
        Some(f) if extended => f & 0b100 != 0,
        Some(f) => f & 0x80 != 0,
        None => false,
    };
    withheld || class == 7 || class == 18
}

/// Reads a LAS or LAZ file.
pub fn read(bytes: &[u8]) -> Result<RawGeometry, IoError> {
    read_counting(bytes, &mut None, &mut Progress::none())
}

/// [`read`], setting `left_out` to the withheld and noise points it skipped and reporting the
/// share of points read to `progress`.
pub fn read_counting(
    bytes: &[u8],
    left_out: &mut Option<LeftOut>,
    progress: &mut Progress,
) -> Result<RawGeometry, IoError> {
    check_counts(bytes)?;
    guarded(|| decode(bytes, left_out, progress))
}

/// Runs the crates' decoding, natively turning a panic into an error. The laz crate's
/// arithmetic decoder indexes its models with decoded symbols, so corrupt compressed data can
/// panic it deep inside (which no check of the header can foresee).
/// Natively the CLI then says the data is corrupt instead of crashing (the panic's own message
/// still goes to stderr: the process's panic hook is left alone). In wasm a panic cannot be
/// caught: the worker traps and the app reports it and restarts the worker.
fn guarded<T>(f: impl FnOnce() -> Result<T, IoError>) -> Result<T, IoError> {
    #[cfg(not(target_arch = "wasm32"))]
    {
        std::panic::catch_unwind(std::panic::AssertUnwindSafe(f)).unwrap_or_else(|_| {
            Err(IoError::Decompress {
                format: F,
                at: Location::Byte(0),
                message: "the LASzip decoder stopped on it (a panic in the laz crate)".into(),
            })
        })
    }
    #[cfg(target_arch = "wasm32")]
    f()
}

/// Decodes the points of a LAS or LAZ file whose header counts passed [`check_counts`].
fn decode(
    bytes: &[u8],
    left_out: &mut Option<LeftOut>,
    progress: &mut Progress,
) -> Result<RawGeometry, IoError> {
    let mut reader = las::Reader::new(Cursor::new(bytes.to_vec())).map_err(|e| {
        error(
            e,
            bytes,
            "a LAS 1.0–1.4 header (for LAZ also its LASzip record and chunk table)",
        )
    })?;
    let header = reader.header();
    let count = header.number_of_points();
    let mut points = Vec::with_capacity(count.min(bytes.len() as u64 / 8) as usize);
    let mut data = las::PointDataBuilder::new()
        .for_header(reader.header())
        .build();
    let extended = header.point_format().is_extended;
    let record = u64::from(header.point_format().len());
    let mut read = 0u64;
    while read < count {
        progress.report(READING, read as f64 / count as f64);
        let want = (CHUNK_BYTES / record.max(1)).clamp(1, count - read);
        let got = reader.fill_points(want, &mut data).map_err(|e| {
            error(
                e,
                bytes,
                &format!(
                    "{count} point records (the header's count), read {}",
                    points.len()
                ),
            )
        })?;
        if got == 0 {
            return Err(IoError::truncated(
                F,
                Location::Byte(bytes.len()),
                format!(
                    "{count} point records (the header's count), found {}",
                    points.len()
                ),
            ));
        }
        let flags = data.raw_bytes().chunks_exact(data.record_len().max(1));
        for (((x, y), z), (class, rec)) in data
            .x()
            .zip(data.y())
            .zip(data.z())
            .zip(data.classification().zip(flags))
        {
            read += 1;
            if ruled_out(class, rec, extended) {
                continue;
            }
            let p = DVec3::new(x, y, z);
            if !p.is_finite() {
                return Err(IoError::NonFinite {
                    format: F,
                    at: Location::Byte(0),
                    index: read as usize - 1,
                    x,
                    y,
                    z,
                });
            }
            points.push(p);
        }
    }
    let left = (read as usize).saturating_sub(points.len());
    let left = (
        left,
        "points flagged withheld or classified as noise (7, 18)",
    );
    let points = LeftOut::kept(F, Location::Byte(0), points, left, left_out)?;
    Ok((points, Vec::new(), Encoding::BinaryLe))
}

#[cfg(test)]
mod tests {
    use super::*;
    use las::{Builder, Point, Writer};

    fn file(points: &[DVec3], laz: bool) -> Vec<u8> {
        file_with(points, laz, 0, |_| Point::default())
    }

    /// A LAS 1.4 file of point format `format`; `point(i)` gives each point's other fields.
    fn file_with(
        points: &[DVec3],
        laz: bool,
        format: u8,
        point: impl Fn(usize) -> Point,
    ) -> Vec<u8> {
        let mut b = Builder::from((1, 4));
        b.point_format = las::point::Format::new(format).unwrap();
        b.point_format.is_compressed = laz;
        b.transforms = las::Vector {
            x: las::Transform {
                scale: 0.001,
                offset: 500_000.0,
            },
            y: las::Transform {
                scale: 0.001,
                offset: 4_000_000.0,
            },
            z: las::Transform {
                scale: 0.001,
                offset: 0.0,
            },
        };
        let mut w = Writer::new(Cursor::new(Vec::new()), b.into_header().unwrap()).unwrap();
        let f = las::point::Format::new(format).unwrap();
        for (i, p) in points.iter().enumerate() {
            let mut q = Point {
                x: p.x,
                y: p.y,
                z: p.z,
                ..point(i)
            };
            q.gps_time = f.has_gps_time.then_some(i as f64);
            q.color = f.has_color.then(|| las::Color::new(1, 2, 3));
            w.write_point(q).unwrap();
        }
        w.close().unwrap();
        w.into_inner().unwrap().into_inner()
    }

    fn cloud(n: usize) -> Vec<DVec3> {
        (0..n)
            .map(|i| {
                let t = i as f64 * 0.37;
                DVec3::new(
                    500_000.0 + crate::fmath::cos(t),
                    4_000_000.0 + crate::fmath::sin(t),
                    i as f64 * 0.001,
                )
            })
            .collect()
    }

    /// Georeferenced coordinates (5 × 10⁵, 4 × 10⁶) come back to the file's millimetre.
    #[test]
    fn las_and_laz_give_the_points_back() {
        let c = cloud(250_000); // more than one chunk (4 MiB of 20-byte records)
        for laz in [false, true] {
            let bytes = file(&c, laz);
            assert!(sniff(&bytes));
            let (p, t, e) = read(&bytes).unwrap();
            assert_eq!((p.len(), t.len(), e), (c.len(), 0, Encoding::BinaryLe));
            let worst = p.iter().zip(&c).map(|(a, b)| (*a - *b).abs().max_element());
            assert!(worst.fold(0.0, f64::max) <= 0.0005 + 1e-9, "laz {laz}");
        }
    }

    /// Withheld and noise points are left out, in the legacy and the extended layouts.
    #[test]
    fn withheld_and_noise_points_are_left_out() {
        use las::point::Classification as C;
        let c = cloud(40);
        let point = |i: usize| Point {
            classification: [C::Ground, C::LowPoint, C::HighNoise, C::Building][i % 4],
            is_withheld: i % 5 == 0,
            ..Default::default()
        };
        let kept: Vec<DVec3> = (0..40)
            .filter(|i| i % 4 != 1 && i % 4 != 2 && i % 5 != 0)
            .map(|i| c[i])
            .collect();
        for (format, laz) in [(0, false), (1, true), (6, false), (7, true)] {
            let mut left_out = None;
            let (p, _, _) = read_counting(
                &file_with(&c, laz, format, point),
                &mut left_out,
                &mut Progress::none(),
            )
            .unwrap();
            assert_eq!(left_out.map(|l| l.points), Some(40 - kept.len()));
            assert_eq!(p.len(), kept.len(), "format {format}");
            let worst = p
                .iter()
                .zip(&kept)
                .map(|(a, b)| (*a - *b).abs().max_element());
            assert!(
                worst.fold(0.0, f64::max) <= 0.0005 + 1e-9,
                "format {format}"
            );
        }
        let noise = |_| Point {
            classification: C::LowPoint,
            ..Default::default()
        };
        let err = read(&file_with(&c, false, 0, noise)).unwrap_err();
        assert!(
            err.to_string().contains("noise (7, 18) and no other point"),
            "{err}"
        );
    }

    #[test]
    fn damaged_files_are_errors_not_panics() {
        for laz in [false, true] {
            let bytes = file(&cloud(300), laz);
            for cut in (0..bytes.len()).step_by(7) {
                assert!(read(&bytes[..cut]).is_err(), "laz {laz}, cut at {cut}");
            }
            // Flipped bytes in the point data: an error or some points, never a panic.
            for at in (400..bytes.len()).step_by(13) {
                let mut b = bytes.clone();
                b[at] ^= 0x5a;
                let _ = read(&b);
            }
        }
        // A chunk table that claims 4 × 10⁹ chunks.
        let mut chunks = file(&cloud(300), true);
        let start = u32::from_le_bytes(chunks[96..100].try_into().unwrap()) as usize;
        let table = i64::from_le_bytes(chunks[start..start + 8].try_into().unwrap()) as usize;
        chunks[table + 4..table + 8].copy_from_slice(&u32::MAX.to_le_bytes());
        let err = read(&chunks).unwrap_err();
        assert!(
            err.to_string().contains("4294967295 LASzip chunks"),
            "{err}"
        );
        // A LAZ point count whose byte size overflows 64 bits (the crate multiplies them: a
        // panic with debug assertions).
        let mut huge = file(&cloud(3), true);
        huge[107..111].copy_from_slice(&0u32.to_le_bytes());
        huge[247..255].copy_from_slice(&(1u64 << 62).to_le_bytes());
        assert!(matches!(read(&huge), Err(IoError::CountTooLarge { .. })));
        // An extended VLR that claims 2⁴⁰ bytes.
        let mut evlr = file(&cloud(3), false);
        let at = evlr.len() as u64;
        evlr[235..243].copy_from_slice(&at.to_le_bytes());
        evlr[243..247].copy_from_slice(&1u32.to_le_bytes());
        evlr.extend([0u8; 20]);
        evlr.extend((1u64 << 40).to_le_bytes());
        evlr.extend([0u8; 32]);
        let err = read(&evlr).unwrap_err();
        assert!(
            err.to_string().contains("bytes of an extended VLR"),
            "{err}"
        );
        let mut big = file(&cloud(3), false);
        big[107..111].copy_from_slice(&u32::MAX.to_le_bytes()); // legacy point count
        big[247..255].copy_from_slice(&u64::MAX.to_le_bytes()); // 1.4 point count
        assert!(matches!(read(&big), Err(IoError::CountTooLarge { .. })));
    }
}
