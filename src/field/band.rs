//! The exact near band: every node within `k` cells of the target gets its exact distance.
//!
//! Instead of a nearest-neighbour query per node, each primitive *splats* its exact distance onto
//! the nodes of its own neighbourhood and every node keeps the minimum. A node whose nearest
//! primitive lies within `r = k·c` is inside that primitive's neighbourhood (its cube of half side
//! `r` for a point; its bounding box grown by `r`, cut to the slab `|n·(x − a)| ≤ r`, for a
//! triangle), so it receives its true minimum: the band `{d ≤ r}` is exact, with no kd-tree or BVH,
//! duplicates cost nothing, and the work is proportional to (primitives × band volume each).
//!
//! Nodes inside a neighbourhood but farther than `r` keep the distance to some nearby primitive:
//! an upper bound of the truth. They stay unfrozen and fast sweeping may lower them.

use super::grid::Grid;
use crate::geometry::primitives::closest_point_on_triangle;
use crate::geometry::spatial::bvh::Bvh;
use crate::progress::Progress;
use glam::DVec3;

/// From this many triangles on, the band is found node by node ([`triangles_band_by_nodes`])
/// rather than triangle by triangle: a marching-cubes iso-surface of a volume has millions of
/// triangles far smaller than a cell, and splatting each over its (2k+1)³ nodes would visit every
/// node many times over.
pub const NODE_QUERY_TRIANGLES: usize = 1_000_000;

/// The initial condition for fast sweeping.
pub struct Band {
    /// Per node: the exact distance in the band, an upper bound or `init` elsewhere.
    pub values: Vec<f64>,
    /// Per node: true when the value is the exact distance and `≤ r` (frozen for sweeping).
    pub frozen: Vec<bool>,
    /// For triangle targets: the triangle that realises the value (`u32::MAX` where none).
    pub nearest_triangle: Option<Vec<u32>>,
}

/// Node index ranges `[lo, hi]` (inclusive) of the nodes within `[a − r, b + r]` on `axis`;
/// `None` when empty.
#[inline]
fn node_range(grid: &Grid, axis: usize, lo: f64, hi: f64) -> Option<(usize, usize)> {
    let o = grid.origin[axis];
    let n = grid.dims[axis] as f64;
    let a = ((lo - o) / grid.cell).ceil().max(0.0);
    let b = ((hi - o) / grid.cell).floor().min(n - 1.0);
    (a <= b).then_some((a as usize, b as usize))
}

/// The progress phase of the band computations.
pub const PHASE: &str = "distance field: near band";

/// Exact band around a point cloud: all nodes with distance ≤ `width_cells·c` to the nearest
/// point. `init` is the value of untouched nodes (∞ or the truncation distance).
pub fn points_band(
    grid: &Grid,
    points: &[DVec3],
    width_cells: f64,
    init: f64,
    progress: &mut Progress,
) -> Band {
    let r = width_cells * grid.cell;
    let r2 = r * r;
    let [nx, ny, nz] = grid.dims;
    let plane = nx * ny;
    // Each point splats onto the nodes of its cube; every node keeps the minimum, which does not
    // depend on the order. The grid is cut into slabs of z-planes, each slab filled from the
    // points that reach it (bucketed by a counting sort), so that the slabs are independent:
    // in parallel natively, and progress is reported between groups of slabs.
    let reach: Vec<Option<NodeBox>> = crate::parallel::map(points.len(), |i| {
        let p = points[i];
        let (x, y, z) = (
            node_range(grid, 0, p.x - r, p.x + r)?,
            node_range(grid, 1, p.y - r, p.y + r)?,
            node_range(grid, 2, p.z - r, p.z + r)?,
        );
        Some([x.0, x.1, y.0, y.1, z.0, z.1].map(|k| k as u32))
    });
    let (start, members) = bucket_by_slab(&reach, nz);
    let slabs = start.len() - 1;
    let mut d2 = vec![init * init; plane * nz];
    let total = slabs.max(1);
    crate::parallel::for_each_chunk_mut(
        &mut d2,
        plane * SLAB_PLANES,
        SLABS_PER_REPORT,
        |s, slab| {
            let z_first = s * SLAB_PLANES;
            let mut dx2: Vec<f64> = Vec::new();
            for &i in &members[start[s] as usize..start[s + 1] as usize] {
                let (p, b) = (points[i as usize], unbox(reach[i as usize]));
                let (x0, x1) = (b[0], b[1]);
                dx2.clear();
                dx2.extend((x0..=x1).map(|ix| {
                    let d = grid.origin.x + grid.cell * ix as f64 - p.x;
                    d * d
                }));
                let z_last = z_first + slab.len() / plane - 1;
                for iz in b[4].max(z_first)..=b[5].min(z_last) {
                    let dz = grid.origin.z + grid.cell * iz as f64 - p.z;
                    let dz2 = dz * dz;
                    for iy in b[2]..=b[3] {
                        let dy = grid.origin.y + grid.cell * iy as f64 - p.y;
                        let dyz = dy * dy + dz2;
                        if dyz > r2 {
                            continue;
                        }
                        let row = x0 + nx * (iy + ny * (iz - z_first));
                        let out = &mut slab[row..=row + (x1 - x0)];
                        for (v, &a) in out.iter_mut().zip(&dx2) {
                            // A select and a store every time, not a store on a branch: it
                            // vectorises natively, and the minimum is the same.
                            let s = a + dyz;
                            *v = if s < *v { s } else { *v };
                        }
                    }
                }
            }
        },
        &mut |done| progress.report(PHASE, done as f64 / total as f64),
    );
    finish(d2, r2, init)
}

