//! The binary PLY body (little- or big-endian): fixed-size vertex records are read in place,
//! other elements record by record.

use super::{
    face_list, non_finite, push_face, Element, Header, Kind, Parsed, Scalar, VertexLayout, F,
};
use crate::io::error::{IoError, Location};
use crate::io::{READING, REPORT_EVERY};
use crate::progress::Progress;
use glam::DVec3;

/// A binary body being read: the input and its header, where reading is, and the output.
struct Body<'a, 'o, 'p> {
    bytes: &'a [u8],
    h: &'a Header,
    /// Index of the vertex element.
    vi: usize,
    layout: &'a VertexLayout,
    be: bool,
    pos: usize,
    /// Reused buffer for one face's indices.
    idx: Vec<i64>,
    out: &'o mut Parsed,
    progress: &'o mut Progress<'p>,
}

/// Reads the binary body after the header into `out`.
pub(super) fn parse_binary(
    bytes: &[u8],
    h: &Header,
    vi: usize,
    layout: &VertexLayout,
    be: bool,
    out: &mut Parsed,
    progress: &mut Progress,
) -> Result<(), IoError> {
    let mut body = Body {
        bytes,
        h,
        vi,
        layout,
        be,
        pos: h.body,
        idx: Vec::new(),
        out,
        progress,
    };
    for (ei, el) in h.elements.iter().enumerate() {
        let stride = el.fixed_stride();
        if ei == vi {
            if let Some(stride) = stride {
                body.fixed_vertices(el, stride)?;
                continue;
            }
        } else if let (Some(stride), None) = (stride, face_list(el)?) {
            body.skip_fixed(el, stride)?;
            continue;
        }
        let flist = if ei == vi { None } else { face_list(el)? };
        body.records(ei, el, flist)?;
    }
    Ok(())
}

impl<'a> Body<'a, '_, '_> {
    /// The share of the file before byte `pos`.
    fn share(&self, pos: usize) -> f64 {
        pos as f64 / self.bytes.len() as f64
    }

    /// Fast path: reads fixed-size vertex records of `stride` bytes in place.
    fn fixed_vertices(&mut self, el: &Element, stride: usize) -> Result<(), IoError> {
        let (bytes, pos, be) = (self.bytes, self.pos, self.be);
        let offs: Vec<(usize, Scalar)> = el
            .props
            .iter()
            .scan(0usize, |o, p| {
                let Kind::Scalar(s) = p.kind else {
                    unreachable!("fixed stride has scalars only")
                };
                let r = (*o, s);
                *o += s.size();
                Some(r)
            })
            .collect();
        let n = el.count as usize;
        let len = n * stride;
        if bytes.len() - pos < len {
            return Err(IoError::truncated(
                F,
                Location::Byte(bytes.len()),
                format!("{n} vertex records of {stride} bytes from byte {pos}"),
            ));
        }
        let [(ox, tx), (oy, ty), (oz, tz)] = self.layout.xyz.map(|i| offs[i]);
        for (i, rec) in bytes[pos..pos + len].chunks_exact(stride).enumerate() {
            if i % REPORT_EVERY == 0 {
                let share = self.share(pos + i * stride);
                self.progress.report(READING, share);
            }
            let p = DVec3::new(
                tx.get(&rec[ox..], be),
                ty.get(&rec[oy..], be),
                tz.get(&rec[oz..], be),
            );
            if !p.is_finite() {
                return Err(non_finite(Location::Byte(pos + i * stride), i, p));
            }
            self.out.points.push(p);
            if let (Some(e), Some(v)) = (self.layout.extra, self.out.extra.as_mut()) {
                let (o, t) = offs[e];
                v.push(t.get(&rec[o..], be));
            }
        }
        self.pos += len;
        Ok(())
    }

    /// Skips an element of fixed-size records of `stride` bytes that is not read.
    fn skip_fixed(&mut self, el: &Element, stride: usize) -> Result<(), IoError> {
        let len = el.count as u128 * stride as u128;
        if ((self.bytes.len() - self.pos) as u128) < len {
            return Err(IoError::truncated(
                F,
                Location::Byte(self.bytes.len()),
                format!(
                    "{} \"{}\" records of {stride} bytes",
                    el.count,
                    String::from_utf8_lossy(&el.name)
                ),
            ));
        }
        self.pos += len as usize;
        Ok(())
    }

