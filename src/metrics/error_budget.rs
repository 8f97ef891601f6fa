//! Where a wrap's remaining error comes from: every target point's distance
//! to the wrap, and every wrap vertex's distance to the target, put in one class by its cause.
//!
//! * `features` — target points within one grid cell of a crease line or corner of a mesh
//!   target ([`crate::geometry::creases`]): the error of edges and corners not kept sharp.
//! * `sizing` — other target points whose nearest wrap face has every vertex on the target:
//!   the face's chord cuts across the target's bend, and only shorter edges there reduce it.
//! * `not_reached` — other target points whose nearest wrap face has a vertex off the target:
//!   the surface was held back (a valley bridged by the smoothing, a move the fit refused, a
//!   hole in the scan spanned).
//! * `vertices_off` — wrap vertices off the target (the mesh → target side of the Hausdorff
//!   distance): the same causes as `not_reached`, seen from the wrap.
//!
//! "On the target" means within 1 % of a cell of a mesh target (the fit puts vertices on its
//! triangles) or a quarter cell of a cloud's nearest point (the fit puts them on a plane through
//! the points, between them). On a cloud every distance is to the nearest *point*, so
//! `vertices_off` there is floored by the point spacing, not only by the wrap's error.

use crate::geometry::creases::detect_creases;
use crate::geometry::spatial::bvh::{PointBvh, TriangleBvh};
use crate::metrics::distance::{distances_to_points, distances_to_triangles};
use crate::target::{CreaseSource, Surface, Target};
use glam::DVec3;
use serde::Serialize;

/// One class of the budget (distances in target units and in % of the target's diagonal).
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize)]
pub struct BudgetClass {
    /// Points in the class.
    pub count: usize,
    /// Mean and largest distance.
    pub mean: f64,
    pub max: f64,
    pub mean_percent: f64,
    pub max_percent: f64,
}

/// The error budget of a wrap (see the module doc).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct ErrorBudget {
    pub features: BudgetClass,
    pub sizing: BudgetClass,
    pub not_reached: BudgetClass,
    pub vertices_off: BudgetClass,
    /// The two-sided Hausdorff distance, in % of the target's diagonal.
    pub hausdorff_percent: f64,
    /// The class that holds it.
    pub hausdorff_from: &'static str,
}

/// The error budget of the wrap `(positions, triangles)` against `target`, with the wrap's
/// grid `cell` (target units) and the fit's crease angle (degrees; 0: no feature class).
pub fn error_budget(
    positions: &[DVec3],
    triangles: &[[u32; 3]],
    target: &Target,
    cell: f64,
    crease_angle_deg: f64,
) -> ErrorBudget {
    let diag = target.bbox.diagonal().max(f64::MIN_POSITIVE);
    let oracle = target.oracle();
    // Wrap vertices → target, and how close counts as on it.
    let (off, on_tol): (Vec<f64>, f64) = match oracle.surface() {
        Surface::Triangles { points, triangles } => (
            distances_to_triangles(positions, &TriangleBvh::new(points, triangles)),
            0.01 * cell,
        ),
        Surface::Points(points) => (
            distances_to_points(positions, &PointBvh::new(points)),
            0.25 * cell,
        ),
    };
    let dihedral = oracle.creases() == Some(CreaseSource::Dihedral);
    let creases = (dihedral && crease_angle_deg > 0.0).then(|| {
        detect_creases(
            &target.points,
            &target.triangles,
            crease_angle_deg.to_radians(),
        )
    });
    // Target points → wrap, with the class of each.
    let wrap = TriangleBvh::new(positions, triangles);
    let classed: Vec<(u8, f64)> = crate::parallel::map(target.points.len(), |i| {
        let p = target.points[i];
        let Some(hit) = wrap.closest_point(p) else {
            return (NOT_REACHED, f64::INFINITY);
        };
        let d = hit.distance_squared.sqrt();
        let near_crease = creases.as_ref().is_some_and(|c| {
            c.closest_edge_point(p, cell).is_some()
                || c.nearest_corner(p).is_some_and(|(_, dc)| dc <= cell)
        });
        let reached = triangles[hit.triangle as usize]
            .iter()
            .all(|&v| off[v as usize] <= on_tol);
        let class = if near_crease {
            FEATURES
        } else if reached {
            SIZING
        } else {
            NOT_REACHED
        };
        (class, d)
    });
    let summary = |d: &mut dyn Iterator<Item = f64>| {
        let (mut n, mut sum, mut max) = (0usize, 0.0, 0.0f64);
        for x in d {
            n += 1;
            sum += x;
            max = max.max(x);
        }
        let mean = if n == 0 { 0.0 } else { sum / n as f64 };
        BudgetClass {
            count: n,
            mean,
            max,
            mean_percent: 100.0 * mean / diag,
            max_percent: 100.0 * max / diag,
        }
    };
    let class = |k: u8| summary(&mut classed.iter().filter(|c| c.0 == k).map(|c| c.1));
    let (features, sizing, not_reached) = (class(FEATURES), class(SIZING), class(NOT_REACHED));
    let vertices_off = summary(&mut off.iter().copied());
    let named = [
        ("features", features.max),
        ("sizing", sizing.max),
        ("not_reached", not_reached.max),
        ("vertices_off", vertices_off.max),
    ];
    let (from, h) = named
        .into_iter()
        .fold(("none", 0.0), |a, b| if b.1 > a.1 { b } else { a });
    ErrorBudget {
        features,
        sizing,
        not_reached,
        vertices_off,
        hausdorff_percent: 100.0 * h / diag,
        hausdorff_from: from,
    }
}

