//! Final fit: moves the settled surface from the offset level set d = d₀ onto the target.
//!
//! The evolution stops where the distance field equals d₀ (about one cell out), because a
//! smaller d₀ would let the surface slip between the points of a cloud. Once it has settled,
//! each vertex is moved onto the target: for a point cloud, along the normal of the plane fitted
//! (weighted PCA, lifted by a quadric) to the points around it — a one-step moving-least-squares
//! projection, whose direction is the data's and so varies smoothly from vertex to vertex where
//! the wrap's own normals do not (over a sparse or curve-like sampling the settled surface is
//! dimpled, and moves along its normals longer than its edges fold it); for a mesh, along the
//! vertex normal by the component on it of the way to the closest point of the triangles
//! (exactly onto it where it lies along the normal). Vertices without a clear local
//! surface (too few points, plane nearly parallel to the normal, a move longer than the limit —
//! e.g. where the surface bridges a hole in a scan) take their neighbours' mean move when most
//! of those have one, and otherwise stay where they are.

use crate::geometry::creases::Creases;
use crate::geometry::eigen3::smallest_eigenvector;
use crate::geometry::spatial::bvh::TriangleBvh;
use crate::geometry::spatial::point_grid::{Near, PointGrid};
use crate::mesh::HalfedgeMesh;
use crate::target::{Surface, Target};
use glam::{DMat3, DVec3};

/// Settings of the final fit, in the stabilised frame's units (the evolver converts cells).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SnapParams {
    /// Neighbourhood radius for the plane fit.
    pub radius: f64,
    /// Longest allowed move of a vertex.
    pub max_move: f64,
    /// Fewest points a plane may be fitted to.
    pub min_points: usize,
    /// Most points a plane is fitted to: the nearest within `radius`. Bounds the fit's cost on
    /// dense scans (thousands of points within the radius) without changing it on sparse ones.
    pub max_points: usize,
    /// A cloud's moves follow the fitted plane's normal, not the vertex normal, and the fold
    /// check holds moved faces to the data's side (see [`fold_limited_shares`]).
    pub moving_least_squares: bool,
}

/// What the target looks like to the fit.
pub enum SnapTarget {
    /// A point cloud, bucketed (shared: a cloud's creases are found on the same grid, beside the
    /// steps).
    Points(std::sync::Arc<PointGrid>),
    /// A triangle mesh.
    Triangles(TriangleBvh),
}

impl SnapTarget {
    /// The target in the stabilised frame (`phi·(p − center)`): a point grid of cell `radius`
    /// for clouds, a BVH for meshes.
    pub fn new(target: &Target, center: DVec3, phi: f64, radius: f64) -> Self {
        let framed = |points: &[DVec3]| -> Vec<DVec3> {
            points.iter().map(|&p| phi * (p - center)).collect()
        };
        match target.oracle().surface() {
            Surface::Points(points) => {
                SnapTarget::Points(std::sync::Arc::new(PointGrid::new(&framed(points), radius)))
            }
            Surface::Triangles { points, triangles } => {
                SnapTarget::Triangles(TriangleBvh::new(&framed(points), triangles))
            }
        }
    }
}

/// Vertices per progress report of the moves (and per parallel batch natively).
const PROGRESS_CHUNK: usize = 4096;

