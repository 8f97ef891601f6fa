//! Point lists: XYZ, PTS, TXT, CSV, ASC. One point per line; the first three numbers are x, y, z
//! and further columns (normals, colours, intensity) are ignored. Values may be separated by
//! whitespace, commas or semicolons. Lines before the first point that are not three numbers
//! (column headers, a PTS point count) are skipped; after that, such a line is an error (it
//! usually means a corrupt or mixed file). `#` starts a comment.

use super::error::{Format, IoError, Location};
use super::text::{parse_f64, show, Lines};
use super::{Encoding, RawGeometry, READING, REPORT_EVERY};
use crate::progress::Progress;
use glam::DVec3;

const F: Format = Format::Xyz;

#[inline]
fn is_sep(b: &u8) -> bool {
    b.is_ascii_whitespace() || *b == b',' || *b == b';'
}

/// The first three numbers of a line, or the index of the first token that is not a number.
#[inline]
fn three(line: &[u8]) -> Result<DVec3, (usize, &[u8])> {
    let mut c = [0f64; 3];
    let mut toks = line.split(is_sep).filter(|t| !t.is_empty());
    for (k, v) in c.iter_mut().enumerate() {
        let t = toks.next().ok_or((k, &b""[..]))?;
        *v = parse_f64(t).ok_or((k, t))?;
    }
    Ok(DVec3::from_array(c))
}

/// Reads a point list.
pub fn read(bytes: &[u8]) -> Result<RawGeometry, IoError> {
    read_progress(bytes, &mut Progress::none())
}

/// [`read`], reporting the share of lines read to `progress`.
pub fn read_progress(bytes: &[u8], progress: &mut Progress) -> Result<RawGeometry, IoError> {
    // A typical line has ≥ 18 bytes; the estimate only avoids re-allocations and is bounded by
    // the input size.
    let mut points = Vec::with_capacity(bytes.len() / 24);
    let mut lines = Lines::new(bytes, 0, 1);
    while let Some((n, line)) = lines.next() {
        if n % REPORT_EVERY == 0 {
            progress.report(READING, lines.pos() as f64 / bytes.len() as f64);
        }
        let line = match line.iter().position(|&b| b == b'#') {
            Some(i) => &line[..i],
            None => line,
        };
        if line.iter().all(is_sep) {
            continue;
        }
        match three(line) {
            Ok(p) => {
                if !p.is_finite() {
                    return Err(IoError::NonFinite {
                        format: F,
                        at: Location::Line(n),
                        index: points.len(),
                        x: p.x,
                        y: p.y,
                        z: p.z,
                    });
                }
                points.push(p);
            }
            Err(_) if points.is_empty() => {} // a header line
            Err((k, t)) => {
                return Err(IoError::syntax(
                    F,
                    Location::Line(n),
                    format!(
                        "three numbers x y z (point {}); {} is not a number",
                        points.len(),
                        ["x", "y", "z"][k]
                    ),
                    if t.is_empty() {
                        "end of line".to_string()
                    } else {
                        show(t)
                    },
                ))
            }
        }
    }
    if points.is_empty() {
        return Err(IoError::syntax(
            F,
            Location::Line(1),
            "at least one line of three numbers x y z",
            "none",
        ));
    }
    Ok((points, Vec::new(), Encoding::Ascii))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn headers_commas_and_extra_columns() {
        let (p, _, _) = read(b"x,y,z,nx\n1,2,3,9\n4;5;6\n 7 8 9 1 1 1\n\n").unwrap();
        assert_eq!(
            p,
            vec![
                DVec3::new(1., 2., 3.),
                DVec3::new(4., 5., 6.),
                DVec3::new(7., 8., 9.)
            ]
        );
        let (p, _, _) = read(b"2\n1 2 3\n4 5 6\n").unwrap();
        assert_eq!(p.len(), 2);
        assert!(matches!(
            read(b"1 2 3\n4 five 6\n"),
            Err(IoError::Syntax {
                at: Location::Line(2),
                ..
            })
        ));
    }
}