    /// Reads element `ei` record by record: vertices when it is the vertex element, faces from
    /// the list property `flist`, and everything else skipped.
    fn records(&mut self, ei: usize, el: &Element, flist: Option<usize>) -> Result<(), IoError> {
        let (be, is_vertex) = (self.be, ei == self.vi);
        if flist.is_some() {
            self.out.triangles.reserve(el.count as usize);
        }
        let mut vals = [0f64; 3];
        for r in 0..el.count as usize {
            if r % REPORT_EVERY == 0 {
                let share = self.share(self.pos);
                self.progress.report(READING, share);
            }
            let rec_start = self.pos;
            let mut extra_val = 0.0;
            for (pi, p) in el.props.iter().enumerate() {
                match p.kind {
                    Kind::Scalar(s) => {
                        let b = self.scalar_bytes(el, r, &p.name, s)?;
                        if is_vertex {
                            if let Some(k) = self.layout.xyz.iter().position(|&x| x == pi) {
                                vals[k] = s.get(b, be);
                            }
                            if self.layout.extra == Some(pi) {
                                extra_val = s.get(b, be);
                            }
                        }
                    }
                    Kind::List { count, item } => {
                        self.list(el, r, count, item, flist == Some(pi))?;
                    }
                }
            }
            if is_vertex {
                let p = DVec3::from_array(vals);
                if !p.is_finite() {
                    return Err(non_finite(Location::Byte(rec_start), r, p));
                }
                self.out.points.push(p);
                if let Some(v) = self.out.extra.as_mut() {
                    v.push(extra_val);
                }
            }
        }
        Ok(())
    }

    /// The bytes of scalar property `name` (type `s`) of record `r`, moving past them.
    fn scalar_bytes(
        &mut self,
        el: &Element,
        r: usize,
        name: &[u8],
        s: Scalar,
    ) -> Result<&'a [u8], IoError> {
        let pos = self.pos;
        let Some(b) = self.bytes.get(pos..pos + s.size()) else {
            return Err(IoError::truncated(
                F,
                Location::Byte(pos),
                format!(
                    "property {} of {} {r} of {}",
                    String::from_utf8_lossy(name),
                    String::from_utf8_lossy(&el.name),
                    el.count
                ),
            ));
        };
        self.pos += s.size();
        Ok(b)
    }

    /// Reads a list property of record `r`, moving past it; a `face` list becomes triangles.
    fn list(
        &mut self,
        el: &Element,
        r: usize,
        count: Scalar,
        item: Scalar,
        face: bool,
    ) -> Result<(), IoError> {
        let (bytes, be) = (self.bytes, self.be);
        let ename = || String::from_utf8_lossy(&el.name);
        let Some(b) = bytes.get(self.pos..self.pos + count.size()) else {
            return Err(IoError::truncated(
                F,
                Location::Byte(self.pos),
                format!("the list length of {} {r} of {}", ename(), el.count),
            ));
        };
        let n = count.get_int(b, be);
        let list_at = self.pos;
        self.pos += count.size();
        let pos = self.pos;
        let len = (n.max(0) as u128) * item.size() as u128;
        if n < 0 || ((bytes.len() - pos) as u128) < len {
            return Err(IoError::truncated(
                F,
                Location::Byte(list_at),
                format!(
                    "{n} list items of {} {r} of {} ({} bytes left)",
                    ename(),
                    el.count,
                    bytes.len() - pos
                ),
            ));
        }
        let len = len as usize;
        if face {
            self.idx.clear();
            self.idx.extend(
                bytes[pos..pos + len]
                    .chunks_exact(item.size())
                    .map(|c| item.get_int(c, be)),
            );
            push_face(
                &mut self.out.triangles,
                &self.idx,
                self.h.elements[self.vi].count,
                r,
                Location::Byte(list_at),
            )?;
        }
        self.pos += len;
        Ok(())
    }
}
