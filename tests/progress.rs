//! Progress of the long phases (issue 16, item 6): a cloud's stray-point test, the field build,
//! the start surface, a cloud's crease detection and the final fit report a phase name and a
//! fraction, in order, each phase from 0 to 100 %. Natively and in headless Chromium.

use lsw::demo::shapes::generate;
use lsw::flow::{Evolver, WrapSettings};
use lsw::progress::Progress;
use lsw::target::Target;
use wasm_bindgen_test::*;

wasm_bindgen_test_configure!(run_in_browser);

#[wasm_bindgen_test(unsupported = test)]
fn phases_report_in_order_and_each_reaches_the_end() {
    let (p, t) = generate("torus-g1-cloud").unwrap();
    let target = Target::new(p, t).unwrap();
    let mut settings = WrapSettings::default();
    settings.stop.steps = 12;
    let mut seen: Vec<(String, f64)> = Vec::new();
    let mut sink = |phase: &str, f: f64| seen.push((phase.to_string(), f));
    {
        let mut progress = Progress::to(&mut sink);
        let mut ev = Evolver::new_with_progress(&target, settings, &mut progress).unwrap();
        while !ev.is_done() {
            ev.step_with_progress(&mut progress).unwrap();
        }
    }
    // Phases in the order they run, each once, each ending at 1.
    let mut phases: Vec<&str> = Vec::new();
    for (p, _) in &seen {
        if phases.last() != Some(&p.as_str()) {
            assert!(!phases.contains(&p.as_str()), "{p} came back: {seen:?}");
            phases.push(p);
        }
    }
    assert_eq!(
        phases,
        [
            "stray points",
            "distance field: near band",
            "distance field: sweeps",
            "start surface",
            "sharp creases",
            "final fit"
        ],
        "{seen:?}"
    );
    for phase in &phases {
        let fr: Vec<f64> = seen.iter().filter(|s| s.0 == *phase).map(|s| s.1).collect();
        assert!(fr.windows(2).all(|w| w[0] <= w[1]), "{phase}: {fr:?}");
        // (A phase's first report starts its time in the app's breakdown by phase.)
        assert_eq!(fr.first(), Some(&0.0), "{phase}: {fr:?}");
        assert_eq!(fr.last(), Some(&1.0), "{phase}: {fr:?}");
        assert!(
            fr.iter().all(|f| (0.0..=1.0).contains(f)),
            "{phase}: {fr:?}"
        );
    }
}
