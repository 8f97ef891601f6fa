//! Sharp creases of a triangle-mesh target: the edges whose two faces turn by more than an
//! angle, and the corners where crease lines meet, turn or end. The final fit snaps the wrap
//! onto them (so a cube stays a cube) and the metrics measure how well a wrap reproduces their
//! dihedral angles. Only edges with exactly two consistently oriented, non-degenerate faces can
//! be creases: a boundary or non-manifold edge says nothing about the surface's turn.

use super::primitives::closest_point_on_segment;
use super::spatial::bvh::{Bvh, PointBvh};
use glam::DVec3;
use std::collections::HashMap;

/// One crease edge of the target.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Crease {
    /// End points.
    pub ends: [DVec3; 2],
    /// Unit normals of the two faces.
    pub normals: [DVec3; 2],
    /// Unit directions in each face's plane, perpendicular to the edge, into the face.
    pub inward: [DVec3; 2],
    /// Each face's height over the edge (how far `inward` stays on the face).
    pub heights: [f64; 2],
    /// The angle between the face normals (radians): 0 flat, π/2 a cube's edge.
    pub turn: f64,
    /// Convex (a ridge) rather than concave (a valley).
    pub convex: bool,
}

/// Numbers per crease edge in [`Creases::to_flat`].
const FLAT_EDGE: usize = 22;

/// The creases and corners of a target, with search structures.
pub struct Creases {
    /// Crease edges.
    pub edges: Vec<Crease>,
    /// Corners: target vertices with one or more than two crease edges, or two that turn by
    /// more than the crease angle.
    pub corners: Vec<DVec3>,
    edge_bvh: Bvh,
    corner_bvh: PointBvh,
}

/// A point on the crease lines.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CreaseHit {
    /// The closest point.
    pub point: DVec3,
    /// Its distance from the query.
    pub distance: f64,
    /// The crease edge it lies on.
    pub edge: u32,
}

/// Half-edges `(low, high, face, forward)`, `forward` 1 when the face runs from low to high.
type HalfEdge = (u32, u32, u32, u32);

/// The creases of the mesh `(points, triangles)` turning by more than `min_turn` radians.
/// Coincident points are welded first (STL files repeat every vertex per face).
pub fn detect_creases(points: &[DVec3], triangles: &[[u32; 3]], min_turn: f64) -> Creases {
    let weld = weld_by_position(points);
    let normals = face_normals(points, triangles);
    let half = sorted_half_edges(triangles, &weld);
    let (edges, incident, open_vertices) =
        crease_edges(points, triangles, &normals, &half, min_turn);
    let mut corner_ids = line_corners(points, &edges, &incident, min_turn);
    corner_ids.extend(cone_points(
        points,
        triangles,
        &normals,
        &weld,
        open_vertices,
        &incident,
        CONE_DEFECT_PER_TURN * min_turn,
    ));
    corner_ids.sort_unstable();
    let corners: Vec<DVec3> = corner_ids.iter().map(|&v| points[v as usize]).collect();
    Creases::new(edges, corners)
}

/// Per point, the id of the first point at exactly its position, so that unwelded inputs share
/// their edges.
fn weld_by_position(points: &[DVec3]) -> Vec<u32> {
    let mut first: HashMap<[u64; 3], u32> = HashMap::new();
    points
        .iter()
        .enumerate()
        .map(|(i, p)| {
            *first
                .entry(p.to_array().map(f64::to_bits))
                .or_insert(i as u32)
        })
        .collect()
}

/// Unit face normals; None for faces too thin to have one.
fn face_normals(points: &[DVec3], triangles: &[[u32; 3]]) -> Vec<Option<DVec3>> {
    triangles
        .iter()
        .map(|t| {
            let [a, b, c] = t.map(|v| points[v as usize]);
            let n = (b - a).cross(c - a);
            let longest = (b - a)
                .length_squared()
                .max((c - b).length_squared())
                .max((a - c).length_squared());
            (n.length() > 1e-6 * longest && n.is_finite()).then(|| n.normalize())
        })
        .collect()
}

