//! Collision detection for surgery: pairs of surface vertices that are close in space, lie back
//! to back (a thin slab of the inside between them: normals opposed, each behind the other), and
//! both lie far from the target. A genus-0 surface shrinking onto a handle grows two
//! membranes across the handle's hole that approach each other in empty space; those are the
//! pairs found here. Sheets meeting *at the data* (the two sides of one scan layer, a membrane
//! sagging onto the inside of a scan) are never paired: their vertices are near the target.
//!
//! A membrane stuck in a *tunnel* is paired too: a through-hole at least as deep as it is wide
//! has a distance field that is flat along its axis (every point of the axis is the hole's radius
//! from the wall), so the membranes over its two ends feel no pull towards each other and never
//! meet. Two facing far vertices are also paired when a path marched from one to the other stays
//! in empty space and data rings it all the way (see [`tunnel_partner`]); a slot or a notch open
//! on one side is not ringed and stays closed, as do the two sides of a part (data between them).
//!
//! Cost: one bucket grid over the far vertices and one k-nearest query per far vertex, O(V); the
//! tunnel search marches the distance field inwards from each far vertex left unpaired and stops
//! at the first data, so it costs a few field samples per vertex except in tunnels.

use crate::geometry::spatial::point_grid::{Near, PointGrid};
use crate::mesh::HalfedgeMesh;
use glam::DVec3;

/// Neighbours examined per far vertex.
const NEIGHBOURS: usize = 16;

/// Facing: the normals of the two vertices make an angle above ≈ 135°.
const FACING_COS: f64 = -0.7;

/// What to pair.
#[derive(Clone, Debug, PartialEq)]
pub struct FacingQuery {
    /// A vertex is in empty space when its distance to the target exceeds this.
    pub empty: f64,
    /// Two facing vertices pair when their gap along the normals is below this fraction of the
    /// smaller of their distances to the target (and they are at most an edge apart sideways).
    pub gap_ratio: f64,
    /// Balls (centre, radius) round the holes already opened: nothing in such a hole pairs (see
    /// [`in_opened_hole`]). The membrane left around a fresh tube still faces its other half
    /// across the tube; cutting it again would open a second handle in the same hole.
    pub opened: Vec<(DVec3, f64)>,
    /// Tunnels: two facing sheets also pair when their gap is below this multiple of the smaller
    /// of their distances to the target and the path between them is a tunnel through the data
    /// ([`tunnel_partner`]). 0: off.
    pub tunnel_ratio: f64,
    /// A tunnel narrower than this (its distance to the data along the way) stays closed (the
    /// `surgery.close_gaps` width: `empty` alone admits tunnels a little narrower, see
    /// [`PATH_CLEAR`]).
    pub min_width: f64,
    /// The target's genus where known (a closed one-part mesh's): a neck cut that would take a
    /// handle away is made only while the surface has more handles than this. Unknown (a
    /// cloud's): only a neck whose sheets face across it (see [`super::bridge`]).
    pub least_genus: Option<i64>,
}

/// A hole's membrane may reach farther from its tube than the ball in [`FacingQuery::opened`]:
/// up to this many times the ball's radius, a vertex joined to the tube's centre by a straight
/// path through empty space is still in the same hole.
const SAME_HOLE_REACH: f64 = 3.0;
/// Data lies on such a path where the distance drops below this share of `empty`, or of the
/// distance at its nearer end where that is larger (its samples are a quarter of `empty` apart:
/// the distance is 1-Lipschitz, so a path crossing the data has a sample within an eighth of
/// `empty` of it; a membrane's own vertices are farther than half).
const DATA_ON_THE_WAY: f64 = 0.5;

/// Whether `p` lies in a hole already opened (`opened`: balls round the tubes, see
/// [`FacingQuery::opened`]): within [`SAME_HOLE_REACH`] times its ball, with
/// no data on the straight way to its centre (`probe` signed: the inside of a solid is data).
/// A square hole can keep membrane in its corners beyond the ball round its first tube, and a
/// second tube there would add a false handle; the ball round a tube across a wide, low hole
/// (between two rails) reaches the holes above and below it, which have a rail on the way.
pub fn in_opened_hole(
    p: DVec3,
    opened: &[(DVec3, f64)],
    empty: f64,
    probe: &dyn Fn(DVec3) -> f64,
) -> bool {
    opened.iter().any(|&(c, r)| {
        let d2 = p.distance_squared(c);
        let reach = SAME_HOLE_REACH * r;
        if d2 > reach * reach {
            return false;
        }
        if empty <= 0.0 {
            return d2 <= r * r;
        }
        // (Half the nearer end's distance, not only half of `empty`: between two holes of a plate
        // thicker than `empty`, a path through its unsigned inside keeps half its thickness.)
        let floor = DATA_ON_THE_WAY * empty.max(probe(p).min(probe(c)));
        let samples = (d2.sqrt() / (0.25 * empty)).ceil().max(1.0) as usize;
        (1..=samples).all(|k| probe(p.lerp(c, k as f64 / samples as f64)) > floor)
    })
}

