//! Final fit on mesh targets: reaching into the concavities that the fit bridged.
//!
//! The fit moves each vertex along its normal towards its closest target point. A vertex on a
//! surface that spans a slit narrower than a grid cell (a mouth, the gap under a cupped ear) has
//! its closest point on the slit's lip, so no pass of that fit ever enters the slit, however
//! fine the edges there: the target's samples inside stay missed, and they are the Hausdorff
//! distance. Here the miss is answered from the target's side: the wrap vertex nearest to a
//! missed sample moves onto that sample, when the way there is clear of the target (a sample
//! inside the target's material, under another part, stays missed). The pass's remesh then
//! splits the long edges of that dent and the next pass's moves put the new vertices on the
//! slit's walls.

use crate::flow::snap::move_onto_closest;
use crate::geometry::spatial::bvh::TriangleBvh;
use crate::mesh::HalfedgeMesh;
use glam::DVec3;

/// Moves wrap vertices onto target samples the wrap misses by more than `tol`; returns how many
/// moved.
///
/// `samples` are the target's points (a mesh's vertices), `misses` the indices to try (the
/// previous pass's misses; of many, a share spread over the wrap). Each missed sample under the
/// wrap proposes a move of the nearest
/// vertex of the wrap face nearest to it, no longer than `max_move` and along a segment that
/// does not run through the target's material (nor, on a `closed` target, inside it) — or, when
/// that way is blocked, of the nearest vertex two rings around whose way is clear; each vertex
/// takes its farthest proposal (the deepest point of the concavity, so that the dent's sides lie
/// along the walls), and its other neighbours follow by [`DENT_SHARE`] of it where their way is
/// as clear.
/// The moves are not checked for self-intersections here: the fit's contact guard does that.
pub fn reach_into_misses(
    mesh: &mut HalfedgeMesh,
    target: &TriangleBvh,
    samples: &[DVec3],
    misses: &[u32],
    tol: f64,
    max_move: f64,
    closed: bool,
) -> usize {
    if misses.is_empty() {
        return 0;
    }
    mesh.garbage_collect();
    let tris = mesh.triangles();
    let positions = mesh.positions();
    let ways = Ways {
        target,
        samples,
        positions,
        max_move,
        floor: MOVE_FLOOR * max_move,
        closed,
    };
    let mut tries = misses_under(&tris, positions, samples, misses, tol);
    // At most [`TRIES_PER_VERTEX`] per wrap vertex: a folded target misses a great many samples
    // in narrow gaps whose ways are nearly all blocked, and testing them all would dominate the
    // pass.
    let most = TRIES_PER_VERTEX * positions.len();
    if tries.len() > most {
        tries = spread_over_wrap(tries, most);
    }
    let proposals: Vec<Option<(u32, f64, u32)>> =
        crate::parallel::map(tries.len(), |i| ways.propose(mesh, &tris, tries[i]));
    // Per vertex, the farthest sample; ties go to the earlier sample (the same mesh each run).
    let mut best: Vec<Option<(f64, u32)>> = vec![None; positions.len()];
    for &(v, d2, m) in proposals.iter().flatten() {
        let slot = &mut best[v as usize];
        if slot.is_none_or(|(b, _)| d2 > b) {
            *slot = Some((d2, m));
        }
    }
    let (new, moved) = ways.dent(mesh, &best);
    mesh.positions_mut().copy_from_slice(&new);
    moved
}

/// The tries of a reach, `(sample, wrap face nearest to it, squared distance)`: the `misses`
/// under the wrap farther than `tol`. Only there is a concavity bridged (one outside it is a
/// sharp tip that the wrap cut, the crease fit's to place).
fn misses_under(
    tris: &[[u32; 3]],
    positions: &[DVec3],
    samples: &[DVec3],
    misses: &[u32],
    tol: f64,
) -> Vec<(u32, u32, f64)> {
    let wrap = TriangleBvh::new(positions, tris);
    let hits =
        wrap.closest_points_within(misses.len(), |i| samples[misses[i] as usize], f64::INFINITY);
    let under: Vec<Option<(u32, f64)>> = crate::parallel::map(misses.len(), |i| {
        let s = samples[misses[i] as usize];
        let hit = hits[i]?;
        if hit.distance_squared <= tol * tol {
            return None;
        }
        let [a, b, c] = tris[hit.triangle as usize].map(|v| positions[v as usize]);
        let below = (s - hit.point).dot((b - a).cross(c - a)) < 0.0;
        below.then_some((hit.triangle, hit.distance_squared))
    });
    (misses.iter().zip(under))
        .filter_map(|(&m, u)| u.map(|(t, d2)| (m, t, d2)))
        .collect()
}

