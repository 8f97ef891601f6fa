//! How faithful a valid wrap is to its data, beside the certificate's validity: how far the
//! surface strays from the data *in units of the data's own spacing* (a membrane left in empty
//! space lies many spacings from any data; a surface on the data lies within one), how many of
//! its edges fold over (adjacent faces turning by more than a right angle where the target does
//! not), and the shape of its triangles. Measurements only: what counts as unfaithful is the
//! verdict's to say.

use super::quality::{kappa, min_angle};
use glam::DVec3;
use serde::{Deserialize, Serialize};

/// A vertex this many local spacings or more from the data is *far*: farther than a sampling's
/// own gaps reach.
pub const FAR_SPACINGS: f64 = 3.0;

/// Adjacent faces whose normals turn by more than this (radians) fold over.
pub const FOLD_TURN: f64 = std::f64::consts::FRAC_PI_2;

/// Faces with κ(J_Δ) at most this are well shaped (the remesher's quality band).
pub const GOOD_KAPPA: f64 = 1.5;

/// A far region of fewer vertices is a sampling's gap, not a surface spanning something.
pub const REGION_VERTICES: usize = 8;

/// A far region that is no opening is a membrane in empty space when it reaches this many local
/// spacings from the data: the inner sheet of a wrap round an open shell stays within a few.
pub const MEMBRANE_SPACINGS: f64 = 8.0;

/// What the data says near a place: its local spacing, and whether it has a crease there.
pub trait DataNear {
    /// The spacing of the data near each of `points`, which lie `distances` from it (the
    /// sampling's for a cloud, the edges' for a mesh).
    fn spacings(&self, points: &[DVec3], distances: &[f64]) -> Vec<Option<f64>>;
    /// Whether the data itself turns sharply between the places nearest to `a` and `b` (a crease
    /// or corner the wrap should follow).
    fn turns_between(&self, a: DVec3, b: DVec3) -> bool;
    /// Whether the data ends near `p`: the data nearest to it lies at an edge of the sampled
    /// surface (a mesh's boundary; a cloud's point with no neighbours on one side).
    fn at_edge(&self, p: DVec3) -> bool;
}

/// The faithfulness measurements of a wrap.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[cfg_attr(target_arch = "wasm32", derive(tsify::Tsify))]
pub struct Faithfulness {
    /// Largest distance from a wrap vertex to the data, in local spacings of the data there.
    pub distance_max_spacings: f64,
    /// 99th percentile of that distance.
    pub distance_p99_spacings: f64,
    /// Vertices [`FAR_SPACINGS`] or more from the data.
    pub far_vertices: usize,
    /// `far_vertices` over all vertices.
    #[serde(default)]
    pub far_share: f64,
    /// Edges whose faces turn by more than [`FOLD_TURN`] where the target does not.
    pub folds: usize,
    /// `folds` over the interior edges.
    pub fold_share: f64,
    /// Smallest interior angle of any face, degrees.
    pub min_angle_deg: f64,
    /// Share of faces with κ(J_Δ) ≤ [`GOOD_KAPPA`].
    pub kappa_good_share: f64,
    /// The far vertices and the vertices of folded edges, ascending (for highlighting).
    #[serde(default)]
    pub flagged_vertices: Vec<u32>,
    /// Connected far regions of [`REGION_VERTICES`] or more whose nearest data mostly lies
    /// where it ends: openings of the data that the closed wrap spans (a scan's hole), and their
    /// vertices.
    #[serde(default)]
    pub openings: usize,
    #[serde(default)]
    pub opening_vertices: usize,
    /// The other far regions of [`REGION_VERTICES`] or more: membranes left in empty space
    /// between parts of the data that go on, and their share of the wrap's area (a flat
    /// membrane holds few vertices).
    #[serde(default)]
    pub membranes: usize,
    #[serde(default)]
    pub membrane_share: f64,
}

