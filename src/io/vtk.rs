//! Legacy VTK polydata (ASCII): writer with named per-vertex scalars (for ParaView), and a reader
//! for the same subset (POINTS, POLYGONS, TRIANGLE_STRIPS, POINT_DATA SCALARS) so the writer can
//! be round-tripped and VTK files can be wrapped. Binary legacy VTK and other dataset types
//! (unstructured grids, structured points) are rejected as unsupported.

use super::error::{Format, IoError, Location};
use super::text::{parse_f64, parse_i64, show, Lines, Tokens};
use super::{RawMesh, WriteInput};
use glam::DVec3;
use std::fmt::Write as _;

const F: Format = Format::Vtk;

/// Named per-vertex scalars read from POINT_DATA.
pub type Scalars = Vec<(String, Vec<f64>)>;

struct Reader<'a> {
    t: Tokens<'a>,
}

impl<'a> Reader<'a> {
    fn at(&self) -> Location {
        Location::Line(self.t.line())
    }

    fn token(&mut self, expected: &str) -> Result<&'a [u8], IoError> {
        self.t
            .next_token()
            .ok_or_else(|| IoError::truncated(F, Location::Line(self.t.line()), expected))
    }

    fn int(&mut self, expected: &str) -> Result<i64, IoError> {
        let t = self.token(expected)?;
        parse_i64(t).ok_or_else(|| IoError::syntax(F, self.at(), expected, show(t)))
    }

    fn count(&mut self, what: &str, min_bytes_each: u128) -> Result<usize, IoError> {
        let at = self.at();
        let c = self.int(&format!("the number of {what}"))?;
        let available = self.t.remaining();
        let needed = c.max(0) as u128 * min_bytes_each;
        if c < 0 || needed > available as u128 + 1 {
            return Err(IoError::CountTooLarge {
                format: F,
                at,
                element: what.into(),
                count: c.max(0) as u64,
                available,
                needed,
            });
        }
        Ok(c as usize)
    }

    fn float(&mut self, expected: &str) -> Result<f64, IoError> {
        let t = self.token(expected)?;
        parse_f64(t).ok_or_else(|| IoError::syntax(F, self.at(), expected, show(t)))
    }
}

/// Reads legacy ASCII VTK polydata: points, triangles (polygons and strips triangulated) and the
/// per-vertex scalars.
pub fn read(bytes: &[u8]) -> Result<(RawMesh, Scalars), IoError> {
    let mut r = read_preamble(bytes)?;
    let mut points: Vec<DVec3> = Vec::new();
    let mut tris: Vec<[u32; 3]> = Vec::new();
    let mut scalars: Scalars = Vec::new();
    let mut point_data: Option<usize> = None;
    let mut idx: Vec<u32> = Vec::new();
    while let Some(kw) = r.t.next_token() {
        let at = r.at();
        match kw {
            // After POINT_DATA only attributes follow; the ones not read here (vectors,
            // normals, cell data, fields) end the geometry. (A second POINTS/POLYGONS after
            // POINT_DATA would make the scalars disagree with the points.)
            _ if point_data.is_some() && kw != b"SCALARS" => break,
            b"POINTS" if !points.is_empty() => {
                return Err(IoError::syntax(
                    F,
                    at,
                    "a single POINTS section",
                    "a second POINTS",
                ))
            }
            b"POINTS" => r.points(&mut points)?,
            b"POLYGONS" | b"TRIANGLE_STRIPS" | b"VERTICES" | b"LINES" => {
                r.cells(kw, points.len(), &mut idx, &mut tris)?
            }
            b"POINT_DATA" => {
                let n = r.count("point data values", 2)?;
                if n != points.len() {
                    return Err(IoError::syntax(
                        F,
                        at,
                        format!("POINT_DATA {}", points.len()),
                        n.to_string(),
                    ));
                }
                point_data = Some(n);
            }
            b"SCALARS" if point_data.is_some() => {
                scalars.push(r.scalars(point_data.unwrap_or(0))?);
            }
            b"CELL_DATA" | b"FIELD" | b"METADATA" => break,
            other => {
                return Err(IoError::syntax(
                    F,
                    at,
                    "POINTS, POLYGONS, TRIANGLE_STRIPS, VERTICES, LINES or POINT_DATA",
                    show(other),
                ))
            }
        }
    }
    Ok(((points, tris), scalars))
}

