//! The tube between two loops: the zip of least total rung length.

use crate::mesh::HalfedgeMesh;
use glam::DVec3;

/// The tube between loops `a` and `b` (each in its region's halfedge direction): `a` forwards,
/// `b` backwards, with the shortest rungs. A zip is a staircase of rungs (a_i, b_k) from (0, 0)
/// round to (n, m), each step a triangle; for each start of `b` (the [`ZIP_WORK`] / (n·m)
/// nearest to `a[0]`, all of them on small loops) the staircase of least total rung length,
/// within a band about the diagonal, is found by dynamic programming, and the least
/// of those is kept (none past [`ZIP_CELLS`]). A greedy zip (the shorter diagonal from the
/// vertex nearest `a[0]`) twists small, zigzag loops into a tube that crosses itself; so does
/// the least *area* (a twisted tube narrows in the middle: less area, crossing faces). `None`
/// when no zip is valid.
pub(super) fn zip_loops(mesh: &HalfedgeMesh, a: &[u32], b: &[u32]) -> Option<Vec<[u32; 3]>> {
    let (n, m) = (a.len(), b.len());
    if n < 3 || m < 3 || (n + 1) * (m + 1) > ZIP_CELLS {
        return None;
    }
    let pa: Vec<DVec3> = a.iter().map(|&v| mesh.position(v)).collect();
    let pb: Vec<DVec3> = b.iter().map(|&v| mesh.position(v)).collect();
    let mut starts: Vec<usize> = (0..m).collect();
    starts.sort_by(|&i, &j| {
        let (di, dj) = (pb[i].distance(pa[0]), pb[j].distance(pa[0]));
        di.total_cmp(&dj).then(i.cmp(&j))
    });
    starts.truncate((ZIP_WORK / (n * m)).clamp(1, m));
    let mut cost = vec![0.0; (n + 1) * (m + 1)];
    let at = |i: usize, k: usize| i * (m + 1) + k;
    // Within the band, the rungs of the first and the last side of the staircase, (0, k) and
    // (n, k) or (i, 0) and (i, m), never meet: no edge of three faces, and no zip that fans one
    // loop out from a vertex of the other (two such fans make two discs instead of a tube).
    let in_band = |i: usize, k: usize| (2 * i * m).abs_diff(2 * k * n) < n * m;
    let mut best: Option<(f64, Vec<[u32; 3]>)> = None;
    for j0 in starts {
        let bk = |k: usize| (j0 + m - k % m) % m;
        let rung = |i: usize, k: usize| pa[i % n].distance(pb[bk(k)]);
        for i in 0..=n {
            for k in 0..=m {
                cost[at(i, k)] = match (i, k) {
                    (0, 0) => 0.0,
                    _ if !in_band(i, k) => f64::INFINITY,
                    _ => {
                        let from_a = if i > 0 {
                            cost[at(i - 1, k)]
                        } else {
                            f64::INFINITY
                        };
                        let from_b = if k > 0 {
                            cost[at(i, k - 1)]
                        } else {
                            f64::INFINITY
                        };
                        from_a.min(from_b) + rung(i, k)
                    }
                };
            }
        }
        let total = cost[at(n, m)];
        if best.as_ref().is_some_and(|(c, _)| *c <= total) || !total.is_finite() {
            continue;
        }
        // Back from (n, m): the step that the minimum came by (ties to `a`).
        let (mut i, mut k) = (n, m);
        let mut tris = Vec::with_capacity(n + m);
        while (i, k) != (0, 0) {
            let via_a = i > 0 && (k == 0 || cost[at(i - 1, k)] <= cost[at(i, k - 1)]);
            if via_a {
                tris.push([a[(i - 1) % n], a[i % n], b[bk(k)]]);
                i -= 1;
            } else {
                tris.push([b[bk(k)], b[bk(k - 1)], a[i % n]]);
                k -= 1;
            }
        }
        tris.reverse();
        if uses_an_edge_twice(&tris) {
            continue;
        }
        best = Some((total, tris));
    }
    best.map(|(_, tris)| tris)
}

/// Staircase cells (n·m per start of `b`) a zip may fill across all the starts it tries.
const ZIP_WORK: usize = 1 << 21;
/// Loops with more staircase cells than this (two loops of some √`ZIP_CELLS` vertices each, far
/// longer than any hole's rim on a wrap of ordinary size) are not zipped: their costs alone would
/// take too much memory.
const ZIP_CELLS: usize = 1 << 24;

