//! The test-shape suite: deterministic, roughly unit-sized shapes that each probe one promise or
//! one failure mode of the wrap (genus 1–5, the point-spacing limit, open cuts, sharp edges, near
//! contact, thin walls, self-intersecting and degenerate inputs). The CLI (`lsw demo`), the tests,
//! the benchmark suite (`benches/suite.sh`) and the app share the one list [`SHAPES`].
//!
//! Every shape is `(points, triangles)`; empty triangles mean a point cloud (no normals). Smooth
//! closed shapes are implicit surfaces extracted by [`marching_cubes`]; shapes with sharp edges or
//! exact boundaries are built polyhedrally. All randomness is seeded, so every call returns the
//! same bits.

use super::{capsule, sample_mesh, torus_sdf, DemoError, Rng};
use crate::geometry::icosphere::unit_icosphere;
use glam::DVec3;
use std::collections::BTreeMap;
use std::f64::consts::PI;

pub(crate) use super::implicit::smooth_min;
pub use super::implicit::{implicit_surface, Shape};

/// Every shape of the suite: (kebab-case name, one-line description), in suite order.
pub const SHAPES: &[(&str, &str)] = &[
    ("torus-g1", "closed mesh of genus 1: one torus (marching tetrahedra, ~15 K triangles)"),
    ("torus-g2", "closed mesh of genus 2: two overlapping tori in a row"),
    ("torus-g3", "closed mesh of genus 3: three overlapping tori in a row"),
    ("torus-g4", "closed mesh of genus 4: four overlapping tori in a row"),
    ("torus-g5", "closed mesh of genus 5: five overlapping tori in a row"),
    ("torus-g1-cloud", "20 000 points sampled from torus-g1 (no normals)"),
    ("torus-g2-cloud", "20 000 points sampled from torus-g2 (no normals)"),
    ("torus-g3-cloud", "20 000 points sampled from torus-g3 (no normals)"),
    ("torus-g4-cloud", "20 000 points sampled from torus-g4 (no normals)"),
    ("torus-g5-cloud", "20 000 points sampled from torus-g5 (no normals)"),
    (
        "torus-sparse-cloud",
        "1 500 points on a torus (R 0.5, r 0.25): tube radius ≈ 4.4 mean point spacings",
    ),
    (
        "sphere-cut-cloud",
        "10 000 points on the unit sphere with the cap z > 0.5 (60° half-angle) cut away",
    ),
    (
        "sphere-cut",
        "open mesh of the unit sphere with the cap z > 0.5 (60° half-angle) cut away: one boundary loop",
    ),
    (
        "cube-hole",
        "exact polyhedral unit cube with a cylindrical through-hole (r 0.25, 64 sides): genus 1, sharp edges",
    ),
    (
        "two-spheres",
        "two disjoint closed spheres (r 0.5) with a gap of 1 % of the diagonal: one mesh, two components",
    ),
    (
        "two-spheres-apart-cloud",
        "20 000 points on two spheres (r 0.5) 30 % of the diagonal apart: two components, genus 0",
    ),
    ("thin-plate", "closed box 1 × 0.6 × 0.01 (a thin but real wall)"),
    ("thin-plate-cloud", "20 000 points sampled from thin-plate (no normals)"),
    (
        "self-intersecting",
        "one triangle list of two overlapping closed spheres (r 0.5, centres 0.5 apart): intersects itself",
    ),
    ("coplanar-3", "exactly 3 points (degenerate)"),
    ("coplanar-cloud", "500 points in the unit square of the plane z = 0 (degenerate)"),
    (
        "dumbbell",
        "two spheres (r 0.35) joined by a thin neck (r 0.06): closed, genus 0",
    ),
    ("cube", "exact unit cube, each face a 16 × 16 grid: 12 sharp 90° edges and 8 corners"),
    (
        "cad-part",
        "an L-shaped block with a 45° chamfer (1 × 1 × 0.4): convex 90° and 135° edges, a concave edge",
    ),
    (
        "fish",
        "sculpted cartoon fish: thin tail and dorsal fins (1.4 % of the diagonal) blended into the body, eye sockets",
    ),
    (
        "creature",
        "sculpted four-legged creature: legs, thin ears, a thin tail, eye sockets; closed, genus 0",
    ),
    (
        "bust",
        "sculpted bust: nose, deep eye sockets, a mouth slit 0.7 % of the diagonal wide, cupped thin ears",
    ),
    (
        "plate-holes",
        "flat plate 1 × 0.6 × 0.06 with three through-holes (r 0.1, 0.05, 0.03): genus 3, sharp rims",
    ),
    (
        "figure",
        "sculpted cartoon figure whose legs and arms nearly touch (gaps 1 % of the diagonal): closed, genus 0",
    ),
    ("cube-cloud", "20 000 points sampled from cube (no normals): sharp edges in a cloud"),
    (
        "sphere-curves",
        "2 200 points on the unit sphere along 11 circles only (6 through the poles, 5 parallels): a curve-sampled cloud, genus 0",
    ),
    (
        "torus-curves",
        "2 400 points on a torus (R 0.5, r 0.2) along 12 tube cross-sections and 4 circles round its axis: a curve-sampled cloud, genus 1",
    ),
    (
        "cube-edges",
        "720 points along the 12 edges of the unit cube only: a wireframe cloud, genus 0",
    ),
    (
        "cad-part-cloud",
        "20 000 points sampled from cad-part (no normals): convex, concave and 135° edges in a cloud",
    ),
];

