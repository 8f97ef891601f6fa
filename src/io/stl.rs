//! STL: reader (ASCII and binary, including binary files whose 80-byte header starts with
//! "solid") and binary writer. STL stores each triangle's three corners separately; the reader
//! welds corners with bit-identical coordinates into shared vertices, in first-seen order.
//!
//! Hand-written rather than using `stl_io`: its errors are plain `std::io::Error`s with no byte
//! offset or line, it decides ASCII vs. binary from the "solid" prefix alone, and the triangle
//! count of a binary header is not bounded by the file size before reserving memory. The format
//! is small enough that 150 lines give exact errors and bounded allocation.

use super::detect::is_exact_binary_stl;
use super::error::{Format, IoError, Location};
use super::text::{first_binary_byte, parse_f64, show, trim, words, Lines};
use super::{Encoding, RawGeometry, RawMesh, WriteInput, READING, REPORT_EVERY};
use crate::progress::Progress;
use glam::DVec3;
use std::collections::HashMap;

const F: Format = Format::Stl;

/// Welds corners with identical coordinates (−0 and +0 are the same) into indexed vertices.
struct Welder {
    map: HashMap<[u64; 3], u32>,
    points: Vec<DVec3>,
    corners: usize,
}

impl Welder {
    fn with_capacity(triangles: usize) -> Self {
        Self {
            map: HashMap::with_capacity(triangles / 2 + 3),
            points: Vec::with_capacity(triangles / 2 + 3),
            corners: 0,
        }
    }

    fn add(&mut self, p: DVec3, at: Location) -> Result<u32, IoError> {
        if !p.is_finite() {
            return Err(IoError::NonFinite {
                format: F,
                at,
                index: self.corners,
                x: p.x,
                y: p.y,
                z: p.z,
            });
        }
        self.corners += 1;
        let key = (p + DVec3::ZERO).to_array().map(f64::to_bits); // + 0.0 turns −0 into +0
        let next = self.points.len() as u32;
        let i = *self.map.entry(key).or_insert(next);
        if i == next {
            self.points.push(p);
        }
        Ok(i)
    }
}

/// Reads an STL file (ASCII or binary), welding duplicate vertices.
pub fn read(bytes: &[u8]) -> Result<RawGeometry, IoError> {
    read_progress(bytes, &mut Progress::none())
}

/// [`read`], reporting the share of the file read to `progress`.
pub fn read_progress(bytes: &[u8], progress: &mut Progress) -> Result<RawGeometry, IoError> {
    let starts_solid = words(&bytes[..bytes.len().min(256)]).next() == Some(b"solid");
    if !is_exact_binary_stl(bytes) && starts_solid && first_binary_byte(bytes, 4096).is_none() {
        let (p, t) = read_ascii(bytes, progress)?;
        return Ok((p, t, Encoding::Ascii));
    }
    if !is_exact_binary_stl(bytes) && !starts_solid && is_text(bytes) {
        return Err(not_stl_text(bytes));
    }
    let (p, t) = read_binary(bytes, progress)?;
    Ok((p, t, Encoding::BinaryLe))
}

/// Whether the file's start is printable text: UTF-8 with no control bytes but line breaks and
/// tabs (a binary STL's header and counts have some).
fn is_text(bytes: &[u8]) -> bool {
    let head = &bytes[..bytes.len().min(4096)];
    first_binary_byte(head, 4096).is_none()
        && head
            .iter()
            .all(|&b| b >= 0x20 || matches!(b, b'\t' | b'\n' | b'\r'))
}

/// Text that does not begin with "solid" is neither STL encoding: say so, with its first word,
/// rather than report it as a binary STL's short or overstated header.
fn not_stl_text(bytes: &[u8]) -> IoError {
    let first = words(&bytes[..bytes.len().min(256)])
        .next()
        .unwrap_or_default();
    IoError::Syntax {
        format: Format::Stl,
        at: Location::Line(1),
        expected: "\"solid\" (an ASCII STL) or a binary STL (text was found: this is not an STL \
                   file)"
            .into(),
        found: format!("\"{}\"", String::from_utf8_lossy(first)),
    }
}

fn read_binary(bytes: &[u8], progress: &mut Progress) -> Result<RawMesh, IoError> {
    if bytes.len() < 84 {
        return Err(IoError::truncated(
            F,
            Location::Byte(bytes.len()),
            "an 84-byte binary STL header (80-byte comment + triangle count)",
        ));
    }
    let n = u32::from_le_bytes([bytes[80], bytes[81], bytes[82], bytes[83]]) as usize;
    let available = bytes.len() - 84;
    if (n as u128) * 50 > available as u128 {
        return Err(IoError::CountTooLarge {
            format: F,
            at: Location::Byte(80),
            element: "triangles (50 bytes each)".into(),
            count: n as u64,
            available,
            needed: n as u128 * 50,
        });
    }
    let mut w = Welder::with_capacity(n);
    let mut tris = Vec::with_capacity(n);
    let f = |b: &[u8], o: usize| f32::from_le_bytes([b[o], b[o + 1], b[o + 2], b[o + 3]]) as f64;
    for (t, rec) in bytes[84..84 + 50 * n].chunks_exact(50).enumerate() {
        if t % REPORT_EVERY == 0 {
            progress.report(READING, t as f64 / n as f64);
        }
        let mut tri = [0u32; 3];
        for (k, slot) in tri.iter_mut().enumerate() {
            let o = 12 + 12 * k;
            let p = DVec3::new(f(rec, o), f(rec, o + 4), f(rec, o + 8));
            *slot = w.add(p, Location::Byte(84 + 50 * t + o))?;
        }
        tris.push(tri);
    }
    Ok((w.points, tris))
}

