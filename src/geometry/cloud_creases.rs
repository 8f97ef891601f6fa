//! Sharp creases and corners of a point-cloud target, found from local plane fits (a cloud
//! carries no normals), so that the final fit snaps a scanned CAD part's edges and corners as it
//! does a mesh's ([`super::creases`]).
//!
//! Every tested point gets the weighted-PCA normal of its neighbourhood and its surface
//! variation λ₁/(λ₁+λ₂+λ₃) (0 on a plane). A point whose neighbourhood is not flat may lie near a
//! crease. Its *flat* neighbours within [`GATHER`] radii — those about a radius or more from
//! any crease — fall into groups of nearly equal normals: one group is a smooth surface, two a
//! crease (the line where the two planes meet), three a corner (the point where they meet).
//! A smooth but tightly curved surface has varying normals too, but they vary continuously: a
//! group wider than [`GROUP_SPREAD`] of the crease angle, or flat neighbours off their group's
//! plane, reject the point.
//!
//! A cloud has no orientation, so normals are compared as lines (a crease's two planes meet at
//! the same angle seen from either side); a crease's turn comes from the angle between its two
//! half-planes. Which side is solid is guessed from the cloud's centroid, so
//! [`Crease::convex`] (and the sign of [`Crease::normals`]) can be wrong on concave parts; the
//! fit uses only the lines and corners.

use super::creases::{Crease, Creases};
use super::eigen3::smallest_eigenvector;
use super::spatial::point_grid::{Near, PointGrid};
use crate::mesh::disjoint::DisjointSets;
use glam::{DMat3, DVec3};

/// Points per neighbourhood of the plane fits.
const NEIGHBOURS: usize = 32;
/// Most points tested (every k-th point of a denser cloud): bounds the cost on dense scans.
const MAX_TESTED: usize = 50_000;
/// Surface variation above which a point may lie near a crease (a 40° crease through the
/// middle of a disk gives about 0.016; noise of 3 % of the radius about 0.002).
pub const CANDIDATE_VARIATION: f64 = 0.004;
/// Surface variation below which a neighbourhood counts as flat.
const FLAT_VARIATION: f64 = 0.002;
/// Largest angle between a group's normals and their mean, as a fraction of the crease angle.
const GROUP_SPREAD: f64 = 0.25;
/// Largest distance of a flat neighbour from its group's plane, as a fraction of the radius.
const PLANE_TOLERANCE: f64 = 0.05;
/// How far (in radii) a near-crease point looks for flat neighbours: flat points lie a radius
/// or more from any crease, and near a corner each of its three faces must show a few.
const GATHER: f64 = 3.0;
/// Shortest crease line kept, in radii (see [`long_lines`]).
const MIN_LINE: f64 = 4.0;
/// Fewest flat neighbours per group.
const MIN_GROUP: usize = 6;

