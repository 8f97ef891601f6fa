//! Topology surgery: a Lagrangian surface cannot change its genus by moving, so a
//! surface shrinking onto a handle would span the handle's hole with two membranes pressed
//! together. Surgery finds such membranes ([`detect`]) and replaces them by a tube ([`bridge`]):
//! the hole opens and the flow goes on to fit its walls.
//!
//! Only sheets that meet *far from the data* are cut. Scan holes are spanned by a single membrane
//! and the two sides of one scan layer meet at the data, so neither is ever cut.

pub mod bridge;
pub mod detect;

use crate::flow::guarded::{guarded, GuardPolicy, Verdict};
use crate::geometry::operators::normals::angle_weighted_normals;
use crate::mesh::{HalfedgeMesh, MeshReport};
use crate::metrics::intersections::self_intersecting_pairs;
use bridge::{glue_facing_regions, Cut, Glued, Pass, Tube};
use detect::{facing_pairs_and_tunnels, far_parts, in_opened_hole, FacingQuery, PATCH_WIDTHS};
use glam::DVec3;
use serde::Serialize;

/// A patch is cut once most of its rim lies within this many `empty` distances of the target.
const RIM: f64 = 2.0;

/// An opened hole's ball reaches this many `empty` distances beyond its tube's rim: the
/// membrane left around the tube is at most `empty` from the data, with a margin.
pub const OPENED_MARGIN: f64 = 1.5;

/// What a topology change did (serialised in lower case: `"handle"`, `"merge"`, `"pinch"`,
/// `"drop"`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
#[cfg_attr(target_arch = "wasm32", derive(tsify::Tsify))]
pub enum SurgeryKind {
    /// Two membranes cut and joined by a tube: genus +1.
    Handle,
    /// A tube between two components.
    Merge,
    /// A neck in empty space cut and both sides capped.
    Pinch,
    /// A component enclosing no data removed.
    Drop,
}

/// One topology change, for the statistics and the app's timeline.
#[derive(Clone, Debug, PartialEq, Serialize)]
#[cfg_attr(target_arch = "wasm32", derive(tsify::Tsify))]
pub struct SurgeryEvent {
    /// The step after which it happened.
    pub step: u32,
    /// What happened.
    pub kind: SurgeryKind,
    /// Where (centre of the tube), in the target's units.
    pub position: [f64; 3],
    /// Radius of the cut (farthest loop vertex from `position`), in the target's units.
    pub radius: f64,
    /// Genus of the surface before and after (summed over components).
    pub genus_before: i64,
    pub genus_after: i64,
    /// Connected components before and after.
    pub components_before: usize,
    pub components_after: usize,
}

/// A surface after successful surgery.
pub struct Operated {
    pub mesh: HalfedgeMesh,
    pub tubes: Vec<Tube>,
    pub genus_before: i64,
    pub genus_after: i64,
    pub components_before: usize,
    pub components_after: usize,
}

/// Where the cloud is sampled sparsely (`sparse` below 1 in [`open_handles`]), a tube's hole must
/// be this many local "empty" distances from the data at its centre.
const SPARSE_HOLE: f64 = 1.5;

/// Membranes have settled when their count of paired vertices grew by less than this factor
/// since the last look.
const SETTLED_GROWTH: f64 = 1.1;

/// A tunnel's membranes reach this many times its half-width from its path when the look with
/// [`PATCH_WIDTHS`] cut nothing.
const NARROW_PATCH_WIDTHS: f64 = 0.5;

/// What one look for facing membranes found.
pub struct Look {
    /// Vertices paired with a facing sheet (pass it to the next look).
    pub paired: usize,
    /// The operated surface, if surgery was done.
    pub operated: Option<Operated>,
    /// Nothing was done because the surface already had intersecting faces (it had moved since
    /// the contact guard's last check): look again once it is certified.
    pub intersecting: bool,
    /// The tunnels paired across (see [`detect::facing_pairs_and_tunnels`]).
    pub tunnels: Vec<(DVec3, f64)>,
}