/// Moves vertices along `normals` onto the target; returns how many moved. `progress(f)` hears
/// the fraction of the vertices whose move is computed (every [`PROGRESS_CHUNK`] vertices and
/// the last): on a dense scan this is the long part of the final fit.
///
/// A cloud's `creases` (see [`crate::geometry::cloud_creases`]): a vertex within the fit radius
/// of one moves onto the plane of the crease's face on its side, not onto a plane fitted to the
/// points around it, which would straddle the crease and round it off.
pub fn snap_to_target(
    mesh: &mut HalfedgeMesh,
    normals: &[DVec3],
    target: &SnapTarget,
    params: &SnapParams,
    creases: Option<&Creases>,
    progress: &mut dyn FnMut(f64),
) -> usize {
    let n_vertices = mesh.n_vertices();
    let positions = mesh.positions();
    let fitted: Vec<(Option<DVec3>, Option<DVec3>)> = crate::parallel::map_chunked(
        n_vertices,
        PROGRESS_CHUNK,
        |i| {
            let p = positions[i];
            match vertex_move(target, creases, p, normals[i], params) {
                Some((step, normal)) if step.length() <= params.max_move => {
                    (Some(p + step), normal)
                }
                _ => (None, None),
            }
        },
        &mut |done| progress(done as f64 / n_vertices as f64),
    );
    let (moves, data_normals): (Vec<_>, Vec<_>) = fitted.into_iter().unzip();
    // (A cloud's vertices with points around them only: one bridging a hole in the scan has
    // none and stays where the evolution left it.)
    let moves = match target {
        SnapTarget::Points(grid) => fill_from_neighbours(mesh, positions, moves, |p| {
            let mut near = Vec::with_capacity(params.min_points);
            grid.nearest_within_unordered(p, params.radius, params.min_points, &mut near);
            near.len() >= params.min_points
        }),
        SnapTarget::Triangles(_) => moves,
    };
    let old = mesh.positions().to_vec();
    let reference = params.moving_least_squares.then_some(&data_normals[..]);
    let share = fold_limited_shares(mesh, &old, &moves, reference);
    let mut moved = 0;
    for (i, q) in mesh.positions_mut().iter_mut().enumerate() {
        if share[i] > 0.0 {
            *q = partial(old[i], moves[i], share[i]);
            moved += 1;
        }
    }
    moved
}

/// The fit's step for the vertex at `p` (normal `n`) and, for a plane fitted to a cloud, the
/// plane's normal turned to `n`'s side; None without a step.
fn vertex_move(
    target: &SnapTarget,
    creases: Option<&Creases>,
    p: DVec3,
    n: DVec3,
    params: &SnapParams,
) -> Option<(DVec3, Option<DVec3>)> {
    match target {
        SnapTarget::Points(grid) => {
            match creases.and_then(|c| crease_plane_offset(c, p, n, params.radius)) {
                Some(t) => Some((t? * n, None)),
                None => {
                    let (step, m) = plane_move(grid, p, n, params)?;
                    Some((step, Some(m)))
                }
            }
        }
        // Along the normal by the closest point's component on it, also where that point lies
        // off to the side (near a crease or in a narrow valley): moving to the point itself
        // crowds vertices there, and refusing such moves leaves the vertex farther off still.
        SnapTarget::Triangles(bvh) => Some(((bvh.closest_point(p)?.point - p).dot(n) * n, None)),
    }
}

/// Moves every vertex of `mesh` farther than `min_off` from the mesh target `bvh` onto its closest
/// point (moves longer than `max_move` are not made); returns how many moved. For a *closed*
/// target only, after the fit's moves along the normals: there every vertex belongs on the
/// target (no hole to bridge), and one the normal move left off — beside a crease, where its
/// normal leans towards the other face — is put on it.
pub fn snap_to_closest(
    mesh: &mut HalfedgeMesh,
    bvh: &TriangleBvh,
    min_off: f64,
    max_move: f64,
) -> usize {
    move_onto_closest(mesh, bvh, max_move, |_, v, off| off(v) > min_off)
}

/// Moves the vertices `pick` chooses onto their closest points of the mesh target `bvh` (no
/// farther than `max_move`); returns how many moved. `pick(mesh, v, off)` sees every vertex's
/// distance to its closest point through `off` (∞ where there is none), as the mesh was before
/// any of these moves.
pub fn move_onto_closest(
    mesh: &mut HalfedgeMesh,
    bvh: &TriangleBvh,
    max_move: f64,
    pick: impl Fn(&HalfedgeMesh, u32, &dyn Fn(u32) -> f64) -> bool,
) -> usize {
    let pos = mesh.positions();
    let closest: Vec<Option<DVec3>> =
        crate::parallel::map(pos.len(), |i| bvh.closest_point(pos[i]).map(|h| h.point));
    let off =
        |v: u32| closest[v as usize].map_or(f64::INFINITY, |q| (q - pos[v as usize]).length());
    let moves: Vec<Option<DVec3>> = (0..pos.len() as u32)
        .map(|v| {
            let q = closest[v as usize]?;
            (off(v) <= max_move && pick(mesh, v, &off)).then_some(q)
        })
        .collect();
    let mut moved = 0;
    for (p, m) in mesh.positions_mut().iter_mut().zip(moves) {
        if let Some(q) = m {
            *p = q;
            moved += 1;
        }
    }
    moved
}

