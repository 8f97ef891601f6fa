//! Valid by default: every generated failure class (tori of genus 1–5 as meshes and clouds, a
//! torus cloud at the spacing limit, cut spheres, a cube with a hole, two spheres almost touching,
//! a thin plate, a self-intersecting input, a dumbbell) wraps to a surface whose certificate is
//! valid — closed, manifold, oriented, 0 intersecting face pairs by exact predicates — and
//! degenerate inputs are refused by name. Runs natively and in headless Chromium (a subset there).
//!
//! Most of these are the corpus tier (`cargo test -- --ignored`, which `.ci/test` runs); the
//! default tier keeps the units and pinch-apart properties.
//!
//! The wraps use the defaults except a coarser grid (24 cells per minimum side instead of 40) and
//! coarser final edges (λ_min 0.3 instead of 0.14, about 4× fewer vertices) to keep the suite
//! fast; the start surfaces and guards are the same.

use glam::DVec3;
use lsw::demo::shapes::generate;
use lsw::flow::{Evolver, StartSurface, WrapSettings};
use lsw::metrics::certificate::{certify, Certificate};
use lsw::target::Target;
use wasm_bindgen_test::*;

wasm_bindgen_test_configure!(run_in_browser);

#[path = "common/wraps.rs"]
mod wraps;
use wraps::{coarse, target};

/// Wraps `target` with `settings` and returns the start used, the vertex count and the
/// certificate of the result.
fn wrap_target(
    name: &str,
    target: &Target,
    settings: WrapSettings,
) -> (StartSurface, usize, Certificate) {
    let mut ev = Evolver::new(target, settings).unwrap_or_else(|e| panic!("{name}: {e}"));
    ev.run(|_| {}).unwrap_or_else(|e| panic!("{name}: {e}"));
    let c = certify(&ev.positions(), &ev.triangles(), Some(target));
    println!(
        "{name}: start {:?}, {} vertices, genus {:?}, components {:?}, SI {}",
        ev.start_surface(),
        ev.positions().len(),
        c.genus,
        c.components,
        c.self_intersections
    );
    (ev.start_surface(), ev.positions().len(), c)
}

/// Wraps `name` with [`coarse`] settings and returns the start used and the certificate of the
/// result.
fn wrap(name: &str, start: StartSurface) -> (StartSurface, Certificate) {
    let mut settings = coarse();
    settings.start.surface = start;
    let (start, _, c) = wrap_target(name, &target(name), settings);
    (start, c)
}

fn assert_valid(name: &str, c: &Certificate) {
    assert!(
        c.valid && c.closed && c.manifold && c.oriented && c.self_intersections == 0,
        "{name}: {c:?}"
    );
}

#[test]
#[ignore = "corpus tier (whole wraps): cargo test -- --ignored"]
fn closed_meshes_keep_their_genus_with_the_auto_start() {
    for (name, genus, components) in [
        ("torus-g1", 1, 1),
        ("torus-g2", 2, 1),
        ("torus-g3", 3, 1),
        ("torus-g4", 4, 1),
        ("torus-g5", 5, 1),
        ("cube-hole", 1, 1),
        ("dumbbell", 0, 1),
        ("thin-plate", 0, 1),
        ("plate-holes", 3, 1),
    ] {
        let (start, c) = wrap(name, StartSurface::Auto);
        assert_eq!(start, StartSurface::Isosurface, "{name}");
        assert_valid(name, &c);
        assert_eq!(
            (c.genus, c.components),
            (Some(genus), Some(components)),
            "{name}"
        );
    }
}

#[test]
#[ignore = "corpus tier (whole wraps): cargo test -- --ignored"]
fn clouds_and_open_inputs_wrap_valid() {
    for name in [
        // Merged into one component by the start surface (a 1 % gap is below d_iso): still valid.
        "two-spheres",
        "torus-g1-cloud",
        "torus-g3-cloud",
        "torus-g5-cloud",
        "torus-sparse-cloud",
        "sphere-cut-cloud",
        "sphere-cut",
        "thin-plate-cloud",
        "self-intersecting",
    ] {
        let (_, c) = wrap(name, StartSurface::Auto);
        assert_valid(name, &c);
    }
}

/// A scan with stray returns: 1 % of a genus-3 torus cloud's count scattered over a box half as
/// large again as the torus's. Every stray farther from the torus than the test's radius
/// (`field.outlier_spacings` median spacings) is left out, no point of the torus is, and the
/// wrap is valid with the torus's genus and stays on it. (With every point kept, the bunny
/// cloud with 0.5 % strays diverged at step 98.)
#[test]
#[ignore = "corpus tier (whole wraps): cargo test -- --ignored"]
fn a_cloud_with_stray_points_wraps_without_them() {
    let clean = target("torus-g3-cloud");
    let (lo, size) = (clean.bbox.min, clean.bbox.size());
    let n = clean.points.len() / 100;
    let mut rng = lsw::demo::Rng::new(12345);
    let mut unit = || rng.uniform();
    let strays: Vec<glam::DVec3> = (0..n)
        .map(|_| lo - 0.25 * size + 1.5 * size * glam::DVec3::new(unit(), unit(), unit()))
        .collect();
    let noisy = Target::new([clean.points.clone(), strays.clone()].concat(), vec![]).unwrap();
    let spacings = WrapSettings::default().tuning.field.outlier_spacings;
    let (kept, left_out) = noisy.without_isolated_points(spacings).unwrap();
    let bits = |p: &glam::DVec3| p.to_array().map(f64::to_bits);
    let kept_set: std::collections::HashSet<[u64; 3]> = kept.points.iter().map(bits).collect();
    assert!(clean.points.iter().all(|p| kept_set.contains(&bits(p))));
    let reach = spacings * lsw::geometry::spatial::spacing::median_spacing(&clean.points);
    let far: Vec<&glam::DVec3> = strays
        .iter()
        .filter(|&&s| clean.points.iter().all(|&p| (p - s).length() > reach))
        .collect();
    assert!(far.iter().all(|p| !kept_set.contains(&bits(p))));
    println!(
        "{n} strays, {} beyond reach, {left_out} left out",
        far.len()
    );
    assert!(
        far.len() >= n / 4,
        "the test's strays mostly landed near the torus"
    );

    // The defaults: with the coarser final edges of the other tests here, the strays left near
    // the torus (within the radius) closed some of its holes in 4 of 6 random sets (the clean
    // cloud keeps them); at the defaults all 6 keep genus 3 (benches/RESULTS.md).
    let mut ev = Evolver::new(&noisy, WrapSettings::default()).unwrap();
    ev.run(|_| {}).unwrap();
    assert_eq!(ev.isolated_points(), left_out);
    let c = certify(&ev.positions(), &ev.triangles(), Some(&clean));
    assert_valid("torus-g3-cloud with strays", &c);
    assert_eq!((c.genus, c.components), (Some(3), Some(1)), "{c:?}");
    let off = c.distance_max.unwrap() / clean.bbox.diagonal();
    assert!(
        off < 0.05,
        "the wrap reaches {:.1} % of the diagonal off the torus",
        100.0 * off
    );
}

