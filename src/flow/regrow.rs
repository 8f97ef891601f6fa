//! Regrowing a wrap that cuts through a thin part of the target.
//!
//! Early in the evolution the wrap's edges are longer than a thin plate is thick. Where its two
//! sheets settle onto the plate's faces, the triangles that turn around the plate's rim join a
//! vertex on one face to a vertex on the other, a chord through the plate a whole edge short of
//! the rim, and more at a corner. Later splits put new vertices on that chord, inside the
//! offset surface (δ = d − d₀ < 0), where the flow holds them still: the rim stays cut for the
//! rest of the run, and a thin plate loses its corners.
//!
//! Such a vertex is told apart from one that merely settled a little inside d₀ by looking along
//! its outward normal: on a chord the offset level lies beyond the rim, farther than d₀ away;
//! for a settled vertex it lies within a fraction of d₀. The chord's vertices move out to that
//! level, a little each step, and the remesh splits the edges they stretch; the new vertices
//! move out in turn until the wrap goes round the rim again.

use glam::DVec3;

/// How a vertex inside the offset surface finds its way out (see the module doc). Lengths are
/// in the evolution's (stabilised) frame.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Regrow {
    /// The offset level d₀.
    pub d0: f64,
    /// The offset level must lie farther than this along the normal (a vertex that settled
    /// just inside d₀ finds it within a fraction of d₀).
    pub min_depth: f64,
    /// How far along the normal to look for it.
    pub reach: f64,
    /// Spacing of the samples along the normal (half a grid cell: the field is trilinear).
    pub spacing: f64,
}

/// The distance along the unit normal `n` from `p` (where the distance is `at_p`, already
/// sampled by the step) to where `distance` first reaches the offset level, when `p` lies inside
/// it and that level is farther than `min_depth` and within `reach`; None otherwise. The
/// crossing is interpolated between the two samples that bracket it.
pub fn outward_to_offset(
    distance: impl Fn(DVec3) -> f64,
    p: DVec3,
    at_p: f64,
    n: DVec3,
    r: &Regrow,
) -> Option<f64> {
    let mut prev = at_p;
    // (Written so that a NaN answers no.)
    let inside = prev < r.d0;
    let stepped = r.spacing > 0.0;
    if !inside || !stepped {
        return None;
    }
    let steps = (r.reach / r.spacing).ceil() as usize;
    // Deep inside a solid that a cloud encloses the field is negative, and it rises to +2 cells
    // at the near band's inner edge (`tuning.field.enclosed_cells`): that rise is no crossing of d₀.
    // From there the way out goes down through the band to the surface and up past d₀ beyond.
    let mut through_band = at_p < 0.0;
    let mut below = !through_band;
    for k in 1..=steps {
        let d = distance(p + (k as f64 * r.spacing) * n);
        // Deeper at the first sample: the normal points further into the solid. Marching on
        // to the solid's far side would move a fold of the wrap that got in deeper each step,
        // and its new vertices after it (see the tests).
        if k == 1 && through_band && d < at_p {
            return None;
        }
        if through_band {
            through_band = d < r.d0;
        } else if below && d >= r.d0 {
            let t = (r.d0 - prev) / (d - prev);
            let along = (k as f64 - 1.0 + t) * r.spacing;
            return (along > r.min_depth && along <= r.reach).then_some(along);
        } else {
            below = d < r.d0;
        }
        prev = d;
    }
    None
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Distance to the plate |x| ≤ 0.5, |y| ≤ 0.3, |z| ≤ 0.005.
    fn plate(p: DVec3) -> f64 {
        let h = DVec3::new(0.5, 0.3, 0.005);
        (p.abs() - h).max(DVec3::ZERO).length()
    }

    fn settings() -> Regrow {
        Regrow {
            d0: 0.006,
            min_depth: 0.009,
            reach: 0.12,
            spacing: 0.004,
        }
    }

    #[test]
    fn a_vertex_on_a_chord_through_the_plate_finds_the_level_beyond_its_rim() {
        let r = settings();
        let along =
            outward_to_offset(plate, DVec3::new(0.44, 0.0, 0.0), 0.0, DVec3::X, &r).unwrap();
        // The rim is 0.06 away and the level d₀ beyond it; the field here is exact, so only
        // the interpolation's bracket (one spacing) limits the answer.
        assert!((along - 0.066).abs() < 1e-9, "{along}");
        // Diagonally, towards a corner cut off by the chord from (0.44, 0.3) to (0.5, 0.24).
        let n = DVec3::new(1.0, 1.0, 0.0).normalize();
        let along = outward_to_offset(plate, DVec3::new(0.47, 0.27, 0.0), 0.0, n, &r);
        let want = DVec3::new(0.03, 0.03, 0.0).length() + 0.006;
        assert!(
            (along.unwrap() - want).abs() < 0.004,
            "{along:?} against {want}"
        );
    }

    #[test]
    fn a_vertex_settled_just_inside_the_level_stays() {
        let r = settings();
        let p = DVec3::new(0.1, 0.1, 0.005 + 0.9 * r.d0);
        assert_eq!(outward_to_offset(plate, p, plate(p), DVec3::Z, &r), None);
        // Outside the level, nothing to do either.
        let p = DVec3::new(0.1, 0.1, 0.005 + 1.5 * r.d0);
        assert_eq!(outward_to_offset(plate, p, plate(p), DVec3::Z, &r), None);
    }

    /// A slab |z| ≤ 0.05 sampled as a cloud: unsigned, but negative deeper than 0.02 inside.
    fn slab(p: DVec3) -> f64 {
        let d = (p.z.abs() - 0.05).abs();
        if p.z.abs() < 0.03 {
            -d
        } else {
            d
        }
    }

    #[test]
    fn a_vertex_deep_inside_an_enclosed_solid_goes_out_past_its_surface() {
        let r = Regrow {
            reach: 0.2,
            ..settings()
        };
        let p = DVec3::new(0.0, 0.0, 0.0);
        let along = outward_to_offset(slab, p, slab(p), DVec3::Z, &r).unwrap();
        assert!((along - (0.05 + r.d0)).abs() < r.spacing, "{along}");
    }

    #[test]
    fn a_vertex_in_an_enclosed_solid_goes_out_the_near_way_or_not_at_all() {
        // A fold of the wrap that got into a solid has normals that point further in; marching
        // on through the solid to its far side would grow the fold each step, and the vertex
        // count with it.
        let r = Regrow {
            reach: 0.2,
            ..settings()
        };
        let p = DVec3::new(0.0, 0.0, -0.01);
        assert_eq!(outward_to_offset(slab, p, slab(p), DVec3::Z, &r), None);
        let along = outward_to_offset(slab, p, slab(p), -DVec3::Z, &r).unwrap();
        assert!((along - (0.04 + r.d0)).abs() < r.spacing, "{along}");
    }

    #[test]
    fn a_rim_beyond_the_reach_is_left_alone() {
        let r = settings();
        // 0.3 from the rim, along the plate: the level lies beyond the reach of 0.12.
        let p = DVec3::new(0.2, 0.0, 0.0);
        assert_eq!(outward_to_offset(plate, p, 0.0, DVec3::X, &r), None);
        let reach = Regrow { reach: 0.4, ..r };
        let along = outward_to_offset(plate, p, 0.0, DVec3::X, &reach).unwrap();
        assert!((along - 0.306).abs() < 1e-9, "{along}");
    }
}
