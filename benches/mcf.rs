//! Time per semi-implicit MCF step (Laplacian + assembly + three solves) by icosphere level.
//! Run: `cargo bench --bench mcf`. Results go to benches/RESULTS.md.

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion};
use lsw::flow::{mcf_step, McfSettings};
use lsw::geometry::icosphere::icosphere;
use lsw::DVec3;

fn bench_mcf(c: &mut Criterion) {
    let mut g = c.benchmark_group("mcf_step");
    g.sample_size(20);
    for level in [4u32, 5, 6] {
        let settings = McfSettings {
            tau: 1e-4,
            ..Default::default()
        };
        g.bench_with_input(BenchmarkId::from_parameter(level), &level, |b, &level| {
            let mesh = icosphere(level, 1.0, DVec3::ZERO).unwrap();
            b.iter_batched_ref(
                || mesh.clone(),
                |m| mcf_step(m, &settings).unwrap(),
                criterion::BatchSize::LargeInput,
            )
        });
    }
    g.finish();
}

criterion_group!(benches, bench_mcf);
criterion_main!(benches);
