//! Object File Format (OFF) reader, with the COFF (colours), NOFF (normals), CNOFF and STOFF
//! (texture coordinates) variants: the extra per-vertex values and per-face colours are skipped.
//! Polygons are fan-triangulated; a file with zero faces is a point cloud. Binary OFF and the
//! 4D/nD variants are rejected as unsupported.
//!
//! Read line by line (one vertex or face per line, as every exporter writes) because COFF colours
//! have 3 or 4 components, which makes a pure token stream ambiguous.

use super::error::{Format, IoError, Location};
use super::text::{parse_f64, parse_i64, show, words, Lines};
use super::{Encoding, RawGeometry};
use glam::DVec3;

const F: Format = Format::Off;

/// The line without a `#` comment.
fn strip(line: &[u8]) -> &[u8] {
    match line.iter().position(|&b| b == b'#') {
        Some(i) => &line[..i],
        None => line,
    }
}

/// Reads an OFF file into points and (fan-triangulated) triangles.
pub fn read(bytes: &[u8]) -> Result<RawGeometry, IoError> {
    let mut lines = Lines::new(bytes, 0, 1)
        .map(|(n, l)| (n, strip(l)))
        .filter(|(_, l)| !l.trim_ascii().is_empty());
    let (count_line, nv, nf) = read_header(&mut lines, bytes.len())?;
    let points = read_vertices(&mut lines, nv, count_line)?;
    let tris = read_faces(&mut lines, bytes, nv, nf)?;
    Ok((points, tris, Encoding::Ascii))
}

/// Reads the keyword line and the counts; returns the counts' line, the vertex and face counts.
fn read_header<'a>(
    lines: &mut impl Iterator<Item = (usize, &'a [u8])>,
    available: usize,
) -> Result<(usize, u64, u64), IoError> {
    let Some((n0, first)) = lines.next() else {
        return Err(IoError::truncated(F, Location::Line(1), "an OFF header"));
    };
    let mut w = words(first);
    let key = w.next().unwrap_or(b"");
    let prefix = key.strip_suffix(b"OFF").ok_or_else(|| {
        IoError::syntax(
            F,
            Location::Line(n0),
            "OFF, COFF, NOFF, CNOFF or STOFF",
            show(key),
        )
    })?;
    if prefix.contains(&b'4') || prefix.contains(&b'n') {
        return Err(IoError::Unsupported {
            format: F,
            what: format!("the {} (4D / nD) variant", String::from_utf8_lossy(key)),
        });
    }
    let mut rest: Vec<&[u8]> = w.collect();
    if rest.first() == Some(&&b"BINARY"[..]) {
        return Err(IoError::Unsupported {
            format: F,
            what: "binary OFF".into(),
        });
    }
    let mut count_line = n0;
    if rest.is_empty() {
        let Some((n, l)) = lines.next() else {
            return Err(IoError::truncated(
                F,
                Location::Line(n0 + 1),
                "the counts line \"VERTICES FACES EDGES\"",
            ));
        };
        count_line = n;
        rest = words(l).collect();
    }
    let (nv, nf) = parse_counts(&rest, Location::Line(count_line), available)?;
    Ok((count_line, nv, nf))
}

/// Parses the vertex and face counts and checks them against the file size.
fn parse_counts(rest: &[&[u8]], at: Location, available: usize) -> Result<(u64, u64), IoError> {
    let count = |i: usize| -> Result<u64, IoError> {
        let t = rest.get(i).copied().unwrap_or(b"");
        parse_i64(t)
            .filter(|&c| c >= 0)
            .map(|c| c as u64)
            .ok_or_else(|| IoError::syntax(F, at, "vertex and face counts \"V F E\"", show(t)))
    };
    let (nv, nf) = (count(0)?, count(1)?);
    // Each vertex line holds at least "x y z\n" (6 bytes), each face line "3 a b c\n" (8).
    let needed = nv as u128 * 6 + nf as u128 * 8;
    if needed > available as u128 + 1 || nv > u32::MAX as u64 {
        return Err(IoError::CountTooLarge {
            format: F,
            at,
            element: format!("vertices and {nf} faces"),
            count: nv,
            available,
            needed,
        });
    }
    Ok((nv, nf))
}