/// Whether a directed edge occurs twice among `tris` (an edge of three faces once glued).
fn uses_an_edge_twice(tris: &[[u32; 3]]) -> bool {
    let mut edges: Vec<(u32, u32)> = tris
        .iter()
        .flat_map(|t| [(t[0], t[1]), (t[1], t[2]), (t[2], t[0])])
        .collect();
    let count = edges.len();
    edges.sort_unstable();
    edges.dedup();
    edges.len() != count
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Loops of 3 to 8 vertices at random (a fixed generator; sizes, centres and radii) on two
    /// parallel planes: every zip made uses each loop edge once and no edge twice in one
    /// direction (an edge of three faces), even where a short loop meets a long one.
    #[test]
    fn a_zip_never_uses_an_edge_twice() {
        let mut state = 0x2545_f491_4f6c_dd1d_u64;
        let mut rand = || {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            (state >> 11) as f64 / (1u64 << 53) as f64
        };
        let mut zipped = 0;
        for _ in 0..2000 {
            let (n, m) = (3 + (rand() * 6.0) as usize, 3 + (rand() * 6.0) as usize);
            let mut positions = Vec::new();
            for (count, z, r) in [(n, 1.0, 0.05 + rand()), (m, 0.0, 0.05 + rand())] {
                let (phase, cx, cy) = (rand() * 6.3, rand() - 0.5, rand() - 0.5);
                for k in 0..count {
                    let angle =
                        phase + std::f64::consts::TAU * (k as f64 + 0.4 * rand()) / count as f64;
                    positions.push(DVec3::new(
                        cx + r * crate::fmath::cos(angle),
                        cy + r * crate::fmath::sin(angle),
                        z,
                    ));
                }
            }
            // Two fans, so that every vertex is in the mesh; only the positions are used.
            let fan = |o: u32, c: u32| (1..c - 1).map(move |k| [o, o + k, o + k + 1]);
            let tris: Vec<[u32; 3]> = fan(0, n as u32).chain(fan(n as u32, m as u32)).collect();
            let mesh = HalfedgeMesh::from_triangles(positions, &tris).unwrap();
            let a: Vec<u32> = (0..n as u32).collect();
            let b: Vec<u32> = (n as u32..(n + m) as u32).rev().collect();
            let Some(tube) = zip_loops(&mesh, &a, &b) else {
                continue;
            };
            zipped += 1;
            let mut edges: Vec<(u32, u32)> = tube
                .iter()
                .flat_map(|t| [(t[0], t[1]), (t[1], t[2]), (t[2], t[0])])
                .collect();
            let count = edges.len();
            edges.sort_unstable();
            edges.dedup();
            assert_eq!(
                edges.len(),
                count,
                "an edge used twice: n {n}, m {m}, {tube:?}"
            );
            assert_eq!(tube.len(), n + m);
        }
        assert!(zipped > 1500, "{zipped}");
    }

    /// The loops of a narrow hole through a plate sampled densely and noisily, in
    /// cylindrical coordinates about the hole's axis: a round 6-vertex loop and a zigzag 9-vertex
    /// one 6.5 radii below it. The tube zipped between them does not cross itself (a greedy zip
    /// or the zip of least area would).
    #[test]
    fn a_deep_narrow_tube_does_not_cross_itself() {
        let a = [(-31.0, 0.027), (-88.0, 0.027), (-150.0, 0.025)]
            .into_iter()
            .chain([(151.0, 0.026), (94.0, 0.026), (35.0, 0.026)])
            .map(|(deg, r)| (deg, r, 0.0));
        let b = [
            (11.0, 0.019, 0.168),
            (67.0, 0.035, 0.173),
            (122.0, 0.018, 0.169),
        ]
        .into_iter()
        .chain([
            (139.0, 0.047, 0.178),
            (-174.0, 0.033, 0.175),
            (-120.0, 0.039, 0.181),
        ])
        .chain([
            (-100.0, 0.015, 0.172),
            (-46.0, 0.035, 0.179),
            (-7.0, 0.043, 0.181),
        ]);
        let positions: Vec<DVec3> = a
            .chain(b)
            .map(|(deg, r, z): (f64, f64, f64)| {
                let t = deg.to_radians();
                DVec3::new(r * crate::fmath::cos(t), r * crate::fmath::sin(t), z)
            })
            .collect();
        let fan = |o: u32, c: u32| (1..c - 1).map(move |k| [o, o + k, o + k + 1]);
        let tris: Vec<[u32; 3]> = fan(0, 6).chain(fan(6, 9)).collect();
        let mesh = HalfedgeMesh::from_triangles(positions.clone(), &tris).unwrap();
        let (a, b): (Vec<u32>, Vec<u32>) = ((0..6).collect(), (6..15).collect());
        let tube = zip_loops(&mesh, &a, &b).unwrap();
        assert_eq!(tube.len(), 15);
        let crossings = crate::metrics::intersections::self_intersecting_pairs(&positions, &tube);
        assert!(crossings.is_empty(), "{} crossings", crossings.len());
    }
}
