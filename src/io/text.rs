//! Shared helpers of the text readers: line and token iteration over raw bytes with 1-based line
//! numbers, number parsing, and printable excerpts for error messages.
//!
//! Readers work on `&[u8]`, not `&str`, so one stray non-UTF-8 byte in a comment does not reject a
//! whole file, and no copy of the input is made.

/// Iterates over lines as `(line_number, bytes)`, 1-based, without the `\n` / `\r\n` ending.
pub(crate) struct Lines<'a> {
    data: &'a [u8],
    pos: usize,
    line: usize,
}

impl<'a> Lines<'a> {
    /// Lines of `data` starting at byte `pos`, which is on line `line` (1-based).
    pub(crate) fn new(data: &'a [u8], pos: usize, line: usize) -> Self {
        Self { data, pos, line }
    }

    /// Byte offset of the next line's start.
    pub(crate) fn pos(&self) -> usize {
        self.pos
    }

    /// Line number the next returned line will have.
    pub(crate) fn line(&self) -> usize {
        self.line
    }
}

impl<'a> Iterator for Lines<'a> {
    type Item = (usize, &'a [u8]);

    fn next(&mut self) -> Option<Self::Item> {
        if self.pos >= self.data.len() {
            return None;
        }
        let rest = &self.data[self.pos..];
        let (mut l, adv) = match rest.iter().position(|&b| b == b'\n') {
            Some(i) => (&rest[..i], i + 1),
            None => (rest, rest.len()),
        };
        if let [head @ .., b'\r'] = l {
            l = head;
        }
        self.pos += adv;
        let n = self.line;
        self.line += 1;
        Some((n, l))
    }
}

/// Whitespace-separated tokens of one line.
pub(crate) fn words(line: &[u8]) -> impl Iterator<Item = &[u8]> {
    line.split(|b| b.is_ascii_whitespace())
        .filter(|t| !t.is_empty())
}

/// The line with leading/trailing ASCII whitespace removed.
pub(crate) fn trim(line: &[u8]) -> &[u8] {
    line.trim_ascii()
}

/// Tokens across lines (whitespace-separated), tracking line numbers; `#` starts a comment to
/// the end of the line when `comments` is set.
pub(crate) struct Tokens<'a> {
    data: &'a [u8],
    pos: usize,
    line: usize,
    comments: bool,
}

impl<'a> Tokens<'a> {
    /// Tokens of `data` from byte `pos`, which is on line `line`.
    pub(crate) fn new(data: &'a [u8], pos: usize, line: usize, comments: bool) -> Self {
        Self {
            data,
            pos,
            line,
            comments,
        }
    }

    /// Current line (of the last token returned, or where reading stands).
    pub(crate) fn line(&self) -> usize {
        self.line
    }

    /// Bytes not yet consumed.
    pub(crate) fn remaining(&self) -> usize {
        self.data.len() - self.pos
    }

    /// The next token, or `None` at the end of the data.
    pub(crate) fn next_token(&mut self) -> Option<&'a [u8]> {
        let d = self.data;
        loop {
            while self.pos < d.len() && d[self.pos].is_ascii_whitespace() {
                if d[self.pos] == b'\n' {
                    self.line += 1;
                }
                self.pos += 1;
            }
            if self.comments && self.pos < d.len() && d[self.pos] == b'#' {
                while self.pos < d.len() && d[self.pos] != b'\n' {
                    self.pos += 1;
                }
                continue;
            }
            break;
        }
        if self.pos >= d.len() {
            return None;
        }
        let start = self.pos;
        while self.pos < d.len() && !d[self.pos].is_ascii_whitespace() {
            self.pos += 1;
        }
        Some(&d[start..self.pos])
    }
}

/// Parses a decimal or scientific floating-point token (also `nan`/`inf`, which the readers then
/// reject with the vertex index).
#[inline]
pub(crate) fn parse_f64(tok: &[u8]) -> Option<f64> {
    std::str::from_utf8(tok).ok()?.parse().ok()
}

/// Parses a (possibly signed) integer token.
#[inline]
pub(crate) fn parse_i64(tok: &[u8]) -> Option<i64> {
    std::str::from_utf8(tok).ok()?.parse().ok()
}

/// A short printable excerpt of `tok` for error messages (quoted, at most 40 characters).
pub(crate) fn show(tok: &[u8]) -> String {
    if let Some((i, b)) = first_binary_byte(tok, 40) {
        return format!("binary data (byte 0x{b:02x} at offset {i} of the token)");
    }
    let s = String::from_utf8_lossy(&tok[..tok.len().min(40)]);
    let clean: String = s
        .chars()
        .map(|c| if c.is_control() { '?' } else { c })
        .collect();
    if tok.len() > 40 {
        format!("\"{clean}…\"")
    } else {
        format!("\"{clean}\"")
    }
}

/// Offset and value of the first byte that cannot occur in a text file (NUL, or a byte that
/// breaks UTF-8), looking at the first `limit` bytes.
pub(crate) fn first_binary_byte(data: &[u8], limit: usize) -> Option<(usize, u8)> {
    let head = &data[..data.len().min(limit)];
    if let Some(i) = head.iter().position(|&b| b == 0) {
        return Some((i, 0));
    }
    match std::str::from_utf8(head) {
        Ok(_) => None,
        // A multi-byte character cut by the limit is not an error.
        Err(e) if e.error_len().is_none() && head.len() < data.len() => None,
        Err(e) => Some((e.valid_up_to(), head[e.valid_up_to()])),
    }
}
