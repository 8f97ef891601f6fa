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

/// What the data says near a place: its local spacing, and whether it has a crease there.
pub trait DataNear {
    /// The spacing of the data near each of `points`, which lie `distances` from it (the
    /// sampling's for a cloud, the edges' for a mesh).
    fn spacings(&self, points: &[DVec3], distances: &[f64]) -> Vec<Option<f64>>;
    /// Whether the data itself turns sharply between the places nearest to `a` and `b` (a crease
    /// or corner the wrap should follow).
    fn turns_between(&self, a: DVec3, b: DVec3) -> bool;
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
}

/// Measures the wrap `(positions, triangles)` whose vertices lie `distances` from the data.
pub fn faithfulness(
    positions: &[DVec3],
    triangles: &[[u32; 3]],
    distances: &[f64],
    data: &(impl DataNear + Sync),
) -> Faithfulness {
    // The distances' part and the faces' part are independent: natively one beside the other.
    let ((sorted, mut flagged), (folds, interior, fold_ends, min_angle_rad, good)) =
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
    }
}

/// Every vertex's distance in local spacings, ascending, and the vertices [`FAR_SPACINGS`] or
/// more off.
fn far_from_data(
    positions: &[DVec3],
    distances: &[f64],
    data: &impl DataNear,
) -> (Vec<f64>, Vec<u32>) {
    let spacings = data.spacings(positions, distances);
    let ratios: Vec<f64> = spacings
        .iter()
        .zip(distances)
        .map(|(s, d)| s.filter(|s| *s > 0.0).map_or(0.0, |s| d / s))
        .collect();
    let far = (0..positions.len() as u32)
        .filter(|&v| ratios[v as usize] >= FAR_SPACINGS)
        .collect();
    let mut sorted = ratios;
    sorted.sort_by(f64::total_cmp);
    (sorted, far)
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
        }
        assert_eq!(faithfulness(&p, &t, &[0.0; 4], &Creased).folds, 0);
    }
}
