//! The sign of a mesh distance field: negative inside, positive outside [docs/method.md §2.6,
//! §13.4].
//!
//! * **Band nodes** take the sign of `(p − q)·n` where `q` is the closest point on the nearest
//!   triangle and `n` the angle-weighted pseudo-normal of the feature holding `q` (face normal,
//!   sum of the two face normals of an edge, angle-weighted vertex normal; Bærentzen & Aanæs
//!   2005). For a closed, consistently oriented mesh this is exact.
//! * **All other nodes** by a 6-connected flood fill of the exterior from the grid border over
//!   non-band nodes; what the fill does not reach is inside. A path from outside to inside between
//!   neighbouring nodes must cross the surface, and the node next to the crossing lies within c/2
//!   of it, hence in the band: the band (≥ 1 cell) seals the inside. The reference instead leaves
//!   the whole band negative on both sides (a zero level shifted outwards).
//!
//! Which meshes get a sign: closed and consistently oriented ones ([`Signedness::Signed`]);
//! meshes whose only defects are a few boundary edges (≤ 2 % of the edges, "nearly closed",
//! [`Signedness::SignedWithHoles`]) when the fill still finds an inside; everything else, and
//! every point cloud, stays unsigned ([`Signedness::Unsigned`]). An inward-oriented closed mesh
//! (negative volume) is handled by flipping its normals.

use super::grid::Grid;
use crate::geometry::primitives::{closest_point_on_triangle, TriangleFeature};
pub use crate::mesh::stars::{closure, Closure};
use crate::mesh::stars::{closure_with, edge_uses, Stars};
use glam::DVec3;
use serde::{Deserialize, Serialize};

/// Which kind of field was produced.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Signedness {
    /// Unsigned distance `d ≥ 0` (point clouds, open soups, non-manifold meshes, or by request).
    Unsigned,
    /// Signed: negative inside a closed, consistently oriented mesh.
    Signed,
    /// Signed, for a mesh with a few boundary edges whose holes the near band sealed.
    SignedWithHoles,
}

/// Pseudo-normals of faces, edges and vertices.
struct PseudoNormals<'a> {
    face: Vec<DVec3>,
    vertex: Vec<DVec3>,
    /// Edge pseudo-normals are the sums of the face normals of the edge's triangles, found in
    /// the stars when asked (only band nodes nearest to an edge ask).
    stars: &'a Stars,
    triangles: &'a [[u32; 3]],
}

impl<'a> PseudoNormals<'a> {
    fn new(points: &[DVec3], triangles: &'a [[u32; 3]], stars: &'a Stars) -> Self {
        let mut face = Vec::with_capacity(triangles.len());
        let mut vertex = vec![DVec3::ZERO; points.len()];
        for t in triangles {
            let p = t.map(|v| points[v as usize]);
            let n = (p[1] - p[0]).cross(p[2] - p[0]).normalize_or_zero();
            face.push(n);
            for k in 0..3 {
                let e1 = (p[(k + 1) % 3] - p[k]).normalize_or_zero();
                let e2 = (p[(k + 2) % 3] - p[k]).normalize_or_zero();
                let angle = crate::fmath::acos(e1.dot(e2).clamp(-1.0, 1.0));
                vertex[t[k] as usize] += angle * n;
            }
        }
        Self {
            face,
            vertex,
            stars,
            triangles,
        }
    }

    fn of(&self, t: usize, tri: [u32; 3], f: TriangleFeature) -> DVec3 {
        match f {
            TriangleFeature::Face => self.face[t],
            TriangleFeature::Vertex(k) => self.vertex[tri[k as usize] as usize],
            TriangleFeature::Edge(k) => {
                let k = k as usize;
                let (a, b) = (tri[k].min(tri[(k + 1) % 3]), tri[k].max(tri[(k + 1) % 3]));
                // Every use of the edge, in ascending triangle order (as a per-triangle
                // accumulation would add them).
                let mut n = DVec3::ZERO;
                edge_uses(self.stars, self.triangles, a, |o, _, t| {
                    if o == b {
                        n += self.face[t as usize];
                    }
                });
                n
            }
        }
    }
}

