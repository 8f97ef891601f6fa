//! Queries on the hierarchy: nearest primitive under a caller's distance, box overlaps with a
//! box, and the overlapping pairs of the tree with itself.

use super::{box_dist2, Bvh, Node};
use glam::DVec3;

impl Bvh {
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
