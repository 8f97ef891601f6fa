//! A bounding-volume hierarchy over triangles or points, with exact closest-point queries and box
//! overlap queries (the acceleration behind distances, back-projection and the self-intersection
//! count).
//!
//! Built top-down by median split along the widest centroid axis (leaves of ≤ 4 primitives);
//! deterministic for a given input. Queries visit the nearer child first and prune by the
//! squared box distance, so results are exact, not approximate.

// `!(x > y)` is used deliberately: it is also true when x is NaN.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

use crate::geometry::predicates::{segment_crosses_triangle, segment_meets_triangle};
use glam::DVec3;

const LEAF_SIZE: usize = 4;

/// One node: its box and either two children or a run of primitives.
#[derive(Clone, Copy, Debug)]
struct Node {
    min: DVec3,
    max: DVec3,
    /// Inner node: index of the left child. Leaf: first index into `order`.
    start: u32,
    /// Leaf: primitive count; 0 for an inner node.
    count: u32,
    /// Inner node: right child.
    right: u32,
}

impl Node {
    /// A node whose box and links the builder fills in later.
    const PLACEHOLDER: Node = Node {
        min: DVec3::ZERO,
        max: DVec3::ZERO,
        start: 0,
        count: 0,
        right: 0,
    };
}

/// A BVH over primitives given by their boxes. Primitive ids are indices into the input.
#[derive(Clone, Debug, Default)]
pub struct Bvh {
    nodes: Vec<Node>,
    order: Vec<u32>,
}

#[inline]
fn box_dist2(p: DVec3, min: DVec3, max: DVec3) -> f64 {
    let d = (min - p).max(p - max).max(DVec3::ZERO);
    d.length_squared()
}

/// The nodes of a tree that splits every range of more than `leaf` primitives at its middle
/// (`len / 2`), as both builders do: the exact capacity of its node list. (A guess of `2n /
/// leaf` is too small, since such leaves hold about `0.6·leaf`, and a list that outgrows its
/// capacity is held twice while it doubles.)
fn halving_tree_nodes(n: usize, leaf: usize) -> usize {
    // The ranges of one level differ in length by one at most: count them by length.
    let mut level = vec![(n, 1usize)];
    let mut total = 0;
    while !level.is_empty() {
        let mut next: Vec<(usize, usize)> = Vec::with_capacity(2);
        for (len, k) in level {
            total += k;
            if len > leaf {
                for half in [len / 2, len - len / 2] {
                    match next.iter_mut().find(|e| e.0 == half) {
                        Some(e) => e.1 += k,
                        None => next.push((half, k)),
                    }
                }
            }
        }
        level = next;
    }
    total
}

/// Spreads the low 21 bits of `v` to every third bit (for 63-bit Morton codes).
fn spread3(v: u64) -> u64 {
    let mut x = v & 0x1f_ffff;
    x = (x | x << 32) & 0x1f00000000ffff;
    x = (x | x << 16) & 0x1f0000ff0000ff;
    x = (x | x << 8) & 0x100f00f00f00f00f;
    x = (x | x << 4) & 0x10c30c30c30c30c3;
    (x | x << 2) & 0x1249249249249249
}

/// Below this many primitives a tree is built on one thread.
const PARALLEL_BUILD: usize = 4096;

/// The boxes a [`Bvh::new`] is built over.
struct Boxes<'a> {
    mins: &'a [DVec3],
    maxs: &'a [DVec3],
    centroids: &'a [DVec3],
}

