//! Guards of the evolution: a step is accepted only if the surface it leaves is free of
//! self-intersections and shows no sign of divergence.
//!
//! *Contact.* Where two sheets of the surface would pass through each other (the two sides of a
//! concavity closing, the membrane over a handle's hole), the vertices of the faces involved are
//! put back where they were before the step, round after round until no intersecting pair is
//! left; the previous surface was clean, so reverting everything ends it at the latest. Reverted
//! vertices are then *held* (no advection) for a few steps, so the sheets rest at a small gap
//! instead of pushing against each other every step.
//!
//! *Divergence.* A non-finite coordinate, a vertex far outside the region the surface started in,
//! a runaway area or vertex count: the step is rolled back and the evolution stops with the
//! reason.

// `!(x > y)` is used deliberately: it is also true when x is NaN.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

use crate::flow::guarded::{guarded, GuardPolicy, Verdict};
use crate::geometry::spatial::bvh::Bvh;
use crate::mesh::HalfedgeMesh;
use crate::metrics::intersections::{pair_intersects, self_intersecting_pairs};
use glam::DVec3;
use serde::{Deserialize, Serialize};

/// The name of the per-vertex layer counting the steps a vertex stays held.
pub const HELD_LAYER: &str = "held";

/// Settings of the guards.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct GuardSettings {
    /// Contact guard: no step, remesh or fit may leave intersecting faces. Default true.
    pub contact: bool,
    /// Steps a reverted vertex is held (advection off). Range 0–100; default 3.
    pub hold_steps: u32,
    /// The contact check runs every this many steps (and before the final fit); when it finds
    /// intersections the evolution goes back to the last clean state and redoes the steps
    /// checking each. 1 checks every step. Range ≥ 1; default 16 (one check costs about as
    /// much as two steps, and contact is rare).
    pub check_every: u32,
    /// After a roll-back the steps are checked one by one until `2·check_every` of them in a
    /// row made no contact (a surface still pressing on itself would otherwise roll back again
    /// as soon as the checks are spaced out, and redo its steps each time). False: for
    /// `2·check_every` steps whatever they meet. Default false: a contact that would heal
    /// between spaced-out checks is resolved instead, which changes some results
    /// (docs/decisions/0021-contact-guard.md).
    pub guarded_until_clear: bool,
    /// Rounds of selective reverts before the whole move is reverted. Range 1–100; default 8.
    pub max_rounds: u32,
    /// Divergence: a vertex farther than this many bounding-box diagonals (of the target) outside
    /// the box of the start surface and the target. Range (0, 100]; default 0.5.
    pub escape_diagonals: f64,
    /// Divergence: surface area above this multiple of the start surface's area plus the target
    /// box's area. Range (1, 10⁶]; default 1000.
    pub max_area_growth: f64,
    /// Divergence: more vertices than this. Default 2 000 000 (far beyond any fine wrap).
    pub max_vertices: usize,
}

impl Default for GuardSettings {
    fn default() -> Self {
        Self {
            contact: true,
            hold_steps: 3,
            check_every: 16,
            guarded_until_clear: false,
            max_rounds: 8,
            escape_diagonals: 0.5,
            max_area_growth: 1000.0,
            max_vertices: 2_000_000,
        }
    }
}

/// What the contact guard did in one call.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize)]
#[cfg_attr(target_arch = "wasm32", derive(tsify::Tsify))]
pub struct ContactReport {
    /// Intersecting face pairs found before any revert.
    pub pairs: usize,
    /// Vertices put back.
    pub reverted: usize,
    /// Check rounds run.
    pub rounds: u32,
    /// True when the selective rounds did not suffice and every vertex was put back.
    pub reverted_all: bool,
    /// Non-zero when a periodic check found intersections at this step and the evolution went
    /// back to the last certified state to redo the steps since, checking each.
    pub rolled_back_from: u32,
}