/// z-planes per slab of [`points_band`]: small enough for many slabs per thread, large enough
/// that a point's cube (2k + 1 planes) rarely spans more than two.
const SLAB_PLANES: usize = 8;

/// Slabs between two progress reports of the bands (natively each group of slabs is spread over
/// the threads; in wasm, with one thread, a report per slab keeps the bar moving on a big mesh,
/// whose band takes seconds there). The values do not depend on it.
const SLABS_PER_REPORT: usize = if cfg!(target_arch = "wasm32") { 1 } else { 8 };

/// Square roots, band flags, truncation.
fn finish(mut d2: Vec<f64>, r2: f64, init: f64) -> Band {
    let init2 = init * init;
    let mut frozen = vec![false; d2.len()];
    for (v, f) in d2.iter_mut().zip(frozen.iter_mut()) {
        if *v < init2 {
            *f = *v <= r2;
            *v = v.sqrt();
        } else {
            *v = init;
        }
    }
    Band {
        values: d2,
        frozen,
        nearest_triangle: None,
    }
}

/// Exact band around a triangle soup: all nodes with distance ≤ `width_cells·c` to the nearest
/// triangle, plus the index of that triangle (for the sign).
pub fn triangles_band(
    grid: &Grid,
    points: &[DVec3],
    triangles: &[[u32; 3]],
    width_cells: f64,
    init: f64,
    progress: &mut Progress,
) -> Band {
    let r = width_cells * grid.cell;
    let r2 = r * r;
    let [nx, ny, nz] = grid.dims;
    let plane = nx * ny;
    // As in `points_band`: the grid is cut into slabs of z-planes, each filled by the clusters
    // of triangles that reach it. A node keeps the nearest triangle among those whose reach
    // holds it, the lowest index on a tie, whatever the order: the slabs are independent and
    // the result depends neither on the thread count nor on the clustering.
    let reach: Vec<Option<NodeBox>> = triangles
        .iter()
        .map(|tri| {
            let [a, b, c] = tri.map(|v| points[v as usize]);
            let lo = a.min(b).min(c) - DVec3::splat(r);
            let hi = a.max(b).max(c) + DVec3::splat(r);
            let (x, y, z) = (
                node_range(grid, 0, lo.x, hi.x)?,
                node_range(grid, 1, lo.y, hi.y)?,
                node_range(grid, 2, lo.z, hi.z)?,
            );
            Some([x.0, x.1, y.0, y.1, z.0, z.1].map(|k| k as u32))
        })
        .collect();
    let clusters = cluster_triangles(grid, points, triangles, &reach);
    let cluster_reach: Vec<Option<NodeBox>> = clusters.iter().map(|c| Some(c.nodes)).collect();
    let (start, members) = bucket_by_slab(&cluster_reach, nz);
    let slabs = start.len() - 1;
    let mut best = vec![
        Nearest {
            d2: init * init,
            d1: f32_up(init),
            triangle: u32::MAX,
        };
        plane * nz
    ];
    // Rounding in the clusters' lower bounds and in the exact distances, as a distance: on a
    // CAD part nodes lie on faces (distance 0 give or take rounding), where no relative margin
    // helps. Far above the rounding of coordinates this large, far below any real gap.
    let far = grid.origin.abs() + grid.cell * DVec3::new(nx as f64, ny as f64, nz as f64);
    let slack = 1e-12 * far.max_element();
    crate::parallel::for_each_chunk_mut(
        &mut best,
        plane * SLAB_PLANES,
        SLABS_PER_REPORT,
        |s, slab| {
            let z_first = s * SLAB_PLANES;
            let z_last = z_first + slab.len() / plane - 1;
            let mut work = ClusterWork {
                slack,
                ..Default::default()
            };
            for &k in &members[start[s] as usize..start[s + 1] as usize] {
                let cluster = &clusters[k as usize];
                work.prepare(points, triangles, &reach, cluster);
                work.splat(grid, cluster, r, (z_first, z_last), slab);
            }
        },
        &mut |done| progress.report(PHASE, done as f64 / slabs.max(1) as f64),
    );
    let nearest = best.iter().map(|b| b.triangle).collect();
    // Collected in place, into the nodes' allocation: give back its unused half.
    let mut d2: Vec<f64> = best.into_iter().map(|b| b.d2).collect();
    d2.shrink_to_fit();
    let mut band = finish(d2, r2, init);
    band.nearest_triangle = Some(nearest);
    band
}