/// Measures the wrap `(positions, triangles)` whose vertices lie `distances` from the data.
pub fn faithfulness(
    positions: &[DVec3],
    triangles: &[[u32; 3]],
    distances: &[f64],
    data: &(impl DataNear + Sync),
) -> Faithfulness {
    // The distances' part and the faces' part are independent: natively one beside the other.
    let ((sorted, mut flagged, ratios), (folds, interior, fold_ends, min_angle_rad, good)) =
        crate::parallel::beside(
            || far_from_data(positions, distances, data),
            || {
                let mut ends = Vec::new();
                let (folds, interior) = folded_edges(positions, triangles, data, &mut ends);
                let (m, g) = shape(positions, triangles);
                (folds, interior, ends, m, g)
            },
        );
    let far_vertices = flagged.len();
    let regions = far_regions(
        triangles,
        &flagged,
        |v| ratios[v as usize],
        |v| data.at_edge(positions[v as usize]),
    );
    let (openings, opening_vertices, membranes, membrane_vertices) = regions;
    let area = vertex_areas(positions, triangles);
    let membrane_area: f64 = membrane_vertices.iter().map(|&v| area[v as usize]).sum();
    flagged.extend(fold_ends);
    flagged.sort_unstable();
    flagged.dedup();
    Faithfulness {
        distance_max_spacings: sorted.last().copied().unwrap_or(0.0),
        distance_p99_spacings: super::quality::percentile_sorted(&sorted, 0.99),
        far_vertices,
        far_share: far_vertices as f64 / positions.len().max(1) as f64,
        folds,
        fold_share: folds as f64 / interior.max(1) as f64,
        min_angle_deg: if triangles.is_empty() {
            0.0
        } else {
            min_angle_rad.to_degrees()
        },
        kappa_good_share: good as f64 / triangles.len().max(1) as f64,
        flagged_vertices: flagged,
        openings,
        opening_vertices,
        membranes,
        membrane_share: membrane_area / area.iter().sum::<f64>().max(f64::MIN_POSITIVE),
    }
}

/// The connected regions of the `far` vertices (ascending), split by where the data nearest to
/// them lies: where it ends (`at_edge`) for half of a region's vertices or more, the region
/// spans an opening of the data; else, where it reaches [`MEMBRANE_SPACINGS`] (`spacings` of a
/// vertex), it is a membrane between parts of the data that go on. Returns (openings, their
/// vertices, membranes, their vertices); other regions, and those under [`REGION_VERTICES`],
/// count as neither. (The membranes' vertices are returned, their count of the others.)
fn far_regions(
    triangles: &[[u32; 3]],
    far: &[u32],
    spacings: impl Fn(u32) -> f64,
    at_edge: impl Fn(u32) -> bool + Sync,
) -> (usize, usize, usize, Vec<u32>) {
    let is_far = |v: u32| far.binary_search(&v).is_ok();
    let mut sets =
        crate::mesh::disjoint::DisjointSets::new(far.last().map_or(0, |&v| v as usize + 1));
    let edges = triangles
        .iter()
        .flat_map(|t| (0..3).map(move |k| (t[k], t[(k + 1) % 3])));
    for (a, b) in edges.filter(|&(a, b)| is_far(a) && is_far(b)) {
        sets.union(a, b);
    }
    let mut regions: Vec<(u32, u32)> = far.iter().map(|&v| (sets.find(v), v)).collect();
    regions.sort_unstable();
    let big: Vec<&[(u32, u32)]> = regions
        .chunk_by(|a, b| a.0 == b.0)
        .filter(|r| r.len() >= REGION_VERTICES)
        .collect();
    let members: Vec<u32> = big.iter().flat_map(|r| r.iter().map(|m| m.1)).collect();
    let ends = crate::parallel::map(members.len(), |k| at_edge(members[k]));
    let mut out = (0, 0, 0, Vec::new());
    let mut at = 0;
    for r in big {
        let edge = ends[at..at + r.len()].iter().filter(|&&e| e).count();
        at += r.len();
        let deepest = r.iter().map(|m| spacings(m.1)).fold(0.0, f64::max);
        if 2 * edge >= r.len() {
            out.0 += 1;
            out.1 += r.len();
        } else if deepest >= MEMBRANE_SPACINGS {
            out.2 += 1;
            out.3.extend(r.iter().map(|m| m.1));
        }
    }
    out
}