/// Faces (indices) that intersect any face in `dirty`, given the positions now in `mesh`: a BVH
/// over the dirty faces only, queried by every face (cheap when few faces are dirty).
fn pairs_touching(positions: &[DVec3], tris: &[[u32; 3]], dirty: &[usize]) -> Vec<(usize, usize)> {
    let boxes = |t: &[u32; 3]| {
        let p = t.map(|v| positions[v as usize]);
        (p[0].min(p[1]).min(p[2]), p[0].max(p[1]).max(p[2]))
    };
    let (mins, maxs): (Vec<DVec3>, Vec<DVec3>) = dirty.iter().map(|&f| boxes(&tris[f])).unzip();
    let bvh = Bvh::new(&mins, &maxs);
    let mut out = Vec::new();
    for (g, t) in tris.iter().enumerate() {
        let (lo, hi) = boxes(t);
        bvh.for_each_overlap(lo, hi, |k| {
            let f = dirty[k as usize];
            if f != g && pair_intersects(positions, tris, f, g) {
                out.push((f.min(g), f.max(g)));
            }
        });
    }
    out.sort_unstable();
    out.dedup();
    out
}

/// The contact guard's rounds as a [`guarded_edit`](crate::flow::guarded::guarded_edit): the
/// pairs the last check found, and what putting their vertices back will touch.
struct Rounds<'a> {
    mesh: &'a mut HalfedgeMesh,
    old: &'a [DVec3],
    tris: Vec<[u32; 3]>,
    /// The faces around each vertex (filled at the first failed check).
    vertex_faces: Vec<Vec<usize>>,
    /// Pairs found by the first check.
    first: usize,
    /// Vertices the next round puts back where they moved, and those it puts back outright
    /// (one-rings), and the faces that moves (the next check's).
    back: Vec<usize>,
    rings: Vec<usize>,
    dirty: Vec<usize>,
}

impl Rounds<'_> {
    /// The check of a round: the intersecting pairs (all at first, then those touching the
    /// faces put back), whose vertices are frozen to be put back; where they are all back
    /// already, the one-rings of their vertices too.
    fn check(&mut self, reverted: &mut [bool]) -> Verdict {
        let pairs: Vec<(usize, usize)> = if self.vertex_faces.is_empty() {
            let pairs = self_intersecting_pairs(self.mesh.positions(), &self.tris);
            self.first = pairs.len();
            pairs
                .into_iter()
                .map(|(a, b)| (a as usize, b as usize))
                .collect()
        } else {
            pairs_touching(self.mesh.positions(), &self.tris, &self.dirty)
        };
        if pairs.is_empty() {
            return Verdict::Clean;
        }
        if self.vertex_faces.is_empty() {
            self.vertex_faces = vec![Vec::new(); self.mesh.n_vertices()];
            for (f, t) in self.tris.iter().enumerate() {
                for &v in t {
                    self.vertex_faces[v as usize].push(f);
                }
            }
        }
        let corners = |pairs: &[(usize, usize)]| -> Vec<usize> {
            let faces = pairs.iter().flat_map(|&(a, b)| [a, b]);
            faces
                .flat_map(|f| self.tris[f])
                .map(|v| v as usize)
                .collect()
        };
        let back = corners(&pairs);
        let (pos, old) = (self.mesh.positions(), self.old);
        // (`!=`, not bits: a move to the other zero or to NaN counts as one.)
        let progress = back.iter().any(|&v| pos[v] != old[v]);
        self.rings = match progress {
            true => Vec::new(),
            // Both faces are back where they were but still meet a moved face.
            false => back
                .iter()
                .flat_map(|&v| self.mesh.neighbors(v as u32))
                .map(|w| w as usize)
                .collect(),
        };
        self.dirty.clear();
        for &v in back.iter().chain(&self.rings) {
            reverted[v] = true;
            self.dirty.extend_from_slice(&self.vertex_faces[v]);
        }
        self.dirty.sort_unstable();
        self.dirty.dedup();
        self.back = back;
        Verdict::Retry
    }
}

