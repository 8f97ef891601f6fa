//! Time to build the distance field (near band + fast sweeping + gradient) of the bunny point
//! cloud at the paper's resolution (40 cells per minimum dimension: 133×133×121 nodes).
//! Run: `LSW_SHARED_DATA=/path/to/data cargo bench --bench field`. Without `LSW_SHARED_DATA` a
//! synthetic cloud with the bunny's bounding box and point count (same grid) is used instead.
//! Results go to benches/RESULTS.md.

use criterion::{criterion_group, criterion_main, Criterion};
use lsw::field::{DistanceField, FieldSettings};
use lsw::target::Target;
use lsw::DVec3;

/// 11,988 points on an ellipsoid with the bunny cloud's bounding box.
fn bunny_sized_cloud() -> Target {
    let (lo, hi) = (
        DVec3::new(-0.09469, 0.03333, -0.06184),
        DVec3::new(0.06101, 0.18722, 0.05879),
    );
    let (c, h) = (0.5 * (lo + hi), 0.5 * (hi - lo));
    let n = 11_988;
    let golden = std::f64::consts::PI * (3.0 - 5f64.sqrt());
    let pts = (0..n)
        .map(|i| {
            let y = 1.0 - 2.0 * (i as f64 + 0.5) / n as f64;
            let s = (1.0 - y * y).sqrt();
            let t = golden * i as f64;
            c + h * DVec3::new(s * lsw::fmath::cos(t), y, s * lsw::fmath::sin(t))
        })
        .collect();
    Target::new(pts, vec![]).unwrap()
}

fn bench_field(c: &mut Criterion) {
    let mut g = c.benchmark_group("distance_field");
    g.sample_size(20);
    let settings = FieldSettings::default();
    match std::env::var_os("LSW_SHARED_DATA") {
        Some(dir) => {
            let path = std::path::Path::new(&dir).join("bunnyPts_3.ply");
            let target = lsw::io::read_path(&path).unwrap().target;
            let f = DistanceField::new(&target, &settings).unwrap();
            eprintln!(
                "bunnyPts_3: dims {:?}, {:?}, {:?}",
                f.dims(),
                f.sweep_report(),
                f.timings()
            );
            // LSW_FIELD_REPEAT=N: build the field N more times, print the fastest run and stop
            // (for `perf stat` / `perf record`, and on a busy machine where criterion's mean
            // mostly measures the other processes).
            if let Some(n) = std::env::var_os("LSW_FIELD_REPEAT") {
                let n: usize = n.to_str().and_then(|s| s.parse().ok()).unwrap_or(10);
                let mut best = f64::INFINITY;
                for _ in 0..n {
                    let t0 = lsw::clock::now_ms();
                    let f = DistanceField::new(&target, &settings).unwrap();
                    best = best.min(lsw::clock::now_ms() - t0);
                    std::hint::black_box(f);
                }
                eprintln!("bunnyPts_3: fastest of {n} runs {best:.1} ms");
                return;
            }
            g.bench_function("bunny_points", |b| {
                b.iter(|| DistanceField::new(&target, &settings).unwrap())
            });
            let spot = lsw::io::read_path(std::path::Path::new(&dir).join("spot.obj"))
                .unwrap()
                .target;
            g.bench_function("spot_mesh_signed", |b| {
                b.iter(|| DistanceField::new(&spot, &settings).unwrap())
            });
        }
        None => eprintln!(
            "LSW_SHARED_DATA is not set: benchmarking a synthetic cloud of the bunny's size only"
        ),
    }
    let synthetic = bunny_sized_cloud();
    g.bench_function("bunny_sized_synthetic_points", |b| {
        b.iter(|| DistanceField::new(&synthetic, &settings).unwrap())
    });
    g.finish();
}

criterion_group!(benches, bench_field);
criterion_main!(benches);
