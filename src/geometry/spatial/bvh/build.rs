//! Building the hierarchy: median splits over the centroids ([`Bvh::new`], the root's halves in
//! parallel natively) or middle splits along the Morton curve ([`Bvh::new_morton`]).

use super::{Bvh, Node, LEAF_SIZE};
use glam::DVec3;

/// The nodes of a tree that splits every range of more than `leaf` primitives at its middle
/// (`len / 2`), as both builders do: the exact capacity of its node list. (A guess of `2n /
/// leaf` is too small, since such leaves hold about `0.6·leaf`, and a list that outgrows its
/// capacity is held twice while it doubles.)
pub(super) fn halving_tree_nodes(n: usize, leaf: usize) -> usize {
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
pub(super) const PARALLEL_BUILD: usize = 4096;

/// The boxes a [`Bvh::new`] is built over.
pub(super) struct Boxes<'a> {
    pub(super) mins: &'a [DVec3],
    pub(super) maxs: &'a [DVec3],
    pub(super) centroids: &'a [DVec3],
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
    pub(super) fn subtree(&self, order: &mut [u32], offset: usize) -> Vec<Node> {
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
}