/// Puts vertices of intersecting faces back to `old` (same connectivity, intersection-free) until
/// the mesh is intersection-free, and marks them held for `hold_steps` steps: a
/// [`guarded_edit`](crate::flow::guarded::guarded_edit) whose edit puts back the vertices of the
/// pairs its check found, round after round, then everything.
pub fn resolve_contacts(
    mesh: &mut HalfedgeMesh,
    old: &[DVec3],
    settings: &GuardSettings,
) -> ContactReport {
    let n = mesh.n_vertices();
    let mut rounds = Rounds {
        tris: mesh.triangles(),
        mesh: &mut *mesh,
        old,
        vertex_faces: Vec::new(),
        first: 0,
        back: Vec::new(),
        rings: Vec::new(),
        dirty: Vec::new(),
    };
    let mut reverted = vec![false; n];
    let policy = GuardPolicy {
        tries: settings.max_rounds as usize + 1,
        applied: true,
    };
    let outcome = guarded(
        &mut rounds,
        &mut reverted,
        policy,
        |r, _| {
            let pos = r.mesh.positions_mut();
            for &v in &r.back {
                if pos[v] != r.old[v] {
                    pos[v] = r.old[v];
                }
            }
            for &w in &r.rings {
                pos[w] = r.old[w];
            }
            true
        },
        |r, reverted| r.check(reverted),
        |r| r.mesh.positions_mut().copy_from_slice(r.old),
    );
    let mut report = ContactReport {
        pairs: rounds.first,
        rounds: outcome.checks as u32,
        reverted_all: !outcome.clean,
        ..Default::default()
    };
    if report.pairs == 0 {
        return report;
    }
    if report.reverted_all {
        reverted.iter_mut().for_each(|r| *r = true);
    }
    report.reverted = reverted.iter().filter(|&&r| r).count();
    if settings.hold_steps > 0 {
        if mesh.vertex_scalars(HELD_LAYER).is_none() {
            mesh.set_vertex_scalar_layer(HELD_LAYER, 0.0);
        }
        if let Some(held) = mesh.vertex_scalars_mut(HELD_LAYER) {
            for (h, &r) in held.iter_mut().zip(&reverted) {
                if r {
                    *h = settings.hold_steps as f64;
                }
            }
        }
    }
    report
}

/// Counts one step off every held vertex.
pub fn release_held(mesh: &mut HalfedgeMesh) {
    if let Some(held) = mesh.vertex_scalars_mut(HELD_LAYER) {
        for h in held {
            *h = (*h - 1.0).max(0.0);
        }
    }
}

/// True for vertices held by the contact guard.
pub fn held_mask(mesh: &HalfedgeMesh) -> Vec<bool> {
    match mesh.vertex_scalars(HELD_LAYER) {
        Some(h) => h.iter().map(|&x| x > 0.0).collect(),
        None => vec![false; mesh.n_vertices()],
    }
}

/// Why the evolution was judged to diverge.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum Divergence {
    /// A coordinate became NaN or infinite.
    #[error("vertex {vertex} has a non-finite position")]
    NonFinite { vertex: usize },
    /// A vertex left the region of the start surface and the target by a wide margin.
    #[error("vertex {vertex} escaped {distance:.3e} beyond the allowed region")]
    Escaped { vertex: usize, distance: f64 },
    /// The surface area grew past the limit.
    #[error("the surface area grew to {area:.3e}, above the limit {limit:.3e}")]
    AreaRunaway { area: f64, limit: f64 },
    /// The vertex count grew past the limit.
    #[error("the vertex count grew to {count}")]
    VertexRunaway { count: usize },
}

/// The limits the divergence guard checks, in the frame the mesh lives in.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DivergenceLimits {
    /// Allowed region (the start surface's and the target's boxes, grown by the margin).
    pub min: DVec3,
    pub max: DVec3,
    /// Largest allowed surface area.
    pub max_area: f64,
    /// Largest allowed vertex count.
    pub max_vertices: usize,
}

/// The first sign of divergence in `mesh`, if any.
pub fn check_divergence(mesh: &HalfedgeMesh, limits: &DivergenceLimits) -> Result<(), Divergence> {
    for (vertex, p) in mesh.positions().iter().enumerate() {
        if !p.is_finite() {
            return Err(Divergence::NonFinite { vertex });
        }
        if p.cmplt(limits.min).any() || p.cmpgt(limits.max).any() {
            let d = (limits.min - *p).max(*p - limits.max).max(DVec3::ZERO);
            return Err(Divergence::Escaped {
                vertex,
                distance: d.length(),
            });
        }
    }
    if mesh.n_vertices() > limits.max_vertices {
        return Err(Divergence::VertexRunaway {
            count: mesh.n_vertices(),
        });
    }
    let area = mesh.surface_area();
    if !(area <= limits.max_area) {
        return Err(Divergence::AreaRunaway {
            area,
            limit: limits.max_area,
        });
    }
    Ok(())
}

