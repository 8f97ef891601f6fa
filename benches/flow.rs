//! Time per LSW evolution step (normals + assembly + solve, no remeshing) at 2 K, 10 K and 40 K
//! vertices: an icosphere of level 4, 5, 6 wrapping a sphere point cloud.
//! Run: `cargo bench --bench flow`. Results go to benches/RESULTS.md.
//!
//! Criterion times the whole first step from the start surface (the hardest solve: ε ≈ 1
//! everywhere). Before it, each size prints the phase split of the fastest of ten such steps
//! (normals + assembly + solve is the measure; the step also samples d at the new
//! positions).

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion};
use lsw::flow::{Evolver, WrapSettings};
use lsw::target::Target;

fn sphere_cloud(n: usize) -> Target {
    Target::new(lsw::geometry::sphere::fibonacci_sphere(n), vec![]).unwrap()
}

fn bench_flow(c: &mut Criterion) {
    let target = sphere_cloud(20_000);
    let mut g = c.benchmark_group("lsw_step");
    g.sample_size(20);
    for level in [4u32, 5, 6] {
        let settings = {
            let mut w = WrapSettings::default();
            w.start.icosphere_level = level;
            w.remesh.enabled = false;
            w.flow.schedule = vec![];
            w.stop.steps = 100_000;
            w
        };
        let ev = Evolver::new(&target, settings).unwrap();
        let n = ev.mesh().n_vertices();
        let mut best: Option<lsw::flow::StepReport> = None;
        for _ in 0..10 {
            let mut e = Evolver::new(&target, ev.settings().clone()).unwrap();
            let r = e.step().unwrap();
            if best.as_ref().is_none_or(|b| r.times.total < b.times.total) {
                best = Some(r);
            }
        }
        let t = best.unwrap().times;
        println!(
            "lsw_step/{n}: fastest of 10 first steps {:.2} ms = normals {:.2} + assembly {:.2} + solve {:.2} (phases {:.2}) + distance refresh",
            t.total,
            t.normals,
            t.assembly,
            t.solve,
            t.normals + t.assembly + t.solve
        );
        g.bench_with_input(BenchmarkId::from_parameter(n), &n, |b, _| {
            b.iter_batched_ref(
                || Evolver::new(&target, ev.settings().clone()).unwrap(),
                |e| e.step().unwrap(),
                criterion::BatchSize::LargeInput,
            )
        });
    }
    g.finish();
}

criterion_group!(benches, bench_flow);
criterion_main!(benches);