/// The share of its move each vertex of `mesh` (at `old`) makes towards `moves`. A face that
/// the moves would fold (turn its normal by more than 60°) halves the move of its vertex that
/// strays most from the face's mean move, up to three times, then undoes it: the fit must not
/// create self-intersections where the offset surface bridges a hole or a narrow gap. Undoing
/// the moves of all three vertices at once would leave a fit distance off the surface wherever
/// the plane fits' noise tilts a small face, and would cut acute corners.
///
/// A face whose straying vertex has no move (left) keeps its turn: at a sharp corner the right
/// surface turns that much, and blaming another vertex there cuts the corner. The fit's
/// intersection check after the pass is the guard of validity.
fn fold_limited_shares(
    mesh: &HalfedgeMesh,
    old: &[DVec3],
    moves: &[Option<DVec3>],
    reference: Option<&[Option<DVec3>]>,
) -> Vec<f64> {
    let mut share: Vec<f64> = moves
        .iter()
        .map(|m| if m.is_some() { 1.0 } else { 0.0 })
        .collect();
    for _ in 0..FOLD_ROUNDS {
        let apply = |i: usize| partial(old[i], moves[i], share[i]);
        let mut changed = false;
        // (Each face on its own: in parallel natively, collected in face order.)
        let rejected = crate::parallel::map(mesh.n_faces(), |f| {
            let vs = mesh.face_vertices(f as u32);
            if !vs.iter().any(|&v| share[v as usize] > 0.0) {
                return None;
            }
            let [a, b, c] = vs.map(|v| old[v as usize]);
            let [a2, b2, c2] = vs.map(|v| apply(v as usize));
            let (n0, n1) = ((b - a).cross(c - a), (b2 - a2).cross(c2 - a2));
            let n0 = reference.map_or(n0, |r| data_side(n0, vs.map(|v| r[v as usize])));
            if n0.dot(n1) <= 0.5 * n0.length() * n1.length() {
                // The vertex whose move strays most from the face's mean move: the one whose
                // (noisy or far) move tilts the face.
                let d = [a2 - a, b2 - b, c2 - c];
                let mean = (d[0] + d[1] + d[2]) / 3.0;
                let k = (0..3)
                    .max_by(|&i, &j| {
                        (d[i] - mean)
                            .length_squared()
                            .total_cmp(&(d[j] - mean).length_squared())
                    })
                    .unwrap_or(0);
                return Some(vs[k]);
            }
            None
        });
        let mut reject: Vec<u32> = rejected.into_iter().flatten().collect();
        reject.sort_unstable();
        reject.dedup();
        for v in reject {
            let s = &mut share[v as usize];
            if *s > 0.0 {
                *s = if *s > SMALLEST_SHARE { 0.5 * *s } else { 0.0 };
                changed = true;
            }
        }
        if !changed {
            break;
        }
    }
    share
}

/// The direction a face should face after the fit: the mean of its vertices' fitted data
/// normals (a corner without one counts the face's own direction `n0`). A face of a dimpled
/// settled surface may turn by more than the fold limit onto a smooth one; what must not turn is
/// the moved face against the data.
fn data_side(n0: DVec3, normals: [Option<DVec3>; 3]) -> DVec3 {
    let own = n0.normalize_or_zero();
    normals.iter().map(|m| m.unwrap_or(own)).sum()
}

/// `share` of the way from `p` to its move (exactly the move at 1; `p` without one).
fn partial(p: DVec3, to: Option<DVec3>, share: f64) -> DVec3 {
    match to {
        Some(q) if share == 1.0 => q,
        Some(q) if share > 0.0 => p + share * (q - p),
        _ => p,
    }
}

/// Rounds of the fold check in [`snap_to_target`]: a move is halved up to three times
/// (1 → 1/8), then undone, with rounds to spare for the undos' own folds.
const FOLD_ROUNDS: usize = 6;
/// The smallest share of a move kept; a fold at this share undoes the move.
const SMALLEST_SHARE: f64 = 0.2;

