//! Metrics against brute force and hand-computed values. Runs natively and in headless Chromium.

use lsw::geometry::icosphere::icosphere;
use lsw::geometry::spatial::bvh::closest_point_on_triangle;
use lsw::metrics::distance::{two_sided_distances, DistanceStats};
use lsw::metrics::intersections::count_self_intersections;
use lsw::metrics::quality::{kappa, quality_stats, radius_ratio};
use lsw::metrics::volume::enclosed_volume;
use lsw::DVec3;
use wasm_bindgen_test::*;

wasm_bindgen_test_configure!(run_in_browser);

fn rng(seed: u64) -> impl FnMut() -> f64 {
    let mut s = seed ^ 0xD1B5_4A32_D192_ED03;
    move || {
        s = s
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (s >> 11) as f64 / (1u64 << 53) as f64
    }
}

fn brute_to_triangles(p: DVec3, pos: &[DVec3], tris: &[[u32; 3]]) -> f64 {
    tris.iter()
        .map(|t| {
            let [a, b, c] = t.map(|v| pos[v as usize]);
            (closest_point_on_triangle(p, a, b, c).0 - p).length()
        })
        .fold(f64::INFINITY, f64::min)
}

fn close(a: f64, b: f64) -> bool {
    (a - b).abs() <= 1e-12 * (1.0 + b.abs())
}

fn same(a: &DistanceStats, b: &DistanceStats) {
    assert_eq!(a.count, b.count);
    for (x, y) in [
        (a.mean, b.mean),
        (a.rms, b.rms),
        (a.p95, b.p95),
        (a.max, b.max),
    ] {
        assert!(close(x, y), "{a:?} vs {b:?}");
    }
}

#[wasm_bindgen_test(unsupported = test)]
fn mesh_to_mesh_and_mesh_to_cloud_match_brute_force() {
    let mut r = rng(3);
    let mut sphere = icosphere(3, 1.0, DVec3::ZERO).unwrap();
    for p in sphere.positions_mut() {
        *p *= 1.0 + 0.1 * (r() - 0.5);
    }
    let (sp, st) = (sphere.positions().to_vec(), sphere.triangles());
    let other = icosphere(2, 1.05, DVec3::new(0.1, -0.05, 0.02)).unwrap();
    let (op, ot) = (other.positions().to_vec(), other.triangles());

    let d = two_sided_distances(&sp, &st, &op, &ot);
    let there: Vec<f64> = sp
        .iter()
        .map(|&p| brute_to_triangles(p, &op, &ot))
        .collect();
    let back: Vec<f64> = op
        .iter()
        .map(|&p| brute_to_triangles(p, &sp, &st))
        .collect();
    same(&d.mesh_to_target, &DistanceStats::from_distances(&there));
    same(&d.target_to_mesh, &DistanceStats::from_distances(&back));
    assert!(d.mesh_to_target.max > 0.01 && d.target_to_mesh.max > 0.01);
    assert_eq!(d.hausdorff, d.mesh_to_target.max.max(d.target_to_mesh.max));

    // Point cloud target: vertices → nearest point, points → triangles.
    let cloud: Vec<DVec3> = (0..500)
        .map(|_| DVec3::new(r() - 0.5, r() - 0.5, r() - 0.5) * 2.4)
        .collect();
    let d = two_sided_distances(&sp, &st, &cloud, &[]);
    let there: Vec<f64> = sp
        .iter()
        .map(|p| {
            cloud
                .iter()
                .map(|q| (*q - *p).length())
                .fold(f64::INFINITY, f64::min)
        })
        .collect();
    let back: Vec<f64> = cloud
        .iter()
        .map(|&p| brute_to_triangles(p, &sp, &st))
        .collect();
    same(&d.mesh_to_target, &DistanceStats::from_distances(&there));
    same(&d.target_to_mesh, &DistanceStats::from_distances(&back));

    let pc = d.percent_of(2.0);
    assert!(close(pc.hausdorff, 50.0 * d.hausdorff));
}

#[wasm_bindgen_test(unsupported = test)]
fn distance_stats_by_hand() {
    let s = DistanceStats::from_distances(&[3.0, 1.0, 2.0, 4.0]);
    assert_eq!((s.count, s.max, s.p95), (4, 4.0, 4.0));
    assert!(close(s.mean, 2.5));
    assert!(close(s.rms, (30.0f64 / 4.0).sqrt()));
}

#[wasm_bindgen_test(unsupported = test)]
fn sphere_quality_volume_and_intersections() {
    let m = icosphere(4, 1.0, DVec3::ZERO).unwrap();
    let (p, t) = (m.positions().to_vec(), m.triangles());
    let q = quality_stats(&p, &t);
    // The icosphere's triangles are close to, but not exactly, equilateral.
    assert!(
        q.kappa.min > 1.0 - 1e-12 && q.kappa.max < 1.1,
        "{:?}",
        q.kappa
    );
    assert_eq!(q.kappa_le_1_5, 1.0);
    assert!(q.radius_ratio.mean > 0.97);
    let v = enclosed_volume(&p, &t);
    assert!((v - 4.0 / 3.0 * std::f64::consts::PI).abs() < 0.02);
    assert_eq!(count_self_intersections(&p, &t), 0);

    // Push one vertex through the opposite side: faces now cross.
    let mut p2 = p.clone();
    p2[0] = -1.3 * p2[0];
    assert!(count_self_intersections(&p2, &t) > 0);
}

#[wasm_bindgen_test(unsupported = test)]
fn hand_computed_triangles() {
    let (a, b) = (DVec3::ZERO, DVec3::new(2.0, 0.0, 0.0));
    let eq = DVec3::new(1.0, 3f64.sqrt(), 0.0);
    assert!((kappa(a, b, eq) - 1.0).abs() < 1e-14);
    assert!((radius_ratio(a, b, eq) - 1.0).abs() < 1e-14);
    // Right isosceles, legs 2: κ = (4 + 4 + 8)/(4√3·2) = 2/√3; 2r_in/r_circ = 2(√2 − 1).
    let r = DVec3::new(0.0, 2.0, 0.0);
    assert!((kappa(a, b, r) - 2.0 / 3f64.sqrt()).abs() < 1e-14);
    assert!((radius_ratio(a, b, r) - 2.0 * (2f64.sqrt() - 1.0)).abs() < 1e-14);
    // Needle: apex 1e-4 above the base midpoint.
    let n = DVec3::new(1.0, 1e-4, 0.0);
    let s2 = 4.0 + 2.0 * (1.0 + 1e-8);
    assert!((kappa(a, b, n) - s2 / (4.0 * 3f64.sqrt() * 1e-4)).abs() < 1e-6);
    assert!(radius_ratio(a, b, n) < 1e-3);
}
