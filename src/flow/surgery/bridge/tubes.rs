//! Tubes between mutually facing regions: each pair whose faces form two disks spanning their
//! hole is cut out and its loops zipped.

use super::labels::Labels;
use super::loops::{disk_loop, remove_region};
use super::zip::zip_loops;
use super::{record, Cut, Pass, Work};

/// A patch spans its hole when the median distance of its rim to the target is below this share
/// of its deepest vertex's (or below `rim`).
const RIM_DEPTH: f64 = 0.5;

impl Pass<'_> {
    /// Glues each mutually facing pair of `labels` (`faces_of`: the label each mostly faces)
    /// with a tube, adding the tube's faces and record to `work` and marking the regions' faces
    /// removed.
    pub(super) fn tubes(&self, labels: &Labels, faces_of: &[Option<u32>], work: &mut Work) {
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
                disk_loop(mesh, &labels.of, id(a), &work.removed),
                disk_loop(mesh, &labels.of, id(b), &work.removed),
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
            remove_region(mesh, &labels.of, &[id(a), id(b)], &mut work.removed);
            let start = work.tris.len();
            work.tris.extend(tube);
            let sides = [labels.seeds[a as usize], labels.seeds[b as usize]];
            work.tubes.push(record(
                mesh,
                Cut::Tube,
                la,
                lb,
                labels.name(a),
                sides,
                start..work.tris.len(),
            ));
        }
    }
}
