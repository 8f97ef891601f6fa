//! Final fit, sharp features: the wrap's vertices are put onto the target's corners and crease
//! lines ([`crate::geometry::creases`]) and its edges are aligned with them, so that the
//! remesh that follows keeps them sharp (feature edges are split along themselves and never
//! flipped, their vertices slide only along them, corners are pinned).
//!
//! Without this, a surface that settled at the offset d₀ and was then projected onto the faces
//! keeps a bevel about a cell wide along every crease and cuts every corner: on a target of
//! flat faces that is the whole Hausdorff error.
//!
//! Order: corners first (each takes its nearest wrap vertex), then crease vertices (nearest
//! first, one per half edge length along a line, so two never land on one point), then flips
//! that join two crease vertices which the triangulation left unconnected. A move or flip that
//! would turn a face over is not made; the fit's intersection check covers the rest.

use super::reach::{through_material, MOVE_FLOOR};
use crate::geometry::creases::{CreaseHit, Creases};
use crate::geometry::operators::normals::angle_weighted_normals;
use crate::geometry::spatial::bvh::TriangleBvh;
use crate::mesh::HalfedgeMesh;
use crate::remesh::features::Features;
use glam::DVec3;
use std::collections::HashMap;

/// Wrap vertices placed on a corner or crease line and edges marked along them.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct CreaseReport {
    /// Vertices moved onto a target corner.
    pub corners: usize,
    /// Vertices on a crease line (corners excluded).
    pub crease_vertices: usize,
    /// Edges along a crease line.
    pub crease_edges: usize,
    /// Flips that joined two crease vertices.
    pub flips: usize,
}

/// A vertex may land on a corner or crease this far away, in its mean edge lengths.
const REACH: f64 = 0.5;
/// An edge lies along a crease when its midpoint is within this fraction of its length of one.
const ALONG: f64 = 0.1;

/// Snaps `mesh` onto `creases` (see the module doc); returns the wrap's features, indexed like
/// the mesh (which is garbage-collected first), for `remesh_with_features`.
///
/// `reach` is how far a vertex may move onto a corner or crease line (beyond half its edge
/// length): the settled surface rounds a ridge by about d₀ and bridges a valley (curvature
/// flow holds it back there), so on fine meshes its nearest vertices lie cells away.
///
/// Vertices with `banned[v]` (indexed after garbage collection; shorter means none) are left
/// alone and take part in no flip: the caller bans those near an intersection the last try made.
///
/// With the target's `triangles` (a mesh target), a vertex does not move through the target's
/// material: a vertex's nearest crease can lie across a thin slit (seen from a lip, the far end
/// of a mouth), and the faces pulled there would cut through the material.
pub fn snap_to_creases(
    mesh: &mut HalfedgeMesh,
    creases: &Creases,
    reach: f64,
    banned: &[bool],
    triangles: Option<&TriangleBvh>,
) -> (Features, CreaseReport) {
    mesh.garbage_collect();
    let mut features = Features::none(mesh);
    features.pinned = vec![false; mesh.n_vertices()];
    let mut report = CreaseReport::default();
    if creases.is_empty() || mesh.n_faces() == 0 {
        return (features, report);
    }
    let nv = mesh.n_vertices();
    let snap = Snap {
        creases,
        reach,
        banned,
        triangles: triangles.map(|t| (t, MOVE_FLOOR * reach)),
        spacing: (0..nv as u32).map(|v| mesh.mean_edge_length(v)).collect(),
        normals: angle_weighted_normals(mesh),
    };
    report.corners = snap.corners(mesh, &mut features);
    let candidates = snap.crease_candidates(mesh, &features);
    report.crease_vertices = snap.crease_vertices(mesh, &mut features, candidates);
    report.flips = snap.join_crease_vertices(mesh, &features);
    for e in 0..mesh.n_edges() as u32 {
        let (a, b) = (mesh.to(2 * e + 1), mesh.to(2 * e));
        if features.vertices[a as usize]
            && features.vertices[b as usize]
            && along(mesh, creases, a, b)
        {
            features.edges[e as usize] = true;
            report.crease_edges += 1;
        }
    }
    (features, report)
}

/// What the crease snap reads as it goes (see [`snap_to_creases`]).
struct Snap<'a> {
    creases: &'a Creases,
    reach: f64,
    banned: &'a [bool],
    /// The target's triangles, and the least dip a way through them may make.
    triangles: Option<(&'a TriangleBvh, f64)>,
    /// Each vertex's mean edge length before the snap.
    spacing: Vec<f64>,
    /// Each vertex's normal before the snap.
    normals: Vec<DVec3>,
}