/// A cloud sampled 20× more sparsely on one side (an ellipsoid; a random sampling, not a
/// lattice): the sparse side is surface, not strays. Counted alone, its points had fewer than six
/// within the stray radius and 942 of its ~950 were left out; the wrap then slipped into the
/// open half-shell and diverged (benches/RESULTS.md, twenty-first session). Now nearly all stay,
/// and the wrap with the defaults is valid, genus 0, and covers the sparse side.
#[test]
#[ignore = "corpus tier (whole wraps): cargo test -- --ignored"]
fn a_cloud_sampled_sparsely_on_one_side_keeps_that_side() {
    let mut rng = lsw::demo::Rng::new(11);
    let mut points = Vec::new();
    while points.len() < 20_000 {
        let d = glam::DVec3::new(rng.normal(), rng.normal(), rng.normal()).normalize();
        if d.x < 0.0 && rng.uniform() > 0.05 {
            continue;
        }
        points.push(d * glam::DVec3::new(1.0, 0.6, 0.4));
    }
    let sparse = points.iter().filter(|p| p.x < 0.0).count();
    let target = Target::new(points, vec![]).unwrap();
    let mut ev = Evolver::new(&target, WrapSettings::default()).unwrap();
    let left_out = ev.isolated_points();
    assert!(
        left_out * 10 <= sparse,
        "{left_out} of the sparse side's {sparse} points left out"
    );
    ev.run(|_| {}).unwrap();
    let c = certify(&ev.positions(), &ev.triangles(), Some(&target));
    assert_valid("half-sparse ellipsoid", &c);
    assert_eq!((c.genus, c.components), (Some(0), Some(1)), "{c:?}");
    // Every sparse point lies on or inside the wrap, and the wrap's farthest vertex is within
    // a sparse spacing or so of the data (the ellipsoid is 2.6 across).
    assert!(!c.target_part_outside, "{c:?}");
    assert!(c.distance_max.unwrap() < 0.25, "{c:?}");
}

/// Clouds whose density falls steadily from one end to the other, as a scanner sees a part at a
/// growing angle: every point kept with a chance of 1 at the high-x end down to `low` at the
/// low-x end. Surgery took the sparse end's sampling gaps for holes (empty space at the global
/// median spacing): the torus came out with genus 4, the cut sphere with 1. Now a tube where
/// the cloud is sparser than its median needs a hole that is empty at the local spacing, and
/// both keep their genus.
#[test]
#[ignore = "corpus tier (whole wraps): cargo test -- --ignored"]
fn a_cloud_sampled_more_sparsely_towards_one_end_keeps_its_genus() {
    for (name, low, genus) in [("torus-g1-cloud", 0.05, 1), ("sphere-cut-cloud", 0.1, 0)] {
        let (points, _) = generate(name).unwrap();
        let (lo, hi) = points
            .iter()
            .fold((f64::MAX, f64::MIN), |(a, b), p| (a.min(p.x), b.max(p.x)));
        let mut rng = lsw::demo::Rng::new(5);
        let kept: Vec<DVec3> = points
            .into_iter()
            .filter(|p| rng.uniform() < low + (1.0 - low) * (p.x - lo) / (hi - lo))
            .collect();
        let target = Target::new(kept, vec![]).unwrap();
        let (_, _, c) = wrap_target(name, &target, WrapSettings::default());
        assert_valid(name, &c);
        assert_eq!((c.genus, c.components), (Some(genus), Some(1)), "{name}");
    }
}

/// A plate cloud 1 % as thick as it is wide, at the defaults. The early wrap's edges are longer
/// than the plate is thick, and the triangles turning round its rim cut it short; without
/// `flow::regrow` the corners stayed cut (704 of the 20 000 points outside the wrap, a Hausdorff
/// distance of 5.2 % of the diagonal). Now the wrap goes round the rim.
#[test]
#[ignore = "corpus tier (whole wraps): cargo test -- --ignored"]
fn a_thin_plate_cloud_keeps_its_rim_and_corners() {
    let target = target("thin-plate-cloud");
    let (_, _, c) = wrap_target("thin-plate-cloud", &target, WrapSettings::default());
    assert_valid("thin-plate-cloud", &c);
    assert_eq!((c.genus, c.components), (Some(0), Some(1)), "{c:?}");
    let outside = c.target_points_outside.unwrap();
    assert!(
        outside <= 20,
        "{outside} of 20 000 points outside the wrap: {c:?}"
    );
}

/// `n` points uniformly at random (xorshift, seeded) on the surface of a union of boxes
/// (centre, half sizes): each box's faces, less what lies inside another box.
fn boxes_cloud(boxes: &[(DVec3, DVec3)], n: usize) -> Vec<DVec3> {
    let mut state = 0x9E37_79B9_7F4A_7C15u64;
    let mut uniform = move || {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        (state >> 11) as f64 / (1u64 << 53) as f64
    };
    let inside = |p: DVec3, (c, h): (DVec3, DVec3)| ((p - c).abs() - h).max_element() < -1e-12;
    // Each face pair normal to axis a has area 8·h_b·h_c.
    let areas: Vec<[f64; 3]> = boxes
        .iter()
        .map(|(_, h)| [h.y * h.z, h.x * h.z, h.x * h.y])
        .collect();
    let total: f64 = areas.iter().flatten().sum();
    let mut points = Vec::new();
    while points.len() < n {
        let mut r = uniform() * total;
        let (mut k, mut a) = (0, 0);
        'pick: for (i, faces) in areas.iter().enumerate() {
            for (j, &f) in faces.iter().enumerate() {
                (k, a) = (i, j);
                if r < f {
                    break 'pick;
                }
                r -= f;
            }
        }
        let (c, h) = boxes[k];
        let mut q = DVec3::new(
            (2.0 * uniform() - 1.0) * h.x,
            (2.0 * uniform() - 1.0) * h.y,
            (2.0 * uniform() - 1.0) * h.z,
        );
        q[a] = if uniform() < 0.5 { -h[a] } else { h[a] };
        let p = c + q;
        if !boxes
            .iter()
            .enumerate()
            .any(|(j, &b)| j != k && inside(p, b))
        {
            points.push(p);
        }
    }
    points
}

/// 30 000 points on a square frame of four bars 0.1 × 0.1 in cross-section, the frame 1 across.
fn square_frame_cloud() -> Vec<DVec3> {
    let bar = |x: f64, y: f64, hx: f64, hy: f64| (DVec3::new(x, y, 0.0), DVec3::new(hx, hy, 0.05));
    boxes_cloud(
        &[
            bar(0.0, 0.45, 0.5, 0.05),
            bar(0.0, -0.45, 0.5, 0.05),
            bar(0.45, 0.0, 0.05, 0.5),
            bar(-0.45, 0.0, 0.05, 0.5),
        ],
        30_000,
    )
}

/// A square frame's cloud at the defaults: genus 1. Its bars are a tenth as thick as the frame is
/// wide. At a corner, a wrap vertex that slipped past the rim into the bar lies between the bar's
/// top and bottom faces, far from both, and the full-wrap term drove it on through the corner to
/// the inner wall: the corners were cut (813 points outside), and the surgery took the sheets
/// meeting inside for membranes (genus 3). The cloud's field is now negative deep inside the bars
/// (`field.enclosed_cells`), so such a vertex is held and regrown out past the surface.
#[test]
#[ignore = "corpus tier (whole wraps): cargo test -- --ignored"]
fn a_square_frame_cloud_keeps_its_corners() {
    let target = Target::new(square_frame_cloud(), Vec::new()).unwrap();
    let (_, _, c) = wrap_target("square frame", &target, WrapSettings::default());
    assert_valid("square frame", &c);
    assert_eq!((c.genus, c.components), (Some(1), Some(1)), "{c:?}");
    let outside = c.target_points_outside.unwrap();
    assert!(outside <= 20, "{outside} points outside the wrap: {c:?}");
}

