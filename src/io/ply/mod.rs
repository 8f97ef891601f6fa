//! Stanford PLY: reader (ASCII, binary little- and big-endian) and binary little-endian writer.
//!
//! Hand-written rather than using a crate: the PLY crates build a dynamic property map per
//! element (one allocation per vertex), which is far too slow for a million points,
//! and do not report byte offsets or bound their allocations by the file size. Here the vertex
//! records are read in place from the input slice (no copy), element counts are checked against
//! the bytes that follow the header before anything is allocated, and every error names the line
//! (header, ASCII body) or byte offset (binary body).
//!
//! The vertex element must have scalar `x`, `y`, `z` properties (any numeric type); all other
//! properties and elements are skipped. A `face` element's `vertex_indices` (or `vertex_index`)
//! list is fan-triangulated. No face element (or zero faces) means a point cloud.

use super::error::{Format, IoError, Location};
use super::{Encoding, RawGeometry};
use crate::progress::Progress;
use glam::DVec3;

mod ascii;
mod binary;
mod header;
mod write;

use ascii::parse_ascii;
use binary::parse_binary;
use header::parse_header;
pub(crate) use write::header_name;
pub use write::write;

const F: Format = Format::Ply;

/// A PLY scalar type.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Scalar {
    I8,
    U8,
    I16,
    U16,
    I32,
    U32,
    F32,
    F64,
}

impl Scalar {
    fn parse(name: &[u8]) -> Option<Scalar> {
        Some(match name {
            b"char" | b"int8" => Scalar::I8,
            b"uchar" | b"uint8" => Scalar::U8,
            b"short" | b"int16" => Scalar::I16,
            b"ushort" | b"uint16" => Scalar::U16,
            b"int" | b"int32" => Scalar::I32,
            b"uint" | b"uint32" => Scalar::U32,
            b"float" | b"float32" => Scalar::F32,
            b"double" | b"float64" => Scalar::F64,
            _ => return None,
        })
    }

    fn size(self) -> usize {
        match self {
            Scalar::I8 | Scalar::U8 => 1,
            Scalar::I16 | Scalar::U16 => 2,
            Scalar::I32 | Scalar::U32 | Scalar::F32 => 4,
            Scalar::F64 => 8,
        }
    }

    fn is_integer(self) -> bool {
        !matches!(self, Scalar::F32 | Scalar::F64)
    }

    /// Reads one value from the start of `b` (which holds at least `size()` bytes).
    #[inline(always)]
    fn get(self, b: &[u8], big_endian: bool) -> f64 {
        macro_rules! rd {
            ($t:ty, $n:expr) => {{
                let mut a = [0u8; $n];
                a.copy_from_slice(&b[..$n]);
                if big_endian {
                    <$t>::from_be_bytes(a) as f64
                } else {
                    <$t>::from_le_bytes(a) as f64
                }
            }};
        }
        match self {
            Scalar::I8 => b[0] as i8 as f64,
            Scalar::U8 => b[0] as f64,
            Scalar::I16 => rd!(i16, 2),
            Scalar::U16 => rd!(u16, 2),
            Scalar::I32 => rd!(i32, 4),
            Scalar::U32 => rd!(u32, 4),
            Scalar::F32 => rd!(f32, 4),
            Scalar::F64 => rd!(f64, 8),
        }
    }

    /// Reads an integer (list count or index); integer types only.
    #[inline(always)]
    fn get_int(self, b: &[u8], big_endian: bool) -> i64 {
        self.get(b, big_endian) as i64
    }
}

#[derive(Clone, Debug)]
enum Kind {
    Scalar(Scalar),
    List { count: Scalar, item: Scalar },
}

#[derive(Clone, Debug)]
struct Property {
    name: Vec<u8>,
    kind: Kind,
}

#[derive(Clone, Debug)]
struct Element {
    name: Vec<u8>,
    count: u64,
    props: Vec<Property>,
    line: usize,
}

impl Element {
    /// Smallest number of bytes one record can take in the body (for the count check).
    fn min_bytes(&self, enc: Encoding) -> u128 {
        match enc {
            // Every value is at least one character plus one separator.
            Encoding::Ascii => 2 * self.props.len() as u128,
            _ => self
                .props
                .iter()
                .map(|p| match p.kind {
                    Kind::Scalar(s) => s.size(),
                    Kind::List { count, .. } => count.size(),
                } as u128)
                .sum(),
        }
    }

