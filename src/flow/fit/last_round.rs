//! A mesh target's last round of moves, after the passes. Every pass ends with a remesh, whose
//! new and smoothed vertices lie on the surface before it, not on the target: one more round of
//! moves without a remesh brings them onto it. After a reach it also settles the tips of flaps
//! left in concavities; on a closed target every vertex still off it goes to its closest point.

use super::checks::{
    intersects_as_written, partial_moves, resolve_contacts_as_written, tidy_slivers,
};
use super::reach::settle_flap_tips;
use super::Fit;
use crate::flow::guarded::{guarded, GuardPolicy, Verdict};
use crate::flow::scaling::round_as_written;
use crate::flow::snap::{snap_to_closest, snap_to_target, SnapTarget};
use crate::geometry::operators::normals::angle_weighted_normals;
use crate::mesh::HalfedgeMesh;

impl Fit<'_, '_> {
    /// The last round of moves on a mesh target (none on a cloud), undone if it leaves faces
    /// intersecting as written.
    pub(super) fn last_round(&mut self) {
        self.sw.lap();
        if let SnapTarget::Triangles(bvh) = self.target {
            let opt = self.opt;
            let (contact, phi, center) = (opt.contact, opt.phi, opt.center);
            // (Its slivers first: a folded one holds its neighbours' moves back.)
            tidy_slivers(self.mesh, contact, phi, center);
            let clean = self.mesh.clone();
            let (creases, reached_any) = (self.creases, self.state.reached_any);
            let moved = |mesh: &mut HalfedgeMesh, _: &[bool]| {
                let normals = angle_weighted_normals(mesh);
                snap_to_target(mesh, &normals, self.target, &opt.snap, creases, &mut |_| {});
                // (On a closed target the second move covers the flap tips too.)
                if opt.closed {
                    snap_to_closest(mesh, bvh, opt.settled, opt.snap.max_move);
                } else if reached_any {
                    settle_flap_tips(mesh, bvh, opt.refine_tol, opt.snap.max_move);
                }
                if contact {
                    // As written: snapped faces that lie in one target plane are exactly
                    // coplanar there, and only there do the ones that overlap show.
                    let wanted = mesh.positions().to_vec();
                    let (old, guard) = (clean.positions(), &opt.guard);
                    resolve_contacts_as_written(mesh, old, guard, phi, center);
                    partial_moves(mesh, old, &wanted, guard, phi, center);
                }
                round_as_written(mesh, phi, center);
                true
            };
            let outcome = guarded(
                &mut *self.mesh,
                &mut [],
                GuardPolicy::ONCE,
                moved,
                |mesh, _| Verdict::clean_if(!(contact && intersects_as_written(mesh, phi, center))),
                |mesh| *mesh = clean.clone(),
            );
            self.state.certified |= contact && outcome.clean;
        }
        self.times.last_round += self.sw.lap();
    }
}