/// A ladder-back chair of boxes as a cloud of 30 000 points: seat, four legs, and a back of two
/// posts and three rails, genus 3. The back's holes are wide and low (0.83 × 0.2). A hole once
/// opened was left alone within a ball round its tube, and the ball round the lowest hole's tube
/// (radius 0.36) reached the hole above it, whose membrane was then never cut: genus 2, a vertex
/// 0.1 from the data, 2 400 vertices. Before that, the top hole got two tubes and the middle one
/// none. Now a vertex in reach of an opened hole is in it only with no data (a rail) on the
/// straight way to the tube's centre.
#[test]
#[ignore = "corpus tier (whole wraps): cargo test -- --ignored"]
fn a_ladder_back_chair_cloud_gets_a_handle_per_hole() {
    let b = |c: [f64; 3], h: [f64; 3]| (DVec3::from_array(c), DVec3::from_array(h));
    let mut boxes = vec![b([0.0, 0.0, 0.5], [0.5, 0.5, 0.04])];
    for (x, y) in [(-0.44, -0.44), (-0.44, 0.44), (0.44, -0.44), (0.44, 0.44)] {
        boxes.push(b([x, y, 0.23], [0.03, 0.03, 0.23]));
    }
    for x in [-0.44, 0.44] {
        boxes.push(b([x, 0.46, 0.95], [0.03, 0.03, 0.45]));
    }
    for z in [0.85, 1.1, 1.35] {
        boxes.push(b([0.0, 0.46, z], [0.44, 0.025, 0.025]));
    }
    let target = Target::new(boxes_cloud(&boxes, 30_000), Vec::new()).unwrap();
    let (_, _, c) = wrap_target("ladder-back chair", &target, WrapSettings::default());
    assert_valid("ladder-back chair", &c);
    assert_eq!((c.genus, c.components), (Some(3), Some(1)), "{c:?}");
    // Membranes left uncut also kept the surface coarse (0.1 from the data).
    let worst = c.distance_max.unwrap();
    assert!(worst < 0.06, "a vertex {worst} from the data: {c:?}");
}

/// The twelve edge bars of a unit cube, `h` half as thick as they are wide, as a cloud: a cube
/// drilled along all three axes, and with thin bars its frame.
fn cube_frame_cloud(h: f64) -> Target {
    let c = 0.5 - h;
    let mut bars = Vec::new();
    for axis in 0..3 {
        for (s, t) in [(-1.0, -1.0), (-1.0, 1.0), (1.0, -1.0), (1.0, 1.0)] {
            let (mut centre, mut half) = (DVec3::ZERO, DVec3::splat(h));
            centre[(axis + 1) % 3] = s * c;
            centre[(axis + 2) % 3] = t * c;
            half[axis] = 0.5;
            bars.push((centre, half));
        }
    }
    Target::new(boxes_cloud(&bars, 30_000), Vec::new()).unwrap()
}

/// A cube drilled through along all three axes (square tunnels 0.44 wide in a unit cube: the
/// union of its twelve edge bars), genus 5. The six membranes over the tunnels meet in the
/// middle, each beside four others: after the first tube the others lay in its hole's ball and
/// were taken for the same hole, and the membranes that met several others paired along rings,
/// where no tube fits (genus 1). A hub stayed in the middle, a bubble of the wrap's inside 0.24
/// from the data, until it deflated (`flow.deflate_far`). Deflated, it became a saddle-shaped
/// membrane whose tube crossed the surface at its rim (3 to 5 pairs of faces) and was never
/// cut (genus 4, 0.30 from the data); the tube a ring further in fits (genus 5, 0.057).
#[test]
#[ignore = "corpus tier (whole wraps): cargo test -- --ignored"]
fn a_cube_drilled_along_three_axes_gets_five_handles() {
    assert_frame_wrapped("drilled cube", 0.14);
}

/// A cube's frame of thin bars (0.08 wide): the six membranes over its faces sink, meet and are
/// cut, and what is left between the tubes is a bubble of the inside that the advection held
/// against the curvature flow (genus 4, 0.49 from the data, with `flow.deflate_far` 0), until
/// the surface far from the data with the data in front of it deflated once the surgery had cut.
#[test]
#[ignore = "corpus tier (whole wraps): cargo test -- --ignored"]
fn a_cube_frame_cloud_is_wrapped_bar_by_bar() {
    assert_frame_wrapped("cube frame", 0.04);
}

/// [`cube_frame_cloud`]`(h)` wraps at the defaults to one valid genus-5 part with no vertex
/// 0.1 or more from the data (no hub or membrane left in the frame).
fn assert_frame_wrapped(name: &str, h: f64) {
    let target = cube_frame_cloud(h);
    let (_, _, c) = wrap_target(name, &target, WrapSettings::default());
    assert_valid(name, &c);
    assert_eq!((c.genus, c.components), (Some(5), Some(1)), "{c:?}");
    let worst = c.distance_max.unwrap();
    assert!(worst < 0.1, "a vertex {worst} from the data: {c:?}");
}

/// Two spheres' cloud at the defaults: the wrap pinches into two parts. Around the pinch a vertex
/// whose faces collapse gets negative cotangent weights, and the solve once converged to a
/// near-singular solution that threw it five box sizes away (the run diverged with no mesh); such a
/// solve is now retried with non-negative weights.
#[test]
fn two_spheres_pinch_apart_at_the_defaults() {
    // As `lsw demo` writes it: single-precision coordinates.
    let (p, t) = generate("two-spheres-apart-cloud").unwrap();
    let p = p.iter().map(|q| q.as_vec3().as_dvec3()).collect();
    let target = Target::new(p, t).unwrap();
    let (_, _, c) = wrap_target("two-spheres-apart-cloud", &target, WrapSettings::default());
    assert_valid("two-spheres-apart-cloud", &c);
    assert_eq!((c.genus, c.components), (Some(0), Some(2)), "{c:?}");
}

/// Lengths are relative to the target: the same cloud in other units (×1024, exact in floating
/// point) wraps to the same mesh, vertex for vertex. The curved splits' reach was once taken in
/// units of the input (metres and millimetres gave different wraps of the same scan).
#[test]
fn a_wrap_does_not_depend_on_the_units() {
    let name = "torus-g2-cloud";
    let (p, t) = generate(name).unwrap();
    let scaled = Target::new(p.iter().map(|&q| 1024.0 * q).collect(), t.clone()).unwrap();
    let ev = |target: &Target| {
        let mut ev = Evolver::new(target, coarse()).unwrap();
        ev.run(|_| {}).unwrap();
        ev.positions()
    };
    let (a, b) = (ev(&Target::new(p, t).unwrap()), ev(&scaled));
    assert_eq!(a.len(), b.len(), "{name}: vertex counts differ");
    let worst = a
        .iter()
        .zip(&b)
        .map(|(x, y)| (1024.0 * *x - *y).length())
        .fold(0.0, f64::max);
    assert_eq!(
        worst, 0.0,
        "{name}: vertices differ by up to {worst} (×1024 units)"
    );
}

/// A mesh with debris: the unit cube and twenty closed cubes a fifth of a grid cell wide floating
/// around it. Wrapped, five such cubes already left 18 intersecting face pairs, and a hundred made
/// the evolution diverge. The specks are left out and counted, and the wrap is valid.
#[test]
#[ignore = "corpus tier (whole wraps): cargo test -- --ignored"]
fn a_mesh_with_floating_debris_wraps_without_it() {
    let (mut points, mut triangles) = generate("cube").unwrap();
    let (lo, hi) = points.iter().fold(
        (glam::DVec3::INFINITY, glam::DVec3::NEG_INFINITY),
        |(a, b), &p| (a.min(p), b.max(p)),
    );
    let size = hi - lo;
    let mut rng = lsw::demo::Rng::new(5);
    for _ in 0..20 {
        let at = lo - 0.5 * size
            + 2.0 * size * glam::DVec3::new(rng.uniform(), rng.uniform(), rng.uniform());
        let off = points.len() as u32;
        for k in 0..8u32 {
            let corner = glam::DVec3::new((k & 1) as f64, (k >> 1 & 1) as f64, (k >> 2) as f64);
            points.push(at + 0.01 * size.x * corner);
        }
        // The cube's twelve triangles, outward.
        for f in [
            [0, 2, 3],
            [0, 3, 1],
            [4, 5, 7],
            [4, 7, 6],
            [0, 1, 5],
            [0, 5, 4],
            [2, 6, 7],
            [2, 7, 3],
            [0, 4, 6],
            [0, 6, 2],
            [1, 3, 7],
            [1, 7, 5],
        ] {
            triangles.push(f.map(|v: u32| v + off));
        }
    }
    let target = Target::new(points, triangles).unwrap();
    let mut ev = Evolver::new(&target, WrapSettings::default()).unwrap();
    assert!(ev.specks() >= 15, "{} specks left out", ev.specks());
    ev.run(|_| {}).unwrap();
    let c = certify(&ev.positions(), &ev.triangles(), Some(&target));
    assert_valid("cube with debris", &c);
    // Against the mesh as wrapped, no part of it lies outside (the specks do: not counted).
    let wrapped = ev.despecked_target().expect("specks were left out");
    assert_eq!(
        wrapped.triangles.len(),
        target.triangles.len() - 12 * ev.specks()
    );
    let c = certify(&ev.positions(), &ev.triangles(), Some(wrapped));
    assert!(!c.target_part_outside, "{c:?}");
}

