//! The distance field: exact near band, fast sweeping, sign, gradient and trilinear sampling.
//! Synthetic tests run natively and in headless Chromium; real-data tests read
//! `LSW_SHARED_DATA` (native only) and print a notice when it is unset.

#[path = "common/field_data.rs"]
mod field_data;

use field_data::*;
use lsw::field::{DistanceField, FieldError, FieldSettings, Signedness};
use lsw::geometry::icosphere::unit_icosphere;
use lsw::target::Target;
use lsw::DVec3;
use wasm_bindgen_test::*;

wasm_bindgen_test_configure!(run_in_browser);

fn field(t: &Target) -> DistanceField {
    DistanceField::new(t, &FieldSettings::default()).unwrap()
}

/// The first-order sweep's error bound used throughout: `0.5·c·(1 + ln(max(1, d/c)))` (the
/// Godunov scheme's error grows like c·log(d/c) away from the source).
fn sweep_bound(d: f64, c: f64) -> f64 {
    0.5 * c * (1.0 + lsw::fmath::ln((d.abs() / c).max(1.0)))
}

/// Max of |d(x) − (|x − c| − R)| / [`sweep_bound`] over all nodes, plus the sign error count.
fn sphere_errors(f: &DistanceField, c: DVec3, r: f64, signed: bool) -> (f64, usize) {
    let g = f.grid();
    let (mut worst, mut wrong_sign) = (0.0f64, 0usize);
    for (i, &d) in f.values().iter().enumerate() {
        let s = (g.position_of(i) - c).length() - r;
        let exact = if signed { s } else { s.abs() };
        worst = worst.max((d - exact).abs() / sweep_bound(s, g.cell));
        if signed && s.abs() > 0.01 * r && (d < 0.0) != (s < 0.0) {
            wrong_sign += 1;
        }
    }
    (worst, wrong_sign)
}

#[wasm_bindgen_test(unsupported = test)]
fn sphere_point_cloud_matches_analytic_distance() {
    let c = DVec3::new(0.3, -0.2, 0.1);
    let t = Target::new(fibonacci_sphere(20_000, 1.0, c), vec![]).unwrap();
    let unsigned = FieldSettings {
        enclosed_cells: 0.0,
        ..Default::default()
    };
    let f = DistanceField::new(&t, &unsigned).unwrap();
    assert_eq!(f.signedness(), Signedness::Unsigned);
    assert!(!f.is_signed());
    assert_eq!(f.enclosed_nodes(), 0);
    assert!(f.values().iter().all(|&d| d >= 0.0));
    let (worst, _) = sphere_errors(&f, c, 1.0, false);
    println!(
        "sphere cloud: dims {:?}, c = {:.4}, max |d − ||x|−R|| / bound = {worst:.3}, {:?}, {:?}",
        f.dims(),
        f.cell_size(),
        f.sweep_report(),
        f.timings()
    );
    assert!(f.sweep_report().converged);
    assert!(worst < 1.0, "error {worst} × the bound");

    // At the defaults the ball's inside deeper than 2 cells, which the cloud encloses, is
    // negative (`field.enclosed_cells`); every other node keeps its value.
    let g = field(&t);
    assert_eq!(g.signedness(), Signedness::Unsigned);
    assert!(g.enclosed_nodes() > 0);
    let level = 2.0 * g.cell_size();
    let mut negative = 0;
    for (i, (&a, &b)) in f.values().iter().zip(g.values()).enumerate() {
        let s = (g.grid().position_of(i) - c).length() - 1.0;
        if b < 0.0 {
            negative += 1;
            assert_eq!(b, -a);
            assert!(a >= level && s < 0.0, "node {i}: {a} at {s}");
        } else {
            assert_eq!(b, a);
            assert!(
                s > -level - sweep_bound(s, g.cell_size()),
                "node {i}: {a} at {s}"
            );
        }
    }
    assert_eq!(negative, g.enclosed_nodes());
}