/// Number of points of the sampled clouds (`torus-gN-cloud`, `thin-plate-cloud`).
pub const CLOUD_POINTS: usize = 20_000;

/// A shape of [`SHAPES`] by name.
pub fn generate(name: &str) -> Result<Shape, DemoError> {
    let cloud = |(p, t): Shape, seed: u64| -> Result<Shape, DemoError> {
        Ok((sample_mesh(&p, &t, CLOUD_POINTS, seed)?, vec![]))
    };
    match name {
        "torus-g1" => Ok(torus_chain(1)),
        "torus-g2" => Ok(torus_chain(2)),
        "torus-g3" => Ok(torus_chain(3)),
        "torus-g4" => Ok(torus_chain(4)),
        "torus-g5" => Ok(torus_chain(5)),
        "torus-g1-cloud" => cloud(torus_chain(1), 101),
        "torus-g2-cloud" => cloud(torus_chain(2), 102),
        "torus-g3-cloud" => cloud(torus_chain(3), 103),
        "torus-g4-cloud" => cloud(torus_chain(4), 104),
        "torus-g5-cloud" => cloud(torus_chain(5), 105),
        "torus-sparse-cloud" => Ok((torus_cloud(0.5, 0.25, 1500, 11), vec![])),
        "sphere-curves" => Ok((super::curves::sphere_curves(), vec![])),
        "torus-curves" => Ok((super::curves::torus_curves(), vec![])),
        "cube-edges" => Ok((super::curves::cube_edges(), vec![])),
        "sphere-cut-cloud" => Ok((cut_sphere_cloud(10_000, 0.5, 12), vec![])),
        "sphere-cut" => Ok(cut_sphere(128, 48, 0.5)),
        "cube-hole" => Ok(cube_with_hole(0.25, 64, 16)),
        "two-spheres" => Ok(two_spheres(0.01)),
        "two-spheres-apart-cloud" => cloud(two_spheres(0.3), 107),
        "thin-plate" => Ok(thin_plate()),
        "thin-plate-cloud" => cloud(thin_plate(), 106),
        "self-intersecting" => Ok(overlapping_spheres(0.5)),
        "coplanar-3" => Ok((
            vec![
                DVec3::ZERO,
                DVec3::new(1.0, 0.0, 0.0),
                DVec3::new(0.0, 1.0, 0.0),
            ],
            vec![],
        )),
        "coplanar-cloud" => Ok((plane_cloud(500, 13), vec![])),
        "dumbbell" => Ok(dumbbell(0.35, 0.06, 0.6)),
        "cube" => Ok(grid_box(DVec3::ONE, [16, 16, 16])),
        "cad-part" => Ok(cad_part()),
        "fish" => Ok(super::sculpted::fish()),
        "creature" => Ok(super::sculpted::creature()),
        "bust" => Ok(super::sculpted::bust()),
        "plate-holes" => Ok(super::sculpted::plate_holes()),
        "figure" => Ok(super::sculpted::figure()),
        "cube-cloud" => cloud(grid_box(DVec3::ONE, [16, 16, 16]), 108),
        "cad-part-cloud" => cloud(cad_part(), 109),
        other => Err(DemoError::UnknownShape(other.to_string())),
    }
}