/// Directions of the ring of rays cast around a tunnel's axis.
const RING_RAYS: usize = 8;
/// A ring ray looks for data this many times its start's distance to the target: a round hole's
/// wall is at 1×, an oval hole's far wall at its aspect ratio.
const RING_REACH: f64 = 4.0;
/// Points along a tunnel's path where the ring is tested (fractions of the path).
const RING_AT: [f64; 3] = [0.25, 0.5, 0.75];

/// For every vertex, the nearest vertex of a facing sheet in empty space (`None` when there is
/// none). `distances` are the vertices' distances to the target, `normals` their unit normals.
/// `probe` is the distance to the target at any point (its absolute value is used).
/// Deterministic: ties go to the smaller index.
pub fn facing_pairs(
    mesh: &HalfedgeMesh,
    normals: &[DVec3],
    distances: &[f64],
    q: &FacingQuery,
    probe: &dyn Fn(DVec3) -> f64,
) -> Vec<Option<u32>> {
    facing_pairs_and_tunnels(mesh, normals, distances, q, probe, PATCH_WIDTHS).0
}

/// [`facing_pairs`], and the tunnels it paired across: each hole's middle and the farthest wall
/// met from there (a ball in which no later look should pair again: a hole wider one way than
/// the other keeps membrane around its tube that would open it a second time). A tunnel's
/// membranes reach `patch_widths` times its half-width from its two ends ([`PATCH_WIDTHS`]).
pub fn facing_pairs_and_tunnels(
    mesh: &HalfedgeMesh,
    normals: &[DVec3],
    distances: &[f64],
    q: &FacingQuery,
    probe: &dyn Fn(DVec3) -> f64,
    patch_widths: f64,
) -> (Vec<Option<u32>>, Vec<(DVec3, f64)>) {
    let mut holes = Vec::new();
    let n = mesh.n_vertices();
    let mut partner = vec![None; n];
    if let Some(s) = Sheet::beyond(mesh, normals, distances, q, q.empty, probe, true) {
        let part = components(mesh);
        let far_part = far_parts(mesh, distances, q.empty);
        let mut near: Vec<Near> = Vec::with_capacity(NEIGHBOURS);
        for (i, &v) in s.far.iter().enumerate() {
            let (p, nv, dv) = (s.pts[i], normals[v as usize], distances[v as usize].abs());
            s.grid
                .nearest_within(p, q.gap_ratio * dv + s.edges[i], NEIGHBOURS, &mut near);
            partner[v as usize] = near.iter().find_map(|c| {
                let j = c.index as usize;
                let u = s.far[j];
                let (nu, du) = (normals[u as usize], distances[u as usize].abs());
                let w = c.point - p;
                // Separation along the normals and sideways. Back to back (u behind v and v
                // behind u: a slab of the inside between them) on one surface; face to face (the
                // outside between them) only across two components, which then merge.
                let (sv, su) = (-w.dot(nv), w.dot(nu));
                let side = (w + sv * nv).length();
                let back_to_back = sv > 0.0 && su > 0.0;
                let face_to_face = sv < 0.0 && su < 0.0 && part[u as usize] != part[v as usize];
                // In an opened hole, only sheets that empty space does not join yet.
                let same_hole =
                    (s.opened[i] || s.opened[j]) && far_part[u as usize] == far_part[v as usize];
                let facing = nv.dot(nu) < FACING_COS
                    && !same_hole
                    && (back_to_back || face_to_face)
                    && sv.abs().max(su.abs()) < q.gap_ratio * du.min(dv)
                    && side <= s.edges[i].max(s.edges[j]);
                (u != v && facing).then_some(u)
            });
        }
    }
    // Tunnels: the membranes over a narrow hole may rest nearer the data than `empty` (a hole
    // of 3 `empty` across has its axis 1.5 away); the clear path and the ring tell it from a part.
    let tunnels = (q.tunnel_ratio > 0.0)
        .then(|| {
            Sheet::beyond(
                mesh,
                normals,
                distances,
                q,
                TUNNEL_FAR * q.empty,
                probe,
                false,
            )
        })
        .flatten();
    if let Some(s) = tunnels {
        // Only the vertices near a membrane's centre look straight down the tunnel (the others'
        // normals tilt towards its wall): each membrane is the patch of far vertices around the
        // one that found the tunnel, and the two patches pair with each other.
        let mut slot = vec![u32::MAX; n];
        for (i, &v) in s.far.iter().enumerate() {
            slot[v as usize] = i as u32;
        }
        for i in 0..s.far.len() {
            let v = s.far[i];
            if partner[v as usize].is_some() {
                continue;
            }
            let Some(Found {
                partner: u,
                width,
                hole,
            }) = tunnel_partner(&s, i, q, probe)
            else {
                continue;
            };
            holes.push(hole);
            let reach = (patch_widths * width).max(PATCH_EDGES * s.edges[i]);
            let (a, b) = (
                s.patch(mesh, &slot, v, reach),
                s.patch(mesh, &slot, u, reach),
            );
            for (side, other) in [(&a, u), (&b, v)] {
                for &x in side.iter() {
                    partner[x as usize].get_or_insert(other);
                }
            }
        }
    }
    (partner, holes)
}