#[wasm_bindgen_test(unsupported = test)]
fn sphere_mesh_is_signed_and_accurate() {
    let (p, tris) = unit_icosphere(4);
    let r = 0.7;
    let c = DVec3::new(-1.0, 2.0, 0.5);
    let t = Target::new(p.iter().map(|&q| c + r * q).collect(), tris).unwrap();
    let f = field(&t);
    assert_eq!(f.signedness(), Signedness::Signed);
    let (worst, wrong) = sphere_errors(&f, c, r, true);
    println!("sphere mesh: max |d − (|x|−R)| / bound = {worst:.3}, wrong signs {wrong}");
    assert_eq!(wrong, 0);
    assert!(worst < 1.0, "error {worst} × the bound");
    // Inward-oriented copy: same sign convention (negative inside).
    let flipped: Vec<[u32; 3]> = t.triangles.iter().map(|&[a, b, c]| [a, c, b]).collect();
    let f2 = field(&Target::new(t.points.clone(), flipped).unwrap());
    assert_eq!(sphere_errors(&f2, c, r, true).1, 0);
    assert!(f2.sample(c) < 0.0);
}

/// A 12-triangle box (large triangles, sharp edges and corners) against its analytic signed
/// distance: the band is exact and every sign is right, also next to edges and corners.
#[wasm_bindgen_test(unsupported = test)]
fn box_mesh_signed_distance_is_exact_in_the_band() {
    let h = DVec3::new(1.0, 0.6, 0.35);
    let c = DVec3::new(0.2, -0.1, 0.4);
    let p: Vec<DVec3> = (0..8)
        .map(|k| {
            c + h * DVec3::new(
                if k & 1 == 0 { -1.0 } else { 1.0 },
                if k & 2 == 0 { -1.0 } else { 1.0 },
                if k & 4 == 0 { -1.0 } else { 1.0 },
            )
        })
        .collect();
    // Outward-oriented faces of the cube (corner k = bits x, y, z).
    let quads = [
        [0, 2, 3, 1],
        [4, 5, 7, 6],
        [0, 1, 5, 4],
        [2, 6, 7, 3],
        [0, 4, 6, 2],
        [1, 3, 7, 5],
    ];
    let tris: Vec<[u32; 3]> = quads
        .iter()
        .flat_map(|q| [[q[0], q[1], q[2]], [q[0], q[2], q[3]]])
        .collect();
    let f = field(&Target::new(p, tris).unwrap());
    assert_eq!(f.signedness(), Signedness::Signed);
    let g = f.grid();
    let sdf = |x: DVec3| {
        let q = (x - c).abs() - h;
        q.max(DVec3::ZERO).length() + q.max_element().min(0.0)
    };
    let (mut worst_band, mut worst) = (0.0f64, 0.0f64);
    for (i, (&v, &b)) in f.values().iter().zip(f.band_mask()).enumerate() {
        let e = sdf(g.position_of(i));
        if e.abs() > 1e-12 {
            assert_eq!(v < 0.0, e < 0.0, "sign at node {i}: field {v}, exact {e}");
        }
        if b {
            worst_band = worst_band.max((v - e).abs());
        } else {
            worst = worst.max((v - e).abs() / sweep_bound(e, g.cell));
        }
    }
    println!("box: band max error {worst_band:.2e}, sweep error / bound {worst:.3}");
    assert!(worst_band < 1e-12);
    assert!(worst < 1.0);
}

#[wasm_bindgen_test(unsupported = test)]
fn open_mesh_is_unsigned() {
    // A hemisphere-like open cap: half the faces of an icosphere.
    let (p, tris) = unit_icosphere(3);
    let cap: Vec<[u32; 3]> = tris
        .into_iter()
        .filter(|t| t.iter().all(|&v| p[v as usize].z > -0.1))
        .collect();
    let f = field(&Target::new(p, cap).unwrap());
    assert_eq!(f.signedness(), Signedness::Unsigned);
    assert!(f.values().iter().all(|&v| v >= 0.0));
}

#[wasm_bindgen_test(unsupported = test)]
fn trilinear_reproduces_linear_functions() {
    let t = Target::new(fibonacci_sphere(500, 1.0, DVec3::ZERO), vec![]).unwrap();
    let f = field(&t);
    let (a, b) = (DVec3::new(0.3, -1.7, 2.2), 0.25);
    let lin = |p: DVec3| a.dot(p) + b;
    let g = *f.grid();
    let vals: Vec<f64> = (0..g.node_count()).map(|i| lin(g.position_of(i))).collect();
    let bb = f.bbox();
    let mut s = 7u64;
    let mut rnd = || {
        s = s
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (s >> 11) as f64 / (1u64 << 53) as f64
    };
    for _ in 0..2000 {
        let p = bb.min + DVec3::new(rnd(), rnd(), rnd()) * bb.size();
        let v = lsw::field::sample::trilinear(&g, &vals, p);
        assert!((v - lin(p)).abs() < 1e-12, "{p:?}: {v} vs {}", lin(p));
    }
    // Outside the box the point is clamped, not extrapolated.
    let far = bb.max + DVec3::splat(5.0);
    let v = lsw::field::sample::trilinear(&g, &vals, far);
    assert!((v - lin(bb.max)).abs() < 1e-12);
    // Node values are reproduced exactly by the field's own sampler.
    for i in (0..g.node_count()).step_by(997) {
        let v = f.values()[i];
        assert!((f.sample(g.position_of(i)) - v).abs() <= 1e-12 * (1.0 + v.abs()));
    }
}