/// A closed surface of genus `g` (at least 1): `g` tori (radii 0.5 and 0.2, centres 1.2 apart
/// along x, so neighbours overlap) united by the minimum of their distance functions, scaled so
/// that x spans [−1, 1]. The grid spacing grows with g^¼, so the triangle count grows far
/// slower than the genus.
pub fn torus_chain(g: usize) -> Shape {
    let g = g.max(1);
    let (big, small, pitch) = (0.5, 0.2, 1.2);
    let half = 0.5 * pitch * (g - 1) as f64 + big + small;
    let centres: Vec<DVec3> = (0..g)
        .map(|i| DVec3::new((i as f64 - 0.5 * (g - 1) as f64) * pitch, 0.0, 0.0))
        .collect();
    let cell = 0.048 * crate::fmath::powf(g as f64, 0.25);
    let pad = DVec3::splat(2.0 * cell);
    let ext = DVec3::new(half, big + small, small);
    let sdf = |p: DVec3| {
        centres
            .iter()
            .map(|&c| torus_sdf(p, c, big, small))
            .fold(f64::INFINITY, f64::min)
    };
    let (p, t) = implicit_surface(sdf, -ext - pad, ext + pad, cell);
    (p.into_iter().map(|q| q / half).collect(), t)
}

/// `n` points on the torus around the z axis with radii `big`, `small`, uniform by area
/// (rejection on the area element `big + small·cos v`).
pub fn torus_cloud(big: f64, small: f64, n: usize, seed: u64) -> Vec<DVec3> {
    let mut rng = Rng::new(seed);
    let mut out = Vec::with_capacity(n);
    while out.len() < n {
        let u = 2.0 * PI * rng.uniform();
        let v = 2.0 * PI * rng.uniform();
        if rng.uniform() * (big + small) > big + small * crate::fmath::cos(v) {
            continue;
        }
        let ring = big + small * crate::fmath::cos(v);
        out.push(DVec3::new(
            ring * crate::fmath::cos(u),
            ring * crate::fmath::sin(u),
            small * crate::fmath::sin(v),
        ));
    }
    out
}

/// `n` points uniform on the unit sphere below the plane `z = z_cut` (Archimedes: z uniform).
pub fn cut_sphere_cloud(n: usize, z_cut: f64, seed: u64) -> Vec<DVec3> {
    let mut rng = Rng::new(seed);
    (0..n)
        .map(|_| {
            let z = -1.0 + (z_cut + 1.0) * rng.uniform();
            let phi = 2.0 * PI * rng.uniform();
            let r = (1.0 - z * z).max(0.0).sqrt();
            DVec3::new(r * crate::fmath::cos(phi), r * crate::fmath::sin(phi), z)
        })
        .collect()
}

/// Pushes triangle `t`, flipped if needed so that its normal points along `outward`.
fn push_oriented(tris: &mut Vec<[u32; 3]>, p: &[DVec3], t: [u32; 3], outward: DVec3) {
    let [a, b, c] = t.map(|v| p[v as usize]);
    if (b - a).cross(c - a).dot(outward) < 0.0 {
        tris.push([t[0], t[2], t[1]]);
    } else {
        tris.push(t);
    }
}

/// The unit sphere below `z = z_cut` as an open latitude–longitude mesh: `lat` rings from the
/// cut (the boundary loop, exactly on the sphere and the plane) down to the south pole, `lon`
/// vertices per ring, outward oriented.
pub fn cut_sphere(lon: usize, lat: usize, z_cut: f64) -> Shape {
    let theta0 = crate::fmath::acos(z_cut.clamp(-1.0, 1.0));
    let mut p = Vec::with_capacity(lon * lat + 1);
    for j in 0..lat {
        let theta = theta0 + (PI - theta0) * j as f64 / lat as f64;
        for i in 0..lon {
            let phi = 2.0 * PI * i as f64 / lon as f64;
            p.push(DVec3::new(
                crate::fmath::sin(theta) * crate::fmath::cos(phi),
                crate::fmath::sin(theta) * crate::fmath::sin(phi),
                crate::fmath::cos(theta),
            ));
        }
    }
    let pole = p.len() as u32;
    p.push(DVec3::new(0.0, 0.0, -1.0));
    let v = |j: usize, i: usize| (j * lon + i % lon) as u32;
    let mut t = Vec::with_capacity(2 * lon * lat);
    for j in 0..lat - 1 {
        for i in 0..lon {
            let quad = [v(j, i), v(j, i + 1), v(j + 1, i + 1), v(j + 1, i)];
            let out = quad.iter().map(|&k| p[k as usize]).sum::<DVec3>();
            push_oriented(&mut t, &p, [quad[0], quad[1], quad[2]], out);
            push_oriented(&mut t, &p, [quad[0], quad[2], quad[3]], out);
        }
    }
    for i in 0..lon {
        let tri = [v(lat - 1, i), v(lat - 1, i + 1), pole];
        push_oriented(&mut t, &p, tri, DVec3::NEG_Z);
    }
    (p, t)
}