/// A tunnel's membrane reaches this many times the tunnel's half-width (the distance to the
/// target at its middle) from the vertex that found it (by default; see
/// [`super::open_handles`] for the narrower retry). Wider patches cut tubes wider than their
/// holes, which end farther from the data; narrower ones miss small holes (see
/// docs/decisions/).
pub const PATCH_WIDTHS: f64 = 1.5;
/// … and at least this many of its edges: a hole a few edges wide (the smallest of a plate's)
/// needs a patch of a ring or two to make a tube.
const PATCH_EDGES: f64 = 2.0;

/// Vertices of a tunnel's membranes are farther from the data than this share of `empty`.
const TUNNEL_FAR: f64 = 0.5;
/// A tunnel's path keeps farther from the data than this share of `empty`: 2.25 point spacings,
/// a gap that a random sampling of a wall leaves about once in 10⁷ spacings². Closer, a path
/// can slip through both faces of a sparsely sampled plate, whose inside then looks like a
/// tunnel and gets a false handle.
const PATH_CLEAR: f64 = 0.75;
/// A tunnel's path runs level: farther from the data than this share of its vertex's distance
/// all the way (along a hole's axis the distance hardly changes). Paths through holes stay
/// well above this share; paths from the lining of a sampled shell cut open (the wrap dents
/// into it through the opening) towards the shell fall well below it within a step, though
/// their rings meet the curved wall all round as a hole's would.
const LEVEL: f64 = 0.8;
/// A ring ray meets the data within this share of `empty` (1.5 spacings, one cell: it does not
/// slip through the gaps of a sampled wall).
const RING_HIT: f64 = 0.5;
/// A tunnel's wall reaches this share of `empty` either side of its middle along the path: a ring
/// there lies 1.5× [`RING_HIT`] off a sheet through the middle, so that its rays along the sheet
/// miss it, while the walls of real tunnels reach at least about this far.
const DEPTH: f64 = 0.75;

/// Vertices farther from the data than a threshold, bucketed for neighbour queries.
struct Sheet<'a> {
    far: Vec<u32>,
    /// Whether each far vertex lies in an opened hole.
    opened: Vec<bool>,
    pts: Vec<DVec3>,
    /// Mean length of each far vertex's edges.
    edges: Vec<f64>,
    normals: &'a [DVec3],
    distances: &'a [f64],
    grid: PointGrid,
}