#[wasm_bindgen_test(unsupported = test)]
fn gradient_of_sphere_field_points_to_centre() {
    let c = DVec3::new(0.1, 0.2, -0.3);
    let (p, tris) = unit_icosphere(4);
    let t = Target::new(p.iter().map(|&q| c + q).collect(), tris).unwrap();
    let f = field(&t);
    let mut worst = 0.0f64;
    let bb = f.bbox();
    for k in 0..400 {
        // Points between 1.3 and 2.5 radii from the centre (outside the sphere).
        let dir = fibonacci_sphere(400, 1.0, DVec3::ZERO)[k];
        let r = 1.3 + 1.2 * (k as f64 / 400.0);
        let x = c + r * dir;
        if x.cmplt(bb.min).any() || x.cmpgt(bb.max).any() {
            continue;
        }
        let g = f.sample_gradient(x);
        let cosang = g.normalize().dot((c - x).normalize());
        worst = worst.max(lsw::fmath::acos(cosang.clamp(-1.0, 1.0)).to_degrees());
        assert!(g.length() > 0.9 && g.length() <= 1.0 + 1e-6);
    }
    println!("sphere gradient: worst angle to the centre direction {worst:.3}°");
    assert!(worst < 3.0, "gradient off by {worst}°");
}

#[wasm_bindgen_test(unsupported = test)]
fn scaled_field_samples_consistently() {
    let t = Target::new(fibonacci_sphere(2000, 1.0, DVec3::ZERO), vec![]).unwrap();
    let f = field(&t);
    let (center, phi) = (DVec3::new(0.2, 0.1, -0.4), 3.5);
    let s = f.scaled(center, phi);
    for k in 0..200 {
        let x = DVec3::new(k as f64 * 0.013 - 1.3, 0.4 - k as f64 * 0.005, 0.7);
        let xs = phi * (x - center);
        assert!((s.sample(xs) - phi * f.sample(x)).abs() < 1e-9);
        assert!((s.sample_gradient(xs) - f.sample_gradient(x)).length() < 1e-9);
    }
    assert!((s.cell_size() - phi * f.cell_size()).abs() < 1e-15);
}

