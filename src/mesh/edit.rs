//! Local topology edits on the halfedge mesh: edge split, halfedge collapse, edge flip, and the
//! garbage collection that compacts the elements the edits delete.
//!
//! The edits follow PMP's `SurfaceMesh` (split / collapse / flip with deletion flags and a
//! separate compaction), restricted to **interior** edges: LSW's surfaces are closed, and the
//! remesher never edits a boundary edge. Every edit is O(valence); none allocates on the heap
//! except for the amortised growth of the element arrays.
//!
//! Deleted elements stay in the arrays (flagged, see [`HalfedgeMesh::is_deleted_vertex`]) until
//! [`HalfedgeMesh::garbage_collect`] compacts them; in between, whole-mesh functions such as
//! `validate()` must not be used. Per-vertex scalar layers follow the edits: a split vertex gets the
//! mean of the edge's two ends, a collapse keeps the survivor's value, and compaction remaps them.
//!
//! Halfedge conventions used in the docs below: edge `e` owns `2e` and `2e + 1`; for an interior
//! halfedge `h = a→b`, the face left of `h` is `(a, b, c)` and the face left of `opposite(h)` is
//! `(b, a, d)`; `c` and `d` are the edge's *opposite vertices*.

use super::halfedge::{HalfedgeMesh, INVALID};
use glam::DVec3;

/// Index maps produced by [`HalfedgeMesh::garbage_collect`]: `old index → new index`,
/// [`INVALID`] for a deleted element. Callers use them to remap their own per-element arrays.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct GarbageMaps {
    /// New index of every old vertex.
    pub vertices: Vec<u32>,
    /// New index of every old edge (halfedge `h` maps to `2·edges[h/2] + h % 2`).
    pub edges: Vec<u32>,
    /// New index of every old face.
    pub faces: Vec<u32>,
}

impl HalfedgeMesh {
    /// Makes the deletion-flag arrays as long as the element arrays (they start empty).
    fn ensure_flags(&mut self) {
        self.v_deleted.resize(self.positions.len(), false);
        self.e_deleted.resize(self.h_to.len() / 2, false);
        self.f_deleted.resize(self.f_halfedge.len(), false);
    }

    /// Appends a vertex (with every scalar layer set to `value_of(layer)`).
    fn push_vertex(&mut self, p: DVec3, a: u32, b: u32) -> u32 {
        let v = self.positions.len() as u32;
        self.positions.push(p);
        self.v_halfedge.push(INVALID);
        self.v_deleted.push(false);
        for (_, vals) in &mut self.vertex_scalars {
            let m = 0.5 * (vals[a as usize] + vals[b as usize]);
            vals.push(m);
        }
        v
    }

    /// Appends an edge (two halfedges) and returns its index.
    fn push_edge(&mut self) -> u32 {
        let e = (self.h_to.len() / 2) as u32;
        self.h_to.extend([INVALID, INVALID]);
        self.h_next.extend([INVALID, INVALID]);
        self.h_prev.extend([INVALID, INVALID]);
        self.h_face.extend([INVALID, INVALID]);
        self.e_deleted.push(false);
        e
    }

    /// Appends a face and returns its index.
    fn push_face(&mut self, h: u32) -> u32 {
        let f = self.f_halfedge.len() as u32;
        self.f_halfedge.push(h);
        self.f_deleted.push(false);
        f
    }

    #[inline]
    fn link(&mut self, h: u32, n: u32) {
        self.h_next[h as usize] = n;
        self.h_prev[n as usize] = h;
    }

    /// True when edge `e` has a face on both sides.
    #[inline]
    pub fn is_interior_edge(&self, e: u32) -> bool {
        self.h_face[(2 * e) as usize] != INVALID && self.h_face[(2 * e + 1) as usize] != INVALID
    }

    /// True when `v` has an outgoing boundary halfedge (O(valence)).
    pub fn is_boundary_vertex(&self, v: u32) -> bool {
        self.outgoing(v).any(|h| self.is_boundary_halfedge(h))
    }

    /// True when `a` and `b` are joined by an edge (O(valence of `a`)).
    pub fn are_adjacent(&self, a: u32, b: u32) -> bool {
        self.outgoing(a).any(|h| self.to(h) == b)
    }