/// The cube `[−0.5, 0.5]³` with a through-hole along z: a regular `sides`-gon prism of
/// circumradius `radius`, its wall cut into `layers` rings. Exact and polyhedral: flat faces,
/// sharp edges, genus 1, outward oriented. The top and bottom annuli are fans from the four
/// cube corners, so each cube side is two triangles. `sides` must be a multiple of 4.
pub fn cube_with_hole(radius: f64, sides: usize, layers: usize) -> Shape {
    let sides = sides.max(4) / 4 * 4;
    let layers = layers.max(1);
    let mut p = Vec::new();
    // Corners: bottom k = 0..4, top k = 4..8, at angles 45° + 90°·k.
    for z in [-0.5, 0.5] {
        for k in 0..4 {
            let a = PI / 4.0 + PI / 2.0 * k as f64;
            p.push(DVec3::new(
                0.5f64.copysign(crate::fmath::cos(a)),
                0.5f64.copysign(crate::fmath::sin(a)),
                z,
            ));
        }
    }
    let ring0 = p.len();
    for l in 0..=layers {
        let z = -0.5 + l as f64 / layers as f64;
        for i in 0..sides {
            let a = 2.0 * PI * i as f64 / sides as f64;
            p.push(DVec3::new(
                radius * crate::fmath::cos(a),
                radius * crate::fmath::sin(a),
                z,
            ));
        }
    }
    let ring = |l: usize, i: usize| (ring0 + l * sides + i % sides) as u32;
    let mut t = Vec::new();
    // Top (l = layers, corners 4..8, normal +z) and bottom (l = 0, corners 0..4, normal −z).
    for (l, c0, n) in [(layers, 4u32, DVec3::Z), (0, 0u32, DVec3::NEG_Z)] {
        let q = sides / 4;
        for k in 0..4 {
            let c = c0 + k as u32;
            for i in k * q..(k + 1) * q {
                push_oriented(&mut t, &p, [c, ring(l, i), ring(l, i + 1)], n);
            }
            let next = c0 + ((k + 1) % 4) as u32;
            push_oriented(&mut t, &p, [c, next, ring(l, (k + 1) * q)], n);
        }
    }
    // The hole's wall, facing the axis.
    for l in 0..layers {
        for i in 0..sides {
            let quad = [
                ring(l, i),
                ring(l, i + 1),
                ring(l + 1, i + 1),
                ring(l + 1, i),
            ];
            let c = quad.iter().map(|&k| p[k as usize]).sum::<DVec3>();
            let inward = -DVec3::new(c.x, c.y, 0.0);
            push_oriented(&mut t, &p, [quad[0], quad[1], quad[2]], inward);
            push_oriented(&mut t, &p, [quad[0], quad[2], quad[3]], inward);
        }
    }
    // The four sides: bottom corners k, k+1 and top corners k+4, k+5.
    for k in 0..4u32 {
        let (a, b) = (k, (k + 1) % 4);
        let out = p[a as usize] + p[b as usize];
        let out = DVec3::new(out.x, out.y, 0.0);
        push_oriented(&mut t, &p, [a, b, b + 4], out);
        push_oriented(&mut t, &p, [a, b + 4, a + 4], out);
    }
    (p, t)
}

/// Two level-4 icospheres of radius 0.5 whose surfaces are `gap_fraction` of the bounding-box
/// diagonal apart (nominal spheres; the inscribed facets are slightly farther apart).
pub fn two_spheres(gap_fraction: f64) -> Shape {
    // The diagonal depends on the gap: sqrt((2 + gap)² + 2); a few fixed-point steps converge.
    let mut gap = 0.0f64;
    for _ in 0..20 {
        gap = gap_fraction * ((2.0 + gap) * (2.0 + gap) + 2.0).sqrt();
    }
    let d = 0.5 + 0.5 * gap;
    sphere_pair(0.5, DVec3::new(-d, 0.0, 0.0), DVec3::new(d, 0.0, 0.0))
}