impl<'a> Sheet<'a> {
    /// The vertices farther than `beyond` from the data, bucketed for queries up to the largest
    /// reach of `q`; `None` when fewer than two. Those in the opened holes (see
    /// [`in_opened_hole`]) are flagged in `opened` when `keep_opened`, else left out.
    fn beyond(
        mesh: &HalfedgeMesh,
        normals: &'a [DVec3],
        distances: &'a [f64],
        q: &FacingQuery,
        beyond: f64,
        probe: &dyn Fn(DVec3) -> f64,
        keep_opened: bool,
    ) -> Option<Self> {
        let mut far = Vec::new();
        let mut opened = Vec::new();
        for v in 0..mesh.n_vertices() as u32 {
            if mesh.is_deleted_vertex(v) || distances[v as usize].abs() <= beyond {
                continue;
            }
            let in_hole = in_opened_hole(mesh.position(v), &q.opened, q.empty, probe);
            if keep_opened || !in_hole {
                far.push(v);
                opened.push(in_hole);
            }
        }
        if far.len() < 2 {
            return None;
        }
        let pts: Vec<DVec3> = far.iter().map(|&v| mesh.position(v)).collect();
        // Vertices are spaced by their edges, which may be far longer than the gap between two
        // sheets: the gap is taken along the normal, and a partner may sit up to an edge
        // away sideways.
        let edges: Vec<f64> = far.iter().map(|&v| mesh.mean_edge_length(v)).collect();
        let max_reach = far
            .iter()
            .zip(&edges)
            .map(|(&v, e)| q.gap_ratio * distances[v as usize].abs() + e)
            .fold(0.0, f64::max);
        if !(max_reach > 0.0 && max_reach.is_finite()) {
            return None;
        }
        let grid = PointGrid::new(&pts, max_reach);
        Some(Self {
            far,
            opened,
            pts,
            edges,
            normals,
            distances,
            grid,
        })
    }

    /// The far vertices joined to `from` through far vertices within `radius` of it (`slot`:
    /// each vertex's index in `far`, `u32::MAX` when not far).
    fn patch(&self, mesh: &HalfedgeMesh, slot: &[u32], from: u32, radius: f64) -> Vec<u32> {
        let centre = mesh.position(from);
        let mut seen = vec![false; self.far.len()];
        let mut patch = vec![from];
        if let Some(s) = seen.get_mut(slot[from as usize] as usize) {
            *s = true;
        }
        let mut k = 0;
        while k < patch.len() {
            let v = patch[k];
            k += 1;
            for u in mesh.neighbors(v) {
                let i = slot[u as usize] as usize;
                if i < seen.len()
                    && !seen[i]
                    && mesh.position(u).distance_squared(centre) <= radius * radius
                {
                    seen[i] = true;
                    patch.push(u);
                }
            }
        }
        patch
    }
}

