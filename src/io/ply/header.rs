//! The PLY header: format line, elements and their properties up to `end_header`.

use super::{Element, Header, Kind, Property, Scalar, F};
use crate::io::error::{IoError, Location};
use crate::io::text::{parse_i64, show, words, Lines};
use crate::io::Encoding;

/// Reads the header lines from `ply` to `end_header`.
pub(super) fn parse_header(bytes: &[u8]) -> Result<Header, IoError> {
    let mut lines = Lines::new(bytes, 0, 1);
    match lines.next() {
        Some((_, l)) if l.trim_ascii() == b"ply" => {}
        Some((_, l)) => {
            return Err(IoError::syntax(F, Location::Line(1), "\"ply\"", show(l)));
        }
        None => return Err(IoError::Empty { format: Some(F) }),
    }
    let mut encoding = None;
    let mut elements: Vec<Element> = Vec::new();
    while let Some((n, line)) = lines.next() {
        let at = Location::Line(n);
        let w: Vec<&[u8]> = words(line).take(6).collect();
        match w.first().copied() {
            None | Some(b"comment") | Some(b"obj_info") => {}
            Some(b"format") => encoding = Some(parse_format(&w, at)?),
            Some(b"element") => elements.push(parse_element(&w, line, n)?),
            Some(b"property") => {
                let Some(el) = elements.last_mut() else {
                    return Err(IoError::syntax(
                        F,
                        at,
                        "an element line before the first property",
                        show(line),
                    ));
                };
                el.props.push(parse_property(&w, line, at)?);
            }
            Some(b"end_header") => {
                let Some(encoding) = encoding else {
                    return Err(IoError::syntax(
                        F,
                        at,
                        "a \"format\" line before end_header",
                        "end_header",
                    ));
                };
                return Ok(Header {
                    encoding,
                    elements,
                    body: lines.pos(),
                    body_line: lines.line(),
                });
            }
            Some(other) => {
                return Err(IoError::syntax(
                    F,
                    at,
                    "a header keyword (format, comment, element, property, end_header)",
                    show(other),
                ))
            }
        }
    }
    Err(IoError::truncated(
        F,
        Location::Line(lines.line()),
        "\"end_header\"",
    ))
}

/// The body encoding named by a `format` line's words.
fn parse_format(w: &[&[u8]], at: Location) -> Result<Encoding, IoError> {
    Ok(match w.get(1).copied() {
        Some(b"ascii") => Encoding::Ascii,
        Some(b"binary_little_endian") => Encoding::BinaryLe,
        Some(b"binary_big_endian") => Encoding::BinaryBe,
        other => {
            return Err(IoError::syntax(
                F,
                at,
                "ascii, binary_little_endian or binary_big_endian",
                show(other.unwrap_or(b"")),
            ))
        }
    })
}

/// The element (with no properties yet) declared by an `element NAME COUNT` line on line `n`.
fn parse_element(w: &[&[u8]], line: &[u8], n: usize) -> Result<Element, IoError> {
    let (name, count) = match (w.get(1), w.get(2).and_then(|c| parse_i64(c))) {
        (Some(name), Some(c)) if c >= 0 => (name.to_vec(), c as u64),
        _ => {
            return Err(IoError::syntax(
                F,
                Location::Line(n),
                "\"element NAME COUNT\" with a count ≥ 0",
                show(line),
            ))
        }
    };
    Ok(Element {
        name,
        count,
        props: Vec::new(),
        line: n,
    })
}

/// The property declared by a `property TYPE NAME` or `property list COUNT ITEM NAME` line.
fn parse_property(w: &[&[u8]], line: &[u8], at: Location) -> Result<Property, IoError> {
    let bad_type = |t: &[u8]| {
        IoError::syntax(
            F,
            at,
            "a PLY type (char, uchar, short, ushort, int, uint, float, double)",
            show(t),
        )
    };
    if w.get(1).copied() == Some(b"list") {
        let (Some(c), Some(i), Some(name)) = (w.get(2), w.get(3), w.get(4)) else {
            return Err(IoError::syntax(
                F,
                at,
                "\"property list COUNT_TYPE ITEM_TYPE NAME\"",
                show(line),
            ));
        };
        let count = Scalar::parse(c).ok_or_else(|| bad_type(c))?;
        let item = Scalar::parse(i).ok_or_else(|| bad_type(i))?;
        if !count.is_integer() {
            return Err(IoError::syntax(
                F,
                at,
                "an integer list count type",
                show(c),
            ));
        }
        Ok(Property {
            name: name.to_vec(),
            kind: Kind::List { count, item },
        })
    } else {
        let (Some(t), Some(name)) = (w.get(1), w.get(2)) else {
            return Err(IoError::syntax(F, at, "\"property TYPE NAME\"", show(line)));
        };
        Ok(Property {
            name: name.to_vec(),
            kind: Kind::Scalar(Scalar::parse(t).ok_or_else(|| bad_type(t))?),
        })
    }
}