#[test]
#[ignore = "corpus tier (whole wraps): cargo test -- --ignored"]
fn every_start_is_valid_on_a_genus_two_torus() {
    for start in [StartSurface::Icosphere, StartSurface::Isosurface] {
        let (_, c) = wrap("torus-g2", start);
        assert_valid(&format!("torus-g2 / {start:?}"), &c);
    }
    // The isosurface start on clouds takes only the exterior (never the inner sheet): a valid
    // result, or a clear refusal when the exterior leaks through the gaps between the points.
    for name in ["sphere-cut-cloud", "torus-g2-cloud"] {
        let target = target(name);
        let settings = {
            let mut w = WrapSettings::default();
            w.start.surface = StartSurface::Isosurface;
            w
        };
        match Evolver::new(&target, settings) {
            Ok(mut ev) => {
                ev.run(|_| {}).unwrap_or_else(|e| panic!("{name}: {e}"));
                let c = certify(&ev.positions(), &ev.triangles(), Some(&target));
                assert_valid(name, &c);
                assert_eq!(c.components, Some(1), "{name}");
            }
            Err(e) => {
                let msg = e.to_string();
                assert!(msg.contains("use --start icosphere"), "{name}: {msg}");
                println!("{name}: refused: {msg}");
            }
        }
    }
}

#[wasm_bindgen_test(unsupported = test)]
fn degenerate_inputs_are_refused_before_any_work() {
    for name in ["coplanar-3", "coplanar-cloud"] {
        let err = Evolver::new(&target(name), WrapSettings::default())
            .err()
            .unwrap_or_else(|| panic!("{name} was accepted"));
        let msg = err.to_string();
        assert!(
            msg.contains("plane") || msg.contains("distinct point"),
            "{name}: {msg}"
        );
    }
}

/// The browser subset: one of each kind (closed mesh of genus 2, open cut cloud, near contact,
/// thin part). Natively these run in the tests above.
#[wasm_bindgen_test]
fn browser_subset_is_valid() {
    let (_, c) = wrap("torus-g2", StartSurface::Auto);
    assert_valid("torus-g2", &c);
    assert_eq!(c.genus, Some(2));
    for name in ["sphere-cut-cloud", "two-spheres", "thin-plate"] {
        let (_, c) = wrap(name, StartSurface::Auto);
        assert_valid(name, &c);
    }
}

/// A small, noisy scan (the head phantom at 20 voxels, noise as strong as the tissue contrast):
/// its Otsu isosurface is full of bubbles and tunnels, so the exterior isosurface start leaks and
/// intersects itself. `auto` must then start from the icosphere and give a valid wrap (it used to
/// stop with "the isosurface start is not usable"); an explicit isosurface start is refused by
/// name.
#[test]
#[ignore = "corpus tier (whole wraps): cargo test -- --ignored"]
fn auto_start_falls_back_to_the_icosphere_on_a_noisy_volume() {
    use lsw::demo::phantom::phantom_volume;
    use lsw::demo::Rng;
    use lsw::flow::EvolveError;
    use lsw::io::volume::Inside;
    let mut vol = phantom_volume(20);
    let mut rng = Rng::new(7);
    for v in &mut vol.values {
        *v += (160.0 * (rng.uniform() - 0.5)) as f32;
    }
    let iso = vol.otsu().unwrap();
    let target = Target::from_volume(&vol, iso, Inside::Bright).unwrap();
    let mut settings = WrapSettings::default();
    settings.start.surface = StartSurface::Isosurface;
    let refused = Evolver::new(&target, settings.clone()).err();
    assert!(
        matches!(refused, Some(EvolveError::StartIntersects { .. })),
        "the isosurface start should leak here: {refused:?}"
    );
    settings.start.surface = StartSurface::Auto;
    settings.remesh.min_edge_multiplier = 0.3;
    settings.field.cells_per_min_dimension = 24;
    let mut ev = Evolver::new(&target, settings).unwrap();
    assert_eq!(ev.start_surface(), StartSurface::Icosphere);
    ev.run(|_| {}).unwrap();
    let c = certify(&ev.positions(), &ev.triangles(), Some(&target));
    println!("noisy phantom: {} vertices, {c:?}", ev.positions().len());
    assert_valid("noisy phantom", &c);
}

/// A voxel plate with nine square holes (a binary volume: a staircase iso-surface) keeps the
/// isosurface start under `auto`: its start at `auto`'s fine edges intersects after the remesh,
/// and the coarser isosurface start is tried before the icosphere (which took 95 K vertices and
/// 25 s to open the nine handles). The start has the plate's genus. A coarser start with
/// another topology than the target's is not taken.
#[test]
#[ignore = "corpus tier (whole wraps): cargo test -- --ignored"]
fn auto_retries_the_isosurface_start_with_coarser_edges() {
    use lsw::io::volume::{Inside, ScalarType, VoxelVolume};
    let dims = [84, 84, 16];
    let mut values = vec![0f32; dims[0] * dims[1] * dims[2]];
    for z in 4..12 {
        for y in 4..80 {
            for x in 4..80 {
                let hole = |c: usize| [18, 42, 66].iter().any(|&h: &usize| c.abs_diff(h) < 6);
                if !(hole(x) && hole(y)) {
                    values[x + dims[0] * (y + dims[1] * z)] = 1.0;
                }
            }
        }
    }
    let vol = VoxelVolume {
        dims,
        values,
        index_to_world: glam::DMat4::IDENTITY,
        datatype: ScalarType::U8,
        frame: "test plate".into(),
        frames: 1,
        frame_index: 0,
    };
    let target = Target::from_volume(&vol, 0.5, Inside::Bright).unwrap();
    let mut explicit = WrapSettings::default();
    explicit.start.surface = StartSurface::Isosurface;
    explicit.remesh.min_edge_multiplier = lsw::flow::settings::AUTO_ISOSURFACE_MIN_EDGE;
    assert!(
        Evolver::new(&target, explicit).is_err(),
        "the fine isosurface start no longer intersects here: the test shows nothing"
    );
    let ev = Evolver::new(&target, WrapSettings::default()).unwrap();
    assert_eq!(ev.start_surface(), StartSurface::Isosurface);
    let report = ev.mesh().validate().unwrap();
    assert_eq!((report.genus, report.components), (9, 1));

    // Two linked voxel tori: the coarser isosurface start is clean but has 5 components (the
    // offsets merge where the tori link), not the target's 2, so `auto` takes the icosphere.
    let n = 64;
    let mut values = vec![0f32; n * n * n];
    for (i, v) in values.iter_mut().enumerate() {
        let (x, y, z) = (i % n, i / n % n, i / (n * n));
        let p = glam::DVec3::new(x as f64 - 32.0, y as f64 - 32.0, z as f64 - 32.0) / 10.0;
        let ring = |a: f64, b: f64, c: f64| lsw::fmath::hypot((a * a + b * b).sqrt() - 1.3, c);
        if ring(p.x - 0.8, p.y, p.z) < 0.35 || ring(p.x + 0.8, p.z, p.y) < 0.35 {
            *v = 1.0;
        }
    }
    let linked = VoxelVolume {
        dims: [n, n, n],
        values,
        ..vol
    };
    let target = Target::from_volume(&linked, 0.5, Inside::Bright).unwrap();
    // (At 38 cells: at the default 40 this grid, sized by the tori's principal box, has a fine
    // start that does not intersect but merges them too, genus 6; the linked tori wrap as one
    // part at any start, see the twenty-first session in benches/RESULTS.md.)
    let mut settings = WrapSettings::default();
    settings.field.cells_per_min_dimension = 38;
    let mut explicit = settings.clone();
    explicit.start.surface = StartSurface::Isosurface;
    explicit.remesh.min_edge_multiplier = lsw::flow::settings::AUTO_ISOSURFACE_MIN_EDGE;
    assert!(
        Evolver::new(&target, explicit).is_err(),
        "the fine isosurface start no longer intersects here: the test shows nothing"
    );
    let ev = Evolver::new(&target, settings).unwrap();
    assert_eq!(ev.start_surface(), StartSurface::Icosphere);
}