#[wasm_bindgen_test(unsupported = test)]
fn bad_inputs_give_typed_errors() {
    let s = FieldSettings::default();
    let empty = Target {
        points: vec![],
        triangles: vec![],
        bbox: lsw::geometry::aabb::Aabb::EMPTY,
        sampled: false,
    };
    assert_eq!(
        DistanceField::new(&empty, &s).unwrap_err(),
        FieldError::EmptyTarget
    );
    let one = Target::new(vec![DVec3::new(1.0, 2.0, 3.0)], vec![]).unwrap();
    assert_eq!(
        DistanceField::new(&one, &s).unwrap_err(),
        FieldError::DegenerateTarget
    );
    let same = Target::new(vec![DVec3::ONE; 50], vec![]).unwrap();
    assert_eq!(
        DistanceField::new(&same, &s).unwrap_err(),
        FieldError::DegenerateTarget
    );
    // Flat (planar) target: sized from its smaller in-plane side, and it works.
    let flat: Vec<DVec3> = (0..400)
        .map(|i| DVec3::new((i % 20) as f64 * 0.1, (i / 20) as f64 * 0.05, 0.0))
        .collect();
    // (Its points lie 0.05 apart: without the sparse-cloud floor, which would coarsen the grid.)
    let dense = FieldSettings {
        min_cell_spacings: 0.0,
        ..s.clone()
    };
    let f = DistanceField::new(&Target::new(flat, vec![]).unwrap(), &dense).unwrap();
    assert!((f.cell_size() - 0.95 / 40.0).abs() < 1e-12);
    assert!(f.dims().iter().all(|&n| n >= 2) && f.values().iter().all(|v| v.is_finite()));
    // A line (two flat sides) also works; identical points do not.
    let line = Target::new(vec![DVec3::ZERO, DVec3::X], vec![]).unwrap();
    assert!(DistanceField::new(&line, &s).is_ok());
    // Over the memory cap: the error names the cap and a resolution that fits.
    let big = FieldSettings {
        cells_per_min_dimension: 4000,
        ..Default::default()
    };
    let t = Target::new(fibonacci_sphere(100, 1.0, DVec3::ZERO), vec![]).unwrap();
    match DistanceField::new(&t, &big).unwrap_err() {
        e @ FieldError::TooLarge {
            cap_bytes,
            cells_that_fit,
            ..
        } => {
            let msg = e.to_string();
            println!("{msg}");
            assert!(msg.contains("1024 MiB") && msg.contains(&cells_that_fit.to_string()));
            assert_eq!(cap_bytes, 1 << 30);
            let fit = FieldSettings {
                cells_per_min_dimension: cells_that_fit,
                memory_cap_bytes: 1 << 24,
                ..Default::default()
            };
            // The suggested resolution does fit under the cap it was computed for.
            assert!(lsw::field::Grid::for_bbox(
                &t.bbox,
                &FieldSettings {
                    memory_cap_bytes: 1 << 30,
                    ..fit.clone()
                }
            )
            .is_ok());
            assert!(matches!(
                DistanceField::new(&t, &fit),
                Err(FieldError::TooLarge { .. })
            ));
        }
        e => panic!("unexpected {e:?}"),
    }
    // Bad settings and bad triangles.
    let bad = FieldSettings {
        band_cells: 0.0,
        ..Default::default()
    };
    assert!(matches!(
        DistanceField::new(&t, &bad),
        Err(FieldError::InvalidSetting {
            name: "band_cells",
            ..
        })
    ));
    let mut broken = t.clone();
    broken.triangles.push([0, 1, 1000]);
    assert_eq!(
        DistanceField::new(&broken, &s).unwrap_err(),
        FieldError::BadTriangle { triangle: 0 }
    );
}

#[wasm_bindgen_test(unsupported = test)]
fn bunny_sized_cloud_timing() {
    // Same grid as the bunny point cloud at the paper's resolution; prints the time (natively and
    // in the browser, for benches/RESULTS.md).
    let t = Target::new(bunny_sized_cloud(11_988), vec![]).unwrap();
    let t0 = lsw::clock::now_ms();
    // The synthetic cloud is sparser than the real scan: keep the paper's grid regardless.
    let settings = FieldSettings {
        min_cell_spacings: 0.0,
        ..FieldSettings::default()
    };
    let f = DistanceField::new(&t, &settings).unwrap();
    let ms = lsw::clock::now_ms() - t0;
    let msg = format!(
        "bunny-sized synthetic cloud: dims {:?}, {ms:.1} ms total, {:?}, {:?}",
        f.dims(),
        f.timings(),
        f.sweep_report()
    );
    println!("{msg}");
    #[cfg(target_arch = "wasm32")]
    console_log!("{msg}");
    assert_eq!(f.dims(), [133, 133, 121]);
}

