//! Facing regions: the paired vertices grouped into connected labels, and which label each
//! mostly faces.

use crate::mesh::HalfedgeMesh;

/// Vertex labels of facing regions, numbered from `first_id` (distinct between the regions and
/// the pieces of tangled ones).
pub(super) struct Labels {
    pub(super) of: Vec<Option<u32>>,
    pub(super) sizes: Vec<usize>,
    /// Each label's first vertex.
    pub(super) seeds: Vec<u32>,
    pub(super) first_id: u32,
}

impl Labels {
    /// The name of label `local` (counted from 0) in `skip` and [`super::Tube::region`]: a region's
    /// number, or a piece's first vertex with [`PIECE`] set (pieces are numbered after what the
    /// first pass used, which a retry may change; their first vertices stay).
    pub(super) fn name(&self, local: u32) -> u32 {
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
    pub(super) fn facing(votes: &[Vec<(u32, usize)>]) -> Vec<Option<u32>> {
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
    pub(super) fn votes(&self, partner: &[Option<u32>]) -> Vec<Vec<(u32, usize)>> {
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

/// The pieces of the paired vertices with equal `key`, connected through edges, labelled from
/// `first_id` in vertex order (deterministic).
pub(super) fn split(
    mesh: &HalfedgeMesh,
    key: impl Fn(usize) -> Option<(u32, u32)>,
    first_id: u32,
) -> Labels {
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
pub(super) fn regions(mesh: &HalfedgeMesh, partner: &[Option<u32>]) -> Labels {
    split(mesh, |v| partner[v].map(|_| (0, 0)), 0)
}