const FEATURES: u8 = 0;
const SIZING: u8 = 1;
const NOT_REACHED: u8 = 2;

#[cfg(test)]
mod tests {
    use super::*;
    use crate::demo::shapes::grid_box;
    use crate::geometry::icosphere::unit_icosphere;

    #[test]
    fn chords_are_sizing_pushed_out_vertices_are_not_reached_and_cut_corners_are_features() {
        // A fine sphere as the target, a coarse inscribed one as the wrap: every wrap vertex
        // lies on the target, so the whole error is the chords' — sizing.
        let (fine, tf) = unit_icosphere(4);
        let target = Target::new(fine.clone(), tf).unwrap();
        let (mut coarse, tc) = unit_icosphere(2);
        let b = error_budget(&coarse, &tc, &target, 0.05, 40.0);
        assert_eq!(b.hausdorff_from, "sizing", "{b:?}");
        assert_eq!(b.features.count + b.not_reached.count, 0, "{b:?}");
        assert!(b.vertices_off.max < 0.01 * 0.05);
        // Chord sagitta of a level-2 icosphere: about 1 − cos(edge/2) ≈ 0.01.
        assert!((0.003..0.03).contains(&b.sizing.max), "{b:?}");
        // One vertex pushed out by 0.1: it holds the Hausdorff, and target points near it are
        // not reached.
        coarse[0] *= 1.1;
        let b = error_budget(&coarse, &tc, &target, 0.05, 40.0);
        assert_eq!(b.hausdorff_from, "vertices_off", "{b:?}");
        assert!((b.vertices_off.max - 0.1).abs() < 1e-3, "{b:?}");
        assert!(b.not_reached.count > 0);
        // A cube wrapped by its own vertices moved 0.05 inwards at the corners: features.
        let (p, t) = grid_box(DVec3::ONE, [4, 4, 4]);
        let cube = Target::new(p.clone(), t.clone()).unwrap();
        let cut: Vec<DVec3> = p
            .iter()
            .map(|q| {
                if q.abs() == DVec3::splat(0.5) {
                    *q * 0.9
                } else {
                    *q
                }
            })
            .collect();
        let b = error_budget(&cut, &t, &cube, 0.1, 40.0);
        assert_eq!(b.hausdorff_from, "features", "{b:?}");
        assert!(b.features.max > 0.04, "{b:?}");
        assert_eq!(b.sizing.max, 0.0, "{b:?}");
    }
}
