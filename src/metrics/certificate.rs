//! The certificate every result carries: closed, manifold, oriented, finite, genus and
//! components, the exact self-intersection count, and the distance range to the target.
//! `valid` is the first promise of the tool — closed, manifold, oriented, finite and without a
//! single intersecting face pair; a result that is not valid is never presented as done.

use super::faithful::{faithfulness, DataNear, Faithfulness};
use super::intersections::count_self_intersections;
use crate::geometry::spatial::bvh::TriangleBvh;
use crate::geometry::spatial::point_grid::PointGrid;
use crate::mesh::{edge_counts, HalfedgeMesh, MeshBuildError, ValidationError};
use crate::target::{Surface, Target};
use glam::DVec3;
use serde::{Deserialize, Serialize};

/// The certificate of a triangle mesh (keys are a stable interface: `certificate` in
/// `lsw wrap --stats`, `lsw wrap`'s output and `lsw metrics`).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[cfg_attr(target_arch = "wasm32", derive(tsify::Tsify))]
pub struct Certificate {
    /// Closed, manifold, oriented, finite, no intersecting face pair.
    pub valid: bool,
    /// No boundary edge.
    pub closed: bool,
    /// Every edge has at most two faces and every vertex one fan.
    pub manifold: bool,
    /// Neighbouring faces agree on orientation.
    pub oriented: bool,
    /// Every coordinate is finite.
    pub finite: bool,
    /// Genus (closed manifold oriented meshes only).
    pub genus: Option<i64>,
    /// Connected components (closed manifold oriented meshes only).
    pub components: Option<usize>,
    /// Euler characteristic V − E + F (closed manifold oriented meshes only).
    pub euler_characteristic: Option<i64>,
    /// Face pairs that meet other than in their shared vertices or edge (exact predicates).
    pub self_intersections: usize,
    /// Faces of zero area (reported, not part of `valid`: the exact test already catches folds).
    pub degenerate_faces: usize,
    /// Smallest and largest distance from a result vertex to the target (target units), when a
    /// target is given.
    pub distance_min: Option<f64>,
    pub distance_max: Option<f64>,
    /// The first broken property in words, or `None` when valid.
    pub problem: Option<String>,
    /// How close to the data the wrap stays, in the data's own spacing, and how its faces fold
    /// and are shaped (closed manifold wraps with a target; see
    /// [`super::faithful`]).
    #[serde(default)]
    pub faithfulness: Option<Faithfulness>,
    /// Genus and components (1) of the target's triangles when they form one closed manifold
    /// part (None for clouds, open or non-manifold meshes, and targets of several parts: a wrap
    /// takes the outside of nested shells, of a noisy iso-surface's specks, of overlapping
    /// parts). The wrap should have the same; a difference (a handle lost or added) is shown,
    /// not part of `valid`.
    #[serde(default)]
    pub target_genus: Option<i64>,
    #[serde(default)]
    pub target_components: Option<usize>,
    /// Of `target_points_checked` target points (every point of a cloud or vertex of a mesh,
    /// or an even subsample of at most [`OUTSIDE_SAMPLES`]), how many lie outside the wrap and
    /// farther from it than [`OUTSIDE_TOLERANCE`] of the target's diagonal: a part of the
    /// target the wrap cut off (a thin spike that poked through a coarse face early on). None
    /// without a target or for a wrap that is not closed.
    #[serde(default)]
    pub target_points_outside: Option<usize>,
    #[serde(default)]
    pub target_points_checked: Option<usize>,
    /// More than [`OUTSIDE_SHARE`] of the checked points lie outside: a part of the target is
    /// left out (a noisy scan's few far points are not). Shown, not part of `valid`.
    #[serde(default)]
    pub target_part_outside: bool,
}

impl Certificate {
    /// What a certificate shows beside `valid`, in words: the wrap's genus or parts differ from
    /// the target's (a handle lost or added, a speck split off), or a part of the target lies
    /// outside the wrap. Empty when neither. A script that checks `valid` alone would take such
    /// a wrap as done; `lsw wrap` prints these on stderr and as `warnings`.
    pub fn warnings(&self) -> Vec<String> {
        let mut w = Vec::new();
        if let (Some(tg), Some(tc), Some(g), Some(c)) = (
            self.target_genus,
            self.target_components,
            self.genus,
            self.components,
        ) {
            if (tg, tc) != (g, c) {
                w.push(format!(
                    "the target has genus {tg} in {tc} part(s) and the wrap genus {g} in {c}"
                ));
            }
        }
        if self.target_part_outside {
            w.push(format!(
                "{} of {} target points checked lie outside the wrap: a part of the target is \
                 left out",
                self.target_points_outside.unwrap_or(0),
                self.target_points_checked.unwrap_or(0)
            ));
        }
        w
    }
}