/// A voxel trefoil knot (a tube of radius 0.12 round the curve (sin t + 2 sin 2t, cos t −
/// 2 cos 2t, −sin 3t)·0.3, 96³ voxels over ±1.1, a one-voxel ramp): its strands pass 0.12
/// apart, 5 voxels, 3–4 cells of the volume's default grid. The isosurface start joined them at
/// a crossing and kept a speck of tetrahedra, and the wrap ended so (genus 1 in 2 parts; at
/// 120³ genus 2 in 4). `auto` now takes the start of a 1.5× finer grid, which has the knot's
/// topology, when a volume's one-part iso-surface and its start differ.
#[test]
#[ignore = "corpus tier (whole wraps): cargo test -- --ignored"]
fn a_voxel_knot_keeps_its_strands_apart() {
    use lsw::io::volume::{Inside, ScalarType, VoxelVolume};
    let (n, ext, r) = (96usize, 1.1, 0.12);
    let h = 2.0 * ext / (n - 1) as f64;
    let curve: Vec<DVec3> = (0..240)
        .map(|k| {
            let t = std::f64::consts::TAU * k as f64 / 240.0;
            let (sin, cos) = (lsw::fmath::sin, lsw::fmath::cos);
            let (s, c) = (sin(t), cos(t));
            let (s2, c2, s3) = (sin(2.0 * t), cos(2.0 * t), sin(3.0 * t));
            DVec3::new(s + 2.0 * s2, c - 2.0 * c2, -s3) * 0.3
        })
        .collect();
    // The distance to the curve where it matters (within a voxel of the tube), by segment.
    let mut d = vec![f64::INFINITY; n * n * n];
    let voxel = |x: f64| ((x + ext) / h).clamp(0.0, (n - 1) as f64);
    for k in 0..curve.len() {
        let (a, b) = (curve[k], curve[(k + 1) % curve.len()]);
        let (lo, hi) = (a.min(b) - (r + h), a.max(b) + (r + h));
        let (i0, i1) = (lo.to_array().map(voxel), hi.to_array().map(voxel));
        for z in i0[2].ceil() as usize..=i1[2].floor() as usize {
            for y in i0[1].ceil() as usize..=i1[1].floor() as usize {
                for x in i0[0].ceil() as usize..=i1[0].floor() as usize {
                    let p = DVec3::new(x as f64, y as f64, z as f64) * h - DVec3::splat(ext);
                    let ab = b - a;
                    let t = ((p - a).dot(ab) / ab.length_squared()).clamp(0.0, 1.0);
                    let slot = &mut d[x + n * (y + n * z)];
                    *slot = slot.min((p - a - t * ab).length() - r);
                }
            }
        }
    }
    let values = d
        .iter()
        .map(|&d| (0.5 - d / (2.0 * h)).clamp(0.0, 1.0) as f32)
        .collect();
    let vol = VoxelVolume {
        dims: [n, n, n],
        values,
        index_to_world: glam::DMat4::IDENTITY,
        datatype: ScalarType::F32,
        frame: "test knot".into(),
        frames: 1,
        frame_index: 0,
    };
    let target = Target::from_volume(&vol, 0.5, Inside::Bright).unwrap();
    let (start, _, c) = wrap_target("knot", &target, WrapSettings::default());
    assert_eq!(start, StartSurface::Isosurface);
    assert_valid("knot", &c);
    assert_eq!((c.target_genus, c.target_components), (Some(1), Some(1)));
    assert_eq!((c.genus, c.components), (Some(1), Some(1)), "{c:?}");
}

/// A ball (r 0.8) bored through by a hole of radius 0.07, 1.75 cells of the default grid: the
/// isosurface start, an offset of ~1 cell, closes the bore or meets itself in it, and the
/// icosphere taken after it wrapped over the hole (genus 0, 70 K vertices). `auto` now takes the
/// isosurface start of a finer grid, which keeps the bore.
#[test]
#[ignore = "corpus tier (whole wraps): cargo test -- --ignored"]
fn a_narrow_bore_gets_a_finer_isosurface_start() {
    let bead = |p: DVec3| (p.length() - 0.8).max(0.07 - (p.x * p.x + p.y * p.y).sqrt());
    let (p, t) =
        lsw::demo::shapes::implicit_surface(bead, DVec3::splat(-1.0), DVec3::splat(1.0), 0.02);
    let target = Target::new(p, t).unwrap();
    let mut ev = Evolver::new(&target, WrapSettings::default()).unwrap();
    assert_eq!(ev.start_surface(), StartSurface::Isosurface);
    ev.run(|_| {}).unwrap();
    let c = certify(&ev.positions(), &ev.triangles(), Some(&target));
    println!("bead: {} vertices, {c:?}", ev.positions().len());
    assert_valid("bead", &c);
    assert_eq!((c.genus, c.target_genus), (Some(1), Some(1)));
}

// The faces dropped (71 of 2 192, drawn at random once): this pattern led the fit into the
// redo (most others do not).
const DROPPED: [usize; 71] = [
    49, 56, 99, 106, 130, 216, 266, 283, 306, 332, 378, 429, 513, 590, 715, 717, 742, 743, 749,
    796, 801, 809, 824, 868, 880, 889, 896, 908, 956, 963, 1007, 1008, 1092, 1162, 1181, 1215,
    1227, 1252, 1262, 1314, 1365, 1371, 1403, 1430, 1436, 1465, 1477, 1497, 1524, 1525, 1526, 1532,
    1533, 1546, 1591, 1613, 1614, 1656, 1712, 1736, 1746, 1758, 1831, 1890, 1892, 1936, 1973, 1985,
    2056, 2061, 2184,
];

/// A scan with holes: cube-hole with 3 % of its faces dropped, wrapped at the defaults. Its fit
/// redid passes whose remesh intersected, and the moves it put back in the stabilised frame
/// still met as written: 12 pairs, and the result was refused. The redo now puts them back as
/// written, and a surface the passes leave intersecting gives way to the settled one.
#[test]
#[ignore = "corpus tier (whole wraps): cargo test -- --ignored"]
fn a_mesh_with_dropped_faces_wraps_valid_at_the_defaults() {
    let (p, t) = generate("cube-hole").unwrap();
    assert_eq!(t.len(), 2192);
    let kept: Vec<[u32; 3]> = (0..t.len())
        .filter(|i| DROPPED.binary_search(i).is_err())
        .map(|i| t[i])
        .collect();
    let target = Target::new(p, kept).unwrap();
    let mut ev = Evolver::new(&target, WrapSettings::default()).unwrap();
    ev.run(|_| {}).unwrap();
    let c = certify(&ev.positions(), &ev.triangles(), Some(&target));
    println!("holey cube-hole: {} vertices, {c:?}", ev.positions().len());
    assert_valid("holey cube-hole", &c);
    assert_eq!(c.genus, Some(1));
}