/// Two overlapping level-4 icospheres of radius 0.5 with centres `distance` apart along x, in one
/// triangle list: each closed, together intersecting themselves along a circle.
pub fn overlapping_spheres(distance: f64) -> Shape {
    let h = 0.5 * distance;
    sphere_pair(0.5, DVec3::new(-h, 0.0, 0.0), DVec3::new(h, 0.0, 0.0))
}

/// Two level-4 icospheres of radius `r` at `a` and `b` in one mesh (indices of the second offset).
fn sphere_pair(r: f64, a: DVec3, b: DVec3) -> Shape {
    let (unit, faces) = unit_icosphere(4);
    let nv = unit.len() as u32;
    let p = unit
        .iter()
        .map(|&q| a + r * q)
        .chain(unit.iter().map(|&q| b + r * q))
        .collect();
    let t = faces
        .iter()
        .copied()
        .chain(faces.iter().map(|f| f.map(|v| v + nv)))
        .collect();
    (p, t)
}

/// A closed axis-aligned box of `size` centred at the origin, each face a welded grid of
/// `div[a] × div[b]` squares split into two triangles, outward oriented.
pub fn grid_box(size: DVec3, div: [u32; 3]) -> Shape {
    let div = div.map(|d| d.max(1));
    let mut index: BTreeMap<[u32; 3], u32> = BTreeMap::new();
    let mut p = Vec::new();
    let step = size / DVec3::new(div[0] as f64, div[1] as f64, div[2] as f64);
    let mut vertex = |k: [u32; 3], p: &mut Vec<DVec3>| -> u32 {
        *index.entry(k).or_insert_with(|| {
            p.push(DVec3::new(k[0] as f64, k[1] as f64, k[2] as f64) * step - 0.5 * size);
            (p.len() - 1) as u32
        })
    };
    let mut t = Vec::new();
    for a in 0..3 {
        let (b, c) = ((a + 1) % 3, (a + 2) % 3);
        for side in [0, div[a]] {
            let mut out = DVec3::ZERO;
            out[a] = if side == 0 { -1.0 } else { 1.0 };
            for i in 0..div[b] {
                for j in 0..div[c] {
                    let mut quad = [[0u32; 3]; 4];
                    for (q, (di, dj)) in quad.iter_mut().zip([(0, 0), (1, 0), (1, 1), (0, 1)]) {
                        q[a] = side;
                        q[b] = i + di;
                        q[c] = j + dj;
                    }
                    let v = quad.map(|k| vertex(k, &mut p));
                    push_oriented(&mut t, &p, [v[0], v[1], v[2]], out);
                    push_oriented(&mut t, &p, [v[0], v[2], v[3]], out);
                }
            }
        }
    }
    (p, t)
}

/// The thin plate: a closed 1 × 0.6 × 0.01 box, squares of 0.02 on its faces (6 320 triangles).
pub fn thin_plate() -> Shape {
    grid_box(DVec3::new(1.0, 0.6, 0.01), [50, 30, 1])
}

/// The CAD test part: the L-shaped outline (0,0) (1,0) (1,0.35) (0.85,0.5) (0.5,0.5) (0.5,1)
/// (0,1) — a 45° chamfer at one outer corner, one concave corner — extruded 0.4 along z and
/// centred. Its edges are 90° and 135° convex creases and one 90° concave crease.
pub fn cad_part() -> Shape {
    let outline = [
        (0.0, 0.0),
        (1.0, 0.0),
        (1.0, 0.35),
        (0.85, 0.5),
        (0.5, 0.5),
        (0.5, 1.0),
        (0.0, 1.0),
    ]
    .map(|(x, y)| (x - 0.5, y - 0.5));
    // The outline is star-shaped from this point of the corner square (on no edge's line).
    extruded_polygon(&outline, (-0.27, -0.23), 0.4, 0.05)
}