/// The facing far vertex across a tunnel from far vertex `i`, if any, and the tunnel's
/// half-width (the distance to the data half-way). The path marches inwards along the vertex's
/// normal in steps of half an edge, drawn at each step towards the tunnel's axis (up the distance
/// across the path: a membrane's normals tilt towards the wall, and a hole only a little wider
/// than `empty` leaves no room for a straight path from off its axis). It must keep farther than
/// [`PATH_CLEAR`] from the data, and than [`LEVEL`] times the vertex's distance, at its points
/// and along its steps, until it comes within an edge of a far vertex whose normal
/// faces back (a slab of the inside between them), within `tunnel_ratio` times the smaller
/// distance, the hop to it keeping as clear as the first step. Then, at a quarter, half and three
/// quarters of the way, the path must be farther than [`RING_HIT`] from the data and rays in
/// every direction across it must meet the data within [`RING_REACH`] times that distance (the
/// hole's wall); so must rays from [`DEPTH`] either side of the middle between the two vertices.
/// The ring is what tells a tunnel from a path that slipped through a sparse wall: beside a
/// wall, rays along it never meet it; the rings off the middle tell it from a gap in a sampled
/// sheet, whose only wall is the sheet.
fn tunnel_partner(
    s: &Sheet,
    i: usize,
    q: &FacingQuery,
    probe: &dyn Fn(DVec3) -> f64,
) -> Option<Found> {
    let v = s.far[i];
    let (p, nv, dv) = (
        s.pts[i],
        s.normals[v as usize],
        s.distances[v as usize].abs(),
    );
    let clear = PATH_CLEAR * q.empty;
    let step = 0.5 * s.edges[i];
    if !(step > 0.0 && clear > 0.0 && nv.length_squared() > 0.5) {
        return None;
    }
    let dir = -nv;
    let d = |x: DVec3| probe(x).abs();
    // The path's steps (each up to half an edge) keep as clear as its points, the first one
    // from the vertex as clear as the vertex: a step may span a wall (from the wrap outside a
    // sampled shell cut open, over the shell, to the lining inside it).
    let keeps_clear = |from: DVec3, to: DVec3, clear: f64| {
        let gap = to - from;
        let length = gap.length();
        length <= 0.0 || ray_meets_data(from, gap / length, length, clear, probe).is_none()
    };
    let mut near: Vec<Near> = Vec::with_capacity(4);
    let mut path = Vec::new();
    let mut x = p;
    let (u, pu) = loop {
        if path.len() as f64 * step > q.tunnel_ratio * dv {
            return None;
        }
        x += step * dir;
        let h = 0.5 * step;
        let g = DVec3::new(
            d(x + h * DVec3::X) - d(x - h * DVec3::X),
            d(x + h * DVec3::Y) - d(x - h * DVec3::Y),
            d(x + h * DVec3::Z) - d(x - h * DVec3::Z),
        ) / (2.0 * h);
        x += 0.5 * step * (g - g.dot(dir) * dir).clamp_length_max(1.0);
        let (from, keep) = match path.last() {
            Some(&last) => (last, clear),
            None => (p, TUNNEL_FAR * q.empty),
        };
        if d(x) <= clear.max(LEVEL * dv) || !keeps_clear(from, x, keep) {
            return None;
        }
        path.push(x);
        s.grid.nearest_within(x, s.edges[i], 4, &mut near);
        let found = near.iter().find_map(|c| {
            let u = s.far[c.index as usize];
            let nu = s.normals[u as usize];
            let w = c.point - p;
            let du = s.distances[u as usize].abs();
            (u != v
                && nv.dot(nu) < FACING_COS
                && -w.dot(nv) > 0.0
                && w.dot(nu) > 0.0
                && -w.dot(nv) < q.tunnel_ratio * du.min(dv)
                && keeps_clear(x, c.point, TUNNEL_FAR * q.empty))
            .then_some((u, c.point))
        });
        if let Some(found) = found {
            break found;
        }
    };
    let (a, b) = dir.any_orthonormal_pair();
    // The ring's rays: every direction across the path.
    let rays = (0..RING_RAYS).map(|k| {
        let angle = std::f64::consts::TAU * k as f64 / RING_RAYS as f64;
        a * crate::fmath::cos(angle) + b * crate::fmath::sin(angle)
    });
    let at = |f: f64| path[((f * path.len() as f64) as usize).min(path.len() - 1)];
    // The farthest wall met by the rings: the hole's extent about its middle.
    let mut extent: f64 = 0.0;
    let ringed = RING_AT.iter().all(|&f| {
        let m = at(f);
        let dm = d(m);
        dm > clear.max(q.min_width)
            && rays.clone().all(|ray| {
                let hit = ray_meets_data(m, ray, RING_REACH * dm, RING_HIT * q.empty, probe);
                extent = extent.max(hit.unwrap_or(0.0) + m.distance(at(0.5)));
                hit.is_some()
            })
    });
    // The wall runs along the tunnel: rings [`DEPTH`] either side of the middle between the two
    // membranes meet it too. A gap in a sampled sheet (no thickness), into which the wrap's two
    // sides sag until they face each other across it, is ringed at the sheet only.
    let deep = || {
        let (mid, reach) = (p.lerp(pu, 0.5), RING_REACH * d(at(0.5)));
        [-1.0, 1.0].iter().all(|&side| {
            let m = mid + side * DEPTH * q.empty * dir;
            rays.clone()
                .all(|ray| ray_meets_data(m, ray, reach, RING_HIT * q.empty, probe).is_some())
        })
    };
    (ringed && deep()).then_some(Found {
        partner: u,
        width: d(at(0.5)),
        hole: (at(0.5), extent),
    })
}

/// A tunnel found from one vertex.
struct Found {
    partner: u32,
    /// The distance to the data half-way.
    width: f64,
    /// The hole: the path's middle and the farthest wall the rings met from it.
    hole: (DVec3, f64),
}

/// How far the ray from `o` along unit `dir` goes before it comes within `clear` of the data,
/// `None` when not before `length` (sphere tracing: each step is the distance to the data less
/// `clear`, at least a tenth of it).
fn ray_meets_data(
    o: DVec3,
    dir: DVec3,
    length: f64,
    clear: f64,
    probe: &dyn Fn(DVec3) -> f64,
) -> Option<f64> {
    let mut t = 0.0;
    while t <= length {
        let d = probe(o + t * dir).abs();
        if d <= clear {
            return Some(t);
        }
        t += (d - clear).max(0.1 * clear);
    }
    None
}

/// The connected component of every vertex (deterministic numbering).
fn components(mesh: &HalfedgeMesh) -> Vec<u32> {
    components_of(mesh, |_| true)
}

