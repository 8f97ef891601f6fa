//! The hierarchy over an indexed triangle set: exact closest points (one at a time or in warm
//! started batches), segment crossings and the inside test.

use super::Bvh;
use crate::geometry::predicates::{segment_crosses_triangle, segment_meets_triangle};
use glam::DVec3;

/// The closest point on triangle `[a, b, c]` to `p` and its barycentric coordinates
/// `(u, v, w)` with `point = u·a + v·b + w·c` (see
/// [`crate::geometry::primitives::closest_point_barycentric`]).
pub fn closest_point_on_triangle(p: DVec3, a: DVec3, b: DVec3, c: DVec3) -> (DVec3, DVec3) {
    let (q, bary, _) = crate::geometry::primitives::closest_point_barycentric(p, a, b, c);
    (q, bary)
}

/// Result of a closest-point query on a triangle set.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ClosestHit {
    /// Index of the nearest triangle.
    pub triangle: u32,
    /// The closest point.
    pub point: DVec3,
    /// Its barycentric coordinates in that triangle.
    pub barycentric: DVec3,
    /// Squared distance from the query point.
    pub distance_squared: f64,
}

/// A BVH over an indexed triangle set (positions and triangles copied in).
#[derive(Clone, Debug, Default)]
pub struct TriangleBvh {
    bvh: Bvh,
    positions: Vec<DVec3>,
    triangles: Vec<[u32; 3]>,
}

impl TriangleBvh {
    /// Builds the hierarchy over `triangles` (indices into `positions`).
    pub fn new(positions: &[DVec3], triangles: &[[u32; 3]]) -> Self {
        let (mut mins, mut maxs) = (
            Vec::with_capacity(triangles.len()),
            Vec::with_capacity(triangles.len()),
        );
        for t in triangles {
            let [a, b, c] = t.map(|v| positions[v as usize]);
            mins.push(a.min(b).min(c));
            maxs.push(a.max(b).max(c));
        }
        Self {
            bvh: Bvh::new(&mins, &maxs),
            positions: positions.to_vec(),
            triangles: triangles.to_vec(),
        }
    }

    /// The triangles.
    pub fn triangles(&self) -> &[[u32; 3]] {
        &self.triangles
    }
    /// The positions.
    pub fn positions(&self) -> &[DVec3] {
        &self.positions
    }
    /// The underlying box hierarchy (for overlap queries).
    pub fn bvh(&self) -> &Bvh {
        &self.bvh
    }

    /// Exact closest point on the triangle set (`None` if it is empty).
    pub fn closest_point(&self, p: DVec3) -> Option<ClosestHit> {
        self.closest_point_within(p, f64::INFINITY)
    }

    /// [`Self::closest_point`] among the triangles within `max_distance` of `p` (`None` when
    /// there is none): a query far from everything ends at once.
    pub fn closest_point_within(&self, p: DVec3, max_distance: f64) -> Option<ClosestHit> {
        let (t, d2) = self
            .bvh
            .nearest_within(p, max_distance * max_distance, |i| {
                let [a, b, c] = self.triangles[i as usize].map(|v| self.positions[v as usize]);
                (closest_point_on_triangle(p, a, b, c).0 - p).length_squared()
            })?;
        let [a, b, c] = self.triangles[t as usize].map(|v| self.positions[v as usize]);
        let (point, barycentric) = closest_point_on_triangle(p, a, b, c);
        Some(ClosestHit {
            triangle: t,
            point,
            barycentric,
            distance_squared: d2,
        })
    }