impl Boxes<'_> {
    /// Fills `node`'s box from the primitives `order` and, unless they fit a leaf, orders them
    /// about the median along the longest axis of their centroids; returns that median index
    /// (None for a leaf).
    fn bound_and_split(&self, order: &mut [u32], node: &mut Node) -> Option<usize> {
        let (mut bmin, mut bmax) = (DVec3::INFINITY, DVec3::NEG_INFINITY);
        let (mut cmin, mut cmax) = (DVec3::INFINITY, DVec3::NEG_INFINITY);
        for &i in order.iter() {
            bmin = bmin.min(self.mins[i as usize]);
            bmax = bmax.max(self.maxs[i as usize]);
            cmin = cmin.min(self.centroids[i as usize]);
            cmax = cmax.max(self.centroids[i as usize]);
        }
        node.min = bmin;
        node.max = bmax;
        if order.len() <= LEAF_SIZE {
            return None;
        }
        let ext = cmax - cmin;
        let axis = if ext.x >= ext.y && ext.x >= ext.z {
            0
        } else if ext.y >= ext.z {
            1
        } else {
            2
        };
        let mid = order.len() / 2;
        order.select_nth_unstable_by(mid, |&a, &b| {
            self.centroids[a as usize][axis]
                .total_cmp(&self.centroids[b as usize][axis])
                .then(a.cmp(&b))
        });
        Some(mid)
    }

    /// [`Boxes::bound_and_split`] for a range too big for a leaf.
    fn split_range(&self, order: &mut [u32], node: &mut Node) -> usize {
        self.bound_and_split(order, node).unwrap_or(order.len())
    }

    /// The nodes of the tree over `order` (which is `offset` into the whole order), its root
    /// first; node links are indices into the returned list.
    fn subtree(&self, order: &mut [u32], offset: usize) -> Vec<Node> {
        let n = order.len();
        let mut nodes = Vec::with_capacity(halving_tree_nodes(n, LEAF_SIZE));
        nodes.push(Node::PLACEHOLDER);
        // Explicit stack: (node index, start, end), relative to `order`.
        let mut stack = vec![(0usize, 0usize, n)];
        while let Some((ni, s, e)) = stack.pop() {
            let mut node = nodes[ni];
            match self.bound_and_split(&mut order[s..e], &mut node) {
                None => {
                    node.start = (offset + s) as u32;
                    node.count = (e - s) as u32;
                    nodes[ni] = node;
                }
                Some(half) => {
                    let left = nodes.len();
                    node.start = left as u32;
                    node.right = left as u32 + 1;
                    node.count = 0;
                    nodes[ni] = node;
                    nodes.push(Node::PLACEHOLDER);
                    nodes.push(Node::PLACEHOLDER);
                    stack.push((left, s, s + half));
                    stack.push((left + 1, s + half, e));
                }
            }
        }
        nodes
    }
}

impl Bvh {
    /// Builds the hierarchy fast, for one-off queries such as a self-overlap pass: primitives
    /// sorted along the Morton curve of their box centres, then split at the middle of each range
    /// (no per-node partitioning). Leaves hold up to `leaf` primitives. Deterministic.
    pub fn new_morton(mins: &[DVec3], maxs: &[DVec3], leaf: usize) -> Self {
        assert_eq!(mins.len(), maxs.len());
        Self::new_morton_with(mins.len(), |i| (mins[i], maxs[i]), leaf)
    }

    /// [`Self::new_morton`] over `n` primitives whose boxes `bounds(i) = (min, max)` are computed
    /// where needed rather than stored: for millions of triangles (a big volume's iso-surface)
    /// the two arrays would take 48 bytes a triangle at the field's peak of memory. The same tree.
    pub fn new_morton_with(
        n: usize,
        bounds: impl Fn(usize) -> (DVec3, DVec3),
        leaf: usize,
    ) -> Self {
        let leaf = leaf.max(1);
        let mut bvh = Bvh {
            nodes: Vec::with_capacity(halving_tree_nodes(n, leaf)),
            order: Vec::with_capacity(n),
        };
        if n == 0 {
            return bvh;
        }
        let (mut lo, mut hi) = (DVec3::INFINITY, DVec3::NEG_INFINITY);
        for i in 0..n {
            let (a, b) = bounds(i);
            let c = 0.5 * (a + b);
            lo = lo.min(c);
            hi = hi.max(c);
        }
        let scale = DVec3::splat((1u64 << 21) as f64 - 1.0) / (hi - lo).max(DVec3::splat(1e-300));
        let mut keyed: Vec<(u64, u32)> = (0..n)
            .map(|i| {
                let (a, b) = bounds(i);
                let q = ((0.5 * (a + b) - lo) * scale).max(DVec3::ZERO);
                let code =
                    spread3(q.x as u64) | spread3(q.y as u64) << 1 | spread3(q.z as u64) << 2;
                (code, i as u32)
            })
            .collect();
        keyed.sort_unstable();
        bvh.order.extend(keyed.iter().map(|k| k.1));
        drop(keyed);
        bvh.nodes.push(Node::PLACEHOLDER);
        // Children are built before their parent's box is needed: a post-order pass over an
        // explicit stack of (node, start, end, children done).
        let mut stack = vec![(0usize, 0usize, n, false)];
        while let Some((ni, s, e, done)) = stack.pop() {
            if e - s <= leaf {
                let (mut bmin, mut bmax) = (DVec3::INFINITY, DVec3::NEG_INFINITY);
                for &i in &bvh.order[s..e] {
                    let (a, b) = bounds(i as usize);
                    bmin = bmin.min(a);
                    bmax = bmax.max(b);
                }
                bvh.nodes[ni] = Node {
                    min: bmin,
                    max: bmax,
                    start: s as u32,
                    count: (e - s) as u32,
                    right: 0,
                };
                continue;
            }
            if done {
                let (l, r) = (bvh.nodes[ni].start as usize, bvh.nodes[ni].right as usize);
                let (a, b) = (bvh.nodes[l], bvh.nodes[r]);
                bvh.nodes[ni].min = a.min.min(b.min);
                bvh.nodes[ni].max = a.max.max(b.max);
                continue;
            }
            let left = bvh.split(ni);
            let mid = s + (e - s) / 2;
            stack.push((ni, s, e, true));
            stack.push((left + 1, mid, e, false));
            stack.push((left, s, mid, false));
        }
        bvh
    }