    fn fixed_stride(&self) -> Option<usize> {
        self.props
            .iter()
            .map(|p| match p.kind {
                Kind::Scalar(s) => Some(s.size()),
                Kind::List { .. } => None,
            })
            .sum()
    }
}

struct Header {
    encoding: Encoding,
    elements: Vec<Element>,
    body: usize,
    body_line: usize,
}

/// What to extract from the vertex element.
struct VertexLayout {
    xyz: [usize; 3],
    extra: Option<usize>,
}

/// What the body parse produced.
struct Parsed {
    points: Vec<DVec3>,
    triangles: Vec<[u32; 3]>,
    extra: Option<Vec<f64>>,
}

/// Reads a PLY file into points and (fan-triangulated) triangles.
pub fn read(bytes: &[u8]) -> Result<RawGeometry, IoError> {
    read_progress(bytes, &mut Progress::none())
}

/// [`read`], reporting the share of the file read to `progress`.
pub fn read_progress(bytes: &[u8], progress: &mut Progress) -> Result<RawGeometry, IoError> {
    let h = parse_header(bytes)?;
    let p = parse_body(bytes, &h, None, progress)?;
    Ok((p.points, p.triangles, h.encoding))
}

/// Reads the named per-vertex scalar property (e.g. one written by [`write()`]) as `f64`s.
pub fn read_vertex_property(bytes: &[u8], name: &str) -> Result<Vec<f64>, IoError> {
    let h = parse_header(bytes)?;
    let p = parse_body(bytes, &h, Some(name.as_bytes()), &mut Progress::none())?;
    Ok(p.extra.unwrap_or_default())
}

fn vertex_layout(el: &Element, extra: Option<&[u8]>) -> Result<VertexLayout, IoError> {
    let find = |name: &[u8]| -> Result<usize, IoError> {
        match el.props.iter().position(|p| p.name == name) {
            Some(i) if matches!(el.props[i].kind, Kind::Scalar(_)) => Ok(i),
            Some(_) => Err(IoError::syntax(
                F,
                Location::Line(el.line),
                format!("a scalar property {}", String::from_utf8_lossy(name)),
                "a list",
            )),
            None => Err(IoError::syntax(
                F,
                Location::Line(el.line),
                format!(
                    "a property {} on element vertex",
                    String::from_utf8_lossy(name)
                ),
                "none",
            )),
        }
    };
    Ok(VertexLayout {
        xyz: [find(b"x")?, find(b"y")?, find(b"z")?],
        extra: match extra {
            Some(n) => Some(find(n)?),
            None => None,
        },
    })
}

fn check_counts(bytes: &[u8], h: &Header) -> Result<(), IoError> {
    let available = bytes.len() - h.body;
    let slack = if h.encoding == Encoding::Ascii { 1 } else { 0 };
    let mut needed: u128 = 0;
    for el in &h.elements {
        needed += el.count as u128 * el.min_bytes(h.encoding);
        if needed > (available + slack) as u128 {
            return Err(IoError::CountTooLarge {
                format: F,
                at: Location::Line(el.line),
                element: format!("\"{}\" elements", String::from_utf8_lossy(&el.name)),
                count: el.count,
                available,
                needed,
            });
        }
    }
    Ok(())
}

fn parse_body(
    bytes: &[u8],
    h: &Header,
    extra: Option<&[u8]>,
    progress: &mut Progress,
) -> Result<Parsed, IoError> {
    check_counts(bytes, h)?;
    let Some(vi) = h.elements.iter().position(|e| e.name == b"vertex") else {
        return Err(IoError::syntax(
            F,
            Location::Line(h.body_line.saturating_sub(1)),
            "an \"element vertex\" in the header",
            "none",
        ));
    };
    let layout = vertex_layout(&h.elements[vi], extra)?;
    let nv = h.elements[vi].count;
    if nv > u32::MAX as u64 {
        return Err(IoError::Unsupported {
            format: F,
            what: format!("{nv} vertices (more than 2^32)"),
        });
    }
    // The counts were checked against the file size, so these capacities are bounded by it.
    let mut out = Parsed {
        points: Vec::with_capacity(nv as usize),
        triangles: Vec::new(),
        extra: extra.map(|_| Vec::with_capacity(nv as usize)),
    };
    match h.encoding {
        Encoding::Ascii => parse_ascii(bytes, h, vi, &layout, &mut out, progress)?,
        enc => {
            let be = enc == Encoding::BinaryBe;
            parse_binary(bytes, h, vi, &layout, be, &mut out, progress)?
        }
    }
    Ok(out)
}

