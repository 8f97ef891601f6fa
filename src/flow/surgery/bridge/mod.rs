//! Surgery on facing patches of a closed surface: two patches that face each other are cut out
//! and their boundary loops glued with a tube (genus +1, or one component less when the patches
//! lie on two components); a ring-shaped patch that faces itself (a neck pinching in empty
//! space) is cut out and both its loops capped (one component more, or genus −1).
//!
//! The patches are the facing vertices found by [`super::detect::facing_pairs`], grouped into
//! connected regions of the surface; a region is cut only when its faces form a disk (one simple
//! boundary loop) and its partners form another such disk. The tube zips the two loops with the
//! shortest rungs, A forwards and B backwards, so its faces take the orientation of the
//! surface they join.

mod labels;
mod loops;
mod neck;
mod tangled;
mod tubes;
mod zip;

use crate::mesh::HalfedgeMesh;
use glam::DVec3;
use labels::{regions, Labels};

/// What an operation did to the surface.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Cut {
    /// Two patches replaced by a tube.
    Tube,
    /// A neck replaced by two caps.
    Pinch,
}

/// One operation: a tube glued between two patches, or a neck cut and capped.
#[derive(Clone, Debug, PartialEq)]
pub struct Tube {
    /// Which operation.
    pub cut: Cut,
    /// Centroid of the two loops (the hole the tube opens, or the neck cut).
    pub position: DVec3,
    /// Farthest loop vertex from `position`.
    pub radius: f64,
    /// Vertices on the two loops.
    pub loop_vertices: [usize; 2],
    /// The region it was made for (pass it to `skip` to leave that operation out).
    pub region: u32,
    /// A vertex of each side's region (of a pinch: twice the neck's), in the surface operated on.
    pub sides: [u32; 2],
    /// Its new faces: indices into [`Glued::triangles`].
    pub faces: std::ops::Range<usize>,
}

/// The surface after surgery (compacted: vertices of the cut patches removed).
pub struct Glued {
    pub positions: Vec<DVec3>,
    pub triangles: Vec<[u32; 3]>,
    pub tubes: Vec<Tube>,
}

/// Regions of at least `min_vertices` paired vertices, matched into (A, B) pairs of distinct,
/// mutually facing regions; each pair is replaced by a tube, and each region facing itself
/// across a neck by two caps. `None` when nothing qualifies.
///
/// A patch is cut only once it spans its hole: the median distance of its rim to the target
/// (`distances` per vertex) below `rim` or below half its deepest vertex's, or once the membranes
/// have `settled` (stopped closing in on each other). Two membranes first touch at one point; a
/// tube cut there would leave the rest of them facing each other around it, and cutting that
/// later would open a second handle through the same hole.
pub fn glue_facing_regions(pass: &Pass) -> Option<Glued> {
    let level = regions(pass.mesh, pass.partner);
    let votes = level.votes(pass.partner);
    let faces_of = Labels::facing(&votes);
    let mut work = Work::new(pass.mesh);
    pass.tubes(&level, &faces_of, &mut work);
    pass.tangled_tubes(&level, &votes, &mut work);
    pass.necks(&level, &faces_of, &mut work);
    (!work.tubes.is_empty()).then(|| work.glued(pass.mesh))
}

/// The operations of one pass so far: the faces they cut out, their new vertices and faces, and
/// their records.
struct Work {
    /// Per face of the surface: cut out.
    removed: Vec<bool>,
    /// The surface's vertices, then the caps' centres.
    positions: Vec<DVec3>,
    /// The new faces, in the order of the records.
    tris: Vec<[u32; 3]>,
    tubes: Vec<Tube>,
}

impl Work {
    /// Nothing done yet on `mesh`.
    fn new(mesh: &HalfedgeMesh) -> Self {
        Work {
            removed: vec![false; mesh.n_faces()],
            positions: mesh.positions().to_vec(),
            tris: Vec::new(),
            tubes: Vec::new(),
        }
    }

    /// The faces of `mesh` left, followed by the new ones (the records' face ranges moved after
    /// the faces left), without the vertices no face uses any more.
    fn glued(self, mesh: &HalfedgeMesh) -> Glued {
        let Work {
            removed,
            positions,
            tris: new_tris,
            mut tubes,
        } = self;
        let mut tris: Vec<[u32; 3]> = (0..mesh.n_faces() as u32)
            .filter(|&f| !mesh.is_deleted_face(f) && !removed[f as usize])
            .map(|f| mesh.face_vertices(f))
            .collect();
        let kept = tris.len();
        for t in &mut tubes {
            t.faces = kept + t.faces.start..kept + t.faces.end;
        }
        tris.extend(new_tris);
        let (positions, triangles) = compact(&positions, &tris);
        Glued {
            positions,
            triangles,
            tubes,
        }
    }
}

/// What to glue (see [`glue_facing_regions`]).
pub struct Pass<'a> {
    pub mesh: &'a HalfedgeMesh,
    /// Each vertex's facing vertex, if any.
    pub partner: &'a [Option<u32>],
    /// Each vertex's distance to the target.
    pub distances: &'a [f64],
    /// A patch spans its hole once its rim's median distance is below this.
    pub rim: f64,
    /// The membranes stopped closing in on each other: cut them as they are.
    pub settled: bool,
    /// Smallest region cut (vertices).
    pub min_vertices: usize,
    /// Regions left out (see [`Tube::region`]).
    pub skip: &'a [u32],
    /// Each vertex's part in empty space ([`super::detect::far_parts`]).
    pub far: &'a [u32],
    /// Handles the surface has beyond the target's, where the target's genus is known: neck
    /// cuts may take away that many (see [`super::detect::FacingQuery::least_genus`]).
    pub spare_handles: Option<i64>,
}

/// The record of an operation on loops `a` and `b` (their centroid and the farthest loop vertex)
/// made for region `region` between `sides`, with new faces `faces` (indices among the new
/// faces for now).
fn record(
    mesh: &HalfedgeMesh,
    cut: Cut,
    a: &[u32],
    b: &[u32],
    region: u32,
    sides: [u32; 2],
    faces: std::ops::Range<usize>,
) -> Tube {
    let c: DVec3 =
        a.iter().chain(b).map(|&v| mesh.position(v)).sum::<DVec3>() / (a.len() + b.len()) as f64;
    let radius = a
        .iter()
        .chain(b)
        .map(|&v| mesh.position(v).distance(c))
        .fold(0.0, f64::max);
    Tube {
        cut,
        position: c,
        radius,
        loop_vertices: [a.len(), b.len()],
        region,
        sides,
        faces,
    }
}

/// Drops unreferenced vertices, keeping the order of the others.
pub(super) fn compact(positions: &[DVec3], tris: &[[u32; 3]]) -> (Vec<DVec3>, Vec<[u32; 3]>) {
    let mut map = vec![u32::MAX; positions.len()];
    for t in tris {
        for &v in t {
            map[v as usize] = 0;
        }
    }
    let mut out = Vec::new();
    for (v, m) in map.iter_mut().enumerate() {
        if *m == 0 {
            *m = out.len() as u32;
            out.push(positions[v]);
        }
    }
    let tris = tris.iter().map(|t| t.map(|v| map[v as usize])).collect();
    (out, tris)
}