/// A prism: the counter-clockwise, star-shaped `outline` (in the plane z = 0) extruded to
/// `height` and centred in z. Walls are grids of at most `step` along the outline and up; the
/// two caps are fans from `star` (a point that sees the whole outline) to the wall's boundary
/// vertices, so the mesh is welded and closed. Outward oriented.
pub fn extruded_polygon(outline: &[(f64, f64)], star: (f64, f64), height: f64, step: f64) -> Shape {
    let layers = (height / step).ceil().max(1.0) as usize;
    // The outline, subdivided: points along each edge, the edge's start included.
    let mut ring: Vec<(f64, f64)> = Vec::new();
    for (i, &(x0, y0)) in outline.iter().enumerate() {
        let (x1, y1) = outline[(i + 1) % outline.len()];
        let k = (crate::fmath::hypot(x1 - x0, y1 - y0) / step)
            .ceil()
            .max(1.0) as usize;
        for j in 0..k {
            let t = j as f64 / k as f64;
            ring.push((x0 + t * (x1 - x0), y0 + t * (y1 - y0)));
        }
    }
    let n = ring.len();
    let mut p = Vec::with_capacity(n * (layers + 1) + 2);
    for l in 0..=layers {
        let z = height * (l as f64 / layers as f64 - 0.5);
        p.extend(ring.iter().map(|&(x, y)| DVec3::new(x, y, z)));
    }
    let at = |l: usize, i: usize| (l * n + i % n) as u32;
    let mut t = Vec::new();
    for l in 0..layers {
        for i in 0..n {
            let quad = [at(l, i), at(l, i + 1), at(l + 1, i + 1), at(l + 1, i)];
            let edge = p[quad[1] as usize] - p[quad[0] as usize];
            let out = DVec3::new(edge.y, -edge.x, 0.0);
            push_oriented(&mut t, &p, [quad[0], quad[1], quad[2]], out);
            push_oriented(&mut t, &p, [quad[0], quad[2], quad[3]], out);
        }
    }
    for (l, out) in [(0, DVec3::NEG_Z), (layers, DVec3::Z)] {
        let centre = p.len() as u32;
        p.push(DVec3::new(star.0, star.1, p[at(l, 0) as usize].z));
        for i in 0..n {
            push_oriented(&mut t, &p, [centre, at(l, i), at(l, i + 1)], out);
        }
    }
    (p, t)
}

/// `n` points uniform in the square `[−0.5, 0.5]²` of the plane `z = 0`.
pub fn plane_cloud(n: usize, seed: u64) -> Vec<DVec3> {
    let mut rng = Rng::new(seed);
    (0..n)
        .map(|_| DVec3::new(rng.uniform() - 0.5, rng.uniform() - 0.5, 0.0))
        .collect()
}

