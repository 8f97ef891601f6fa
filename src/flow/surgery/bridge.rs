//! Surgery on facing patches of a closed surface: two patches that face each other are cut out
//! and their boundary loops glued with a tube (genus +1, or one component less when the patches
//! lie on two components); a ring-shaped patch that faces itself (a neck pinching in empty
//! space) is cut out and both its loops capped (one component more, or genus −1).
//!
//! The patches are the facing vertices found by [`super::detect::facing_pairs`], grouped into
//! connected regions of the surface; a region is cut only when its faces form a disk (one simple
//! boundary loop) and its partners form another such disk. The tube zips the two loops by the
//! shorter diagonal (the classic contour-stitching rule), A forwards and B backwards, so its faces
//! take the orientation of the surface they join.

use crate::mesh::HalfedgeMesh;
use glam::DVec3;

/// What an operation did to the surface.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Cut {
    /// Two patches replaced by a tube.
    Tube,
    /// A neck replaced by two caps.
    Pinch,
}

/// One operation: a tube glued between two patches, or a neck cut and capped.
#[derive(Clone, Debug, PartialEq)]
pub struct Tube {
    /// Which operation.
    pub cut: Cut,
    /// Centroid of the two loops (the hole the tube opens, or the neck cut).
    pub position: DVec3,
    /// Farthest loop vertex from `position`.
    pub radius: f64,
    /// Vertices on the two loops.
    pub loop_vertices: [usize; 2],
    /// The region it was made for (pass it to `skip` to leave that operation out).
    pub region: u32,
    /// A vertex of each side's region (of a pinch: twice the neck's), in the surface operated on.
    pub sides: [u32; 2],
    /// Its new faces: indices into [`Glued::triangles`].
    pub faces: std::ops::Range<usize>,
}

/// The surface after surgery (compacted: vertices of the cut patches removed).
pub struct Glued {
    pub positions: Vec<DVec3>,
    pub triangles: Vec<[u32; 3]>,
    pub tubes: Vec<Tube>,
}

/// A patch spans its hole when the median distance of its rim to the target is below this share
/// of its deepest vertex's (or below `rim`).
const RIM_DEPTH: f64 = 0.5;