/// The welded half-edges, sorted so that the two sides of an edge are neighbours.
fn sorted_half_edges(triangles: &[[u32; 3]], weld: &[u32]) -> Vec<HalfEdge> {
    let mut half: Vec<HalfEdge> = Vec::with_capacity(3 * triangles.len());
    for (f, t) in triangles.iter().enumerate() {
        let w = t.map(|v| weld[v as usize]);
        for k in 0..3 {
            let (a, b) = (w[k], w[(k + 1) % 3]);
            if a != b {
                half.push((a.min(b), a.max(b), f as u32, (a < b) as u32));
            }
        }
    }
    half.sort_unstable();
    half
}

/// The crease edges among the sorted half-edges, the crease edges at each vertex, and the
/// vertices on a boundary or non-manifold edge (their angle sums say nothing).
fn crease_edges(
    points: &[DVec3],
    triangles: &[[u32; 3]],
    normals: &[Option<DVec3>],
    half: &[HalfEdge],
    min_turn: f64,
) -> (Vec<Crease>, HashMap<u32, Vec<u32>>, Vec<u32>) {
    let mut edges = Vec::new();
    let mut incident: HashMap<u32, Vec<u32>> = HashMap::new();
    let mut open_vertices: Vec<u32> = Vec::new();
    let mut i = 0;
    while i < half.len() {
        let mut j = i + 1;
        while j < half.len() && (half[j].0, half[j].1) == (half[i].0, half[i].1) {
            j += 1;
        }
        if j - i != 2 || half[i].3 == half[i + 1].3 {
            open_vertices.extend([half[i].0, half[i].1]);
        }
        // Exactly two faces that traverse the edge in opposite directions.
        if j - i == 2 && half[i].3 != half[i + 1].3 {
            let (fa, fb) = (half[i].2 as usize, half[i + 1].2 as usize);
            if let (Some(na), Some(nb)) = (normals[fa], normals[fb]) {
                let turn = crate::fmath::acos(na.dot(nb).clamp(-1.0, 1.0));
                if turn > min_turn {
                    let (a, b) = (points[half[i].0 as usize], points[half[i].1 as usize]);
                    edges.push(crease(
                        points,
                        [triangles[fa], triangles[fb]],
                        [a, b],
                        [na, nb],
                        turn,
                    ));
                    for v in [half[i].0, half[i].1] {
                        incident.entry(v).or_default().push(edges.len() as u32 - 1);
                    }
                }
            }
        }
        i = j;
    }
    (edges, incident, open_vertices)
}

/// The vertex of triangle `t` farthest from the line through `a` and `b` (`a` for none).
fn far_vertex(points: &[DVec3], t: [u32; 3], a: DVec3, b: DVec3) -> DVec3 {
    t.iter()
        .map(|&v| points[v as usize])
        .max_by(|p, q| {
            let (dp, dq) = ((*p - a).cross(b - a), (*q - a).cross(b - a));
            dp.length_squared().total_cmp(&dq.length_squared())
        })
        .unwrap_or(a)
}

/// The unit direction from the edge `a b` into triangle `t`, perpendicular to the edge, and the
/// triangle's height over the edge.
fn inward_side(points: &[DVec3], t: [u32; 3], a: DVec3, b: DVec3) -> (DVec3, f64) {
    let q = far_vertex(points, t, a, b);
    let foot = closest_point_on_segment(q, a, b);
    let d = q - foot;
    // The edge's line, not the segment: the apex may project past an end.
    let e = (b - a).normalize_or_zero();
    let d = d - d.dot(e) * e;
    (d.normalize_or_zero(), d.length())
}

/// The crease on edge `ends` between the faces `faces` with unit normals `normals`.
fn crease(
    points: &[DVec3],
    faces: [[u32; 3]; 2],
    ends: [DVec3; 2],
    normals: [DVec3; 2],
    turn: f64,
) -> Crease {
    let [a, b] = ends;
    let ((ia, ha), (ib, hb)) = (
        inward_side(points, faces[0], a, b),
        inward_side(points, faces[1], a, b),
    );
    Crease {
        ends,
        normals,
        inward: [ia, ib],
        heights: [ha, hb],
        turn,
        // A ridge: the other face falls away below this face's plane.
        convex: (far_vertex(points, faces[1], a, b) - a).dot(normals[0]) < 0.0,
    }
}

