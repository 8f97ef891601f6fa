//! Topology surgery (issue 14): a genus-0 start surface shrinking onto a target with handles
//! opens each handle by cutting the two membranes that meet across its hole and gluing a tube;
//! a neck between separate objects is cut and capped; scan holes stay spanned. After every surgery the surface is certified (closed, manifold,
//! oriented, 0 intersecting face pairs by exact predicates) and its genus is the event's.
//! Runs natively and, a subset, in headless Chromium.
//!
//! The defaults throughout. (With the coarser final edges of `valid_wraps.rs`, λ_min 0.3, the
//! genus-5 chain's holes are about two edges wide: too few vertices for a membrane to form,
//! and they stay closed.)

use lsw::demo::shapes::generate;
use lsw::flow::surgery::SurgeryEvent;
use lsw::flow::{Evolver, StartSurface, WrapSettings};
use lsw::metrics::certificate::certify;
use lsw::target::Target;
use wasm_bindgen_test::*;

wasm_bindgen_test_configure!(run_in_browser);

/// Wraps the generated shape `name` from `start`, certifying the surface after every step that
/// operated; returns the final genus and the events.
fn wrap(name: &str, start: StartSurface) -> (i64, Vec<SurgeryEvent>) {
    let mut settings = WrapSettings::default();
    settings.start.surface = start;
    wrap_with(name, settings)
}

/// [`wrap`] with any settings.
fn wrap_with(name: &str, settings: WrapSettings) -> (i64, Vec<SurgeryEvent>) {
    let start = settings.start.surface;
    let (p, t) = generate(name).unwrap_or_else(|e| panic!("{name}: {e}"));
    let target = Target::new(p, t).unwrap();
    let mut ev = Evolver::new(&target, settings).unwrap_or_else(|e| panic!("{name}: {e}"));
    while !ev.is_done() {
        let r = ev.step().unwrap_or_else(|e| panic!("{name}: {e}"));
        // The surface now has the topology the last event left (a report carries the events of
        // any steps redone on the way).
        if let Some(e) = r.surgery.last() {
            let c = certify(&ev.positions(), &ev.triangles(), None);
            assert!(
                c.valid && c.self_intersections == 0,
                "{name}: after the surgery of step {}: {c:?}",
                e.step
            );
            assert_eq!(c.genus, Some(e.genus_after), "{name}: step {}", e.step);
            assert_eq!(r.genus, e.genus_after, "{name}: the step's report");
        }
    }
    let c = certify(&ev.positions(), &ev.triangles(), Some(&target));
    assert!(c.valid && c.self_intersections == 0, "{name}: {c:?}");
    let events = ev.surgery_events().to_vec();
    println!(
        "{name} / {start:?}: genus {:?}, {} vertices, events at steps {:?}",
        c.genus,
        ev.positions().len(),
        events.iter().map(|e| e.step).collect::<Vec<_>>()
    );
    (c.genus.unwrap_or(-1), events)
}

#[test]
fn sphere_to_torus_and_double_torus_on_clouds() {
    for (name, genus) in [("torus-g1-cloud", 1), ("torus-g2-cloud", 2)] {
        let (g, events) = wrap(name, StartSurface::Auto);
        assert_eq!(g, genus, "{name}");
        assert_eq!(events.len(), genus as usize, "{name}: one tube per handle");
        assert!(events.iter().all(|e| e.kind == "handle"));
        assert_eq!(events[0].genus_before, 0);
    }
}

#[test]
fn higher_genus_clouds_and_the_sampling_limit_get_their_genus() {
    for (name, genus) in [
        ("torus-g3-cloud", 3),
        ("torus-g5-cloud", 5),
        ("torus-sparse-cloud", 1),
    ] {
        assert_eq!(wrap(name, StartSurface::Auto).0, genus, "{name}");
    }
}

#[test]
fn meshes_with_handles_get_their_genus_from_the_icosphere_start() {
    for (name, genus) in [("torus-g3", 3), ("cube-hole", 1)] {
        assert_eq!(wrap(name, StartSurface::Icosphere).0, genus, "{name}");
    }
}

#[test]
fn scan_holes_thin_parts_and_necks_are_never_cut() {
    for name in ["sphere-cut-cloud", "thin-plate-cloud", "dumbbell"] {
        let (g, events) = wrap(name, StartSurface::Icosphere);
        assert_eq!((g, events.len()), (0, 0), "{name}: {events:?}");
    }
}

#[test]
fn a_neck_between_two_separate_spheres_pinches_into_two_components() {
    let (p, t) = generate("two-spheres-apart-cloud").unwrap();
    let target = Target::new(p, t).unwrap();
    let mut ev = Evolver::new(&target, WrapSettings::default()).unwrap();
    ev.run(|_| {}).unwrap();
    let c = certify(&ev.positions(), &ev.triangles(), Some(&target));
    assert!(c.valid && c.self_intersections == 0, "{c:?}");
    assert_eq!((c.components, c.genus), (Some(2), Some(0)), "{c:?}");
    let kinds: Vec<&str> = ev.surgery_events().iter().map(|e| e.kind).collect();
    assert!(kinds.contains(&"pinch"), "{kinds:?}");
}

#[test]
fn close_gaps_keeps_narrower_handles_closed() {
    // torus-g1-cloud: the hole is 0.8 wide, 28 % of the diagonal (2.88).
    for (close_gaps, genus) in [(0.2, 1), (0.35, 0), (1.0, 0)] {
        let mut s = WrapSettings::default();
        s.surgery.close_gaps = close_gaps;
        let (g, events) = wrap_with("torus-g1-cloud", s);
        assert_eq!(g, genus, "close_gaps {close_gaps}");
        assert_eq!(events.len(), genus as usize, "close_gaps {close_gaps}");
    }
}

/// In the browser: sphere → torus.
#[wasm_bindgen_test]
fn browser_sphere_to_torus() {
    let (g, events) = wrap("torus-g1-cloud", StartSurface::Auto);
    assert_eq!((g, events.len()), (1, 1));
}
