//! Isosurfaces of node values on a regular grid: the starting surface for higher-genus targets
//! [docs/method.md §5.3].
//!
//! **Marching tetrahedra on the Kuhn (Freudenthal) split** rather than table-based marching cubes:
//! every cube is cut into the 6 tetrahedra around its main diagonal (0,0,0)–(1,1,1), the same way
//! in every cube, so neighbouring cubes agree on every face diagonal. The isosurface of the
//! piecewise-linear interpolant is then a closed 2-manifold wherever the level set stays inside the
//! grid, with no ambiguous cases at all (classic marching cubes needs an asymptotic decider or its
//! 33-case extension to avoid holes; the reference has none, docs/method.md §5.3). The price is
//! about twice as many (and less regular) triangles, irrelevant here because the starting surface
//! is remeshed at once.
//!
//! Conventions: a node is *inside* when its value is `< iso`; border nodes of the grid are always
//! treated as outside, so the surface is closed even where the level set would leave the grid.
//! Triangles are oriented counter-clockwise seen from outside (normals towards larger values), as
//! [`crate::mesh::HalfedgeMesh::from_triangles`] expects. Vertices lie on grid edges (cube edges,
//! face diagonals, the main diagonal) by linear interpolation, one vertex per crossed edge
//! (welded), at parameter `t` clamped to `[1e-3, 1 − 1e-3]` so that no two vertices coincide and
//! no triangle degenerates when a node value equals `iso`.

use glam::DVec3;
use std::collections::HashMap;

/// A borrowed scalar grid: values at nodes `origin + (ix, iy, iz)·cell`, index
/// `ix + nx·(iy + ny·iz)`.
#[derive(Clone, Copy, Debug)]
pub struct ScalarGridView<'a> {
    /// Position of node (0, 0, 0).
    pub origin: DVec3,
    /// Node spacing.
    pub cell: f64,
    /// Node counts (nx, ny, nz).
    pub dims: [usize; 3],
    /// Lattice index of the view's first node: node (i, j, k) lies at
    /// `origin + cell·(first + (i, j, k))`. Zero for a whole grid; a window of a larger lattice
    /// keeps that lattice's origin, so its points come out with the same bits.
    pub first: [usize; 3],
    /// `nx·ny·nz` values.
    pub values: &'a [f64],
}

/// Clamp of the edge parameter (see the module docs).
const T_EPS: f64 = 1e-3;

/// Corner `k` of the unit cube: bits (x, y, z) of `k`.
fn corner(k: u8) -> DVec3 {
    DVec3::new((k & 1) as f64, ((k >> 1) & 1) as f64, ((k >> 2) & 1) as f64)
}

/// The 6 Kuhn tetrahedra: paths 0 → e_a → e_a + e_b → (1,1,1) over the axis permutations.
fn kuhn_tets() -> [[u8; 4]; 6] {
    let perms = [
        [0, 1, 2],
        [0, 2, 1],
        [1, 0, 2],
        [1, 2, 0],
        [2, 0, 1],
        [2, 1, 0],
    ];
    perms.map(|[a, b, _]| [0, 1 << a, (1 << a) | (1 << b), 7])
}

/// A triangle as three cube edges `(from corner, to corner)`, `from ⊂ to` bitwise.
type TriEdges = [(u8, u8); 3];

/// Oriented triangles for each tetrahedron and each inside-mask of its 4 vertices.
fn case_table() -> Vec<[Vec<TriEdges>; 16]> {
    let edge = |a: u8, b: u8| if a & b == a { (a, b) } else { (b, a) };
    kuhn_tets()
        .iter()
        .map(|tet| {
            std::array::from_fn(|mask| {
                let inside: Vec<u8> = (0..4)
                    .filter(|&k| mask & (1 << k) != 0)
                    .map(|k| tet[k])
                    .collect();
                let outside: Vec<u8> = (0..4)
                    .filter(|&k| mask & (1 << k) == 0)
                    .map(|k| tet[k])
                    .collect();
                let mut tris: Vec<TriEdges> = match (inside.len(), outside.len()) {
                    (1, 3) => {
                        let p = inside[0];
                        vec![[
                            edge(p, outside[0]),
                            edge(p, outside[1]),
                            edge(p, outside[2]),
                        ]]
                    }
                    (3, 1) => {
                        let q = outside[0];
                        vec![[edge(inside[0], q), edge(inside[1], q), edge(inside[2], q)]]
                    }
                    (2, 2) => {
                        let (p, q, r, s) = (inside[0], inside[1], outside[0], outside[1]);
                        // Cyclic order around the planar quad: pr, ps, qs, qr.
                        let (e0, e1, e2, e3) = (edge(p, r), edge(p, s), edge(q, s), edge(q, r));
                        vec![[e0, e1, e2], [e0, e2, e3]]
                    }
                    _ => vec![],
                };
                // Orient each triangle so its normal (at edge midpoints, exact in binary) points
                // from the inside corners to the outside corners.
                if !tris.is_empty() {
                    let cin =
                        inside.iter().map(|&k| corner(k)).sum::<DVec3>() / inside.len() as f64;
                    let cout =
                        outside.iter().map(|&k| corner(k)).sum::<DVec3>() / outside.len() as f64;
                    for t in &mut tris {
                        let m = t.map(|(a, b)| 0.5 * (corner(a) + corner(b)));
                        let n = (m[1] - m[0]).cross(m[2] - m[0]);
                        if n.dot(cout - cin) < 0.0 {
                            t.swap(1, 2);
                        }
                    }
                }
                tris
            })
        })
        .collect()
}