/// The creases (turning by more than `min_turn` radians) and corners of the surface the cloud
/// `points` samples, seen at the scale `radius` (a few point spacings or more: the plane fits
/// use the points within it). `grid` buckets `points` for queries of that radius (the final
/// fit's own, [`crate::flow::snap::SnapTarget::Points`], so it is built once).
pub fn detect_cloud_creases(
    points: &[DVec3],
    grid: &PointGrid,
    radius: f64,
    min_turn: f64,
    done: &mut dyn FnMut(f64),
) -> Creases {
    if points.len() < 4 * NEIGHBOURS || !(radius > 0.0 && radius.is_finite()) {
        done(1.0);
        return Creases::new(vec![], vec![]);
    }
    let stride = points.len().div_ceil(MAX_TESTED);
    let tested: Vec<DVec3> = points.iter().step_by(stride).copied().collect();
    let centroid = points.iter().fold(DVec3::ZERO, |a, &p| a + p) / points.len() as f64;
    // 1. The normal (either sign) and surface variation of every tested point.
    let n = tested.len();
    // (Asked in cell order, then put back: the same fits.)
    let order = grid.query_order(&tested);
    let by_cell: Vec<Option<(DVec3, f64)>> = crate::parallel::map_chunked(
        n,
        PROGRESS_CHUNK,
        |j| {
            let mut near = Vec::with_capacity(NEIGHBOURS);
            let p = tested[order[j] as usize];
            grid.nearest_within_unordered(p, radius, NEIGHBOURS, &mut near);
            plane_fit(near.iter().map(|q| q.point))
        },
        &mut |k| done(0.5 * k as f64 / n as f64),
    );
    let mut fits = vec![None; n];
    for (&i, fit) in order.iter().zip(by_cell) {
        fits[i as usize] = fit;
    }
    // 2. Near-crease points: groups of their flat neighbours' normals.
    let flat_grid = PointGrid::new(&tested, GATHER * radius);
    let found: Vec<Option<Feature>> = crate::parallel::map_chunked(
        n,
        PROGRESS_CHUNK,
        |i| {
            let (_, variation) = fits[i]?;
            if variation <= CANDIDATE_VARIATION {
                return None;
            }
            let mut near = Vec::with_capacity(8 * NEIGHBOURS);
            flat_grid.nearest_within_unordered(
                tested[i],
                GATHER * radius,
                8 * NEIGHBOURS,
                &mut near,
            );
            let flat: Vec<(DVec3, DVec3)> = near
                .iter()
                .filter_map(|&Near { index, point, .. }| {
                    let (m, v) = fits[index as usize]?;
                    (v < FLAT_VARIATION).then_some((point, m))
                })
                .collect();
            let groups = group_normals(&flat, min_turn, radius)?;
            feature_of(tested[i], &groups, radius, centroid)
        },
        &mut |k| done(0.5 + 0.5 * k as f64 / n as f64),
    );
    // 3. Crease pieces on lines long enough; corners merged (every point near one finds it).
    let mut pieces = Vec::new();
    let mut edges = Vec::new();
    let mut corners: Vec<(DVec3, usize)> = Vec::new();
    for f in found.into_iter().flatten() {
        match f {
            Feature::Crease(c) => pieces.push(c),
            Feature::Corner(x, lines) => {
                match corners
                    .iter_mut()
                    .find(|(c, k)| (*c / *k as f64 - x).length() < radius)
                {
                    Some((sum, k)) => {
                        *sum += x;
                        *k += 1;
                    }
                    None => {
                        corners.push((x, 1));
                        edges.extend(lines);
                    }
                }
            }
        }
    }
    let corners: Vec<DVec3> = corners.iter().map(|&(sum, k)| sum / k as f64).collect();
    edges.extend(long_lines(pieces, radius, min_turn));
    done(1.0);
    Creases::new(edges, corners)
}

/// Tested points per progress report (each chunk is spread over the threads).
const PROGRESS_CHUNK: usize = 8192;

/// The crease pieces that belong to lines at least [`MIN_LINE`] radii long: a piece joins the
/// pieces within a radius that run along its line. A scan's noise or a small sharp bump gives a
/// few pieces in one spot; a machined edge gives a line of them.
fn long_lines(pieces: Vec<Crease>, radius: f64, min_turn: f64) -> Vec<Crease> {
    let mid = |c: &Crease| 0.5 * (c.ends[0] + c.ends[1]);
    let dir = |c: &Crease| (c.ends[1] - c.ends[0]).normalize_or_zero();
    let mids: Vec<DVec3> = pieces.iter().map(mid).collect();
    let grid = PointGrid::new(&mids, radius);
    let mut lines = DisjointSets::new(pieces.len());
    let parallel = crate::fmath::cos(GROUP_SPREAD * min_turn);
    let mut near = Vec::new();
    for (i, c) in pieces.iter().enumerate() {
        let d = dir(c);
        grid.nearest_within_unordered(mids[i], radius, 64, &mut near);
        for &Near { index, point, .. } in &near {
            let j = index as usize;
            let off = point - mids[i];
            let on_line = (off - off.dot(d) * d).length() < 0.25 * radius;
            if j > i && on_line && dir(&pieces[j]).dot(d).abs() > parallel {
                lines.union(i as u32, j as u32);
            }
        }
    }
    // Each line's extent along its first piece's direction.
    let mut extent: std::collections::BTreeMap<usize, (DVec3, f64, f64)> = Default::default();
    for (i, m) in mids.iter().enumerate() {
        let r = lines.find(i as u32) as usize;
        let e = extent
            .entry(r)
            .or_insert((dir(&pieces[r]), f64::INFINITY, f64::NEG_INFINITY));
        let t = m.dot(e.0);
        (e.1, e.2) = (e.1.min(t), e.2.max(t));
    }
    let long = |i: usize, lines: &mut DisjointSets| {
        let (_, lo, hi) = extent[&(lines.find(i as u32) as usize)];
        hi - lo + radius >= MIN_LINE * radius
    };
    (0..pieces.len())
        .filter(|&i| long(i, &mut lines))
        .map(|i| pieces[i])
        .collect()
}

