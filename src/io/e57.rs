//! E57 (ASTM E2807), the interchange format of terrestrial laser scanners: one file holds several
//! scans, each in Cartesian or spherical coordinates with its own pose. The scans are read into
//! one cloud in the file's common frame: spherical coordinates turned Cartesian and every scan's
//! pose applied (what a registered scan project means). Points marked invalid (no return) or
//! holding only a direction are left out; colours, intensities and images are ignored.
//!
//! Read through the `e57` crate (pure Rust, no unsafe code, no unwrap or panic by its own lints):
//! E57 is XML plus CRC-checked binary pages with bit-packed compressed vectors, too much for a
//! hand-written reader. It reads from the input slice, so no copy is made.

use super::error::{Format, IoError, Location};
use super::{Encoding, LeftOut, RawGeometry, READING, REPORT_EVERY};
use crate::progress::Progress;
use glam::DVec3;
use std::io::Cursor;

const F: Format = Format::E57;

/// True when `bytes` start with E57's file signature.
pub fn sniff(bytes: &[u8]) -> bool {
    bytes.starts_with(b"ASTM-E57")
}

/// The crate's error as ours, with `what` we were reading. Its messages say what went wrong in
/// E57's own terms (page, section, XML node).
fn error(e: e57::Error, bytes: &[u8], what: &str) -> IoError {
    match e {
        e57::Error::NotImplemented { desc } => IoError::Unsupported {
            format: F,
            what: desc,
        },
        e57::Error::Read { desc, .. } if bytes.len() % 1024 != 0 => IoError::Truncated {
            format: F,
            at: Location::Byte(bytes.len()),
            // E57 files are whole 1 024-byte pages: a file that is not was cut.
            expected: format!("{what} ({desc}); the file is not a whole number of pages"),
        },
        e => IoError::syntax(F, Location::Byte(0), what, e.to_string()),
    }
}

/// Where a scan's coordinates sit in its records.
enum Layout {
    Cartesian([usize; 3]),
    /// Range, azimuth, elevation.
    Spherical([usize; 3]),
}

/// A scan's record layout: Cartesian coordinates if it has them, else spherical, and the state
/// record that marks a point invalid (0 valid, 1 a direction only, 2 no return).
fn layout(cloud: &e57::PointCloud) -> Option<(Layout, Option<usize>)> {
    use e57::RecordName as N;
    let at = |name: N| cloud.prototype.iter().position(|r| r.name == name);
    if let (Some(x), Some(y), Some(z)) = (at(N::CartesianX), at(N::CartesianY), at(N::CartesianZ)) {
        return Some((Layout::Cartesian([x, y, z]), at(N::CartesianInvalidState)));
    }
    let (r, a, e) = (
        at(N::SphericalRange)?,
        at(N::SphericalAzimuth)?,
        at(N::SphericalElevation)?,
    );
    Some((Layout::Spherical([r, a, e]), at(N::SphericalInvalidState)))
}

/// Reads every scan of an E57 file into one point cloud.
///
/// The crate's raw reader gives the records; the conversions are done here with
/// [`crate::fmath`] (its simple reader calls the platform's `sin`, whose last bit differs between
/// the CLI and the browser, and it can stop on a point whose values are not all decoded yet).
pub fn read(bytes: &[u8]) -> Result<RawGeometry, IoError> {
    read_counting(bytes, &mut None, &mut Progress::none())
}

/// [`read`], setting `left_out` to the invalid points it skipped and reporting the share of
/// records read to `progress`.
pub fn read_counting(
    bytes: &[u8],
    left_out: &mut Option<LeftOut>,
    progress: &mut Progress,
) -> Result<RawGeometry, IoError> {
    let mut reader = e57::E57Reader::new(Cursor::new(bytes))
        .map_err(|e| error(e, bytes, "an E57 header and XML section"))?;
    let clouds = reader.pointclouds();
    if clouds.is_empty() {
        return Err(IoError::syntax(
            F,
            Location::Byte(0),
            "at least one scan (a data3D point cloud)",
            "none",
        ));
    }
    // The XML's counts bound nothing: reserve no more than the bytes could hold.
    let total = clouds.iter().fold(0u64, |n, c| n.saturating_add(c.records));
    let mut points = Vec::with_capacity(total.min(bytes.len() as u64 / 4) as usize);
    let (mut left, mut done) = (0u64, 0u64);
    for (k, cloud) in clouds.iter().enumerate() {
        let what = format!("the points of scan {k} ({} records)", cloud.records);
        let (coords, state) = layout(cloud).ok_or_else(|| {
            IoError::syntax(
                F,
                Location::Byte(0),
                format!("Cartesian or spherical coordinates in scan {k}"),
                "neither",
            )
        })?;
        let pose = cloud.transform.clone().unwrap_or_default();
        let q = pose.rotation;
        let rotation = glam::DQuat::from_xyzw(q.x, q.y, q.z, q.w).normalize();
        let t = pose.translation;
        let translation = DVec3::new(t.x, t.y, t.z);
        let value = |v: &[e57::RecordValue], i: usize| -> Result<f64, IoError> {
            v[i].to_f64(&cloud.prototype[i].data_type)
                .map_err(|e| error(e, bytes, &what))
        };
        let scan = reader
            .pointcloud_raw(cloud)
            .map_err(|e| error(e, bytes, &what))?;
        for v in scan {
            let v = v.map_err(|e| error(e, bytes, &what))?;
            done += 1;
            if done % REPORT_EVERY as u64 == 0 {
                progress.report(READING, done as f64 / total.max(1) as f64);
            }
            if let Some(s) = state {
                if value(&v, s)? != 0.0 {
                    left += 1;
                    continue;
                }
            }
            let local = match coords {
                Layout::Cartesian([x, y, z]) => {
                    DVec3::new(value(&v, x)?, value(&v, y)?, value(&v, z)?)
                }
                Layout::Spherical([r, a, e]) => {
                    let (r, (sa, ca), (se, ce)) = (
                        value(&v, r)?,
                        crate::fmath::sin_cos(value(&v, a)?),
                        crate::fmath::sin_cos(value(&v, e)?),
                    );
                    DVec3::new(r * ce * ca, r * ce * sa, r * se)
                }
            };
            let p = rotation * local + translation;
            if p.is_finite() {
                points.push(p);
            } else {
                left += 1;
            }
        }
    }
    let left = (left as usize, "points marked invalid or not finite");
    let points = LeftOut::kept(F, Location::Byte(0), points, left, left_out)?;
    Ok((points, Vec::new(), Encoding::BinaryLe))
}

