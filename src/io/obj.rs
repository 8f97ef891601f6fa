//! Wavefront OBJ: reader (`v` and `f` lines, `v/vt/vn` index forms, negative indices, polygons,
//! any number of objects/groups) and writer.
//!
//! Hand-written rather than using `tobj`: tobj's errors carry no line number (a user cannot find
//! the bad line in a large file), it drops files with only `v` lines (point clouds), and it builds
//! per-object, per-attribute arrays LSW does not need. Only positions and face corners are read;
//! texture coordinates, normals, materials, lines and free-form geometry are skipped. Faces are
//! fan-triangulated. A file without `f` lines is a point cloud.

use super::error::{Format, IoError, Location};
use super::text::{parse_f64, parse_i64, show, trim, words, Lines};
use super::{Encoding, RawGeometry, WriteInput, READING, REPORT_EVERY};
use crate::progress::Progress;
use glam::DVec3;
use std::fmt::Write as _;

const F: Format = Format::Obj;

/// Reads an OBJ file into points and (fan-triangulated) triangles.
pub fn read(bytes: &[u8]) -> Result<RawGeometry, IoError> {
    read_progress(bytes, &mut Progress::none())
}

/// [`read`], reporting the share of lines read to `progress`.
pub fn read_progress(bytes: &[u8], progress: &mut Progress) -> Result<RawGeometry, IoError> {
    let mut points: Vec<DVec3> = Vec::new();
    let mut tris: Vec<[u32; 3]> = Vec::new();
    // Positive indices may point forward (past the vertices read so far); they are checked once
    // all vertices are known: (line, face, index).
    let mut forward: Vec<(usize, usize, i64)> = Vec::new();
    let mut corners: Vec<u32> = Vec::new();
    let mut faces = 0usize;
    let mut lines = Lines::new(bytes, 0, 1);
    while let Some((n, line)) = lines.next() {
        if n % REPORT_EVERY == 0 {
            progress.report(READING, lines.pos() as f64 / bytes.len() as f64);
        }
        let line = trim(line);
        let at = Location::Line(n);
        let mut w = words(line);
        let Some(key) = w.next() else { continue };
        match key {
            b"v" => {
                let mut c = [0f64; 3];
                for (k, slot) in c.iter_mut().enumerate() {
                    let t = w.next().ok_or_else(|| {
                        IoError::syntax(F, at, "three coordinates after \"v\"", format!("{k}"))
                    })?;
                    *slot =
                        parse_f64(t).ok_or_else(|| IoError::syntax(F, at, "a number", show(t)))?;
                }
                let p = DVec3::from_array(c);
                if !p.is_finite() {
                    return Err(IoError::NonFinite {
                        format: F,
                        at,
                        index: points.len(),
                        x: p.x,
                        y: p.y,
                        z: p.z,
                    });
                }
                points.push(p);
            }
            b"f" | b"fo" => {
                corners.clear();
                let nv = points.len() as i64;
                for t in w {
                    let head = t.split(|&b| b == b'/').next().unwrap_or(t);
                    let i = parse_i64(head).ok_or_else(|| {
                        IoError::syntax(F, at, "a vertex index (i, i/t, i//n or i/t/n)", show(t))
                    })?;
                    let resolved = if i < 0 { nv + i } else { i - 1 };
                    if i == 0 || resolved < 0 || resolved > u32::MAX as i64 {
                        return Err(IoError::IndexOutOfRange {
                            format: F,
                            at,
                            face: faces,
                            index: i,
                            count: points.len(),
                        });
                    }
                    if resolved >= nv {
                        forward.push((n, faces, i));
                    }
                    corners.push(resolved as u32);
                }
                if corners.len() < 3 {
                    return Err(IoError::syntax(
                        F,
                        at,
                        "a face with at least 3 vertices",
                        format!("{} vertices", corners.len()),
                    ));
                }
                for k in 1..corners.len() - 1 {
                    tris.push([corners[0], corners[k], corners[k + 1]]);
                }
                faces += 1;
            }
            [b'#', ..] => {}
            [c, ..] if c.is_ascii_alphabetic() => {} // vt, vn, o, g, s, usemtl, mtllib, l, …
            _ => {
                return Err(IoError::syntax(
                    F,
                    at,
                    "an OBJ statement (v, f, vt, vn, o, g, …)",
                    show(line),
                ))
            }
        }
    }
    if let Some(&(line, face, index)) = forward.iter().find(|f| f.2 > points.len() as i64) {
        return Err(IoError::IndexOutOfRange {
            format: F,
            at: Location::Line(line),
            face,
            index,
            count: points.len(),
        });
    }
    Ok((points, tris, Encoding::Ascii))
}

/// Writes OBJ: a comment with the LSW version and settings, `v` lines (shortest round-trip
/// decimal), and 1-based `f` lines. Scalars cannot be stored and are ignored.
pub fn write(input: &WriteInput) -> Result<Vec<u8>, IoError> {
    input.check(F)?;
    let mut s = String::with_capacity(40 * input.positions.len() + 24 * input.triangles.len());
    let _ = writeln!(s, "# written by LSW {}", crate::VERSION);
    if let Some(j) = input.settings_compact(F)? {
        let _ = writeln!(s, "# settings {j}");
    }
    for p in input.positions {
        let _ = writeln!(s, "v {} {} {}", p.x, p.y, p.z);
    }
    for t in input.triangles {
        let _ = writeln!(s, "f {} {} {}", t[0] + 1, t[1] + 1, t[2] + 1);
    }
    Ok(s.into_bytes())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn forms_negative_indices_and_polygons() {
        let src = b"mtllib x.mtl\no a\nv 0 0 0\nv 1 0 0 1.0\nv 1 1 0\nv 0 1 0\nvt 0 0\nvn 0 0 1\ng g1\nf 1/1/1 2/1/1 3//1 4\nf -4 -3 -2\n";
        let (p, t, _) = read(src).unwrap();
        assert_eq!(p.len(), 4);
        assert_eq!(t, vec![[0, 1, 2], [0, 2, 3], [0, 1, 2]]);
        let (p, t, _) = read(b"v 1 2 3\nv 4 5 6\n").unwrap();
        assert_eq!((p.len(), t.len()), (2, 0));
        assert!(matches!(
            read(b"f 1 2 3\nv 0 0 0\nv 1 0 0\n"),
            Err(IoError::IndexOutOfRange { index: 3, .. })
        ));
    }
}