/// What one near-crease point found: a piece of a crease line, or a corner with the three
/// lines leaving it.
enum Feature {
    Crease(Crease),
    Corner(DVec3, Vec<Crease>),
}

/// A group of flat neighbours with nearly one normal: its plane `n·x = offset` and centroid.
#[derive(Clone, Copy)]
struct Group {
    normal: DVec3,
    offset: f64,
    centroid: DVec3,
}

/// The unit normal and surface variation of the PCA plane through `points`; None when they do
/// not determine one.
pub fn plane_fit(points: impl Iterator<Item = DVec3> + Clone) -> Option<(DVec3, f64)> {
    let (mut c, mut k) = (DVec3::ZERO, 0usize);
    for q in points.clone() {
        c += q;
        k += 1;
    }
    if k < 6 {
        return None;
    }
    c /= k as f64;
    let mut cov = DMat3::ZERO;
    for q in points {
        let d = q - c;
        cov += DMat3::from_cols(d * d.x, d * d.y, d * d.z);
    }
    // The adjugate's longest column lies along the smallest axis: a guess never orthogonal to it.
    let [c0, c1, c2] = [cov.x_axis, cov.y_axis, cov.z_axis];
    let guess = [c1.cross(c2), c2.cross(c0), c0.cross(c1)]
        .into_iter()
        .max_by(|a, b| a.length_squared().total_cmp(&b.length_squared()))?;
    let n = smallest_eigenvector(cov, guess)?;
    let trace = cov.x_axis.x + cov.y_axis.y + cov.z_axis.z;
    (trace > 0.0).then(|| (n, n.dot(cov * n) / trace))
}

/// `n` turned to agree with `reference`.
fn orient(n: DVec3, reference: DVec3) -> DVec3 {
    if n.dot(reference) < 0.0 {
        -n
    } else {
        n
    }
}

/// The flat neighbours' normals in groups at least `min_turn` apart (one to three groups); None
/// when they do not split cleanly (too few, a group too wide or off its plane: a curved surface).
fn group_normals(flat: &[(DVec3, DVec3)], min_turn: f64, radius: f64) -> Option<Vec<Group>> {
    if flat.len() < MIN_GROUP {
        return None;
    }
    // Normals as lines: the angle between them is at most 90°.
    let angle = |a: DVec3, b: DVec3| crate::fmath::acos(a.dot(b).abs());
    // Seeds by farthest point: the normal farthest from the mean, then from every seed.
    let mean = flat
        .iter()
        .fold(DVec3::ZERO, |a, f| a + orient(f.1, flat[0].1))
        .normalize_or_zero();
    // (Each normal's angle computed once, not twice per comparison: `acos` is most of this
    // function's cost.)
    let farthest = |key: &dyn Fn(DVec3) -> f64| {
        flat.iter()
            .map(|f| (key(f.1), f.1))
            .max_by(|a, b| a.0.total_cmp(&b.0))
    };
    let (_, first) = farthest(&|n| angle(n, mean))?;
    let mut seeds = vec![first];
    loop {
        let gap = |n: DVec3| {
            seeds
                .iter()
                .map(|&s| angle(n, s))
                .fold(f64::INFINITY, f64::min)
        };
        let (far_gap, far) = farthest(&gap)?;
        if far_gap <= min_turn {
            break;
        }
        if seeds.len() == 3 {
            return None;
        }
        seeds.push(far);
    }
    let nearest = |n: DVec3| {
        (0..seeds.len())
            .max_by(|&a, &b| n.dot(seeds[a]).abs().total_cmp(&n.dot(seeds[b]).abs()))
            .unwrap_or(0)
    };
    let mut groups = Vec::with_capacity(seeds.len());
    for (g, &seed) in seeds.iter().enumerate() {
        let members: Vec<(DVec3, DVec3)> =
            flat.iter().copied().filter(|f| nearest(f.1) == g).collect();
        if members.len() < MIN_GROUP {
            return None;
        }
        let normal = members
            .iter()
            .fold(DVec3::ZERO, |a, f| a + orient(f.1, seed))
            .normalize_or_zero();
        let spread = members
            .iter()
            .map(|f| angle(f.1, normal))
            .fold(0.0, f64::max);
        if spread > GROUP_SPREAD * min_turn {
            return None;
        }
        let k = members.len() as f64;
        let centroid = members.iter().fold(DVec3::ZERO, |a, f| a + f.0) / k;
        // The plane through the members' positions: their normals lean a little towards a
        // crease just beyond their own neighbourhoods, their positions do not.
        let normal =
            plane_fit(members.iter().map(|f| f.0)).map_or(normal, |(m, _)| orient(m, normal));
        let offset = normal.dot(centroid);
        let off_plane = members
            .iter()
            .map(|f| (normal.dot(f.0) - offset).abs())
            .fold(0.0, f64::max);
        if off_plane > PLANE_TOLERANCE * radius {
            return None;
        }
        groups.push(Group {
            normal,
            offset,
            centroid,
        });
    }
    for (i, a) in groups.iter().enumerate() {
        if groups[i + 1..]
            .iter()
            .any(|b| angle(a.normal, b.normal) <= min_turn)
        {
            return None;
        }
    }
    Some(groups)
}