/// Signed volume enclosed by the triangles (positive for outward orientation).
fn signed_volume(points: &[DVec3], triangles: &[[u32; 3]]) -> f64 {
    let c = points.iter().copied().sum::<DVec3>() / points.len().max(1) as f64;
    triangles
        .iter()
        .map(|t| {
            let [a, b, d] = t.map(|v| points[v as usize] - c);
            a.dot(b.cross(d))
        })
        .sum::<f64>()
        / 6.0
}

/// Marks the exterior: nodes reachable from the grid border through non-frozen nodes
/// (6-connected). A scanline fill: each seed grows into its whole run along x, and the rows
/// beside the run (y ± 1, z ± 1) get one seed per stretch of open nodes. The stack then holds
/// runs rather than nodes, and rows are read in order (several times faster than a node-by-node
/// fill). The exterior is a set, so the order of the fill cannot change it.
fn flood_exterior(grid: &Grid, frozen: impl Fn(usize) -> bool) -> Vec<bool> {
    let [nx, ny, nz] = grid.dims;
    let mut outside = vec![false; grid.node_count()];
    let open = |outside: &[bool], i: usize| !outside[i] && !frozen(i);
    // Seeds: every border node (closed ones are skipped when popped).
    let mut stack: Vec<(usize, usize, usize)> = Vec::new();
    for z in 0..nz {
        for y in 0..ny {
            if z == 0 || z == nz - 1 || y == 0 || y == ny - 1 {
                stack.extend((0..nx).map(|x| (x, y, z)));
            } else {
                stack.push((0, y, z));
                stack.push((nx - 1, y, z));
            }
        }
    }
    while let Some((x, y, z)) = stack.pop() {
        let row = nx * (y + ny * z);
        if !open(&outside, row + x) {
            continue;
        }
        let (mut lo, mut hi) = (x, x);
        while lo > 0 && open(&outside, row + lo - 1) {
            lo -= 1;
        }
        while hi + 1 < nx && open(&outside, row + hi + 1) {
            hi += 1;
        }
        outside[row + lo..=row + hi].fill(true);
        let beside = [
            (y > 0).then(|| (y - 1, z)),
            (y + 1 < ny).then_some((y + 1, z)),
            (z > 0).then(|| (y, z - 1)),
            (z + 1 < nz).then_some((y, z + 1)),
        ];
        for (by, bz) in beside.into_iter().flatten() {
            let brow = nx * (by + ny * bz);
            let mut in_stretch = false;
            for bx in lo..=hi {
                let o = open(&outside, brow + bx);
                if o && !in_stretch {
                    stack.push((bx, by, bz));
                }
                in_stretch = o;
            }
        }
    }
    outside
}

/// Negates `values` where `inside` (None: nowhere).
pub fn negate_inside(values: &mut [f64], inside: Option<&[bool]>) {
    for (v, _) in values
        .iter_mut()
        .zip(inside.unwrap_or_default())
        .filter(|(_, &i)| i)
    {
        *v = -*v;
    }
}

/// The exterior flood of [`negate_enclosed`] runs over the nodes this many cells farther from
/// the data than its `level`: a random sampling leaves gaps that a band of `level` = 2 cells
/// (4 median spacings, `tuning.field.min_cell_spacings`) now and then lets the flood through; one cell
/// more seals them.
const SEAL_CELLS: f64 = 1.0;
/// Node steps by which the exterior then grows into the nodes between `level` and the seal: a
/// node outside the data within one cell of the sealed exterior is at most two 6-connected steps
/// from it; one more for rounding. (Through a gap it reaches only a few nodes inside.)
const SEAL_STEPS: usize = 3;