fn read_ascii(bytes: &[u8], progress: &mut Progress) -> Result<RawMesh, IoError> {
    let mut w = Welder::with_capacity(0);
    let mut tris = Vec::new();
    let mut corners: Vec<u32> = Vec::new();
    let mut in_facet = false;
    let mut last = 0;
    let mut lines = Lines::new(bytes, 0, 1);
    while let Some((n, line)) = lines.next() {
        if n % REPORT_EVERY == 0 {
            progress.report(READING, lines.pos() as f64 / bytes.len() as f64);
        }
        last = n;
        let at = Location::Line(n);
        let mut ws = words(trim(line));
        let Some(key) = ws.next() else { continue };
        match key {
            b"solid" | b"endsolid" | b"outer" => {}
            b"facet" => {
                if in_facet {
                    return Err(IoError::syntax(F, at, "\"endfacet\"", "\"facet\""));
                }
                in_facet = true;
                corners.clear();
            }
            b"vertex" => {
                if !in_facet {
                    return Err(IoError::syntax(
                        F,
                        at,
                        "\"facet\" before \"vertex\"",
                        "\"vertex\"",
                    ));
                }
                let mut c = [0f64; 3];
                for v in c.iter_mut() {
                    let t = ws.next().ok_or_else(|| {
                        IoError::syntax(F, at, "three coordinates after \"vertex\"", "end of line")
                    })?;
                    *v = parse_f64(t).ok_or_else(|| IoError::syntax(F, at, "a number", show(t)))?;
                }
                corners.push(w.add(DVec3::from_array(c), at)?);
            }
            b"endloop" => {}
            b"endfacet" => {
                if !in_facet || corners.len() < 3 {
                    return Err(IoError::syntax(
                        F,
                        at,
                        "a facet with 3 vertices",
                        format!("{} vertices", corners.len()),
                    ));
                }
                for k in 1..corners.len() - 1 {
                    tris.push([corners[0], corners[k], corners[k + 1]]);
                }
                in_facet = false;
            }
            other => {
                return Err(IoError::syntax(
                    F,
                    at,
                    "an ASCII STL keyword (facet, outer loop, vertex, endloop, endfacet, endsolid)",
                    show(other),
                ))
            }
        }
    }
    if in_facet {
        return Err(IoError::truncated(
            F,
            Location::Line(last + 1),
            "\"endfacet\"",
        ));
    }
    Ok((w.points, tris))
}

/// Writes binary STL. The 80-byte header holds "LSW VERSION" (never "solid", so readers do not
/// mistake it for ASCII); there is no room for settings or scalars.
pub fn write(input: &WriteInput) -> Result<Vec<u8>, IoError> {
    input.check(F)?;
    if input.triangles.len() > u32::MAX as usize {
        return Err(IoError::InvalidInput {
            format: F,
            what: "more than 2^32 triangles".into(),
        });
    }
    let mut out = Vec::with_capacity(84 + 50 * input.triangles.len());
    let mut header = format!("LSW {} binary STL", crate::VERSION).into_bytes();
    header.resize(80, b' ');
    out.extend_from_slice(&header);
    out.extend_from_slice(&(input.triangles.len() as u32).to_le_bytes());
    let put = |out: &mut Vec<u8>, v: DVec3| {
        for c in v.to_array() {
            out.extend_from_slice(&(c as f32).to_le_bytes());
        }
    };
    for t in input.triangles {
        let [a, b, c] = t.map(|i| input.positions[i as usize]);
        put(&mut out, (b - a).cross(c - a).normalize_or_zero());
        for p in [a, b, c] {
            put(&mut out, p);
        }
        out.extend_from_slice(&[0, 0]);
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    #[test]
    fn text_that_is_not_ascii_stl_is_named_so() {
        let e = read(b"This is just a note.\nNothing to see here.\n").unwrap_err();
        let text = e.to_string();
        assert!(text.contains("this is not an STL file"), "{text}");
        assert!(text.contains("found \"This\""), "{text}");
        // Binary data is still read as a binary STL (and refused by its header's count).
        let mut b = vec![0u8; 80];
        b.extend(1000u32.to_le_bytes());
        assert!(read(&b)
            .unwrap_err()
            .to_string()
            .contains("header declares 1000"));
    }

    use super::*;

    #[test]
    fn ascii_welds_and_binary_with_solid_header() {
        let src = b"solid t\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 1 0\nendloop\nendfacet\nfacet normal 0 0 1\nouter loop\nvertex 1 0 0\nvertex 1 1 0\nvertex -0 1 0\nendloop\nendfacet\nendsolid t\n";
        let (p, t, e) = read(src).unwrap();
        assert_eq!(e, Encoding::Ascii);
        assert_eq!(p.len(), 4);
        assert_eq!(t, vec![[0, 1, 2], [1, 3, 2]]);
        let mut b = b"solid but binary".to_vec();
        b.resize(80, 0);
        b.extend_from_slice(&1u32.to_le_bytes());
        b.extend_from_slice(&[0; 12]);
        for v in [[0f32, 0., 0.], [1., 0., 0.], [0., 1., 0.]] {
            for c in v {
                b.extend_from_slice(&c.to_le_bytes());
            }
        }
        b.extend_from_slice(&[0, 0]);
        let (p, t, e) = read(&b).unwrap();
        assert_eq!((p.len(), t.len(), e), (3, 1, Encoding::BinaryLe));
    }
}