    /// The halfedge `a→b`, if `a` and `b` are adjacent.
    pub fn find_halfedge(&self, a: u32, b: u32) -> Option<u32> {
        self.outgoing(a).find(|&h| self.to(h) == b)
    }

    /// Splits interior edge `e` at position `p` and returns the new vertex `m`.
    ///
    /// The two faces `(a, b, c)` and `(b, a, d)` become four: `(a, m, c)`, `(m, b, c)`,
    /// `(m, a, d)`, `(b, m, d)`. Edge `e` keeps the half `a–m` (`a = to(2e + 1)`), a new edge holds
    /// `m–b`, and two new edges join `m` to `c` and `d` — in that order, so the three new edge
    /// indices are `n_edges()`, `+1`, `+2` before the call. Per-vertex scalar layers of `m` are the
    /// mean of the ends' values.
    ///
    /// # Panics
    /// If `e` is a boundary edge (LSW's remesher only splits interior edges).
    pub fn split_edge(&mut self, e: u32, p: DVec3) -> u32 {
        assert!(
            self.is_interior_edge(e),
            "split_edge: edge {e} is on the boundary"
        );
        self.ensure_flags();
        let (h0, h1) = (2 * e, 2 * e + 1);
        let (a, b) = (self.to(h1), self.to(h0));
        let (n0, p0) = (self.next(h0), self.prev(h0));
        let (n1, p1) = (self.next(h1), self.prev(h1));
        let (c, d) = (self.to(n0), self.to(n1));
        let (f0, f1) = (self.face(h0), self.face(h1));

        let m = self.push_vertex(p, a, b);
        let e1 = self.push_edge();
        let e2 = self.push_edge();
        let e3 = self.push_edge();
        let (h2, h3) = (2 * e1, 2 * e1 + 1); // m→b, b→m
        let (h4, h5) = (2 * e2, 2 * e2 + 1); // m→c, c→m
        let (h6, h7) = (2 * e3, 2 * e3 + 1); // m→d, d→m
        let f2 = self.push_face(h2);
        let f3 = self.push_face(h3);

        self.h_to[h0 as usize] = m;
        self.h_to[h2 as usize] = b;
        self.h_to[h3 as usize] = m;
        self.h_to[h4 as usize] = c;
        self.h_to[h5 as usize] = m;
        self.h_to[h6 as usize] = d;
        self.h_to[h7 as usize] = m;

        // f0 = (a, m, c)
        self.link(h0, h4);
        self.link(h4, p0);
        self.link(p0, h0);
        // f2 = (m, b, c)
        self.link(h2, n0);
        self.link(n0, h5);
        self.link(h5, h2);
        // f1 = (m, a, d)
        self.link(h1, n1);
        self.link(n1, h7);
        self.link(h7, h1);
        // f3 = (b, m, d)
        self.link(h3, h6);
        self.link(h6, p1);
        self.link(p1, h3);

        for (h, f) in [
            (h4, f0),
            (h2, f2),
            (n0, f2),
            (h5, f2),
            (h7, f1),
            (h3, f3),
            (h6, f3),
            (p1, f3),
        ] {
            self.h_face[h as usize] = f;
        }
        self.f_halfedge[f0 as usize] = h0;
        self.f_halfedge[f1 as usize] = h1;

        self.v_halfedge[m as usize] = h2;
        if self.v_halfedge[b as usize] == h1 {
            self.v_halfedge[b as usize] = h3;
        }
        m
    }