/// Negates the nodes of a cloud's unsigned field that lie deeper than `level` inside a solid the
/// cloud samples all round, and returns how many there were. The exterior is flooded
/// ([`flood_exterior`], 6-connected) over the nodes at least `level` + [`SEAL_CELLS`] cells from
/// every point, then grown [`SEAL_STEPS`] steps into those at least `level` away; what lies at
/// least `level` away and is not exterior is enclosed. The near band of the points seals the
/// inside where the sampling has no gap much wider than the band; where it has, the flood gets
/// in and nothing changes.
pub fn negate_enclosed(grid: &Grid, values: &mut [f64], level: f64) -> usize {
    // (A NaN counts as near, like a band node.)
    let near = |v: f64, l: f64| v < l || v.is_nan();
    let seal = level + SEAL_CELLS * grid.cell;
    let mut outside = flood_exterior(grid, |i| near(values[i], seal));
    let mut candidates: Vec<usize> = (0..values.len())
        .filter(|&i| !outside[i] && !near(values[i], level))
        .collect();
    for _ in 0..SEAL_STEPS {
        let grown: Vec<usize> = candidates
            .iter()
            .copied()
            .filter(|&i| {
                grid.axis_neighbours(i)
                    .into_iter()
                    .flatten()
                    .any(|j| outside[j])
            })
            .collect();
        if grown.is_empty() {
            break;
        }
        for &i in &grown {
            outside[i] = true;
        }
        candidates.retain(|&i| !outside[i]);
    }
    // Enclosed are the parts of what is left that reach beyond the seal: a pocket between the
    // level and the seal alone is a gap of a sparse sampling seen through a fine grid, not a
    // solid (negated, such pockets would hold the wrap and open a false handle).
    let mut enclosed = vec![false; values.len()];
    let mut stack: Vec<usize> = candidates
        .iter()
        .copied()
        .filter(|&i| !near(values[i], seal))
        .collect();
    for &i in &stack {
        enclosed[i] = true;
    }
    let candidate = |i: usize, outside: &[bool]| !outside[i] && !near(values[i], level);
    while let Some(i) = stack.pop() {
        for j in grid.axis_neighbours(i).into_iter().flatten() {
            if !enclosed[j] && candidate(j, &outside) {
                enclosed[j] = true;
                stack.push(j);
            }
        }
    }
    let mut count = 0;
    for (v, e) in values.iter_mut().zip(enclosed) {
        if e && v.is_finite() {
            *v = -*v;
            count += 1;
        }
    }
    count
}