/// Reads `nv` vertex lines (x y z first; the rest of each line is skipped).
fn read_vertices<'a>(
    lines: &mut impl Iterator<Item = (usize, &'a [u8])>,
    nv: u64,
    count_line: usize,
) -> Result<Vec<DVec3>, IoError> {
    let mut points = Vec::with_capacity(nv as usize);
    for i in 0..nv as usize {
        let Some((n, l)) = lines.next() else {
            return Err(IoError::truncated(
                F,
                Location::Line(count_line + i + 1),
                format!("vertex {i} of {nv}"),
            ));
        };
        let at = Location::Line(n);
        let mut c = [0f64; 3];
        let mut ws = words(l);
        for v in c.iter_mut() {
            let t = ws.next().unwrap_or(b"");
            *v = parse_f64(t)
                .ok_or_else(|| IoError::syntax(F, at, format!("vertex {i}: x y z"), show(t)))?;
        }
        let p = DVec3::from_array(c);
        if !p.is_finite() {
            return Err(IoError::NonFinite {
                format: F,
                at,
                index: i,
                x: p.x,
                y: p.y,
                z: p.z,
            });
        }
        points.push(p);
    }
    Ok(points)
}

/// Reads `nf` face lines and fan-triangulates them.
fn read_faces<'a>(
    lines: &mut impl Iterator<Item = (usize, &'a [u8])>,
    bytes: &[u8],
    nv: u64,
    nf: u64,
) -> Result<Vec<[u32; 3]>, IoError> {
    let mut tris = Vec::with_capacity(nf as usize);
    let mut idx: Vec<u32> = Vec::new();
    for f in 0..nf as usize {
        let Some((n, l)) = lines.next() else {
            return Err(IoError::truncated(
                F,
                Location::Line(bytes.iter().filter(|&&b| b == b'\n').count() + 1),
                format!("face {f} of {nf}"),
            ));
        };
        face_indices(l, Location::Line(n), f, nv, &mut idx)?;
        for j in 1..idx.len() - 1 {
            tris.push([idx[0], idx[j], idx[j + 1]]);
        }
    }
    Ok(tris)
}

/// Parses one face line's vertex count and indices into `idx`, checking each index.
fn face_indices(
    l: &[u8],
    at: Location,
    f: usize,
    nv: u64,
    idx: &mut Vec<u32>,
) -> Result<(), IoError> {
    let mut ws = words(l);
    let t = ws.next().unwrap_or(b"");
    let k = parse_i64(t)
        .filter(|&k| k >= 3)
        .ok_or_else(|| IoError::syntax(F, at, format!("face {f}: a vertex count ≥ 3"), show(t)))?;
    idx.clear();
    for _ in 0..k {
        let t = ws.next().ok_or_else(|| {
            IoError::syntax(
                F,
                at,
                format!("face {f}: {k} vertex indices"),
                format!("{}", idx.len()),
            )
        })?;
        let i = parse_i64(t).ok_or_else(|| IoError::syntax(F, at, "a vertex index", show(t)))?;
        if i < 0 || i as u64 >= nv {
            return Err(IoError::IndexOutOfRange {
                format: F,
                at,
                face: f,
                index: i,
                count: nv as usize,
            });
        }
        idx.push(i as u32);
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn coff_with_comments_and_quads() {
        let src = b"COFF # coloured\n# counts\n4 1 0\n0 0 0 255 0 0 255\n1 0 0 0 255 0 255\n1 1 0 0 0 255 255\n0 1 0 9 9 9 255\n4 0 1 2 3 1 0 0\n";
        let (p, t, _) = read(src).unwrap();
        assert_eq!(p.len(), 4);
        assert_eq!(t, vec![[0, 1, 2], [0, 2, 3]]);
        let (p, t, _) = read(b"OFF 2 0 0\n1 2 3\n4 5 6\n").unwrap();
        assert_eq!((p.len(), t.len()), (2, 0));
    }
}