    /// Topological legality of collapsing halfedge `h = v0→v1` (removing `v0`, keeping `v1`).
    ///
    /// Legal when: the edge is interior and not deleted, and not both ends lie on the boundary;
    /// the opposite vertices `c ≠ d`; the link condition holds (the only common neighbours of
    /// `v0` and `v1` are `c` and `d`, so no edge or face is duplicated); `c` and `d` keep
    /// valence ≥ 3; and the mesh is not a tetrahedron (both ends of valence 3), whose collapse
    /// would leave a two-face "pillow".
    /// Geometry (fold-overs) is not checked here; see [`HalfedgeMesh::collapse_flips_faces`].
    pub fn is_collapse_ok(&self, h: u32) -> bool {
        let e = h >> 1;
        if self.is_deleted_edge(e) || !self.is_interior_edge(e) {
            return false;
        }
        let o = h ^ 1;
        let (v0, v1) = (self.from(h), self.to(h));
        let c = self.to(self.next(h));
        let d = self.to(self.next(o));
        if c == d {
            return false;
        }
        if !self.valence_exceeds(c, 3) || !self.valence_exceeds(d, 3) {
            return false;
        }
        // An interior edge between two boundary vertices: collapsing it pinches the surface.
        if self.is_boundary_vertex(v0) && self.is_boundary_vertex(v1) {
            return false;
        }
        // v1's one-ring on the stack (valences are small); a huge valence takes the slow path.
        let mut ring1 = [0u32; 32];
        let mut n1 = 0usize;
        for h1 in self.outgoing(v1) {
            if n1 == ring1.len() {
                return self.is_collapse_ok_slow(v0, v1, c, d);
            }
            ring1[n1] = self.to(h1);
            n1 += 1;
        }
        let mut n0 = 0usize;
        for h0 in self.outgoing(v0) {
            n0 += 1;
            let w = self.to(h0);
            if w == v1 || w == c || w == d {
                continue;
            }
            // Link condition: common neighbours must be exactly {c, d}.
            if ring1[..n1].contains(&w) {
                return false;
            }
        }
        n0 > 3 || n1 > 3
    }

    /// `valence(v) > k`, stopping after `k + 1` edges.
    #[inline]
    fn valence_exceeds(&self, v: u32, k: usize) -> bool {
        self.outgoing(v).take(k + 1).count() > k
    }

    fn is_collapse_ok_slow(&self, v0: u32, v1: u32, c: u32, d: u32) -> bool {
        let (val0, val1) = (self.valence(v0), self.valence(v1));
        if val0 <= 3 && val1 <= 3 {
            return false;
        }
        for h0 in self.outgoing(v0) {
            let w = self.to(h0);
            if w == v1 || w == c || w == d {
                continue;
            }
            if self.are_adjacent(w, v1) {
                return false;
            }
        }
        true
    }

    /// True when moving `from(h)` onto `p` (as a collapse of `h` would, with `p` the survivor's
    /// position) turns the normal of a remaining face around `from(h)` by more than the angle
    /// whose cosine is `min_cos`, or makes such a face degenerate (area below `min_area`).
    pub fn collapse_flips_faces(&self, h: u32, p: DVec3, min_cos: f64, min_area: f64) -> bool {
        let v0 = self.from(h);
        let v1 = self.to(h);
        let x0 = self.position(v0);
        for ho in self.outgoing(v0) {
            let f = self.face(ho);
            if f == INVALID {
                continue;
            }
            let hn = self.next(ho);
            let (a, b) = (self.to(ho), self.to(hn));
            if a == v1 || b == v1 {
                continue; // one of the two faces that vanish
            }
            let (pa, pb) = (self.position(a), self.position(b));
            let n_old = (pa - x0).cross(pb - x0);
            let n_new = (pa - p).cross(pb - p);
            let len_new = n_new.length();
            if 0.5 * len_new <= min_area {
                return true;
            }
            let len_old = n_old.length();
            if len_old > 0.0 && n_old.dot(n_new) < min_cos * len_old * len_new {
                return true;
            }
        }
        false
    }

