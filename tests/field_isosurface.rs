//! Isosurfaces (marching tetrahedra on the Kuhn split): closed, manifold, oriented, with the
//! right genus. Synthetic tests run natively and in headless Chromium; the multi-holed tori read
//! `LSW_SHARED_DATA` (native only).

#[path = "common/field_data.rs"]
mod field_data;

use lsw::field::{DistanceField, FieldSettings, Signedness};
use lsw::geometry::marching_cubes::{marching_cubes, ScalarGridView};
use lsw::mesh::HalfedgeMesh;
use lsw::target::Target;
use lsw::DVec3;
use wasm_bindgen_test::*;

wasm_bindgen_test_configure!(run_in_browser);

/// Builds the halfedge mesh, validates it and returns (χ, genus, components, signed volume).
fn check_closed(pos: Vec<DVec3>, tris: &[[u32; 3]], what: &str) -> (i64, i64, usize, f64) {
    assert!(!tris.is_empty(), "{what}: empty isosurface");
    let m = HalfedgeMesh::from_triangles(pos, tris).unwrap_or_else(|e| panic!("{what}: {e}"));
    let r = m.validate().unwrap_or_else(|e| panic!("{what}: {e}"));
    let vol = m.signed_volume();
    println!(
        "{what}: {} V, {} F, χ = {}, genus {}, {} component(s), volume {vol:.5}",
        r.vertices, r.faces, r.euler_characteristic, r.genus, r.components
    );
    (r.euler_characteristic, r.genus, r.components, vol)
}

/// The n³ grid of `analytic` as a view for marching cubes.
fn cube_view(origin: DVec3, cell: f64, n: usize, values: &[f64]) -> ScalarGridView<'_> {
    ScalarGridView {
        first: [0; 3],
        origin,
        cell,
        dims: [n; 3],
        values,
    }
}

fn analytic(n: usize, lo: f64, hi: f64, f: impl Fn(DVec3) -> f64) -> (DVec3, f64, Vec<f64>) {
    let cell = (hi - lo) / (n - 1) as f64;
    let origin = DVec3::splat(lo);
    let mut v = Vec::with_capacity(n * n * n);
    for iz in 0..n {
        for iy in 0..n {
            for ix in 0..n {
                v.push(f(
                    origin + cell * DVec3::new(ix as f64, iy as f64, iz as f64)
                ));
            }
        }
    }
    (origin, cell, v)
}

#[wasm_bindgen_test(unsupported = test)]
fn sphere_field_gives_a_closed_sphere() {
    let n = 40;
    let (origin, cell, v) = analytic(n, -1.5, 1.5, |p| p.length() - 1.0);
    let view = cube_view(origin, cell, n, &v);
    for iso in [0.0, 0.2, -0.3] {
        let (pos, tris) = marching_cubes(&view, iso);
        let worst = pos
            .iter()
            .map(|p| (p.length() - (1.0 + iso)).abs())
            .fold(0.0, f64::max);
        let (chi, genus, comps, vol) = check_closed(pos, &tris, &format!("sphere iso {iso}"));
        assert_eq!((chi, genus, comps), (2, 0, 1));
        let r = 1.0 + iso;
        let exact = 4.0 / 3.0 * std::f64::consts::PI * r * r * r;
        assert!(
            vol > 0.0 && (vol - exact).abs() < 0.03 * exact,
            "{vol} vs {exact}"
        );
        assert!(worst < 0.5 * cell, "vertex off the sphere by {worst}");
    }
}

#[wasm_bindgen_test(unsupported = test)]
fn torus_field_gives_a_torus() {
    let (rr, r) = (1.0, 0.35);
    let torus = |p: DVec3| {
        let q = (p.x * p.x + p.y * p.y).sqrt() - rr;
        (q * q + p.z * p.z).sqrt() - r
    };
    for n in [24, 41, 64] {
        let (origin, cell, v) = analytic(n, -1.6, 1.6, torus);
        let view = cube_view(origin, cell, n, &v);
        let (pos, tris) = marching_cubes(&view, 0.0);
        let (chi, genus, comps, vol) = check_closed(pos, &tris, &format!("torus n = {n}"));
        assert_eq!((chi, genus, comps), (0, 1, 1));
        assert!(vol > 0.0);
    }
}