/// Every vertex's distance in local spacings, ascending, the vertices [`FAR_SPACINGS`] or more
/// off, and the distances in vertex order.
fn far_from_data(
    positions: &[DVec3],
    distances: &[f64],
    data: &impl DataNear,
) -> (Vec<f64>, Vec<u32>, Vec<f64>) {
    let spacings = data.spacings(positions, distances);
    let ratios: Vec<f64> = spacings
        .iter()
        .zip(distances)
        .map(|(s, d)| s.filter(|s| *s > 0.0).map_or(0.0, |s| d / s))
        .collect();
    let far = (0..positions.len() as u32)
        .filter(|&v| ratios[v as usize] >= FAR_SPACINGS)
        .collect();
    let mut sorted = ratios.clone();
    sorted.sort_by(f64::total_cmp);
    (sorted, far, ratios)
}

/// Each vertex's share of the area: a third of its faces'.
fn vertex_areas(positions: &[DVec3], triangles: &[[u32; 3]]) -> Vec<f64> {
    let mut area = vec![0.0; positions.len()];
    for t in triangles {
        let [a, b, c] = t.map(|v| positions[v as usize]);
        let third = (b - a).cross(c - a).length() / 6.0;
        for &v in t {
            area[v as usize] += third;
        }
    }
    area
}

/// The smallest angle of any face (radians) and how many faces are well shaped.
fn shape(positions: &[DVec3], triangles: &[[u32; 3]]) -> (f64, usize) {
    triangles.iter().fold((f64::INFINITY, 0usize), |(m, g), t| {
        let [a, b, c] = t.map(|v| positions[v as usize]);
        (
            m.min(min_angle(a, b, c)),
            g + usize::from(kappa(a, b, c) <= GOOD_KAPPA),
        )
    })
}

/// The edges whose two faces turn by more than [`FOLD_TURN`] where the data does not turn
/// between them, and the interior edges counted; the folded edges' ends go to `flagged`.
fn folded_edges(
    positions: &[DVec3],
    triangles: &[[u32; 3]],
    data: &impl DataNear,
    flagged: &mut Vec<u32>,
) -> (usize, usize) {
    let face = |f: usize| {
        let [a, b, c] = triangles[f].map(|v| positions[v as usize]);
        ((b - a).cross(c - a).normalize_or_zero(), (a + b + c) / 3.0)
    };
    let (mut folds, mut interior) = (0, 0);
    for ((u, v), faces) in edge_faces(triangles) {
        let [f, g] = faces[..] else { continue };
        interior += 1;
        let ((nf, cf), (ng, cg)) = (face(f), face(g));
        if nf.dot(ng) >= crate::fmath::cos(FOLD_TURN) {
            continue;
        }
        if !data.turns_between(cf, cg) {
            folds += 1;
            flagged.extend([u, v]);
        }
    }
    (folds, interior)
}