/// Extracts the isosurface `value = iso` as welded, oriented triangles (see the module docs).
/// Returns positions and triangles; both are empty when the level set does not cross the grid.
pub fn marching_cubes(grid: &ScalarGridView, iso: f64) -> (Vec<DVec3>, Vec<[u32; 3]>) {
    let [nx, ny, _] = grid.dims;
    assert_eq!(
        grid.values.len(),
        grid.dims.iter().product::<usize>(),
        "values do not match dims"
    );
    let nodes = GridNodes {
        origin: grid.origin,
        cell: grid.cell,
        dims: grid.dims,
        first: grid.first,
    };
    marching_cubes_with(
        &nodes,
        |ix, iy, iz| grid.values[ix + nx * (iy + ny * iz)],
        iso,
    )
}

/// The lattice of [`marching_cubes_with`]: a [`ScalarGridView`] without its values.
#[derive(Clone, Copy, Debug)]
pub struct GridNodes {
    pub origin: DVec3,
    pub cell: f64,
    pub dims: [usize; 3],
    pub first: [usize; 3],
}

/// [`marching_cubes`] with the node values read through `value(ix, iy, iz)` (indices in
/// `grid.dims`): a caller whose values are a function of stored ones (a voxel volume padded and
/// offset by its iso-value) need not write them all out first (for a large volume that copy
/// would be gigabytes).
pub fn marching_cubes_with(
    grid: &GridNodes,
    value: impl Fn(usize, usize, usize) -> f64,
    iso: f64,
) -> (Vec<DVec3>, Vec<[u32; 3]>) {
    let [nx, ny, nz] = grid.dims;
    let mut positions = Vec::new();
    let mut triangles = Vec::new();
    if nx < 2 || ny < 2 || nz < 2 {
        return (positions, triangles);
    }
    let table = case_table();
    let (sy, sz) = (nx, nx * ny);
    let offset =
        |k: u8| (k & 1) as usize + ((k >> 1) & 1) as usize * sy + ((k >> 2) & 1) as usize * sz;
    let offsets: [usize; 8] = std::array::from_fn(|k| offset(k as u8));
    // Value used for the inside test and interpolation: border nodes are forced outside.
    let value = |ix: usize, iy: usize, iz: usize| -> f64 {
        let v = value(ix, iy, iz);
        let border = ix == 0 || iy == 0 || iz == 0 || ix == nx - 1 || iy == ny - 1 || iz == nz - 1;
        if border {
            v.max(iso)
        } else {
            v
        }
    };
    // Crossed edge (lower node index · 8 + direction bits) → vertex index.
    let mut vertex_of: HashMap<u64, u32> = HashMap::new();
    for iz in 0..nz - 1 {
        for iy in 0..ny - 1 {
            for ix in 0..nx - 1 {
                let base = ix + sy * iy + sz * iz;
                let vals: [f64; 8] = std::array::from_fn(|k| {
                    let k = k as u8;
                    value(
                        ix + (k & 1) as usize,
                        iy + ((k >> 1) & 1) as usize,
                        iz + ((k >> 2) & 1) as usize,
                    )
                });
                let mut cube_mask = 0u8;
                for (k, &v) in vals.iter().enumerate() {
                    if v < iso {
                        cube_mask |= 1 << k;
                    }
                }
                if cube_mask == 0 || cube_mask == 0xff {
                    continue;
                }
                let [fx, fy, fz] = grid.first;
                let (gx, gy, gz) = ((ix + fx) as f64, (iy + fy) as f64, (iz + fz) as f64);
                let cell_origin = grid.origin + grid.cell * DVec3::new(gx, gy, gz);
                for (tet, cases) in kuhn_tets().iter().zip(&table) {
                    let mut mask = 0usize;
                    for (k, &c) in tet.iter().enumerate() {
                        if cube_mask & (1 << c) != 0 {
                            mask |= 1 << k;
                        }
                    }
                    for tri in &cases[mask] {
                        let ids = tri.map(|(a, b)| {
                            let key = ((base + offsets[a as usize]) as u64) * 8 + (a ^ b) as u64;
                            *vertex_of.entry(key).or_insert_with(|| {
                                let (va, vb) = (vals[a as usize], vals[b as usize]);
                                let t = ((iso - va) / (vb - va)).clamp(T_EPS, 1.0 - T_EPS);
                                let pa = corner(a);
                                let p = pa + t * (corner(b) - pa);
                                positions.push(cell_origin + grid.cell * p);
                                (positions.len() - 1) as u32
                            })
                        });
                        triangles.push(ids);
                    }
                }
            }
        }
    }
    (positions, triangles)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_case_has_consistent_orientation() {
        // The two triangles of a quad share an edge in opposite directions.
        for cases in case_table() {
            for tris in cases.iter() {
                if tris.len() == 2 {
                    let (t0, t1) = (tris[0], tris[1]);
                    let dir = |t: TriEdges| [(t[0], t[1]), (t[1], t[2]), (t[2], t[0])];
                    let shared = dir(t0)
                        .iter()
                        .filter(|(a, b)| dir(t1).contains(&(*b, *a)))
                        .count();
                    assert_eq!(shared, 1);
                }
            }
        }
    }
}
