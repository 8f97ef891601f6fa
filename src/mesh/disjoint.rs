//! Disjoint sets (union–find) over `0..n`: the connected parts of a triangle list, the fans about
//! a vertex, a mesh's specks, a cloud's crease lines. One implementation, so that every caller
//! gets the same roots: a set's root is its smallest member, whatever the order of the unions,
//! which keeps the numbering of parts deterministic.

/// A forest of `n` singletons to be joined.
pub struct DisjointSets {
    parent: Vec<u32>,
}

impl DisjointSets {
    /// `n` sets of one member each.
    pub fn new(n: usize) -> Self {
        Self {
            parent: (0..n as u32).collect(),
        }
    }

    /// How many members (not sets) there are.
    pub fn len(&self) -> usize {
        self.parent.len()
    }

    /// True when there are no members.
    pub fn is_empty(&self) -> bool {
        self.parent.is_empty()
    }

    /// The root of `x`'s set (its smallest member), halving the path on the way.
    pub fn find(&mut self, mut x: u32) -> u32 {
        let p = &mut self.parent;
        while p[x as usize] != x {
            p[x as usize] = p[p[x as usize] as usize];
            x = p[x as usize];
        }
        x
    }

    /// Joins the sets of `a` and `b` (the smaller root becomes the root of both).
    pub fn union(&mut self, a: u32, b: u32) {
        let (a, b) = (self.find(a), self.find(b));
        if a != b {
            self.parent[a.max(b) as usize] = a.min(b);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn roots_are_the_smallest_members_whatever_the_order() {
        let mut s = DisjointSets::new(7);
        for (a, b) in [(5, 6), (6, 3), (1, 2), (4, 6)] {
            s.union(a, b);
        }
        let roots: Vec<u32> = (0..7).map(|v| s.find(v)).collect();
        assert_eq!(roots, [0, 1, 1, 3, 3, 3, 3]);
        s.union(2, 4);
        assert!((1..7).all(|v| s.find(v) == 1));
        assert_eq!(s.find(0), 0);
        assert_eq!(s.len(), 7);
    }
}