/// Every edge `(u, v)` (u < v) with the faces that have it, in edge order.
fn edge_faces(triangles: &[[u32; 3]]) -> Vec<((u32, u32), Vec<usize>)> {
    let mut sides: Vec<((u32, u32), usize)> = triangles
        .iter()
        .enumerate()
        .flat_map(|(f, t)| {
            (0..3).map(move |k| ((t[k].min(t[(k + 1) % 3]), t[k].max(t[(k + 1) % 3])), f))
        })
        .collect();
    sides.sort_unstable();
    let mut out: Vec<((u32, u32), Vec<usize>)> = Vec::new();
    for (e, f) in sides {
        match out.last_mut() {
            Some((last, faces)) if *last == e => faces.push(f),
            _ => out.push((e, vec![f])),
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Data sampled every `spacing` everywhere, with normal +z.
    struct Even(f64);
    impl DataNear for Even {
        fn spacings(&self, p: &[DVec3], _: &[f64]) -> Vec<Option<f64>> {
            vec![Some(self.0); p.len()]
        }
        fn turns_between(&self, _: DVec3, _: DVec3) -> bool {
            false
        }
        fn at_edge(&self, _: DVec3) -> bool {
            false
        }
    }

    /// A flat square of two triangles, or with its second triangle folded back over the first.
    fn square(fold: bool) -> (Vec<DVec3>, Vec<[u32; 3]>) {
        let d = if fold {
            DVec3::new(0.8, 0.3, 0.05)
        } else {
            DVec3::new(0.0, 1.0, 0.0)
        };
        let p = vec![DVec3::ZERO, DVec3::X, DVec3::new(1.0, 1.0, 0.0), d];
        (p, vec![[0, 1, 2], [0, 2, 3]])
    }

    #[test]
    fn a_flat_surface_on_the_data_is_faithful() {
        let (p, t) = square(false);
        let f = faithfulness(&p, &t, &[0.0, 0.01, 0.02, 0.0], &Even(0.01));
        assert_eq!((f.far_vertices, f.folds), (0, 0));
        assert!((f.distance_max_spacings - 2.0).abs() < 1e-12);
        assert!((f.min_angle_deg - 45.0).abs() < 1e-9);
        assert_eq!(f.kappa_good_share, 1.0);
        assert!(f.flagged_vertices.is_empty());
    }

    /// Brute force: the vertex 5 spacings off is far, the folded edge is counted with its ends,
    /// and a fold that follows the target's own crease is not.
    #[test]
    fn far_vertices_and_folds_are_flagged() {
        let (p, t) = square(true);
        let tri = |t: &[u32; 3]| {
            let [a, b, c] = t.map(|v| p[v as usize]);
            (b - a).cross(c - a).normalize()
        };
        assert!(
            tri(&t[0]).dot(tri(&t[1])) < 0.0,
            "the faces turn by more than 90°"
        );
        let f = faithfulness(&p, &t, &[0.0, 0.05, 0.0, 0.0], &Even(0.01));
        assert_eq!((f.far_vertices, f.folds, f.fold_share), (1, 1, 1.0));
        assert_eq!(f.flagged_vertices, [0, 1, 2]);
        struct Creased;
        impl DataNear for Creased {
            fn spacings(&self, p: &[DVec3], _: &[f64]) -> Vec<Option<f64>> {
                vec![Some(1.0); p.len()]
            }
            fn turns_between(&self, a: DVec3, b: DVec3) -> bool {
                (a.z > 1e-3) != (b.z > 1e-3)
            }
            fn at_edge(&self, _: DVec3) -> bool {
                false
            }
        }
        assert_eq!(faithfulness(&p, &t, &[0.0; 4], &Creased).folds, 0);
    }

    /// A 12 × 12 vertex grid with two far blocks of 3 × 3: the one whose data ends nearby is an
    /// opening, the other a membrane; a lone far vertex is neither.
    #[test]
    fn far_regions_are_openings_or_membranes_by_their_rim() {
        let n = 12u32;
        let id = |i: u32, j: u32| i + n * j;
        let mut t = Vec::new();
        for j in 0..n - 1 {
            for i in 0..n - 1 {
                t.push([id(i, j), id(i + 1, j), id(i + 1, j + 1)]);
                t.push([id(i, j), id(i + 1, j + 1), id(i, j + 1)]);
            }
        }
        let block = |i0: u32, j0: u32| (0..9).map(move |k| id(i0 + k % 3, j0 + k / 3));
        let mut far: Vec<u32> = block(1, 1).chain(block(7, 7)).chain([id(5, 1)]).collect();
        far.sort_unstable();
        // The data ends by the first block (i, j ≤ 4).
        let at_edge = |v: u32| v % n <= 4 && v / n <= 4;
        let deep = |_| MEMBRANE_SPACINGS;
        let second: Vec<u32> = block(7, 7).collect();
        assert_eq!(far_regions(&t, &far, deep, at_edge), (1, 9, 1, second));
        // A far region close to the data (the inner sheet round an open shell) is no membrane.
        let shallow = |_| MEMBRANE_SPACINGS - 1.0;
        assert_eq!(far_regions(&t, &far, shallow, at_edge), (1, 9, 0, vec![]));
    }
}
