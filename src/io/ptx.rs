//! PTX, Leica Cyclone's text export of terrestrial scans (also written by CloudCompare, FARO
//! Scene, LAStools). One or more scans, each a grid of `columns × rows` points after a 10-line
//! header: the column and row counts, the scanner's registered position and axes (3 lines of 3,
//! informative), and a 4 × 4 matrix (4 lines of 4) that takes the scan's points into the common
//! frame as row vectors, `[x y z 1] · M`, its last row the translation. Point lines are
//! `x y z intensity [r g b]`; a line of zeros is a grid cell without a return and is left out.
//!
//! Read as a plain point list, a PTX file's header lines (the scanner's position, axes and
//! matrix rows) would become points and the grid's empty cells would pile up at the origin.

use super::error::{Format, IoError, Location};
use super::text::{parse_f64, show, words, Lines};
use super::{Encoding, LeftOut, RawGeometry, READING, REPORT_EVERY};
use crate::progress::Progress;
use glam::DVec3;

const F: Format = Format::Ptx;

/// The numbers of a line, or `None` when a token is not one.
fn numbers(line: &[u8]) -> Option<Vec<f64>> {
    words(line).map(parse_f64).collect()
}

/// True when `bytes` start like a PTX scan header: two lines of one whole number each (columns,
/// rows), then three numbers (the scanner's position). A point list starts with at most one
/// count line (PTS) and then points, so this does not take one; a PTX whose header is damaged
/// further down is still read as PTX, and its error says where.
pub fn sniff(bytes: &[u8]) -> bool {
    let head = &bytes[..bytes.len().min(2048)];
    let lines: Vec<Vec<f64>> = Lines::new(head, 0, 1)
        .take(3)
        .map_while(|(_, l)| numbers(l))
        .collect();
    lines.len() == 3
        && lines[..2]
            .iter()
            .all(|l| l.len() == 1 && l[0] >= 1.0 && l[0].fract() == 0.0)
        && lines[2].len() == 3
}

/// Reads a PTX file.
pub fn read(bytes: &[u8]) -> Result<RawGeometry, IoError> {
    read_counting(bytes, &mut None, &mut Progress::none())
}