#[wasm_bindgen_test(unsupported = test)]
fn level_set_leaving_the_grid_is_closed_by_the_border() {
    // A plane z = 0.1 crosses the whole grid: the border closes it into a box-like surface.
    let n = 12;
    let (origin, cell, v) = analytic(n, -1.0, 1.0, |p| p.z - 0.1);
    let view = cube_view(origin, cell, n, &v);
    let (pos, tris) = marching_cubes(&view, 0.0);
    let (chi, _, comps, vol) = check_closed(pos, &tris, "plane");
    assert_eq!((chi, comps), (2, 1));
    assert!(vol > 0.0);
    // Values exactly at the iso level (a node lattice plane) do not break manifoldness.
    let (origin, cell, v) = analytic(11, -1.0, 1.0, |p| (p.z * 5.0).round() / 5.0);
    let view = cube_view(origin, cell, 11, &v);
    let (pos, tris) = marching_cubes(&view, 0.0);
    assert_eq!(check_closed(pos, &tris, "steps").0, 2);
}

fn torus_mesh(rr: f64, r: f64, nu: usize, nv: usize) -> Target {
    let mut pts = Vec::new();
    for i in 0..nu {
        for j in 0..nv {
            let (u, v) = (
                std::f64::consts::TAU * i as f64 / nu as f64,
                std::f64::consts::TAU * j as f64 / nv as f64,
            );
            pts.push(DVec3::new(
                (rr + r * lsw::fmath::cos(v)) * lsw::fmath::cos(u),
                (rr + r * lsw::fmath::cos(v)) * lsw::fmath::sin(u),
                r * lsw::fmath::sin(v),
            ));
        }
    }
    let id = |i: usize, j: usize| ((i % nu) * nv + (j % nv)) as u32;
    let mut tris = Vec::new();
    for i in 0..nu {
        for j in 0..nv {
            tris.push([id(i, j), id(i + 1, j), id(i + 1, j + 1)]);
            tris.push([id(i, j), id(i + 1, j + 1), id(i, j + 1)]);
        }
    }
    Target::new(pts, tris).unwrap()
}

#[wasm_bindgen_test(unsupported = test)]
fn torus_mesh_field_isosurface_keeps_genus_one() {
    let t = torus_mesh(1.0, 0.4, 48, 24);
    let f = DistanceField::new(&t, &FieldSettings::default()).unwrap();
    assert_eq!(f.signedness(), Signedness::Signed);
    assert!(f.sample(DVec3::new(1.0, 0.0, 0.0)) < 0.0);
    assert!(f.sample(DVec3::ZERO) > 0.0);
    let d0 = 0.87 * f.cell_size();
    let (pos, tris) = f.isosurface(d0);
    let (chi, genus, comps, _) = check_closed(pos, &tris, "torus mesh field");
    assert_eq!((chi, genus, comps), (0, 1, 1));
    let (pos, tris) = f.isosurface_resampled(d0, 1.5);
    let (chi, _, _, _) = check_closed(pos, &tris, "torus mesh field, resampled ×1.5");
    assert_eq!(chi, 0);
}

fn multi_torus(file: &str, genus: i64) {
    let dir = field_data::data_dir(file);
    let t = field_data::load(&dir.join(file));
    // The tori are flat (β_min ≈ 0.46 of ≈ 4.6): 16 cells across the thickness keep the grid at
    // ≈ 2 M nodes (40 would need 28 M) and still resolve every handle.
    let s = FieldSettings {
        cells_per_min_dimension: 16,
        ..Default::default()
    };
    let f = DistanceField::new(&t, &s).unwrap();
    println!(
        "{file}: dims {:?}, {:?}, {:?}",
        f.dims(),
        f.signedness(),
        f.timings()
    );
    assert!(f.is_signed());
    // d₀ = half the voxel diagonal, the start level of the reference's isosurface runs.
    let d0 = 0.5 * 3f64.sqrt() * f.cell_size();
    let (pos, tris) = f.isosurface(d0);
    let (_, g, comps, vol) = check_closed(pos, &tris, file);
    assert_eq!((g, comps), (genus, 1));
    assert!(vol > 0.0);
}

#[test]
#[cfg_attr(
    not(shared_data),
    ignore = "needs the shared test data (LSW_SHARED_DATA)"
)]
fn two_torus_isosurface_has_genus_2() {
    multi_torus("2Torus.obj", 2);
}

#[test]
#[cfg_attr(
    not(shared_data),
    ignore = "needs the shared test data (LSW_SHARED_DATA)"
)]
fn three_torus_isosurface_has_genus_3() {
    multi_torus("3Torus.obj", 3);
}