/// A messy export of a closed mesh: every face with its own corners (as OBJ, PLY and glTF exports
/// split vertices along seams), every third face wound backwards, every seventh stored twice.
/// Reading mends the indices, so the target is signed and the wrap starts from its exterior
/// isosurface with the target's genus. (Before, the field was unsigned and the icosphere
/// wrapped it: ~97 K vertices in 15 s at the full defaults, against 6.7 K for the clean file.)
#[test]
#[ignore = "corpus tier (whole wraps): cargo test -- --ignored"]
fn a_mesh_with_split_flipped_and_repeated_faces_wraps_like_the_clean_one() {
    let (p, t) = generate("cube-hole").unwrap();
    let mut obj = String::new();
    let mut faces = String::new();
    let mut corner = 1;
    for (i, f) in t.iter().enumerate() {
        for &v in f {
            let q = p[v as usize];
            obj += &format!("v {} {} {}\n", q.x, q.y, q.z);
        }
        let (a, b, c) = (corner, corner + 1, corner + 2);
        corner += 3;
        let face = if i % 3 == 0 {
            format!("f {a} {c} {b}\n")
        } else {
            format!("f {a} {b} {c}\n")
        };
        faces += &face;
        if i % 7 == 0 {
            faces += &face;
        }
    }
    obj += &faces;
    let read = lsw::io::read_bytes(obj.as_bytes(), Some("messy.obj")).unwrap();
    let repairs = read.repairs.expect("the indices are mended");
    assert_eq!(repairs.merged_vertices, 3 * t.len() - p.len());
    assert_eq!(repairs.dropped_faces, t.len().div_ceil(7));
    assert!(repairs.flipped_faces > 0);
    let mut sizes = Vec::new();
    for target in [&read.target, &target("cube-hole")] {
        let (start, vertices, c) = wrap_target("messy cube-hole", target, coarse());
        assert_valid("messy cube-hole", &c);
        assert_eq!((c.genus, c.target_genus), (Some(1), Some(1)));
        assert_eq!(start, StartSurface::Isosurface);
        sizes.push(vertices as f64);
    }
    assert!(sizes[0] < 1.2 * sizes[1], "{sizes:?}");
}

/// Two boxes touching along an edge, as an STL reader welds them: four faces meet at that edge,
/// so the mesh is not manifold and had no signed field (the icosphere wrapped it: DoubleWedge.stl,
/// two wedges on one edge, took 79 K vertices and 9.4 s for a Hausdorff of 0.60 %). Reading now
/// pairs the faces around the edge and splits its vertices: two closed boxes, a signed field, the
/// isosurface start.
#[test]
#[ignore = "corpus tier (whole wraps): cargo test -- --ignored"]
fn boxes_touching_along_an_edge_wrap_from_their_isosurface() {
    // The app's box soup (two unit cubes side by side, every face with its own corners), its
    // second cube moved up by one: the cubes now touch along the edge x = y = 1.
    let (p, t) = lsw::demo::box_soup();
    let mut obj: String = (p.iter().enumerate())
        .map(|(i, q)| {
            let up = if i >= p.len() / 2 { 1.0 } else { 0.0 };
            format!("v {} {} {}\n", q.x, q.y + up, q.z)
        })
        .collect();
    for f in &t {
        obj += &format!("f {} {} {}\n", f[0] + 1, f[1] + 1, f[2] + 1);
    }
    let read = lsw::io::read_bytes(obj.as_bytes(), Some("boxes.obj")).unwrap();
    assert_eq!(read.repairs.map(|r| r.split_vertices), Some(2));
    let (start, _, c) = wrap_target("boxes on an edge", &read.target, coarse());
    assert_valid("boxes on an edge", &c);
    assert_eq!(start, StartSurface::Isosurface);
    let diagonal = read.target.bbox.diagonal();
    assert!(c.distance_max.unwrap() < 0.005 * diagonal, "{c:?}");
}

/// The same scan with holes, read from a file: reading closes its holes (each a few missing
/// faces), so the field is signed and the wrap starts from the isosurface with the target's
/// genus (from the icosphere it took 118 K vertices and 16 s at the full defaults).
#[test]
#[ignore = "corpus tier (whole wraps): cargo test -- --ignored"]
fn a_mesh_read_with_dropped_faces_has_its_holes_closed() {
    let (p, t) = generate("cube-hole").unwrap();
    let mut obj: String = p
        .iter()
        .map(|q| format!("v {} {} {}\n", q.x, q.y, q.z))
        .collect();
    for (i, f) in t.iter().enumerate() {
        if DROPPED.binary_search(&i).is_err() {
            obj += &format!("f {} {} {}\n", f[0] + 1, f[1] + 1, f[2] + 1);
        }
    }
    let read = lsw::io::read_bytes(obj.as_bytes(), Some("holey.obj")).unwrap();
    let repairs = read.repairs.expect("holes closed");
    assert!(repairs.filled_holes > 40, "{repairs:?}");
    let (start, _, c) = wrap_target("holey cube-hole, read", &read.target, coarse());
    assert_valid("holey cube-hole, read", &c);
    assert_eq!(start, StartSurface::Isosurface);
    assert_eq!(c.genus, Some(1));
}

/// A plate cloud with three round through-holes as deep as the smallest is wide (demo
/// `plate-holes`, turned so that no hole lies along an axis). The distance field is flat along a
/// hole's axis, so the membranes over its two ends never meet; the surgery's tunnel test opens
/// them (`surgery.tunnel_ratio`). Without it (`surgery.tunnel_ratio=0`) this cloud's wrap has
/// genus 1: both smaller holes stay closed.
#[test]
#[ignore = "corpus tier (whole wraps): cargo test -- --ignored"]
fn a_turned_plate_cloud_opens_its_narrow_through_holes() {
    let (p, t) = lsw::demo::sculpted::plate_holes();
    let turn = glam::DQuat::from_euler(glam::EulerRot::XYZ, 0.4, -1.0, 2.0);
    let points: Vec<glam::DVec3> = lsw::demo::sample_mesh(&p, &t, 30_000, 4)
        .unwrap()
        .into_iter()
        .map(|q| turn * q)
        .collect();
    let target = Target::new(points, vec![]).unwrap();
    let (_, _, c) = wrap_target("plate-holes cloud", &target, WrapSettings::default());
    assert_valid("plate-holes cloud", &c);
    assert_eq!(c.genus, Some(3), "{c:?}");
}

/// A single-layer sheet sampled at random (an open scan of a wavy panel: no thickness, no
/// holes). Random sampling leaves gaps of a few spacings; the wrap's two sides sag into them and
/// face each other across one, and the tunnel test, which looked at the path and at a ring round
/// its middle, paired them through the gaps: 5 handles on these 3 000 points (6, 13 and 7 on
/// other sheets of 3 000, 10 000 and 30 000). A tunnel's wall also runs along the path; a sheet's
/// gap has none.
#[test]
#[ignore = "corpus tier (whole wraps): cargo test -- --ignored"]
fn a_randomly_sampled_sheet_gets_no_handles_through_its_sampling_gaps() {
    let target = random_wavy_sheet(3000, 3009);
    let (_, _, c) = wrap_target("random sheet", &target, WrapSettings::default());
    assert_valid("random sheet", &c);
    assert_eq!(c.genus, Some(0), "{c:?}");
}

/// `n` random points on the open sheet z = 0.05 sin 5x over [−1, 1]², no thickness.
fn random_wavy_sheet(n: usize, seed: u64) -> Target {
    random_sheet(n, seed, |x, _| 0.05 * lsw::fmath::sin(5.0 * x))
}