/// Looks for facing membranes in empty space: glues each facing pair of patches with a tube and
/// cuts each neck that faces itself, capping both sides. The result is kept only when it is a
/// closed, oriented manifold free of self-intersections whose Euler characteristic changed by
/// −2 per tube and +2 per cut neck (else the surface stays as it was). `distances` are
/// the vertices' distances to the target, `probe` the distance at any point (for tunnels, see
/// [`detect`]); `sparse(p)` (≤ 1) shrinks "empty" distances where a cloud is sampled more
/// sparsely than its median (1 elsewhere): a tube there needs its centre [`SPARSE_HOLE`] times
/// `empty` from the data after shrinking, or it spans a gap of the sampling, not a hole;
/// `previous` is the last look's `paired`.
pub fn open_handles(
    mesh: &HalfedgeMesh,
    distances: &[f64],
    probe: &dyn Fn(DVec3) -> f64,
    sparse: &dyn Fn(DVec3) -> f64,
    query: &FacingQuery,
    min_vertices: usize,
    previous: usize,
) -> Look {
    let normals = angle_weighted_normals(mesh);
    let look = |widths: f64| {
        let (partner, tunnels) =
            facing_pairs_and_tunnels(mesh, &normals, distances, query, probe, widths);
        let paired = partner.iter().filter(|p| p.is_some()).count();
        let settled = paired as f64 <= SETTLED_GROWTH * previous as f64;
        let op = match paired < 2 * min_vertices {
            true => Ok(None),
            false => operate(
                mesh,
                &partner,
                distances,
                query,
                Reading { probe, sparse },
                settled,
                min_vertices,
            ),
        };
        (paired, tunnels, op)
    };
    let (mut paired, mut tunnels, mut op) = look(PATCH_WIDTHS);
    if matches!(op, Ok(None)) && !tunnels.is_empty() {
        // Nothing cut although a tunnel paired: its tube may have crossed the surface. Membranes
        // resting tilted across a bore (a scan that saw its wall only near the ends) give rims
        // whose tube crosses itself; narrower patches round the path give rounder loops.
        (paired, tunnels, op) = look(NARROW_PATCH_WIDTHS);
    }
    let (operated, intersecting) = match op {
        Ok(op) => (op, false),
        Err(Intersecting) => (None, true),
    };
    Look {
        paired,
        operated,
        intersecting,
        tunnels,
    }
}

/// How [`operate`] reads the target at any point: the distance, and the factor for a sparse
/// sampling (see [`open_handles`]).
struct Reading<'a> {
    probe: &'a dyn Fn(DVec3) -> f64,
    sparse: &'a dyn Fn(DVec3) -> f64,
}

/// The surface to operate on had intersecting faces of its own.
struct Intersecting;

/// Cuts and glues; `None` when nothing qualified or the result failed a check. A tube in the
/// same hole as an earlier tube of this look (a membrane that met in two spots: within its ball,
/// [`detect::in_opened_hole`], between sheets that this look's earlier tubes join through empty
/// space, [`detect::far_parts`]) is left out; so are the operations whose new faces cross others,
/// and the rest is tried again (one bad tube must not hold back the other holes): a guarded edit
/// whose frozen regions are the ones left out.
fn operate(
    mesh: &HalfedgeMesh,
    partner: &[Option<u32>],
    distances: &[f64],
    query: &FacingQuery,
    reading: Reading,
    settled: bool,
    min_vertices: usize,
) -> Result<Option<Operated>, Intersecting> {
    let Ok(before) = mesh.validate() else {
        return Ok(None);
    };
    let rim = RIM * query.empty;
    let far = far_parts(mesh, distances, query.empty);
    let mut tries = Tries {
        partner: std::borrow::Cow::Borrowed(partner),
        skip: Vec::new(),
        eroded: 0,
        glued: None,
        operated: None,
        intersecting: false,
    };
    let policy = GuardPolicy {
        tries: 3 + ERODE,
        applied: false,
    };
    guarded(
        &mut tries,
        &mut [],
        policy,
        |t, _| {
            t.glued = glue_facing_regions(&Pass {
                mesh,
                partner: &t.partner,
                distances,
                rim,
                settled,
                min_vertices,
                skip: &t.skip,
                far: &far,
                spare_handles: query.least_genus.map(|g| before.genus - g),
            });
            t.glued.is_some()
        },
        |t, _| t.check(mesh, &far, query, &reading, &before),
        // Nothing was applied: `mesh` is as it came.
        |_| {},
    );
    match tries.intersecting {
        true => Err(Intersecting),
        false => Ok(tries.operated),
    }
}

