//! PCD, the Point Cloud Library's format (v0.5–0.7): a text header (`FIELDS`, `SIZE`, `TYPE`,
//! `COUNT`, `WIDTH`, `HEIGHT`, `POINTS`, `DATA`) followed by `ascii`, `binary` (one record per
//! point) or `binary_compressed` data (LZF-compressed, one array per field).
//!
//! Only `x`, `y`, `z` are read (any numeric type); colours, normals and other fields are skipped.
//! Points with a NaN or infinite coordinate are left out, not refused: an organized cloud (a depth
//! camera's image, `HEIGHT` > 1) marks its pixels without a measurement that way. `VIEWPOINT` is
//! the sensor's pose, not a transform of the points (PCL does not apply it either), so it is
//! ignored.
//!
//! Hand-written: the format is small, its binary records are read in place from the input slice,
//! and the counts are checked against the bytes that follow before anything is allocated. The
//! LZF decompressor is here too (30 lines, every access bounds-checked): the crate of that name is
//! deprecated and wraps no more than this.

use super::error::{Format, IoError, Location};
use super::text::{parse_f64, parse_i64, show, words, Lines};
use super::{Encoding, LeftOut, RawGeometry, READING};
use crate::progress::Progress;
use glam::DVec3;

const F: Format = Format::Pcd;

/// True when `bytes` start like a PCD header: its comment line, or (after comments) `VERSION` or
/// `FIELDS`.
pub fn sniff(bytes: &[u8]) -> bool {
    if bytes.starts_with(b"# .PCD") {
        return true;
    }
    let head = &bytes[..bytes.len().min(4096)];
    for (_, line) in Lines::new(head, 0, 1) {
        let line = line.trim_ascii();
        if line.is_empty() || line.starts_with(b"#") {
            continue;
        }
        let first = words(line).next().unwrap_or(b"");
        return first == b"VERSION" || first == b"FIELDS";
    }
    false
}

/// A field's scalar type: `TYPE` letter and `SIZE` in bytes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Scalar {
    F32,
    F64,
    I8,
    I16,
    I32,
    I64,
    U8,
    U16,
    U32,
    U64,
}

impl Scalar {
    fn new(kind: &[u8], size: u64) -> Option<Scalar> {
        Some(match (kind, size) {
            (b"F", 4) => Scalar::F32,
            (b"F", 8) => Scalar::F64,
            (b"I", 1) => Scalar::I8,
            (b"I", 2) => Scalar::I16,
            (b"I", 4) => Scalar::I32,
            (b"I", 8) => Scalar::I64,
            (b"U", 1) => Scalar::U8,
            (b"U", 2) => Scalar::U16,
            (b"U", 4) => Scalar::U32,
            (b"U", 8) => Scalar::U64,
            _ => return None,
        })
    }

    /// The little-endian value at the start of `b` (which holds at least the type's size).
    #[inline(always)]
    fn get(self, b: &[u8]) -> f64 {
        macro_rules! rd {
            ($t:ty, $n:expr) => {{
                let mut a = [0u8; $n];
                a.copy_from_slice(&b[..$n]);
                <$t>::from_le_bytes(a) as f64
            }};
        }
        match self {
            Scalar::F32 => rd!(f32, 4),
            Scalar::F64 => rd!(f64, 8),
            Scalar::I8 => b[0] as i8 as f64,
            Scalar::I16 => rd!(i16, 2),
            Scalar::I32 => rd!(i32, 4),
            Scalar::I64 => rd!(i64, 8),
            Scalar::U8 => b[0] as f64,
            Scalar::U16 => rd!(u16, 2),
            Scalar::U32 => rd!(u32, 4),
            Scalar::U64 => rd!(u64, 8),
        }
    }
}

/// How the points follow the header.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Data {
    Ascii,
    Binary,
    BinaryCompressed,
}

/// The header's layout of one point.
struct Header {
    /// Per field: bytes per value and values per point (`SIZE`, `COUNT`).
    size_count: Vec<(u64, u64)>,
    /// Index of the `x`, `y`, `z` fields and their types.
    xyz: [(usize, Scalar); 3],
    /// The point count, and as the header states it (in messages: `usize` is 32 bits in wasm).
    points: usize,
    declared: u64,
    data: Data,
    /// Byte offset of the first point and the line it starts on.
    start: usize,
    line: usize,
}