/// A node's nearest triangle so far in [`triangles_band`]: its squared distance, the distance
/// rounded up (kept so that the bounding-sphere rejection needs no square root per visit; a
/// bound too large only skips fewer nodes) and its index. 16 bytes a node.
#[derive(Clone, Copy)]
struct Nearest {
    d2: f64,
    d1: f32,
    triangle: u32,
}

/// `x` as an f32 no smaller than it.
fn f32_up(x: f64) -> f32 {
    let y = x as f32;
    if (y as f64) < x {
        y * (1.0 + f32::EPSILON)
    } else {
        y
    }
}

/// A primitive's node ranges `[x0, x1, y0, y1, z0, z1]` (inclusive), in u32: one per point of
/// a scan of millions.
type NodeBox = [u32; 6];

/// The node ranges of a bucketed primitive, as indices.
fn unbox(b: Option<NodeBox>) -> [usize; 6] {
    b.expect("bucketed").map(|k| k as usize)
}

/// Counting sort of primitives into the z-slabs their node ranges reach: `members[start[s]..
/// start[s + 1]]` are the primitives (in index order) reaching slab `s`.
fn bucket_by_slab(reach: &[Option<NodeBox>], nz: usize) -> (Vec<u32>, Vec<u32>) {
    let slabs = nz.div_ceil(SLAB_PLANES);
    let mut start = vec![0u32; slabs + 1];
    for b in reach.iter().flatten() {
        for s in b[4] as usize / SLAB_PLANES..=b[5] as usize / SLAB_PLANES {
            start[s + 1] += 1;
        }
    }
    for s in 0..slabs {
        start[s + 1] += start[s];
    }
    let mut fill = start.clone();
    let mut members = vec![0u32; start[slabs] as usize];
    for (i, b) in reach.iter().enumerate() {
        let Some(b) = b else { continue };
        for s in b[4] as usize / SLAB_PLANES..=b[5] as usize / SLAB_PLANES {
            members[fill[s] as usize] = i as u32;
            fill[s] += 1;
        }
    }
    (start, members)
}

/// Edge of the cubes that group triangles into clusters for [`triangles_band`], in cells.
const CLUSTER_CELLS: f64 = 1.0;

/// Triangles whose centres share a cube of [`CLUSTER_CELLS`]: their grown boxes nearly coincide,
/// so one test against the cluster's box turns a node away from all of them. (Splatted one by
/// one, a dense mesh's triangles would visit every band node hundreds of times.)
struct Cluster {
    /// The triangles, in index order.
    triangles: Vec<u32>,
    /// Union of the triangles' node ranges.
    nodes: NodeBox,
    /// Box of the triangles' corners: no triangle is nearer a node than this box.
    lo: DVec3,
    hi: DVec3,
}

