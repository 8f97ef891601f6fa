//! Test helpers for the distance-field tests: the shared-data folder, loading through `lsw::io`,
//! synthetic targets and brute-force distances.
#![allow(dead_code)]

use lsw::target::Target;
use lsw::DVec3;

/// The shared test-data folder from `LSW_SHARED_DATA`. Tests that read it are ignored unless the
/// build saw the folder (`cfg(shared_data)`, set by build.rs), so this finds it when it runs.
pub fn data_dir(test: &str) -> std::path::PathBuf {
    match std::env::var_os("LSW_SHARED_DATA") {
        Some(d) => std::path::PathBuf::from(d),
        None => panic!("{test}: LSW_SHARED_DATA is not set (the build had it: rebuild)"),
    }
}

/// Reads a target through `lsw::io` (PLY, OBJ, …). `read_bytes` rather than `read_path`, which
/// is native-only: these files compile for wasm32 too (where the real-data tests never get a path).
pub fn load(path: &std::path::Path) -> Target {
    let bytes = std::fs::read(path).unwrap_or_else(|e| panic!("{path:?}: {e}"));
    lsw::io::read_bytes(&bytes, path.file_name().and_then(|n| n.to_str()))
        .unwrap_or_else(|e| panic!("{path:?}: {e}"))
        .target
}

/// `n` points spread evenly on the sphere of radius `r` about `c` (the library's Fibonacci
/// lattice with its pole on the y axis).
pub fn fibonacci_sphere(n: usize, r: f64, c: DVec3) -> Vec<DVec3> {
    lsw::geometry::sphere::fibonacci_sphere(n)
        .into_iter()
        .map(|p| c + r * DVec3::new(p.x, p.z, p.y))
        .collect()
}

/// A point cloud with the bunny's size: `n` points on an ellipsoid whose bounding box is that of
/// `bunnyPts_3.ply`, so the default grid has the paper's dimensions (≈134×133×122 nodes).
pub fn bunny_sized_cloud(n: usize) -> Vec<DVec3> {
    let lo = DVec3::new(-0.09469, 0.03333, -0.06184);
    let hi = DVec3::new(0.06101, 0.18722, 0.05879);
    let (c, h) = (0.5 * (lo + hi), 0.5 * (hi - lo));
    fibonacci_sphere(n, 1.0, DVec3::ZERO)
        .into_iter()
        .map(|p| c + p * h)
        .collect()
}

/// Exact distance from `p` to the nearest of `points` (brute force).
pub fn brute_point_distance(p: DVec3, points: &[DVec3]) -> f64 {
    points
        .iter()
        .map(|q| (p - *q).length_squared())
        .fold(f64::INFINITY, f64::min)
        .sqrt()
}

/// Triangles with their bounding boxes, for brute-force nearest-triangle distances.
pub struct Soup {
    tris: Vec<[DVec3; 3]>,
    boxes: Vec<(DVec3, DVec3)>,
}

impl Soup {
    pub fn new(t: &Target) -> Self {
        let tris: Vec<[DVec3; 3]> = t
            .triangles
            .iter()
            .map(|f| f.map(|v| t.points[v as usize]))
            .collect();
        let boxes = tris
            .iter()
            .map(|[a, b, c]| (a.min(*b).min(*c), a.max(*b).max(*c)))
            .collect();
        Self { tris, boxes }
    }

    /// Exact distance to the nearest triangle: every triangle is visited; the exact test is
    /// skipped only when the triangle's box is already farther than the best so far.
    pub fn distance(&self, p: DVec3) -> f64 {
        let mut best = f64::INFINITY;
        for (t, (lo, hi)) in self.tris.iter().zip(&self.boxes) {
            let q = p.clamp(*lo, *hi);
            if (p - q).length_squared() >= best {
                continue;
            }
            let d = lsw::geometry::primitives::point_triangle_distance_squared(p, t[0], t[1], t[2]);
            best = best.min(d);
        }
        best.sqrt()
    }
}