/// A dumbbell: spheres of radius `r` at x = ±`half_length`, joined by a cylinder (capsule) of
/// radius `neck` along x, blended with a small smooth minimum. Closed, genus 0.
pub fn dumbbell(r: f64, neck: f64, half_length: f64) -> Shape {
    let (c1, c2) = (
        DVec3::new(-half_length, 0.0, 0.0),
        DVec3::new(half_length, 0.0, 0.0),
    );
    let sdf = |p: DVec3| {
        let spheres = ((p - c1).length() - r).min((p - c2).length() - r);
        smooth_min(spheres, capsule(p, c1, c2, neck), 0.04)
    };
    let cell = 0.028;
    let ext = DVec3::new(half_length + r, r, r) + DVec3::splat(2.0 * cell);
    implicit_surface(sdf, -ext, ext, cell)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::{edge_counts, HalfedgeMesh, MeshReport};

    fn closed(name: &str) -> (Shape, MeshReport) {
        let s = generate(name).unwrap();
        let mesh = HalfedgeMesh::from_triangles(s.0.clone(), &s.1).unwrap();
        let rep = mesh
            .validate()
            .unwrap_or_else(|e| panic!("{name} is not a valid closed mesh: {e}"));
        assert!(mesh.signed_volume() > 0.0, "{name} is not outward oriented");
        (s, rep)
    }

    fn diagonal(p: &[DVec3]) -> f64 {
        crate::geometry::aabb::Aabb::from_points(p).diagonal()
    }

    #[test]
    fn registry_names_are_unique_kebab_case_and_generate() {
        for (i, (name, desc)) in SHAPES.iter().enumerate() {
            assert!(!desc.is_empty());
            assert!(name
                .chars()
                .all(|c| c.is_ascii_lowercase() || c.is_ascii_digit() || c == '-'));
            assert!(SHAPES[..i].iter().all(|(n, _)| n != name), "{name} twice");
        }
        assert_eq!(
            generate("nope"),
            Err(DemoError::UnknownShape("nope".into()))
        );
    }

    #[test]
    fn every_shape_is_deterministic_finite_and_roughly_unit_sized() {
        for (name, _) in SHAPES {
            let a = generate(name).unwrap();
            assert_eq!(a, generate(name).unwrap(), "{name} is not deterministic");
            assert!(a.0.iter().all(|p| p.is_finite()), "{name}");
            let d = diagonal(&a.0);
            assert!((1.0..=3.5).contains(&d), "{name}: diagonal {d}");
            let n = a.0.len() as u32;
            assert!(a.1.iter().flatten().all(|&v| v < n), "{name}");
        }
    }

    #[test]
    fn tori_have_the_promised_genus_and_size() {
        for g in 1..=5 {
            let ((_, t), rep) = closed(&format!("torus-g{g}"));
            assert_eq!(rep.genus, g as i64, "torus-g{g}");
            assert_eq!(rep.components, 1, "torus-g{g}");
            assert!(
                (10_000..=32_000).contains(&t.len()),
                "torus-g{g}: {} triangles",
                t.len()
            );
        }
    }

    #[test]
    fn torus_clouds_lie_on_their_meshes() {
        for g in [1, 5] {
            let (mesh, _) = generate(&format!("torus-g{g}")).unwrap();
            let (cloud, tris) = generate(&format!("torus-g{g}-cloud")).unwrap();
            assert!(tris.is_empty());
            assert_eq!(cloud.len(), CLOUD_POINTS);
            let lo = mesh.iter().copied().reduce(DVec3::min).unwrap();
            let hi = mesh.iter().copied().reduce(DVec3::max).unwrap();
            assert!(cloud
                .iter()
                .all(|q| q.cmpge(lo - 1e-12).all() && q.cmple(hi + 1e-12).all()));
        }
    }

    #[test]
    fn sparse_torus_cloud_is_at_the_spacing_limit() {
        let (p, t) = generate("torus-sparse-cloud").unwrap();
        assert!(t.is_empty());
        assert_eq!(p.len(), 1500);
        let (big, small) = (0.5, 0.25);
        for q in &p {
            let ring = (q.x * q.x + q.y * q.y).sqrt() - big;
            assert!(((ring * ring + q.z * q.z).sqrt() - small).abs() < 1e-12);
        }
        let spacing = (4.0 * PI * PI * big * small / p.len() as f64).sqrt();
        let ratio = small / spacing;
        assert!(
            (4.0..=5.0).contains(&ratio),
            "tube radius / spacing {ratio}"
        );
    }

    #[test]
    fn cut_sphere_cloud_and_mesh_have_the_cap_removed() {
        let (p, t) = generate("sphere-cut-cloud").unwrap();
        assert!(t.is_empty());
        assert_eq!(p.len(), 10_000);
        assert!(p
            .iter()
            .all(|q| (q.length() - 1.0).abs() < 1e-12 && q.z <= 0.5));
        // Uniform on the sphere: the mean z of the band z ∈ [−1, 0.5] is −0.25.
        let mean_z = p.iter().map(|q| q.z).sum::<f64>() / p.len() as f64;
        assert!((mean_z + 0.25).abs() < 0.02, "mean z {mean_z}");

        let (p, t) = generate("sphere-cut").unwrap();
        let counts = edge_counts(&t);
        assert_eq!(counts.boundary, 128, "one boundary loop of 128 edges");
        assert_eq!(counts.non_manifold, 0);
        // An open disc: χ = V − E + F = 1.
        assert_eq!(p.len() as i64 - counts.edges as i64 + t.len() as i64, 1);
        let mesh = HalfedgeMesh::from_triangles(p.clone(), &t).unwrap();
        assert!(matches!(
            mesh.validate(),
            Err(crate::mesh::ValidationError::Boundary { .. })
        ));
        assert!(p.iter().all(|q| q.z <= 0.5 + 1e-12));
        // Outward: every face normal points away from the centre.
        for f in &t {
            let [a, b, c] = f.map(|v| p[v as usize]);
            assert!((b - a).cross(c - a).dot(a + b + c) > 0.0);
        }
    }

    #[test]
    fn cube_with_hole_is_exact_genus_one() {
        let ((p, _), rep) = closed("cube-hole");
        assert_eq!(rep.genus, 1);
        assert_eq!(rep.components, 1);
        let mesh = HalfedgeMesh::from_triangles(p, &generate("cube-hole").unwrap().1).unwrap();
        let n = 64.0;
        let prism = 0.5 * n * 0.25 * 0.25 * crate::fmath::sin(2.0 * PI / n);
        assert!((mesh.signed_volume() - (1.0 - prism)).abs() < 1e-12);
        assert!((diagonal(mesh.positions()) - 3f64.sqrt()).abs() < 1e-12);
    }

    #[test]
    fn two_spheres_are_disjoint_and_almost_touch() {
        let ((p, _), rep) = closed("two-spheres");
        assert_eq!(rep.components, 2);
        assert_eq!(rep.genus, 0);
        let half = p.len() / 2;
        let gap = p[..half]
            .iter()
            .flat_map(|a| p[half..].iter().map(move |b| (*a - *b).length()))
            .fold(f64::INFINITY, f64::min);
        let rel = gap / diagonal(&p);
        assert!((0.01..0.015).contains(&rel), "gap {rel} of the diagonal");
    }

    #[test]
    fn thin_plate_is_a_thin_closed_box_and_its_cloud_covers_it() {
        let ((p, t), rep) = closed("thin-plate");
        assert_eq!(rep.genus, 0);
        assert_eq!(t.len(), 6320);
        let size = crate::geometry::aabb::Aabb::from_points(&p).size();
        assert!((size - DVec3::new(1.0, 0.6, 0.01)).abs().max_element() < 1e-12);
        let mesh = HalfedgeMesh::from_triangles(p, &t).unwrap();
        assert!((mesh.signed_volume() - 0.006).abs() < 1e-12);
        let (c, t) = generate("thin-plate-cloud").unwrap();
        assert!(t.is_empty());
        assert_eq!(c.len(), CLOUD_POINTS);
        assert!(c.iter().any(|q| q.z > 0.004) && c.iter().any(|q| q.z < -0.004));
        assert!(c
            .iter()
            .all(|q| q.x.abs() <= 0.5 + 1e-12 && q.y.abs() <= 0.3 + 1e-12));
    }

    #[test]
    fn self_intersecting_soup_is_two_closed_overlapping_spheres() {
        let ((p, _), rep) = closed("self-intersecting");
        assert_eq!(rep.components, 2);
        let half = p.len() / 2;
        let b = DVec3::new(0.25, 0.0, 0.0);
        let inside = p[..half]
            .iter()
            .filter(|q| (**q - b).length() < 0.5)
            .count();
        assert!(inside > 0 && inside < half, "{inside} of {half}");
    }

    #[test]
    fn cad_shapes_are_closed_genus_zero_with_the_promised_volume() {
        for (name, volume) in [
            ("cube", 1.0),
            ("cad-part", (0.75 - 0.5 * 0.15 * 0.15) * 0.4),
        ] {
            let ((p, t), rep) = closed(name);
            assert_eq!((rep.genus, rep.components), (0, 1), "{name}");
            let mesh = HalfedgeMesh::from_triangles(p, &t).unwrap();
            assert!((mesh.signed_volume() - volume).abs() < 1e-12, "{name}");
        }
    }

    #[test]
    fn degenerate_clouds_are_planar() {
        let (p, t) = generate("coplanar-3").unwrap();
        assert_eq!((p.len(), t.len()), (3, 0));
        let (p, t) = generate("coplanar-cloud").unwrap();
        assert_eq!((p.len(), t.len()), (500, 0));
        assert!(p
            .iter()
            .all(|q| q.z == 0.0 && q.x.abs() <= 0.5 && q.y.abs() <= 0.5));
    }

    #[test]
    fn dumbbell_is_closed_genus_zero_with_a_thin_neck() {
        let ((p, t), rep) = closed("dumbbell");
        assert_eq!((rep.genus, rep.components), (0, 1));
        assert!(
            (10_000..=60_000).contains(&t.len()),
            "{} triangles",
            t.len()
        );
        // The neck at x = 0 is thin: every vertex near the mid-plane is within ~neck of the axis.
        let near: Vec<f64> = p
            .iter()
            .filter(|q| q.x.abs() < 0.05)
            .map(|q| crate::fmath::hypot(q.y, q.z))
            .collect();
        assert!(!near.is_empty());
        assert!(near.iter().all(|&r| r < 0.09), "{near:?}");
    }
}