/// The `most` of `tries` (as [`misses_under`] gives them) spread over the wrap: each face's
/// deepest, then each face's second deepest, and so on (the deepest of all lie in a few deep
/// gaps, all blocked: taking them first would reach none); in the order of their samples.
fn spread_over_wrap(mut tries: Vec<(u32, u32, f64)>, most: usize) -> Vec<(u32, u32, f64)> {
    tries.sort_by(|x, y| x.1.cmp(&y.1).then(y.2.total_cmp(&x.2)).then(x.0.cmp(&y.0)));
    let mut rank = vec![0u32; tries.len()];
    for i in 1..tries.len() {
        if tries[i].1 == tries[i - 1].1 {
            rank[i] = rank[i - 1] + 1;
        }
    }
    let mut order: Vec<usize> = (0..tries.len()).collect();
    order.sort_by(|&i, &j| {
        let (x, y) = (&tries[i], &tries[j]);
        rank[i]
            .cmp(&rank[j])
            .then(y.2.total_cmp(&x.2))
            .then(x.0.cmp(&y.0))
    });
    order.truncate(most);
    let mut kept: Vec<(u32, u32, f64)> = order.into_iter().map(|i| tries[i]).collect();
    kept.sort_by_key(|x| x.0);
    kept
}

/// The ways of a reach from the wrap's vertices (`positions`) to the target's `samples`.
struct Ways<'a> {
    target: &'a TriangleBvh,
    samples: &'a [DVec3],
    positions: &'a [DVec3],
    max_move: f64,
    /// The least dip [`through_material`] allows.
    floor: f64,
    closed: bool,
}

impl Ways<'_> {
    /// Whether the way from vertex `v` to `s` is clear: no longer than the longest move, not
    /// through the target's material (`strict`: not crossing the target at all), and on a
    /// closed target not inside it.
    fn clear(&self, v: u32, s: DVec3, strict: bool) -> bool {
        let p = self.positions[v as usize];
        // (From a vertex where two overlapping parts of a target meet, the way into one
        // part's material, towards the other's buried surface, may cross nothing: its
        // middle is inside.)
        let inside = || self.closed && self.target.encloses(0.5 * (p + s));
        let through = || match strict {
            true => self
                .target
                .crosses(p - STRETCH * (s - p), s - STRETCH * (s - p)),
            false => through_material(self.target, p, s, self.floor),
        };
        (s - p).length() <= self.max_move && !through() && !inside()
    }

    /// The move a try `(sample, face, squared distance)` proposes: `(vertex, squared distance,
    /// sample)`, from the face's corner nearest to the sample, or when that way is blocked
    /// from the nearest vertex two rings around with a clear way; None when none has one.
    fn propose(
        &self,
        mesh: &HalfedgeMesh,
        tris: &[[u32; 3]],
        (m, face, d2): (u32, u32, f64),
    ) -> Option<(u32, f64, u32)> {
        let (positions, closed) = (self.positions, self.closed);
        let s = self.samples[m as usize];
        let t = tris[face as usize];
        let v = nearest_corner(t, positions, s);
        if self.clear(v, s, false) {
            return Some((v, d2, m));
        }
        // The nearest corner's way is blocked (a lip between it and a slit's far corner): the
        // vertex two rings around the face nearest to the sample whose way is clear. On an open
        // target, with no inside to test, its way must cross nothing at all (with the sliver
        // allowed, such a way can dip under a sheet to a sample behind it); on a closed one the
        // sliver is allowed, since requiring a clean way everywhere reaches fewer samples.
        let mut ring = mesh.rings_around(&t, 2);
        ring.sort_by(|&a, &b| {
            let d = |v: u32| (positions[v as usize] - s).length_squared();
            d(a).total_cmp(&d(b)).then(a.cmp(&b))
        });
        ring.into_iter()
            .find(|&u| {
                // (On a closed target it must also arrive from outside: a sample on a buried
                // surface is reached only through the material.)
                let arrives = || {
                    !self
                        .target
                        .encloses(s - ARRIVAL * (s - positions[u as usize]))
                };
                u != v && self.clear(u, s, !closed) && (!closed || arrives())
            })
            .map(|u| (u, d2, m))
    }

    /// The new positions, and how many vertices moved onto a sample: each vertex with a `best`
    /// `(squared distance, sample)` onto it. The moved vertices' other neighbours follow by
    /// [`DENT_SHARE`] of the mean move where their way is as clear, so that the dent starts
    /// with sloped sides rather than a spike whose remeshed sides fold into a flap (a flap
    /// stands off the concavity's wall, a dent does not).
    fn dent(&self, mesh: &HalfedgeMesh, best: &[Option<(f64, u32)>]) -> (Vec<DVec3>, usize) {
        let (positions, samples, target) = (self.positions, self.samples, self.target);
        let mut follow = vec![(DVec3::ZERO, 0u32); positions.len()];
        for (v, b) in best.iter().enumerate() {
            if let Some((_, s)) = b {
                let d = samples[*s as usize] - positions[v];
                for u in mesh.neighbors(v as u32) {
                    if best[u as usize].is_none() {
                        let f = &mut follow[u as usize];
                        *f = (f.0 + d, f.1 + 1);
                    }
                }
            }
        }
        let mut new = positions.to_vec();
        let mut moved = 0;
        for (v, q) in new.iter_mut().enumerate() {
            if let Some((_, s)) = best[v] {
                *q = samples[s as usize];
                moved += 1;
            } else if let (sum, k @ 1..) = follow[v] {
                let to = *q + DENT_SHARE * sum / k as f64;
                let blocked = through_material(target, *q, to, self.floor)
                    || (self.closed && target.encloses(to));
                if !blocked {
                    *q = to;
                }
            }
        }
        (new, moved)
    }
}