    /// Builds the hierarchy over boxes `[mins[i], maxs[i]]`: median splits along the longest
    /// axis of the centroids' box. Natively the root's two halves are built on two threads
    /// (the same tree: nodes are only numbered differently).
    pub fn new(mins: &[DVec3], maxs: &[DVec3]) -> Self {
        let n = mins.len();
        let mut order: Vec<u32> = (0..n as u32).collect();
        if n == 0 {
            return Bvh {
                nodes: Vec::new(),
                order,
            };
        }
        let centroids: Vec<DVec3> = mins
            .iter()
            .zip(maxs)
            .map(|(a, b)| 0.5 * (*a + *b))
            .collect();
        let boxes = Boxes {
            mins,
            maxs,
            centroids: &centroids,
        };
        if n < PARALLEL_BUILD {
            let nodes = boxes.subtree(&mut order, 0);
            return Bvh { nodes, order };
        }
        let mut root = Node::PLACEHOLDER;
        let mid = boxes.split_range(&mut order, &mut root);
        let (lower, upper) = order.split_at_mut(mid);
        let (left, right) =
            crate::parallel::beside(|| boxes.subtree(lower, 0), || boxes.subtree(upper, mid));
        let mut nodes = Vec::with_capacity(1 + left.len() + right.len());
        root.start = 1;
        root.right = 1 + left.len() as u32;
        nodes.push(root);
        for (sub, offset) in [(left, 1u32), (right, root.right)] {
            nodes.extend(sub.into_iter().map(|mut node| {
                if node.count == 0 {
                    node.start += offset;
                    node.right += offset;
                }
                node
            }));
        }
        Bvh { nodes, order }
    }

    /// Turns node `ni` into an inner node with two new children (placeholders, filled in by the
    /// caller); returns the left child's index (the right one follows it).
    fn split(&mut self, ni: usize) -> usize {
        let left = self.nodes.len();
        let blank = self.nodes[ni];
        self.nodes.push(blank);
        self.nodes.push(blank);
        let node = &mut self.nodes[ni];
        node.start = left as u32;
        node.right = left as u32 + 1;
        node.count = 0;
        left
    }

    /// True when built over no primitives.
    pub fn is_empty(&self) -> bool {
        self.nodes.is_empty()
    }

    /// The box around every primitive (the root's; zero-sized when empty).
    pub fn bounds(&self) -> (DVec3, DVec3) {
        self.nodes
            .first()
            .map_or((DVec3::ZERO, DVec3::ZERO), |n| (n.min, n.max))
    }

    /// Nearest primitive to `p` under `dist2(id, p)` (an exact squared distance that is at least
    /// the squared distance to the primitive's box). Returns `(id, squared distance)`.
    pub fn nearest(&self, p: DVec3, dist2: impl FnMut(u32) -> f64) -> Option<(u32, f64)> {
        self.nearest_within(p, f64::INFINITY, dist2)
    }