/// A vertex without a move of its own but with target points around it (`has_points`: a plane
/// nearly along its normal, a move too long) takes the mean move of its neighbours when at
/// least two thirds of them have one. Left where it was, it would stand a fit distance off the
/// surface among moved neighbours, their faces folded, and the fold check would then undo the
/// moves of a whole patch around it. One pass, from the computed moves only, so the result does
/// not depend on the vertex order.
fn fill_from_neighbours(
    mesh: &HalfedgeMesh,
    positions: &[DVec3],
    moves: Vec<Option<DVec3>>,
    has_points: impl Fn(DVec3) -> bool,
) -> Vec<Option<DVec3>> {
    (0..moves.len())
        .map(|i| {
            if moves[i].is_some() || !has_points(positions[i]) {
                return moves[i];
            }
            let (mut sum, mut with, mut all) = (DVec3::ZERO, 0usize, 0usize);
            for u in mesh.neighbors(i as u32) {
                all += 1;
                if let Some(q) = moves[u as usize] {
                    sum += q - positions[u as usize];
                    with += 1;
                }
            }
            (all > 0 && 3 * with >= 2 * all).then(|| positions[i] + sum / with as f64)
        })
        .collect()
}

/// Where `p` lies within `radius` of a crease line: the signed distance along `n` to the plane of
/// the crease's face on p's side (None inside when the normal runs nearly parallel to it).
fn crease_plane_offset(creases: &Creases, p: DVec3, n: DVec3, radius: f64) -> Option<Option<f64>> {
    let hit = creases.closest_edge_point(p, radius)?;
    let e = &creases.edges[hit.edge as usize];
    let d = p - hit.point;
    let m = e.normals[usize::from(d.dot(e.inward[1]) > d.dot(e.inward[0]))];
    let cos = m.dot(n);
    Some((cos.abs() >= 0.5).then(|| (hit.point - p).dot(m) / cos))
}

/// The move from `p` onto the surface fitted to the points near `p`, along the fitted plane's
/// normal (or along `n`, see [`SnapParams::moving_least_squares`]); None where the plane's normal
/// lies more than 60° from the vertex normal `n`.
///
/// Only the sheet of points nearest along the normal takes part: points more than half the
/// radius deeper than the shallowest one belong to the far side of a thin part (an ear, a
/// fin) and would pull the fit into the middle of it.
fn plane_move(grid: &PointGrid, p: DVec3, n: DVec3, params: &SnapParams) -> Option<(DVec3, DVec3)> {
    let mut nearest = Vec::with_capacity(params.max_points);
    grid.nearest_within_unordered(p, params.radius, params.max_points, &mut nearest);
    plane_move_of(
        nearest.iter().map(|&Near { point, .. }| point),
        p,
        n,
        params,
    )
}

/// [`plane_move`] from the points `near` p (those within the radius).
fn plane_move_of(
    points: impl Iterator<Item = DVec3>,
    p: DVec3,
    n: DVec3,
    params: &SnapParams,
) -> Option<(DVec3, DVec3)> {
    let h2 = (0.5 * params.radius).powi(2);
    let mut near: Vec<(DVec3, f64)> = Vec::with_capacity(params.max_points);
    let mut shallowest = f64::INFINITY;
    for q in points {
        let depth = (p - q).dot(n);
        shallowest = shallowest.min(depth);
        near.push((q, depth));
    }
    let keep = shallowest + 0.5 * params.radius;
    let (mut wsum, mut c, mut count) = (0.0, DVec3::ZERO, 0usize);
    for (q, depth) in &mut near {
        let w = if *depth <= keep {
            crate::fmath::exp(-(*q - p).length_squared() / h2)
        } else {
            0.0
        };
        *depth = w;
        if w > 0.0 {
            wsum += w;
            c += w * *q;
            count += 1;
        }
    }
    if count < params.min_points || wsum <= 0.0 {
        return None;
    }
    c /= wsum;
    let mut cov = DMat3::ZERO;
    for (q, w) in &near {
        let d = *q - c;
        cov += DMat3::from_cols(d * (w * d.x), d * (w * d.y), d * (w * d.z));
    }
    let m = smallest_eigenvector(cov, n)?;
    if m.dot(n).abs() < 0.5 {
        return None;
    }
    // The plane through the weighted centroid sits inside a curved patch by about h²/2R (the
    // weights' spread over twice the radius of curvature), which on thin curved parts is well
    // above the fit's noise. The height of a quadric fitted over the plane removes it.
    let lift = quadric_height(&near, c, m, p, params.min_points).unwrap_or(0.0);
    let cos = m.dot(n);
    let step = if params.moving_least_squares {
        ((c - p).dot(m) + lift) * m
    } else {
        ((c - p).dot(m) / cos + lift / cos) * n
    };
    Some((step, if cos < 0.0 { -m } else { m }))
}