/// The tries of one look's cuts and glues (see [`operate`]).
struct Tries<'a> {
    partner: std::borrow::Cow<'a, [Option<u32>]>,
    /// Regions left out.
    skip: Vec<u32>,
    /// Times the rims were eroded.
    eroded: usize,
    /// The last try's glued surface, to check.
    glued: Option<Glued>,
    operated: Option<Operated>,
    /// The surface had intersecting faces of its own.
    intersecting: bool,
}

impl Tries<'_> {
    /// The check of a try: its twins and gaps left out, else the rebuilt surface's exact check,
    /// its crossing operations eroded or left out.
    fn check(
        &mut self,
        mesh: &HalfedgeMesh,
        far: &[u32],
        query: &FacingQuery,
        reading: &Reading,
        before: &MeshReport,
    ) -> Verdict {
        let Some(glued) = self.glued.take() else {
            return Verdict::GiveUp;
        };
        let left_out = twins_and_gaps(&glued.tubes, far, query, reading);
        if !left_out.is_empty() {
            self.skip.extend(left_out);
            return Verdict::Retry;
        }
        let Glued {
            positions,
            triangles,
            tubes,
        } = glued;
        let Some((out, after)) = rebuilt(positions, &triangles, &tubes, before) else {
            return Verdict::GiveUp;
        };
        let pairs = self_intersecting_pairs(out.positions(), &out.triangles());
        if pairs.is_empty() {
            self.operated = Some(Operated {
                mesh: out,
                tubes,
                genus_before: before.genus,
                genus_after: after.genus,
                components_before: before.components,
                components_after: after.components,
            });
            return Verdict::Clean;
        }
        let Ok(bad) = blamed(&tubes, &pairs) else {
            self.intersecting = true;
            return Verdict::GiveUp;
        };
        // Crossings at a curved membrane's rim, where the sheets part: the same cut a ring
        // further in, where they lie closer, is tried before the operation is left out.
        if self.skip.is_empty() && self.eroded < ERODE {
            let sides = bad.iter().flat_map(|&t| tubes[t].sides);
            erode_rims(mesh, self.partner.to_mut(), sides);
            self.eroded += 1;
            return Verdict::Retry;
        }
        if bad.len() == tubes.len() {
            return Verdict::GiveUp;
        }
        self.skip.extend(bad.into_iter().map(|t| tubes[t].region));
        Verdict::Retry
    }
}

/// The regions of the `tubes` to leave out of this look: the tubes in the same hole as an
/// earlier one (within its ball, between parts in empty space, `far`, that the earlier tubes
/// join), then those whose centre lies in a gap of a sparse sampling rather than a hole.
fn twins_and_gaps(tubes: &[Tube], far: &[u32], query: &FacingQuery, reading: &Reading) -> Vec<u32> {
    let Reading { probe, sparse } = *reading;
    let mut balls = Vec::new();
    let mut twins = Vec::new();
    let mut sparse_gaps = Vec::new();
    // Union-find over the parts in empty space: the tubes so far join theirs.
    let mut set: Vec<u32> = (0..=far
        .iter()
        .filter(|&&p| p != u32::MAX)
        .max()
        .map_or(0, |&m| m))
        .collect();
    let root = |set: &[u32], mut p: u32| {
        while set[p as usize] != p {
            p = set[p as usize];
        }
        p
    };
    for t in tubes.iter().filter(|t| t.cut == Cut::Tube) {
        let f = sparse(t.position);
        // A gap of a sparse sampling, not a hole: leave the operation out.
        if f < 1.0 && probe(t.position).abs() * f < SPARSE_HOLE * query.empty {
            sparse_gaps.push(t.region);
            continue;
        }
        let [a, b] = t.sides.map(|v| far[v as usize]);
        let joined = a != u32::MAX && b != u32::MAX && {
            let (ra, rb) = (root(&set, a), root(&set, b));
            set[ra.max(rb) as usize] = ra.min(rb);
            ra == rb
        };
        if joined && in_opened_hole(t.position, &balls, query.empty, probe) {
            twins.push(t.region);
        } else {
            balls.push((t.position, t.radius + OPENED_MARGIN * query.empty));
        }
    }
    twins.extend(sparse_gaps);
    twins
}

