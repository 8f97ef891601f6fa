//! Index repair of a triangle list that is closed in shape but not in its indices: corners at
//! the same position stored as separate vertices (OBJ, PLY and glTF exports split vertices
//! along UV seams and hard edges), faces stored twice, faces wound the wrong way.
//!
//! Such a mesh cannot have a signed distance field (its edges are boundary or non-manifold),
//! so it would be wrapped like a point cloud: from an icosphere, without its genus, with no
//! inside to guide the flow, far slower and into far more vertices than the clean file. The
//! repair changes no position and no shape:
//!
//! 1. corners with bit-identical coordinates become one vertex (the first in file order);
//! 2. faces with a repeated corner, and second copies of a face (either winding), are dropped;
//! 3. where more than two faces meet at an edge (solids touching along it), they are paired
//!    around it: each face with its neighbour on its inner side, when the pairing is mutual and
//!    each pair runs the edge both ways;
//! 4. faces are wound consistently across every paired edge, and each closed part is turned
//!    outwards (positive volume) — or inwards when another closed part contains it an odd
//!    number of times (a hollow part's inner wall);
//! 5. a vertex whose faces fall into several fans (joined by paired edges) gets one copy per fan,
//!    so parts that touch at an edge or a vertex become separate closed parts (each then has a
//!    signed field of its own instead of being wrapped as a cloud);
//! 6. holes of at most [`MOST_HOLE_EDGES`] edges in a large part are closed by a fan (a few
//!    missing faces, so the part can start from the isosurface instead of the icosphere).
//!
//! It is used only where it turns a mesh with non-manifold or inconsistent edges into one
//! without, or closes boundary edges; an already closed and oriented mesh is touched only to turn
//! a part wound against the others ([`facing_parts`]).

use super::disjoint::DisjointSets;
use glam::DVec3;
use serde::{Deserialize, Serialize};

/// What [`repair`] changed.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[cfg_attr(target_arch = "wasm32", derive(tsify::Tsify))]
pub struct Repairs {
    /// Vertices merged into an earlier one at the same position.
    pub merged_vertices: usize,
    /// Faces dropped: with a repeated corner (after merging), or stored twice (the second copy;
    /// both copies where they are the wall between two solids).
    pub dropped_faces: usize,
    /// Faces whose winding was reversed.
    pub flipped_faces: usize,
    /// Vertex copies made where separate fans of faces met at one vertex.
    pub split_vertices: usize,
    /// Small holes closed (boundary loops of at most [`MOST_HOLE_EDGES`] edges).
    pub filled_holes: usize,
}

/// The most edges of a hole that mending closes (a few missing faces of a scan). Larger openings
/// (a cut sphere's, a scan's open base) stay open: the wrap spans them.
pub const MOST_HOLE_EDGES: usize = 12;

/// Points of a part tested for lying inside another.
const PROBES: usize = 8;

/// Closed parts tested against each other for nesting at most (each test visits every face of
/// the other part); beyond it, parts are taken as side by side.
const MOST_NESTED_PARTS: usize = 32;

/// (Boundary edges, edges used other than once each way) of a triangle list, by its stars (a
/// counting sort by vertex, several times faster than sorting every edge).
fn edge_defects(tris: &[[u32; 3]]) -> (usize, usize) {
    let c = super::stars::closure(tris);
    (c.boundary_edges, c.bad_edges)
}

/// Every face's edges, sorted by edge: (edge key, face, runs from its smaller vertex).
fn edge_uses(tris: &[[u32; 3]]) -> Vec<(u64, u32, bool)> {
    let mut uses: Vec<(u64, u32, bool)> = tris
        .iter()
        .enumerate()
        .flat_map(|(f, t)| {
            [(t[0], t[1]), (t[1], t[2]), (t[2], t[0])].map(|(a, b)| (key(a, b), f as u32, a < b))
        })
        .collect();
    uses.sort_unstable();
    uses
}

/// The undirected edge {a, b} as one sortable key.
fn key(a: u32, b: u32) -> u64 {
    ((a.min(b) as u64) << 32) | a.max(b) as u64
}

/// Mended points and triangles, and what changed.
pub type Mended = (Vec<DVec3>, Vec<[u32; 3]>, Repairs);