    /// [`Bvh::nearest`] among the primitives with squared distance ≤ `max_d2` (`None` when there
    /// is none): boxes farther than that are never opened, so a query far from everything ends
    /// at once.
    pub fn nearest_within(
        &self,
        p: DVec3,
        max_d2: f64,
        mut dist2: impl FnMut(u32) -> f64,
    ) -> Option<(u32, f64)> {
        if self.nodes.is_empty() {
            return None;
        }
        // Just above the bound, so that a primitive exactly at it is still taken.
        let mut best = (u32::MAX, max_d2 * (1.0 + 1e-12) + f64::MIN_POSITIVE);
        // (node, squared distance to its box), so a popped node is pruned without recomputing.
        let mut stack: [(u32, f64); 64] = [(0, 0.0); 64];
        let mut sp = 1usize;
        while sp > 0 {
            sp -= 1;
            let (ni, d) = stack[sp];
            if d >= best.1 {
                continue;
            }
            let node = &self.nodes[ni as usize];
            if node.count > 0 {
                for &i in &self.order[node.start as usize..(node.start + node.count) as usize] {
                    let d = dist2(i);
                    if d < best.1 || (d == best.1 && i < best.0) {
                        best = (i, d);
                    }
                }
            } else {
                let (l, r) = (node.start, node.right);
                let dl = {
                    let n = &self.nodes[l as usize];
                    box_dist2(p, n.min, n.max)
                };
                let dr = {
                    let n = &self.nodes[r as usize];
                    box_dist2(p, n.min, n.max)
                };
                if sp + 2 > stack.len() {
                    // Unreachable for median-split trees (depth ≤ log2 n + 1).
                    continue;
                }
                // Push the farther child first so the nearer one is popped next.
                let (first, second) = if dl <= dr {
                    ((r, dr), (l, dl))
                } else {
                    ((l, dl), (r, dr))
                };
                stack[sp] = first;
                stack[sp + 1] = second;
                sp += 2;
            }
        }
        (best.0 != u32::MAX).then_some(best)
    }

    /// Calls `f(i, j)` once for every unordered pair of distinct primitives whose boxes overlap
    /// (a dual traversal of the tree against itself: no per-primitive descent from the root),
    /// in a fixed order; `i` and `j` come in no particular order within a pair. Leaf pairs are
    /// reported whole: the primitives' own boxes are not compared.
    pub fn for_each_self_overlap(&self, mut f: impl FnMut(u32, u32)) {
        self.for_each_self_overlap_slots(|a, b| f(self.order[a], self.order[b]));
    }

    /// The primitives in tree order: leaves hold runs of this array (see
    /// [`Bvh::for_each_self_overlap_slots`]).
    pub fn order(&self) -> &[u32] {
        &self.order
    }

    /// [`Bvh::for_each_self_overlap`] by position in [`Bvh::order`] (a caller that copies its
    /// data into that order reads it contiguously).
    pub fn for_each_self_overlap_slots(&self, mut f: impl FnMut(usize, usize)) {
        if self.nodes.is_empty() {
            return;
        }
        let overlap = |a: &Node, b: &Node| !(a.min.cmpgt(b.max).any() || a.max.cmplt(b.min).any());
        let range = |n: &Node| n.start as usize..(n.start + n.count) as usize;
        let mut stack: Vec<(u32, u32)> = vec![(0, 0)];
        while let Some((a, b)) = stack.pop() {
            let (na, nb) = (&self.nodes[a as usize], &self.nodes[b as usize]);
            if a == b {
                if na.count > 0 {
                    for i in range(na) {
                        for j in i + 1..range(na).end {
                            f(i, j);
                        }
                    }
                } else {
                    let (l, r) = (na.start, na.right);
                    stack.push((l, r));
                    stack.push((r, r));
                    stack.push((l, l));
                }
                continue;
            }
            if !overlap(na, nb) {
                continue;
            }
            match (na.count > 0, nb.count > 0) {
                (true, true) => {
                    for i in range(na) {
                        for j in range(nb) {
                            f(i, j);
                        }
                    }
                }
                // Descend into the inner node (the larger box when both are inner).
                (true, false) => {
                    stack.push((a, nb.right));
                    stack.push((a, nb.start));
                }
                (false, true) => {
                    stack.push((na.right, b));
                    stack.push((na.start, b));
                }
                (false, false) => {
                    let va = (na.max - na.min).element_sum();
                    let vb = (nb.max - nb.min).element_sum();
                    if va >= vb {
                        stack.push((na.right, b));
                        stack.push((na.start, b));
                    } else {
                        stack.push((a, nb.right));
                        stack.push((a, nb.start));
                    }
                }
            }
        }
    }