/// Regions of at least `min_vertices` paired vertices, matched into (A, B) pairs of distinct,
/// mutually facing regions; each pair is replaced by a tube, and each region facing itself
/// across a neck by two caps. `None` when nothing qualifies.
///
/// A patch is cut only once it spans its hole: the median distance of its rim to the target
/// (`distances` per vertex) below `rim` or below half its deepest vertex's, or once the membranes
/// have `settled` (stopped closing in on each other). Two membranes first touch at one point; a
/// tube cut there would leave the rest of them facing each other around it, and cutting that
/// later would open a second handle through the same hole.
pub fn glue_facing_regions(pass: &Pass) -> Option<Glued> {
    let Pass {
        mesh,
        partner,
        min_vertices,
        skip,
        far,
        mut spare_handles,
        ..
    } = *pass;
    let level = regions(mesh, partner);
    let (region, sizes, seeds) = (&level.of, &level.sizes, &level.seeds);
    let n_regions = sizes.len();
    let votes = level.votes(partner);
    let faces_of = Labels::facing(&votes);
    let mut removed = vec![false; mesh.n_faces()];
    let mut tubes_tris = Vec::new();
    let mut tubes = Vec::new();
    pass.tubes(&level, &faces_of, &mut removed, &mut tubes_tris, &mut tubes);
    // Tangled regions: a membrane that meets several others (the arms of one cavity: a cube
    // drilled along three axes) pairs along a ring, not a disk, and no tube fits it. Each such
    // region is split by the region its vertices face, and the pieces are paired.
    let mut used = vec![false; n_regions];
    for f in (0..mesh.n_faces() as u32).filter(|&f| removed[f as usize]) {
        let [a, b, c] = mesh.face_vertices(f).map(|v| region[v as usize]);
        if let (Some(r), true) = (a, a == b && b == c) {
            used[r as usize] = true;
        }
    }
    let tangled: Vec<bool> = (0..n_regions as u32)
        .map(|r| {
            let mut sheets: Vec<u32> = votes[r as usize]
                .iter()
                .filter(|&&(s, n)| s != r && n >= min_vertices)
                .map(|&(s, _)| far[seeds[s as usize] as usize])
                .collect();
            sheets.sort_unstable();
            sheets.dedup();
            sheets.len() >= 2
                && !used[r as usize]
                && !skip.contains(&r)
                && disk_loop(mesh, region, r, &removed).is_none()
        })
        .collect();
    if tangled.iter().any(|&t| t) {
        let key = |v: usize| -> Option<(u32, u32)> {
            let r = region[v]?;
            let s = region[partner[v]? as usize]?;
            match tangled[r as usize] {
                true => Some((r, s)),
                false if !used[r as usize] && !skip.contains(&r) => Some((r, u32::MAX)),
                false => None,
            }
        };
        let pieces = split(mesh, key, n_regions as u32);
        let faces_of = Labels::facing(&pieces.votes(partner));
        pass.tubes(
            &pieces,
            &faces_of,
            &mut removed,
            &mut tubes_tris,
            &mut tubes,
        );
    }
    // Necks: a ring facing itself across its axis.
    let mut positions = mesh.positions().to_vec();
    for a in 0..n_regions as u32 {
        if faces_of[a as usize] != Some(a) || sizes[a as usize] < min_vertices || skip.contains(&a)
        {
            continue;
        }
        let Some(loops) = region_loops(mesh, region, a, &removed, 0) else {
            continue;
        };
        // No waiting here: the stumps of a neck cut at its thinnest part retract onto the data
        // (or, around nothing, are dropped).
        let [la, lb] = [&loops[0], &loops[1]];
        let centroid =
            |lp: &[u32]| lp.iter().map(|&v| mesh.position(v)).sum::<DVec3>() / lp.len() as f64;
        let (ca, cb) = (centroid(la), centroid(lb));
        // A neck whose loops stay joined round the rest of the surface takes a handle away:
        // only a handle the target lacks, or (its genus unknown) one whose sheets face across
        // the neck (see `faces_across`).
        if joined_beyond(mesh, region, a, la[0], lb[0]) {
            let take = match &mut spare_handles {
                Some(k) => std::mem::replace(k, *k - 1) > 0,
                None => faces_across(mesh, region, partner, a, cb - ca),
            };
            if !take {
                continue;
            }
        }
        remove_region(mesh, region, &[a], &mut removed);
        let start = tubes_tris.len();
        for (lp, away) in [(la, cb - ca), (lb, ca - cb)] {
            tubes_tris.extend(cap(&mut positions, lp, away.normalize_or_zero()));
        }
        let sides = [seeds[a as usize]; 2];
        tubes.push(record(
            mesh,
            Cut::Pinch,
            la,
            lb,
            a,
            sides,
            start..tubes_tris.len(),
        ));
    }
    if tubes.is_empty() {
        return None;
    }
    let mut tris: Vec<[u32; 3]> = (0..mesh.n_faces() as u32)
        .filter(|&f| !mesh.is_deleted_face(f) && !removed[f as usize])
        .map(|f| mesh.face_vertices(f))
        .collect();
    let kept = tris.len();
    for t in &mut tubes {
        t.faces = kept + t.faces.start..kept + t.faces.end;
    }
    tris.extend(tubes_tris);
    let (positions, triangles) = compact(&positions, &tris);
    Some(Glued {
        positions,
        triangles,
        tubes,
    })
}

/// A neck's sheets face each other across its axis: the mean |cos| of the angle between a pair's
/// line and the axis stays below this (0 across, 1 along).
const NECK_ALONG: f64 = 0.5;