/// The repaired points and triangles and what changed, or None when the mesh needs no repair
/// (no triangles; closed and oriented, with every part facing out or, nested, in) or the repair
/// would not make it better: it must end with no non-manifold or inconsistent edge, and with
/// fewer defects than it started with.
pub fn repair(points: &[DVec3], triangles: &[[u32; 3]]) -> Option<Mended> {
    if triangles.is_empty() {
        return None;
    }
    let (closure, rims) = super::stars::closure_and_rims(triangles);
    let before = (closure.boundary_edges, closure.bad_edges);
    if before == (0, 0) {
        return facing_parts(points, triangles);
    }
    // With boundary edges only (an open scan), only corners merged on them could close any: a
    // cheap check spares an open scan the whole mending, which would change nothing.
    if before.1 == 0 && !coincident(points, &rims) && !small_loop(&rims) {
        return None;
    }
    let (points, remap) = merge_coincident(points);
    let merged = remap.len() - points.len();
    // A face stored twice, wound both ways, is either a repeat or the wall between two solids
    // that touch face to face (the box soup: two cubes sharing a square). Keeping one copy
    // mends a repeat; dropping both mends a wall. Where both windings occur, both are tried and
    // the one with fewer defects is kept (then the one with fewer holes filled, then keeping one).
    let (kept, walls) = distinct_faces(triangles, &remap, false);
    let mut tries: Vec<_> = mend(points.clone(), kept, merged, triangles.len())
        .into_iter()
        .collect();
    if walls {
        let (without, _) = distinct_faces(triangles, &remap, true);
        tries.extend(mend(points, without, merged, triangles.len()));
    }
    let ((points, tris, repairs), after) = tries
        .into_iter()
        .min_by_key(|((_, _, r), (boundary, bad))| (boundary + bad, r.filled_holes))?;
    let better = after.1 == 0 && (after.0 + after.1 < before.0 + before.1);
    (better && !tris.is_empty()).then_some((points, tris, repairs))
}

/// One mending of the merged `points` and distinct faces `tris` (of `faces` in the file):
/// faces paired around edges, wound consistently, fans split, parts turned; with the edge
/// defects left (boundary, inconsistent). None when a part cannot be wound consistently.
fn mend(
    points: Vec<DVec3>,
    mut tris: Vec<[u32; 3]>,
    merged: usize,
    faces: usize,
) -> Option<(Mended, (usize, usize))> {
    let mut repairs = Repairs {
        merged_vertices: merged,
        dropped_faces: faces - tris.len(),
        ..Repairs::default()
    };
    let pairs = edge_pairs(&points, &tris);
    let (mut flips, parts) = consistent_winding(&tris, &pairs)?;
    turn(&mut tris, &flips);
    let (points, split) = split_fans(points, &mut tris, &pairs);
    repairs.split_vertices = split;
    let turned = outwards(&points, &tris, &parts, &open_faces(&tris));
    turn(&mut tris, &turned);
    flips.iter_mut().zip(&turned).for_each(|(f, o)| *f ^= o);
    // Faces that end wound against how the file wrote them (a dropped copy does not count).
    repairs.flipped_faces = flips.iter().filter(|&&f| f).count();
    // Holes are closed only in parts much larger than them (a stray face or strip, closed on
    // itself, would become a flat pillow).
    let mut big = vec![false; tris.len()];
    for faces in parts.iter().filter(|f| f.len() > 4 * MOST_HOLE_EDGES) {
        faces.iter().for_each(|&f| big[f as usize] = true);
    }
    repairs.filled_holes = fill_small_holes(&mut tris, &big);
    if repairs.filled_holes > 0 {
        // The patches join their parts, which may now be closed: turn those their way.
        let pairs = edge_pairs(&points, &tris);
        let (_, parts) = consistent_winding(&tris, &pairs)?;
        let turned = outwards(&points, &tris, &parts, &open_faces(&tris));
        turn(&mut tris, &turned);
    }
    let after = edge_defects(&tris);
    Some(((points, tris, repairs), after))
}

/// Whether the boundary edges `rims` (pairs of ends) form a simple loop of at most
/// [`MOST_HOLE_EDGES`] edges: a hole [`fill_small_holes`] would close.
fn small_loop(rims: &[u32]) -> bool {
    let mut ends: Vec<(u32, u32)> = rims
        .chunks_exact(2)
        .flat_map(|e| [(e[0], e[1]), (e[1], e[0])])
        .collect();
    ends.sort_unstable();
    let degree = |v: u32| ends.partition_point(|e| e.0 <= v) - ends.partition_point(|e| e.0 < v);
    let mut seen = vec![false; ends.len()];
    for start in 0..ends.len() {
        if seen[start] {
            continue;
        }
        // Walk the loop through `start`'s vertex, while every vertex has two rim edges.
        let (first, mut from, mut at) = (ends[start].0, ends[start].0, ends[start].1);
        seen[start] = true;
        let mut edges = 1;
        while at != first && edges <= MOST_HOLE_EDGES && degree(at) == 2 {
            let i = ends.partition_point(|e| e.0 < at);
            let next = if ends[i].1 != from { i } else { i + 1 };
            seen[next] = true;
            (from, at) = (at, ends[next].1);
            edges += 1;
        }
        if at == first && edges <= MOST_HOLE_EDGES && degree(first) == 2 {
            return true;
        }
    }
    false
}