    /// Collapses halfedge `h = v0→v1`: `v0` is removed, `v1` keeps its position and scalar
    /// values, and the two faces beside the edge vanish. Of the two edges of each vanishing face
    /// that merge, the one through `v0` survives (edge of `prev(h)` and of `next(opposite(h))`)
    /// and the one through `v1` is deleted (edge of `next(h)` and of `prev(opposite(h))`).
    ///
    /// Call [`HalfedgeMesh::is_collapse_ok`] first: an illegal collapse corrupts the mesh.
    pub fn collapse_edge(&mut self, h: u32) {
        debug_assert!(self.is_collapse_ok(h), "illegal collapse of halfedge {h}");
        self.ensure_flags();
        let o = h ^ 1;
        let (v0, v1) = (self.from(h), self.to(h));
        let (hn, hp) = (self.next(h), self.prev(h));
        let (on, op) = (self.next(o), self.prev(o));
        let (fh, fo) = (self.face(h), self.face(o));
        let (vl, vr) = (self.to(hn), self.to(on));

        // Every halfedge into v0 now ends at v1.
        let start = self.v_halfedge[v0 as usize];
        let mut g = start;
        loop {
            self.h_to[(g ^ 1) as usize] = v1;
            g = self.ccw_rotated(g);
            if g == start {
                break;
            }
        }

        // Face fh = (v0, v1, vl) degenerates to the 2-gon {hn: v1→vl, hp: vl→v1}.
        // Drop hn's edge; hp takes the place of opposite(hn) in its face.
        self.replace_in_face(hn ^ 1, hp);
        // Face fo = (v1, v0, vr) degenerates to {on: v1→vr, op: vr→v1}.
        // Drop op's edge; on takes the place of opposite(op) in its face.
        self.replace_in_face(op ^ 1, on);

        self.v_halfedge[v1 as usize] = on;
        self.v_halfedge[vl as usize] = hp;
        self.v_halfedge[vr as usize] = on ^ 1;
        // Keep the convention that a boundary vertex's handle is its boundary halfedge.
        for v in [v1, vl, vr] {
            let b = self.outgoing(v).find(|&g| self.is_boundary_halfedge(g));
            if let Some(b) = b {
                self.v_halfedge[v as usize] = b;
            }
        }

        self.v_deleted[v0 as usize] = true;
        self.v_halfedge[v0 as usize] = INVALID;
        for edge in [h >> 1, hn >> 1, op >> 1] {
            self.e_deleted[edge as usize] = true;
        }
        self.f_deleted[fh as usize] = true;
        self.f_deleted[fo as usize] = true;
        self.n_garbage += 6;
    }

    /// Puts halfedge `new` where `old` is in `old`'s face (links, face, face handle).
    fn replace_in_face(&mut self, old: u32, new: u32) {
        let (n, p, f) = (self.next(old), self.prev(old), self.face(old));
        self.link(p, new);
        self.link(new, n);
        self.h_face[new as usize] = f;
        if f != INVALID && self.f_halfedge[f as usize] == old {
            self.f_halfedge[f as usize] = new;
        }
    }

    /// Topological legality of flipping edge `e`: interior, not deleted, the opposite vertices
    /// `c ≠ d` are not already adjacent (which would duplicate an edge), and both ends keep
    /// valence ≥ 3.
    pub fn is_flip_ok(&self, e: u32) -> bool {
        if self.is_deleted_edge(e) || !self.is_interior_edge(e) {
            return false;
        }
        let (h0, h1) = (2 * e, 2 * e + 1);
        let c = self.to(self.next(h0));
        let d = self.to(self.next(h1));
        if c == d {
            return false;
        }
        if self.valence(self.to(h0)) <= 3 || self.valence(self.to(h1)) <= 3 {
            return false;
        }
        !self.are_adjacent(c, d)
    }

    /// Flips edge `e`: faces `(a, b, c)`, `(b, a, d)` become `(c, a, d)`, `(d, b, c)`; afterwards
    /// halfedge `2e` goes `d→c` and `2e + 1` goes `c→d`. Call [`HalfedgeMesh::is_flip_ok`] first.
    pub fn flip_edge(&mut self, e: u32) {
        debug_assert!(self.is_flip_ok(e), "illegal flip of edge {e}");
        let (h0, h1) = (2 * e, 2 * e + 1);
        let (a, b) = (self.to(h1), self.to(h0));
        let (a1, a2) = (self.next(h0), self.prev(h0)); // b→c, c→a
        let (b1, b2) = (self.next(h1), self.prev(h1)); // a→d, d→b
        let (c, d) = (self.to(a1), self.to(b1));
        let (f0, f1) = (self.face(h0), self.face(h1));
        self.h_to[h0 as usize] = c;
        self.h_to[h1 as usize] = d;
        // f0 = (c, a, d): a2, b1, h0
        self.link(a2, b1);
        self.link(b1, h0);
        self.link(h0, a2);
        // f1 = (d, b, c): b2, a1, h1
        self.link(b2, a1);
        self.link(a1, h1);
        self.link(h1, b2);
        self.h_face[b1 as usize] = f0;
        self.h_face[a1 as usize] = f1;
        self.f_halfedge[f0 as usize] = h0;
        self.f_halfedge[f1 as usize] = h1;
        if self.v_halfedge[a as usize] == h0 {
            self.v_halfedge[a as usize] = b1;
        }
        if self.v_halfedge[b as usize] == h1 {
            self.v_halfedge[b as usize] = a1;
        }
    }