/// How many missed samples [`reach_into_misses`] tries per wrap vertex, at most: above what an
/// ordinary concavity needs, so the bound only binds on folded targets.
const TRIES_PER_VERTEX: usize = 2;

/// The least dip [`through_material`] allows, as a share of the longest move (a vertex on the
/// target up to rounding).
pub(crate) const MOVE_FLOOR: f64 = 1e-3;

/// The share of a moved vertex's move that its neighbours follow (see [`reach_into_misses`]):
/// the value is not critical; this one lines a socket closest (see docs/decisions/).
const DENT_SHARE: f64 = 0.3;

/// Moves the tips of the thin flaps that reaching leaves onto the target; returns how many moved.
///
/// A vertex pulled into a concavity drags a dent whose sides the next passes put on the walls;
/// where a pass's moves and its remesh disagree, a flap remains: a vertex farther than `tol`
/// from the target, standing in the concavity's air, while all its neighbours lie on the walls.
/// Its move along its own normal (the fit's rule) hardly shortens the way, because that normal
/// is the flap's, so such a vertex moves to its closest target point itself (no farther than
/// `max_move`). A vertex of a surface that spans a hole of the target has neighbours off the
/// target too and stays where it is.
pub fn settle_flap_tips(
    mesh: &mut HalfedgeMesh,
    target: &TriangleBvh,
    tol: f64,
    max_move: f64,
) -> usize {
    move_onto_closest(mesh, target, max_move, |mesh, v, off| {
        off(v) > tol && mesh.neighbors(v).all(|u| off(u) <= tol)
    })
}

/// The corner of triangle `t` nearest to `s` (the lower index on a tie).
fn nearest_corner(t: [u32; 3], positions: &[DVec3], s: DVec3) -> u32 {
    let d = |v: u32| (positions[v as usize] - s).length_squared();
    t.into_iter()
        .fold(t[0], |b, v| if d(v) < d(b) { v } else { b })
}

/// True when the way from `p` to `s` runs through the target's material: it passes through a
/// target triangle from side to side, and its middle lies farther than `floor` and than a
/// [`SLIVER`] of its length from the target. Both ends lie on the target, so the crossings are
/// tested over the segment begun a hundredth behind `p` and ended a hundredth before `s`: a
/// vertex on a roof whose way goes down through it crosses the roof just behind its start. The
/// sliver lets through what only grazes the target: a chord under a convex face (it dips by
/// length/8R: 0.03 of its length on a ball of radius four times the way), a way along a
/// faceted wall.
pub(crate) fn through_material(target: &TriangleBvh, p: DVec3, s: DVec3, floor: f64) -> bool {
    let crosses = target.crosses(p - STRETCH * (s - p), s - STRETCH * (s - p));
    crosses && target.distance(0.5 * (p + s)) > (SLIVER * (s - p).length()).max(floor)
}