/// Closes every hole of at most [`MOST_HOLE_EDGES`] edges whose rim is a simple loop, by a fan
/// of faces wound to match the faces around it, where the faces along it are `big` (of a large
/// part); returns how many.
fn fill_small_holes(tris: &mut Vec<[u32; 3]>, big: &[bool]) -> usize {
    // The rim of a hole runs backwards through the patch: for each boundary edge a → b of a
    // face, the patch has b → a. The patch's edges, sorted: (start, end, along a big part).
    let mut patch: Vec<(u32, u32, bool)> = Vec::new();
    let uses = edge_uses(tris);
    for run in uses.chunk_by(|a, b| a.0 == b.0) {
        if let [(key, face, forward)] = run {
            let (lo, hi) = ((key >> 32) as u32, *key as u32);
            let (a, b) = if *forward { (hi, lo) } else { (lo, hi) };
            patch.push((a, b, big[*face as usize]));
        }
    }
    patch.sort_unstable();
    // A vertex with several patch edges leaving it is where holes touch: not a simple loop.
    let leaving = |v: u32| patch.partition_point(|e| e.0 <= v) - patch.partition_point(|e| e.0 < v);
    let mut used = vec![false; patch.len()];
    let mut filled = 0;
    for start in 0..patch.len() {
        if used[start] || leaving(patch[start].0) != 1 {
            continue;
        }
        let mut rim = vec![patch[start].0];
        let mut at = patch[start].1;
        let mut steps = vec![start];
        while at != rim[0] && rim.len() < MOST_HOLE_EDGES && leaving(at) == 1 {
            rim.push(at);
            let i = patch.partition_point(|e| e.0 < at);
            steps.push(i);
            at = patch[i].1;
        }
        if at != rim[0] || steps.iter().any(|&i| used[i] || !patch[i].2) {
            continue;
        }
        // The fan's apex: the first rim vertex none of whose diagonals is an edge already (a
        // third face on it would make it non-manifold).
        let k = rim.len();
        let exists = |a: u32, b: u32| uses.binary_search_by_key(&key(a, b), |u| u.0).is_ok();
        let Some(apex) = (0..k).find(|&a| (2..k - 1).all(|i| !exists(rim[a], rim[(a + i) % k])))
        else {
            continue;
        };
        steps.iter().for_each(|&i| used[i] = true);
        let at = |i: usize| rim[(apex + i) % k];
        tris.extend((1..k - 1).map(|i| [at(0), at(i), at(i + 1)]));
        filled += 1;
    }
    filled
}

/// A position's coordinates as bits, equal exactly for bit-identical positions (−0 as +0).
pub fn position_key(p: DVec3) -> [u64; 3] {
    [p.x, p.y, p.z].map(|c| (c + 0.0).to_bits())
}

/// Whether two of the vertices `ids` (repeats allowed) sit at bit-identical positions.
fn coincident(points: &[DVec3], ids: &[u32]) -> bool {
    let mut ids = ids.to_vec();
    ids.sort_unstable();
    ids.dedup();
    let mut keys: Vec<[u64; 3]> = ids
        .iter()
        .map(|&i| position_key(points[i as usize]))
        .collect();
    keys.sort_unstable();
    keys.windows(2).any(|w| w[0] == w[1])
}

/// Points with bit-identical coordinates merged into the first (−0 and +0 alike), and the map
/// from old to new indices. Order is kept.
fn merge_coincident(points: &[DVec3]) -> (Vec<DVec3>, Vec<u32>) {
    // (coordinates' bits, index), sorted: runs of one position, smallest index first.
    let mut keyed: Vec<([u64; 3], u32)> = (points.iter().enumerate())
        .map(|(i, &p)| (position_key(p), i as u32))
        .collect();
    keyed.sort_unstable();
    // Each point's representative: the first (smallest index) of its run.
    let mut first = vec![0u32; points.len()];
    for run in keyed.chunk_by(|a, b| a.0 == b.0) {
        for &(_, i) in run {
            first[i as usize] = run[0].1;
        }
    }
    let mut remap = vec![0u32; points.len()];
    let mut kept = Vec::with_capacity(points.len());
    for i in 0..points.len() {
        remap[i] = if first[i] as usize == i {
            kept.push(points[i]);
            (kept.len() - 1) as u32
        } else {
            remap[first[i] as usize]
        };
    }
    (kept, remap)
}

/// The faces remapped, without faces that repeat a corner; of faces with the same corners, the
/// first — or, with `walls`, none where they are wound both ways. Also whether any are.
fn distinct_faces(triangles: &[[u32; 3]], remap: &[u32], walls: bool) -> (Vec<[u32; 3]>, bool) {
    let faces: Vec<[u32; 3]> = triangles
        .iter()
        .map(|t| t.map(|v| remap[v as usize]))
        .collect();
    // (corners sorted, wound as sorted (an even permutation of them), face)
    let mut order: Vec<([u32; 3], bool, u32)> = (faces.iter().enumerate())
        .filter(|(_, &[a, b, c])| a != b && b != c && c != a)
        .map(|(f, t)| {
            let mut s = *t;
            s.sort_unstable();
            let k = t.iter().position(|&v| v == s[0]).unwrap_or(0);
            (s, t[(k + 1) % 3] == s[1], f as u32)
        })
        .collect();
    order.sort_unstable_by_key(|&(s, _, f)| (s, f));
    let mut keep = vec![false; faces.len()];
    let mut both_ways = false;
    for run in order.chunk_by(|a, b| a.0 == b.0) {
        let mixed = run.iter().any(|r| r.1 != run[0].1);
        both_ways |= mixed;
        if !(walls && mixed) {
            keep[run[0].2 as usize] = true;
        }
    }
    let kept: Vec<[u32; 3]> = faces
        .iter()
        .zip(&keep)
        .filter(|(_, &k)| k)
        .map(|(t, _)| *t)
        .collect();
    (kept, both_ways)
}

