//! Detail on sculpted closed meshes (issue 15): generated stand-ins for the organic meshes
//! users drop (a creature with legs, thin ears, a thin tail and eye sockets; a fish with thin
//! fins) wrap at the defaults to valid genus-0 surfaces within the bar — Hausdorff
//! ≤ 1 % of the diagonal, mean distance ≤ 0.15 % both ways, ≤ 80 K vertices. The fit's
//! error-adaptive sizing is what brings a bust's eye sockets and mouth in: with it off
//! (`fit.refine_error_cells` = 0) the 95th percentile of the target's distances to the wrap is
//! about 1.5 times as large. Reaching into what the fit still bridges (`fit.reach`) lines the bust's
//! mouth, a slit narrower than a grid cell, and the bust meets the bar too. (From its f32 PLY,
//! its OBJ or turned six ways its Hausdorff distance is 0.57–0.85 %; see benches/RESULTS.md.)
//! Shapes of known curvature — a sphere with a bump, a torus with a thin tube — meet it too.

use glam::DVec3;
use lsw::demo::shapes::{generate, implicit_surface};
use lsw::flow::{Evolver, WrapSettings};
use lsw::geometry::spatial::bvh::TriangleBvh;
use lsw::metrics::certificate::certify;
use lsw::metrics::distance::{distances_to_triangles, two_sided_distances};
use lsw::target::Target;

/// Wraps shape `name` with `settings`; checks the result is valid and of genus 0, and returns
/// the target's points, the target and the wrap (positions, triangles).
fn wrapped(name: &str, settings: WrapSettings) -> (Vec<DVec3>, Target, Vec<DVec3>, Vec<[u32; 3]>) {
    wrapped_shape(name, generate(name).unwrap(), 0, settings)
}

/// [`wrapped`] for a given shape, of genus `genus`.
fn wrapped_shape(
    name: &str,
    (p, t): (Vec<DVec3>, Vec<[u32; 3]>),
    genus: i64,
    settings: WrapSettings,
) -> (Vec<DVec3>, Target, Vec<DVec3>, Vec<[u32; 3]>) {
    let target = Target::new(p.clone(), t).unwrap();
    let mut ev = Evolver::new(&target, settings).unwrap();
    ev.run(|_| {}).unwrap();
    let (pos, tris) = (ev.positions(), ev.triangles());
    let c = certify(&pos, &tris, Some(&target));
    assert!(c.valid && c.self_intersections == 0, "{name}: {c:?}");
    assert_eq!(c.genus, Some(genus), "{name}");
    (p, target, pos, tris)
}

/// Wraps shape `name` (defaults, error-adaptive sizing at `refine` cells) and returns
/// (vertices, Hausdorff %, mean wrap → target %, mean target → wrap %, p95 target → wrap %).
fn wrap(name: &str, refine: f64) -> (usize, f64, f64, f64, f64) {
    let mut settings = WrapSettings::default();
    settings.tuning.fit.refine_error_cells = refine;
    measured(name, wrapped(name, settings), refine)
}

/// (vertices, Hausdorff %, mean wrap → target %, mean target → wrap %, p95 target → wrap %) of
/// a wrap from [`wrapped`].
fn measured(
    name: &str,
    (p, target, pos, tris): (Vec<DVec3>, Target, Vec<DVec3>, Vec<[u32; 3]>),
    refine: f64,
) -> (usize, f64, f64, f64, f64) {
    let diag = target.bbox.diagonal();
    let d = two_sided_distances(&pos, &tris, &p, &target.triangles);
    let pc = |x: f64| 100.0 * x / diag;
    let out = (
        pos.len(),
        pc(d.hausdorff),
        pc(d.mesh_to_target.mean),
        pc(d.target_to_mesh.mean),
        pc(d.target_to_mesh.p95),
    );
    println!("{name} (refine {refine} cells): {out:?}");
    out
}

#[test]
#[ignore = "corpus tier (whole wraps): cargo test -- --ignored"]
fn sculpted_shapes_meet_the_detail_bar() {
    let refine = WrapSettings::default().tuning.fit.refine_error_cells;
    for name in ["creature", "fish", "bust"] {
        let (n, h, m1, m2, _) = wrap(name, refine);
        assert!(n <= 80_000, "{name}: {n} vertices");
        assert!(h <= 1.0, "{name}: Hausdorff {h} %");
        assert!(m1 <= 0.15 && m2 <= 0.15, "{name}: means {m1} / {m2} %");
    }
}

