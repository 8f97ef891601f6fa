use glam::DVec3;
use lsw::geometry::spatial::point_grid::PointGrid;
fn main() {
    let path = std::env::args().nth(1).unwrap();
    let read = lsw::io::read_path(std::path::Path::new(&path)).unwrap();
    let pts: Vec<DVec3> = read.target.points.clone();
    let bb = lsw::geometry::aabb::Aabb::from_points(&pts);
    let c = bb.size().min_element() / 100.0;
    for (radius, k) in [(2.0 * c, 256), (2.0 * c, 64), (2.0 * c, 32)] {
        let t0 = std::time::Instant::now();
        let g = PointGrid::new(&pts, radius);
        let t1 = t0.elapsed();
        let mut out = Vec::new();
        let (mut n, mut tot) = (0usize, 0usize);
        let t2 = std::time::Instant::now();
        for i in (0..pts.len()).step_by(25) {
            let p = pts[i] + DVec3::splat(0.3 * c);
            g.nearest_within_unordered(p, radius, k, &mut out);
            n += 1;
            tot += out.len();
        }
        let dt = t2.elapsed();
        println!("radius {radius:.4} cell {:.4} k {k}: build {:?}, {n} queries {:?} = {:.2} us each, mean found {:.0}", g.cell(), t1, dt, dt.as_secs_f64() * 1e6 / n as f64, tot as f64 / n as f64);
    }
}