/// Vertices where crease lines end, branch or turn by more than `min_turn`, in no order.
fn line_corners(
    points: &[DVec3],
    edges: &[Crease],
    incident: &HashMap<u32, Vec<u32>>,
    min_turn: f64,
) -> Vec<u32> {
    incident
        .iter()
        .filter(|(&v, es)| {
            if es.len() != 2 {
                return true;
            }
            let p = points[v as usize];
            let dir = |e: u32| {
                let [a, b] = edges[e as usize].ends;
                (if a == p { b - a } else { a - b }).normalize_or_zero()
            };
            // Two crease edges through v: a corner unless they continue one line.
            crate::fmath::acos((-dir(es[0])).dot(dir(es[1])).clamp(-1.0, 1.0)) > min_turn
        })
        .map(|(&v, _)| v)
        .collect()
}

/// A vertex on no crease is still a corner when its angle defect (2π minus the angles of its
/// faces there: the surface's concentrated curvature) exceeds this fraction of the crease angle.
/// The apex of a low-poly sphere's facets (CubeSphere.obj: 0.59 rad) would otherwise be cut by
/// the wrap's faces; on a fine smooth mesh a vertex's defect is tiny (4π spread over all).
const CONE_DEFECT_PER_TURN: f64 = 0.5;

/// Welded vertices (ids of the first copy) whose fan is closed (not in `open`: on a boundary or
/// non-manifold edge), manifold and free of slivers (`normals[f]` None), that lie on no crease,
/// and whose angle defect exceeds `min_defect` radians: the apexes of cones.
fn cone_points(
    points: &[DVec3],
    triangles: &[[u32; 3]],
    normals: &[Option<DVec3>],
    weld: &[u32],
    mut open: Vec<u32>,
    incident: &HashMap<u32, Vec<u32>>,
    min_defect: f64,
) -> Vec<u32> {
    // Per welded vertex (None: in no face).
    let mut angle_sum: Vec<Option<f64>> = vec![None; points.len()];
    for (t, n) in triangles.iter().zip(normals) {
        let w = t.map(|v| weld[v as usize]);
        if n.is_none() {
            // A sliver's angles (0, 0, π) would skew its vertices' sums: leave them out.
            open.extend(w);
            continue;
        }
        let p = w.map(|v| points[v as usize]);
        for k in 0..3 {
            let (a, b) = (p[(k + 1) % 3] - p[k], p[(k + 2) % 3] - p[k]);
            let angle = crate::fmath::atan2(a.cross(b).length(), a.dot(b));
            *angle_sum[w[k] as usize].get_or_insert(0.0) += angle;
        }
    }
    open.sort_unstable();
    (0..points.len() as u32)
        .filter(|&v| {
            angle_sum[v as usize]
                .is_some_and(|sum| (std::f64::consts::TAU - sum).abs() > min_defect)
                && !incident.contains_key(&v)
                && open.binary_search(&v).is_err()
        })
        .collect()
}

impl Creases {
    /// Crease edges and corners, with their search structures.
    pub fn new(edges: Vec<Crease>, corners: Vec<DVec3>) -> Self {
        let (mins, maxs): (Vec<DVec3>, Vec<DVec3>) = edges
            .iter()
            .map(|c| (c.ends[0].min(c.ends[1]), c.ends[0].max(c.ends[1])))
            .unzip();
        Creases {
            edge_bvh: Bvh::new(&mins, &maxs),
            corner_bvh: PointBvh::new(&corners),
            edges,
            corners,
        }
    }

    /// The creases as plain numbers, to cross to another worker: the edge and corner counts,
    /// then [`FLAT_EDGE`] numbers per edge and three per corner (bit for bit: a crease found in
    /// a helper worker gives the fit the same result as one found by the fit).
    pub fn to_flat(&self) -> Vec<f64> {
        let mut out = Vec::with_capacity(2 + FLAT_EDGE * self.edges.len() + 3 * self.corners.len());
        out.extend([self.edges.len() as f64, self.corners.len() as f64]);
        for c in &self.edges {
            for v in [c.ends, c.normals, c.inward].iter().flatten() {
                out.extend(v.to_array());
            }
            out.extend(c.heights);
            out.extend([c.turn, if c.convex { 1.0 } else { 0.0 }]);
        }
        for p in &self.corners {
            out.extend(p.to_array());
        }
        out
    }

