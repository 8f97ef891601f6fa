//! Necks: a ring-shaped region facing itself across its axis, cut out and both loops capped.

use super::labels::Labels;
use super::loops::{region_loops, remove_region};
use super::{record, Cut, Pass, Work};
use crate::mesh::HalfedgeMesh;
use glam::DVec3;

impl Pass<'_> {
    /// Cuts out each region of `level` that faces itself (`faces_of`: the region each mostly
    /// faces) and forms an annulus, capping both its loops, and adds the caps and records to
    /// `work`.
    pub(super) fn necks(&self, level: &Labels, faces_of: &[Option<u32>], work: &mut Work) {
        let Pass {
            mesh,
            partner,
            min_vertices,
            skip,
            mut spare_handles,
            ..
        } = *self;
        let (region, sizes, seeds) = (&level.of, &level.sizes, &level.seeds);
        for a in 0..sizes.len() as u32 {
            if faces_of[a as usize] != Some(a)
                || sizes[a as usize] < min_vertices
                || skip.contains(&a)
            {
                continue;
            }
            let Some(loops) = region_loops(mesh, region, a, &work.removed, 0) else {
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
            remove_region(mesh, region, &[a], &mut work.removed);
            let start = work.tris.len();
            for (lp, away) in [(la, cb - ca), (lb, ca - cb)] {
                work.tris
                    .extend(cap(&mut work.positions, lp, away.normalize_or_zero()));
            }
            let sides = [seeds[a as usize]; 2];
            work.tubes.push(record(
                mesh,
                Cut::Pinch,
                la,
                lb,
                a,
                sides,
                start..work.tris.len(),
            ));
        }
    }
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
