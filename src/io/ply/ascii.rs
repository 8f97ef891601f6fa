//! The ASCII PLY body: one record per (non-blank) line.

use super::Kind;
use super::{face_list, non_finite, push_face, Header, Parsed, VertexLayout, F};
use crate::io::error::{IoError, Location};
use crate::io::text::{parse_f64, parse_i64, show, words, Lines};
use crate::io::{READING, REPORT_EVERY};
use crate::progress::Progress;
use glam::DVec3;

/// Reads the ASCII body after the header into `out`.
pub(super) fn parse_ascii(
    bytes: &[u8],
    h: &Header,
    vi: usize,
    layout: &VertexLayout,
    out: &mut Parsed,
    progress: &mut Progress,
) -> Result<(), IoError> {
    let mut lines = Lines::new(bytes, h.body, h.body_line);
    let mut idx: Vec<i64> = Vec::new();
    for (ei, el) in h.elements.iter().enumerate() {
        let ename = String::from_utf8_lossy(&el.name);
        let flist = if ei == vi { None } else { face_list(el)? };
        let nprops = el.props.len();
        for r in 0..el.count as usize {
            if r % REPORT_EVERY == 0 {
                progress.report(READING, lines.pos() as f64 / bytes.len() as f64);
            }
            let (n, line) = next_line(&mut lines, &ename, r, el.count)?;
            let at = Location::Line(n);
            let mut toks = words(line);
            let mut vals = [0f64; 3];
            let mut extra_val = 0.0;
            for (pi, p) in el.props.iter().enumerate() {
                let missing = || {
                    IoError::syntax(
                        F,
                        at,
                        format!(
                            "a value for property {} ({nprops} properties per {ename})",
                            String::from_utf8_lossy(&p.name)
                        ),
                        "end of line",
                    )
                };
                let t = toks.next().ok_or_else(missing)?;
                match p.kind {
                    Kind::Scalar(_) => {
                        if ei == vi {
                            let k = layout.xyz.iter().position(|&x| x == pi);
                            if k.is_some() || layout.extra == Some(pi) {
                                let v = parse_f64(t)
                                    .ok_or_else(|| IoError::syntax(F, at, "a number", show(t)))?;
                                if let Some(k) = k {
                                    vals[k] = v;
                                }
                                if layout.extra == Some(pi) {
                                    extra_val = v;
                                }
                            }
                        }
                    }
                    Kind::List { .. } => {
                        let face = flist == Some(pi);
                        list_items(t, &mut toks, face, at, &mut idx)?;
                        if face {
                            push_face(&mut out.triangles, &idx, h.elements[vi].count, r, at)?;
                        }
                    }
                }
            }
            if ei == vi {
                let p = DVec3::from_array(vals);
                if !p.is_finite() {
                    return Err(non_finite(at, r, p));
                }
                out.points.push(p);
                if let Some(v) = out.extra.as_mut() {
                    v.push(extra_val);
                }
            }
        }
    }
    Ok(())
}

/// The next non-blank line, holding record `r` of `count` of element `ename`.
fn next_line<'a>(
    lines: &mut Lines<'a>,
    ename: &str,
    r: usize,
    count: u64,
) -> Result<(usize, &'a [u8]), IoError> {
    loop {
        match lines.next() {
            Some((_, l)) if l.trim_ascii().is_empty() => continue,
            Some(x) => return Ok(x),
            None => {
                return Err(IoError::truncated(
                    F,
                    Location::Line(lines.line()),
                    format!("{ename} {r} of {count}"),
                ))
            }
        }
    }
}

/// Reads a list whose length token is `t` from `toks` into `idx` (parsed as indices when `face`,
/// zeros otherwise).
fn list_items<'t>(
    t: &[u8],
    toks: &mut impl Iterator<Item = &'t [u8]>,
    face: bool,
    at: Location,
    idx: &mut Vec<i64>,
) -> Result<(), IoError> {
    let c = parse_i64(t)
        .filter(|&c| c >= 0)
        .ok_or_else(|| IoError::syntax(F, at, "a list length", show(t)))?;
    idx.clear();
    for _ in 0..c {
        let t = toks.next().ok_or_else(|| {
            IoError::syntax(
                F,
                at,
                format!("{c} list items"),
                format!("{} items", idx.len()),
            )
        })?;
        if face {
            idx.push(
                parse_i64(t)
                    .ok_or_else(|| IoError::syntax(F, at, "an integer vertex index", show(t)))?,
            );
        } else {
            idx.push(0);
        }
    }
    Ok(())
}