    /// Creases from [`Creases::to_flat`]'s numbers; None if they are not such a list.
    pub fn from_flat(flat: &[f64]) -> Option<Self> {
        let count = |x: f64| (x >= 0.0 && x.fract() == 0.0 && x < 1e9).then_some(x as usize);
        let (n_edges, n_corners) = (count(*flat.first()?)?, count(*flat.get(1)?)?);
        if flat.len() != 2 + FLAT_EDGE * n_edges + 3 * n_corners
            || flat.iter().any(|x| !x.is_finite())
        {
            return None;
        }
        let v = |k: usize| DVec3::from_slice(&flat[k..k + 3]);
        let edges = flat[2..2 + FLAT_EDGE * n_edges]
            .chunks_exact(FLAT_EDGE)
            .map(|e| {
                let v = |k: usize| DVec3::from_slice(&e[3 * k..3 * k + 3]);
                Crease {
                    ends: [v(0), v(1)],
                    normals: [v(2), v(3)],
                    inward: [v(4), v(5)],
                    heights: [e[18], e[19]],
                    turn: e[20],
                    convex: e[21] != 0.0,
                }
            })
            .collect();
        let first = 2 + FLAT_EDGE * n_edges;
        let corners = (0..n_corners).map(|k| v(first + 3 * k)).collect();
        Some(Creases::new(edges, corners))
    }

    /// No creases at all.
    pub fn is_empty(&self) -> bool {
        self.edges.is_empty()
    }

    /// The closest point on the crease lines within `max_distance` of `p`.
    pub fn closest_edge_point(&self, p: DVec3, max_distance: f64) -> Option<CreaseHit> {
        let (edge, d2) = self
            .edge_bvh
            .nearest_within(p, max_distance * max_distance, |e| {
                let [a, b] = self.edges[e as usize].ends;
                (closest_point_on_segment(p, a, b) - p).length_squared()
            })?;
        let [a, b] = self.edges[edge as usize].ends;
        Some(CreaseHit {
            point: closest_point_on_segment(p, a, b),
            distance: d2.sqrt(),
            edge,
        })
    }

    /// The nearest corner to `p`: (index, distance).
    pub fn nearest_corner(&self, p: DVec3) -> Option<(u32, f64)> {
        self.corner_bvh.nearest(p).map(|(i, d2)| (i, d2.sqrt()))
    }