/// The crease piece (two groups) or corner (three) that `p` lies near; None for one group or
/// when the planes meet farther than the radius ([`GATHER`] radii for a corner) from `p`.
fn feature_of(p: DVec3, groups: &[Group], radius: f64, centroid: DVec3) -> Option<Feature> {
    match groups {
        [a, b] => {
            let d = a.normal.cross(b.normal).normalize_or_zero();
            let q = meet([a.normal, b.normal, d], [a.offset, b.offset, d.dot(p)])?;
            let half = 0.5 * radius;
            ((q - p).length() <= radius)
                .then(|| Feature::Crease(crease(q - half * d, q + half * d, a, b, centroid)))
        }
        [a, b, c] => {
            let x = meet(
                [a.normal, b.normal, c.normal],
                [a.offset, b.offset, c.offset],
            )?;
            if (x - p).length() > GATHER * radius {
                return None;
            }
            // Each pair's line leaves the corner towards the pair's points.
            let lines = [(a, b), (b, c), (c, a)]
                .iter()
                .map(|&(g, h)| {
                    let d = g.normal.cross(h.normal).normalize_or_zero();
                    let d = orient(d, 0.5 * (g.centroid + h.centroid) - x);
                    crease(x, x + GATHER * radius * d, g, h, centroid)
                })
                .collect();
            Some(Feature::Corner(x, lines))
        }
        _ => None,
    }
}

/// The point where three planes `rows·x = rhs` meet; None when they are nearly parallel.
fn meet(rows: [DVec3; 3], rhs: [f64; 3]) -> Option<DVec3> {
    let m = DMat3::from_cols(rows[0], rows[1], rows[2]).transpose();
    let det = m.determinant();
    (det.abs() > 1e-6).then(|| m.inverse() * DVec3::from_array(rhs))
}