/// Groups the triangles that reach the grid into [`Cluster`]s, in order of their cubes.
fn cluster_triangles(
    grid: &Grid,
    points: &[DVec3],
    triangles: &[[u32; 3]],
    reach: &[Option<NodeBox>],
) -> Vec<Cluster> {
    let size = CLUSTER_CELLS * grid.cell;
    let mut keyed: Vec<(u64, u32)> = (0..triangles.len())
        .filter(|&t| reach[t].is_some())
        .map(|t| {
            let [a, b, c] = triangles[t].map(|v| points[v as usize]);
            let q = ((a + b + c) / 3.0 - grid.origin) / size;
            // (Centres outside the grid clamp to its faces; the key only groups.)
            let k = [q.x, q.y, q.z].map(|x| x.clamp(0.0, (1u64 << 21) as f64 - 1.0) as u64);
            (k[0] | k[1] << 21 | k[2] << 42, t as u32)
        })
        .collect();
    keyed.sort_unstable();
    keyed
        .chunk_by(|x, y| x.0 == y.0)
        .map(|run| {
            let members: Vec<u32> = run.iter().map(|&(_, t)| t).collect();
            let mut nodes = [u32::MAX, 0, u32::MAX, 0, u32::MAX, 0];
            let (mut lo, mut hi) = (DVec3::INFINITY, DVec3::NEG_INFINITY);
            for &t in &members {
                let b = reach[t as usize].expect("clustered");
                for axis in 0..3 {
                    nodes[2 * axis] = nodes[2 * axis].min(b[2 * axis]);
                    nodes[2 * axis + 1] = nodes[2 * axis + 1].max(b[2 * axis + 1]);
                }
                for v in triangles[t as usize].map(|v| points[v as usize]) {
                    lo = lo.min(v);
                    hi = hi.max(v);
                }
            }
            Cluster {
                triangles: members,
                nodes,
                lo,
                hi,
            }
        })
        .collect()
}

/// What [`ClusterWork::splat`] needs of one triangle.
struct Prepared {
    corners: [DVec3; 3],
    normal: DVec3,
    centre: DVec3,
    /// Bounding-sphere radius about `centre`, slightly enlarged.
    radius: f64,
    t: u32,
    /// Node ranges `[x0, x1, y0, y1, z0, z1]`.
    nodes: [usize; 6],
}

/// Scratch of one slab's splats, reused from cluster to cluster.
#[derive(Default)]
struct ClusterWork {
    prepared: Vec<Prepared>,
    /// This row's `(triangle in prepared, first x node, last x node)`.
    row: Vec<(u32, usize, usize)>,
    /// Margin of the lower bounds over rounding (see `triangles_band`).
    slack: f64,
}

impl ClusterWork {
    /// Takes in the triangles of `cluster`.
    fn prepare(
        &mut self,
        points: &[DVec3],
        triangles: &[[u32; 3]],
        reach: &[Option<NodeBox>],
        cluster: &Cluster,
    ) {
        self.prepared.clear();
        self.prepared.extend(cluster.triangles.iter().map(|&t| {
            let [a, b, c] = triangles[t as usize].map(|v| points[v as usize]);
            let centre = (a + b + c) / 3.0;
            Prepared {
                corners: [a, b, c],
                normal: (b - a).cross(c - a).normalize_or_zero(),
                centre,
                // Slightly enlarged so that rounding never makes the bound exceed the distance.
                radius: (a - centre)
                    .length()
                    .max((b - centre).length())
                    .max((c - centre).length())
                    * (1.0 + 1e-12),
                t,
                nodes: unbox(reach[t as usize]),
            }
        }));
    }