impl Header {
    /// Bytes of one binary record (64-bit and saturating: a header may claim anything, and
    /// `usize` is 32 bits in wasm; the record is checked against the data before it is used).
    fn record(&self) -> u64 {
        self.offset(self.size_count.len())
    }

    /// Byte offset of field `f` within a binary record (and of its array, per point, in a
    /// compressed block).
    fn offset(&self, f: usize) -> u64 {
        let sizes = self.size_count[..f].iter().map(|(s, c)| s * c);
        sizes.fold(0, u64::saturating_add)
    }

    /// Index of field `f`'s first value among a text line's values.
    fn column(&self, f: usize) -> usize {
        let counts = self.size_count[..f].iter().map(|&(_, c)| c as usize);
        counts.fold(0, usize::saturating_add)
    }
}

fn bad(line: usize, expected: impl Into<String>, found: &[u8]) -> IoError {
    IoError::syntax(F, Location::Line(line), expected, show(found))
}

/// The numbers after a header keyword.
fn numbers(line: usize, key: &str, values: &[&[u8]]) -> Result<Vec<u64>, IoError> {
    values
        .iter()
        .map(|v| {
            parse_i64(v)
                .and_then(|n| u64::try_from(n).ok())
                .ok_or_else(|| bad(line, format!("a count or size after {key}"), v))
        })
        .collect()
}

fn header(bytes: &[u8]) -> Result<Header, IoError> {
    let mut fields: Option<Vec<&[u8]>> = None;
    let (mut sizes, mut types, mut counts) = (None, None, None);
    let (mut width, mut height, mut points) = (None, None, None);
    let mut lines = Lines::new(bytes, 0, 1);
    let mut last = 1;
    while let Some((n, line)) = lines.next() {
        last = n;
        let line = match line.iter().position(|&b| b == b'#') {
            Some(i) => &line[..i],
            None => line,
        };
        let mut w = words(line);
        let Some(key) = w.next() else { continue };
        let values: Vec<&[u8]> = w.collect();
        let one = |what: &str| -> Result<u64, IoError> {
            match values.as_slice() {
                [v] => numbers(n, what, &[v]).map(|v| v[0]),
                _ => Err(bad(n, format!("one number after {what}"), line)),
            }
        };
        match key {
            b"VERSION" | b"VIEWPOINT" => {}
            b"FIELDS" | b"COLUMNS" => fields = Some(values.clone()),
            b"SIZE" => sizes = Some((n, numbers(n, "SIZE", &values)?)),
            b"TYPE" => types = Some((n, values.clone())),
            b"COUNT" => counts = Some((n, numbers(n, "COUNT", &values)?)),
            b"WIDTH" => width = Some(one("WIDTH")?),
            b"HEIGHT" => height = Some(one("HEIGHT")?),
            b"POINTS" => points = Some(one("POINTS")?),
            b"DATA" => {
                let data = match values.first().map(|v| v.to_ascii_lowercase()).as_deref() {
                    Some(b"ascii") => Data::Ascii,
                    Some(b"binary") => Data::Binary,
                    Some(b"binary_compressed") => Data::BinaryCompressed,
                    _ => {
                        return Err(bad(
                            n,
                            "DATA ascii, binary or binary_compressed",
                            values.first().copied().unwrap_or(b""),
                        ))
                    }
                };
                return layout(
                    n,
                    fields,
                    sizes,
                    types,
                    counts,
                    (width, height, points),
                    data,
                    (lines.pos(), lines.line()),
                );
            }
            _ => return Err(bad(n, "a PCD header keyword (FIELDS, SIZE, TYPE, …)", key)),
        }
    }
    Err(IoError::truncated(
        F,
        Location::Line(last),
        "the header's DATA line",
    ))
}