/// Vertices farther from the data than this share of `empty` join membranes in [`far_parts`]:
/// every paired vertex is (see [`TUNNEL_FAR`]).
const FAR_PART: f64 = TUNNEL_FAR;

/// The parts of the surface in empty space: the component of every vertex farther than
/// [`FAR_PART`] × `empty` from the data (`distances`) among such vertices, `u32::MAX` for the
/// others. Two membranes over one hole are joined through empty space once a tube runs between
/// them; membranes over different holes, or over the arms of one cavity (a cube drilled through
/// along three axes), meet only at the data, however close they come in the middle.
pub fn far_parts(mesh: &HalfedgeMesh, distances: &[f64], empty: f64) -> Vec<u32> {
    components_of(mesh, |v| distances[v as usize].abs() > FAR_PART * empty)
}

/// The connected component of every vertex `keep` accepts, among those (deterministic
/// numbering); `u32::MAX` for the others.
fn components_of(mesh: &HalfedgeMesh, keep: impl Fn(u32) -> bool) -> Vec<u32> {
    let n = mesh.n_vertices();
    let mut part = vec![u32::MAX; n];
    let mut id = 0;
    let mut stack = Vec::new();
    for s in 0..n as u32 {
        if part[s as usize] != u32::MAX || !keep(s) {
            continue;
        }
        part[s as usize] = id;
        stack.push(s);
        while let Some(v) = stack.pop() {
            if mesh.is_deleted_vertex(v) {
                continue;
            }
            for u in mesh.neighbors(v) {
                if part[u as usize] == u32::MAX && keep(u) {
                    part[u as usize] = id;
                    stack.push(u);
                }
            }
        }
        id += 1;
    }
    part
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::icosphere::icosphere;
    use crate::geometry::operators::normals::angle_weighted_normals;
    use glam::DVec2;

    /// The query of these tests: `empty` 0.5, gap ratio 0.25, nothing opened, no tunnels.
    fn query() -> FacingQuery {
        FacingQuery {
            empty: 0.5,
            gap_ratio: 0.25,
            opened: vec![],
            tunnel_ratio: 0.0,
            min_width: 0.0,
            least_genus: None,
        }
    }

    /// A sphere squashed into a pancake: its top and bottom face each other across a small gap.
    fn pancake(gap: f64) -> HalfedgeMesh {
        let mut m = icosphere(4, 1.0, DVec3::ZERO).unwrap();
        for p in m.positions_mut() {
            p.z *= gap / 2.0;
        }
        m
    }

    #[test]
    fn a_pancake_in_empty_space_pairs_its_two_faces() {
        let m = pancake(0.02);
        let normals = angle_weighted_normals(&m);
        let far = vec![1.0; m.n_vertices()];
        let mut q = query();
        let pairs = facing_pairs(&m, &normals, &far, &q, &|_| 1.0);
        let paired: Vec<u32> = (0..m.n_vertices() as u32)
            .filter(|&v| pairs[v as usize].is_some())
            .collect();
        assert!(paired.len() > m.n_vertices() / 2, "{}", paired.len());
        for v in paired {
            let u = pairs[v as usize].unwrap();
            let (pv, pu) = (m.position(v), m.position(u));
            assert!(pv.z * pu.z < 0.0, "pairs join top and bottom");
            assert!((pv - pu).length() < 0.1);
        }
        // Nothing pairs inside a hole already opened.
        q.opened.push((DVec3::ZERO, 2.0));
        assert!(facing_pairs(&m, &normals, &far, &q, &|_| 1.0)
            .iter()
            .all(Option::is_none));
    }

    /// The pancake's top and bottom inside an opened hole's ball, joined only at its rim. Joined
    /// through empty space (the rim far from the data, as around a tube) they are that hole and
    /// do not pair; with the rim on the data they are two membranes that meet in one cavity (the
    /// arms of a cube drilled along three axes) and pair.
    #[test]
    fn sheets_joined_only_at_the_data_pair_in_an_opened_hole() {
        let m = pancake(0.02);
        let normals = angle_weighted_normals(&m);
        let q = FacingQuery {
            opened: vec![(DVec3::ZERO, 2.0)],
            ..query()
        };
        let count = |distances: &[f64]| {
            facing_pairs(&m, &normals, distances, &q, &|_| 1.0)
                .iter()
                .filter(|p| p.is_some())
                .count()
        };
        let far = vec![1.0; m.n_vertices()];
        assert_eq!(count(&far), 0);
        let rim_on_data: Vec<f64> = m
            .positions()
            .iter()
            .map(|p| {
                if p.truncate().length() > 0.9 {
                    0.0
                } else {
                    1.0
                }
            })
            .collect();
        assert!(count(&rim_on_data) > m.n_vertices() / 2);
        assert_eq!(far_parts(&m, &far, q.empty).iter().max(), Some(&0));
        let parts = far_parts(&m, &rim_on_data, q.empty);
        assert_eq!(parts.iter().filter(|&&p| p != u32::MAX).max(), Some(&1));
    }

    /// A hole opened by a small tube at x = −1.5: the pancake (|x|, |y| ≤ 1) lies partly in the
    /// tube's ball and the rest within reach of it. Through empty space it is the same hole and
    /// nothing pairs; with data on the way (a bar at x = −1.1) it is another hole and its faces
    /// pair.
    #[test]
    fn membrane_joined_to_an_opened_hole_through_empty_space_is_that_hole() {
        let m = pancake(0.02);
        let normals = angle_weighted_normals(&m);
        let far = vec![1.0; m.n_vertices()];
        let q = FacingQuery {
            opened: vec![(DVec3::new(-1.5, 0.0, 0.0), 1.0)],
            ..query()
        };
        let count = |probe: &dyn Fn(DVec3) -> f64| {
            facing_pairs(&m, &normals, &far, &q, probe)
                .iter()
                .filter(|p| p.is_some())
                .count()
        };
        let empty = |_: DVec3| 1.0;
        assert_eq!(count(&empty), 0);
        let bar = |p: DVec3| DVec2::new(p.x + 1.1, p.z).length();
        assert!(count(&bar) > m.n_vertices() / 2);
        // Beyond reach (3 balls), a vertex is never taken for the opened hole.
        let far_hole = FacingQuery {
            opened: vec![(DVec3::new(-4.5, 0.0, 0.0), 1.0)],
            ..q.clone()
        };
        let pairs = facing_pairs(&m, &normals, &far, &far_hole, &empty);
        assert!(pairs.iter().filter(|p| p.is_some()).count() > m.n_vertices() / 2);
    }

    /// Distance to a plate `|z| ≤ h` with a round hole of radius `r` about the z axis, or (slot)
    /// with a straight slot `|y| < r` across it, open at both ends.
    fn plate_distance(p: DVec3, r: f64, h: f64, slot: bool) -> f64 {
        let across = if slot {
            p.y.abs()
        } else {
            p.truncate().length()
        };
        let above = (p.z.abs() - h).max(0.0);
        if across < r {
            DVec2::new(r - across, above).length()
        } else {
            above
        }
    }

    /// A pancake 1 thick with its faces over a hole 1.2 wide and 0.6 deep: the faces are 1
    /// apart and 1.2 from the wall, far above a quarter of their distance, so only the tunnel
    /// test pairs them; over a slot (open at its ends) or over a solid plate it does not.
    #[test]
    fn membranes_over_a_deep_hole_pair_as_a_tunnel_and_only_there() {
        let m = pancake(1.0);
        let normals = angle_weighted_normals(&m);
        let pairs_wider = |tunnel_ratio: f64, min_width: f64, probe: &dyn Fn(DVec3) -> f64| {
            let d: Vec<f64> = m.positions().iter().map(|&p| probe(p)).collect();
            let q = FacingQuery {
                tunnel_ratio,
                min_width,
                ..query()
            };
            facing_pairs(&m, &normals, &d, &q, probe)
        };
        let pairs =
            |tunnel_ratio: f64, probe: &dyn Fn(DVec3) -> f64| pairs_wider(tunnel_ratio, 0.0, probe);
        let hole = |p: DVec3| plate_distance(p, 1.2, 0.3, false);
        let found = pairs(4.0, &hole);
        let paired: Vec<u32> = (0..m.n_vertices() as u32)
            .filter(|&v| found[v as usize].is_some())
            .collect();
        assert!(paired.len() > 20, "{}", paired.len());
        for v in paired {
            let (pv, pu) = (m.position(v), m.position(found[v as usize].unwrap()));
            assert!(
                pv.z * pu.z < 0.0,
                "pairs join top and bottom: {pv:?} {pu:?}"
            );
        }
        // The hole found: its middle between the faces, its farthest wall across the hole.
        let d: Vec<f64> = m.positions().iter().map(|&p| hole(p)).collect();
        let mut q = FacingQuery {
            tunnel_ratio: 4.0,
            ..query()
        };
        let (wide, holes) = facing_pairs_and_tunnels(&m, &normals, &d, &q, &hole, PATCH_WIDTHS);
        assert!(!holes.is_empty());
        // Narrower patches (the retry when a tube crossed the surface) pair fewer vertices,
        // round the same path.
        let (narrow, _) = facing_pairs_and_tunnels(&m, &normals, &d, &q, &hole, 0.5);
        let count = |f: &[Option<u32>]| f.iter().filter(|p| p.is_some()).count();
        assert!(
            count(&narrow) > 2 && count(&narrow) < count(&wide),
            "{} {}",
            count(&narrow),
            count(&wide)
        );
        assert!((0..narrow.len()).all(|v| narrow[v].is_none() || wide[v].is_some()));
        for (c, extent) in holes {
            assert!(c.z.abs() < 0.3 && c.truncate().length() < 0.6, "{c:?}");
            assert!(extent > 0.9 && extent < 2.4, "{extent}");
        }
        // Nothing pairs in a hole already opened.
        q.opened.push((DVec3::ZERO, 2.0));
        assert!(facing_pairs(&m, &normals, &d, &q, &hole)
            .iter()
            .all(Option::is_none));
        let none = |f: &[Option<u32>]| f.iter().all(Option::is_none);
        assert!(none(&pairs(0.0, &hole)), "off at 0");
        assert!(
            none(&pairs(0.5, &hole)),
            "the gap is over half the distance"
        );
        let slot = |p: DVec3| plate_distance(p, 1.2, 0.3, true);
        assert!(none(&pairs(4.0, &slot)), "a slot is open at its ends");
        let solid = |p: DVec3| (p.z.abs() - 0.05).max(0.0).min(hole(p));
        assert!(none(&pairs(4.0, &solid)), "a part lies between the faces");
    }

    /// The inside lining of a sampled shell (a sphere cut open, which the wrap dents into) and
    /// the wrap outside it, each within an edge of the other across the shell, facing back; rings
    /// between them meet the curved shell all round. Neither is a tunnel: a path from the lining
    /// falls towards the shell ([`LEVEL`]), and the first step from the outside spans the shell.
    /// Paired, they would give a cut shell false handles.
    #[test]
    fn a_partner_across_a_wall_is_no_tunnel() {
        let (level, shell, inner, outer) = (1, 2.4, 1.5, 2.8);
        let lining = icosphere(level, inner, DVec3::ZERO).unwrap();
        let wrap = icosphere(level, outer, DVec3::ZERO).unwrap();
        let n = lining.n_vertices() as u32;
        let positions: Vec<DVec3> = lining
            .positions()
            .iter()
            .chain(wrap.positions())
            .copied()
            .collect();
        let tris: Vec<[u32; 3]> = lining
            .triangles()
            .into_iter()
            .map(|[a, b, c]| [a, c, b])
            .chain(wrap.triangles().into_iter().map(|t| t.map(|v| v + n)))
            .collect();
        let m = HalfedgeMesh::from_triangles(positions, &tris).unwrap();
        let normals = angle_weighted_normals(&m);
        let probe = |p: DVec3| (p.length() - shell).abs();
        let d: Vec<f64> = m.positions().iter().map(|&p| probe(p)).collect();
        let q = FacingQuery {
            tunnel_ratio: 4.0,
            ..query()
        };
        let (found, holes) = facing_pairs_and_tunnels(&m, &normals, &d, &q, &probe, PATCH_WIDTHS);
        assert!(holes.is_empty(), "{holes:?}");
        assert!(found.iter().all(Option::is_none));
    }

    #[test]
    fn sheets_near_the_data_or_far_apart_are_not_paired() {
        let m = pancake(0.02);
        let normals = angle_weighted_normals(&m);
        let q = query();
        // At the data: every vertex within `empty` of the target.
        let near = vec![0.1; m.n_vertices()];
        assert!(facing_pairs(&m, &normals, &near, &q, &|_| 1.0)
            .iter()
            .all(Option::is_none));
        // A round sphere: opposite sides are 2 apart, far above a quarter of their distance.
        let s = icosphere(4, 1.0, DVec3::ZERO).unwrap();
        let far = vec![1.0; s.n_vertices()];
        let ns = angle_weighted_normals(&s);
        assert!(facing_pairs(&s, &ns, &far, &q, &|_| 1.0)
            .iter()
            .all(Option::is_none));
    }
}