/// Whether the vertices of region `r` face their partners across `axis` (the line between its two
/// loops), as a neck's do. The wrap's two sides pressed together round a narrow through-hole also
/// form a ring facing itself: curvature flow squeezed the hole to a thin tube of the outside, which
/// the ring surrounds, and its two sheets face each other along the tube. Capping that ring's loops
/// would fill the hole and lose the handle. Asked only where the target's genus is unknown (a
/// cloud's) and the pinch would not split the surface.
fn faces_across(
    mesh: &HalfedgeMesh,
    region: &[Option<u32>],
    partner: &[Option<u32>],
    r: u32,
    axis: DVec3,
) -> bool {
    let axis = axis.normalize_or_zero();
    let (mut along, mut n) = (0.0, 0usize);
    for (v, p) in partner.iter().enumerate() {
        let (Some(u), true) = (p, region[v] == Some(r)) else {
            continue;
        };
        let d = (mesh.position(*u) - mesh.position(v as u32)).normalize_or_zero();
        along += d.dot(axis).abs();
        n += 1;
    }
    axis != DVec3::ZERO && n > 0 && along < NECK_ALONG * n as f64
}

/// Whether vertices `a` and `b` are joined through faces of `mesh` outside region `r` (a face is
/// in it when all its vertices are): cutting `r` out leaves them on one piece.
fn joined_beyond(mesh: &HalfedgeMesh, region: &[Option<u32>], r: u32, a: u32, b: u32) -> bool {
    let outside = |f: u32| {
        mesh.is_deleted_face(f)
            || mesh
                .face_vertices(f)
                .iter()
                .any(|&v| region[v as usize] != Some(r))
    };
    let mut seen = vec![false; mesh.n_vertices()];
    let mut stack = vec![a];
    seen[a as usize] = true;
    while let Some(v) = stack.pop() {
        if v == b {
            return true;
        }
        for h in mesh.outgoing(v) {
            let u = mesh.to(h);
            let o = HalfedgeMesh::opposite(h);
            let kept = |h: u32| !mesh.is_boundary_halfedge(h) && outside(mesh.face(h));
            if !seen[u as usize] && (kept(h) || kept(o)) {
                seen[u as usize] = true;
                stack.push(u);
            }
        }
    }
    false
}

/// Vertex labels of facing regions, numbered from `first_id` (distinct between the regions and
/// the pieces of tangled ones).
struct Labels {
    of: Vec<Option<u32>>,
    sizes: Vec<usize>,
    /// Each label's first vertex.
    seeds: Vec<u32>,
    first_id: u32,
}

impl Labels {
    /// The name of label `local` (counted from 0) in `skip` and [`Tube::region`]: a region's
    /// number, or a piece's first vertex with [`PIECE`] set (pieces are numbered after what the
    /// first pass used, which a retry may change; their first vertices stay).
    fn name(&self, local: u32) -> u32 {
        match self.first_id {
            0 => local,
            _ => PIECE | self.seeds[local as usize],
        }
    }

    /// The label of vertex `v`, counted from 0.
    fn local(&self, v: usize) -> Option<u32> {
        self.of[v].map(|l| l - self.first_id)
    }

    /// The region each region mostly faces by its `votes` ([`Labels::votes`]; ties to the smaller
    /// label), counted from 0.
    fn facing(votes: &[Vec<(u32, usize)>]) -> Vec<Option<u32>> {
        votes
            .iter()
            .map(|list| {
                list.iter()
                    .max_by_key(|&&(r, c)| (c, std::cmp::Reverse(r)))
                    .map(|&(r, _)| r)
            })
            .collect()
    }

    /// For each region, the regions its vertices' partners lie in and how many lie in each.
    fn votes(&self, partner: &[Option<u32>]) -> Vec<Vec<(u32, usize)>> {
        let mut votes: Vec<Vec<(u32, usize)>> = vec![Vec::new(); self.sizes.len()];
        for (v, p) in partner.iter().enumerate() {
            if let (Some(u), Some(a)) = (p, self.local(v)) {
                if let Some(b) = self.local(*u as usize) {
                    let list = &mut votes[a as usize];
                    match list.iter_mut().find(|(r, _)| *r == b) {
                        Some(e) => e.1 += 1,
                        None => list.push((b, 1)),
                    }
                }
            }
        }
        votes
    }
}

/// Set in the name of a piece of a tangled region (see [`Labels::name`]).
const PIECE: u32 = 1 << 31;