    /// Each triangle of `cluster` offers its exact distance to the nodes of `slab` (planes
    /// `z_first..=z_last`) within `r` of its plane and its grown box; each node keeps the nearest,
    /// the lower index on a tie — what one pass over all triangles in index order leaves, so the
    /// clusters' order does not matter.
    fn splat(
        &mut self,
        grid: &Grid,
        cluster: &Cluster,
        r: f64,
        (z_first, z_last): (usize, usize),
        slab: &mut [Nearest],
    ) {
        let [nx, ny, _] = grid.dims;
        let b = cluster.nodes.map(|k| k as usize);
        for iz in b[4].max(z_first)..=b[5].min(z_last) {
            let z = grid.origin.z + grid.cell * iz as f64;
            for iy in b[2]..=b[3] {
                let y = grid.origin.y + grid.cell * iy as f64;
                self.row.clear();
                let (mut x0, mut x1) = (usize::MAX, 0);
                for (k, p) in self.prepared.iter().enumerate() {
                    let n = p.nodes;
                    if iz < n[4] || iz > n[5] || iy < n[2] || iy > n[3] {
                        continue;
                    }
                    if let Some((xa, xb)) = row_range(grid, p, y, z, r) {
                        self.row.push((k as u32, xa, xb));
                        x0 = x0.min(xa);
                        x1 = x1.max(xb);
                    }
                }
                if self.row.is_empty() {
                    continue;
                }
                let row = nx * (iy + ny * (iz - z_first));
                for ix in x0..=x1 {
                    let p = DVec3::new(grid.origin.x + grid.cell * ix as f64, y, z);
                    let node = &mut slab[row + ix];
                    // No triangle of the cluster is nearer than its box: a node that already
                    // holds a nearer value (by a margin over rounding) is done with them all.
                    let gap = (cluster.lo - p).max(p - cluster.hi).max(DVec3::ZERO);
                    let lim = node.d1 as f64 + self.slack;
                    if gap.length_squared() > lim * lim {
                        continue;
                    }
                    for &(k, xa, xb) in &self.row {
                        if ix < xa || ix > xb {
                            continue;
                        }
                        let tri = &self.prepared[k as usize];
                        // Cheap lower bound from the bounding sphere: skip nodes that already
                        // hold a value no farther than the sphere (most nodes, where
                        // neighbouring triangles' regions overlap).
                        // (|p − centre| − radius ≥ d ⇔ |p − centre|² ≥ (radius + d)².)
                        let reach = tri.radius + node.d1 as f64;
                        if (p - tri.centre).length_squared() >= reach * reach {
                            continue;
                        }
                        let [a, bb, c] = tri.corners;
                        // Nor nearer than its plane.
                        if tri.normal.dot(p - a).abs() > node.d1 as f64 + self.slack {
                            continue;
                        }
                        let q = closest_point_on_triangle(p, a, bb, c).0;
                        let s = (p - q).length_squared();
                        if s < node.d2 || (s == node.d2 && tri.t < node.triangle) {
                            *node = Nearest {
                                d2: s,
                                d1: f32_up(s.sqrt()),
                                triangle: tri.t,
                            };
                        }
                    }
                }
            }
        }
    }
}

/// The nodes `[first, last]` of row `(y, z)` within `r` of the plane of `p`, inside its box;
/// `None` when none is.
fn row_range(grid: &Grid, p: &Prepared, y: f64, z: f64, r: f64) -> Option<(usize, usize)> {
    let (a, nrm) = (p.corners[0], p.normal);
    let (x0, x1) = (p.nodes[0], p.nodes[1]);
    // Slab |n·(x − a)| ≤ r cut along x when the plane is not parallel to the x axis.
    if nrm.x.abs() > 1e-3 {
        // n·(x − a) = nrm.x·(x − a.x) + rest, |…| ≤ r  ⇒ x in an interval.
        let rest = nrm.y * (y - a.y) + nrm.z * (z - a.z);
        let u = a.x + (-r - rest) / nrm.x;
        let v = a.x + (r - rest) / nrm.x;
        let (u, v) = (u.min(v), u.max(v));
        let (p, q) = node_range(grid, 0, u, v)?;
        let (xa, xb) = (x0.max(p), x1.min(q));
        (xa <= xb).then_some((xa, xb))
    } else if nrm != DVec3::ZERO && (nrm.y * (y - a.y) + nrm.z * (z - a.z)).abs() > r {
        None
    } else {
        Some((x0, x1))
    }
}