/// Reverses the faces marked.
fn turn(tris: &mut [[u32; 3]], which: &[bool]) {
    for (t, &f) in tris.iter_mut().zip(which) {
        if f {
            t.swap(1, 2);
        }
    }
}

/// Which faces to reverse so that every paired edge (see [`edge_pairs`]) is run once each way,
/// and the parts (faces joined through paired edges). None when a part cannot be wound
/// consistently (a Möbius band).
fn consistent_winding(tris: &[[u32; 3]], pairs: &[Pair]) -> Option<(Vec<bool>, Vec<Vec<u32>>)> {
    // Neighbours across paired edges, as compressed rows: (other face, same direction).
    let mut start = vec![0usize; tris.len() + 1];
    for p in pairs {
        start[p.faces[0] as usize + 1] += 1;
        start[p.faces[1] as usize + 1] += 1;
    }
    for f in 0..tris.len() {
        start[f + 1] += start[f];
    }
    let mut fill = start.clone();
    let mut adjacent = vec![(0u32, false); pairs.len() * 2];
    for &Pair {
        faces: [a, b],
        same,
        ..
    } in pairs
    {
        adjacent[fill[a as usize]] = (b, same);
        fill[a as usize] += 1;
        adjacent[fill[b as usize]] = (a, same);
        fill[b as usize] += 1;
    }
    // Breadth-first over each part: a neighbour that runs the shared edge the same way takes
    // the opposite flip.
    let mut flip = vec![false; tris.len()];
    let mut part = vec![u32::MAX; tris.len()];
    let mut parts: Vec<Vec<u32>> = Vec::new();
    for seed in 0..tris.len() {
        if part[seed] != u32::MAX {
            continue;
        }
        let id = parts.len() as u32;
        let mut faces = vec![seed as u32];
        part[seed] = id;
        let mut i = 0;
        while i < faces.len() {
            let f = faces[i] as usize;
            i += 1;
            for &(g, same) in &adjacent[start[f]..start[f + 1]] {
                let want = flip[f] ^ same;
                if part[g as usize] == u32::MAX {
                    part[g as usize] = id;
                    flip[g as usize] = want;
                    faces.push(g);
                } else if flip[g as usize] != want {
                    return None;
                }
            }
        }
        parts.push(faces);
    }
    Some((flip, parts))
}

/// A closed, oriented mesh of several parts, each turned to face out (or in, where nested an
/// odd number of times): the field signs a mesh by its total volume, so a part wound against
/// the others would be signed inside out. None when every part already faces its way, for one part
/// (its sign follows its volume), and beyond [`MOST_NESTED_PARTS`] parts (nesting unchecked, a
/// hollow part's inner wall would be turned out).
fn facing_parts(points: &[DVec3], tris: &[[u32; 3]]) -> Option<Mended> {
    let mut parts = DisjointSets::new(points.len());
    for t in tris {
        parts.union(t[0], t[1]);
        parts.union(t[1], t[2]);
    }
    let roots: Vec<u32> = tris.iter().map(|t| parts.find(t[0])).collect();
    let mut ids: Vec<u32> = roots.clone();
    ids.sort_unstable();
    ids.dedup();
    if !(2..=MOST_NESTED_PARTS).contains(&ids.len()) {
        return None;
    }
    let mut parts: Vec<Vec<u32>> = vec![Vec::new(); ids.len()];
    for (f, r) in roots.iter().enumerate() {
        let k = ids.binary_search(r).unwrap_or(0);
        parts[k].push(f as u32);
    }
    let flips = outwards(points, tris, &parts, &vec![false; tris.len()]);
    let flipped_faces = flips.iter().filter(|&&f| f).count();
    if flipped_faces == 0 {
        return None;
    }
    let mut tris = tris.to_vec();
    turn(&mut tris, &flips);
    let repairs = Repairs {
        flipped_faces,
        ..Repairs::default()
    };
    Some((points.to_vec(), tris, repairs))
}

/// Faces with an edge not used exactly once each way.
fn open_faces(tris: &[[u32; 3]]) -> Vec<bool> {
    let mut open = vec![false; tris.len()];
    for run in edge_uses(tris).chunk_by(|a, b| a.0 == b.0) {
        if !matches!(run, [a, b] if a.2 != b.2) {
            run.iter().for_each(|u| open[u.1 as usize] = true);
        }
    }
    open
}