/// Height over the plane (centroid `c`, normal `m`) of the weighted quadric
/// `z = a + b·u + c·v + d·u² + e·u·v + f·v²` fitted to `near` (points and weights), at the foot
/// of `p`; None when the points do not determine it (fewer than `min_points`, or all on a line).
fn quadric_height(
    near: &[(DVec3, f64)],
    c: DVec3,
    m: DVec3,
    p: DVec3,
    min_points: usize,
) -> Option<f64> {
    let t1 = m.any_orthonormal_vector();
    let t2 = m.cross(t1);
    let basis = |d: DVec3| {
        let (u, v) = (d.dot(t1), d.dot(t2));
        nalgebra::Vector6::new(1.0, u, v, u * u, u * v, v * v)
    };
    // The normal equations' upper triangle (21 sums) and right-hand side, accumulated by hand:
    // this runs for every vertex over up to `max_points` points.
    let (mut upper, mut atz) = ([0.0; 21], nalgebra::Vector6::zeros());
    let mut count = 0;
    for &(q, w) in near {
        if w > 0.0 {
            let d = q - c;
            let b = basis(d);
            let mut k = 0;
            for i in 0..6 {
                let wb = w * b[i];
                for j in i..6 {
                    upper[k] += wb * b[j];
                    k += 1;
                }
            }
            atz += (w * d.dot(m)) * b;
            count += 1;
        }
    }
    if count < min_points.max(6) {
        return None;
    }
    let mut ata = nalgebra::Matrix6::<f64>::zeros();
    let mut k = 0;
    for i in 0..6 {
        for j in i..6 {
            ata[(i, j)] = upper[k];
            ata[(j, i)] = upper[k];
            k += 1;
        }
    }
    // Points (nearly) on a line leave the system singular: no lift. A lift is bounded by the
    // patch's RMS tangent radius (at the rim of a scan the quadric is extrapolated; limiting
    // it further by how far p's foot lies from the centroid would not help there and would
    // lose much of the gain elsewhere).
    let coef = ata.cholesky()?.solve(&atz);
    let spread = (ata[(0, 3)] + ata[(0, 5)]) / ata[(0, 0)];
    let h = basis(p - c).dot(&coef);
    (h.is_finite() && h * h < spread).then_some(h)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::icosphere::icosphere;

    /// With room for every point within the radius, the fit on the k nearest is the fit on all
    /// points within the radius found by scanning the whole cloud (up to summation order); with
    /// a small k on a dense cloud it stays within a small fraction of the radius.
    #[test]
    fn nearest_k_fit_matches_the_radius_fit_of_a_full_scan() {
        let mut rng = crate::demo::Rng::new(5);
        let pts: Vec<DVec3> = crate::geometry::sphere::fibonacci_sphere(3000)
            .into_iter()
            .map(|p| p * (1.0 + 0.01 * (rng.uniform() - 0.5)))
            .collect();
        let mut params = SnapParams {
            radius: 0.15,
            max_move: 0.5,
            min_points: 6,
            max_points: 100_000,
            moving_least_squares: true,
        };
        let grid = PointGrid::new(&pts, params.radius);
        let (mut compared, mut worst_small_k) = (0, 0.0f64);
        for i in 0..200 {
            let n = DVec3::new(rng.uniform(), rng.uniform(), rng.uniform()) - DVec3::splat(0.5);
            let n = n.normalize();
            let p = n * (1.05 + 0.02 * i as f64 / 200.0);
            let within = pts
                .iter()
                .copied()
                .filter(|q| (*q - p).length_squared() <= params.radius * params.radius);
            let full = plane_move_of(within, p, n, &params).map(|m| m.0);
            let knn = plane_move(&grid, p, n, &params).map(|m| m.0);
            match (full, knn) {
                (Some(a), Some(b)) => {
                    assert!((a - b).length() < 1e-12, "{a} vs {b}");
                    compared += 1;
                }
                (a, b) => assert_eq!(a.is_some(), b.is_some()),
            }
            let small = SnapParams {
                max_points: 32,
                ..params
            };
            if let (Some(a), Some((b, _))) = (full, plane_move(&grid, p, n, &small)) {
                worst_small_k = worst_small_k.max((a - b).length());
            }
        }
        assert!(compared > 150, "only {compared} fits");
        assert!(
            worst_small_k < 0.01,
            "k = 32 moves the fit by {worst_small_k}"
        );
        params.max_points = 6;
        assert!(plane_move(&grid, DVec3::X * 1.05, DVec3::X, &params).is_some());
    }

    /// On a patch as wide as a third of the radius of curvature the fitted plane sits inside the
    /// sphere by about h²/2R (h = half the fit radius: 0.011 here); the quadric's lift removes
    /// that, so every snapped point lands on the sphere to a few thousandths of it.
    #[test]
    fn the_quadric_lift_removes_the_curvature_bias() {
        let pts = crate::geometry::sphere::fibonacci_sphere(20_000);
        let params = SnapParams {
            radius: 0.3,
            max_move: 0.5,
            min_points: 6,
            max_points: 100_000,
            moving_least_squares: true,
        };
        let grid = PointGrid::new(&pts, params.radius);
        let bias = (0.5 * params.radius).powi(2) / 2.0;
        let mut worst = 0.0f64;
        for p in crate::geometry::sphere::fibonacci_sphere(200) {
            let (t, _) = plane_move(&grid, 1.1 * p, p, &params).unwrap();
            worst = worst.max(((1.1 * p + t).length() - 1.0).abs());
        }
        assert!(
            worst < 0.05 * bias,
            "worst radial error {worst} (plane bias {bias})"
        );
    }

    #[test]
    fn offset_sphere_snaps_onto_sampled_sphere() {
        // Points on the unit sphere; the mesh is the sphere of radius 1.05.
        let pts = crate::geometry::sphere::fibonacci_sphere(20_000);
        let grid = PointGrid::new(&pts, 0.1);
        let mut mesh = icosphere(4, 1.05, DVec3::ZERO).unwrap();
        let normals: Vec<DVec3> = mesh.positions().iter().map(|p| p.normalize()).collect();
        let params = SnapParams {
            radius: 0.1,
            max_move: 0.2,
            min_points: 6,
            max_points: 64,
            moving_least_squares: true,
        };
        let mut heard = Vec::new();
        let moved = snap_to_target(
            &mut mesh,
            &normals,
            &SnapTarget::Points(grid.into()),
            &params,
            None,
            &mut |f| heard.push(f),
        );
        assert!(heard.windows(2).all(|w| w[0] < w[1]) && heard.last() == Some(&1.0));
        assert_eq!(moved, mesh.n_vertices());
        let worst = mesh
            .positions()
            .iter()
            .map(|p| (p.length() - 1.0).abs())
            .fold(0.0, f64::max);
        assert!(worst < 2e-3, "worst radial error {worst}");
        // Vertices whose own normal is useless (tangent: the plane runs along it) take their
        // neighbours' move and land on the sphere too; the fold check keeps them.
        let mut mesh = icosphere(4, 1.05, DVec3::ZERO).unwrap();
        let mut normals: Vec<DVec3> = mesh.positions().iter().map(|p| p.normalize()).collect();
        let spoiled: Vec<usize> = (0..normals.len()).step_by(37).collect();
        for &v in &spoiled {
            normals[v] = normals[v].any_orthonormal_vector();
        }
        let moved = snap_to_target(
            &mut mesh,
            &normals,
            &SnapTarget::Points(PointGrid::new(&pts, 0.1).into()),
            &params,
            None,
            &mut |_| {},
        );
        assert_eq!(moved, mesh.n_vertices());
        for &v in &spoiled {
            let r = mesh.position(v as u32).length();
            assert!((r - 1.0).abs() < 2e-3, "vertex {v} at radius {r}");
        }
        // A move longer than the limit is refused (and there are no points to fill from).
        let mut far = icosphere(2, 1.5, DVec3::ZERO).unwrap();
        let normals: Vec<DVec3> = far.positions().iter().map(|p| p.normalize()).collect();
        let params = SnapParams {
            radius: 0.1,
            max_move: 0.2,
            min_points: 6,
            max_points: 64,
            moving_least_squares: true,
        };
        assert_eq!(
            snap_to_target(
                &mut far,
                &normals,
                &SnapTarget::Points(PointGrid::new(&pts, 0.1).into()),
                &params,
                None,
                &mut |_| {}
            ),
            0
        );
    }

    /// An n × n grid of spacing 0.1 in x and y, vertex k at height `z(k)`, triangulated facing +z.
    fn sheet(n: usize, z: impl Fn(usize) -> f64) -> (Vec<DVec3>, HalfedgeMesh) {
        let pts: Vec<DVec3> = (0..n * n)
            .map(|k| DVec3::new(0.1 * (k % n) as f64, 0.1 * (k / n) as f64, z(k)))
            .collect();
        let mut faces = Vec::new();
        for j in 0..n as u32 - 1 {
            for i in 0..n as u32 - 1 {
                let a = j * n as u32 + i;
                faces.push([a, a + 1, a + n as u32 + 1]);
                faces.push([a, a + n as u32 + 1, a + n as u32]);
            }
        }
        let mesh = HalfedgeMesh::from_triangles(pts.clone(), &faces).unwrap();
        (pts, mesh)
    }

    #[test]
    fn a_folding_move_is_cut_down_not_dropped() {
        // A flat 5 × 5 grid of spacing 0.1 at z = 0.1; every vertex moves down to z = 0, the
        // centre one to −0.2 (some of its faces would turn by 70°, with half the move by 35°).
        let n = 5;
        let centre = n * n / 2;
        let (pts, mesh) = sheet(n, |_| 0.1);
        let mut moves: Vec<Option<DVec3>> = pts.iter().map(|p| Some(p.with_z(0.0))).collect();
        moves[centre] = Some(pts[centre].with_z(-0.2));
        let share = fold_limited_shares(&mesh, &pts, &moves, None);
        assert_eq!(share[centre], 0.5);
        assert!(
            (0..n * n).all(|v| v == centre || share[v] == 1.0),
            "{share:?}"
        );
        assert!((partial(pts[centre], moves[centre], 0.5).z + 0.05).abs() < 1e-15);
        // A move that folds even at an eighth is dropped, and only its own.
        moves[centre] = Some(pts[centre].with_z(-5.0));
        let share = fold_limited_shares(&mesh, &pts, &moves, None);
        assert_eq!(share[centre], 0.0);
        assert!(
            (0..n * n).all(|v| v == centre || share[v] == 1.0),
            "{share:?}"
        );
    }

    /// A dimple's faces turn by more than the fold limit when the fit flattens it: checked
    /// against the old faces the flattening is cut down; held to the data's normals it is made.
    #[test]
    fn a_dimple_flattened_onto_the_data_is_not_a_fold() {
        let n = 5;
        let centre = n * n / 2;
        let (pts, mesh) = sheet(n, |k| if k == centre { 0.4 } else { 0.1 });
        let moves: Vec<Option<DVec3>> = pts.iter().map(|p| Some(p.with_z(0.0))).collect();
        let against_old = fold_limited_shares(&mesh, &pts, &moves, None);
        assert!(against_old[centre] < 1.0, "{against_old:?}");
        let up = vec![Some(DVec3::Z); n * n];
        let held = fold_limited_shares(&mesh, &pts, &moves, Some(&up));
        assert!(held.iter().all(|&s| s == 1.0), "{held:?}");
        // A move that turns a face against the data is still cut down.
        let mut folding = moves.clone();
        folding[centre] = Some(pts[centre].with_z(-0.3));
        let cut = fold_limited_shares(&mesh, &pts, &folding, Some(&up));
        assert!(cut[centre] < 1.0, "{cut:?}");
    }
}