/// Which nodes of an unsigned mesh field lie inside (see the module docs), and which kind of
/// field negating them ([`negate_inside`]) makes (None: unsigned). `nearest[i]` is the triangle
/// realising band node `i`. It reads only the band and the mesh, not the values: it can be
/// worked out while the sweep fills them in away from the band.
pub fn mesh_inside(
    grid: &Grid,
    frozen: &[bool],
    nearest: &[u32],
    points: &[DVec3],
    triangles: &[[u32; 3]],
) -> (Signedness, Option<Vec<bool>>) {
    let stars = Stars::new(points.len(), triangles);
    let cl = closure_with(&stars, triangles, points.len());
    let kind = if cl.bad_edges > 0 || cl.edges == 0 {
        return (Signedness::Unsigned, None);
    } else if cl.boundary_edges == 0 {
        Signedness::Signed
    } else if cl.boundary_edges * 50 <= cl.edges {
        Signedness::SignedWithHoles
    } else {
        return (Signedness::Unsigned, None);
    };
    let outside = flood_exterior(grid, |i| frozen[i]);
    let interior = outside
        .iter()
        .zip(frozen)
        .filter(|(&o, &f)| !o && !f)
        .count();
    if kind == Signedness::SignedWithHoles && interior == 0 {
        // The fill leaked through a hole (or the object is thinner than the band): no sign.
        return (Signedness::Unsigned, None);
    }
    let normals = PseudoNormals::new(points, triangles, &stars);
    let orientation = if signed_volume(points, triangles) < 0.0 {
        -1.0
    } else {
        1.0
    };
    // (Each node on its own: in parallel natively.)
    let inside = crate::parallel::map(frozen.len(), |i| {
        if frozen[i] {
            let t = nearest[i] as usize;
            let tri = triangles[t];
            let [a, b, c] = tri.map(|v| points[v as usize]);
            let p = grid.position_of(i);
            let (q, f) = closest_point_on_triangle(p, a, b, c);
            orientation * (p - q).dot(normals.of(t, tri, f)) < 0.0
        } else {
            !outside[i]
        }
    });
    (kind, Some(inside))
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::collections::HashMap;

    /// |distance to a spherical shell of radius 1| on a grid over [-2, 2]³: an unsigned field whose
    /// inside (d up to 1) the shell encloses.
    fn shell(n: usize) -> (Vec<f64>, Grid) {
        let grid = Grid {
            origin: DVec3::splat(-2.0),
            cell: 4.0 / (n - 1) as f64,
            dims: [n; 3],
        };
        let mut v = Vec::new();
        for z in 0..n {
            for y in 0..n {
                for x in 0..n {
                    let p = DVec3::new(x as f64, y as f64, z as f64) * grid.cell + grid.origin;
                    v.push((p.length() - 1.0).abs());
                }
            }
        }
        (v, grid)
    }

    #[test]
    fn only_the_deep_inside_of_a_shell_is_negated() {
        let (mut values, grid) = shell(41);
        let before = values.clone();
        let level = 0.3;
        let count = negate_enclosed(&grid, &mut values, level);
        assert!(count > 0);
        let mut negated = 0;
        for (i, (&v, &b)) in values.iter().zip(&before).enumerate() {
            let z = i / (41 * 41);
            let y = (i / 41) % 41;
            let x = i % 41;
            let r =
                (DVec3::new(x as f64, y as f64, z as f64) * grid.cell - DVec3::splat(2.0)).length();
            if r < 1.0 - level - 1e-9 {
                assert_eq!(v, -b, "r {r}");
            } else if r > 1.0 - level + 1e-9 {
                assert_eq!(v, b, "r {r}");
            }
            if v != b {
                negated += 1;
            }
        }
        assert_eq!(negated, count);
        // A gap wider than the barrier: the inside is linked to the outside and nothing changes.
        let (mut open, grid) = shell(41);
        for (i, v) in open.iter_mut().enumerate() {
            let p = DVec3::new((i % 41) as f64, ((i / 41) % 41) as f64, (i / 1681) as f64)
                * grid.cell
                - DVec3::splat(2.0);
            if p.z > 0.5 && p.x * p.x + p.y * p.y < 0.36 {
                *v = v.max(0.4);
            }
        }
        let kept = open.clone();
        assert_eq!(negate_enclosed(&grid, &mut open, level), 0);
        assert_eq!(open, kept);
    }

    /// The edge counts by hashing every directed edge (the definition).
    fn closure_by_hashing(triangles: &[[u32; 3]]) -> Closure {
        let mut uses: HashMap<(u32, u32), (u32, u32)> = HashMap::new();
        for t in triangles {
            for k in 0..3 {
                let (a, b) = (t[k], t[(k + 1) % 3]);
                let e = uses.entry((a.min(b), a.max(b))).or_insert((0, 0));
                if a < b {
                    e.0 += 1;
                } else {
                    e.1 += 1;
                }
            }
        }
        let mut c = Closure {
            edges: uses.len(),
            boundary_edges: 0,
            bad_edges: 0,
        };
        for &(f, b) in uses.values() {
            match (f, b) {
                (1, 1) => {}
                (1, 0) | (0, 1) => c.boundary_edges += 1,
                _ => c.bad_edges += 1,
            }
        }
        c
    }

    #[test]
    fn star_closure_and_edge_normals_match_hashing_on_messy_soups() {
        let mut rng = crate::demo::Rng::new(7);
        for case in 0..40 {
            let nv = 4 + case;
            let points: Vec<DVec3> = (0..nv)
                .map(|_| DVec3::new(rng.uniform(), rng.uniform(), rng.uniform()))
                .collect();
            // Random triangles, some with repeated vertices, some duplicated or flipped.
            let mut tris: Vec<[u32; 3]> = (0..3 * nv)
                .map(|_| [0; 3].map(|_| (rng.uniform() * nv as f64) as u32 % nv as u32))
                .collect();
            tris.push(tris[0]);
            tris.push([tris[1][0], tris[1][2], tris[1][1]]);
            assert_eq!(closure(&tris), closure_by_hashing(&tris), "case {case}");
            // Edge pseudo-normals: the sum of the face normals of every use, in triangle order.
            let stars = Stars::new(points.len(), &tris);
            let pn = PseudoNormals::new(&points, &tris, &stars);
            let mut by_hash: HashMap<(u32, u32), DVec3> = HashMap::new();
            for (t, tri) in tris.iter().enumerate() {
                for k in 0..3 {
                    let (a, b) = (tri[k], tri[(k + 1) % 3]);
                    *by_hash.entry((a.min(b), a.max(b))).or_insert(DVec3::ZERO) += pn.face[t];
                }
            }
            for (t, &tri) in tris.iter().enumerate() {
                for k in 0..3u8 {
                    let (a, b) = (tri[k as usize], tri[(k as usize + 1) % 3]);
                    let got = pn.of(t, tri, TriangleFeature::Edge(k));
                    assert_eq!(
                        got,
                        by_hash[&(a.min(b), a.max(b))],
                        "case {case} t {t} k {k}"
                    );
                }
            }
        }
    }
}