/// The glued surface as a mesh, with its report, when it is a valid closed manifold whose Euler
/// characteristic changed by −2 per tube and +2 per cut neck from `before`'s.
fn rebuilt(
    positions: Vec<DVec3>,
    triangles: &[[u32; 3]],
    tubes: &[Tube],
    before: &MeshReport,
) -> Option<(HalfedgeMesh, MeshReport)> {
    let out = HalfedgeMesh::from_triangles(positions, triangles).ok()?;
    let after = out.validate().ok()?;
    let change: i64 = tubes
        .iter()
        .map(|t| if t.cut == Cut::Tube { -2 } else { 2 })
        .sum();
    (after.euler_characteristic == before.euler_characteristic + change).then_some((out, after))
}

/// The operations (indices into `tubes`, sorted, once each) to blame for the crossing faces
/// `pairs`: each crossing is blamed on the operation that made its faces, and two operations
/// crossing each other on the later one (the first stays in: tubes across the arms of one cavity
/// can cross, and blaming both would leave every tube of the look out). Crossings among the old
/// faces were there before: `Intersecting`.
fn blamed(tubes: &[Tube], pairs: &[(u32, u32)]) -> Result<Vec<usize>, Intersecting> {
    let owner = |f: u32| tubes.iter().position(|t| t.faces.contains(&(f as usize)));
    let mut bad = Vec::new();
    for &(f, g) in pairs {
        match (owner(f), owner(g)) {
            (None, None) => return Err(Intersecting),
            (Some(t), None) | (None, Some(t)) => bad.push(t),
            (Some(s), Some(t)) => bad.push(s.max(t)),
        }
    }
    bad.sort_unstable();
    bad.dedup();
    Ok(bad)
}

/// Rings by which a cut whose new faces cross the surface is moved into its membranes
/// ([`erode_rims`]) before it is left out.
const ERODE: usize = 2;

/// Unpairs the rim of each facing region that holds one of `seeds`: its paired vertices with
/// an unpaired neighbour. The regions' loops move a ring inwards.
fn erode_rims(mesh: &HalfedgeMesh, partner: &mut [Option<u32>], seeds: impl Iterator<Item = u32>) {
    let mut seen = vec![false; partner.len()];
    let mut rim = Vec::new();
    for s in seeds {
        if seen[s as usize] || partner[s as usize].is_none() {
            continue;
        }
        seen[s as usize] = true;
        let mut stack = vec![s];
        while let Some(v) = stack.pop() {
            let mut edge = false;
            for u in mesh.neighbors(v) {
                match partner[u as usize] {
                    None => edge = true,
                    Some(_) if !seen[u as usize] => {
                        seen[u as usize] = true;
                        stack.push(u);
                    }
                    Some(_) => {}
                }
            }
            if edge {
                rim.push(v);
            }
        }
    }
    for v in rim {
        partner[v as usize] = None;
    }
}

/// The event records of `op`, in the target's units: positions mapped by `to_target`, lengths
/// divided by `scale`.
pub fn events(
    op: &Operated,
    step: u32,
    scale: f64,
    to_target: impl Fn(DVec3) -> DVec3,
) -> Vec<SurgeryEvent> {
    op.tubes
        .iter()
        .map(|t| SurgeryEvent {
            step,
            kind: match t.cut {
                Cut::Pinch => SurgeryKind::Pinch,
                Cut::Tube if op.components_after < op.components_before => SurgeryKind::Merge,
                Cut::Tube => SurgeryKind::Handle,
            },
            position: to_target(t.position).to_array(),
            radius: t.radius / scale,
            genus_before: op.genus_before,
            genus_after: op.genus_after,
            components_before: op.components_before,
            components_after: op.components_after,
        })
        .collect()
}

