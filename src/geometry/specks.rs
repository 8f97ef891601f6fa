//! Specks of a mesh: small closed parts floating apart from the rest (a scan's loose debris, a
//! model's stray bits), under two grid cells across. The wrap cannot resolve them (its offset
//! surface around one is a blob of a few cells), and wrapping them fails: a few leave intersecting
//! faces, many make the evolution diverge. A mesh target leaves them out, as a cloud leaves out its
//! stray points (see [`crate::geometry::spatial::isolated`]).
//!
//! Only closed parts (every edge shared by two of the part's triangles) are specks: an open
//! piece can be a patch of a larger surface split at its seams (a CAD export's T-junctions, a
//! triangle soup), and leaving it out would open a hole in that surface. Small closed parts
//! within a cell of one another form a cluster; a cluster is apart when no vertex of any other
//! part lies within one cell of a member's box, and it is left out when it is also under
//! [`CLUSTER_CELLS`] across and all the specks together hold at most [`MOST_SPECK_AREA`] of the
//! mesh's area (more is a mesh of small parts, not a body with debris).

use crate::geometry::aabb::Aabb;
use crate::mesh::disjoint::DisjointSets;
use glam::DVec3;
use std::collections::HashMap;

/// A part is small when its box's diagonal is under this many cells.
pub const SPECK_CELLS: f64 = 2.0;

/// A cluster of specks (small closed parts within a cell of one another) is left out whole when
/// its box's diagonal is under this many cells; a larger one is a part of the model built of
/// small pieces.
pub const CLUSTER_CELLS: f64 = 4.0;

/// The largest share of a mesh's area that its specks may hold and still be left out.
pub const MOST_SPECK_AREA: f64 = 0.1;

/// Which triangles of the mesh (`points`, `tris`) belong to specks at grid cell `cell`, and how
/// many specks there are; None when there is none.
pub fn speck_triangles(
    points: &[DVec3],
    tris: &[[u32; 3]],
    cell: f64,
) -> Option<(Vec<bool>, usize)> {
    if tris.is_empty() || cell.is_nan() || cell <= 0.0 || cell.is_infinite() {
        return None;
    }
    let part = parts(points.len(), tris);
    let n_parts = part.iter().copied().max().map_or(0, |m| m as usize + 1);
    if n_parts < 2 {
        return None;
    }
    let mut boxes = vec![Aabb::EMPTY; n_parts];
    let mut used = vec![false; points.len()];
    for t in tris {
        for &v in t {
            let b = &mut boxes[part[v as usize] as usize];
            *b = b.grow(points[v as usize]);
            used[v as usize] = true;
        }
    }
    let small: Vec<bool> = boxes
        .iter()
        .map(|b| b.diagonal() < SPECK_CELLS * cell)
        .collect();
    if !small.contains(&true) {
        return None;
    }
    let closed = closed_parts(&part, n_parts, tris);
    let candidate: Vec<bool> = (0..n_parts).map(|c| small[c] && closed[c]).collect();
    // Vertices by cell, for "another part's vertex within a cell of this box".
    let key = |p: DVec3| ((p / cell).floor()).to_array().map(|c| c as i64);
    let mut grid: HashMap<[i64; 3], Vec<u32>> = HashMap::new();
    for (v, &p) in points.iter().enumerate() {
        if used[v] {
            grid.entry(key(p)).or_default().push(v as u32);
        }
    }
    // Candidates near one another form a cluster (debris often comes in bunches); a cluster
    // near any other part is not apart.
    let mut cluster = DisjointSets::new(n_parts);
    let mut touching = vec![false; n_parts];
    for c in (0..n_parts).filter(|&c| candidate[c]) {
        let b = boxes[c].expanded(cell);
        let (lo, hi) = (key(b.min), key(b.max));
        for z in lo[2]..=hi[2] {
            for y in lo[1]..=hi[1] {
                for x in lo[0]..=hi[0] {
                    for &v in grid.get(&[x, y, z]).into_iter().flatten() {
                        let (q, o) = (points[v as usize], part[v as usize] as usize);
                        if o == c || !(q.cmpge(b.min).all() && q.cmple(b.max).all()) {
                            continue;
                        }
                        if candidate[o] {
                            cluster.union(c as u32, o as u32);
                        } else {
                            touching[c] = true;
                        }
                    }
                }
            }
        }
    }
    let mut cluster_box = vec![Aabb::EMPTY; n_parts];
    let mut cluster_touching = vec![false; n_parts];
    for c in (0..n_parts).filter(|&c| candidate[c]) {
        let r = cluster.find(c as u32) as usize;
        cluster_box[r] = cluster_box[r].grow(boxes[c].min).grow(boxes[c].max);
        cluster_touching[r] |= touching[c];
    }
    let speck: Vec<bool> = (0..n_parts)
        .map(|c| {
            let r = cluster.find(c as u32) as usize;
            candidate[c] && !cluster_touching[r] && cluster_box[r].diagonal() < CLUSTER_CELLS * cell
        })
        .collect();
    let count = speck.iter().filter(|&&s| s).count();
    if count == 0 {
        return None;
    }
    let area = |t: &[u32; 3]| {
        let [a, b, c] = t.map(|v| points[v as usize]);
        0.5 * (b - a).cross(c - a).length()
    };
    let (mut total, mut dropped) = (0.0, 0.0);
    let out: Vec<bool> = tris
        .iter()
        .map(|t| {
            let s = speck[part[t[0] as usize] as usize];
            total += area(t);
            if s {
                dropped += area(t);
            }
            s
        })
        .collect();
    (dropped <= MOST_SPECK_AREA * total).then_some((out, count))
}