/// How far before its end (as a share of the way) a way found around a blocked one must be
/// outside a closed target.
const ARRIVAL: f64 = 0.02;

/// The share of the way by which [`through_material`] moves its ends (back from `p`, back
/// from `s`).
const STRETCH: f64 = 0.01;
/// How deep under the target a way's middle may lie, as a share of its length (see
/// [`through_material`]): ways that cut through a lip into the far end of a slit dip by
/// several times this.
const SLIVER: f64 = 0.1;

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::icosphere::icosphere;

    /// A floor at z = −1 under a roof at z = 0 with a slot of width 0.2 along x = 0.
    fn slot() -> (Vec<DVec3>, TriangleBvh) {
        let pos = vec![
            DVec3::new(-2.0, -1.0, -1.0),
            DVec3::new(2.0, -1.0, -1.0),
            DVec3::new(2.0, 1.0, -1.0),
            DVec3::new(-2.0, 1.0, -1.0),
            DVec3::new(0.1, -1.0, 0.0),
            DVec3::new(2.0, -1.0, 0.0),
            DVec3::new(2.0, 1.0, 0.0),
            DVec3::new(0.1, 1.0, 0.0),
            DVec3::new(-2.0, -1.0, 0.0),
            DVec3::new(-0.1, -1.0, 0.0),
            DVec3::new(-0.1, 1.0, 0.0),
            DVec3::new(-2.0, 1.0, 0.0),
            // Samples: the slot's floor, the floor under the roof.
            DVec3::new(0.0, 0.0, -1.0),
            DVec3::new(1.0, 0.0, -1.0),
        ];
        let tris = vec![
            [0, 1, 2],
            [0, 2, 3],
            [4, 5, 6],
            [4, 6, 7],
            [8, 9, 10],
            [8, 10, 11],
        ];
        let bvh = TriangleBvh::new(&pos, &tris);
        (pos, bvh)
    }

    /// A small ball turned inside out: near its bottom it is a wrap over the slot, with the
    /// target under it (on the inner side of its faces).
    fn ball(center: DVec3) -> HalfedgeMesh {
        let b = icosphere(2, 0.3, center).unwrap();
        let flipped: Vec<[u32; 3]> = b.triangles().iter().map(|&[a, b, c]| [a, c, b]).collect();
        HalfedgeMesh::from_triangles(b.positions().to_vec(), &flipped).unwrap()
    }

    #[test]
    fn a_vertex_over_a_slot_moves_to_its_floor() {
        let (pos, target) = slot();
        let mut mesh = ball(DVec3::new(0.0, 0.0, 0.3));
        let bottom = (0..mesh.n_vertices() as u32)
            .min_by(|&a, &b| mesh.position(a).z.total_cmp(&mesh.position(b).z))
            .unwrap();
        let moved = reach_into_misses(&mut mesh, &target, &pos, &[12, 13], 0.05, 2.0, false);
        assert_eq!(mesh.position(bottom), pos[12]);
        // The floor under the roof is reached too, by a vertex whose way runs down the slot.
        assert_eq!(moved, 2);
        assert!((0..mesh.n_vertices() as u32).any(|v| mesh.position(v) == pos[13]));
    }

    #[test]
    fn no_vertex_moves_through_the_target_or_farther_than_allowed() {
        let (pos, target) = slot();
        // Over the roof: the floor beneath is behind it.
        let mut mesh = ball(DVec3::new(1.0, 0.0, 0.3));
        let before = mesh.positions().to_vec();
        assert_eq!(
            reach_into_misses(&mut mesh, &target, &pos, &[13], 0.05, 2.0, false),
            0
        );
        assert_eq!(mesh.positions(), &before[..]);
        // Over the slot, but the floor is farther than the longest move.
        let mut mesh = ball(DVec3::new(0.0, 0.0, 0.3));
        assert_eq!(
            reach_into_misses(&mut mesh, &target, &pos, &[12], 0.05, 0.5, false),
            0
        );
        // A sample the wrap already touches is no miss.
        assert_eq!(
            reach_into_misses(&mut mesh, &target, &pos, &[12], 1.5, 2.0, false),
            0
        );
    }

    /// The nearest vertex's way to a sample beside the slot's floor runs through the roof; a
    /// vertex two rings out, over the slot, has a clear way and moves instead.
    #[test]
    fn a_blocked_way_goes_to_a_neighbour_with_a_clear_one() {
        let (mut pos, target) = slot();
        pos.push(DVec3::new(0.12, 0.0, -1.0));
        let sample = pos.len() as u32 - 1;
        let mut mesh = ball(DVec3::new(0.2, 0.0, 0.3));
        let before = mesh.positions().to_vec();
        let moved = reach_into_misses(&mut mesh, &target, &pos, &[sample], 0.05, 2.0, false);
        assert_eq!(moved, 1);
        let v = (0..mesh.n_vertices())
            .find(|&v| mesh.position(v as u32) == pos[sample as usize])
            .unwrap();
        // It stood over the slot (|x| < 0.1), not over the roof like the nearest vertex.
        assert!(before[v].x.abs() < 0.1, "{:?}", before[v]);
    }

    /// A missed sample outside the wrap is a tip the wrap cut, not a concavity: left alone.
    #[test]
    fn a_sample_outside_the_wrap_is_left_to_the_crease_fit() {
        let (pos, target) = slot();
        let mut mesh = icosphere(2, 0.3, DVec3::new(0.0, 0.0, 0.3)).unwrap();
        assert_eq!(
            reach_into_misses(&mut mesh, &target, &pos, &[12], 0.05, 2.0, false),
            0
        );
    }

    /// Into a closed target's material is refused: the way crosses the surface the vertex
    /// stands on, and its middle is inside.
    #[test]
    fn no_vertex_moves_into_a_closed_targets_material() {
        // Target: a ball of radius 1; its sample at the centre stands for a buried part's.
        let target_mesh = icosphere(2, 1.0, DVec3::ZERO).unwrap();
        let mut pos = target_mesh.positions().to_vec();
        pos.push(DVec3::new(0.0, 0.0, 0.9));
        let bvh = TriangleBvh::new(&pos, &target_mesh.triangles());
        let sample = pos.len() as u32 - 1;
        let mut mesh = ball(DVec3::new(0.0, 0.0, 1.3));
        assert_eq!(
            reach_into_misses(&mut mesh, &bvh, &pos, &[sample], 0.05, 2.0, true),
            0
        );
        let mut mesh = ball(DVec3::new(0.0, 0.0, 1.3));
        assert_eq!(
            reach_into_misses(&mut mesh, &bvh, &pos, &[sample], 0.05, 2.0, false),
            0
        );
    }

    #[test]
    fn a_flap_tip_moves_onto_the_target_and_a_spanning_surface_stays() {
        // Target: the plane z = 0 as two big triangles.
        let pos = vec![
            DVec3::new(-9.0, -9.0, 0.0),
            DVec3::new(9.0, -9.0, 0.0),
            DVec3::new(0.0, 9.0, 0.0),
        ];
        let bvh = TriangleBvh::new(&pos, &[[0, 1, 2]]);
        // An octahedron-like wrap flattened onto the plane but for one raised tip.
        let mut mesh = icosphere(0, 1.0, DVec3::ZERO).unwrap();
        for p in mesh.positions_mut() {
            p.z = 0.0;
        }
        mesh.positions_mut()[0].z = 0.5;
        assert_eq!(settle_flap_tips(&mut mesh, &bvh, 0.1, 1.0), 1);
        assert_eq!(mesh.position(0).z, 0.0);
        // Two raised neighbours: neither is a tip.
        let v = mesh.neighbors(0).next().unwrap();
        mesh.positions_mut()[0].z = 0.5;
        mesh.positions_mut()[v as usize].z = 0.5;
        assert_eq!(settle_flap_tips(&mut mesh, &bvh, 0.1, 1.0), 0);
    }

    /// Of more misses than the bound, each face's deepest is tried before any face's second:
    /// a thousand blocked samples deep under one face (below the floor) do not crowd out the
    /// floor under the roof, reached down the slot.
    #[test]
    fn many_blocked_misses_leave_room_for_a_clear_one() {
        let (mut pos, target) = slot();
        let mut mesh = ball(DVec3::new(0.0, 0.0, 0.3));
        let first = pos.len() as u32;
        pos.extend(std::iter::repeat_n(DVec3::new(0.0, 0.0, -3.0), 1000));
        let mut misses: Vec<u32> = (first..pos.len() as u32).collect();
        assert!(misses.len() > TRIES_PER_VERTEX * mesh.n_vertices());
        misses.push(13);
        let moved = reach_into_misses(&mut mesh, &target, &pos, &misses, 0.05, 4.0, false);
        assert_eq!(moved, 1);
        assert!((0..mesh.n_vertices() as u32).any(|v| mesh.position(v) == pos[13]));
    }
}
