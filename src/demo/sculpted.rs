//! Sculpted stand-ins for the organic meshes users drop (a creature, a cartoon fish): smooth
//! bodies with what a default wrap tends to round off — thin fins meeting the body in concave
//! creases, fin tips, eye sockets, ears, legs and a thin tail. Each is an implicit surface
//! (smooth unions and subtractions of simple distance functions) extracted by marching cubes, so
//! it is closed, genus 0 and deterministic. The wrap has never been tuned on them.

use super::implicit::{implicit_surface, smooth_min, Shape};
use super::{capsule, ellipsoid};
use glam::{DVec2, DVec3};

/// Signed distance in the plane to the triangle `t` (negative inside).
fn triangle_2d(p: DVec2, t: [DVec2; 3]) -> f64 {
    let mut d = f64::INFINITY;
    let mut inside = true;
    for i in 0..3 {
        let (a, b) = (t[i], t[(i + 1) % 3]);
        let e = b - a;
        let s = ((p - a).dot(e) / e.length_squared()).clamp(0.0, 1.0);
        d = d.min((p - (a + s * e)).length());
        inside &= e.perp_dot(p - a) >= 0.0;
    }
    if inside {
        -d
    } else {
        d
    }
}

/// A fin: the triangle `t` in the x–z plane, `half` thick in y (a slab with sharp rims).
fn fin(p: DVec3, t: [DVec2; 3], half: f64) -> f64 {
    let d = triangle_2d(DVec2::new(p.x, p.z), t);
    let w = p.y.abs() - half;
    if d > 0.0 && w > 0.0 {
        crate::fmath::hypot(d, w)
    } else {
        d.max(w)
    }
}

/// A cartoon fish (1.5 × 0.35 × 0.7): an ellipsoid body, a forked-looking tail fin and a dorsal
/// fin 0.024 thick blended into the body with a small smooth
/// minimum (concave creases), and two eye sockets cut into the head.
pub fn fish() -> Shape {
    let v = DVec2::new;
    // Counter-clockwise triangles in the (x, z) plane.
    let tail = [v(-0.42, 0.0), v(-0.75, -0.26), v(-0.68, 0.27)];
    let dorsal = [v(-0.2, 0.12), v(0.18, 0.14), v(-0.12, 0.35)];
    let sdf =
        |p: DVec3| {
            let body = ellipsoid(p, DVec3::ZERO, DVec3::new(0.5, 0.16, 0.22));
            let fins = fin(p, tail, 0.012).min(fin(p, dorsal, 0.012));
            let eyes = ellipsoid(p, DVec3::new(0.34, 0.15, 0.06), DVec3::splat(0.045)).min(
                ellipsoid(p, DVec3::new(0.34, -0.15, 0.06), DVec3::splat(0.045)),
            );
            smooth_min(body, fins, 0.03).max(-eyes)
        };
    let cell = 0.008;
    let lo = DVec3::new(-0.8, -0.2, -0.3) - 2.0 * cell;
    let hi = DVec3::new(0.55, 0.2, 0.4) + 2.0 * cell;
    implicit_surface(sdf, lo, hi, cell)
}

/// A creature (1.2 × 0.5 × 0.95): a body with four legs, a head with two thin ears and eye
/// sockets, and a thin curled tail, blended with a smooth minimum.
pub fn creature() -> Shape {
    let sdf = |p: DVec3| {
        let mut d = ellipsoid(p, DVec3::ZERO, DVec3::new(0.42, 0.22, 0.2));
        for (x, y) in [(0.25, 0.12), (0.25, -0.12), (-0.25, 0.12), (-0.25, -0.12)] {
            let leg = capsule(p, DVec3::new(x, y, -0.05), DVec3::new(x, y, -0.42), 0.055);
            d = smooth_min(d, leg, 0.05);
        }
        let head = ellipsoid(p, DVec3::new(0.52, 0.0, 0.2), DVec3::new(0.17, 0.15, 0.14));
        d = smooth_min(d, head, 0.08);
        for y in [0.09, -0.09] {
            let ear = ellipsoid(p, DVec3::new(0.5, y, 0.38), DVec3::new(0.025, 0.06, 0.1));
            d = smooth_min(d, ear, 0.02);
        }
        let tail = capsule(
            p,
            DVec3::new(-0.4, 0.0, 0.05),
            DVec3::new(-0.58, 0.0, 0.3),
            0.022,
        );
        d = smooth_min(d, tail, 0.03);
        for y in [0.07, -0.07] {
            let eye = ellipsoid(p, DVec3::new(0.66, y, 0.24), DVec3::splat(0.035));
            d = d.max(-eye);
        }
        d
    };
    let cell = 0.008;
    let lo = DVec3::new(-0.62, -0.25, -0.5) - 2.0 * cell;
    let hi = DVec3::new(0.7, 0.25, 0.5) + 2.0 * cell;
    implicit_surface(sdf, lo, hi, cell)
}