/// At most this many target points are tested for lying outside the wrap.
pub const OUTSIDE_SAMPLES: usize = 20_000;
/// A target point counts as outside the wrap when it is farther from it than this fraction of
/// the target's diagonal (well above a fit's residual on a noisy scan).
pub const OUTSIDE_TOLERANCE: f64 = 0.01;
/// A part is left outside when more than this share of the checked points lie outside: a noisy
/// scan has a few points past [`OUTSIDE_TOLERANCE`], a cut-off spike or rounded-off corner holds
/// many times this share.
pub const OUTSIDE_SHARE: f64 = 0.005;

/// Cells of the cloud's grid along its bounding-box diagonal (refined where dense).
const CLOUD_GRID_DIVISIONS: f64 = 200.0;

/// What the certificate needs of a target, built once: its nearest-point structure and its
/// topology, both costly on a large target (the CLI builds it beside the steps).
pub struct CertificateTarget {
    near: Near,
    topology: Option<crate::mesh::MeshReport>,
    /// The target points tested for lying outside the wrap, and how far out counts.
    samples: Vec<DVec3>,
    outside_tolerance: f64,
    /// A cloud's median point spacing (0 for a mesh): within [`ON_DATA_SPACINGS`] of it a place
    /// lies on the data whatever the local spacing.
    median_spacing: f64,
}

enum Near {
    Points(PointGrid),
    /// With each vertex's flag: on a boundary edge or next to one.
    Triangles(TriangleBvh, Vec<bool>),
}

impl CertificateTarget {
    /// A point grid for a cloud, a BVH for a mesh, and the topology of a closed one.
    pub fn new(t: &Target) -> Self {
        let near = match t.oracle().surface() {
            Surface::Points(points) => {
                // A counting-sort grid builds in a fraction of a tree's time on millions of
                // points. Cells no smaller than a surface sampled by this many points would need:
                // on a sparse cloud a nearest-point query otherwise opens rings of empty cells.
                let sampled = t.bbox.diagonal() / (points.len() as f64).sqrt();
                let cell = (t.bbox.diagonal() / CLOUD_GRID_DIVISIONS).max(sampled);
                Near::Points(PointGrid::new(points, cell))
            }
            Surface::Triangles { points, triangles } => Near::Triangles(
                TriangleBvh::new(points, triangles),
                boundary_band(points.len(), triangles),
            ),
        };
        CertificateTarget {
            near,
            topology: t.one_closed_part(),
            samples: outside_samples(t),
            outside_tolerance: OUTSIDE_TOLERANCE * t.bbox.diagonal(),
            median_spacing: t.oracle().spacing().unwrap_or(0.0),
        }
    }

    fn distance(&self, p: DVec3) -> f64 {
        match &self.near {
            Near::Points(grid) => grid.nearest(p).map_or(f64::INFINITY, |n| n.d2.sqrt()),
            Near::Triangles(bvh, _) => bvh.distance(p),
        }
    }
}

/// Each of `n` vertices: whether it lies on an edge of one face of `triangles` or next to one.
fn boundary_band(n: usize, triangles: &[[u32; 3]]) -> Vec<bool> {
    let mut edges: Vec<(u32, u32)> = triangles
        .iter()
        .flat_map(|t| (0..3).map(move |k| (t[k].min(t[(k + 1) % 3]), t[k].max(t[(k + 1) % 3]))))
        .collect();
    edges.sort_unstable();
    let mut on = vec![false; n];
    for run in edges.chunk_by(|a, b| a == b).filter(|run| run.len() == 1) {
        on[run[0].0 as usize] = true;
        on[run[0].1 as usize] = true;
    }
    let mut band = on.clone();
    for t in triangles
        .iter()
        .filter(|t| t.iter().any(|&v| on[v as usize]))
    {
        for &v in t {
            band[v as usize] = true;
        }
    }
    band
}

