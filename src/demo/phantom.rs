//! A procedurally generated head phantom for the app's volume gallery entry (no downloaded data):
//! a skull shell, a brain with two dark ventricles and a bright ring-shaped structure (genus 1,
//! so the isosurface start matters), smooth edges and seeded noise, on anisotropic voxels with a
//! rotated affine, so the app exercises the same reading, histogram, slicing and world-frame code
//! as a real scan.

use super::{ellipsoid, Rng};
use crate::io::volume::{affine, ScalarType, VoxelVolume};
use glam::DVec3;

/// A smooth step from 0 (outside, `d ≫ 0`) to 1 (inside) over about `w` mm around `d = 0`.
fn inside(d: f64, w: f64) -> f64 {
    0.5 - 0.5 * crate::fmath::tanh(d / w)
}

/// The phantom on `n × n × (3n/4)` voxels (n clamped to 16…256), values 0…255-ish: background
/// ≈ 0, skull ≈ 90, brain ≈ 170, ventricles ≈ 40, ring ≈ 240. Voxels 1.6 × 1.6 × 2.0 mm for
/// `n = 120`, scaled so the head spans the grid for any `n`.
pub fn phantom_volume(n: usize) -> VoxelVolume {
    let n = n.clamp(16, 256);
    let nz = (3 * n / 4).max(12);
    let dims = [n, n, nz];
    let s = 192.0 / n as f64;
    let spacing = [s, s, s * 1.25];
    // A small rotation about z (10°) and an origin that centres the head on the world origin.
    let (sn, cs) = crate::fmath::sin_cos(10f64.to_radians());
    let dirs = [DVec3::new(cs, sn, 0.0), DVec3::new(-sn, cs, 0.0), DVec3::Z];
    let cols = [0, 1, 2].map(|k| dirs[k] * spacing[k]);
    let half = cols[0] * (n - 1) as f64 / 2.0
        + cols[1] * (n - 1) as f64 / 2.0
        + cols[2] * (nz - 1) as f64 / 2.0;
    let index_to_world = affine(cols, -half);
    let mut rng = Rng::new(0x5eed_b7a1);
    let mut values = Vec::with_capacity(n * n * nz);
    for z in 0..nz {
        for y in 0..n {
            for x in 0..n {
                let p = index_to_world.transform_point3(DVec3::new(x as f64, y as f64, z as f64));
                let head = ellipsoid(p, DVec3::ZERO, DVec3::new(72.0, 88.0, 70.0));
                let brain = ellipsoid(p, DVec3::new(0.0, 0.0, 4.0), DVec3::new(62.0, 78.0, 58.0));
                let vl = ellipsoid(p, DVec3::new(-12.0, 5.0, 10.0), DVec3::new(7.0, 22.0, 9.0));
                let vr = ellipsoid(p, DVec3::new(12.0, 5.0, 10.0), DVec3::new(7.0, 22.0, 9.0));
                // A ring (torus) of radii 22 and 6 mm below the ventricles.
                let q = p - DVec3::new(0.0, -10.0, -18.0);
                let ring = crate::fmath::hypot(q.truncate().length() - 22.0, q.z) - 6.0;
                let w = 1.2 * s;
                let mut v = 90.0 * inside(head, w);
                v += 80.0 * inside(brain, w);
                v -= 130.0 * inside(vl.min(vr), w);
                v += 70.0 * inside(ring, w);
                v += 6.0 * (rng.uniform() - 0.5);
                values.push(v.clamp(0.0, 255.0) as f32);
            }
        }
    }
    VoxelVolume {
        dims,
        values,
        index_to_world,
        datatype: ScalarType::F32,
        frame: "phantom world frame (mm, head centred on the origin)".into(),
        frames: 1,
        frame_index: 0,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn phantom_has_its_tissues_and_round_trips_through_nifti() {
        let v = phantom_volume(32);
        assert_eq!(v.dims, [32, 32, 24]);
        let (lo, hi) = v.value_range().unwrap();
        assert!(lo < 10.0 && hi > 200.0, "{lo} {hi}");
        let bytes = crate::io::nifti::write(&v);
        let (w, _) = crate::io::nifti::read(&bytes, &Default::default()).unwrap();
        assert_eq!(w.values, v.values);
        assert_eq!(w.dims, v.dims);
        let e = (w.world(DVec3::splat(5.0)) - v.world(DVec3::splat(5.0))).length();
        assert!(e < 1e-4, "{e}");
    }
}