    /// Calls `f(id)` for every primitive whose box overlaps `[min, max]`, in a fixed order.
    pub fn for_each_overlap(&self, min: DVec3, max: DVec3, mut f: impl FnMut(u32)) {
        if self.nodes.is_empty() {
            return;
        }
        let mut stack: [u32; 64] = [0; 64];
        let mut sp = 1usize;
        while sp > 0 {
            sp -= 1;
            let node = &self.nodes[stack[sp] as usize];
            if node.min.cmpgt(max).any() || node.max.cmplt(min).any() {
                continue;
            }
            if node.count > 0 {
                for &i in &self.order[node.start as usize..(node.start + node.count) as usize] {
                    f(i);
                }
            } else if sp + 2 <= stack.len() {
                stack[sp] = node.right;
                stack[sp + 1] = node.start;
                sp += 2;
            }
        }
    }
}

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

/// A BVH over points, for nearest-neighbour distances to a point cloud.
#[derive(Clone, Debug, Default)]
pub struct PointBvh {
    bvh: Bvh,
    points: Vec<DVec3>,
}

impl PointBvh {
    /// Builds the hierarchy over `points`.
    pub fn new(points: &[DVec3]) -> Self {
        Self {
            bvh: Bvh::new(points, points),
            points: points.to_vec(),
        }
    }
    /// Index of and squared distance to the nearest point (`None` if there are no points).
    pub fn nearest(&self, p: DVec3) -> Option<(u32, f64)> {
        self.bvh
            .nearest(p, |i| (self.points[i as usize] - p).length_squared())
    }
    /// [`PointBvh::nearest`] among the points within squared distance `max_d2` of `p`.
    pub fn nearest_within(&self, p: DVec3, max_d2: f64) -> Option<(u32, f64)> {
        self.bvh.nearest_within(p, max_d2, |i| {
            (self.points[i as usize] - p).length_squared()
        })
    }
    /// Nearest point other than point `me` (index and squared distance).
    pub fn nearest_other(&self, p: DVec3, me: u32) -> Option<(u32, f64)> {
        self.bvh.nearest(p, |i| {
            if i == me {
                f64::INFINITY
            } else {
                (self.points[i as usize] - p).length_squared()
            }
        })
    }
    /// Distance to the nearest point (∞ if there are none).
    pub fn distance(&self, p: DVec3) -> f64 {
        self.nearest(p).map_or(f64::INFINITY, |(_, d)| d.sqrt())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Both builders fill their node lists exactly to the capacity counted up front: no list
    /// outgrows it (and doubles), none is left half empty.
    #[test]
    fn the_node_lists_are_counted_exactly() {
        let mut seed = 3u64;
        let mut rnd = move || {
            seed = seed.wrapping_mul(6364136223846793005).wrapping_add(1);
            (seed >> 11) as f64 / (1u64 << 53) as f64
        };
        for n in [1, 2, 4, 5, 7, 100, 1000, 4095, 4096, 10_007, 65_536] {
            let mins: Vec<DVec3> = (0..n).map(|_| DVec3::new(rnd(), rnd(), rnd())).collect();
            let maxs: Vec<DVec3> = mins.iter().map(|&m| m + 0.01).collect();
            for leaf in [1, 2, 4] {
                let bvh = Bvh::new_morton(&mins, &maxs, leaf);
                assert_eq!(bvh.nodes.len(), halving_tree_nodes(n, leaf), "{n} {leaf}");
                assert_eq!(bvh.nodes.capacity(), bvh.nodes.len(), "{n} {leaf}");
            }
            let bvh = Bvh::new(&mins, &maxs);
            assert_eq!(bvh.nodes.len(), halving_tree_nodes(n, LEAF_SIZE), "{n}");
        }
        // By hand: 9 primitives in leaves of up to 2 split 4 + 5, then 2 + 2 and 2 + 3, and the 3
        // into 1 + 2: 1 + 2 + 4 + 2 nodes.
        assert_eq!(halving_tree_nodes(9, 2), 9);
    }

    #[test]
    fn inside_means_an_odd_number_of_crossings_or_a_winding_and_touching_is_no_crossing() {
        let ball = crate::geometry::icosphere::icosphere(1, 1.0, DVec3::ZERO).unwrap();
        let bvh = TriangleBvh::new(ball.positions(), &ball.triangles());
        assert!(bvh.encloses(DVec3::ZERO));
        assert!(bvh.encloses(DVec3::new(0.5, -0.3, 0.2)));
        assert!(!bvh.encloses(DVec3::new(1.5, 0.0, 0.0)));
        assert!(!bvh.encloses(DVec3::new(0.0, -2.0, 0.3)));
        // Two overlapping balls: in the overlap a ray leaves both (even parity), but the
        // winding number is 2.
        let other =
            crate::geometry::icosphere::icosphere(1, 1.0, DVec3::new(1.2, 0.0, 0.0)).unwrap();
        let n = ball.n_vertices() as u32;
        let pos: Vec<DVec3> = ball
            .positions()
            .iter()
            .chain(other.positions())
            .copied()
            .collect();
        let tris: Vec<[u32; 3]> = ball
            .triangles()
            .into_iter()
            .chain(other.triangles().into_iter().map(|t| t.map(|v| v + n)))
            .collect();
        let both = TriangleBvh::new(&pos, &tris);
        assert!(both.encloses(DVec3::new(0.6, 0.05, -0.02)));
        assert!(both.encloses(DVec3::new(-0.5, 0.0, 0.1)));
        assert!(!both.encloses(DVec3::new(0.6, 1.5, 0.0)));
        assert!(bvh.crosses(DVec3::ZERO, DVec3::new(0.0, 0.0, 2.0)));
        assert!(!bvh.crosses(DVec3::ZERO, DVec3::new(0.1, 0.2, 0.3)));
        // From a vertex of the mesh outwards: it touches, it does not cross.
        let v = ball.position(0);
        assert!(!bvh.crosses(v, 2.0 * v));
    }

    fn rng(seed: u64) -> impl FnMut() -> f64 {
        let mut s = seed;
        move || {
            s = s
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (s >> 11) as f64 / (1u64 << 53) as f64
        }
    }

    #[test]
    fn triangle_closest_point_matches_brute_force() {
        let mut r = rng(7);
        let pts: Vec<DVec3> = (0..300).map(|_| DVec3::new(r(), r(), r())).collect();
        let tris: Vec<[u32; 3]> = (0..100).map(|i| [3 * i, 3 * i + 1, 3 * i + 2]).collect();
        let bvh = TriangleBvh::new(&pts, &tris);
        for _ in 0..200 {
            let p = DVec3::new(2.0 * r() - 0.5, 2.0 * r() - 0.5, 2.0 * r() - 0.5);
            let brute = tris
                .iter()
                .map(|t| {
                    let [a, b, c] = t.map(|v| pts[v as usize]);
                    (closest_point_on_triangle(p, a, b, c).0 - p).length_squared()
                })
                .fold(f64::INFINITY, f64::min);
            let hit = bvh.closest_point(p).unwrap();
            assert_eq!(hit.distance_squared, brute);
            let [a, b, c] = tris[hit.triangle as usize].map(|v| pts[v as usize]);
            let q = hit.barycentric.x * a + hit.barycentric.y * b + hit.barycentric.z * c;
            assert!((q - hit.point).length() < 1e-12);
        }
        let cloud = PointBvh::new(&pts);
        for _ in 0..200 {
            let p = DVec3::new(r(), r(), r());
            let brute = pts
                .iter()
                .map(|q| (*q - p).length_squared())
                .fold(f64::INFINITY, f64::min);
            assert_eq!(cloud.nearest(p).unwrap().1, brute);
        }
    }

    /// Above [`PARALLEL_BUILD`] the root's halves are built apart: the tree is the one a
    /// single thread builds (the same boxes, leaves and order, read depth-first), and nearest
    /// queries agree with brute force.
    #[test]
    fn a_tree_built_in_two_halves_is_the_one_built_whole() {
        let mut r = rng(11);
        let n = 3 * PARALLEL_BUILD;
        let mins: Vec<DVec3> = (0..n).map(|_| DVec3::new(r(), r(), 0.3 * r())).collect();
        let maxs: Vec<DVec3> = mins
            .iter()
            .map(|&m| m + 0.01 * DVec3::new(r(), r(), r()))
            .collect();
        let centroids: Vec<DVec3> = mins
            .iter()
            .zip(&maxs)
            .map(|(a, b)| 0.5 * (*a + *b))
            .collect();
        let boxes = Boxes {
            mins: &mins,
            maxs: &maxs,
            centroids: &centroids,
        };
        let mut order: Vec<u32> = (0..n as u32).collect();
        let whole = Bvh {
            nodes: boxes.subtree(&mut order, 0),
            order,
        };
        let halves = Bvh::new(&mins, &maxs);
        assert_eq!(halves.order, whole.order);
        // Depth-first, left first: (box, leaf range) of every node.
        fn walk(b: &Bvh, ni: usize, out: &mut Vec<(DVec3, DVec3, u32, u32)>) {
            let node = b.nodes[ni];
            if node.count > 0 {
                out.push((node.min, node.max, node.start, node.count));
            } else {
                out.push((node.min, node.max, u32::MAX, 0));
                walk(b, node.start as usize, out);
                walk(b, node.right as usize, out);
            }
        }
        let (mut a, mut b) = (Vec::new(), Vec::new());
        walk(&whole, 0, &mut a);
        walk(&halves, 0, &mut b);
        assert!(a.len() > 100);
        assert_eq!(a, b);
        for _ in 0..100 {
            let p = DVec3::new(r(), r(), r());
            let d2 = |i: u32| {
                let (lo, hi) = (mins[i as usize], maxs[i as usize]);
                box_dist2(p, lo, hi)
            };
            let brute = (0..n as u32).map(d2).fold(f64::INFINITY, f64::min);
            assert_eq!(halves.nearest(p, d2).unwrap().1, brute);
        }
    }

    #[test]
    fn closest_point_regions() {
        let (a, b, c) = (DVec3::ZERO, DVec3::X, DVec3::Y);
        let q = closest_point_on_triangle(DVec3::new(0.2, 0.2, 1.0), a, b, c).0;
        assert!((q - DVec3::new(0.2, 0.2, 0.0)).length() < 1e-15);
        assert_eq!(
            closest_point_on_triangle(DVec3::new(-1.0, -1.0, 0.0), a, b, c).0,
            a
        );
        assert_eq!(
            closest_point_on_triangle(DVec3::new(1.0, 1.0, 0.0), a, b, c).0,
            DVec3::new(0.5, 0.5, 0.0)
        );
    }

    /// The warm-started batch gives each point the hit of its own query, ties included: on a
    /// grid of unit squares (two triangles each, many at equal distance from a query) queried
    /// along a path and at random, without a bound and with one.
    #[test]
    fn batched_closest_points_are_the_single_queries() {
        let n = 12u32;
        let pts: Vec<DVec3> = (0..=n)
            .flat_map(|j| (0..=n).map(move |i| DVec3::new(i as f64, j as f64, 0.0)))
            .collect();
        let at = |i: u32, j: u32| j * (n + 1) + i;
        let tris: Vec<[u32; 3]> = (0..n)
            .flat_map(|j| (0..n).map(move |i| (i, j)))
            .flat_map(|(i, j)| {
                let q = [at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1)];
                [[q[0], q[1], q[2]], [q[0], q[2], q[3]]]
            })
            .collect();
        let grid = TriangleBvh::new(&pts, &tris);
        let mut r = rng(3);
        let mut queries: Vec<DVec3> = (0..200)
            .map(|k| DVec3::new(0.05 * k as f64, 0.5 * (k % 7) as f64, 0.5))
            .collect();
        queries.extend((0..200).map(|_| DVec3::new(14.0 * r() - 1.0, 14.0 * r() - 1.0, r())));
        for (bvh, bound) in [(&grid, f64::INFINITY), (&grid, 0.7)] {
            let batch = bvh.closest_points_within(queries.len(), |i| queries[i], bound);
            for (q, hit) in queries.iter().zip(&batch) {
                assert_eq!(*hit, bvh.closest_point_within(*q, bound));
            }
        }
    }
}
