//! Feature detection and feature-preserving remeshing on a cube: corners and creases stay sharp
//! with features on and are rounded off with features off; flat and concave vertices are never
//! marked. Runs natively and in headless Chromium.

use lsw::geometry::icosphere::icosphere;
use lsw::geometry::spatial::bvh::TriangleBvh;
use lsw::mesh::HalfedgeMesh;
use lsw::remesh::features::detect;
use lsw::remesh::{remesh, FeatureDetector, FeatureSettings, RemeshSettings};
use lsw::DVec3;
use wasm_bindgen_test::*;

wasm_bindgen_test_configure!(run_in_browser);

/// The cube [−1, 1]³ with every face an `n × n` grid of quads split into triangles (welded,
/// outward oriented).
fn cube(n: u32) -> HalfedgeMesh {
    let mut pos: Vec<DVec3> = Vec::new();
    let mut index = std::collections::BTreeMap::new();
    let mut id = |p: DVec3, pos: &mut Vec<DVec3>| -> u32 {
        let key = (
            (p.x * 1e6).round() as i64,
            (p.y * 1e6).round() as i64,
            (p.z * 1e6).round() as i64,
        );
        *index.entry(key).or_insert_with(|| {
            pos.push(p);
            pos.len() as u32 - 1
        })
    };
    let mut faces = Vec::new();
    // Each side: normal axis k, sign s; (u, v) axes chosen so that u × v = s·e_k.
    for k in 0..3 {
        for s in [-1.0, 1.0] {
            let (u, v) = ((k + 1) % 3, (k + 2) % 3);
            let g = |i: u32, j: u32| {
                let mut p = DVec3::ZERO;
                p[k] = s;
                p[u] = -1.0 + 2.0 * i as f64 / n as f64;
                p[v] = -1.0 + 2.0 * j as f64 / n as f64;
                p
            };
            for i in 0..n {
                for j in 0..n {
                    let a = id(g(i, j), &mut pos);
                    let b = id(g(i + 1, j), &mut pos);
                    let c = id(g(i + 1, j + 1), &mut pos);
                    let d = id(g(i, j + 1), &mut pos);
                    if s > 0.0 {
                        faces.push([a, b, c]);
                        faces.push([a, c, d]);
                    } else {
                        faces.push([a, c, b]);
                        faces.push([a, d, c]);
                    }
                }
            }
        }
    }
    let m = HalfedgeMesh::from_triangles(pos, &faces).unwrap();
    assert!(m.signed_volume() > 7.9);
    m
}

fn corners() -> Vec<DVec3> {
    let mut c = Vec::new();
    for x in [-1.0, 1.0] {
        for y in [-1.0, 1.0] {
            for z in [-1.0, 1.0] {
                c.push(DVec3::new(x, y, z));
            }
        }
    }
    c
}

/// (worst corner → nearest vertex, worst crease point → surface) after remeshing.
fn sharpness(m: &HalfedgeMesh) -> (f64, f64) {
    let corner = corners()
        .iter()
        .map(|c| {
            m.positions()
                .iter()
                .map(|p| (*p - *c).length())
                .fold(f64::INFINITY, f64::min)
        })
        .fold(0.0, f64::max);
    let bvh = TriangleBvh::new(m.positions(), &m.triangles());
    let mut crease = 0.0f64;
    for c in corners() {
        for k in 0..3 {
            if c[k] > 0.0 {
                continue;
            }
            for t in 1..40 {
                let mut p = c;
                p[k] = -1.0 + 2.0 * t as f64 / 40.0;
                crease = crease.max(bvh.distance(p));
            }
        }
    }
    (corner, crease)
}

fn remeshed_cube(detector: FeatureDetector) -> (HalfedgeMesh, (f64, f64)) {
    let mut m = cube(10);
    let s = RemeshSettings {
        min_edge_length: 0.12,
        max_edge_length: 0.3,
        approx_error: 0.02,
        features: FeatureSettings {
            detector,
            ..Default::default()
        },
        ..Default::default()
    };
    for k in 0..4 {
        remesh(&mut m, &s).unwrap();
        let r = m.validate().unwrap_or_else(|e| panic!("call {k}: {e}"));
        assert_eq!(r.genus, 0);
    }
    let sh = sharpness(&m);
    (m, sh)
}

#[wasm_bindgen_test(unsupported = test)]
fn cube_corners_and_creases_stay_sharp_with_features() {
    let (_, off) = remeshed_cube(FeatureDetector::Off);
    let (_, dihedral) = remeshed_cube(FeatureDetector::DihedralAngle);
    let (_, both) = remeshed_cube(FeatureDetector::Both);
    println!("corner / crease deviation: off {off:?}, dihedral {dihedral:?}, both {both:?}");
    // With features: corners are locked, crease vertices slide along the crease.
    for (name, (corner, crease)) in [("dihedral", dihedral), ("both", both)] {
        assert!(corner < 1e-9, "{name}: corner moved by {corner}");
        assert!(crease < 1e-6, "{name}: crease deviates by {crease}");
    }
    // Without: rounded off, by a visible amount.
    assert!(off.0 > 0.02, "features off: corners still sharp? {off:?}");
    assert!(
        off.1 > 10.0 * dihedral.1.max(1e-4),
        "features off: creases still sharp? {off:?}"
    );
}