/// The part (connected component, numbered from 0 in order of first vertex) of every vertex.
fn parts(n: usize, tris: &[[u32; 3]]) -> Vec<u32> {
    let mut parts = DisjointSets::new(n);
    for t in tris {
        parts.union(t[0], t[1]);
        parts.union(t[1], t[2]);
    }
    let mut label = vec![u32::MAX; n];
    let mut next = 0;
    (0..n as u32)
        .map(|v| {
            let r = parts.find(v) as usize;
            if label[r] == u32::MAX {
                label[r] = next;
                next += 1;
            }
            label[r]
        })
        .collect()
}

/// Whether each part is closed: every undirected edge of its triangles used exactly twice.
fn closed_parts(part: &[u32], n_parts: usize, tris: &[[u32; 3]]) -> Vec<bool> {
    let mut edges: Vec<u64> = tris
        .iter()
        .flat_map(|t| [(t[0], t[1]), (t[1], t[2]), (t[2], t[0])])
        .map(|(a, b)| (u64::from(a.min(b)) << 32) | u64::from(a.max(b)))
        .collect();
    edges.sort_unstable();
    let mut closed = vec![true; n_parts];
    for run in edges.chunk_by(|a, b| a == b) {
        if run.len() != 2 {
            closed[part[(run[0] >> 32) as usize] as usize] = false;
        }
    }
    closed
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::icosphere::icosphere;

    /// A mesh of `spheres` (centre, radius) as one triangle list.
    fn spheres(spheres: &[(DVec3, f64)]) -> (Vec<DVec3>, Vec<[u32; 3]>) {
        let (mut p, mut t) = (Vec::new(), Vec::new());
        for &(c, r) in spheres {
            let s = icosphere(2, r, c).unwrap();
            let off = p.len() as u32;
            p.extend_from_slice(s.positions());
            t.extend(s.triangles().iter().map(|f| f.map(|v| v + off)));
        }
        (p, t)
    }

    #[test]
    fn small_closed_parts_apart_are_specks_and_nothing_else_is() {
        let cell = 0.05;
        // A body, two specks well apart, a small part touching the body, a large part.
        let (p, t) = spheres(&[
            (DVec3::ZERO, 1.0),
            (DVec3::new(2.0, 0.0, 0.0), 0.02),
            (DVec3::new(0.0, 2.0, 0.0), 0.025),
            (DVec3::new(0.0, 0.0, 1.02), 0.025),
            (DVec3::new(0.0, -3.0, 0.0), 0.5),
        ]);
        let per = t.len() / 5;
        let (out, count) = speck_triangles(&p, &t, cell).unwrap();
        assert_eq!(count, 2);
        let parts: Vec<bool> = (0..5).map(|k| out[k * per]).collect();
        assert_eq!(parts, [false, true, true, false, false]);
        assert!(out.chunks(per).all(|c| c.iter().all(|&s| s == c[0])));
        // None at a fine grid.
        assert!(speck_triangles(&p, &t, 0.001).is_none());
    }

    #[test]
    fn a_bunch_of_specks_goes_whole_unless_it_is_large_or_near_the_body() {
        let cell = 0.05;
        let (p, t) = spheres(&[
            (DVec3::ZERO, 1.0),
            // Two specks a few hundredths apart, far from the body: one cluster, left out.
            (DVec3::new(2.0, 0.0, 0.0), 0.02),
            (DVec3::new(2.05, 0.0, 0.0), 0.02),
            // Two near the body's surface, one of them within a cell of its vertices: kept.
            (DVec3::new(0.0, 0.0, 1.05), 0.02),
            (DVec3::new(0.0, 0.0, 1.1), 0.02),
        ]);
        let per = t.len() / 5;
        let (out, count) = speck_triangles(&p, &t, cell).unwrap();
        assert_eq!(count, 2);
        let parts: Vec<bool> = (0..5).map(|k| out[k * per]).collect();
        assert_eq!(parts, [false, true, true, false, false]);
        // A chain of specks longer than the cluster limit: kept.
        let chain: Vec<(DVec3, f64)> = std::iter::once((DVec3::ZERO, 1.0))
            .chain((0..8).map(|i| (DVec3::new(2.0 + 0.05 * i as f64, 0.0, 0.0), 0.02)))
            .collect();
        let (p, t) = spheres(&chain);
        assert!(speck_triangles(&p, &t, cell).is_none());
    }

    #[test]
    fn open_pieces_and_a_mesh_of_small_parts_keep_everything() {
        let cell = 0.05;
        let (p, mut t) = spheres(&[(DVec3::ZERO, 1.0), (DVec3::new(2.0, 0.0, 0.0), 0.02)]);
        // The small sphere with a face missing: open, so kept.
        let body = t.len() / 2;
        t.remove(body);
        assert!(speck_triangles(&p, &t, cell).is_none());
        // Twenty small spheres and nothing else: the specks would be all of the area.
        let many: Vec<(DVec3, f64)> = (0..20)
            .map(|i| (DVec3::new(i as f64 * 0.5, 0.0, 0.0), 0.02))
            .collect();
        let (p, t) = spheres(&many);
        assert!(speck_triangles(&p, &t, cell).is_none());
        // A single part never is a speck of itself.
        let (p, t) = spheres(&[(DVec3::ZERO, 0.01)]);
        assert!(speck_triangles(&p, &t, cell).is_none());
    }
}