/// Tries of a remesh with the regions where it made faces intersect left alone.
pub(crate) const REMESH_TRIES: usize = 3;
/// At most this many intersecting pairs are frozen away; more and the remesh is given up.
const MAX_FROZEN_PAIRS: usize = 64;
/// How many rings around an intersection a remesh retry leaves alone.
const FROZEN_RINGS: usize = 2;

/// Marks in `frozen` the vertices of `before` (a mesh before its remesh into `after`) around the
/// faces of `after` that intersect where `frame` puts them (the check that will judge the
/// surface): the vertex of `before` nearest to each corner of such a face and its neighbours
/// two rings out: the check of a remesh's [`guarded_edit`](crate::flow::guarded::guarded_edit)
/// (too many pairs to freeze: give up).
pub(crate) fn freeze_where_intersecting(
    after: &HalfedgeMesh,
    before: &HalfedgeMesh,
    frame: impl Fn(DVec3) -> DVec3,
    frozen: &mut [bool],
) -> Verdict {
    let pos: Vec<DVec3> = after.positions().iter().map(|&p| frame(p)).collect();
    let tris = after.triangles();
    let pairs = self_intersecting_pairs(&pos, &tris);
    if pairs.is_empty() {
        return Verdict::Clean;
    }
    if pairs.len() > MAX_FROZEN_PAIRS {
        return Verdict::GiveUp;
    }
    let old = before.positions();
    let mut ring: Vec<u32> = Vec::new();
    for (f, g) in pairs {
        for v in tris[f as usize].into_iter().chain(tris[g as usize]) {
            let p = after.position(v);
            let nearest = (0..old.len() as u32)
                .min_by(|&a, &b| {
                    let (da, db) = (old[a as usize] - p, old[b as usize] - p);
                    da.length_squared().total_cmp(&db.length_squared())
                })
                .unwrap_or(0);
            ring.push(nearest);
        }
    }
    for v in before.rings_around(&ring, FROZEN_RINGS) {
        frozen[v as usize] = true;
    }
    Verdict::Retry
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::icosphere::icosphere;

    #[test]
    fn contact_guard_reverts_a_vertex_pushed_through() {
        let mut m = icosphere(3, 1.0, DVec3::ZERO).unwrap();
        let old = m.positions().to_vec();
        // Push one vertex through the sphere and out the other side; move the rest a little.
        for (i, p) in m.positions_mut().iter_mut().enumerate() {
            *p *= if i == 0 { -1.5 } else { 0.98 };
        }
        assert!(!self_intersecting_pairs(m.positions(), &m.triangles()).is_empty());
        let r = resolve_contacts(&mut m, &old, &GuardSettings::default());
        assert!(r.pairs > 0 && r.reverted > 0 && !r.reverted_all, "{r:?}");
        assert!(self_intersecting_pairs(m.positions(), &m.triangles()).is_empty());
        assert_eq!(m.positions()[0], old[0]);
        // Vertices far from the one pushed through kept their move.
        let kept = (0..m.n_vertices())
            .filter(|&i| m.positions()[i] != old[i])
            .count();
        assert!(kept > m.n_vertices() / 2, "{kept}");
        assert!(held_mask(&m)[0]);
        for _ in 0..3 {
            release_held(&mut m);
        }
        assert!(!held_mask(&m)[0]);
    }

    #[test]
    fn divergence_is_named() {
        let mut m = icosphere(1, 1.0, DVec3::ZERO).unwrap();
        let limits = DivergenceLimits {
            min: DVec3::splat(-2.0),
            max: DVec3::splat(2.0),
            max_area: 100.0,
            max_vertices: 1000,
        };
        assert_eq!(check_divergence(&m, &limits), Ok(()));
        m.positions_mut()[3].y = f64::NAN;
        assert_eq!(
            check_divergence(&m, &limits),
            Err(Divergence::NonFinite { vertex: 3 })
        );
        m.positions_mut()[3] = DVec3::new(0.0, 5.0, 0.0);
        assert!(matches!(
            check_divergence(&m, &limits),
            Err(Divergence::Escaped { vertex: 3, .. })
        ));
    }
}