/// [`triangles_band`] computed per node: a BVH query for the nearest triangle at every node that
/// can lie within `width_cells·c` of the target (the nodes near a triangle centre, dilated by the
/// band width plus the largest triangle's reach). On the band (`d ≤ r`) the values are exactly
/// those of the splat and the nearest triangle realises the same distance (on a tie at a shared
/// edge or vertex either may be named). Outside the band, where the splat may leave an upper
/// bound, nodes get no value: the queries stop at the band's radius, and the sweep fills the rest.
pub fn triangles_band_by_nodes(
    grid: &Grid,
    points: &[DVec3],
    triangles: &[[u32; 3]],
    width_cells: f64,
    init: f64,
    progress: &mut Progress,
) -> Band {
    let r = width_cells * grid.cell;
    let r2 = r * r;
    let n = grid.node_count();
    let [nx, ny, nz] = grid.dims;
    let mut reach = 0.0f64;
    let mut marked = vec![false; n];
    for tri in triangles {
        let [a, b, c] = tri.map(|v| points[v as usize]);
        let centre = (a + b + c) / 3.0;
        reach = reach.max(
            (a - centre)
                .length()
                .max((b - centre).length())
                .max((c - centre).length()),
        );
        let q = ((centre - grid.origin) / grid.cell).round();
        if q.is_finite() {
            let [ix, iy, iz] = [q.x, q.y, q.z].map(|x| x.max(0.0) as usize);
            if ix < nx && iy < ny && iz < nz {
                marked[ix + nx * (iy + ny * iz)] = true;
            }
        }
    }
    // Every node within r of a triangle lies within r + reach of its centre, and that centre
    // within half a cell diagonal of its marked node: dilate by that many cells per axis.
    let m = ((r + reach) / grid.cell).ceil() as usize + 1;
    dilate(&mut marked, grid.dims, m);
    let bvh = Bvh::new_morton_with(
        triangles.len(),
        |t| {
            let [a, b, c] = triangles[t].map(|v| points[v as usize]);
            (a.min(b).min(c), a.max(b).max(c))
        },
        4,
    );
    let nodes: Vec<u32> = (0..n as u32).filter(|&i| marked[i as usize]).collect();
    drop(marked);
    // Independent queries: in parallel natively, collected in node order.
    let hits = crate::parallel::map_chunked(
        nodes.len(),
        NODES_PER_REPORT,
        |k| {
            let p = grid.position_of(nodes[k] as usize);
            bvh.nearest_within(p, r2, |t| {
                let [a, b, c] = triangles[t as usize].map(|v| points[v as usize]);
                (p - closest_point_on_triangle(p, a, b, c).0).length_squared()
            })
        },
        &mut |done| progress.report(PHASE, done as f64 / nodes.len().max(1) as f64),
    );
    let mut d2 = vec![init * init; n];
    let mut nearest = vec![u32::MAX; n];
    for (&i, hit) in nodes.iter().zip(hits) {
        if let Some((t, s)) = hit {
            if s < d2[i as usize] {
                d2[i as usize] = s;
                nearest[i as usize] = t;
            }
        }
    }
    let mut band = finish(d2, r2, init);
    band.nearest_triangle = Some(nearest);
    band
}

/// Nodes between two progress reports (and per parallel batch) of [`triangles_band_by_nodes`].
const NODES_PER_REPORT: usize = 16384;

/// Grows the `true` set of a node mask by `m` nodes along each axis (a box dilation, separable).
fn dilate(mask: &mut [bool], dims: [usize; 3], m: usize) {
    let [nx, ny, nz] = dims;
    let strides = [1, nx, nx * ny];
    let lens = [nx, ny, nz];
    let mut line = Vec::new();
    for axis in 0..3 {
        let (len, stride) = (lens[axis], strides[axis]);
        // Every line along `axis`: its first node runs over the other two axes.
        for start in 0..mask.len() {
            if (start / stride) % len != 0 {
                continue;
            }
            line.clear();
            line.extend((0..len).map(|k| mask[start + k * stride]));
            // Distance to the nearest set node, forwards and backwards.
            let mut last: Option<usize> = None;
            for k in 0..len {
                if line[k] {
                    last = Some(k);
                }
                if last.is_some_and(|l| k - l <= m) {
                    mask[start + k * stride] = true;
                }
            }
            last = None;
            for k in (0..len).rev() {
                if line[k] {
                    last = Some(k);
                }
                if last.is_some_and(|l| l - k <= m) {
                    mask[start + k * stride] = true;
                }
            }
        }
    }
}

