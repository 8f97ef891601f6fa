//! The exterior of a level set: nodes with `d ≥ level` that a path of such nodes links to the
//! grid's border. Its boundary is the start surface that cannot seed an invalid wrap — the inner
//! sheet of an unsigned field (the other side of a scan layer) and cavities enclosed by the
//! target are never part of it.
//!
//! Connectivity is that of the Kuhn tetrahedra of [`crate::geometry::marching_cubes`] (6 axis
//! neighbours, the 6 "++" face diagonals and the main diagonal, each both ways), so the flood's
//! components are exactly the components of the marching-tetrahedra outside region.

use crate::geometry::marching_cubes::{marching_cubes, ScalarGridView};
use glam::DVec3;

/// Node offsets joined by an edge of a Kuhn tetrahedron.
const NEIGHBOURS: [[i64; 3]; 14] = [
    [1, 0, 0],
    [-1, 0, 0],
    [0, 1, 0],
    [0, -1, 0],
    [0, 0, 1],
    [0, 0, -1],
    [1, 1, 0],
    [-1, -1, 0],
    [1, 0, 1],
    [-1, 0, -1],
    [0, 1, 1],
    [0, -1, -1],
    [1, 1, 1],
    [-1, -1, -1],
];

/// Marks the exterior nodes of `{v ≥ level}` (border nodes always count as outside, as in the
/// marching tetrahedra). Deterministic breadth-first flood.
pub fn exterior_mask(values: &[f64], dims: [usize; 3], level: f64) -> Vec<bool> {
    let [nx, ny, nz] = dims;
    let idx = |x: usize, y: usize, z: usize| x + nx * (y + ny * z);
    let mut ext = vec![false; values.len()];
    let mut queue = Vec::new();
    for z in 0..nz {
        for y in 0..ny {
            for x in 0..nx {
                let border =
                    x == 0 || y == 0 || z == 0 || x + 1 == nx || y + 1 == ny || z + 1 == nz;
                if border {
                    ext[idx(x, y, z)] = true;
                    queue.push([x, y, z]);
                }
            }
        }
    }
    let mut head = 0;
    while head < queue.len() {
        let [x, y, z] = queue[head];
        head += 1;
        for o in NEIGHBOURS {
            let (qx, qy, qz) = (x as i64 + o[0], y as i64 + o[1], z as i64 + o[2]);
            if qx < 0 || qy < 0 || qz < 0 || qx >= nx as i64 || qy >= ny as i64 || qz >= nz as i64 {
                continue;
            }
            let i = idx(qx as usize, qy as usize, qz as usize);
            if !ext[i] && values[i] >= level && values[i].is_finite() {
                ext[i] = true;
                queue.push([qx as usize, qy as usize, qz as usize]);
            }
        }
    }
    ext
}

/// The boundary of the exterior of `{v ≥ level}`: marching tetrahedra after every non-exterior
/// node is moved below the level (enclosed pockets of large values vanish). Closed, oriented
/// outwards, welded.
pub fn exterior_isosurface(view: &ScalarGridView, level: f64) -> (Vec<DVec3>, Vec<[u32; 3]>) {
    let ext = exterior_mask(view.values, view.dims, level);
    let below = level - view.cell;
    let values: Vec<f64> = view
        .values
        .iter()
        .zip(&ext)
        .map(|(&v, &e)| if e || v < level { v } else { below })
        .collect();
    marching_cubes(
        &ScalarGridView {
            values: &values,
            ..*view
        },
        level,
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::HalfedgeMesh;

    /// |distance to a spherical shell of radius 1| on a grid over [-2, 2]³: an unsigned field with
    /// an inner pocket (the sphere's inside, d up to 1).
    fn shell(n: usize) -> (Vec<f64>, [usize; 3], f64) {
        let cell = 4.0 / (n - 1) as f64;
        let mut v = Vec::new();
        for z in 0..n {
            for y in 0..n {
                for x in 0..n {
                    let p = DVec3::new(x as f64, y as f64, z as f64) * cell - DVec3::splat(2.0);
                    v.push((p.length() - 1.0).abs());
                }
            }
        }
        (v, [n; 3], cell)
    }

    #[test]
    fn unsigned_shell_gives_one_outer_sphere() {
        let (values, dims, cell) = shell(41);
        let view = ScalarGridView {
            first: [0; 3],
            origin: DVec3::splat(-2.0),
            cell,
            dims,
            values: &values,
        };
        // Plain marching tetrahedra: an outer and an inner sheet.
        let (p, t) = marching_cubes(&view, 0.3);
        let m = HalfedgeMesh::from_triangles(p, &t).unwrap();
        assert_eq!(m.validate().unwrap().components, 2);
        // The exterior only: one sphere of radius ≈ 1.3.
        let (p, t) = exterior_isosurface(&view, 0.3);
        let m = HalfedgeMesh::from_triangles(p.clone(), &t).unwrap();
        let r = m.validate().unwrap();
        assert_eq!((r.components, r.genus), (1, 0));
        for q in &p {
            assert!((q.length() - 1.3).abs() < 0.05, "{}", q.length());
        }
    }

    #[test]
    fn border_nodes_are_exterior_even_below_the_level() {
        let values = vec![0.0; 27];
        let ext = exterior_mask(&values, [3, 3, 3], 0.5);
        assert_eq!(ext.iter().filter(|&&e| e).count(), 26);
        assert!(!ext[13]);
    }
}