#[allow(clippy::too_many_arguments)]
fn layout(
    data_line: usize,
    fields: Option<Vec<&[u8]>>,
    sizes: Option<(usize, Vec<u64>)>,
    types: Option<(usize, Vec<&[u8]>)>,
    counts: Option<(usize, Vec<u64>)>,
    (width, height, points): (Option<u64>, Option<u64>, Option<u64>),
    data: Data,
    (start, line): (usize, usize),
) -> Result<Header, IoError> {
    let missing = |what: &str| bad(data_line, format!("{what} before DATA"), b"DATA");
    let fields = fields.ok_or_else(|| missing("FIELDS"))?;
    let (sl, sizes) = sizes.ok_or_else(|| missing("SIZE"))?;
    let (tl, types) = types.ok_or_else(|| missing("TYPE"))?;
    let (cl, counts) = counts.unwrap_or((data_line, vec![1; fields.len()]));
    for (l, what, len) in [
        (sl, "SIZE", sizes.len()),
        (tl, "TYPE", types.len()),
        (cl, "COUNT", counts.len()),
    ] {
        if len != fields.len() {
            return Err(IoError::syntax(
                F,
                Location::Line(l),
                format!("{} values after {what}, one per field", fields.len()),
                len.to_string(),
            ));
        }
    }
    let points = match (points, width, height) {
        (Some(p), ..) => p,
        (None, Some(w), h) => w.saturating_mul(h.unwrap_or(1)),
        (None, None, _) => return Err(missing("POINTS or WIDTH")),
    };
    let mut xyz = [(usize::MAX, Scalar::F32); 3];
    for (k, name) in [&b"x"[..], b"y", b"z"].into_iter().enumerate() {
        let f = fields.iter().position(|f| *f == name).ok_or_else(|| {
            IoError::syntax(
                F,
                Location::Line(data_line),
                "fields x, y and z",
                format!("FIELDS {}", show(&fields.join(&b' '))),
            )
        })?;
        let ty = Scalar::new(types[f], sizes[f]).ok_or_else(|| {
            IoError::syntax(
                F,
                Location::Line(tl),
                "TYPE F with SIZE 4 or 8, or I/U with SIZE 1, 2, 4 or 8",
                format!(
                    "TYPE {} SIZE {} for {}",
                    String::from_utf8_lossy(&types[f][..types[f].len().min(8)]),
                    sizes[f],
                    ["x", "y", "z"][k]
                ),
            )
        })?;
        if counts[f] != 1 {
            return Err(IoError::syntax(
                F,
                Location::Line(cl),
                format!("COUNT 1 for {}", ["x", "y", "z"][k]),
                counts[f].to_string(),
            ));
        }
        xyz[k] = (f, ty);
    }
    // Sizes and counts are bounded by the record, which the data must hold `points` times.
    let size_count = sizes
        .iter()
        .zip(&counts)
        .map(|(&s, &c)| (s.min(1 << 20), c.min(1 << 20)))
        .collect();
    Ok(Header {
        size_count,
        xyz,
        points: usize::try_from(points).unwrap_or(usize::MAX),
        declared: points,
        data,
        start,
        line,
    })
}

/// Reads a PCD file.
pub fn read(bytes: &[u8]) -> Result<RawGeometry, IoError> {
    read_counting(bytes, &mut None, &mut Progress::none())
}

/// [`read`], setting `left_out` to the points without a measurement it skipped and reporting
/// the share of points read to `progress`.
pub fn read_counting(
    bytes: &[u8],
    left_out: &mut Option<LeftOut>,
    progress: &mut Progress,
) -> Result<RawGeometry, IoError> {
    let h = header(bytes)?;
    let (points, encoding) = match h.data {
        Data::Ascii => (ascii(bytes, &h, progress)?, Encoding::Ascii),
        Data::Binary => (binary(bytes, &h, progress)?, Encoding::BinaryLe),
        Data::BinaryCompressed => (compressed(bytes, &h, progress)?, Encoding::BinaryLe),
    };
    let left = (
        h.points - points.len(),
        "points without a measurement (NaN pixels)",
    );
    let points = LeftOut::kept(F, Location::Byte(h.start), points, left, left_out)?;
    Ok((points, Vec::new(), encoding))
}