/// Points round a cloud's point whose directions tell whether the data goes on all round it.
const EDGE_POINTS: usize = 16;

/// A cloud's point lies at an edge of the data when its neighbours, seen along its normal, leave
/// a gap of directions wider than this (radians): a random sampling leaves far narrower ones.
const EDGE_GAP: f64 = 2.0 * std::f64::consts::FRAC_PI_3;

/// Whether the widest gap between the directions from `q` to its neighbours `patch`, in the
/// plane across `normal`, exceeds [`EDGE_GAP`].
fn gap_round(q: DVec3, normal: DVec3, patch: &[DVec3]) -> bool {
    let u = normal.any_orthonormal_vector();
    let w = normal.cross(u);
    let mut angles: Vec<f64> = patch
        .iter()
        .map(|&p| p - q)
        .filter(|d| d.length_squared() > 0.0)
        .map(|d| crate::fmath::atan2(d.dot(w), d.dot(u)))
        .collect();
    if angles.len() < 3 {
        return true;
    }
    angles.sort_by(f64::total_cmp);
    let wrap = angles[0] + std::f64::consts::TAU - angles[angles.len() - 1];
    let widest = angles.windows(2).map(|a| a[1] - a[0]).fold(wrap, f64::max);
    widest > EDGE_GAP
}

/// Median spacings within which a place lies on a cloud's data (see [`DataNear`]): the gaps of a
/// random sampling reach about this far, and a local spacing costs a patch search.
const ON_DATA_SPACINGS: f64 = 1.5;

/// Points of a cloud's patch whose plane fit tells whether the data turns there.
const PATCH_POINTS: usize = 32;

/// Radians by which a mesh's normals turn between two places for the mesh to have a crease
/// there.
const MESH_CREASE_TURN: f64 = std::f64::consts::FRAC_PI_3;

impl DataNear for CertificateTarget {
    fn spacings(&self, points: &[DVec3], distances: &[f64]) -> Vec<Option<f64>> {
        let grid = match &self.near {
            Near::Points(grid) => grid,
            Near::Triangles(bvh, _) => {
                return crate::parallel::map(points.len(), |i| {
                    let [a, b, c] = closest_triangle(bvh, points[i])?;
                    Some(((b - a).length() + (c - b).length() + (a - c).length()) / 3.0)
                })
            }
        };
        // Off the data, the spacing of the patch round the nearest point: found once per point
        // (the vertices over a gap share the points of its rim).
        let on = ON_DATA_SPACINGS * self.median_spacing;
        let nearest = crate::parallel::map(points.len(), |i| {
            (distances[i] > on)
                .then(|| grid.nearest(points[i]))
                .flatten()
        });
        let mut rim: Vec<(u32, DVec3)> = nearest
            .iter()
            .flatten()
            .map(|n| (n.index, n.point))
            .collect();
        rim.sort_unstable_by_key(|r| r.0);
        rim.dedup_by_key(|r| r.0);
        let spacing = crate::parallel::map(rim.len(), |k| {
            crate::geometry::spatial::local_spacing::spacing_at(grid, rim[k].1)
        });
        nearest
            .iter()
            .map(|n| match n {
                None => Some(self.median_spacing),
                Some(n) => rim
                    .binary_search_by_key(&n.index, |r| r.0)
                    .ok()
                    .and_then(|k| spacing[k]),
            })
            .collect()
    }

    fn at_edge(&self, p: DVec3) -> bool {
        match &self.near {
            Near::Points(grid) => {
                let Some(q) = grid.nearest(p) else {
                    return false;
                };
                let mut patch = Vec::new();
                grid.nearest_within(q.point, grid.diagonal(), EDGE_POINTS + 1, &mut patch);
                let points: Vec<DVec3> = patch.iter().map(|n| n.point).collect();
                crate::geometry::cloud_creases::plane_fit(points.iter().copied())
                    .is_some_and(|(normal, _)| gap_round(q.point, normal, &points))
            }
            Near::Triangles(bvh, band) => bvh.closest_point(p).is_some_and(|hit| {
                bvh.triangles()[hit.triangle as usize]
                    .iter()
                    .any(|&v| band[v as usize])
            }),
        }
    }