impl Snap<'_> {
    /// Whether vertex `v` may move or take part in a flip.
    fn free(&self, v: u32) -> bool {
        !self.banned.get(v as usize).copied().unwrap_or(false)
    }

    /// 1. Corners: each takes its nearest wrap vertex within reach; returns how many did.
    fn corners(&self, mesh: &mut HalfedgeMesh, features: &mut Features) -> usize {
        let (creases, spacing) = (self.creases, &self.spacing);
        // (The queries in parallel natively; the choice in vertex order.)
        let corner_limit = |v: usize| (REACH * 1.5 * spacing[v]).max(self.reach);
        let nearest = crate::parallel::map(mesh.n_vertices(), |v| {
            self.free(v as u32)
                .then(|| creases.nearest_corner_within(mesh.position(v as u32), corner_limit(v)))
                .flatten()
        });
        let mut owner: Vec<Option<(f64, u32)>> = vec![None; creases.corners.len()];
        for (v, hit) in nearest.into_iter().enumerate() {
            if let Some((c, d)) = hit {
                let best = &mut owner[c as usize];
                if d <= corner_limit(v) && best.is_none_or(|(bd, _)| d < bd) {
                    *best = Some((d, v as u32));
                }
            }
        }
        let mut placed = 0;
        for (c, o) in owner.iter().enumerate() {
            if let Some((_, v)) = *o {
                if try_move(mesh, &self.normals, v, creases.corners[c], self.triangles) {
                    features.vertices[v as usize] = true;
                    features.pinned[v as usize] = true;
                    placed += 1;
                }
            }
        }
        placed
    }

    /// 2a. The vertices that may go onto a crease line, `(distance, vertex, landing point)`,
    /// nearest first. A vertex facing an edge that already lies on a crease (an earlier pass
    /// put it there) stays: it would land on it.
    fn crease_candidates(&self, mesh: &HalfedgeMesh, features: &Features) -> Vec<Candidate> {
        let (nv, spacing) = (mesh.n_vertices(), &self.spacing);
        // (Independent queries: in parallel natively, collected in vertex order. One query per
        // vertex answers both whether it is on a line and where it would land.)
        let closest: Vec<Option<CreaseHit>> = crate::parallel::map(nv, |v| {
            let reach = (REACH * spacing[v]).max(self.reach);
            self.creases
                .closest_edge_point(mesh.position(v as u32), reach)
        });
        let on_line: Vec<bool> = (0..nv)
            .map(|v| closest[v].is_some_and(|hit| hit.distance <= 1e-9 * spacing[v]))
            .collect();
        let faces_lined_edge = |v: u32| {
            mesh.outgoing(v).any(|h| {
                !mesh.is_boundary_halfedge(h)
                    && on_line[mesh.to(h) as usize]
                    && on_line[mesh.to(mesh.next(h)) as usize]
            })
        };
        let hits = crate::parallel::map(nv, |v| {
            let v = v as u32;
            // (A vertex facing a lined edge stays unless it is on the line itself.)
            let facing_lined = !on_line[v as usize] && faces_lined_edge(v);
            if features.vertices[v as usize] || !self.free(v) || facing_lined {
                return None;
            }
            let hit = closest[v as usize]?;
            Some((hit.distance, v, hit.point))
        });
        let mut candidates: Vec<Candidate> = hits.into_iter().flatten().collect();
        candidates.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
        candidates
    }

    /// 2b. The `candidates` onto their crease lines in turn; one is skipped when a crease
    /// vertex already sits within half its edge length of its landing point, so the line gets
    /// one vertex per edge length, from the row of vertices nearest to it. Returns how many
    /// moved.
    fn crease_vertices(
        &self,
        mesh: &mut HalfedgeMesh,
        features: &mut Features,
        candidates: Vec<Candidate>,
    ) -> usize {
        let spacing = &self.spacing;
        let cell = candidates
            .iter()
            .map(|&(_, v, _)| REACH * spacing[v as usize])
            .fold(f64::MIN_POSITIVE, f64::max);
        let key = |q: DVec3| (q / cell).floor().to_array().map(|x| x as i64);
        let mut placed: HashMap<[i64; 3], Vec<DVec3>> = HashMap::new();
        for v in (0..mesh.n_vertices() as u32).filter(|&v| features.vertices[v as usize]) {
            let p = mesh.position(v);
            placed.entry(key(p)).or_default().push(p);
        }
        let mut moved = 0;
        for (_, v, q) in candidates {
            let r = REACH * spacing[v as usize];
            let k = key(q);
            let crowded = (-1..=1).any(|i| {
                (-1..=1).any(|j| {
                    (-1..=1).any(|l| {
                        placed
                            .get(&[k[0] + i, k[1] + j, k[2] + l])
                            .is_some_and(|ps| ps.iter().any(|&p| (p - q).length() < r))
                    })
                })
            });
            if !crowded && try_move(mesh, &self.normals, v, q, self.triangles) {
                features.vertices[v as usize] = true;
                placed.entry(k).or_default().push(q);
                moved += 1;
            }
        }
        moved
    }

    /// 3. Flips that join two crease vertices across a quad; returns how many.
    fn join_crease_vertices(&self, mesh: &mut HalfedgeMesh, features: &Features) -> usize {
        let mut flips = 0;
        for e in 0..mesh.n_edges() as u32 {
            // (The cheap tests first: few edges face two crease vertices.)
            if mesh.is_deleted_edge(e) || !mesh.is_interior_edge(e) {
                continue;
            }
            if self.joins(mesh, features, e) {
                mesh.flip_edge(e);
                flips += 1;
            }
        }
        flips
    }

    /// Whether flipping interior edge `e` joins the two crease vertices across its quad along a
    /// crease, where the edge itself does not lie along one, without folding the quad over.
    fn joins(&self, mesh: &HalfedgeMesh, features: &Features, e: u32) -> bool {
        let (creases, normals) = (self.creases, &self.normals);
        let (h0, h1) = (2 * e, 2 * e + 1);
        let (a, b) = (mesh.to(h1), mesh.to(h0));
        let (c, d) = (mesh.to(mesh.next(h0)), mesh.to(mesh.next(h1)));
        let on = |v: u32| features.vertices[v as usize];
        let free = |v: u32| self.free(v);
        if !(on(c) && on(d) && [a, b, c, d].into_iter().all(free) && mesh.is_flip_ok(e)) {
            return false;
        }
        if (on(a) && on(b) && along(mesh, creases, a, b)) || !along(mesh, creases, c, d) {
            return false;
        }
        // A crease vertex already joined along its line on both sides needs no more edges
        // along it: a third would skip over a neighbour and overlap its faces.
        let joined = |v: u32| {
            mesh.neighbors(v)
                .filter(|&u| on(u) && along(mesh, creases, v, u))
                .count()
        };
        let full = |v: u32| !features.pinned[v as usize] && joined(v) >= 2;
        if full(c) || full(d) {
            return false;
        }
        // After the flip: (c, a, d) on a's side and (d, b, c) on b's side of the crease.
        let [pa, pb, pc, pd] = [a, b, c, d].map(|v| mesh.position(v));
        // The quad unfolded (seen along the mean normal of a and b) must be convex: the new
        // edge crosses the old one. On a curved crease a bent quad would fold over.
        let up = normals[a as usize] + normals[b as usize];
        let turn = |u: DVec3, v: DVec3, w: DVec3| (v - u).cross(w - u).dot(up);
        if turn(pc, pd, pa) * turn(pc, pd, pb) >= 0.0 || turn(pa, pb, pc) * turn(pa, pb, pd) >= 0.0
        {
            return false;
        }
        let (na, nb) = ((pa - pc).cross(pd - pc), (pb - pd).cross(pc - pd));
        let tiny = 1e-6 * (pc - pd).length_squared();
        !(na.length() <= tiny
            || nb.length() <= tiny
            || na.dot(normals[a as usize]) <= 0.0
            || nb.dot(normals[b as usize]) <= 0.0)
    }
}