/// Pushes `p` unless a coordinate is NaN or infinite (a pixel without a measurement).
#[inline]
fn keep(points: &mut Vec<DVec3>, p: DVec3) {
    if p.is_finite() {
        points.push(p);
    }
}

fn ascii(bytes: &[u8], h: &Header, progress: &mut Progress) -> Result<Vec<DVec3>, IoError> {
    let cols = h.xyz.map(|(f, _)| h.column(f));
    let mut points = Vec::with_capacity(h.points.min(bytes.len() / 6));
    let mut read = 0;
    let mut last = h.line;
    for (n, line) in Lines::new(bytes, h.start, h.line) {
        last = n;
        if read == h.points {
            break;
        }
        progress.items(READING, read, h.points);
        if line.trim_ascii().is_empty() {
            continue;
        }
        let values: Vec<&[u8]> = words(line).collect();
        let mut c = [0.0; 3];
        for k in 0..3 {
            let t = values.get(cols[k]).copied().unwrap_or(b"");
            c[k] = parse_f64(t).ok_or_else(|| {
                bad(
                    n,
                    format!("a number for {} of point {read}", ["x", "y", "z"][k]),
                    t,
                )
            })?;
        }
        keep(&mut points, DVec3::from_array(c));
        read += 1;
    }
    if read < h.points {
        return Err(IoError::truncated(
            F,
            Location::Line(last),
            format!("{} points (POINTS), found {read}", h.declared),
        ));
    }
    Ok(points)
}

/// The header's point count against the bytes that hold them, before allocating.
fn check_count(h: &Header, available: usize, at: usize) -> Result<usize, IoError> {
    let needed = h.declared as u128 * h.record() as u128;
    if needed > available as u128 {
        return Err(IoError::CountTooLarge {
            format: F,
            at: Location::Byte(at),
            element: "points".into(),
            count: h.declared,
            available,
            needed,
        });
    }
    Ok(needed as usize)
}

fn binary(bytes: &[u8], h: &Header, progress: &mut Progress) -> Result<Vec<DVec3>, IoError> {
    let len = check_count(h, bytes.len() - h.start, h.start)?;
    // Within the data (checked above) when there is a point, so within `usize`.
    let stride = h.record() as usize;
    let offs = h.xyz.map(|(f, ty)| (h.offset(f) as usize, ty));
    let mut points = Vec::with_capacity(h.points);
    if stride > 0 {
        for (i, rec) in bytes[h.start..h.start + len]
            .chunks_exact(stride)
            .enumerate()
        {
            progress.items(READING, i, h.points);
            let [x, y, z] = offs.map(|(o, ty)| ty.get(&rec[o..]));
            keep(&mut points, DVec3::new(x, y, z));
        }
    }
    Ok(points)
}

fn compressed(bytes: &[u8], h: &Header, progress: &mut Progress) -> Result<Vec<DVec3>, IoError> {
    let body = &bytes[h.start..];
    if body.len() < 8 {
        return Err(IoError::truncated(
            F,
            Location::Byte(bytes.len()),
            "the compressed and uncompressed sizes (8 bytes) after DATA",
        ));
    }
    let word = |i: usize| u32::from_le_bytes([body[i], body[i + 1], body[i + 2], body[i + 3]]);
    let (packed, size) = (word(0) as usize, word(4) as usize);
    if body.len() - 8 < packed {
        return Err(IoError::truncated(
            F,
            Location::Byte(bytes.len()),
            format!(
                "{packed} bytes of compressed data from byte {}",
                h.start + 8
            ),
        ));
    }
    // Each LZF back-reference of 3 bytes yields at most 264: a larger size is a corrupt header.
    if size as u128 > packed as u128 * 88 + 32 {
        return Err(IoError::CountTooLarge {
            format: F,
            at: Location::Byte(h.start + 4),
            element: "uncompressed bytes".into(),
            count: size as u64,
            available: packed,
            needed: size as u128 / 88,
        });
    }
    let len = check_count(h, size, h.start + 4)?;
    if len != size {
        return Err(IoError::syntax(
            F,
            Location::Byte(h.start + 4),
            format!(
                "an uncompressed size of {len} bytes ({} points of {} bytes)",
                h.points,
                h.record()
            ),
            size.to_string(),
        ));
    }
    let data = lzf_decompress(&body[8..8 + packed], size).map_err(|at| IoError::Decompress {
        format: F,
        at: Location::Byte(h.start + 8 + at),
        message: "LZF data that does not decode to the declared size".into(),
    })?;
    // Field-major: all points' values of field 0, then of field 1, …
    let cols = h.xyz.map(|(f, ty)| {
        let (s, c) = h.size_count[f];
        (h.points * h.offset(f) as usize, (s * c) as usize, ty)
    });
    let mut points = Vec::with_capacity(h.points);
    for i in 0..h.points {
        progress.items(READING, i, h.points);
        let [x, y, z] = cols.map(|(start, step, ty)| ty.get(&data[start + i * step..]));
        keep(&mut points, DVec3::new(x, y, z));
    }
    Ok(points)
}