#[cfg(test)]
mod node_query_tests {
    use super::*;
    use crate::field::FieldSettings;
    use crate::geometry::aabb::Aabb;

    #[test]
    fn node_queries_equal_the_splat_on_the_band() {
        // A genus-2 surface of many triangles, small against the cells of a coarse grid.
        let (p, t) = crate::demo::genus2_surface(120);
        let settings = FieldSettings {
            cells_per_min_dimension: 12,
            ..Default::default()
        };
        let grid = Grid::for_bbox(&Aabb::from_points(&p), &settings).unwrap();
        let none = &mut Progress::none();
        let a = triangles_band(&grid, &p, &t, 3.0, f64::INFINITY, none);
        let b = triangles_band_by_nodes(&grid, &p, &t, 3.0, f64::INFINITY, none);
        assert_eq!(a.frozen, b.frozen);
        let (na, nb) = (a.nearest_triangle.unwrap(), b.nearest_triangle.unwrap());
        let mut band = 0;
        for i in 0..a.values.len() {
            if a.frozen[i] {
                band += 1;
                assert_eq!(a.values[i], b.values[i], "node {i}");
                // The same distance; on a tie (a shared edge or vertex) either triangle may be
                // named, and the sign's pseudo-normals agree for both.
                let q = grid.position_of(i);
                let dist = |k: u32| {
                    let [x, y, z] = t[k as usize].map(|v| p[v as usize]);
                    (q - closest_point_on_triangle(q, x, y, z).0).length()
                };
                assert_eq!(dist(na[i]), dist(nb[i]), "node {i}");
            } else {
                // Outside the band the splat may hold an upper bound; the queries leave it open.
                assert!(b.values[i] == f64::INFINITY, "node {i}");
            }
        }
        assert!(
            band > 1000 && t.len() > 20_000,
            "{band} band nodes, {} triangles",
            t.len()
        );
    }
}

#[cfg(test)]
mod cluster_tests {
    use super::*;
    use crate::field::FieldSettings;
    use crate::geometry::aabb::Aabb;

    /// The plain splat without clusters, the reference the clustered one is checked against:
    /// triangle `t` = `[a, b, c]` offers its exact distance to the nodes of `slab` (whose first
    /// z-plane is `z_first`) within `r` of its plane and its grown box (`xy` node ranges, `z`
    /// planes); each keeps the nearer.
    #[allow(clippy::too_many_arguments)]
    fn splat_triangle(
        grid: &Grid,
        [a, b, c]: [DVec3; 3],
        t: u32,
        r: f64,
        [x0, x1, y0, y1]: [usize; 4],
        (z0, z1): (usize, usize),
        z_first: usize,
        slab: &mut [Nearest],
    ) {
        let [nx, ny, _] = grid.dims;
        let nrm = (b - a).cross(c - a).normalize_or_zero();
        let centre = (a + b + c) / 3.0;
        // Slightly enlarged so that rounding never makes the bound exceed the true distance.
        let radius = (a - centre)
            .length()
            .max((b - centre).length())
            .max((c - centre).length())
            * (1.0 + 1e-12);
        // Slab |n·(x − a)| ≤ r cut along x when the plane is not parallel to the x axis.
        let slab_x = nrm.x.abs() > 1e-3;
        for iz in z0..=z1 {
            let z = grid.origin.z + grid.cell * iz as f64;
            for iy in y0..=y1 {
                let y = grid.origin.y + grid.cell * iy as f64;
                let (mut xa, mut xb) = (x0, x1);
                if slab_x {
                    // n·(x − a) = nrm.x·(x − a.x) + rest, |…| ≤ r  ⇒ x in an interval.
                    let rest = nrm.y * (y - a.y) + nrm.z * (z - a.z);
                    let u = a.x + (-r - rest) / nrm.x;
                    let v = a.x + (r - rest) / nrm.x;
                    let (u, v) = (u.min(v), u.max(v));
                    match node_range(grid, 0, u, v) {
                        Some((p, q)) => {
                            xa = xa.max(p);
                            xb = xb.min(q);
                            if xa > xb {
                                continue;
                            }
                        }
                        None => continue,
                    }
                } else if nrm != DVec3::ZERO && (nrm.y * (y - a.y) + nrm.z * (z - a.z)).abs() > r {
                    continue;
                }
                let row = nx * (iy + ny * (iz - z_first));
                for ix in xa..=xb {
                    let p = DVec3::new(grid.origin.x + grid.cell * ix as f64, y, z);
                    let node = &mut slab[row + ix];
                    // Cheap lower bound from the bounding sphere: skip nodes that already hold
                    // a value no farther than the sphere (most nodes, where neighbouring
                    // triangles' regions overlap).
                    // (|p − centre| − radius ≥ d ⇔ |p − centre|² ≥ (radius + d)².)
                    let reach = radius + node.d1 as f64;
                    if (p - centre).length_squared() >= reach * reach {
                        continue;
                    }
                    let q = closest_point_on_triangle(p, a, b, c).0;
                    let s = (p - q).length_squared();
                    if s < node.d2 {
                        *node = Nearest {
                            d2: s,
                            d1: f32_up(s.sqrt()),
                            triangle: t,
                        };
                    }
                }
            }
        }
    }

