//! Sniffs the format of a file from its content, using the file name only where the content is
//! ambiguous (users rename files, browsers drop files with odd names, and some formats — binary
//! STL — have no magic number at all).
//!
//! Order: unmistakable signatures first (GLB magic, LAS's `LASF`, E57's `ASTM-E57`, a PCD header, `ply` line, a binary STL whose size matches its
//! triangle count exactly), then the extension for formats that may be binary, then a text check
//! (binary garbage under a text extension is rejected here with the offending byte), then text
//! signatures, then the extension, then a look at the first lines (OBJ keywords vs. number rows).

use super::error::{Format, IoError, Location};
use super::text::{first_binary_byte, parse_f64, trim, Lines};

/// How many bytes are inspected for binary content and how many lines for OBJ/XYZ sniffing.
const SNIFF_BYTES: usize = 4096;
const SNIFF_LINES: usize = 200;

/// The lower-cased extension of a file name, if it has one.
pub fn extension(file_name: &str) -> Option<String> {
    let base = file_name.rsplit(['/', '\\']).next().unwrap_or(file_name);
    let (stem, ext) = base.rsplit_once('.')?;
    (!stem.is_empty() && !ext.is_empty()).then(|| ext.to_ascii_lowercase())
}

/// True if `bytes` look like a binary STL: 80-byte header, triangle count, and exactly
/// 50 bytes per triangle after it.
pub(crate) fn is_exact_binary_stl(bytes: &[u8]) -> bool {
    if bytes.len() < 84 {
        return false;
    }
    let n = u32::from_le_bytes([bytes[80], bytes[81], bytes[82], bytes[83]]) as u64;
    84 + 50 * n == bytes.len() as u64
}