    fn turns_between(&self, a: DVec3, b: DVec3) -> bool {
        use crate::geometry::cloud_creases::{plane_fit, CANDIDATE_VARIATION};
        match &self.near {
            Near::Points(grid) => {
                let mut patch = Vec::new();
                grid.nearest_within(0.5 * (a + b), grid.diagonal(), PATCH_POINTS, &mut patch);
                plane_fit(patch.iter().map(|n| n.point))
                    .is_none_or(|(_, variation)| variation > CANDIDATE_VARIATION)
            }
            Near::Triangles(bvh, _) => {
                let normal = |p| {
                    closest_triangle(bvh, p)
                        .map(|[a, b, c]| (b - a).cross(c - a).normalize_or_zero())
                };
                match (normal(a), normal(b)) {
                    (Some(m), Some(n)) => m.dot(n) < crate::fmath::cos(MESH_CREASE_TURN),
                    _ => true,
                }
            }
        }
    }
}

/// The corners of `bvh`'s triangle closest to `p`.
fn closest_triangle(bvh: &TriangleBvh, p: DVec3) -> Option<[DVec3; 3]> {
    let hit = bvh.closest_point(p)?;
    Some(bvh.triangles()[hit.triangle as usize].map(|v| bvh.positions()[v as usize]))
}

/// Certifies `(positions, triangles)`; with `target`, also measures vertex → target distances.
pub fn certify(
    positions: &[DVec3],
    triangles: &[[u32; 3]],
    target: Option<&Target>,
) -> Certificate {
    certify_against(
        positions,
        triangles,
        target.map(CertificateTarget::new).as_ref(),
    )
}

/// What building the half-edge mesh says: manifold and oriented as far as it can tell, the
/// first problem met, the topology, and the faces of zero area.
struct MeshChecks {
    manifold: bool,
    oriented: bool,
    problem: Option<String>,
    report: Option<crate::mesh::MeshReport>,
    degenerate_faces: usize,
}

impl MeshChecks {
    /// `manifold`: the edge counts found no edge with more than two faces; `closed_finite`: no
    /// boundary edge and every position finite (a degenerate face's topology is read then).
    fn of(
        positions: &[DVec3],
        triangles: &[[u32; 3]],
        manifold: bool,
        closed_finite: bool,
    ) -> Self {
        let mut c = MeshChecks {
            manifold,
            oriented: true,
            problem: None,
            report: None,
            degenerate_faces: 0,
        };
        match HalfedgeMesh::from_triangles(positions.to_vec(), triangles) {
            Err(e) => {
                match e {
                    MeshBuildError::NonManifoldEdge { .. } if manifold => c.oriented = false,
                    MeshBuildError::NonManifoldVertex { .. } => c.manifold = false,
                    _ => c.manifold = false,
                }
                c.problem = Some(e.to_string());
            }
            Ok(m) => {
                c.degenerate_faces = (0..m.n_faces() as u32)
                    .filter(|&f| m.face_normal_area(f).1 <= 0.0)
                    .count();
                match m.validate() {
                    Ok(r) => c.report = Some(r),
                    Err(ValidationError::NonManifoldVertex { .. }) => c.manifold = false,
                    Err(ValidationError::DegenerateFace { .. }) if closed_finite => {
                        c.report = Some(m.topology());
                    }
                    Err(e) => c.problem = Some(e.to_string()),
                }
            }
        }
        c
    }
}

/// [`certify`] with the target's side already built.
pub fn certify_against(
    positions: &[DVec3],
    triangles: &[[u32; 3]],
    target: Option<&CertificateTarget>,
) -> Certificate {
    certify_measuring(positions, triangles, target).0
}

