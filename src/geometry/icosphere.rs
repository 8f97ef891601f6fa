//! Subdivided icosahedron: the default starting surface (docs/method.md §5.1).

use crate::mesh::HalfedgeMesh;
use glam::DVec3;
use std::collections::HashMap;

/// Highest supported subdivision level (163 842 vertices).
pub const MAX_LEVEL: u32 = 7;

/// Vertex count of an icosphere of `level` subdivisions: `10·4^level + 2`.
pub fn vertex_count(level: u32) -> usize {
    10 * 4usize.pow(level) + 2
}

/// Why an icosphere could not be built.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum IcosphereError {
    /// Level above [`MAX_LEVEL`]. Fix: use a level in 0..=7.
    #[error("icosphere level {0} is too high (at most {MAX_LEVEL})")]
    LevelTooHigh(u32),
    /// Radius not a positive finite number.
    #[error("icosphere radius must be positive and finite, got {0}")]
    BadRadius(f64),
}

/// Builds an outward-oriented icosphere: the icosahedron, split `level` times 1→4 with edge
/// midpoints pushed back onto the sphere, scaled to `radius` and centred at `center`.
pub fn icosphere(level: u32, radius: f64, center: DVec3) -> Result<HalfedgeMesh, IcosphereError> {
    if level > MAX_LEVEL {
        return Err(IcosphereError::LevelTooHigh(level));
    }
    if !(radius > 0.0 && radius.is_finite()) {
        return Err(IcosphereError::BadRadius(radius));
    }
    let (unit, faces) = unit_icosphere(level);
    let positions = unit.into_iter().map(|p| center + radius * p).collect();
    Ok(
        HalfedgeMesh::from_triangles(positions, &faces)
            .expect("icosphere connectivity is manifold"),
    )
}

/// Unit-sphere positions and counter-clockwise faces of the level-`level` icosphere.
pub fn unit_icosphere(level: u32) -> (Vec<DVec3>, Vec<[u32; 3]>) {
    let g = (1.0 + 5f64.sqrt()) / 2.0;
    let mut pos: Vec<DVec3> = [
        (-1.0, g, 0.0),
        (1.0, g, 0.0),
        (-1.0, -g, 0.0),
        (1.0, -g, 0.0),
        (0.0, -1.0, g),
        (0.0, 1.0, g),
        (0.0, -1.0, -g),
        (0.0, 1.0, -g),
        (g, 0.0, -1.0),
        (g, 0.0, 1.0),
        (-g, 0.0, -1.0),
        (-g, 0.0, 1.0),
    ]
    .iter()
    .map(|&(x, y, z)| DVec3::new(x, y, z).normalize())
    .collect();
    let mut faces: Vec<[u32; 3]> = vec![
        [0, 11, 5],
        [0, 5, 1],
        [0, 1, 7],
        [0, 7, 10],
        [0, 10, 11],
        [1, 5, 9],
        [5, 11, 4],
        [11, 10, 2],
        [10, 7, 6],
        [7, 1, 8],
        [3, 9, 4],
        [3, 4, 2],
        [3, 2, 6],
        [3, 6, 8],
        [3, 8, 9],
        [4, 9, 5],
        [2, 4, 11],
        [6, 2, 10],
        [8, 6, 7],
        [9, 8, 1],
    ];
    for _ in 0..level {
        // Midpoint cache keyed by the sorted edge; only looked up, so order stays deterministic.
        let mut mid: HashMap<(u32, u32), u32> = HashMap::with_capacity(faces.len() * 3 / 2);
        let mut midpoint = |a: u32, b: u32, pos: &mut Vec<DVec3>| -> u32 {
            *mid.entry((a.min(b), a.max(b))).or_insert_with(|| {
                pos.push((pos[a as usize] + pos[b as usize]).normalize());
                (pos.len() - 1) as u32
            })
        };
        let mut next = Vec::with_capacity(faces.len() * 4);
        for &[a, b, c] in &faces {
            let ab = midpoint(a, b, &mut pos);
            let bc = midpoint(b, c, &mut pos);
            let ca = midpoint(c, a, &mut pos);
            next.extend([[a, ab, ca], [b, bc, ab], [c, ca, bc], [ab, bc, ca]]);
        }
        faces = next;
    }
    (pos, faces)
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::PI;

    #[test]
    fn counts_orientation_and_radius() {
        for level in 0..=4 {
            let m = icosphere(level, 2.0, DVec3::new(1.0, 2.0, 3.0)).unwrap();
            let r = m.validate().unwrap();
            assert_eq!(r.vertices, vertex_count(level));
            assert_eq!(r.faces, 20 * 4usize.pow(level));
            assert_eq!(r.euler_characteristic, 2);
            for p in m.positions() {
                assert!(((*p - DVec3::new(1.0, 2.0, 3.0)).length() - 2.0).abs() < 1e-12);
            }
            // Outward: positive volume, approaching the ball's 4/3·π·r³ from below.
            let vol = m.signed_volume();
            assert!(
                vol > 0.0 && vol < 4.0 / 3.0 * PI * 8.0,
                "level {level}: volume {vol}"
            );
        }
        let v4 = icosphere(4, 1.0, DVec3::ZERO).unwrap().signed_volume();
        assert!((v4 / (4.0 / 3.0 * PI) - 1.0).abs() < 0.01);
    }

    #[test]
    fn rejects_bad_arguments() {
        assert_eq!(
            icosphere(8, 1.0, DVec3::ZERO).unwrap_err(),
            IcosphereError::LevelTooHigh(8)
        );
        assert!(icosphere(1, 0.0, DVec3::ZERO).is_err());
        assert!(icosphere(1, f64::NAN, DVec3::ZERO).is_err());
    }
}