/// A sculpted bust (0.9 × 0.6 × 1.0): a head on a neck and shoulders, with a nose, deep eye
/// sockets, a mouth slit 0.012 wide and 0.05 deep between the lips, and ears as thin cupped
/// shells (a bowl cut into a flattened ellipsoid): narrow concavities a wrap tends to bridge.
pub fn bust() -> Shape {
    let sdf = |p: DVec3| {
        let head = ellipsoid(p, DVec3::new(0.0, 0.0, 0.2), DVec3::new(0.24, 0.28, 0.3));
        let neck = capsule(
            p,
            DVec3::new(0.0, -0.03, 0.0),
            DVec3::new(0.0, 0.0, -0.25),
            0.12,
        );
        let shoulders = ellipsoid(p, DVec3::new(0.0, 0.0, -0.36), DVec3::new(0.45, 0.2, 0.13));
        let mut d = smooth_min(smooth_min(head, neck, 0.06), shoulders, 0.08);
        let nose = capsule(
            p,
            DVec3::new(0.0, -0.27, 0.24),
            DVec3::new(0.0, -0.31, 0.16),
            0.035,
        );
        d = smooth_min(d, nose, 0.04);
        let lips = ellipsoid(
            p,
            DVec3::new(0.0, -0.25, 0.06),
            DVec3::new(0.08, 0.045, 0.035),
        );
        d = smooth_min(d, lips, 0.03);
        // The mouth: a thin slab cut between the lips, 0.05 deep from the front.
        let q = p - DVec3::new(0.0, -0.28, 0.06);
        let mouth = (q.x.abs() - 0.07)
            .max(q.z.abs() - 0.006)
            .max(q.y.abs() - 0.05);
        d = d.max(-mouth);
        for x in [0.09, -0.09] {
            let eye = ellipsoid(p, DVec3::new(x, -0.25, 0.28), DVec3::new(0.05, 0.05, 0.035));
            d = d.max(-eye);
            // An ear: a flattened ellipsoid with a bowl cut into its outer face.
            let sx = x.signum();
            let ear = ellipsoid(
                p,
                DVec3::new(sx * 0.24, 0.02, 0.2),
                DVec3::new(0.03, 0.06, 0.1),
            );
            let bowl = ellipsoid(
                p,
                DVec3::new(sx * 0.27, 0.02, 0.21),
                DVec3::new(0.03, 0.04, 0.075),
            );
            d = smooth_min(d, ear.max(-bowl), 0.02);
        }
        d
    };
    let cell = 0.007;
    let lo = DVec3::new(-0.47, -0.36, -0.5) - 2.0 * cell;
    let hi = DVec3::new(0.47, 0.3, 0.52) + 2.0 * cell;
    implicit_surface(sdf, lo, hi, cell)
}