/// The crease from `s` to `e` between the planes of groups `a` and `b`; solid on the side of
/// the smaller angle between the half-planes where that side faces away from `centroid`.
fn crease(s: DVec3, e: DVec3, a: &Group, b: &Group, centroid: DVec3) -> Crease {
    let dir = (e - s).normalize_or_zero();
    let side = |g: &Group| {
        let v = g.centroid - s;
        let v = v - v.dot(dir) * dir;
        (v.normalize_or_zero(), v.length())
    };
    let ((ia, ha), (ib, hb)) = (side(a), side(b));
    // The half-planes open by φ; the surface turns by π − φ either way.
    let opening = crate::fmath::acos(ia.dot(ib));
    let convex = (s - centroid).dot(ia + ib) < 0.0;
    // Outward normals: away from the other half-plane on a ridge, towards it in a valley.
    let out = |n: DVec3, other: DVec3| orient(n, if convex { -other } else { other });
    Crease {
        ends: [s, e],
        normals: [out(a.normal, ib), out(b.normal, ia)],
        inward: [ia, ib],
        heights: [2.0 * ha, 2.0 * hb],
        turn: std::f64::consts::PI - opening,
        convex,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::demo::sample_mesh;
    use crate::demo::shapes::generate;

    fn cube_cloud(n: usize) -> Vec<DVec3> {
        let (p, t) = generate("cube").unwrap();
        sample_mesh(&p, &t, n, 5).unwrap()
    }

    /// Distance from `x` to the nearest edge of the unit cube centred at the origin.
    fn cube_edge_distance(x: DVec3) -> f64 {
        let a = x.abs() - DVec3::splat(0.5);
        // Nearest edge: the two coordinates nearest to ±0.5 at ±0.5, the third clamped.
        let mut d = [a.x.abs(), a.y.abs(), a.z.abs()];
        d.sort_by(f64::total_cmp);
        (d[0] * d[0] + d[1] * d[1]).sqrt()
    }

    /// A cube's cloud: crease pieces on its 12 edges only (none on a face), covering every edge,
    /// 90° turns, and its 8 corners.
    #[test]
    fn finds_the_edges_and_corners_of_a_cube_cloud() {
        let pts = cube_cloud(20_000);
        let radius = 0.05;
        let mut fractions = Vec::new();
        let c = detect_cloud_creases(
            &pts,
            &PointGrid::new(&pts, radius),
            radius,
            40f64.to_radians(),
            &mut |f| fractions.push(f),
        );
        // Progress: rising, in (0, 1], ending at 1, more than once.
        assert!(fractions.len() > 2, "{fractions:?}");
        assert!(fractions.windows(2).all(|w| w[0] <= w[1]), "{fractions:?}");
        assert!(
            fractions[0] > 0.0 && fractions.last() == Some(&1.0),
            "{fractions:?}"
        );
        assert!(c.edges.len() > 50, "{} crease pieces", c.edges.len());
        for e in &c.edges {
            for end in e.ends {
                assert!(cube_edge_distance(end) < 1e-6, "off an edge: {end}");
            }
            assert!(
                (e.turn.to_degrees() - 90.0).abs() < 1.0,
                "turn {}",
                e.turn.to_degrees()
            );
            assert!(e.convex, "{e:?}");
        }
        // Every edge is covered, except within twice the radius of its corners... and there the
        // corners' own lines reach.
        for k in 0..200 {
            let t = -0.5 + k as f64 / 199.0;
            for q in [
                DVec3::new(t, 0.5, 0.5),
                DVec3::new(-0.5, t, -0.5),
                DVec3::new(0.5, -0.5, t),
            ] {
                let hit = c.closest_edge_point(q, radius);
                assert!(hit.is_some(), "no crease near {q}");
            }
        }
        assert_eq!(c.corners.len(), 8, "corners {:?}", c.corners);
        for x in &c.corners {
            assert!((x.abs() - DVec3::splat(0.5)).length() < 1e-6, "corner {x}");
        }
    }

    /// Smooth surfaces give no creases: a sphere much larger than the radius, and a thin torus
    /// tube (radius of curvature 2.5 neighbourhood radii: the normals turn a lot, continuously).
    #[test]
    fn smooth_clouds_have_none() {
        let sphere = crate::geometry::sphere::fibonacci_sphere(20_000);
        assert!(detect_cloud_creases(
            &sphere,
            &PointGrid::new(&sphere, 0.05),
            0.05,
            40f64.to_radians(),
            &mut |_| {}
        )
        .is_empty());
        let (p, t) = generate("torus-g1").unwrap();
        let torus = sample_mesh(&p, &t, 20_000, 3).unwrap();
        let c = detect_cloud_creases(
            &torus,
            &PointGrid::new(&torus, 0.05),
            0.05,
            40f64.to_radians(),
            &mut |_| {},
        );
        assert!(c.is_empty(), "{} crease pieces on a torus", c.edges.len());
    }
}