/// A vertex that may go onto a crease line: `(distance, vertex, landing point)`.
type Candidate = (f64, u32, DVec3);

/// Whether the edge from `a` to `b` lies along a crease (its midpoint within [`ALONG`] of its
/// length of one).
fn along(mesh: &HalfedgeMesh, creases: &Creases, a: u32, b: u32) -> bool {
    let (pa, pb) = (mesh.position(a), mesh.position(b));
    creases
        .closest_edge_point(0.5 * (pa + pb), ALONG * (pa - pb).length())
        .is_some()
}

/// Moves `v` to `q` unless that turns one of its faces over (or makes it degenerate).
fn try_move(
    mesh: &mut HalfedgeMesh,
    normals: &[DVec3],
    v: u32,
    q: DVec3,
    triangles: Option<(&TriangleBvh, f64)>,
) -> bool {
    let old = mesh.position(v);
    if let Some((t, floor)) = triangles {
        // (`q` lies on the target: a move shorter than the floor keeps its middle within half
        // the floor of it, which [`through_material`] never refuses.)
        if (q - old).length() > floor && through_material(t, old, q, floor) {
            return false;
        }
    }
    let n = normals[v as usize];
    let faces_ok = mesh.outgoing(v).all(|h| {
        if mesh.is_boundary_halfedge(h) {
            return true;
        }
        let (a, b) = (
            mesh.position(mesh.to(h)),
            mesh.position(mesh.to(mesh.next(h))),
        );
        let before = (a - old).cross(b - old);
        let after = (a - q).cross(b - q);
        let tiny = 1e-6 * (a - b).length_squared();
        after.length() > tiny && after.dot(before) > 0.0 && after.dot(n) > 0.0
    });
    if faces_ok {
        mesh.positions_mut()[v as usize] = q;
    }
    faces_ok
}
