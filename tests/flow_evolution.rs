//! The LSW evolution end to end on analytic targets. Runs natively and in headless Chromium.

use lsw::flow::{Evolver, Preset, WrapSettings};
use lsw::geometry::sphere::{fibonacci_sphere, mean_radius};
use lsw::target::Target;
use wasm_bindgen_test::*;

wasm_bindgen_test_configure!(run_in_browser);

/// `n` points spread evenly on a sphere of radius `r`.
fn sphere_cloud(n: usize, r: f64) -> Target {
    Target::new(
        fibonacci_sphere(n).into_iter().map(|p| r * p).collect(),
        vec![],
    )
    .unwrap()
}

#[wasm_bindgen_test(unsupported = test)]
fn pure_mcf_preset_follows_the_sphere_law() {
    // ε ≡ 1, η ≡ 0: the evolver's step is the semi-implicit MCF of the skeleton, in the
    // stabilised frame. Checked while r ≥ 0.6·r0, where the scheme's O(τ) lag stays below 1 %.
    let target = sphere_cloud(500, 1.0);
    let settings = {
        let mut w = Preset::Mcf.settings();
        w.start.icosphere_level = 4;
        w.stop.steps = 1000;
        w
    };
    let mut ev = Evolver::new(&target, settings).unwrap();
    let r0 = mean_radius(ev.mesh().positions());
    let tau = ev.settings().flow.tau;
    for k in 1.. {
        let rep = ev.step().unwrap();
        assert_eq!(rep.vertices, 2562, "no remeshing in the MCF preset");
        let exact = (r0 * r0 - 4.0 * tau * k as f64).sqrt();
        if exact < 0.6 * r0 {
            break;
        }
        let r = mean_radius(ev.mesh().positions());
        assert!(
            (r - exact).abs() / exact < 0.01,
            "step {k}: r = {r}, exact {exact}"
        );
        ev.mesh().validate().unwrap();
    }
}

#[wasm_bindgen_test(unsupported = test)]
fn wraps_a_sphere_cloud_onto_radius_r_plus_d0_and_stops_by_itself() {
    let r = 1.0;
    let target = sphere_cloud(20_000, r);
    // The evolution proper settles on d = d₀; the final fit (checked below) then moves it onto R.
    let settings = {
        let mut w = WrapSettings::default();
        w.stop.steps = 400;
        w.flow.schedule = vec![3, 10, 20, 50];
        w.fit.enabled = false;
        w
    };
    let mut ev = Evolver::new(&target, settings.clone()).unwrap();
    // The default radius rule gives exactly 2R for a sphere's bounding cube.
    let start = mean_radius(&ev.positions());
    assert!((start - 2.0 * r).abs() < 0.01, "start radius {start}");
    let mut last = None;
    while !ev.is_done() {
        let rep = ev.step().unwrap();
        let report = ev
            .mesh()
            .validate()
            .unwrap_or_else(|e| panic!("step {}: {e}", rep.step));
        assert_eq!(report.genus, 0);
        assert!(ev.positions().iter().all(|p| p.is_finite()));
        last = Some(rep);
    }
    let last = last.unwrap();
    assert!(last.step < 400, "the stopping rule never fired");
    let cell = 2.0 * r / 40.0;
    let expect = r + ev.iso_level();
    let radii: Vec<f64> = ev.positions().iter().map(|p| p.length()).collect();
    let mean = radii.iter().sum::<f64>() / radii.len() as f64;
    let worst = radii.iter().map(|x| (x - expect).abs()).fold(0.0, f64::max);
    println!("stopped at step {}, {} vertices: mean radius {mean:.5} vs R + d0 = {expect:.5}, worst deviation {:.3} cells", last.step, last.vertices, worst / cell);
    assert!(
        (mean - expect).abs() < 0.1 * cell,
        "mean radius {mean} vs {expect}"
    );
    assert!(worst < 0.5 * cell, "worst deviation {worst}");

    let mut fitted = Evolver::new(&target, {
        let mut w = settings.clone();
        w.fit.enabled = true;
        w
    })
    .unwrap();
    fitted.run(|_| {}).unwrap();
    fitted.mesh().validate().unwrap();
    let radii: Vec<f64> = fitted.positions().iter().map(|p| p.length()).collect();
    let worst = radii.iter().map(|x| (x - r).abs()).fold(0.0, f64::max);
    println!(
        "after the final fit: worst |r − R| = {:.4} cells",
        worst / cell
    );
    assert!(
        worst < 0.1 * cell,
        "final fit left a vertex {worst} from the sphere"
    );
}