/// Decodes liblzf's format into exactly `size` bytes; the error is the input offset where the
/// data stops making sense.
fn lzf_decompress(input: &[u8], size: usize) -> Result<Vec<u8>, usize> {
    let mut out = Vec::with_capacity(size);
    let mut i = 0;
    while i < input.len() {
        let at = i;
        let ctrl = input[i] as usize;
        i += 1;
        if ctrl < 32 {
            // A literal run of ctrl + 1 bytes.
            let run = input.get(i..i + ctrl + 1).ok_or(at)?;
            if out.len() + run.len() > size {
                return Err(at);
            }
            out.extend_from_slice(run);
            i += ctrl + 1;
        } else {
            // A back-reference: length (3 bits, extended by a byte when all set) + 2, offset
            // (5 bits + a byte) + 1 back from the end of the output.
            let mut len = ctrl >> 5;
            if len == 7 {
                len += *input.get(i).ok_or(at)? as usize;
                i += 1;
            }
            let back = ((ctrl & 0x1f) << 8) + *input.get(i).ok_or(at)? as usize + 1;
            i += 1;
            len += 2;
            if back > out.len() || out.len() + len > size {
                return Err(at);
            }
            let from = out.len() - back;
            for k in 0..len {
                out.push(out[from + k]);
            }
        }
    }
    if out.len() != size {
        return Err(input.len());
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    const HEAD: &str = "# .PCD v0.7 - Point Cloud Data file format\nVERSION 0.7\n\
        FIELDS x y z rgb\nSIZE 4 4 4 4\nTYPE F F F U\nCOUNT 1 1 1 1\nWIDTH 3\nHEIGHT 1\n\
        VIEWPOINT 0 0 0 1 0 0 0\nPOINTS 3\n";

    fn cloud() -> Vec<DVec3> {
        vec![
            DVec3::new(1.0, 2.0, 3.0),
            DVec3::new(-4.5, 0.25, 6.0),
            DVec3::new(7.0, 8.0, -9.0),
        ]
    }

    fn binary_file(points: &[DVec3]) -> Vec<u8> {
        let mut b = format!("{HEAD}DATA binary\n").into_bytes();
        for p in points {
            for c in p.to_array() {
                b.extend((c as f32).to_le_bytes());
            }
            b.extend(0xff00_00ffu32.to_le_bytes());
        }
        b
    }

    #[test]
    fn ascii_binary_and_sniff() {
        let text = format!("{HEAD}DATA ascii\n1 2 3 4278190335\n-4.5 0.25 6 0\n7 8 -9 1\n");
        assert!(sniff(text.as_bytes()));
        assert!(sniff(b"VERSION .7\nFIELDS x y z\n"));
        assert!(!sniff(b"1 2 3\n"));
        let (p, t, e) = read(text.as_bytes()).unwrap();
        assert_eq!((p, t.len(), e), (cloud(), 0, Encoding::Ascii));
        let (p, _, e) = read(&binary_file(&cloud())).unwrap();
        assert_eq!((p, e), (cloud(), Encoding::BinaryLe));
    }

    #[test]
    fn pixels_without_a_measurement_are_left_out() {
        let mut c = cloud();
        c.insert(1, DVec3::new(f64::NAN, f64::NAN, f64::NAN));
        let file = String::from_utf8(binary_file(&c)[..HEAD.len()].to_vec())
            .unwrap()
            .replace("WIDTH 3\nHEIGHT 1", "WIDTH 2\nHEIGHT 2")
            .replace("POINTS 3", "POINTS 4");
        let mut bytes = format!("{file}DATA binary\n").into_bytes();
        bytes.extend(&binary_file(&c)[HEAD.len() + 12..]);
        let mut left_out = None;
        assert_eq!(
            read_counting(&bytes, &mut left_out, &mut Progress::none())
                .unwrap()
                .0,
            cloud()
        );
        assert_eq!(left_out.map(|l| l.points), Some(1));
        let all_nan = format!("{HEAD}DATA ascii\nnan nan nan 0\nnan nan nan 0\nnan nan nan 0\n");
        let err = read(all_nan.as_bytes()).unwrap_err().to_string();
        assert!(
            err.contains("3 points without a measurement (NaN pixels) and no"),
            "{err}"
        );
    }

    /// PCL compresses with liblzf; `packed` is its output for the field-major records of
    /// [`cloud`] (arrays x, y, z, rgb of 3 values each), made with `python-lzf` (a binding of
    /// liblzf): literal runs and back-references of both lengths.
    #[test]
    fn compressed_data_as_pcl_writes_it() {
        let mut raw = Vec::new();
        for k in 0..3 {
            for p in cloud() {
                raw.extend((p[k] as f32).to_le_bytes());
            }
        }
        for _ in 0..3 {
            raw.extend(7u32.to_le_bytes());
        }
        let packed: Vec<u8> = vec![
            14, 0, 0, 128, 63, 0, 0, 144, 192, 0, 0, 224, 64, 0, 0, 0, 32, 3, 1, 128, 62, 32, 7, 0,
            65, 32, 10, 32, 11, 0, 192, 32, 3, 2, 16, 193, 7, 32, 16, 128, 3, 1, 0, 0,
        ];
        assert_eq!(lzf_decompress(&packed, raw.len()), Ok(raw.clone()));
        let mut file = format!("{HEAD}DATA binary_compressed\n").into_bytes();
        file.extend((packed.len() as u32).to_le_bytes());
        file.extend((raw.len() as u32).to_le_bytes());
        file.extend(&packed);
        assert_eq!(read(&file).unwrap().0, cloud());
        // Every truncation and a corrupt reference are errors, never a panic.
        for cut in 0..file.len() {
            assert!(read(&file[..cut]).is_err(), "cut at {cut}");
        }
        let mut bad_ref = file.clone();
        // The first back-reference (byte 16: 3 bytes from 4 back) made to reach 7 940 back.
        bad_ref[file.len() - packed.len() + 16] = 63;
        assert!(matches!(read(&bad_ref), Err(IoError::Decompress { .. })));
    }

    #[test]
    fn headers_that_promise_too_much_are_refused_before_allocating() {
        let big = format!("{HEAD}DATA binary\n").replace("POINTS 3", "POINTS 4000000000000");
        assert!(matches!(
            read(big.as_bytes()),
            Err(IoError::CountTooLarge { .. })
        ));
        let mut b = format!("{HEAD}DATA binary_compressed\n").into_bytes();
        b.extend(4u32.to_le_bytes());
        b.extend(u32::MAX.to_le_bytes());
        b.extend([0, 1, 2, 3]);
        assert!(matches!(read(&b), Err(IoError::CountTooLarge { .. })));
        let no_z = HEAD.replace("x y z rgb", "x y q rgb") + "DATA ascii\n";
        let err = read(no_z.as_bytes()).unwrap_err().to_string();
        assert!(err.contains("fields x, y and z"), "{err}");
        let short = format!("{HEAD}DATA ascii\n1 2 3 0\n");
        assert!(matches!(
            read(short.as_bytes()),
            Err(IoError::Truncated { .. })
        ));
    }
}