    /// Every triangle in index order over the whole grid, keeping the strictly nearer.
    fn one_by_one(grid: &Grid, points: &[DVec3], triangles: &[[u32; 3]], r: f64) -> Vec<Nearest> {
        let mut best = vec![
            Nearest {
                d2: f64::INFINITY,
                d1: f32::INFINITY,
                triangle: u32::MAX,
            };
            grid.node_count()
        ];
        for (t, tri) in triangles.iter().enumerate() {
            let [a, b, c] = tri.map(|v| points[v as usize]);
            let lo = a.min(b).min(c) - DVec3::splat(r);
            let hi = a.max(b).max(c) + DVec3::splat(r);
            let (Some(x), Some(y), Some(z)) = (
                node_range(grid, 0, lo.x, hi.x),
                node_range(grid, 1, lo.y, hi.y),
                node_range(grid, 2, lo.z, hi.z),
            ) else {
                continue;
            };
            splat_triangle(
                grid,
                [a, b, c],
                t as u32,
                r,
                [x.0, x.1, y.0, y.1],
                z,
                0,
                &mut best,
            );
        }
        best
    }

    #[test]
    fn clusters_leave_what_one_triangle_after_another_leaves() {
        // Many small triangles a cell (clusters of dozens), a CAD part whose faces meet at
        // right angles on grid-aligned edges (ties at shared edges and corners), and a soup
        // with every internal face twice (exact ties between triangles).
        for (name, cells) in [
            ("genus2", 10),
            ("cube-hole", 9),
            ("cad-part", 40),
            ("box-soup", 7),
        ] {
            // (As read from a file of f32 coordinates.)
            let (p, t) = crate::demo::shape(name).unwrap();
            let p: Vec<DVec3> = p.iter().map(|q| q.as_vec3().as_dvec3()).collect();
            let settings = FieldSettings {
                cells_per_min_dimension: cells,
                ..Default::default()
            };
            let grid = Grid::for_bbox(&Aabb::from_points(&p), &settings).unwrap();
            let r = 3.0 * grid.cell;
            let band = triangles_band(&grid, &p, &t, 3.0, f64::INFINITY, &mut Progress::none());
            let reference = one_by_one(&grid, &p, &t, r);
            let nearest = band.nearest_triangle.unwrap();
            let mut reached = 0;
            for (i, n) in reference.iter().enumerate() {
                let value = if n.d2 < f64::INFINITY {
                    n.d2.sqrt()
                } else {
                    f64::INFINITY
                };
                assert_eq!(
                    band.values[i].to_bits(),
                    value.to_bits(),
                    "{name}: node {i}"
                );
                assert_eq!(nearest[i], n.triangle, "{name}: node {i}");
                reached += usize::from(n.triangle != u32::MAX);
            }
            let clusters = cluster_triangles(&grid, &p, &t, &{
                let reach: Vec<Option<NodeBox>> = vec![Some([0; 6]); t.len()];
                reach
            });
            assert!(reached > 1000, "{name}: {reached} nodes reached");
            if name == "genus2" {
                let most = clusters
                    .iter()
                    .map(|c| c.triangles.len())
                    .max()
                    .unwrap_or(0);
                assert!(most >= 20, "{name}: at most {most} triangles a cluster");
            }
        }
    }
}
