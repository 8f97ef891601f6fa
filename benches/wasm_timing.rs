//! Timed runs in headless Chromium (wasm only; natively this file has no tests): per-step cost of
//! the LSW evolution at 2 K, 10 K and 40 K vertices and of the MCF step at level 6, and the
//! bunny-sized distance field. Numbers are printed, never asserted (speed is measured in
//! benchmarks, not tests). Run optimised for meaningful figures:
//! `cargo test --release --target wasm32-unknown-unknown --bench wasm_timing -- --nocapture` (a bench
//! target run through wasm-bindgen-test's browser runner, outside the test suite).

#![cfg(target_arch = "wasm32")]

use lsw::clock::now_ms;
use lsw::flow::{mcf_step, Evolver, McfSettings, WrapSettings};
use lsw::geometry::icosphere::icosphere;
use lsw::target::Target;
use lsw::DVec3;
use wasm_bindgen_test::*;

wasm_bindgen_test_configure!(run_in_browser);

fn sphere_cloud(n: usize) -> Target {
    Target::new(lsw::geometry::sphere::fibonacci_sphere(n), vec![]).unwrap()
}

#[wasm_bindgen_test]
fn time_lsw_steps_by_size() {
    let target = sphere_cloud(20_000);
    for level in [4u32, 5, 6] {
        let settings = {
            let mut w = WrapSettings::default();
            w.start.icosphere_level = level;
            w.remesh.enabled = false;
            w.flow.schedule = vec![];
            w.stop.steps = 1000;
            w
        };
        // The first step from the start surface (as the native criterion bench times it): best
        // of three fresh evolvers, whole step and its phases.
        let (mut best, mut best_phases) = (f64::INFINITY, [0.0; 3]);
        let mut n = 0;
        for _ in 0..3 {
            let mut ev = Evolver::new(&target, settings.clone()).unwrap();
            n = ev.mesh().n_vertices();
            let t0 = now_ms();
            let r = ev.step().unwrap();
            let ms = now_ms() - t0;
            if ms < best {
                best = ms;
                best_phases = [r.times.normals, r.times.assembly, r.times.solve];
            }
        }
        console_log!(
            "wasm LSW first step, {n} vertices: best {best:.2} ms (normals {:.2}, assembly {:.2}, solve {:.2}; phases {:.2})",
            best_phases[0],
            best_phases[1],
            best_phases[2],
            best_phases.iter().sum::<f64>()
        );
        // Steps 2–6 of one run: mean.
        let mut ev = Evolver::new(&target, settings).unwrap();
        ev.step().unwrap();
        let t0 = now_ms();
        let mut phases = [0.0; 3];
        for _ in 0..5 {
            let r = ev.step().unwrap();
            phases[0] += r.times.normals;
            phases[1] += r.times.assembly;
            phases[2] += r.times.solve;
        }
        let ms = (now_ms() - t0) / 5.0;
        console_log!(
            "wasm LSW steps 2-6, {n} vertices: mean {ms:.2} ms (normals {:.2}, assembly {:.2}, solve {:.2})",
            phases[0] / 5.0,
            phases[1] / 5.0,
            phases[2] / 5.0
        );
    }
}

#[wasm_bindgen_test]
fn time_mcf_step_level6() {
    let mut mesh = icosphere(6, 1.0, DVec3::ZERO).unwrap();
    let settings = McfSettings {
        tau: 1e-4,
        ..Default::default()
    };
    mcf_step(&mut mesh, &settings).unwrap();
    let t0 = now_ms();
    for _ in 0..5 {
        mcf_step(&mut mesh, &settings).unwrap();
    }
    console_log!(
        "wasm MCF step, level 6 (40 962 vertices): {:.2} ms",
        (now_ms() - t0) / 5.0
    );
}

#[wasm_bindgen_test]
fn time_bunny_sized_field() {
    // 11 988 points on a sphere-like blob sized like the bunny: the same grid (≈133³ nodes at
    // 40 cells per minimum dimension with ζ = 1 gives 120³ here).
    let target = sphere_cloud(11_988);
    let t0 = now_ms();
    let f = lsw::field::DistanceField::new(&target, &lsw::field::FieldSettings::default()).unwrap();
    console_log!(
        "wasm distance field, {:?} nodes from 11 988 points: {:.1} ms",
        f.dims(),
        now_ms() - t0
    );
}

#[wasm_bindgen_test]
fn time_bunny_sized_sweep() {
    // The sweep alone (the field's longest part in the browser), on the same grid: best and
    // median of 5 runs from the same band.
    let target = sphere_cloud(11_988);
    let settings = lsw::field::FieldSettings::default();
    let bbox = lsw::geometry::aabb::Aabb::from_points(&target.points);
    let grid = lsw::field::grid::Grid::for_bbox(&bbox, &settings).unwrap();
    let band = lsw::field::band::points_band(
        &grid,
        &target.points,
        settings.band_cells,
        f64::INFINITY,
        &mut lsw::progress::Progress::none(),
    );
    let mut ms = vec![];
    let mut passes = 0;
    for _ in 0..5 {
        let mut values = band.values.clone();
        let t0 = now_ms();
        let r = lsw::field::fast_sweep::fast_sweep(
            &grid,
            &mut values,
            &band.frozen,
            settings.max_sweep_passes,
            settings.sweep_tolerance,
            &mut |_| {},
        );
        ms.push(now_ms() - t0);
        passes = r.passes;
    }
    ms.sort_by(f64::total_cmp);
    console_log!(
        "wasm sweep, {:?} nodes, {passes} passes: best {:.1} ms, median {:.1} ms",
        grid.dims,
        ms[0],
        ms[2]
    );
}