/// [`read`], setting `left_out` to the grid cells without a return it skipped and reporting
/// the share of the file read to `progress`.
pub fn read_counting(
    bytes: &[u8],
    left_out: &mut Option<LeftOut>,
    progress: &mut Progress,
) -> Result<RawGeometry, IoError> {
    let mut lines = Lines::new(bytes, 0, 1);
    let mut points = Vec::with_capacity(bytes.len() / 32);
    let (mut empty, mut scans) = (0usize, 0usize);
    // The next line's numbers, `n` of them (or at least `n` for a point line).
    let mut next = |what: &str, n: usize, exact: bool| -> Result<Option<Vec<f64>>, IoError> {
        let Some((at, line)) = lines.find(|(_, l)| !l.trim_ascii().is_empty()) else {
            return Ok(None);
        };
        if at % REPORT_EVERY == 0 {
            progress.report(READING, lines.pos() as f64 / bytes.len() as f64);
        }
        match numbers(line) {
            Some(v) if v.len() == n || (!exact && v.len() >= n) => Ok(Some(v)),
            _ => Err(IoError::syntax(F, Location::Line(at), what, show(line))),
        }
    };
    while let Some(columns) = next("a scan header: the number of columns", 1, true)? {
        let at = scans;
        let truncated = |what: String| IoError::truncated(F, Location::Byte(bytes.len()), what);
        let count = |what: &str, v: Vec<f64>| -> Result<u64, IoError> {
            match v[0] {
                c if c >= 0.0 && c.fract() == 0.0 && c < 1e12 => Ok(c as u64),
                c => Err(IoError::syntax(
                    F,
                    Location::Byte(0),
                    format!("a whole number of {what} in scan {at}'s header"),
                    c.to_string(),
                )),
            }
        };
        let columns = count("columns", columns)?;
        let rows = next("the number of rows", 1, true)?
            .ok_or_else(|| truncated(format!("scan {at}'s header (rows)")))?;
        let rows = count("rows", rows)?;
        // Every grid cell takes a line of at least 7 bytes ("0 0 0 0"): a larger grid is a
        // corrupt header (and columns × rows may not even fit 64 bits).
        let cells = columns as u128 * rows as u128;
        if cells * 8 > bytes.len() as u128 + 8 {
            return Err(IoError::CountTooLarge {
                format: F,
                at: Location::Byte(0),
                element: format!("grid cells in scan {at} ({columns} × {rows})"),
                count: cells.min(u64::MAX as u128) as u64,
                available: bytes.len(),
                needed: cells * 8,
            });
        }
        let cells = cells as u64;
        for k in 0..4 {
            next("the scanner's position and axes: three numbers", 3, true)?
                .ok_or_else(|| truncated(format!("scan {at}'s header (line {})", k + 3)))?;
        }
        let mut m = [[0.0; 4]; 4];
        for row in &mut m {
            let v = next("a row of the 4 × 4 transformation matrix", 4, true)?
                .ok_or_else(|| truncated(format!("scan {at}'s transformation matrix")))?;
            row.copy_from_slice(&v);
        }
        let (r, t) = (
            [0, 1, 2].map(|i| DVec3::new(m[i][0], m[i][1], m[i][2])),
            DVec3::new(m[3][0], m[3][1], m[3][2]),
        );
        for i in 0..cells {
            let v = next("a point: x y z intensity [r g b]", 3, false)?.ok_or_else(|| {
                truncated(format!(
                    "{cells} points of scan {at} ({columns} × {rows}), found {i}"
                ))
            })?;
            let p = DVec3::new(v[0], v[1], v[2]);
            if p == DVec3::ZERO {
                empty += 1;
                continue;
            }
            let q = r[0] * p.x + r[1] * p.y + r[2] * p.z + t;
            if !q.is_finite() {
                return Err(IoError::NonFinite {
                    format: F,
                    at: Location::Byte(0),
                    index: points.len(),
                    x: q.x,
                    y: q.y,
                    z: q.z,
                });
            }
            points.push(q);
        }
        scans += 1;
    }
    if scans == 0 {
        return Err(IoError::syntax(
            F,
            Location::Line(1),
            "a scan header (columns, rows, position, axes, matrix)",
            "none",
        ));
    }
    let left = (empty, "grid cells without a return (0 0 0)");
    let points = LeftOut::kept(F, Location::Line(1), points, left, left_out)?;
    Ok((points, Vec::new(), Encoding::Ascii))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// rapidlasso's sample (their post on PTX in LAStools), with the points CloudCompare and
    /// LAStools give for it, to their 3 decimals.
    const SAMPLE: &str = "3\n3\n0.000000 0.000000 0.000000\n1.000000 0.000000 0.000000\n\
        0.000000 1.000000 0.000000\n0.000000 0.000000 1.000000\n\
        -0.955179 0.296021 -0.002106 0.000000\n-0.296023 -0.955180 0.001152 0.000000\n\
        -0.001670 0.001724 0.999997 0.000000\n3.847211 12.235314 -0.425777 1.000000\n\
        1.111111 2.111111 3.111 0.111\n1.222222 2.222222 3.222 0.212\n0 0 0 0\n0 0 0 0 \n\
        1.333333 2.333333 3.333 0.312\n1.444444 2.444444 3.444 0.423\n0 0 0 0\n\
        1.555555 2.555555 3.555 0.534\n1.666666 2.666666 3.666 0.678\n";

    #[test]
    fn the_sample_comes_out_where_cloudcompare_puts_it() {
        assert!(sniff(SAMPLE.as_bytes()));
        assert!(!sniff(b"3\n1 2 3\n4 5 6\n"));
        let mut left_out = None;
        let (p, t, _) =
            read_counting(SAMPLE.as_bytes(), &mut left_out, &mut Progress::none()).unwrap();
        let want = [
            [2.156, 10.553, 2.685],
            [2.017, 10.480, 2.796],
            [1.877, 10.407, 2.907],
            [1.738, 10.334, 3.018],
            [1.599, 10.261, 3.129],
            [1.460, 10.188, 3.240],
        ];
        assert!(t.is_empty());
        assert_eq!(p.len(), want.len());
        for (a, b) in p.iter().zip(want) {
            assert!(
                (*a - DVec3::from_array(b)).abs().max_element() < 0.0006,
                "{a}"
            );
        }
        assert_eq!(left_out.map(|l| l.points), Some(3));
        // Two scans: the second one's points are read too.
        let two = format!("{SAMPLE}{SAMPLE}");
        assert_eq!(read(two.as_bytes()).unwrap().0.len(), 12);
    }

    #[test]
    fn damaged_files_are_errors() {
        for cut in [1, 5, 40, 300, SAMPLE.len() - 20] {
            assert!(read(&SAMPLE.as_bytes()[..cut]).is_err(), "cut at {cut}");
        }
        let bad = SAMPLE.replace("0.000000 1.000000 0.000000\n", "0 1\n");
        let err = read(bad.as_bytes()).unwrap_err().to_string();
        assert!(
            err.contains("line 5") && err.contains("three numbers"),
            "{err}"
        );
        let header: String = SAMPLE.lines().take(10).map(|l| format!("{l}\n")).collect();
        let empty = header + &"0 0 0 0\n".repeat(9);
        let err = read(empty.as_bytes()).unwrap_err().to_string();
        assert!(
            err.contains("without a return (0 0 0) and no other"),
            "{err}"
        );
        let huge = SAMPLE.replacen("3\n3\n", "9999999962\n3333333331\n", 1);
        assert!(matches!(
            read(huge.as_bytes()),
            Err(IoError::CountTooLarge { .. })
        ));
    }
}