    /// Renumbers vertices in Morton (Z-curve) order of their positions, and edges and faces in
    /// the order they are first met from those vertices, so that neighbours sit close together
    /// in memory. Splits append vertices at the end and many remeshes leave the numbering
    /// scattered (neighbouring indices thousands apart), which makes every one-ring loop a cache
    /// miss. Geometry, connectivity, orientation and scalar layers are unchanged; deterministic.
    /// Returns the `old → new` maps. The mesh must be garbage-free.
    pub fn reorder_spatially(&mut self) -> GarbageMaps {
        assert!(
            !self.has_garbage(),
            "reorder_spatially needs a garbage-free mesh"
        );
        let (nv, ne, nf) = (self.n_vertices(), self.n_edges(), self.n_faces());
        let (lo, hi) = self.bounds();
        let ext = (hi - lo).max_element().max(f64::MIN_POSITIVE);
        // 21 bits per axis, interleaved into a 63-bit key.
        fn spread(mut x: u64) -> u64 {
            x &= 0x1f_ffff;
            x = (x | x << 32) & 0x1f00000000ffff;
            x = (x | x << 16) & 0x1f0000ff0000ff;
            x = (x | x << 8) & 0x100f00f00f00f00f;
            x = (x | x << 4) & 0x10c30c30c30c30c3;
            (x | x << 2) & 0x1249249249249249
        }
        let scale = ((1u64 << 21) - 1) as f64 / ext;
        let mut keyed: Vec<(u64, u32)> = self
            .positions
            .iter()
            .enumerate()
            .map(|(i, p)| {
                let q = (*p - lo) * scale;
                let k = spread(q.x as u64) | spread(q.y as u64) << 1 | spread(q.z as u64) << 2;
                (k, i as u32)
            })
            .collect();
        keyed.sort_unstable();
        let mut vmap = vec![INVALID; nv];
        for (new, &(_, old)) in keyed.iter().enumerate() {
            vmap[old as usize] = new as u32;
        }
        let mut emap = vec![INVALID; ne];
        let mut fmap = vec![INVALID; nf];
        let (mut ne_new, mut nf_new) = (0u32, 0u32);
        for &(_, v) in &keyed {
            for h in self.outgoing(v) {
                let e = (h >> 1) as usize;
                if emap[e] == INVALID {
                    emap[e] = ne_new;
                    ne_new += 1;
                }
                let f = self.h_face[h as usize];
                if f != INVALID && fmap[f as usize] == INVALID {
                    fmap[f as usize] = nf_new;
                    nf_new += 1;
                }
            }
        }
        // Isolated vertices' edges do not exist; any element not met keeps a slot at the end.
        for m in emap.iter_mut().filter(|m| **m == INVALID) {
            *m = ne_new;
            ne_new += 1;
        }
        for m in fmap.iter_mut().filter(|m| **m == INVALID) {
            *m = nf_new;
            nf_new += 1;
        }
        let hm = |h: u32| {
            if h == INVALID {
                INVALID
            } else {
                2 * emap[(h >> 1) as usize] + (h & 1)
            }
        };
        let mut positions = vec![glam::DVec3::ZERO; nv];
        let mut v_halfedge = vec![INVALID; nv];
        for (old, &new) in vmap.iter().enumerate() {
            positions[new as usize] = self.positions[old];
            v_halfedge[new as usize] = hm(self.v_halfedge[old]);
        }
        for (_, vals) in &mut self.vertex_scalars {
            let mut out = vec![0.0; nv];
            for (old, &new) in vmap.iter().enumerate() {
                out[new as usize] = vals[old];
            }
            *vals = out;
        }
        let nh = 2 * ne;
        let (mut h_to, mut h_next, mut h_prev, mut h_face) =
            (vec![0; nh], vec![0; nh], vec![0; nh], vec![0; nh]);
        for old in 0..nh as u32 {
            let new = hm(old) as usize;
            h_to[new] = vmap[self.h_to[old as usize] as usize];
            h_next[new] = hm(self.h_next[old as usize]);
            h_prev[new] = hm(self.h_prev[old as usize]);
            let f = self.h_face[old as usize];
            h_face[new] = if f == INVALID {
                INVALID
            } else {
                fmap[f as usize]
            };
        }
        let mut f_halfedge = vec![INVALID; nf];
        for old in 0..nf {
            f_halfedge[fmap[old] as usize] = hm(self.f_halfedge[old]);
        }
        self.positions = positions;
        self.v_halfedge = v_halfedge;
        self.h_to = h_to;
        self.h_next = h_next;
        self.h_prev = h_prev;
        self.h_face = h_face;
        self.f_halfedge = f_halfedge;
        GarbageMaps {
            vertices: vmap,
            edges: emap,
            faces: fmap,
        }
    }