/// Exactness in the band and sweep error outside it, against brute force. Returns
/// (band nodes, max band rel. error, max / mean sweep error in cells, max / mean sweep rel. error).
fn check_against_brute(f: &DistanceField, exact: &dyn Fn(DVec3) -> f64, name: &str) {
    let g = f.grid();
    let (mut nband, mut worst_band) = (0usize, 0.0f64);
    for (i, (&v, &b)) in f.values().iter().zip(f.band_mask()).enumerate() {
        if !b {
            continue;
        }
        nband += 1;
        let e = exact(g.position_of(i));
        let rel = (v.abs() - e).abs() / e.max(1e-300);
        assert!(
            (v.abs() - e).abs() <= 1e-9 * e + 1e-15,
            "{name}: band node {i}: field {v}, brute force {e}"
        );
        worst_band = worst_band.max(if e > 0.0 { rel } else { 0.0 });
    }
    assert!(nband > 1000, "{name}: only {nband} band nodes");
    let (mut n, mut max_c, mut sum_c, mut max_rel, mut sum_rel) =
        (0usize, 0.0f64, 0.0, 0.0f64, 0.0);
    let mut max_ratio = 0.0f64;
    for i in (0..g.node_count()).step_by(61) {
        if f.band_mask()[i] {
            continue;
        }
        let e = exact(g.position_of(i));
        let err = (f.values()[i].abs() - e).abs();
        n += 1;
        max_c = max_c.max(err / g.cell);
        sum_c += err / g.cell;
        max_rel = max_rel.max(err / e);
        max_ratio = max_ratio.max(err / sweep_bound(e, g.cell));
        sum_rel += err / e;
    }
    println!(
        "{name}: dims {:?}; {nband} band nodes, max relative error {worst_band:.2e}; \
         sweep on {n} sampled nodes: max {max_c:.3} c / mean {:.3} c, \
         relative max {:.3} % / mean {:.3} %; error / bound max {max_ratio:.3}; {:?}; {:?}",
        f.dims(),
        sum_c / n as f64,
        100.0 * max_rel,
        100.0 * sum_rel / n as f64,
        f.sweep_report(),
        f.timings()
    );
    // First-order sweep from an exact band of radius 3c: within the log-growing bound.
    assert!(
        max_ratio < 1.0,
        "{name}: sweep error {max_ratio} × the bound"
    );
    assert!(max_rel < 0.15, "{name}: sweep relative error {max_rel}");
}

#[test]
#[cfg_attr(
    not(shared_data),
    ignore = "needs the shared test data (LSW_SHARED_DATA)"
)]
fn bunny_point_cloud_band_is_exact() {
    let dir = data_dir("bunny_point_cloud_band_is_exact");
    let t = load(&dir.join("bunnyPts_3.ply"));
    let f = field(&t);
    assert_eq!(f.dims(), [133, 133, 121]);
    check_against_brute(&f, &|p| brute_point_distance(p, &t.points), "bunnyPts_3");
}

#[test]
#[cfg_attr(
    not(shared_data),
    ignore = "needs the shared test data (LSW_SHARED_DATA)"
)]
fn spot_mesh_band_is_exact_and_signed() {
    let dir = data_dir("spot_mesh_band_is_exact_and_signed");
    let t = load(&dir.join("spot.obj"));
    let f = field(&t);
    assert_eq!(f.signedness(), Signedness::Signed);
    let soup = Soup::new(&t);
    check_against_brute(&f, &|p| soup.distance(p), "spot.obj");
    // Outside the target's box (grown by one cell) everything is outside the mesh.
    let g = f.grid();
    let outer = t.bbox.expanded(g.cell);
    for (i, &v) in f.values().iter().enumerate() {
        let p = g.position_of(i);
        if p.cmplt(outer.min).any() || p.cmpgt(outer.max).any() {
            assert!(v > 0.0, "node {i} at {p:?} outside the box has {v}");
        }
    }
    let (lo, _) = f.min_max();
    assert!(lo < -2.0 * g.cell, "no deep inside: min {lo}");
}

#[test]
#[cfg_attr(
    not(shared_data),
    ignore = "needs the shared test data (LSW_SHARED_DATA)"
)]
fn bunny_mesh_with_holes_is_signed() {
    let dir = data_dir("bunny_mesh_with_holes_is_signed");
    // bunny.ply has 5 holes in its base (223 boundary edges of 104 288): the band seals them.
    let t = load(&dir.join("bunny.ply"));
    let f = field(&t);
    assert_eq!(f.signedness(), Signedness::SignedWithHoles);
    let g = f.grid();
    let outer = t.bbox.expanded(g.cell);
    let mut inside = 0usize;
    for (i, &v) in f.values().iter().enumerate() {
        let p = g.position_of(i);
        if p.cmplt(outer.min).any() || p.cmpgt(outer.max).any() {
            assert!(v > 0.0, "node {i} at {p:?} outside the box has {v}");
        }
        inside += (v < 0.0) as usize;
    }
    let (lo, _) = f.min_max();
    println!(
        "bunny.ply: {inside} inside nodes, min {:.4} = {:.1} c, {:?}",
        lo,
        lo / g.cell,
        f.timings()
    );
    assert!(lo < -5.0 * g.cell);
    // Its open copy with most faces removed is no longer nearly closed: unsigned.
    let open = Target::new(
        t.points.clone(),
        t.triangles[..t.triangles.len() / 2].to_vec(),
    )
    .unwrap();
    assert_eq!(field(&open).signedness(), Signedness::Unsigned);
}