/// What to glue (see [`glue_facing_regions`]).
pub struct Pass<'a> {
    pub mesh: &'a HalfedgeMesh,
    /// Each vertex's facing vertex, if any.
    pub partner: &'a [Option<u32>],
    /// Each vertex's distance to the target.
    pub distances: &'a [f64],
    /// A patch spans its hole once its rim's median distance is below this.
    pub rim: f64,
    /// The membranes stopped closing in on each other: cut them as they are.
    pub settled: bool,
    /// Smallest region cut (vertices).
    pub min_vertices: usize,
    /// Regions left out (see [`Tube::region`]).
    pub skip: &'a [u32],
    /// Each vertex's part in empty space ([`super::detect::far_parts`]).
    pub far: &'a [u32],
    /// Handles the surface has beyond the target's, where the target's genus is known: neck
    /// cuts may take away that many (see [`super::detect::FacingQuery::least_genus`]).
    pub spare_handles: Option<i64>,
}

impl Pass<'_> {
    /// Glues each mutually facing pair of `labels` (`faces_of`: the label each mostly faces)
    /// with a tube, adding the tube's faces and record and marking the regions' faces removed.
    fn tubes(
        &self,
        labels: &Labels,
        faces_of: &[Option<u32>],
        removed: &mut [bool],
        tubes_tris: &mut Vec<[u32; 3]>,
        tubes: &mut Vec<Tube>,
    ) {
        let mesh = self.mesh;
        let d = |v: &u32| self.distances[*v as usize].abs();
        let id = |r: u32| r + labels.first_id;
        let spans = |lp: &[u32], r: u32| {
            let mut rim_d: Vec<f64> = lp.iter().map(d).collect();
            let mid = rim_d.len() / 2;
            let median = *rim_d.select_nth_unstable_by(mid, f64::total_cmp).1;
            let deepest = (0..self.partner.len() as u32)
                .filter(|&v| labels.of[v as usize] == Some(id(r)))
                .map(|v| d(&v))
                .fold(0.0, f64::max);
            self.settled || median < self.rim.max(RIM_DEPTH * deepest)
        };
        for a in 0..labels.sizes.len() as u32 {
            let Some(b) = faces_of[a as usize] else {
                continue;
            };
            if self.skip.contains(&labels.name(a)) || b <= a || faces_of[b as usize] != Some(a) {
                continue;
            }
            if labels.sizes[a as usize] < self.min_vertices
                || labels.sizes[b as usize] < self.min_vertices
            {
                continue;
            }
            let (Some(la), Some(lb)) = (
                disk_loop(mesh, &labels.of, id(a), removed),
                disk_loop(mesh, &labels.of, id(b), removed),
            ) else {
                continue;
            };
            let (la, lb) = (&la[0], &lb[0]);
            if !(spans(la, a) && spans(lb, b)) {
                continue;
            }
            let Some(tube) = zip_loops(mesh, la, lb) else {
                continue;
            };
            remove_region(mesh, &labels.of, &[id(a), id(b)], removed);
            let start = tubes_tris.len();
            tubes_tris.extend(tube);
            let sides = [labels.seeds[a as usize], labels.seeds[b as usize]];
            tubes.push(record(
                mesh,
                Cut::Tube,
                la,
                lb,
                labels.name(a),
                sides,
                start..tubes_tris.len(),
            ));
        }
    }
}

/// The pieces of the paired vertices with equal `key`, connected through edges, labelled from
/// `first_id` in vertex order (deterministic).
fn split(mesh: &HalfedgeMesh, key: impl Fn(usize) -> Option<(u32, u32)>, first_id: u32) -> Labels {
    let n = mesh.n_vertices();
    let mut of = vec![None; n];
    let (mut sizes, mut seeds) = (Vec::new(), Vec::new());
    let mut stack = Vec::new();
    for s in 0..n as u32 {
        let Some(k) = key(s as usize) else { continue };
        if of[s as usize].is_some() {
            continue;
        }
        let id = first_id + sizes.len() as u32;
        seeds.push(s);
        of[s as usize] = Some(id);
        stack.push(s);
        let mut size = 0;
        while let Some(v) = stack.pop() {
            size += 1;
            for u in mesh.neighbors(v) {
                if of[u as usize].is_none() && key(u as usize) == Some(k) {
                    of[u as usize] = Some(id);
                    stack.push(u);
                }
            }
        }
        sizes.push(size);
    }
    Labels {
        of,
        sizes,
        seeds,
        first_id,
    }
}