    /// [`Self::closest_point_within`] for the points `point(0..n)`, in index order. Each run of
    /// [`WARM_RUN`] consecutive points bounds a point's search by its distance to the previous
    /// point's triangle: where neighbouring points lie near each other (a mesh's vertices in file
    /// order) that prunes most of the tree before the search starts. The hits are those of one
    /// query each: the bound only skips triangles farther than one already in reach.
    pub fn closest_points_within(
        &self,
        n: usize,
        point: impl Fn(usize) -> DVec3 + Sync + Send,
        max_distance: f64,
    ) -> Vec<Option<ClosestHit>> {
        let runs = crate::parallel::map(n.div_ceil(WARM_RUN), |k| {
            let mut last: Option<u32> = None;
            (k * WARM_RUN..(n.min((k + 1) * WARM_RUN)))
                .map(|i| {
                    let p = point(i);
                    let bound = last.map_or(max_distance, |t| {
                        let [a, b, c] = self.corners(t);
                        (closest_point_on_triangle(p, a, b, c).0 - p)
                            .length()
                            .min(max_distance)
                    });
                    let hit = self.closest_point_within(p, bound);
                    last = hit.as_ref().map(|h| h.triangle);
                    hit
                })
                .collect::<Vec<_>>()
        });
        runs.into_iter().flatten().collect()
    }

    /// Exact distance to the triangle set (∞ if it is empty).
    pub fn distance(&self, p: DVec3) -> f64 {
        self.closest_point(p)
            .map_or(f64::INFINITY, |h| h.distance_squared.sqrt())
    }

    /// True when segment `[a, b]` passes through a triangle from one side to the other (see
    /// [`segment_crosses_triangle`]: touching is no crossing). Exact.
    pub fn crosses(&self, a: DVec3, b: DVec3) -> bool {
        let mut crossed = false;
        self.bvh.for_each_overlap(a.min(b), a.max(b), |f| {
            crossed = crossed || segment_crosses_triangle(a, b, self.corners(f));
        });
        crossed
    }

    /// True when `m` lies inside the triangles, taken as a closed surface: a ray from it crosses
    /// them an odd number of times, or its winding number (crossings outwards less crossings
    /// inwards) is not zero — where two parts of a self-intersecting surface overlap, the ray
    /// leaves both and the parity is even. The ray runs nearly along the axis to the nearest side of
    /// the box, so that its box is thin and the query cheap; slightly off the axis, so that it
    /// does not run along the edges of a grid-aligned mesh. (Meaningless for an open mesh; a
    /// ray through an edge or vertex counts it twice, rare off the axes.)
    pub fn encloses(&self, m: DVec3) -> bool {
        let (lo, hi) = self.bvh.bounds();
        let gaps = [
            m.x - lo.x,
            hi.x - m.x,
            m.y - lo.y,
            hi.y - m.y,
            m.z - lo.z,
            hi.z - m.z,
        ];
        let side = (0..6).fold(0, |b, i| if gaps[i] < gaps[b] { i } else { b });
        let mut dir = DVec3::from_array(RAY_SKEW);
        dir[side / 2] = if side % 2 == 0 { -1.0 } else { 1.0 };
        let end = m + dir * (gaps[side].max(0.0) + (hi - lo).max_element());
        let (mut crossings, mut winding) = (0usize, 0i64);
        self.bvh.for_each_overlap(m.min(end), m.max(end), |f| {
            let [a, b, c] = self.corners(f);
            if segment_meets_triangle(m, end, [a, b, c]) {
                crossings += 1;
                winding += if (b - a).cross(c - a).dot(dir) > 0.0 {
                    1
                } else {
                    -1
                };
            }
        });
        crossings % 2 == 1 || winding != 0
    }

    fn corners(&self, f: u32) -> [DVec3; 3] {
        self.triangles[f as usize].map(|v| self.positions[v as usize])
    }
}

/// How many consecutive points of [`TriangleBvh::closest_points_within`] share one warm start
/// (the runs are spread over the threads).
const WARM_RUN: usize = 32;

/// The ray's tilt off its axis in [`TriangleBvh::encloses`] (irrational-looking, small).
const RAY_SKEW: [f64; 3] = [
    1.3e-3 * std::f64::consts::SQRT_2,
    1.1e-3 * std::f64::consts::E,
    0.9e-3 * std::f64::consts::PI,
];
