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

/// Reading reports its share of the file as it goes ("reading", non-decreasing, ending at 1) in
/// every format that holds big clouds; with no sink it reports nothing.
#[wasm_bindgen_test(unsupported = test)]
fn reading_reports_its_share_of_the_file() {
    use lsw::io::{read_bytes_progress, write_bytes, Format, VolumeOptions, WriteInput};
    let points: Vec<lsw::DVec3> = (0..20_000)
        .map(|i| {
            let t = i as f64 * 0.001;
            lsw::DVec3::new(lsw::fmath::cos(t * 7.0), lsw::fmath::sin(t * 5.0), t)
        })
        .collect();
    let xyz: String = points
        .iter()
        .map(|p| format!("{} {} {}\n", p.x, p.y, p.z))
        .collect();
    let ptx = "20000\n1\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n1 0 0 0\n0 1 0 0\n0 0 1 0\n0 0 0 1\n"
        .to_string()
        + &points
            .iter()
            .map(|p| format!("{} {} {} 0.5\n", p.x, p.y, p.z))
            .collect::<String>();
    let pcd = format!(
        "FIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nWIDTH {n}\nPOINTS {n}\nDATA ascii\n{xyz}",
        n = points.len()
    );
    let files = [
        (
            "cloud.ply",
            write_bytes(Format::Ply, &WriteInput::new(&points, &[])).unwrap(),
        ),
        (
            "cloud.obj",
            write_bytes(Format::Obj, &WriteInput::new(&points, &[])).unwrap(),
        ),
        ("cloud.xyz", xyz.into_bytes()),
        ("cloud.ptx", ptx.into_bytes()),
        ("cloud.pcd", pcd.into_bytes()),
    ];
    for (name, bytes) in files {
        let mut seen: Vec<(String, f64)> = Vec::new();
        let mut sink = |phase: &str, f: f64| seen.push((phase.to_string(), f));
        let read = read_bytes_progress(
            &bytes,
            Some(name),
            &VolumeOptions::default(),
            &mut Progress::to(&mut sink),
        )
        .unwrap_or_else(|e| panic!("{name}: {e}"));
        assert_eq!(read.target.points.len(), points.len(), "{name}");
        assert!(seen.iter().all(|(p, _)| p == "reading"), "{name}: {seen:?}");
        assert!(
            seen.windows(2).all(|w| w[0].1 <= w[1].1),
            "{name}: {seen:?}"
        );
        assert!(seen.len() >= 2 && seen[0].1 < 1.0, "{name}: {seen:?}");
        assert_eq!(seen.last().map(|s| s.1), Some(1.0), "{name}");
    }
}