/// `n` random points on the open sheet z = `height(x, y)` over [−1, 1]², no thickness.
fn random_sheet(n: usize, seed: u64, height: impl Fn(f64, f64) -> f64) -> Target {
    let mut rng = lsw::demo::Rng::new(seed);
    let points: Vec<glam::DVec3> = (0..n)
        .map(|_| {
            let (x, y) = (2.0 * rng.uniform() - 1.0, 2.0 * rng.uniform() - 1.0);
            glam::DVec3::new(x, y, height(x, y))
        })
        .collect();
    Target::new(points, vec![]).unwrap()
}

/// Wraps `target` at the defaults: the certificate, and the second pass if there was one.
fn wrap_with_passes(name: &str, target: &Target) -> (Certificate, Option<lsw::flow::StartedOver>) {
    let mut ev = Evolver::new(target, WrapSettings::default()).unwrap();
    ev.run(|_| {}).unwrap();
    let c = certify(&ev.positions(), &ev.triangles(), Some(target));
    println!(
        "{name}: {:?}, outside {:?}",
        ev.started_over(),
        c.target_points_outside
    );
    assert_valid(name, &c);
    (c, ev.started_over())
}

/// Wraps an open sheet of genus 0 that a first pass leaves partly outside: the second pass must
/// be the result and bring the rim in. Returns the certificate.
fn assert_rim_brought_in(name: &str, sheet: &Target) -> Certificate {
    let (c, again) = wrap_with_passes(name, sheet);
    assert_eq!(c.genus, Some(0), "{c:?}");
    assert!(!c.target_part_outside, "{c:?}");
    assert!(again.is_some_and(|s| s.kept), "{again:?}");
    c
}

/// A random sampling leaves gaps: at the d₀ of a sparse cloud (1.7 median spacings) a tenth of
/// the sheet lies farther than d₀ from every point, and round the rim the two sides of the wrap
/// slipped through those gaps to meet inside the sheet: the first pass leaves 346 of these
/// 10 000 points outside. The wrap then starts over with a d₀ that covers the gaps
/// (`flow.cover_gaps`), which keeps the rim: none outside.
#[test]
#[ignore = "corpus tier (whole wraps): cargo test -- --ignored"]
fn a_randomly_sampled_open_sheet_keeps_its_rim_inside() {
    let c = assert_rim_brought_in("random sheet rim", &random_wavy_sheet(10_000, 3011));
    let outside = c.target_points_outside.unwrap();
    assert!(outside <= 10, "{outside} of the sheet's points outside");
}

/// A denser sheet's sampling gaps are covered at the usual d₀, but full-wrap's push where the
/// normal lies across the gradient drove the coarse early wrap's edge past the rim: the first
/// pass leaves 4 965 of 20 000 checked points of this dome outside, a second pass with only d₀
/// grown 2 447, and the second pass without that push (`flow.second_pass_d2` = 0) 37.
#[test]
#[ignore = "corpus tier (whole wraps): cargo test -- --ignored"]
fn a_densely_sampled_open_dome_keeps_its_rim_inside() {
    let dome = random_sheet(100_000, 3013, |x, y| 0.25 * (1.0 - 0.5 * (x * x + y * y)));
    assert_rim_brought_in("dense dome", &dome);
}

/// A Möbius band sampled at random (10 000 points, no thickness, width 0.6 round a circle of
/// radius 1): the first pass leaves part of its rim outside, and the second pass (D₂ = 0, no
/// push into concavities) brought it in but left a web 0.18 off the data where the band turns
/// (the first pass's farthest vertex: 0.04). A third pass halfway between the two D₂ is the
/// result: the whole band inside, 0.04 off.
#[test]
#[ignore = "corpus tier (whole wraps): cargo test -- --ignored"]
fn a_twisted_band_is_wrapped_close_to_its_data() {
    let mut rng = lsw::demo::Rng::new(5);
    let points: Vec<DVec3> = (0..10_000)
        .map(|_| {
            let (u, s) = (rng.uniform(), 0.6 * (rng.uniform() - 0.5));
            let (a, b) = (std::f64::consts::TAU * u, std::f64::consts::PI * u);
            let r = 1.0 + s * lsw::fmath::cos(b);
            DVec3::new(
                r * lsw::fmath::cos(a),
                r * lsw::fmath::sin(a),
                s * lsw::fmath::sin(b),
            )
        })
        .collect();
    let band = Target::new(points, vec![]).unwrap();
    let (c, again) = wrap_with_passes("twisted band", &band);
    assert_eq!(c.genus, Some(1), "{c:?}");
    assert!(!c.target_part_outside, "{c:?}");
    assert!(c.distance_max.unwrap() < 0.08, "{c:?} {again:?}");
}

/// The same push takes the rim of a single-layer mesh, whose field has no gaps: a 120 × 120 grid
/// of the wavy sheet has 2 811 of its 14 641 vertices outside after the first pass, 31 after the
/// second (D₂ = 0).
#[test]
#[ignore = "corpus tier (whole wraps): cargo test -- --ignored"]
fn an_open_single_layer_mesh_keeps_its_rim_inside() {
    let n = 120;
    let at = |i: usize, j: usize| j * (n + 1) + i;
    let points = (0..(n + 1) * (n + 1))
        .map(|k| {
            let x = -1.0 + 2.0 * (k % (n + 1)) as f64 / n as f64;
            let y = -1.0 + 2.0 * (k / (n + 1)) as f64 / n as f64;
            glam::DVec3::new(x, y, 0.05 * lsw::fmath::sin(5.0 * x))
        })
        .collect();
    let triangles = (0..n * n)
        .flat_map(|k| {
            let (i, j) = (k % n, k / n);
            let [a, b, c, d] = [at(i, j), at(i + 1, j), at(i, j + 1), at(i + 1, j + 1)];
            [[a, b, d], [a, d, c]].map(|t| t.map(|v| v as u32))
        })
        .collect();
    let sheet = Target::new(points, triangles).unwrap();
    assert_rim_brought_in("wavy sheet mesh", &sheet);
}

/// A closed cloud whose sampling has the same gaps keeps its first pass: its wrap only sags into
/// them, nothing is left outside, and nothing starts over.
#[test]
#[ignore = "corpus tier (whole wraps): cargo test -- --ignored"]
fn a_randomly_sampled_closed_cloud_is_wrapped_once() {
    let sphere = Target::new(lsw::demo::noisy_sphere_cloud(3000, 0.0, 3011), vec![]).unwrap();
    let (c, again) = wrap_with_passes("random sphere", &sphere);
    assert_eq!(c.target_points_outside, Some(0), "{c:?}");
    assert_eq!(again, None);
}