#[wasm_bindgen_test(unsupported = test)]
fn mean_curvature_detector_marks_cube_corners_not_faces() {
    let m = cube(6);
    let f = detect(
        &m,
        &FeatureSettings {
            detector: FeatureDetector::MeanCurvature,
            ..Default::default()
        },
    );
    let is_corner = |p: DVec3| p.abs().cmpgt(DVec3::splat(0.999)).all();
    let on_crease = |p: DVec3| p.abs().cmpgt(DVec3::splat(0.999)).bitmask().count_ones() >= 2;
    for (v, p) in m.positions().iter().enumerate() {
        if is_corner(*p) {
            assert!(f.vertices[v], "corner {p:?} not marked");
        }
        if !on_crease(*p) {
            assert!(!f.vertices[v], "flat vertex {p:?} marked");
        }
    }
}

#[wasm_bindgen_test(unsupported = test)]
fn flat_smooth_and_concave_vertices_are_not_marked() {
    let all = FeatureSettings {
        detector: FeatureDetector::Both,
        ..Default::default()
    };
    // A smooth convex sphere: nothing (the reference marks every vertex).
    let s = icosphere(3, 1.0, DVec3::ZERO).unwrap();
    let f = detect(&s, &all);
    assert_eq!((f.n_vertices(), f.n_edges()), (0, 0));
    // The cube turned inside out: all creases and corners are concave.
    let c = cube(6);
    let flipped: Vec<[u32; 3]> = c.triangles().iter().map(|&[a, b, d]| [a, d, b]).collect();
    let inv = HalfedgeMesh::from_triangles(c.positions().to_vec(), &flipped).unwrap();
    let f = detect(&inv, &all);
    assert_eq!((f.n_vertices(), f.n_edges()), (0, 0));
    // Sanity: the same cube outward has creases (so the test can fail).
    let f = detect(&c, &all);
    assert_eq!(f.n_edges(), 12 * 6);
    // With concave creases allowed, the inside-out cube has them too.
    let f = detect(
        &inv,
        &FeatureSettings {
            detector: FeatureDetector::DihedralAngle,
            include_concave_edges: true,
            ..Default::default()
        },
    );
    assert_eq!(f.n_edges(), 12 * 6);
}

/// A frozen region (`Features::frozen`) comes out of a remesh as it went in: its vertices where
/// they were, the faces between them kept, while the rest of a coarse sphere is refined.
#[test]
#[wasm_bindgen_test]
fn a_frozen_region_is_left_as_it_was() {
    use lsw::remesh::{remesh_with_features, Features};
    let mut mesh = icosphere(2, 1.0, DVec3::ZERO).unwrap();
    let before = mesh.clone();
    // Frozen: the vertices above z = 0.6 and their faces.
    let mut f = Features::none(&mesh);
    f.frozen = (0..mesh.n_vertices() as u32)
        .map(|v| mesh.position(v).z > 0.6)
        .collect();
    let frozen: Vec<u32> = (0..mesh.n_vertices() as u32)
        .filter(|&v| f.frozen[v as usize])
        .collect();
    assert!(frozen.len() >= 5);
    let rs = RemeshSettings {
        min_edge_length: 0.05,
        max_edge_length: 0.15,
        approx_error: 0.01,
        ..Default::default()
    };
    remesh_with_features(&mut mesh, &rs, &f).unwrap();
    assert!(
        mesh.n_vertices() > 2 * before.n_vertices(),
        "the rest is refined"
    );
    // Each frozen vertex is still where it was, and each face between three frozen vertices is
    // still a face.
    let key = |p: DVec3| p.to_array().map(f64::to_bits);
    let now: std::collections::HashSet<[[u64; 3]; 3]> = mesh
        .triangles()
        .iter()
        .map(|t| {
            let mut k = t.map(|v| key(mesh.position(v)));
            k.sort_unstable();
            k
        })
        .collect();
    for v in &frozen {
        let p = before.position(*v);
        assert!((0..mesh.n_vertices() as u32).any(|u| mesh.position(u) == p));
    }
    let inside: Vec<[u32; 3]> = before
        .triangles()
        .into_iter()
        .filter(|t| t.iter().all(|&v| f.frozen[v as usize]))
        .collect();
    assert!(!inside.is_empty());
    for t in inside {
        let mut k = t.map(|v| key(before.position(v)));
        k.sort_unstable();
        assert!(now.contains(&k), "a face inside the frozen region changed");
    }
}