/// Which faces to reverse so that every closed part (no face of it `open`) has positive volume,
/// and a closed part inside an odd number of others negative volume.
fn outwards(points: &[DVec3], tris: &[[u32; 3]], parts: &[Vec<u32>], open: &[bool]) -> Vec<bool> {
    let mut flip = vec![false; tris.len()];
    let centre = points.iter().copied().sum::<DVec3>() / points.len().max(1) as f64;
    let wound = |f: u32, flip: &[bool]| {
        let t = tris[f as usize];
        let [a, b, c] = t.map(|v| points[v as usize] - centre);
        if flip[f as usize] {
            [a, c, b]
        } else {
            [a, b, c]
        }
    };
    let closed: Vec<&Vec<u32>> = parts
        .iter()
        .filter(|faces| faces.iter().all(|&f| !open[f as usize]))
        .collect();
    for faces in &closed {
        let volume: f64 = faces
            .iter()
            .map(|&f| {
                let [a, b, c] = wound(f, &flip);
                a.dot(b.cross(c))
            })
            .sum();
        if volume < 0.0 {
            faces.iter().for_each(|&f| flip[f as usize] ^= true);
        }
    }
    if (2..=MOST_NESTED_PARTS).contains(&closed.len()) {
        // Each part's box: a probe outside another's box is outside it (no winding number).
        let boxes: Vec<(DVec3, DVec3)> = closed
            .iter()
            .map(|faces| {
                let corners = faces.iter().flat_map(|&f| wound(f, &flip));
                corners.fold((DVec3::INFINITY, DVec3::NEG_INFINITY), |(lo, hi), q| {
                    (lo.min(q), hi.max(q))
                })
            })
            .collect();
        // A part lies inside another when its box does and so do its probes (the centres of
        // up to 8 faces spread over it): parts that cross each other (a self-intersecting
        // input) are not nested.
        let inner: Vec<bool> = closed
            .iter()
            .zip(&boxes)
            .map(|(faces, (lo, hi))| {
                let probes: Vec<DVec3> = (0..PROBES.min(faces.len()))
                    .map(|k| {
                        let [a, b, c] =
                            wound(faces[k * faces.len() / PROBES.min(faces.len())], &flip);
                        (a + b + c) / 3.0
                    })
                    .collect();
                let depth = closed
                    .iter()
                    .zip(&boxes)
                    .filter(|(other, _)| !std::ptr::eq(**other, *faces))
                    .filter(|(_, (olo, ohi))| lo.cmpge(*olo).all() && hi.cmple(*ohi).all())
                    .filter(|(other, _)| {
                        probes
                            .iter()
                            .all(|&q| winding_number(q, other, &|f| wound(f, &flip)) > 0.5)
                    })
                    .count();
                depth % 2 == 1
            })
            .collect();
        for (faces, inner) in closed.iter().zip(inner) {
            if inner {
                faces.iter().for_each(|&f| flip[f as usize] ^= true);
            }
        }
    }
    flip
}

/// Two faces joined across an edge.
#[derive(Clone, Copy, Debug)]
struct Pair {
    faces: [u32; 2],
    /// Both faces run the edge the same way (one of them must be turned).
    same: bool,
    /// The edge's vertices.
    edge: [u32; 2],
}

/// The faces joined across each edge: the two faces of a two-face edge; around an edge of more
/// faces, the pairs of [`pair_around`] (none where it finds none).
fn edge_pairs(points: &[DVec3], tris: &[[u32; 3]]) -> Vec<Pair> {
    let mut pairs: Vec<Pair> = Vec::new();
    for run in edge_uses(tris).chunk_by(|a, b| a.0 == b.0) {
        let edge = [(run[0].0 >> 32) as u32, run[0].0 as u32];
        match run {
            [a, b] => pairs.push(Pair {
                faces: [a.1, b.1],
                same: a.2 == b.2,
                edge,
            }),
            [_] => {}
            _ => pairs.extend(pair_around(points, tris, edge, run).unwrap_or_default()),
        }
    }
    pairs
}

/// Pairs the faces around an edge used by more than two: sorted by angle about the edge, each
/// face goes with its neighbour on its inner side (the side its normal points away from), as
/// two faces of one solid enclose it. None unless every face's neighbour names it back and
/// each pair runs the edge both ways.
fn pair_around(
    points: &[DVec3],
    tris: &[[u32; 3]],
    [a, b]: [u32; 2],
    run: &[(u64, u32, bool)],
) -> Option<Vec<Pair>> {
    if run.len() % 2 == 1 {
        return None;
    }
    let pa = points[a as usize];
    let axis = (points[b as usize] - pa).normalize_or_zero();
    let x = axis.any_orthonormal_vector();
    let y = axis.cross(x);
    // (angle, face, runs a → b, its inside lies counter-clockwise about the axis)
    let mut around: Vec<(f64, u32, bool, bool)> = run
        .iter()
        .map(|&(_, f, forward)| {
            let t = tris[f as usize];
            let c = t.into_iter().find(|&v| v != a && v != b).unwrap_or(a);
            let d = points[c as usize] - pa;
            let [p0, p1, p2] = t.map(|v| points[v as usize]);
            let n = (p1 - p0).cross(p2 - p0);
            let angle = crate::fmath::atan2(d.dot(y), d.dot(x));
            (angle, f, forward, axis.cross(d).dot(n) < 0.0)
        })
        .collect();
    around.sort_by(|p, q| p.0.total_cmp(&q.0).then(p.1.cmp(&q.1)));
    let k = around.len();
    let partner = |i: usize| {
        if around[i].3 {
            (i + 1) % k
        } else {
            (i + k - 1) % k
        }
    };
    let mut pairs = Vec::with_capacity(k / 2);
    for i in 0..k {
        let j = partner(i);
        if partner(j) != i || around[i].2 == around[j].2 {
            return None;
        }
        if i < j {
            pairs.push(Pair {
                faces: [around[i].1, around[j].1],
                same: false,
                edge: [a, b],
            });
        }
    }
    Some(pairs)
}

