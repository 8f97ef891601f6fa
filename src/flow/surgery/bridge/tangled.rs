//! Tangled regions: a membrane that meets several others (the arms of one branching cavity)
//! pairs along a ring, not a disk, and no tube fits it. Each such region is split by the region
//! its vertices face, and the pieces are paired.

use super::labels::{split, Labels};
use super::loops::disk_loop;
use super::{Pass, Work};
use crate::mesh::HalfedgeMesh;

impl Pass<'_> {
    /// Splits each tangled region of `level` (`votes`: what its vertices face, see
    /// [`Labels::votes`]) into pieces by the region its vertices face, and glues the mutually
    /// facing pieces with tubes (see [`Pass::tubes`]).
    pub(super) fn tangled_tubes(
        &self,
        level: &Labels,
        votes: &[Vec<(u32, usize)>],
        work: &mut Work,
    ) {
        let (mesh, partner, skip) = (self.mesh, self.partner, self.skip);
        let region = &level.of;
        let n_regions = level.sizes.len();
        let used = cut_regions(mesh, region, &work.removed, n_regions);
        let tangled = self.tangled(level, votes, &used, &work.removed);
        if !tangled.iter().any(|&t| t) {
            return;
        }
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
        self.tubes(&pieces, &faces_of, work);
    }

    /// Per region of `level`: whether it is tangled: its vertices face regions on two or more
    /// parts in empty space (`min_vertices` or more of them facing each), and it is neither
    /// `used`, nor left out, nor a disk.
    fn tangled(
        &self,
        level: &Labels,
        votes: &[Vec<(u32, usize)>],
        used: &[bool],
        removed: &[bool],
    ) -> Vec<bool> {
        let (region, seeds) = (&level.of, &level.seeds);
        (0..level.sizes.len() as u32)
            .map(|r| {
                let mut sheets: Vec<u32> = votes[r as usize]
                    .iter()
                    .filter(|&&(s, n)| s != r && n >= self.min_vertices)
                    .map(|&(s, _)| self.far[seeds[s as usize] as usize])
                    .collect();
                sheets.sort_unstable();
                sheets.dedup();
                sheets.len() >= 2
                    && !used[r as usize]
                    && !self.skip.contains(&r)
                    && disk_loop(self.mesh, region, r, removed).is_none()
            })
            .collect()
    }
}

/// Per region of `region` (`n_regions` of them): whether one of its faces (all three vertices
/// in it) is already `removed`.
fn cut_regions(
    mesh: &HalfedgeMesh,
    region: &[Option<u32>],
    removed: &[bool],
    n_regions: usize,
) -> Vec<bool> {
    let mut used = vec![false; n_regions];
    for f in (0..mesh.n_faces() as u32).filter(|&f| removed[f as usize]) {
        let [a, b, c] = mesh.face_vertices(f).map(|v| region[v as usize]);
        if let (Some(r), true) = (a, a == b && b == c) {
            used[r as usize] = true;
        }
    }
    used
}
