//! Remeshing the closed meshes of the shared test-data folder (`LSW_SHARED_DATA`): validity,
//! genus, quality and fidelity (with back-projection the result stays on the input surface).
//! Native only (reads files); ignored when the build had no `LSW_SHARED_DATA`.
#![cfg(not(target_arch = "wasm32"))]

use lsw::io::read_path;
use lsw::mesh::HalfedgeMesh;
use lsw::metrics::distance::two_sided_distances;
use lsw::metrics::quality::quality_stats;
use lsw::remesh::{remesh, RemeshSettings};

/// A closed mesh of the shared test data (the tests reading it are ignored without it).
fn load(name: &str) -> HalfedgeMesh {
    let dir = std::env::var("LSW_SHARED_DATA").expect("LSW_SHARED_DATA (the build had it)");
    let t = read_path(std::path::Path::new(&dir).join(name))
        .unwrap()
        .target;
    HalfedgeMesh::from_triangles(t.points, &t.triangles).unwrap()
}

#[test]
#[cfg_attr(
    not(shared_data),
    ignore = "needs the shared test data (LSW_SHARED_DATA)"
)]
fn shared_closed_meshes_remesh_cleanly() {
    for (name, genus) in [("3Torus.obj", 3), ("spot.obj", 0)] {
        let mut m = load(name);
        let original = (m.positions().to_vec(), m.triangles());
        let diag = lsw::geometry::aabb::Aabb::from_points(m.positions()).diagonal();
        let s = RemeshSettings {
            min_edge_length: 0.004 * diag,
            max_edge_length: 0.016 * diag,
            approx_error: 0.0005 * diag,
            use_projection: true,
            ..Default::default()
        };
        for call in 0..3 {
            let rep = remesh(&mut m, &s).unwrap();
            let v = m
                .validate()
                .unwrap_or_else(|e| panic!("{name}, call {call}: {e}"));
            assert_eq!(v.genus, genus, "{name}: genus");
            eprintln!("{name} call {call}: {rep:?}");
            if call == 0 {
                // The projection target is the surface at the start of the call (PMP's
                // self-reference), so after one call every vertex lies on the input.
                let d =
                    two_sided_distances(m.positions(), &m.triangles(), &original.0, &original.1);
                assert!(d.mesh_to_target.max < 1e-9 * diag, "{name}: {d:?}");
            }
        }
        let q = quality_stats(m.positions(), &m.triangles());
        let d = two_sided_distances(m.positions(), &m.triangles(), &original.0, &original.1)
            .percent_of(diag);
        eprintln!(
            "{name}: {} vertices, κ mean {:.4}, κ ≤ 1.5 {:.4}, 2r/R mean {:.4}, distances {:.4} % / {:.4} %, Hausdorff {:.4} %",
            m.n_vertices(),
            q.kappa.mean,
            q.kappa_le_1_5,
            q.radius_ratio.mean,
            d.mesh_to_target.mean,
            d.target_to_mesh.mean,
            d.hausdorff
        );
        assert!(q.kappa_le_1_5 > 0.99, "{name}: {q:?}");
        assert!(q.radius_ratio.mean > 0.93, "{name}: {q:?}");
        // Later calls project onto the previous call's result: the drift stays at chord-error
        // level.
        assert!(d.hausdorff < 0.5, "{name}: {d:?}");
    }
}