/// Checks the version, title and ASCII lines and `DATASET POLYDATA`; returns a reader after them.
fn read_preamble(bytes: &[u8]) -> Result<Reader<'_>, IoError> {
    let mut lines = Lines::new(bytes, 0, 1);
    match lines.next() {
        Some((_, l)) if l.starts_with(b"# vtk DataFile") => {}
        Some((_, l)) => {
            return Err(IoError::syntax(
                F,
                Location::Line(1),
                "\"# vtk DataFile Version x.x\"",
                show(l),
            ))
        }
        None => return Err(IoError::Empty { format: Some(F) }),
    }
    let _title = lines.next();
    match lines.next() {
        Some((_, l)) if l.trim_ascii().eq_ignore_ascii_case(b"ASCII") => {}
        Some((_, l)) if l.trim_ascii().eq_ignore_ascii_case(b"BINARY") => {
            return Err(IoError::Unsupported {
                format: F,
                what: "binary legacy VTK".into(),
            })
        }
        Some((n, l)) => {
            return Err(IoError::syntax(
                F,
                Location::Line(n),
                "ASCII or BINARY",
                show(l),
            ))
        }
        None => return Err(IoError::truncated(F, Location::Line(3), "ASCII or BINARY")),
    }
    let mut r = Reader {
        t: Tokens::new(bytes, lines.pos(), lines.line(), false),
    };
    let kw = r.token("DATASET")?;
    let ds = r.token("a dataset type")?;
    if kw != b"DATASET" || !ds.eq_ignore_ascii_case(b"POLYDATA") {
        return Err(IoError::Unsupported {
            format: F,
            what: format!("dataset {} (only DATASET POLYDATA is read)", show(ds)),
        });
    }
    Ok(r)
}