    /// Removes deleted elements, renumbering the survivors in their old order (so iteration
    /// order stays deterministic), and remaps per-vertex scalar layers. Returns the index maps so
    /// that callers can remap their own per-element data. Cheap no-op when nothing is deleted.
    pub fn garbage_collect(&mut self) -> GarbageMaps {
        let (nv, ne, nf) = (self.n_vertices(), self.n_edges(), self.n_faces());
        if self.n_garbage == 0 {
            let ident = |n: usize| (0..n as u32).collect::<Vec<u32>>();
            return GarbageMaps {
                vertices: ident(nv),
                edges: ident(ne),
                faces: ident(nf),
            };
        }
        self.ensure_flags();
        fn build_map(deleted: &[bool]) -> Vec<u32> {
            let mut next = 0u32;
            deleted
                .iter()
                .map(|&d| {
                    if d {
                        INVALID
                    } else {
                        next += 1;
                        next - 1
                    }
                })
                .collect()
        }
        let vmap = build_map(&self.v_deleted);
        let emap = build_map(&self.e_deleted);
        let fmap = build_map(&self.f_deleted);
        let hmap = |h: u32| -> u32 {
            if h == INVALID {
                INVALID
            } else {
                2 * emap[(h >> 1) as usize] + (h & 1)
            }
        };
        let fm = |f: u32| {
            if f == INVALID {
                INVALID
            } else {
                fmap[f as usize]
            }
        };

        // Vertices.
        let mut w = 0usize;
        for v in 0..nv {
            if vmap[v] == INVALID {
                continue;
            }
            self.positions[w] = self.positions[v];
            self.v_halfedge[w] = hmap(self.v_halfedge[v]);
            for (_, vals) in &mut self.vertex_scalars {
                vals[w] = vals[v];
            }
            w += 1;
        }
        self.positions.truncate(w);
        self.v_halfedge.truncate(w);
        for (_, vals) in &mut self.vertex_scalars {
            vals.truncate(w);
        }
        // Halfedges, edge by edge.
        let mut w = 0usize;
        for (e, &new) in emap.iter().enumerate() {
            if new == INVALID {
                continue;
            }
            for k in 0..2 {
                let (src, dst) = (2 * e + k, 2 * w + k);
                self.h_to[dst] = vmap[self.h_to[src] as usize];
                self.h_next[dst] = hmap(self.h_next[src]);
                self.h_prev[dst] = hmap(self.h_prev[src]);
                self.h_face[dst] = fm(self.h_face[src]);
            }
            w += 1;
        }
        for arr in [
            &mut self.h_to,
            &mut self.h_next,
            &mut self.h_prev,
            &mut self.h_face,
        ] {
            arr.truncate(2 * w);
        }
        // Faces.
        let mut w = 0usize;
        for (f, &new) in fmap.iter().enumerate() {
            if new == INVALID {
                continue;
            }
            self.f_halfedge[w] = hmap(self.f_halfedge[f]);
            w += 1;
        }
        self.f_halfedge.truncate(w);

        self.v_deleted.clear();
        self.e_deleted.clear();
        self.f_deleted.clear();
        self.n_garbage = 0;
        GarbageMaps {
            vertices: vmap,
            edges: emap,
            faces: fmap,
        }
    }
}

#[cfg(test)]
mod tests {
    use crate::geometry::icosphere::icosphere;
    use crate::mesh::HalfedgeMesh;
    use glam::DVec3;