    /// [`Creases::nearest_corner`] among the corners within `max_distance` of `p` (the same
    /// answer where that is within it; a far query ends at once).
    pub fn nearest_corner_within(&self, p: DVec3, max_distance: f64) -> Option<(u32, f64)> {
        self.corner_bvh
            .nearest_within(p, max_distance * max_distance)
            .map(|(i, d2)| (i, d2.sqrt()))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::demo::shapes::{cad_part, grid_box};
    use std::f64::consts::FRAC_PI_2;

    /// The numbers that cross to another worker give back the same creases, bit for bit, and
    /// anything else is refused.
    #[test]
    fn creases_cross_as_plain_numbers_unchanged() {
        let (p, t) = cad_part();
        let c = detect_creases(&p, &t, 40f64.to_radians());
        assert!(!c.edges.is_empty() && !c.corners.is_empty());
        let flat = c.to_flat();
        let back = Creases::from_flat(&flat).unwrap();
        assert_eq!(back.edges, c.edges);
        assert_eq!(back.corners, c.corners);
        assert!(back.edges.iter().any(|e| e.convex) && back.edges.iter().any(|e| !e.convex));
        assert_eq!(back.to_flat().len(), flat.len());
        for bad in [
            &flat[..flat.len() - 1],
            &[],
            &[1.5, 0.0],
            &[-1.0, 0.0],
            &[0.0, 1.0, 0.0, f64::NAN, 0.0],
        ] {
            assert!(
                Creases::from_flat(bad).is_none(),
                "{:?}",
                &bad[..bad.len().min(5)]
            );
        }
        assert!(Creases::from_flat(&[0.0, 0.0]).unwrap().is_empty());
    }

    #[test]
    fn a_cube_has_twelve_right_angled_convex_edges_and_eight_corners() {
        let (p, t) = grid_box(DVec3::ONE, [4, 4, 4]);
        let c = detect_creases(&p, &t, 40f64.to_radians());
        assert_eq!(c.edges.len(), 12 * 4);
        assert!(c
            .edges
            .iter()
            .all(|e| (e.turn - FRAC_PI_2).abs() < 1e-9 && e.convex));
        assert_eq!(c.corners.len(), 8);
        assert!(c.corners.iter().all(|q| q.abs() == DVec3::splat(0.5)));
        // Inward directions lie in their faces (perpendicular to the normal) and to the edge.
        for e in &c.edges {
            for k in 0..2 {
                assert!(e.inward[k].dot(e.normals[k]).abs() < 1e-12);
                assert!(e.inward[k].dot(e.ends[1] - e.ends[0]).abs() < 1e-12);
                assert!((e.heights[k] - 0.25).abs() < 1e-12);
            }
        }
        let hit = c
            .closest_edge_point(DVec3::new(0.45, 0.47, 0.1), 0.1)
            .unwrap();
        assert!((hit.point - DVec3::new(0.5, 0.5, 0.1)).length() < 1e-12);
        assert!(c.closest_edge_point(DVec3::ZERO, 0.3).is_none());
        // Unwelded (every face with its own vertices, as in STL): the same creases.
        let soup: Vec<DVec3> = t.iter().flat_map(|f| f.map(|v| p[v as usize])).collect();
        let tris: Vec<[u32; 3]> = (0..t.len() as u32)
            .map(|f| [3 * f, 3 * f + 1, 3 * f + 2])
            .collect();
        let c2 = detect_creases(&soup, &tris, 40f64.to_radians());
        assert_eq!((c2.edges.len(), c2.corners.len()), (48, 8));
    }

    #[test]
    fn the_cad_part_has_its_chamfer_and_one_concave_edge() {
        let (p, t) = cad_part();
        let c = detect_creases(&p, &t, 40f64.to_radians());
        let concave: Vec<&Crease> = c.edges.iter().filter(|e| !e.convex).collect();
        // The concave edge is the vertical one at the inner corner (0, 0) after centring.
        assert!(!concave.is_empty());
        assert!(concave
            .iter()
            .all(
                |e| (e.ends[0].truncate() - glam::DVec2::new(0.0, 0.0)).length() < 1e-12
                    && (e.turn - FRAC_PI_2).abs() < 1e-9
            ));
        let chamfer = c
            .edges
            .iter()
            .filter(|e| (e.turn - FRAC_PI_2 / 2.0).abs() < 1e-9);
        assert!(chamfer.count() >= 2);
        // 7 outline corners × 2 caps.
        assert_eq!(c.corners.len(), 14);
        // No crease inside the flat caps (the fans) or along the flat walls.
        assert!(c.edges.iter().all(|e| e.turn > 0.7));
    }

    #[test]
    fn cone_points_without_creases_are_corners() {
        // A square bipyramid whose faces slope 27°: the apex edges turn by 37° (no crease at
        // 40°), the apexes are cones (angle defect 0.46 rad); the rim is a crease loop whose
        // four vertices are corners by its turns.
        let (sin, cos) = crate::fmath::sin_cos(27f64.to_radians());
        let h = 0.5f64.sqrt() * sin / cos;
        let p = vec![
            DVec3::X,
            DVec3::Y,
            -DVec3::X,
            -DVec3::Y,
            DVec3::new(0.0, 0.0, h),
            DVec3::new(0.0, 0.0, -h),
        ];
        let t: Vec<[u32; 3]> = (0..4u32)
            .flat_map(|k| [[k, (k + 1) % 4, 4], [(k + 1) % 4, k, 5]])
            .collect();
        let c = detect_creases(&p, &t, 40f64.to_radians());
        assert_eq!(c.edges.len(), 4);
        assert_eq!(c.corners, p);
        // With a face gone the top apex's fan is open: not a cone (nor a rim corner there).
        let c = detect_creases(&p, &t[1..], 40f64.to_radians());
        assert!(!c.corners.contains(&p[4]) && c.corners.contains(&p[5]));
    }
}