/// Shapes of known curvature, as marching-cubes meshes of their implicit functions: a unit
/// sphere with a bump (a Gaussian 0.1 high and 0.15 rad wide, whose crest bends about nine
/// times as sharply as the sphere) and a torus with a thin tube (radii 0.5 and 0.1, tilted by
/// 45° so its grid is not set by its thickness alone), each meeting the bar with its genus.
#[test]
#[ignore = "corpus tier (whole wraps): cargo test -- --ignored"]
fn shapes_of_known_curvature_meet_the_detail_bar() {
    let bump = |p: DVec3| {
        let r = p.length();
        let off = (p / r.max(1e-12) - DVec3::Z).length_squared();
        r - 1.0 - 0.1 * lsw::fmath::exp(-off / (0.15 * 0.15))
    };
    let (s, c) = (
        std::f64::consts::FRAC_1_SQRT_2,
        std::f64::consts::FRAC_1_SQRT_2,
    );
    let tube = move |p: DVec3| {
        // Turned back by 45° about x into the torus's own frame (axis z).
        let q = DVec3::new(p.x, c * p.y + s * p.z, -s * p.y + c * p.z);
        let ring = DVec3::new(q.x, q.y, 0.0).length() - 0.5;
        (ring * ring + q.z * q.z).sqrt() - 0.1
    };
    let shapes = [
        (
            "sphere with a bump",
            implicit_surface(bump, DVec3::splat(-1.2), DVec3::splat(1.2), 0.02),
            0,
        ),
        (
            "torus with a thin tube",
            implicit_surface(tube, DVec3::splat(-0.7), DVec3::splat(0.7), 0.01),
            1,
        ),
    ];
    for (name, shape, genus) in shapes {
        let settings = WrapSettings::default();
        let refine = settings.tuning.fit.refine_error_cells;
        let (n, h, m1, m2, _) = measured(name, wrapped_shape(name, shape, genus, settings), refine);
        assert!(n <= 80_000, "{name}: {n} vertices");
        assert!(h <= 1.0, "{name}: Hausdorff {h} %");
        assert!(m1 <= 0.15 && m2 <= 0.15, "{name}: means {m1} / {m2} %");
    }
}

#[test]
fn error_adaptive_sizing_reaches_into_the_eye_sockets() {
    let (n1, h1, _, _, with) = wrap(
        "bust",
        WrapSettings::default().tuning.fit.refine_error_cells,
    );
    let (n0, h0, _, _, without) = wrap("bust", 0.0);
    // (0.6 until the fit's last round of moves without a remesh, which also brings the
    // unrefined wrap closer: p95 0.056 against 0.082 % now.)
    assert!(
        with < 0.75 * without,
        "p95 {with} % with against {without} % without"
    );
    assert!(h1 < h0, "Hausdorff {h1} % with against {h0} % without");
    assert!(n1 > n0, "{n1} vertices with against {n0} without");
}

/// The bust's mouth (a slit 0.012 wide and 0.05 deep, under a grid cell of ~0.016): the
/// farthest target vertex in it from the wrap, in % of the diagonal, with `fit.reach` on or off.
fn mouth_miss(reach: bool) -> f64 {
    let mut settings = WrapSettings::default();
    settings.tuning.fit.reach = reach;
    let (p, target, pos, tris) = wrapped("bust", settings);
    let mouth: Vec<_> = p
        .iter()
        .copied()
        .filter(|q| q.x.abs() < 0.08 && (-0.3..-0.22).contains(&q.y) && (0.03..0.09).contains(&q.z))
        .collect();
    assert!(
        mouth.len() > 100,
        "{} target vertices in the mouth",
        mouth.len()
    );
    let d = distances_to_triangles(&mouth, &TriangleBvh::new(&pos, &tris));
    let worst = d.iter().fold(0.0f64, |a, &b| a.max(b));
    100.0 * worst / target.bbox.diagonal()
}

#[test]
fn reaching_lines_a_slit_narrower_than_a_cell() {
    let (with, without) = (mouth_miss(true), mouth_miss(false));
    println!("mouth: farthest target vertex {with} % with reach, {without} % without");
    // Measured: 0.59 % with, 3.05 % without (the CLI, from the f32 PLY: 0.79 and 3.05 %). A
    // vertex whose way to the slit's far corners runs through the lips gives way to one two
    // rings out whose way is clear.
    assert!(
        with < 0.5 * without,
        "{with} % with against {without} % without"
    );
    assert!(with < 1.2, "{with} %");
}