    fn sphere() -> HalfedgeMesh {
        let mut m = icosphere(2, 1.0, DVec3::ZERO).unwrap();
        m.set_vertex_scalar_layer("d", 0.0);
        for (i, x) in m.vertex_scalars_mut("d").unwrap().iter_mut().enumerate() {
            *x = i as f64;
        }
        m
    }

    #[test]
    fn split_keeps_validity_and_interpolates_scalars() {
        let mut m = sphere();
        let (v0, e0, f0) = (m.n_vertices(), m.n_edges(), m.n_faces());
        for e in [0u32, 5, 17, 40] {
            let (a, b) = (m.to(2 * e + 1), m.to(2 * e));
            let p = 0.5 * (m.position(a) + m.position(b));
            let v = m.split_edge(e, p.normalize());
            let d = m.vertex_scalars("d").unwrap();
            assert_eq!(d[v as usize], 0.5 * (d[a as usize] + d[b as usize]));
            m.validate().unwrap();
        }
        assert_eq!(
            (m.n_vertices(), m.n_edges(), m.n_faces()),
            (v0 + 4, e0 + 12, f0 + 8)
        );
        assert_eq!(m.validate().unwrap().euler_characteristic, 2);
    }

    #[test]
    fn flip_keeps_validity_and_is_an_involution_on_counts() {
        let mut m = sphere();
        let before = m.triangles().len();
        let e = 3;
        assert!(m.is_flip_ok(e));
        let (c, d) = (m.to(m.next(2 * e)), m.to(m.next(2 * e + 1)));
        m.flip_edge(e);
        assert_eq!((m.to(2 * e), m.to(2 * e + 1)), (c, d));
        m.validate().unwrap();
        assert_eq!(m.triangles().len(), before);
        // Flipping twice moves the edge on, but keeps the mesh valid.
        m.flip_edge(e);
        m.validate().unwrap();
    }

    #[test]
    fn collapse_and_garbage_collect() {
        let mut m = sphere();
        let d_before: Vec<f64> = m.vertex_scalars("d").unwrap().to_vec();
        let h = 10;
        assert!(m.is_collapse_ok(h));
        let (v0, v1) = (m.from(h), m.to(h));
        m.collapse_edge(h);
        assert!(m.has_garbage() && m.is_deleted_vertex(v0));
        let maps = m.garbage_collect();
        assert!(!m.has_garbage());
        let r = m.validate().unwrap();
        assert_eq!(r.euler_characteristic, 2);
        assert_eq!(maps.vertices[v0 as usize], crate::mesh::INVALID);
        let nv1 = maps.vertices[v1 as usize];
        assert_eq!(
            m.vertex_scalars("d").unwrap()[nv1 as usize],
            d_before[v1 as usize]
        );
        assert_eq!(m.n_vertices(), d_before.len() - 1);
    }

    /// Structural checks that tolerate deleted elements.
    fn check(m: &HalfedgeMesh, round: usize) {
        for e in 0..m.n_edges() as u32 {
            if m.is_deleted_edge(e) {
                continue;
            }
            for h in [2 * e, 2 * e + 1] {
                let (a, b) = (m.from(h), m.to(h));
                assert!(a != b, "round {round}: self-loop edge {e}");
                assert!(
                    !m.is_deleted_vertex(a) && !m.is_deleted_vertex(b),
                    "round {round}: edge {e} to deleted vertex"
                );
                assert_eq!(m.prev(m.next(h)), h, "round {round}");
                assert_eq!(m.next(m.next(m.next(h))), h, "round {round}: non-triangle");
                assert_eq!(m.face(m.next(h)), m.face(h));
                assert!(!m.is_deleted_face(m.face(h)));
                assert!(
                    !m.is_deleted_edge(m.next(h) >> 1),
                    "round {round}: next of {h} deleted"
                );
            }
        }
        for v in 0..m.n_vertices() as u32 {
            if !m.is_deleted_vertex(v) {
                assert_eq!(m.from(m.vertex_halfedge(v)), v, "round {round}: vertex {v}");
                let mut nb: Vec<u32> = m.neighbors(v).collect();
                let n = nb.len();
                nb.sort();
                nb.dedup();
                assert_eq!(nb.len(), n, "round {round}: duplicate neighbour at {v}");
            }
        }
    }