/// [`certify_against`], with each vertex's exact distance to the target, which the certificate
/// needs anyway (None without a target or with a non-finite vertex).
pub fn certify_measuring(
    positions: &[DVec3],
    triangles: &[[u32; 3]],
    target: Option<&CertificateTarget>,
) -> (Certificate, Option<Vec<f64>>) {
    let finite = positions.iter().all(|p| p.is_finite());
    // The checks are independent: natively the self-intersections are counted beside the
    // topology, and the distances computed beside the outside test.
    let (self_intersections, (edges, closed, mesh)) = crate::parallel::beside(
        || match finite {
            true => count_self_intersections(positions, triangles),
            false => 0,
        },
        || {
            let edges = edge_counts(triangles);
            let closed = edges.boundary == 0 && !triangles.is_empty();
            let manifold = edges.non_manifold == 0;
            let mesh = MeshChecks::of(positions, triangles, manifold, closed && finite);
            (edges, closed, mesh)
        },
    );
    let MeshChecks {
        manifold,
        oriented,
        mut problem,
        report,
        degenerate_faces,
    } = mesh;
    if triangles.is_empty() {
        problem = Some("the mesh has no faces".into());
    }
    let valid = closed && manifold && oriented && finite && self_intersections == 0;
    if problem.is_none() && !valid {
        problem = Some(if !finite {
            "a vertex has a non-finite position".to_string()
        } else if !closed {
            format!("the mesh is not closed ({} boundary edges)", edges.boundary)
        } else if !manifold {
            "the mesh is not manifold".to_string()
        } else if !oriented {
            "the faces are not consistently oriented".to_string()
        } else {
            format!("{self_intersections} pairs of faces intersect")
        });
    }
    let (distances, outside) = crate::parallel::beside(
        || match target {
            Some(t) if finite && !positions.is_empty() => {
                Some(crate::parallel::map(positions.len(), |i| {
                    t.distance(positions[i])
                }))
            }
            _ => None,
        },
        || match target {
            Some(t) if closed && manifold && oriented && finite => Some(points_outside(
                positions,
                triangles,
                &t.samples,
                t.outside_tolerance,
            )),
            _ => None,
        },
    );
    let target_topology = target.and_then(|t| t.topology);
    let faithfulness = match (&distances, target) {
        (Some(d), Some(t)) if closed && manifold => Some(faithfulness(positions, triangles, d, t)),
        _ => None,
    };
    let distance_min = distances
        .as_ref()
        .map(|d| d.iter().copied().fold(f64::INFINITY, f64::min));
    let distance_max = distances
        .as_ref()
        .map(|d| d.iter().copied().fold(0.0, f64::max));
    let certificate = Certificate {
        valid,
        closed,
        manifold,
        oriented,
        finite,
        genus: report.map(|r| r.genus),
        components: report.map(|r| r.components),
        euler_characteristic: report.map(|r| r.euler_characteristic),
        self_intersections,
        degenerate_faces,
        distance_min,
        distance_max,
        problem: if valid { None } else { problem },
        faithfulness,
        target_genus: target_topology.map(|t| t.genus),
        target_components: target_topology.map(|t| t.components),
        target_points_outside: outside,
        target_points_checked: outside.and(target.map(|t| t.samples.len())),
        target_part_outside: match (outside, target) {
            (Some(n), Some(t)) => part_outside(n, t.samples.len()),
            _ => false,
        },
    };
    (certificate, distances)
}

/// The target points tested for lying outside a wrap: every point of a cloud or vertex of a
/// mesh, or an even subsample of at most [`OUTSIDE_SAMPLES`].
pub fn outside_samples(t: &Target) -> Vec<DVec3> {
    let stride = t.points.len().div_ceil(OUTSIDE_SAMPLES).max(1);
    t.points.iter().copied().step_by(stride).collect()
}

/// Whether `outside` of `checked` points is a part of the target left out (more than
/// [`OUTSIDE_SHARE`]).
pub fn part_outside(outside: usize, checked: usize) -> bool {
    outside as f64 > OUTSIDE_SHARE * checked as f64
}

/// How many of `points` lie outside the closed surface `(positions, triangles)` and farther
/// from it than `tolerance`.
pub fn points_outside(
    positions: &[DVec3],
    triangles: &[[u32; 3]],
    points: &[DVec3],
    tolerance: f64,
) -> usize {
    outside_distances(positions, triangles, points, tolerance).len()
}

/// The distances to the closed surface `(positions, triangles)` of the `points` that lie
/// outside it and farther than `tolerance` (in the points' order).
pub fn outside_distances(
    positions: &[DVec3],
    triangles: &[[u32; 3]],
    points: &[DVec3],
    tolerance: f64,
) -> Vec<f64> {
    let bvh = TriangleBvh::new(positions, triangles);
    let out = crate::parallel::map(points.len(), |i| {
        let p = points[i];
        let outside = bvh.closest_point_within(p, tolerance).is_none() && !bvh.encloses(p);
        outside.then(|| bvh.distance(p))
    });
    out.into_iter().flatten().collect()
}