/// Index of the face list property of a `face` element, if the element is a face element.
fn face_list(el: &Element) -> Result<Option<usize>, IoError> {
    if el.name != b"face" {
        return Ok(None);
    }
    let lists = |n: &[u8]| {
        el.props
            .iter()
            .position(|p| p.name == n && matches!(p.kind, Kind::List { .. }))
    };
    let i = lists(b"vertex_indices")
        .or_else(|| lists(b"vertex_index"))
        .or_else(|| {
            el.props
                .iter()
                .position(|p| matches!(p.kind, Kind::List { .. }))
        });
    match i {
        Some(i) => {
            if let Kind::List { item, .. } = el.props[i].kind {
                if !item.is_integer() {
                    return Err(IoError::syntax(
                        F,
                        Location::Line(el.line),
                        "an integer type for face vertex indices",
                        "a floating-point type",
                    ));
                }
            }
            Ok(Some(i))
        }
        None if el.count == 0 => Ok(None),
        None => Err(IoError::syntax(
            F,
            Location::Line(el.line),
            "a list property vertex_indices on element face",
            "no list property",
        )),
    }
}

/// Fan-triangulates one face given its vertex indices, checking them.
#[inline]
fn push_face(
    tris: &mut Vec<[u32; 3]>,
    idx: &[i64],
    nv: u64,
    face: usize,
    at: Location,
) -> Result<(), IoError> {
    if idx.len() < 3 {
        return Err(IoError::syntax(
            F,
            at,
            format!("face {face} with at least 3 vertices"),
            format!("{} vertices", idx.len()),
        ));
    }
    for &i in idx {
        if i < 0 || i as u64 >= nv {
            return Err(IoError::IndexOutOfRange {
                format: F,
                at,
                face,
                index: i,
                count: nv as usize,
            });
        }
    }
    for k in 1..idx.len() - 1 {
        tris.push([idx[0] as u32, idx[k] as u32, idx[k + 1] as u32]);
    }
    Ok(())
}

fn non_finite(at: Location, index: usize, p: DVec3) -> IoError {
    IoError::NonFinite {
        format: F,
        at,
        index,
        x: p.x,
        y: p.y,
        z: p.z,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ascii_with_extra_properties_and_quads() {
        let src = b"ply\nformat ascii 1.0\ncomment hi\nelement vertex 4\nproperty float x\nproperty uchar red\nproperty double y\nproperty int z\nelement face 1\nproperty uchar flags\nproperty list uchar int vertex_indices\nend_header\n0 255 0 0\n1 0 0 0\n1 1 1 0\n0 2 1 0\n7 4 0 1 2 3\n";
        let (p, t, e) = read(src).unwrap();
        assert_eq!(e, Encoding::Ascii);
        assert_eq!(p.len(), 4);
        assert_eq!(p[2], DVec3::new(1.0, 1.0, 0.0));
        assert_eq!(t, vec![[0, 1, 2], [0, 2, 3]]);
    }

    #[test]
    fn binary_big_endian_with_list_in_vertex() {
        let mut b = b"ply\nformat binary_big_endian 1.0\nelement vertex 2\nproperty double x\nproperty list uchar float junk\nproperty float y\nproperty short z\nend_header\n".to_vec();
        for (x, y, z) in [(1.5f64, 2.5f32, -3i16), (4.0, 5.0, 6)] {
            b.extend_from_slice(&x.to_be_bytes());
            b.push(2);
            b.extend_from_slice(&[0; 8]);
            b.extend_from_slice(&y.to_be_bytes());
            b.extend_from_slice(&z.to_be_bytes());
        }
        let (p, t, _) = read(&b).unwrap();
        assert!(t.is_empty());
        assert_eq!(
            p,
            vec![DVec3::new(1.5, 2.5, -3.0), DVec3::new(4.0, 5.0, 6.0)]
        );
    }
}
