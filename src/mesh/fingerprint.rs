//! A short fingerprint of a mesh, so a shared link (or a CLI run) can show that it rebuilt the
//! identical result.

use glam::DVec3;

/// 64-bit FNV-1a over the positions rounded to f32 and the triangle indices, as 16 hex digits.
/// f32 rounding makes it insensitive to how the positions are stored, not to real differences.
pub fn mesh_hash(positions: &[DVec3], triangles: &[[u32; 3]]) -> String {
    let mut h: u64 = 0xcbf29ce484222325;
    let mut eat = |bytes: [u8; 4]| {
        for b in bytes {
            h ^= b as u64;
            h = h.wrapping_mul(0x100000001b3);
        }
    };
    for p in positions {
        for c in [p.x, p.y, p.z] {
            eat((c as f32).to_le_bytes());
        }
    }
    for t in triangles {
        for i in t {
            eat(i.to_le_bytes());
        }
    }
    format!("{h:016x}")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn changes_with_any_coordinate_or_index() {
        let p = vec![DVec3::ZERO, DVec3::X, DVec3::Y];
        let h = mesh_hash(&p, &[[0, 1, 2]]);
        assert_eq!(h.len(), 16);
        assert_eq!(h, mesh_hash(&p, &[[0, 1, 2]]));
        assert_ne!(h, mesh_hash(&p, &[[0, 2, 1]]));
        let mut q = p.clone();
        q[2].y += 1e-6;
        assert_ne!(h, mesh_hash(&q, &[[0, 1, 2]]));
    }
}
