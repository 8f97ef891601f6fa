//! The split phase: edges longer than 4/3 of their target length are split at their (curved or
//! chord) midpoint, projected onto the reference surface.

use super::{ends, Work, CURVED_SPLITS_LAYER, MAX_SWEEPS};
use crate::geometry::curved_midpoint::curved_midpoint;
use crate::geometry::operators::normals::area_weighted_normal;
use crate::mesh::HalfedgeMesh;

/// Splits the edges longer than 4/3 of their target length; false when the splits passed
/// `w.split_limit` (the mesh is then part-way split).
pub(super) fn split_long_edges(mesh: &mut HalfedgeMesh, w: &mut Work) -> bool {
    for _ in 0..MAX_SWEEPS {
        let mut any = false;
        let ne = mesh.n_edges() as u32;
        for e in 0..ne {
            if mesh.is_deleted_edge(e) || !mesh.is_interior_edge(e) {
                continue;
            }
            let (a, b) = ends(mesh, e);
            if w.frozen[a as usize] || w.frozen[b as usize] {
                continue;
            }
            let (pa, pb) = (mesh.position(a), mesh.position(b));
            let hmax = 4.0 / 3.0 * w.h[a as usize].min(w.h[b as usize]);
            if (pb - pa).length_squared() <= hmax * hmax {
                continue;
            }
            let feature = w.efeat[e as usize];
            let curved = w.s.curved_splits && !feature && w.reference.is_none() && {
                let layer = mesh.vertex_scalars(CURVED_SPLITS_LAYER);
                layer.is_none_or(|l| l[a as usize] > 0.5 && l[b as usize] > 0.5)
            };
            let mut p = if curved {
                let (na, nb) = (area_weighted_normal(mesh, a), area_weighted_normal(mesh, b));
                curved_midpoint(pa, na, pb, nb)
            } else {
                0.5 * (pa + pb)
            };
            let mut hm = 0.5 * (w.h[a as usize] + w.h[b as usize]);
            if !feature {
                if let Some(r) = &w.reference {
                    let (q, hq) = r.project(p);
                    p = q;
                    if hq.is_finite() {
                        hm = hq;
                    }
                }
            }
            mesh.split_edge(e, p);
            w.h.push(hm);
            w.locked.push(false);
            w.frozen.push(false);
            w.vfeat.push(feature);
            w.efeat.extend([feature, false, false]);
            w.report.splits += 1;
            if w.report.splits > w.split_limit {
                return false;
            }
            any = true;
        }
        if !any {
            break;
        }
    }
    true
}