/// Connected regions of paired vertices (edges between paired vertices), numbered in vertex
/// order (deterministic).
fn regions(mesh: &HalfedgeMesh, partner: &[Option<u32>]) -> Labels {
    split(mesh, |v| partner[v].map(|_| (0, 0)), 0)
}

/// The boundary loop of region `r`'s faces (those with all three vertices in `r`) when they
/// form a disk.
fn disk_loop(
    mesh: &HalfedgeMesh,
    region: &[Option<u32>],
    r: u32,
    removed: &[bool],
) -> Option<Vec<Vec<u32>>> {
    region_loops(mesh, region, r, removed, 1)
}

/// The boundary loops of region `r`'s faces (those with all three vertices in `r`) when they
/// form a connected surface of Euler characteristic `euler` — a disk (1: one loop) or an annulus
/// (0: two loops) — with simple loops of at least three vertices, each in the direction of the
/// region's own halfedges. Faces already `removed` disqualify the region.
fn region_loops(
    mesh: &HalfedgeMesh,
    region: &[Option<u32>],
    r: u32,
    removed: &[bool],
    euler: i64,
) -> Option<Vec<Vec<u32>>> {
    let inside = |f: u32| {
        !mesh.is_deleted_face(f)
            && mesh
                .face_vertices(f)
                .iter()
                .all(|&v| region[v as usize] == Some(r))
    };
    let faces: Vec<u32> = (0..mesh.n_faces() as u32).filter(|&f| inside(f)).collect();
    if faces.is_empty() || faces.iter().any(|&f| removed[f as usize]) {
        return None;
    }
    // Boundary halfedges of the region: in a region face, opposite outside the region.
    let mut next_of = std::collections::BTreeMap::new();
    let mut verts = std::collections::BTreeSet::new();
    let mut interior_edges = 0usize;
    for &f in &faces {
        let h0 = mesh.face_halfedge(f);
        let mut h = h0;
        loop {
            verts.insert(mesh.from(h));
            let o = HalfedgeMesh::opposite(h);
            if mesh.is_boundary_halfedge(o) || !inside(mesh.face(o)) {
                if next_of.insert(mesh.from(h), mesh.to(h)).is_some() {
                    return None; // a loop touches itself at a vertex
                }
            } else {
                interior_edges += 1;
            }
            h = mesh.next(h);
            if h == h0 {
                break;
            }
        }
    }
    let edges = interior_edges / 2 + next_of.len();
    if verts.len() as i64 - edges as i64 + faces.len() as i64 != euler {
        return None;
    }
    let mut loops = Vec::new();
    let mut seen = std::collections::BTreeSet::new();
    for &first in next_of.keys() {
        if !seen.insert(first) {
            continue;
        }
        let mut lp = vec![first];
        let mut v = next_of[&first];
        while v != first {
            if !seen.insert(v) {
                return None;
            }
            lp.push(v);
            v = *next_of.get(&v)?;
        }
        if lp.len() < 3 {
            return None;
        }
        loops.push(lp);
    }
    // A connected region with χ = 2 − 2g − b: one loop for a disk, two for an annulus.
    (loops.len() as i64 == 2 - euler && connected(mesh, &faces, &inside)).then_some(loops)
}

/// Whether `faces` are edge-connected through faces for which `inside` holds.
fn connected(mesh: &HalfedgeMesh, faces: &[u32], inside: &impl Fn(u32) -> bool) -> bool {
    let mut seen = std::collections::BTreeSet::from([faces[0]]);
    let mut stack = vec![faces[0]];
    while let Some(f) = stack.pop() {
        let h0 = mesh.face_halfedge(f);
        let mut h = h0;
        loop {
            let o = HalfedgeMesh::opposite(h);
            if !mesh.is_boundary_halfedge(o) {
                let g = mesh.face(o);
                if inside(g) && seen.insert(g) {
                    stack.push(g);
                }
            }
            h = mesh.next(h);
            if h == h0 {
                break;
            }
        }
    }
    seen.len() == faces.len()
}