#[wasm_bindgen_test(unsupported = test)]
fn failing_solves_are_retried_then_reported_without_touching_the_mesh() {
    let target = sphere_cloud(500, 1.0);
    let mut settings = WrapSettings::default();
    // A solver that cannot converge: every attempt fails. The first retry keeps τ (it only
    // clamps negative weights), each later one halves it.
    settings.tuning.solver.max_iterations = 1;
    settings.tuning.solver.tolerance = 1e-30;
    let mut ev = Evolver::new(&target, settings).unwrap();
    let before = ev.mesh().positions().to_vec();
    match ev.step() {
        Err(lsw::flow::EvolveError::Diverged {
            step, retries, tau, ..
        }) => {
            assert_eq!((step, retries), (1, 4));
            assert!(
                (tau - 0.07 / 8.0).abs() < 1e-12,
                "τ after three halvings: {tau}"
            );
        }
        other => panic!("expected a Diverged error, got {other:?}"),
    }
    assert_eq!(ev.mesh().positions(), &before[..]);
}

#[wasm_bindgen_test(unsupported = test)]
fn same_input_same_mesh() {
    let target = sphere_cloud(3000, 1.0);
    let settings = {
        let mut w = WrapSettings::default();
        w.stop.steps = 25;
        w
    };
    let run = || {
        let mut ev = Evolver::new(&target, settings.clone()).unwrap();
        ev.run(|_| {}).unwrap();
        (ev.positions(), ev.triangles())
    };
    let (a, b) = (run(), run());
    assert_eq!(a.1, b.1);
    assert!(a
        .0
        .iter()
        .zip(&b.0)
        .all(|(p, q)| p.to_array() == q.to_array()));
}

#[wasm_bindgen_test(unsupported = test)]
fn a_forced_divergence_is_rolled_back_and_reported() {
    // τ at the top of its range makes the explicit advection overshoot by orders of magnitude.
    let target = sphere_cloud(2000, 1.0);
    let settings = {
        let mut w = WrapSettings::default();
        w.flow.tau = 10.0;
        w.flow.d1 = 50.0;
        w
    };
    let mut ev = Evolver::new(&target, settings).unwrap();
    let mut before = ev.mesh().positions().to_vec();
    let err = loop {
        match ev.step() {
            Ok(r) => {
                assert!(!r.done, "finished without diverging");
                before = ev.mesh().positions().to_vec();
            }
            Err(e) => break e,
        }
    };
    assert!(
        matches!(
            err,
            lsw::flow::EvolveError::Divergence { .. } | lsw::flow::EvolveError::Diverged { .. }
        ),
        "{err}"
    );
    // The surface is the last good one, the run is over and says why.
    assert!(ev.is_done());
    assert!(
        ev.stop_reason().unwrap().contains("diverged"),
        "{:?}",
        ev.stop_reason()
    );
    ev.mesh().validate().unwrap();
    if matches!(err, lsw::flow::EvolveError::Divergence { .. }) {
        assert_eq!(ev.mesh().positions(), &before[..]);
    }
    let c = lsw::metrics::certificate::certify(&ev.positions(), &ev.triangles(), Some(&target));
    assert!(c.valid, "{c:?}");
}

#[wasm_bindgen_test(unsupported = test)]
fn degenerate_targets_fail_before_any_work() {
    let three = Target::new(vec![lsw::DVec3::ZERO, lsw::DVec3::X, lsw::DVec3::Y], vec![]).unwrap();
    let err = Evolver::new(&three, WrapSettings::default())
        .err()
        .expect("refused");
    assert!(err.to_string().contains("distinct point"), "{err}");
    let flat: Vec<lsw::DVec3> = fibonacci_sphere(300)
        .into_iter()
        .map(|p| lsw::DVec3::new(p.x, p.y, 0.0))
        .collect();
    let err = Evolver::new(&Target::new(flat, vec![]).unwrap(), WrapSettings::default())
        .err()
        .expect("refused");
    assert!(err.to_string().contains("one plane"), "{err}");
}