/// A flat mechanical plate (1 × 0.6 × 0.06, 17:1) with three round through-holes of radii 0.1,
/// 0.05 and 0.03: genus 3, sharp rims. Its grid is set by the longest side (see
/// `field::grid::MIN_REFERENCE_RATIO`), so the smallest hole is the one a coarser grid would
/// close first.
pub fn plate_holes() -> Shape {
    let holes = [(-0.25, 0.0, 0.1), (0.1, 0.1, 0.05), (0.3, -0.12, 0.03)];
    let sdf = |p: DVec3| {
        let q = p.abs() - DVec3::new(0.5, 0.3, 0.03);
        let plate = q.max(DVec3::ZERO).length() + q.max_element().min(0.0);
        holes.iter().fold(plate, |d, &(x, y, r)| {
            d.max(r - DVec2::new(p.x - x, p.y - y).length())
        })
    };
    let cell = 0.006;
    let ext = DVec3::new(0.5, 0.3, 0.03) + 2.0 * cell;
    implicit_surface(sdf, -ext, ext, cell)
}

/// A cartoon figure (genus 0) whose parts nearly touch in one place each, knock knees and hands
/// beside the thighs: an offset of a few cells closes a loop there that the surface lacks.
pub fn figure() -> Shape {
    let gap = 0.016;
    let sdf = |p: DVec3| {
        let body = ellipsoid(p, DVec3::new(0.0, 0.0, 0.15), DVec3::new(0.14, 0.17, 0.32));
        let head = ellipsoid(p, DVec3::new(0.0, 0.0, 0.62), DVec3::splat(0.14));
        let mut d = smooth_min(body, head, 0.06);
        let (leg_r, arm_r) = (0.06, 0.04);
        // Hard unions where parts face each other, so the blend does not narrow the gaps.
        let (mut legs, mut forearms) = (f64::INFINITY, f64::INFINITY);
        for s in [1.0, -1.0] {
            let (hip, foot) = (
                DVec3::new(0.0, s * 0.12, -0.1),
                DVec3::new(0.0, s * 0.14, -0.8),
            );
            let knee = DVec3::new(0.0, s * (leg_r + 0.5 * gap), -0.45);
            legs = legs.min(capsule(p, hip, knee, leg_r).min(capsule(p, knee, foot, leg_r)));
            let shoulder = DVec3::new(0.0, s * 0.16, 0.35);
            let elbow = DVec3::new(0.0, s * 0.32, 0.1);
            d = smooth_min(d, capsule(p, shoulder, elbow, arm_r), 0.02);
            // The hand reaches down beside the thigh, `gap` from it.
            let hand = DVec3::new(0.0, s * (0.18 + gap + arm_r), -0.15);
            forearms = forearms.min(capsule(p, elbow, hand, arm_r));
        }
        d = smooth_min(d, legs, 0.03).min(forearms);
        d
    };
    let cell = 0.008;
    let lo = DVec3::new(-0.16, -0.36, -0.88) - 2.0 * cell;
    let hi = DVec3::new(0.16, 0.36, 0.78) + 2.0 * cell;
    implicit_surface(sdf, lo, hi, cell)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::HalfedgeMesh;

    #[test]
    fn sculpted_shapes_are_closed_genus_zero_with_thin_parts() {
        let shapes = [
            ("fish", fish()),
            ("creature", creature()),
            ("bust", bust()),
            ("figure", figure()),
        ];
        for (name, (p, t)) in shapes {
            let n = t.len();
            let rep = HalfedgeMesh::from_triangles(p.clone(), &t)
                .unwrap()
                .validate()
                .unwrap();
            assert_eq!((rep.genus, rep.components), (0, 1), "{name}");
            assert!((20_000..=400_000).contains(&n), "{name}: {n} triangles");
            // The thin part is there: the fish's fins are 0.024 thick, the creature's tail
            // 0.044 across; both stay within a few cells of their plane or axis.
            let thin = match name {
                "bust" => true,
                // The knees stay apart: no vertex between them.
                "figure" => p
                    .iter()
                    .all(|q| (q.z + 0.45).abs() > 0.02 || q.y.abs() > 0.006),
                "fish" => p.iter().filter(|q| q.x < -0.6).all(|q| q.y.abs() < 0.02),
                _ => p
                    .iter()
                    .filter(|q| q.x < -0.5 && q.z > 0.2)
                    .all(|q| q.y.abs() < 0.03),
            };
            assert!(thin, "{name}");
        }
    }
}