/// Marks the faces with all three vertices in one of `regions` as removed.
fn remove_region(
    mesh: &HalfedgeMesh,
    region: &[Option<u32>],
    regions: &[u32],
    removed: &mut [bool],
) {
    for f in 0..mesh.n_faces() as u32 {
        if !mesh.is_deleted_face(f) {
            let r = mesh.face_vertices(f).map(|v| region[v as usize]);
            if regions.iter().any(|&x| r.iter().all(|&y| y == Some(x))) {
                removed[f as usize] = true;
            }
        }
    }
}

/// The record of an operation on loops `a` and `b` (their centroid and the farthest loop vertex)
/// made for region `region` between `sides`, with new faces `faces` (indices among the new
/// faces for now).
fn record(
    mesh: &HalfedgeMesh,
    cut: Cut,
    a: &[u32],
    b: &[u32],
    region: u32,
    sides: [u32; 2],
    faces: std::ops::Range<usize>,
) -> Tube {
    let c: DVec3 =
        a.iter().chain(b).map(|&v| mesh.position(v)).sum::<DVec3>() / (a.len() + b.len()) as f64;
    let radius = a
        .iter()
        .chain(b)
        .map(|&v| mesh.position(v).distance(c))
        .fold(0.0, f64::max);
    Tube {
        cut,
        position: c,
        radius,
        loop_vertices: [a.len(), b.len()],
        region,
        sides,
        faces,
    }
}

/// Caps loop `lp` (in its region's halfedge direction) with a fan around a new vertex, appended
/// to `positions`: the loop's centroid moved by half the loop's mean radius along `away` (away
/// from the other stump), so the cap is a shallow cone that stays clear of the cut.
fn cap(positions: &mut Vec<DVec3>, lp: &[u32], away: DVec3) -> Vec<[u32; 3]> {
    let c = lp.iter().map(|&v| positions[v as usize]).sum::<DVec3>() / lp.len() as f64;
    let r = lp
        .iter()
        .map(|&v| positions[v as usize].distance(c))
        .sum::<f64>()
        / lp.len() as f64;
    let c = c + 0.5 * r * away;
    let ci = positions.len() as u32;
    positions.push(c);
    (0..lp.len())
        .map(|i| [lp[i], lp[(i + 1) % lp.len()], ci])
        .collect()
}

/// The tube between loops `a` and `b` (each in its region's halfedge direction): `a` forwards,
/// `b` backwards, with the shortest rungs. A zip is a staircase of rungs (a_i, b_k) from (0, 0)
/// round to (n, m), each step a triangle; for each start of `b` (the [`ZIP_WORK`] / (n·m)
/// nearest to `a[0]`, all of them on small loops) the staircase of least total rung length,
/// within a band about the diagonal, is found by dynamic programming, and the least
/// of those is kept (none past [`ZIP_CELLS`]). A greedy zip (the shorter diagonal from the
/// vertex nearest `a[0]`) twists small, zigzag loops into a tube that crosses itself; so does
/// the least *area* (a twisted tube narrows in the middle: less area, crossing faces). `None`
/// when no zip is valid.
fn zip_loops(mesh: &HalfedgeMesh, a: &[u32], b: &[u32]) -> Option<Vec<[u32; 3]>> {
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
/// Loops with more staircase cells than this (loops of some 4 000 vertices each, far longer
/// than any hole's rim on a wrap of ordinary size) are not zipped: their costs alone would
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

/// Drops unreferenced vertices, keeping the order of the others.
pub(super) fn compact(positions: &[DVec3], tris: &[[u32; 3]]) -> (Vec<DVec3>, Vec<[u32; 3]>) {
    let mut map = vec![u32::MAX; positions.len()];
    for t in tris {
        for &v in t {
            map[v as usize] = 0;
        }
    }
    let mut out = Vec::new();
    for (v, m) in map.iter_mut().enumerate() {
        if *m == 0 {
            *m = out.len() as u32;
            out.push(positions[v]);
        }
    }
    let tris = tris.iter().map(|t| t.map(|v| map[v as usize])).collect();
    (out, tris)
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

    /// The loops of a plate's narrow hole (a dense, noisy cloud of a turned plate), in
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
