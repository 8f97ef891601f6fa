//! `lsw info FILE`: reads a geometry file and prints what it holds, as JSON — the quickest way
//! to check that a scan or mesh will be accepted, and what kind of target it makes.

use crate::io::{read_path_with, ReadResult};
use crate::mesh::HalfedgeMesh;
use crate::target::Surface;
use serde_json::json;
use std::path::PathBuf;

/// Arguments of `lsw info`.
#[derive(clap::Args, Debug)]
pub struct InfoArgs {
    /// The file to inspect (any format of [`crate::io::FORMATS`]).
    #[arg(help = super::input_help("The file to inspect"))]
    pub file: PathBuf,
    /// Volume inputs: iso-value, frame, inside, array, iso-surface output.
    #[command(flatten)]
    pub volume: super::volume::VolumeArgs,
}

/// The JSON `lsw info` prints for a read file. Keys: file, format, encoding, kind, vertices,
/// faces, bbox {min, max, diagonal}; points_left_out {points, why} where the file marks points
/// unusable and they were not read (see [`crate::io::LeftOut`]); for meshes also closed,
/// manifold, manifold_problem, euler_characteristic, edges, boundary_edges, non_manifold_edges,
/// isolated_vertices, repairs ({merged_vertices, dropped_faces, flipped_faces, split_vertices,
/// filled_holes} where reading mended the mesh's indices, see
/// [`crate::target::Target::repaired`]; the other keys describe the mended mesh, else null); for
/// volumes also `volume` (see [`super::volume::volume_json`]; the mesh keys then describe the
/// iso-surface).
pub fn info_json(file: &str, r: &ReadResult) -> serde_json::Value {
    let t = &r.target;
    let mut v = json!({
        "file": file,
        "format": r.format,
        "encoding": r.encoding,
        "kind": t.kind(),
        "vertices": t.points.len(),
        "faces": t.triangles.len(),
        "bbox": {
            "min": t.bbox.min.to_array(),
            "max": t.bbox.max.to_array(),
            "diagonal": t.bbox.diagonal(),
        },
    });
    if let Some(l) = r.left_out {
        v.as_object_mut()
            .expect("object")
            .insert("points_left_out".into(), json!(l));
    }
    let faces = match t.oracle().surface() {
        Surface::Triangles { triangles, .. } => Some(triangles),
        Surface::Points(_) => None,
    };
    if faces.is_some() {
        v.as_object_mut()
            .expect("object")
            .insert("repairs".into(), json!(r.repairs));
    }
    if let Some(vr) = &r.volume {
        v.as_object_mut()
            .expect("object")
            .insert("volume".into(), super::volume::volume_json(vr));
    }
    if let Some(triangles) = faces {
        let crate::mesh::EdgeCounts {
            edges,
            boundary,
            non_manifold: over,
        } = crate::mesh::edge_counts(triangles);
        let mut used = vec![false; t.points.len()];
        for &i in triangles.iter().flatten() {
            used[i as usize] = true;
        }
        let nused = used.iter().filter(|&&u| u).count();
        let closed = boundary == 0 && over == 0;
        // Manifold: the halfedge structure can be built (edge-manifold, consistently oriented,
        // no bow-tie boundary vertex) and, when closed, no vertex has two separate fans.
        let problem = match HalfedgeMesh::from_triangles(t.points.clone(), triangles) {
            Err(e) => Some(e.to_string()),
            Ok(m) if closed => match m.validate() {
                Err(e @ crate::mesh::ValidationError::NonManifoldVertex { .. }) => {
                    Some(e.to_string())
                }
                _ => None,
            },
            Ok(_) => None,
        };
        let o = v.as_object_mut().expect("object");
        o.insert("closed".into(), json!(closed));
        o.insert("manifold".into(), json!(problem.is_none()));
        o.insert("manifold_problem".into(), json!(problem));
        o.insert(
            "euler_characteristic".into(),
            json!(nused as i64 - edges as i64 + triangles.len() as i64),
        );
        o.insert("edges".into(), json!(edges));
        o.insert("boundary_edges".into(), json!(boundary));
        o.insert("non_manifold_edges".into(), json!(over));
        o.insert("isolated_vertices".into(), json!(t.points.len() - nused));
    }
    v
}

/// Reads the file and returns the pretty JSON; the error message names format and position.
pub fn run(a: &InfoArgs) -> Result<String, String> {
    let r = read_path_with(&a.file, &a.volume.options()).map_err(super::explained)?;
    a.volume.write_isosurface(&r)?;
    let v = info_json(&a.file.display().to_string(), &r);
    Ok(serde_json::to_string_pretty(&v).expect("JSON of plain values"))
}