/// Gives each fan of faces about a vertex (faces joined through paired edges at it) a vertex of
/// its own: the first fan in corner order keeps the vertex, each other fan gets a copy at the
/// same position, appended. Returns the points and the number of copies.
fn split_fans(
    mut points: Vec<DVec3>,
    tris: &mut [[u32; 3]],
    pairs: &[Pair],
) -> (Vec<DVec3>, usize) {
    let mut fans = DisjointSets::new(tris.len() * 3);
    let corner = |f: u32, v: u32| {
        let k = tris[f as usize].iter().position(|&w| w == v).unwrap_or(0);
        f * 3 + k as u32
    };
    for p in pairs {
        for v in p.edge {
            let (x, y) = (corner(p.faces[0], v), corner(p.faces[1], v));
            fans.union(x, y);
        }
    }
    let mut vertex_of = vec![u32::MAX; fans.len()];
    let mut taken = vec![false; points.len()];
    let mut copies = 0;
    for c in 0..fans.len() {
        let root = fans.find(c as u32) as usize;
        let (f, k) = (c / 3, c % 3);
        if vertex_of[root] == u32::MAX {
            let v = tris[f][k] as usize;
            vertex_of[root] = if taken[v] {
                points.push(points[v]);
                copies += 1;
                (points.len() - 1) as u32
            } else {
                taken[v] = true;
                v as u32
            };
        }
        tris[f][k] = vertex_of[root];
    }
    (points, copies)
}