/// Determines the format of `bytes`; `file_name` (any path form) is a hint.
pub fn detect(bytes: &[u8], file_name: Option<&str>) -> Result<Format, IoError> {
    let by_ext = file_name.and_then(Format::from_file_name);
    if bytes.is_empty() {
        return Err(IoError::Empty { format: by_ext });
    }
    if bytes.starts_with(b"glTF") {
        return Ok(Format::Glb);
    }
    // Volumes: NIfTI's binary header, gzip (only NIfTI is stored as a whole-file gzip among the
    // formats read here), NRRD's magic line, VTK XML ImageData (may hold raw appended bytes), and
    // MetaImage's first key (an .mha holds binary data after its text header).
    if super::nifti::sniff(bytes) || super::volume::is_gzip(bytes) {
        return Ok(Format::Nifti);
    }
    if super::nrrd::sniff(bytes) {
        return Ok(Format::Nrrd);
    }
    if super::vti::sniff(bytes) {
        return Ok(Format::Vti);
    }
    if super::metaimage::sniff(bytes) {
        return Ok(Format::MetaImage);
    }
    if super::las::sniff(bytes) {
        return Ok(Format::Las);
    }
    if super::e57::sniff(bytes) {
        return Ok(Format::E57);
    }
    // Before the text check: a binary PCD's points follow a text header.
    if super::pcd::sniff(bytes) {
        return Ok(Format::Pcd);
    }
    if bytes.starts_with(b"ply\n") || bytes.starts_with(b"ply\r") {
        return Ok(Format::Ply);
    }
    if is_exact_binary_stl(bytes) {
        return Ok(Format::Stl);
    }
    // Formats that may be binary: let their own reader explain what is wrong.
    if let Some(
        f @ (Format::Glb | Format::Ply | Format::Stl | Format::Pcd | Format::Las | Format::E57),
    ) = by_ext
    {
        return Ok(f);
    }
    if let Some(f) = by_ext.filter(|f| f.is_volume()) {
        return Ok(f);
    }
    if let Some((at, b)) = first_binary_byte(bytes, SNIFF_BYTES) {
        let found = format!("binary data (byte 0x{b:02x})");
        return Err(match by_ext {
            Some(format) => IoError::syntax(format, Location::Byte(at), "text", found),
            None => IoError::UnknownFormat {
                reason: format!("no known signature and {found} at byte {at}"),
            },
        });
    }
    let start = bytes.strip_prefix(b"\xEF\xBB\xBF").unwrap_or(bytes);
    let start = trim(&start[..start.len().min(SNIFF_BYTES)]);
    let first_word: &[u8] = start
        .split(|b| b.is_ascii_whitespace())
        .next()
        .unwrap_or(b"");
    if start.starts_with(b"{") {
        return Ok(Format::Gltf);
    }
    if start.starts_with(b"# vtk DataFile") {
        return Ok(Format::Vtk);
    }
    if first_word.ends_with(b"OFF") && first_word.len() <= 6 {
        return Ok(Format::Off);
    }
    if first_word == b"solid" {
        return Ok(Format::Stl);
    }
    // Before the extension: a PTX export renamed .txt or .xyz would read as a point list whose
    // header lines are points.
    if super::ptx::sniff(bytes) {
        return Ok(Format::Ptx);
    }
    if let Some(f) = by_ext {
        return Ok(f);
    }
    for (_, line) in Lines::new(bytes, 0, 1).take(SNIFF_LINES) {
        let line = trim(line);
        let mut w = line.split(|b| b.is_ascii_whitespace() || *b == b',' || *b == b';');
        let head = w.next().unwrap_or(b"");
        if matches!(
            head,
            b"v" | b"f" | b"vn" | b"vt" | b"o" | b"g" | b"mtllib" | b"usemtl"
        ) {
            return Ok(Format::Obj);
        }
        if parse_f64(head).is_some()
            && line
                .split(|b| b.is_ascii_whitespace() || *b == b',' || *b == b';')
                .filter(|t| !t.is_empty())
                .take(3)
                .filter(|t| parse_f64(t).is_some())
                .count()
                == 3
        {
            return Ok(Format::Xyz);
        }
    }
    Err(IoError::UnknownFormat {
        reason: format!(
            "the content starts with {} and the file name has no known extension",
            super::text::show(&start[..start.len().min(20)])
        ),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn signatures_and_extensions() {
        assert_eq!(detect(b"ply\nformat", None), Ok(Format::Ply));
        assert_eq!(detect(b"glTF\x02\0\0\0", None), Ok(Format::Glb));
        assert_eq!(detect(b"OFF\n3 1 0\n", None), Ok(Format::Off));
        assert_eq!(detect(b"COFF\n", None), Ok(Format::Off));
        assert_eq!(detect(b"solid x\nfacet", None), Ok(Format::Stl));
        assert_eq!(detect(b"  {\"asset\":{}}", None), Ok(Format::Gltf));
        assert_eq!(detect(b"# comment\nv 1 2 3\n", None), Ok(Format::Obj));
        assert_eq!(detect(b"x,y,z\n1,2,3\n", None), Ok(Format::Xyz));
        assert_eq!(detect(b"LASF\0\0", None), Ok(Format::Las));
        assert_eq!(detect(b"ASTM-E57\0\0", None), Ok(Format::E57));
        let ptx =
            b"2\n1\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n1 0 0 0\n0 1 0 0\n0 0 1 0\n0 0 0 1\n1 2 3 0\n";
        assert_eq!(detect(ptx, Some("scan.txt")), Ok(Format::Ptx));
        assert_eq!(detect(b"# .PCD v.7\nVERSION .7\n", None), Ok(Format::Pcd));
        assert_eq!(detect(b"FIELDS x y z\nSIZE 4 4 4\n", None), Ok(Format::Pcd));
        assert_eq!(detect(b"1 2 3\n", Some("a.obj")), Ok(Format::Obj));
        assert!(matches!(
            detect(b"", Some("a.glb")),
            Err(IoError::Empty {
                format: Some(Format::Glb)
            })
        ));
        assert!(matches!(
            detect(b"\xff\xfe\0\x01", Some("x.obj")),
            Err(IoError::Syntax {
                format: Format::Obj,
                ..
            })
        ));
        assert_eq!(extension("dir.v2/file.PLY").as_deref(), Some("ply"));
        assert_eq!(extension(".hidden"), None);
    }
}