#[cfg(test)]
mod tests {
    use super::*;
    use e57::{Record, RecordValue};

    /// Two scans: one Cartesian at the origin, one spherical with a pose (turned 90° about z and
    /// moved by (10, 0, 0)), each with a point marked invalid.
    fn file() -> Vec<u8> {
        let mut out = Cursor::new(Vec::new());
        let mut w = e57::E57Writer::new(&mut out, "file").unwrap();
        let mut a = w
            .add_pointcloud(
                "a",
                vec![
                    Record::CARTESIAN_X_F64,
                    Record::CARTESIAN_Y_F64,
                    Record::CARTESIAN_Z_F64,
                    Record::CARTESIAN_INVALID_STATE,
                ],
            )
            .unwrap();
        for (x, y, z, bad) in [(1.0, 2.0, 3.0, 0), (4.0, 5.0, 6.0, 2), (7.0, 8.0, 9.0, 0)] {
            let v = |c| RecordValue::Double(c);
            a.add_point(vec![v(x), v(y), v(z), RecordValue::Integer(bad)])
                .unwrap();
        }
        a.finalize().unwrap();
        let mut b = w
            .add_pointcloud(
                "b",
                vec![
                    Record::SPHERICAL_AZIMUTH_F64,
                    Record::SPHERICAL_ELEVATION_F64,
                    Record::SPHERICAL_RANGE_F64,
                    Record::SPHERICAL_INVALID_STATE,
                ],
            )
            .unwrap();
        let h = std::f64::consts::FRAC_1_SQRT_2;
        b.set_transform(Some(e57::Transform {
            rotation: e57::Quaternion {
                w: h,
                x: 0.0,
                y: 0.0,
                z: h,
            },
            translation: e57::Translation {
                x: 10.0,
                y: 0.0,
                z: 0.0,
            },
        }));
        for (az, el, r, bad) in [(0.0, 0.0, 2.0, 0), (0.3, 0.1, 5.0, 1)] {
            let v = |c| RecordValue::Double(c);
            b.add_point(vec![v(az), v(el), v(r), RecordValue::Integer(bad)])
                .unwrap();
        }
        b.finalize().unwrap();
        w.finalize().unwrap();
        drop(w);
        out.into_inner()
    }

    #[test]
    fn scans_in_the_common_frame_without_invalid_points() {
        let bytes = file();
        assert!(sniff(&bytes));
        let mut left_out = None;
        let (p, t, _) = read_counting(&bytes, &mut left_out, &mut Progress::none()).unwrap();
        assert!(t.is_empty());
        assert_eq!(left_out.map(|l| l.points), Some(2));
        // Scan b's point: 2 along its x axis, turned to its frame's y, moved by (10, 0, 0).
        let want = [
            DVec3::new(1.0, 2.0, 3.0),
            DVec3::new(7.0, 8.0, 9.0),
            DVec3::new(10.0, 2.0, 0.0),
        ];
        assert_eq!(p.len(), want.len());
        for (a, b) in p.iter().zip(want) {
            assert!((*a - b).length() < 1e-12, "{a} against {b}");
        }
    }

    #[test]
    fn damaged_files_are_errors_not_panics() {
        let bytes = file();
        for cut in (0..bytes.len()).step_by(97) {
            assert!(read(&bytes[..cut]).is_err(), "cut at {cut}");
        }
        // A flipped byte breaks a page's checksum (or the XML): an error, never a panic.
        for at in (0..bytes.len()).step_by(61) {
            let mut b = bytes.clone();
            b[at] ^= 0x21;
            let _ = read(&b);
        }
    }
}