/// The same plate cloud with noise (σ = 0.2 % of the diagonal), which eats into the smallest
/// hole (radius 0.03, 5 % of the diagonal). Turned, its axis-aligned box is about ten times as
/// thick as the plate; a grid sized by that box (the method's) had cells 2.1× those of the plate
/// lying flat (3.5× at the genus sweep's 30 000 points), the smallest hole fell under the
/// surgery's resolution and stayed closed (genus 2). The grid now follows the plate's principal
/// box.
#[test]
#[ignore = "corpus tier (whole wraps): cargo test -- --ignored"]
fn a_turned_noisy_plate_cloud_gets_the_grid_of_a_flat_one() {
    let (p, t) = lsw::demo::sculpted::plate_holes();
    let flat = lsw::demo::sample_mesh(&p, &t, 30_000, 5).unwrap();
    let diagonal = 0.002
        * lsw::geometry::aabb::Aabb::from_points(&flat)
            .size()
            .length();
    let mut rng = lsw::demo::Rng::new(11);
    let flat: Vec<glam::DVec3> = flat
        .into_iter()
        .map(|q| q + diagonal * glam::DVec3::new(rng.normal(), rng.normal(), rng.normal()))
        .collect();
    let turn = glam::DQuat::from_euler(glam::EulerRot::XYZ, 1.1, 0.7, -0.5);
    let turned: Vec<glam::DVec3> = flat.iter().map(|&q| turn * q).collect();
    let settings = WrapSettings::default();
    let cell = |points: &[glam::DVec3]| {
        let target = Target::new(points.to_vec(), vec![]).unwrap();
        lsw::field::DistanceField::planned_cell_size(&target, &settings.field_options()).unwrap()
    };
    let ratio = cell(&turned) / cell(&flat);
    // (A cloud's cells are also no finer than two point spacings: both may sit at that floor.)
    assert!(
        (0.8..=lsw::field::grid::TURNED_SLACK + 1e-9).contains(&ratio),
        "{ratio}"
    );
    let target = Target::new(turned, vec![]).unwrap();
    let (_, _, c) = wrap_target("noisy turned plate-holes cloud", &target, settings);
    assert_valid("noisy turned plate-holes cloud", &c);
    assert_eq!(c.genus, Some(3), "{c:?}");
}

/// The demo creature turned (a closed mesh of genus 0): on the grid its principal box gives it,
/// the offset of the fine isosurface start joins two of its parts lying close and starts with a
/// handle (genus 1), and a Lagrangian surface keeps its start's genus. `auto` refuses an
/// isosurface start whose topology differs from a closed mesh's; it took the icosphere, and now
/// takes the isosurface start of a finer grid, whose offset keeps the parts apart.
#[test]
#[ignore = "corpus tier (whole wraps): cargo test -- --ignored"]
fn a_closed_mesh_is_not_started_with_a_handle_it_lacks() {
    let (p, t) = lsw::demo::sculpted::creature();
    let turn = glam::DQuat::from_xyzw(0.675_56, -0.503_35, 0.536_32, 0.051_18).normalize();
    let p: Vec<glam::DVec3> = p.into_iter().map(|q| turn * q).collect();
    let target = Target::new(p, t).unwrap();
    let mut explicit = WrapSettings::default();
    explicit.start.surface = StartSurface::Isosurface;
    explicit.remesh.min_edge_multiplier = lsw::flow::settings::AUTO_ISOSURFACE_MIN_EDGE;
    let fine = Evolver::new(&target, explicit).unwrap();
    let genus = fine.mesh().validate().unwrap().genus;
    assert_eq!(
        genus, 1,
        "the fine start has no extra handle: the test shows nothing"
    );
    let (start, _, c) = wrap_target("turned creature", &target, WrapSettings::default());
    assert_eq!(start, StartSurface::Isosurface);
    assert_valid("turned creature", &c);
    assert_eq!(c.genus, Some(0), "{c:?}");
}

/// The demo figure (a closed mesh of genus 0 whose knees and hands come 1 % of the diagonal
/// close): the default start joins them (genus 2), the 1.5× grid's too, and the 2× grid is over
/// the field's memory cap; the icosphere taken instead ended genus 2. The finest grid the cap
/// allows keeps them apart.
#[test]
#[ignore = "corpus tier (whole wraps): cargo test -- --ignored"]
fn a_figure_whose_knees_nearly_touch_keeps_genus_zero() {
    let (p, t) = lsw::demo::sculpted::figure();
    let target = Target::new(p, t).unwrap();
    let (start, _, c) = wrap_target("figure", &target, WrapSettings::default());
    assert_eq!(start, StartSurface::Isosurface);
    assert_valid("figure", &c);
    assert_eq!((c.genus, c.target_genus), (Some(0), Some(0)), "{c:?}");
}

/// Two spheres set apart, as a cloud, turned (two orientations that failed): one icosphere
/// around both left a neck between them whose pinch never passed (its caps crossed the
/// stumps), and the wrap stayed one part, 0.48 from the data, with under 700 vertices. Each
/// part lying apart now gets its own sphere.
#[test]
#[ignore = "corpus tier (whole wraps): cargo test -- --ignored"]
fn two_spheres_apart_turned_wrap_as_two_parts() {
    let (p, _) = generate("two-spheres-apart-cloud").unwrap();
    // (w, x, y, z) of the turns.
    for [w, x, y, z] in [
        [-0.370_33, 0.740_18, -0.327_22, -0.455_99],
        [0.124_5, 0.844_54, 0.365_19, 0.371_35],
    ] {
        let turn = glam::DQuat::from_xyzw(x, y, z, w).normalize();
        let points: Vec<glam::DVec3> = p.iter().map(|&q| turn * q).collect();
        let target = Target::new(points, vec![]).unwrap();
        let (_, _, c) = wrap_target(
            "two spheres apart, turned",
            &target,
            WrapSettings::default(),
        );
        assert_valid("two spheres apart, turned", &c);
        assert_eq!((c.genus, c.components), (Some(0), Some(2)), "{c:?}");
        assert!(c.distance_max.unwrap() < 0.05, "{c:?}");
    }
}

/// A sphere sampled only along 11 circles (decision 0029): its spacing is read as the circles'
/// distance apart, not as the distance between points along one, so the settled surface spans
/// the gaps; the fit moves along the data's fitted normals, so it lands on the sphere without
/// folding where the settled surface dimples between the circles. (Read at the points' spacing
/// and fitted along the wrap's normals, 3.6 % of its edges folded and most of it stayed 0.15
/// off the sphere.)
#[test]
#[ignore = "corpus tier (whole wraps): cargo test -- --ignored"]
fn a_curve_sampled_sphere_wraps_onto_the_sphere() {
    let (p, _) = generate("sphere-curves").unwrap();
    let target = Target::new(p, vec![]).unwrap();
    let mut ev = Evolver::new(&target, WrapSettings::default()).unwrap();
    ev.run(|_| {}).unwrap();
    let c = certify(&ev.positions(), &ev.triangles(), Some(&target));
    assert_valid("sphere-curves", &c);
    assert_eq!(c.genus, Some(0));
    let folds = c.faithfulness.as_ref().map(|f| f.fold_share);
    assert!(folds.is_some_and(|f| f < 0.001), "fold share {folds:?}");
    let mut off: Vec<f64> = ev
        .positions()
        .iter()
        .map(|p| (p.length() - 1.0).abs())
        .collect();
    off.sort_by(f64::total_cmp);
    let p99 = off[off.len() * 99 / 100];
    assert!(
        p99 < 0.01,
        "99 % of the vertices within {p99} of the sphere"
    );
}

/// After a roll-back the contact guard checks each step until a stretch of them makes no
/// contact (`tuning.guard.guarded_until_clear`): a genus-4 cloud whose membranes keep pressing
/// together rolls back once instead of each time the checks are spaced out again, and since a
/// checked step computes what its redo would, the mesh is the same.
#[test]
#[ignore = "corpus tier (whole wraps): cargo test -- --ignored"]
fn staying_guarded_changes_the_work_not_the_mesh() {
    let t = target("torus-g4-cloud");
    let run = |until_clear: bool| {
        let mut settings = WrapSettings::default();
        settings.tuning.guard.guarded_until_clear = until_clear;
        let mut ev = Evolver::new(&t, settings).unwrap();
        let mut redos = 0;
        ev.run(|r| redos += usize::from(r.times.redone > 0.0))
            .unwrap();
        (ev.positions(), ev.triangles(), redos)
    };
    let (p0, t0, spaced) = run(false);
    let (p1, t1, guarded) = run(true);
    println!("roll-backs: {spaced} spaced out again, {guarded} guarded until clear");
    assert!(spaced >= 2, "the case no longer rolls back twice: {spaced}");
    assert!(guarded < spaced, "{guarded} vs {spaced}");
    assert!(p0 == p1 && t0 == t1, "the meshes differ");
}