    #[test]
    fn many_random_edits_stay_valid() {
        let mut m = sphere();
        let mut s = 0x2545F4914F6CDD1Du64;
        let mut rnd = move || {
            s ^= s << 13;
            s ^= s >> 7;
            s ^= s << 17;
            s
        };
        for round in 0..300 {
            let e = (rnd() % m.n_edges() as u64) as u32;
            if m.is_deleted_edge(e) {
                continue;
            }
            match round % 3 {
                0 => {
                    let (a, b) = (m.to(2 * e + 1), m.to(2 * e));
                    // Jittered, so that re-splitting a re-created edge cannot duplicate a point.
                    let t = 0.3 + 0.4 * (rnd() % 1000) as f64 / 1000.0;
                    let p = m.position(a).lerp(m.position(b), t).normalize();
                    m.split_edge(e, p);
                }
                1 => {
                    if m.is_flip_ok(e) {
                        m.flip_edge(e);
                    }
                }
                _ => {
                    if m.is_collapse_ok(2 * e) {
                        m.collapse_edge(2 * e);
                    }
                }
            }
            check(&m, round);
            if round % 10 == 9 {
                m.garbage_collect();
                for f in 0..m.n_faces() as u32 {
                    let [a, b, c] = m.face_vertices(f);
                    assert!(
                        a != b && b != c && a != c,
                        "round {round} face {f} {:?}",
                        [a, b, c]
                    );
                    let (_, ar) = m.face_normal_area(f);
                    assert!(
                        ar > 1e-12,
                        "round {round} face {f} {:?} {:?}",
                        [a, b, c],
                        [a, b, c].map(|v| m.position(v))
                    );
                }
                let r = m
                    .validate()
                    .unwrap_or_else(|e| panic!("round {round}: {e}"));
                assert_eq!(r.euler_characteristic, 2);
            }
        }
    }

    #[test]
    fn spatial_reorder_keeps_the_mesh() {
        let mut m = sphere();
        // Scramble the numbering first with splits (appended vertices).
        for e in 0..60 {
            let (a, b) = (m.to(2 * e + 1), m.to(2 * e));
            let p = (0.5 * (m.position(a) + m.position(b))).normalize();
            m.split_edge(e, p);
        }
        let tris_before: std::collections::BTreeSet<[u64; 9]> =
            m.triangles().iter().map(|t| canonical(&m, *t)).collect();
        let d_before: f64 = m.vertex_scalars("d").unwrap().iter().sum();
        let vol = m.signed_volume();
        let maps = m.reorder_spatially();
        m.validate().unwrap();
        let tris_after: std::collections::BTreeSet<[u64; 9]> =
            m.triangles().iter().map(|t| canonical(&m, *t)).collect();
        assert_eq!(tris_before, tris_after);
        assert!((m.signed_volume() - vol).abs() < 1e-12);
        assert_eq!(m.vertex_scalars("d").unwrap().iter().sum::<f64>(), d_before);
        assert_eq!(maps.vertices.len(), m.n_vertices());
    }

    /// A face as its three positions' bits, rotated to start at the smallest (orientation kept).
    fn canonical(m: &HalfedgeMesh, t: [u32; 3]) -> [u64; 9] {
        let p = t.map(|v| m.position(v).to_array().map(f64::to_bits));
        let k = (0..3).min_by_key(|&k| p[k]).unwrap();
        let q = [p[k], p[(k + 1) % 3], p[(k + 2) % 3]];
        [
            q[0][0], q[0][1], q[0][2], q[1][0], q[1][1], q[1][2], q[2][0], q[2][1], q[2][2],
        ]
    }

    #[test]
    fn tetrahedron_cannot_collapse_and_flip_to_existing_edge_is_rejected() {
        let p = vec![DVec3::ZERO, DVec3::X, DVec3::Y, DVec3::Z];
        let m =
            HalfedgeMesh::from_triangles(p, &[[0, 2, 1], [0, 1, 3], [1, 2, 3], [0, 3, 2]]).unwrap();
        for h in 0..m.n_halfedges() as u32 {
            assert!(!m.is_collapse_ok(h));
        }
        for e in 0..m.n_edges() as u32 {
            assert!(!m.is_flip_ok(e));
        }
    }
}