/// The generalised winding number of the closed surface `faces` about `p` (1 inside an outward
/// surface, 0 outside), by the solid angles of its triangles (Van Oosterom & Strackee 1983).
fn winding_number(p: DVec3, faces: &[u32], corners: &dyn Fn(u32) -> [DVec3; 3]) -> f64 {
    let total: f64 = faces
        .iter()
        .map(|&f| {
            let [a, b, c] = corners(f).map(|q| q - p);
            let (la, lb, lc) = (a.length(), b.length(), c.length());
            let numerator = a.dot(b.cross(c));
            let denominator = la * lb * lc + a.dot(b) * lc + b.dot(c) * la + c.dot(a) * lb;
            2.0 * crate::fmath::atan2(numerator, denominator)
        })
        .sum();
    total / (4.0 * std::f64::consts::PI)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::icosphere::icosphere;
    use crate::mesh::closed_topology;

    fn sphere(r: f64) -> (Vec<DVec3>, Vec<[u32; 3]>) {
        let s = icosphere(2, r, DVec3::ZERO).unwrap();
        (s.positions().to_vec(), s.triangles())
    }

    fn volume(p: &[DVec3], t: &[[u32; 3]]) -> f64 {
        t.iter()
            .map(|t| {
                let [a, b, c] = t.map(|v| p[v as usize]);
                a.dot(b.cross(c)) / 6.0
            })
            .sum()
    }

    #[test]
    fn a_closed_oriented_mesh_is_left_alone() {
        let (p, t) = sphere(1.0);
        assert!(repair(&p, &t).is_none());
        // Inward-wound but consistent: also closed and oriented as far as edges go.
        let inward: Vec<[u32; 3]> = t.iter().map(|f| [f[0], f[2], f[1]]).collect();
        assert!(repair(&p, &inward).is_none());
    }

    #[test]
    fn flipped_unwelded_and_repeated_faces_give_back_the_sphere() {
        let (p, t) = sphere(1.0);
        // Every face with its own corners, every third face flipped, every fifth repeated.
        let mut soup_p = Vec::new();
        let mut soup_t = Vec::new();
        for (i, f) in t.iter().enumerate() {
            let base = soup_p.len() as u32;
            soup_p.extend(f.map(|v| p[v as usize]));
            let face = if i % 3 == 0 {
                [base, base + 2, base + 1]
            } else {
                [base, base + 1, base + 2]
            };
            soup_t.push(face);
            if i % 5 == 0 {
                soup_t.push([face[0], face[2], face[1]]);
            }
        }
        let (rp, rt, r) = repair(&soup_p, &soup_t).expect("repaired");
        assert_eq!(rp.len(), p.len());
        assert_eq!(rt.len(), t.len());
        assert_eq!(r.merged_vertices, soup_p.len() - p.len());
        assert_eq!(r.dropped_faces, soup_t.len() - t.len());
        let topo = closed_topology(rp.len(), &rt).expect("closed and oriented");
        assert_eq!((topo.genus, topo.components), (0, 1));
        assert!((volume(&rp, &rt) - volume(&p, &t)).abs() < 1e-12);
    }

    #[test]
    fn a_hollow_ball_keeps_its_inner_wall_inwards() {
        let (p, t) = sphere(1.0);
        let n = p.len() as u32;
        // Outer sphere wound inwards, one face flipped; inner sphere (radius 0.5) outwards.
        let mut pts = p.clone();
        pts.extend(p.iter().map(|&q| 0.5 * q));
        let mut tris: Vec<[u32; 3]> = t.iter().map(|f| [f[0], f[2], f[1]]).collect();
        tris[7] = t[7];
        tris.extend(t.iter().map(|f| f.map(|v| v + n)));
        let (rp, rt, r) = repair(&pts, &tris).expect("repaired");
        assert_eq!(r.flipped_faces, t.len() * 2 - 1);
        let outer = volume(&rp, &rt[..t.len()]);
        let inner = volume(&rp, &rt[t.len()..]);
        assert!(outer > 0.0 && inner < 0.0, "{outer} {inner}");
        assert!(closed_topology(rp.len(), &rt).is_some());
    }

    /// An axis-aligned box from `lo` to `hi`, wound outwards, as its own 8 corners.
    fn cube(lo: DVec3, hi: DVec3) -> (Vec<DVec3>, Vec<[u32; 3]>) {
        let p = (0..8)
            .map(|i| {
                DVec3::new(
                    if i & 1 == 0 { lo.x } else { hi.x },
                    if i & 2 == 0 { lo.y } else { hi.y },
                    if i & 4 == 0 { lo.z } else { hi.z },
                )
            })
            .collect();
        let t = vec![
            [0, 2, 1],
            [1, 2, 3],
            [4, 5, 6],
            [5, 7, 6],
            [0, 1, 4],
            [1, 5, 4],
            [2, 6, 3],
            [3, 6, 7],
            [0, 4, 2],
            [2, 4, 6],
            [1, 3, 5],
            [3, 7, 5],
        ];
        (p, t)
    }

    /// Two boxes, their shared corners welded (as the STL reader welds them).
    fn two(
        a: (Vec<DVec3>, Vec<[u32; 3]>),
        b: (Vec<DVec3>, Vec<[u32; 3]>),
    ) -> (Vec<DVec3>, Vec<[u32; 3]>) {
        let n = a.0.len() as u32;
        let (p, remap) = merge_coincident(&[a.0, b.0].concat());
        let t =
            a.1.into_iter()
                .chain(b.1.into_iter().map(|f| f.map(|v| v + n)))
                .map(|f| f.map(|v| remap[v as usize]))
                .collect();
        (p, t)
    }

    #[test]
    fn boxes_touching_along_an_edge_become_two_closed_parts() {
        let unit = cube(DVec3::ZERO, DVec3::ONE);
        assert!(closed_topology(8, &unit.1).is_some_and(|t| t.genus == 0));
        // Along the edge x = y = 1: that edge has four faces once the corners are merged.
        let (p, t) = two(
            unit.clone(),
            cube(DVec3::new(1.0, 1.0, 0.0), DVec3::new(2.0, 2.0, 1.0)),
        );
        let (rp, rt, r) = repair(&p, &t).expect("repaired");
        assert_eq!(
            (r.merged_vertices, r.split_vertices, r.flipped_faces),
            (0, 2, 0)
        );
        let topo = closed_topology(rp.len(), &rt).expect("closed and oriented");
        assert_eq!((topo.components, rp.len()), (2, 16));
        assert!((volume(&rp, &rt) - 2.0).abs() < 1e-12);
        // At the corner (1, 1, 1): no edge is shared, every edge has its two faces, and the
        // field can sign it as it is: left alone.
        let (p, t) = two(unit.clone(), cube(DVec3::ONE, DVec3::splat(2.0)));
        assert!(repair(&p, &t).is_none());
        // Along the edge, with the second box wound inwards: its faces name the wrong sides and
        // the pairing is not mutual, but each box's fan at the edge is its own: split, they are
        // two closed boxes again, and the second is turned outwards.
        let inward = cube(DVec3::new(1.0, 1.0, 0.0), DVec3::new(2.0, 2.0, 1.0));
        let inward = (
            inward.0,
            inward.1.iter().map(|f| [f[0], f[2], f[1]]).collect(),
        );
        let (p, t) = two(unit, inward);
        let (rp, rt, r) = repair(&p, &t).expect("repaired");
        assert_eq!((r.split_vertices, r.flipped_faces), (2, 12));
        assert_eq!(
            closed_topology(rp.len(), &rt).map(|t| t.components),
            Some(2)
        );
        assert!((volume(&rp, &rt) - 2.0).abs() < 1e-12);
    }

    #[test]
    fn closed_parts_wound_against_each_other_are_turned_their_way() {
        let (p, t) = sphere(1.0);
        let n = p.len() as u32;
        let shifted = |d: DVec3| p.iter().map(move |&q| q + d);
        // Two spheres apart, the second wound inwards: it is turned out.
        let pts: Vec<DVec3> = p.iter().copied().chain(shifted(DVec3::X * 3.0)).collect();
        let mut tris = t.clone();
        tris.extend(t.iter().map(|f| [f[0] + n, f[2] + n, f[1] + n]));
        let (_, rt, r) = repair(&pts, &tris).expect("turned");
        assert_eq!((r.flipped_faces, r.merged_vertices), (t.len(), 0));
        assert!(volume(&pts, &rt[t.len()..]) > 0.0);
        // A hollow ball, both walls outwards: the inner wall is turned in.
        let pts: Vec<DVec3> = p
            .iter()
            .copied()
            .chain(p.iter().map(|&q| 0.5 * q))
            .collect();
        let mut tris = t.clone();
        tris.extend(t.iter().map(|f| f.map(|v| v + n)));
        let (_, rt, r) = repair(&pts, &tris).expect("turned");
        assert_eq!(r.flipped_faces, t.len());
        assert!(volume(&pts, &rt[..t.len()]) > 0.0 && volume(&pts, &rt[t.len()..]) < 0.0);
        // ... and as it should be, left alone.
        assert!(repair(&pts, &rt).is_none());
        // Two spheres crossing each other (a self-intersecting input), both facing out: neither
        // lies inside the other, nothing is turned.
        let pts: Vec<DVec3> = p.iter().copied().chain(shifted(DVec3::X)).collect();
        let mut tris = t.clone();
        tris.extend(t.iter().map(|f| f.map(|v| v + n)));
        assert!(repair(&pts, &tris).is_none());
    }

    #[test]
    fn boxes_sharing_a_face_lose_the_wall_between_them() {
        // The app's box soup: two unit cubes side by side, each listing the square they share.
        let unit = cube(DVec3::ZERO, DVec3::ONE);
        let (p, t) = two(unit, cube(DVec3::X, DVec3::new(2.0, 1.0, 1.0)));
        let (rp, rt, r) = repair(&p, &t).expect("repaired");
        assert_eq!(
            (r.dropped_faces, r.split_vertices, r.flipped_faces),
            (4, 0, 0)
        );
        let topo = closed_topology(rp.len(), &rt).expect("closed and oriented");
        assert_eq!((topo.genus, topo.components, rt.len()), (0, 1, 20));
        assert!((volume(&rp, &rt) - 2.0).abs() < 1e-12);
    }

    /// Random soups over a few shared positions (repeats, fans, both windings): mending never
    /// panics, and what it returns has no inconsistent edge and the same positions.
    #[test]
    fn random_soups_mend_or_are_left_alone() {
        let mut rng = crate::demo::Rng::new(17);
        for case in 0..300 {
            let n = 4 + case % 9;
            let p: Vec<DVec3> = (0..n)
                .map(|i| {
                    // A few coincident pairs.
                    let k = if i % 5 == 4 { i - 1 } else { i } as f64;
                    DVec3::new(crate::fmath::sin(k), crate::fmath::cos(2.0 * k), 0.3 * k)
                })
                .collect();
            let t: Vec<[u32; 3]> = (0..2 + case % 23)
                .map(|_| [0, 1, 2].map(|_| (rng.uniform() * n as f64) as u32 % n as u32))
                .collect();
            if let Some((rp, rt, _)) = repair(&p, &t) {
                assert_eq!(edge_defects(&rt).1, 0, "case {case}");
                assert!(rp.iter().all(|q| p.contains(q)), "case {case}");
            }
        }
    }

    #[test]
    fn what_cannot_be_mended_is_not_touched() {
        let (p, t) = sphere(1.0);
        // A third face on an edge stays non-manifold: no repair.
        let mut three = t.clone();
        let [a, b, _] = t[0];
        let mut pts = p.clone();
        pts.push(DVec3::new(3.0, 0.0, 0.0));
        three.push([a, b, p.len() as u32]);
        assert!(repair(&pts, &three).is_none());
        // An opening larger than a few faces (a cap cut away) stays open.
        let cut: Vec<[u32; 3]> = t
            .iter()
            .filter(|f| f.iter().map(|&v| p[v as usize].z).sum::<f64>() < 3.0 * 0.7)
            .copied()
            .collect();
        let (closure, _) = crate::mesh::stars::closure_and_rims(&cut);
        assert!(closure.boundary_edges > MOST_HOLE_EDGES);
        assert!(repair(&p, &cut).is_none());
    }

    #[test]
    fn small_holes_are_closed_large_ones_left() {
        let (p, t) = sphere(1.0);
        // One face missing, and the five around a vertex elsewhere: two small holes.
        let fan: Vec<usize> = (0..t.len()).filter(|&f| t[f].contains(&11)).collect();
        let holey: Vec<[u32; 3]> = (1..t.len())
            .filter(|f| !fan.contains(f))
            .map(|f| t[f])
            .collect();
        assert!(!t[0].contains(&11));
        let (rp, rt, r) = repair(&p, &holey).expect("closed");
        assert_eq!((r.filled_holes, rt.len()), (2, t.len() - 2));
        // Closed and oriented, genus 0 (the fan's centre is left unused).
        assert_eq!(edge_defects(&rt), (0, 0));
        let mut used: Vec<u32> = rt.iter().flatten().copied().collect();
        used.sort_unstable();
        used.dedup();
        assert_eq!(used.len() + rt.len() - 3 * rt.len() / 2, 2);
        assert!(volume(&rp, &rt) > 0.9 * volume(&p, &t));
    }
}