/// Removes the components of a surface that enclose no data: every vertex farther than `empty`
/// from the target (`distances` per vertex), as left behind when a neck pinched beside a bubble.
/// Returns the rest and the centroid of what was dropped; `None` when every component touches
/// the data (or none does: then nothing is certain and nothing is dropped).
pub fn drop_empty_components(
    mesh: &HalfedgeMesh,
    distances: &[f64],
    empty: f64,
) -> Option<(HalfedgeMesh, DVec3)> {
    let n = mesh.n_vertices();
    let mut comp = vec![u32::MAX; n];
    let mut near = Vec::new();
    for s in 0..n as u32 {
        if comp[s as usize] != u32::MAX || mesh.is_deleted_vertex(s) {
            continue;
        }
        let id = near.len() as u32;
        let mut touches = false;
        let mut stack = vec![s];
        comp[s as usize] = id;
        while let Some(v) = stack.pop() {
            touches |= distances[v as usize].abs() <= empty;
            for u in mesh.neighbors(v) {
                if comp[u as usize] == u32::MAX {
                    comp[u as usize] = id;
                    stack.push(u);
                }
            }
        }
        near.push(touches);
    }
    let dropped = near.iter().filter(|&&t| !t).count();
    if dropped == 0 || dropped == near.len() {
        return None;
    }
    let tris: Vec<[u32; 3]> = (0..mesh.n_faces() as u32)
        .filter(|&f| !mesh.is_deleted_face(f))
        .map(|f| mesh.face_vertices(f))
        .filter(|t| near[comp[t[0] as usize] as usize])
        .collect();
    let gone: Vec<DVec3> = (0..n)
        .filter(|&v| comp[v] != u32::MAX && !near[comp[v] as usize])
        .map(|v| mesh.position(v as u32))
        .collect();
    let centroid = gone.iter().sum::<DVec3>() / gone.len().max(1) as f64;
    let (p, t) = bridge::compact(mesh.positions(), &tris);
    Some((HalfedgeMesh::from_triangles(p, &t).ok()?, centroid))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::icosphere::icosphere;

    #[test]
    fn events_keep_their_json_keys_and_kind_names() {
        // `surgery` in `lsw wrap`'s JSON and the app's timeline read these names.
        let e = SurgeryEvent {
            step: 3,
            kind: SurgeryKind::Handle,
            position: [1.0, 2.0, 3.0],
            radius: 0.5,
            genus_before: 0,
            genus_after: 1,
            components_before: 1,
            components_after: 1,
        };
        assert_eq!(
            serde_json::to_string(&e).unwrap(),
            r#"{"step":3,"kind":"handle","position":[1.0,2.0,3.0],"radius":0.5,"genus_before":0,"genus_after":1,"components_before":1,"components_after":1}"#
        );
        let names = [
            SurgeryKind::Handle,
            SurgeryKind::Merge,
            SurgeryKind::Pinch,
            SurgeryKind::Drop,
        ]
        .map(|k| serde_json::to_value(k).unwrap());
        assert_eq!(names, ["handle", "merge", "pinch", "drop"]);
    }

    #[test]
    fn eroding_a_region_unpairs_its_rim_ring_and_only_its_own() {
        let mesh = icosphere(3, 1.0, DVec3::ZERO).unwrap();
        let n = mesh.n_vertices();
        // Two caps paired: around the north pole (the one eroded) and the south pole.
        let cap = |v: usize, z: f64| (mesh.position(v as u32).z * z.signum()) > z.abs();
        let mut partner: Vec<Option<u32>> = (0..n)
            .map(|v| (cap(v, 0.6) || cap(v, -0.6)).then_some(0))
            .collect();
        let before = partner.clone();
        let north = (0..n as u32).find(|&v| cap(v as usize, 0.6)).unwrap();
        erode_rims(&mesh, &mut partner, [north].into_iter());
        for v in 0..n {
            let rim = before[v].is_some()
                && mesh
                    .neighbors(v as u32)
                    .any(|u| before[u as usize].is_none());
            let north_cap = cap(v, 0.6);
            match (north_cap, rim) {
                (true, true) => assert_eq!(partner[v], None, "rim vertex {v} still paired"),
                _ => assert_eq!(partner[v], before[v], "vertex {v} changed"),
            }
        }
        let unpaired = (0..n)
            .filter(|&v| before[v].is_some() && partner[v].is_none())
            .count();
        assert!(unpaired > 0);
        // What is left of the north cap is still a patch: eroding again takes the next ring.
        let left = (0..n)
            .filter(|&v| cap(v, 0.6) && partner[v].is_some())
            .count();
        assert!(left > 0, "the cap vanished in one ring");
    }
}
