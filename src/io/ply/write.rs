//! The PLY writer: binary little-endian with one float property per scalar.

use super::F;
use crate::io::error::IoError;
use crate::io::WriteInput;

/// Makes a name safe for a PLY/VTK header (no whitespace).
pub(crate) fn header_name(name: &str) -> String {
    name.chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() || c == '_' || c == '-' || c == '.' {
                c
            } else {
                '_'
            }
        })
        .collect()
}

/// Writes binary little-endian PLY: float x, y, z, one float property per named scalar, and a
/// `uchar int vertex_indices` face list. Comments record the LSW version and settings.
pub fn write(input: &WriteInput) -> Result<Vec<u8>, IoError> {
    input.check(F)?;
    let names: Vec<String> = input.scalars.iter().map(|(n, _)| header_name(n)).collect();
    for (i, n) in names.iter().enumerate() {
        if ["x", "y", "z"].contains(&n.as_str()) || names[..i].contains(n) {
            return Err(IoError::InvalidInput {
                format: F,
                what: format!("scalar name \"{n}\" is used twice or clashes with x, y, z"),
            });
        }
    }
    let mut head = String::from("ply\nformat binary_little_endian 1.0\n");
    head += &format!("comment written by LSW {}\n", crate::VERSION);
    if let Some(s) = input.settings_compact(F)? {
        head += &format!("comment settings {s}\n");
    }
    head += &format!(
        "element vertex {}\nproperty float x\nproperty float y\nproperty float z\n",
        input.positions.len()
    );
    for n in &names {
        head += &format!("property float {n}\n");
    }
    head += &format!(
        "element face {}\nproperty list uchar int vertex_indices\nend_header\n",
        input.triangles.len()
    );
    let stride = 12 + 4 * names.len();
    let mut out = Vec::with_capacity(
        head.len() + input.positions.len() * stride + 13 * input.triangles.len(),
    );
    out.extend_from_slice(head.as_bytes());
    for (i, p) in input.positions.iter().enumerate() {
        for c in p.to_array() {
            out.extend_from_slice(&(c as f32).to_le_bytes());
        }
        for (_, s) in input.scalars {
            out.extend_from_slice(&(s[i] as f32).to_le_bytes());
        }
    }
    for t in input.triangles {
        out.push(3);
        for &v in t {
            out.extend_from_slice(&(v as i32).to_le_bytes());
        }
    }
    Ok(out)
}