/// How far out the part left outside lies: the distance beyond which at most the
/// [`OUTSIDE_SHARE`] of `checked` points lie outside, given the `outside` points' distances
/// (0 where that share is not exceeded: no part is outside, see [`part_outside`]).
pub fn outside_miss(outside: &[f64], checked: usize) -> f64 {
    let allowed = (OUTSIDE_SHARE * checked as f64) as usize;
    if outside.len() <= allowed {
        return 0.0;
    }
    let mut d = outside.to_vec();
    d.sort_unstable_by(|a, b| b.total_cmp(a));
    d[allowed]
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::icosphere::icosphere;

    /// A wrap on its data is faithful; one 10 spacings off a cloud has every vertex far (brute
    /// force: the cloud is a fine sphere's vertices, the wrap a coarse sphere around them).
    #[test]
    fn faithfulness_reads_distances_in_the_data_spacing() {
        let fine = icosphere(5, 1.0, DVec3::ZERO).unwrap();
        let coarse = icosphere(2, 1.0, DVec3::ZERO).unwrap();
        let (p, t) = (coarse.positions().to_vec(), coarse.triangles());
        let mesh = Target::new(fine.positions().to_vec(), fine.triangles()).unwrap();
        let on = certify(&p, &t, Some(&mesh)).faithfulness.unwrap();
        assert_eq!((on.far_vertices, on.folds), (0, 0), "{on:?}");
        assert!(
            on.distance_max_spacings < 0.1 && on.kappa_good_share > 0.9,
            "{on:?}"
        );
        let cloud = Target::new(fine.positions().to_vec(), vec![]).unwrap();
        let h = crate::geometry::spatial::spacing::median_spacing(&cloud.points);
        let off: Vec<DVec3> = p.iter().map(|q| *q * (1.0 + 10.0 * h)).collect();
        let far = certify(&off, &t, Some(&cloud)).faithfulness.unwrap();
        assert_eq!(far.far_vertices, p.len(), "{far:?}");
        assert!((7.0..13.0).contains(&far.distance_p99_spacings), "{far:?}");
        assert_eq!(far.flagged_vertices.len(), p.len());
    }

    #[test]
    fn sphere_is_valid_broken_ones_are_not() {
        let m = icosphere(2, 1.0, DVec3::ZERO).unwrap();
        let (p, t) = (m.positions().to_vec(), m.triangles());
        let c = certify(&p, &t, None);
        assert!(c.valid, "{c:?}");
        assert_eq!(
            (c.genus, c.components, c.self_intersections),
            (Some(0), Some(1), 0)
        );
        // Open: drop a face.
        let c = certify(&p, &t[1..], None);
        assert!(!c.valid && !c.closed && c.problem.is_some());
        // Inconsistent orientation: flip one face.
        let mut flipped = t.clone();
        flipped[0] = [t[0][0], t[0][2], t[0][1]];
        let c = certify(&p, &flipped, None);
        assert!(!c.valid && !c.oriented, "{c:?}");
        // Self-intersecting: a vertex pushed through the far side.
        let mut q = p.clone();
        q[0] = -1.5 * q[0];
        let c = certify(&q, &t, None);
        assert!(!c.valid && c.self_intersections > 0 && c.closed && c.manifold);
        // Distances to a target: the sphere against its own vertices.
        let target = Target::new(p.clone(), vec![]).unwrap();
        let c = certify(&p, &t, Some(&target));
        assert_eq!((c.distance_min, c.distance_max), (Some(0.0), Some(0.0)));
        assert_eq!((c.target_genus, c.target_components), (None, None));
    }

    /// A closed one-part mesh target's topology is reported beside the wrap's; an open one's
    /// and a two-part one's are not.
    #[test]
    fn a_closed_targets_topology_is_reported() {
        let m = icosphere(2, 1.0, DVec3::ZERO).unwrap();
        let (p, t) = (m.positions().to_vec(), m.triangles());
        let torus = crate::demo::shapes::generate("torus-g2").unwrap();
        let target = Target::new(torus.0, torus.1).unwrap();
        let c = certify(&p, &t, Some(&target));
        assert_eq!((c.genus, c.components), (Some(0), Some(1)));
        assert_eq!((c.target_genus, c.target_components), (Some(2), Some(1)));
        assert!(
            c.valid,
            "a topology difference is shown, not part of `valid`"
        );
        assert_eq!(
            c.warnings(),
            ["the target has genus 2 in 1 part(s) and the wrap genus 0 in 1"]
        );
        assert!(certify(&p, &t, None).warnings().is_empty());
        let open = Target::new(p.clone(), t[1..].to_vec()).unwrap();
        let c = certify(&p, &t, Some(&open));
        assert_eq!((c.target_genus, c.target_components), (None, None));
        let shifted: Vec<DVec3> = p.iter().map(|&q| q + DVec3::X * 3.0).collect();
        let n = p.len() as u32;
        let two_t = t.iter().copied().chain(t.iter().map(|f| f.map(|v| v + n)));
        let two = Target::new([p.clone(), shifted].concat(), two_t.collect()).unwrap();
        let c = certify(&p, &t, Some(&two));
        assert_eq!((c.target_genus, c.target_components), (None, None));
    }

    /// Target points the wrap cut off are counted; points inside it, on it or near it are not.
    #[test]
    fn a_part_outside_lies_as_far_out_as_its_share_allows() {
        let m = icosphere(3, 1.0, DVec3::ZERO).unwrap();
        let (p, t) = (m.positions().to_vec(), m.triangles());
        // A spike of 5 points out to 1.5 along z: at 1.1, 1.2, … 1.5 (about 0.1 … 0.5 out).
        let spike: Vec<DVec3> = (1..=5)
            .map(|k| DVec3::new(0.0, 0.0, 1.0 + 0.1 * k as f64))
            .collect();
        let d = outside_distances(&p, &t, &spike, 0.05);
        assert_eq!(d.len(), 5);
        for (k, d) in d.iter().enumerate() {
            assert!((d - 0.1 * (k + 1) as f64).abs() < 0.01, "{d}");
        }
        // Of 400 checked points, 2 may lie outside (0.5 %): the miss is the third farthest.
        assert!((outside_miss(&d, 400) - 0.3).abs() < 0.01);
        assert!((outside_miss(&d, 200) - 0.4).abs() < 0.01);
        // No part outside: no miss.
        assert_eq!(outside_miss(&d, 1000), 0.0);
        assert_eq!(outside_miss(&[], 10), 0.0);
    }

    #[test]
    fn target_points_left_outside_are_counted() {
        let m = icosphere(3, 1.0, DVec3::ZERO).unwrap();
        let (p, t) = (m.positions().to_vec(), m.triangles());
        // A cloud on the sphere, one inside, and a spike of 5 points out to 1.5 along z.
        let mut cloud = p.clone();
        cloud.push(DVec3::ZERO);
        cloud.extend((1..=5).map(|k| DVec3::new(0.01, 0.02, 1.0 + 0.1 * k as f64)));
        let target = Target::new(cloud.clone(), vec![]).unwrap();
        let c = certify(&p, &t, Some(&target));
        // The diagonal is about 3.6, so the tolerance 0.036: every spike point is outside.
        assert_eq!(c.target_points_outside, Some(5), "{c:?}");
        assert_eq!(c.target_points_checked, Some(cloud.len()));
        assert!(c.target_part_outside, "5 of 648 points");
        // One far point in ten thousand is a noisy scan's, not a part left out.
        let mut noisy: Vec<DVec3> = (0..10_000)
            .map(|i| p[i % p.len()] * (1.0 - 1e-4 * (i / p.len()) as f64))
            .collect();
        noisy.push(DVec3::new(0.0, 0.0, 1.2));
        let target = Target::new(noisy, vec![]).unwrap();
        let c = certify(&p, &t, Some(&target));
        assert_eq!(c.target_points_outside, Some(1), "{c:?}");
        assert!(!c.target_part_outside);
        assert!(c.valid, "shown, not part of `valid`");
        // Without the spike: none. An open wrap: not measured.
        let target = Target::new(cloud[..p.len() + 1].to_vec(), vec![]).unwrap();
        assert_eq!(
            certify(&p, &t, Some(&target)).target_points_outside,
            Some(0)
        );
        let c = certify(&p, &t[1..], Some(&target));
        assert_eq!(
            (c.target_points_outside, c.target_points_checked),
            (None, None)
        );
    }
}