impl Reader<'_> {
    /// Reads a POINTS section (after its keyword) into `points`.
    fn points(&mut self, points: &mut Vec<DVec3>) -> Result<(), IoError> {
        let n = self.count("points", 6)?;
        let _type = self.token("a data type")?;
        points.reserve(n);
        for i in 0..n {
            let p = DVec3::new(self.float("x")?, self.float("y")?, self.float("z")?);
            if !p.is_finite() {
                return Err(IoError::NonFinite {
                    format: F,
                    at: self.at(),
                    index: i,
                    x: p.x,
                    y: p.y,
                    z: p.z,
                });
            }
            points.push(p);
        }
        Ok(())
    }

    /// Reads a cell section `kw` (after its keyword), triangulating polygons and strips into
    /// `tris` and checking every index against `npoints`.
    fn cells(
        &mut self,
        kw: &[u8],
        npoints: usize,
        idx: &mut Vec<u32>,
        tris: &mut Vec<[u32; 3]>,
    ) -> Result<(), IoError> {
        let cells = self.count("cells", 4)?;
        let _size = self.count("cell list entries", 2)?;
        for c in 0..cells {
            let k = self.int("a cell size")?;
            if k < 0 || k as u128 * 2 > self.t.remaining() as u128 + 1 {
                return Err(IoError::syntax(F, self.at(), "a cell size", k.to_string()));
            }
            idx.clear();
            for _ in 0..k {
                let i = self.int("a point index")?;
                if i < 0 || i as usize >= npoints {
                    return Err(IoError::IndexOutOfRange {
                        format: F,
                        at: self.at(),
                        face: c,
                        index: i,
                        count: npoints,
                    });
                }
                idx.push(i as u32);
            }
            match kw {
                b"POLYGONS" => {
                    if idx.len() < 3 {
                        return Err(IoError::syntax(
                            F,
                            self.at(),
                            "a polygon with at least 3 points",
                            format!("{}", idx.len()),
                        ));
                    }
                    for j in 1..idx.len() - 1 {
                        tris.push([idx[0], idx[j], idx[j + 1]]);
                    }
                }
                b"TRIANGLE_STRIPS" => {
                    for j in 0..idx.len().saturating_sub(2) {
                        let (a, b) = if j % 2 == 0 {
                            (j + 1, j + 2)
                        } else {
                            (j + 2, j + 1)
                        };
                        tris.push([idx[j], idx[a], idx[b]]);
                    }
                }
                _ => {}
            }
        }
        Ok(())
    }

    /// Reads a SCALARS section (after its keyword) of `n` points: its name and first components.
    fn scalars(&mut self, n: usize) -> Result<(String, Vec<f64>), IoError> {
        let name = String::from_utf8_lossy(self.token("a scalar name")?).into_owned();
        let _type = self.token("a data type")?;
        // Optional component count, then LOOKUP_TABLE name.
        let mut t = self.token("LOOKUP_TABLE")?;
        let mut comps = 1usize;
        if t != b"LOOKUP_TABLE" {
            comps = parse_i64(t)
                .filter(|c| (1..=4).contains(c))
                .ok_or_else(|| {
                    IoError::syntax(
                        F,
                        self.at(),
                        "a component count 1–4 or LOOKUP_TABLE",
                        show(t),
                    )
                })? as usize;
            t = self.token("LOOKUP_TABLE")?;
        }
        if t != b"LOOKUP_TABLE" {
            return Err(IoError::syntax(F, self.at(), "LOOKUP_TABLE", show(t)));
        }
        let _table = self.token("a lookup table name")?;
        let mut v = Vec::with_capacity(n);
        for _ in 0..n {
            v.push(self.float("a scalar value")?);
            for _ in 1..comps {
                self.float("a scalar value")?;
            }
        }
        Ok((name, v))
    }
}

/// Writes legacy ASCII VTK polydata with the scalars as POINT_DATA (ParaView opens it directly).
/// The title line records the LSW version, and the settings when they fit its 256 characters.
/// Bare points (no triangles) are written as VERTICES cells.
pub fn write(input: &WriteInput) -> Result<Vec<u8>, IoError> {
    input.check(F)?;
    let n = input.positions.len();
    let mut s = String::with_capacity(60 * n + 30 * input.triangles.len());
    let mut title = format!("written by LSW {}", crate::VERSION);
    if let Some(j) = input.settings_compact(F)? {
        let with = format!("{title} settings {j}");
        title = if with.len() < 256 {
            with
        } else {
            format!("{title} (settings omitted: too long for the VTK title line)")
        };
    }
    let _ = write!(
        s,
        "# vtk DataFile Version 3.0\n{title}\nASCII\nDATASET POLYDATA\nPOINTS {n} double\n"
    );
    for p in input.positions {
        let _ = writeln!(s, "{} {} {}", p.x, p.y, p.z);
    }
    if input.triangles.is_empty() {
        let _ = writeln!(s, "VERTICES {n} {}", 2 * n);
        for i in 0..n {
            let _ = writeln!(s, "1 {i}");
        }
    } else {
        let nt = input.triangles.len();
        let _ = writeln!(s, "POLYGONS {nt} {}", 4 * nt);
        for t in input.triangles {
            let _ = writeln!(s, "3 {} {} {}", t[0], t[1], t[2]);
        }
    }
    if !input.scalars.is_empty() {
        let _ = writeln!(s, "POINT_DATA {n}");
        for (name, v) in input.scalars {
            let _ = writeln!(
                s,
                "SCALARS {} double 1\nLOOKUP_TABLE default",
                super::ply::header_name(name)
            );
            for x in *v {
                let _ = writeln!(s, "{x}");
            }
        }
    }
    Ok(s.into_bytes())
}
