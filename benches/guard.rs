//! The contact guard's cost: one exact self-intersection count (the check the guard runs every
//! `guard.check_every` steps, before the final fit and in the certificate) on a perturbed
//! 40 962-vertex / 81 920-face sphere — the size of the bunny's last steps — and on a mesh with
//! a dent pushed through its far side (some intersecting pairs to enumerate).
//! Run: `cargo bench --bench guard`. Results go to benches/RESULTS.md.

use criterion::{criterion_group, criterion_main, Criterion};
use lsw::demo::Rng;
use lsw::geometry::icosphere::icosphere;
use lsw::metrics::intersections::count_self_intersections;
use lsw::DVec3;

/// Level-6 icosphere with every vertex jittered tangentially (≈ 25 % of an edge).
fn perturbed_sphere() -> (Vec<DVec3>, Vec<[u32; 3]>) {
    let m = icosphere(6, 1.0, DVec3::ZERO).unwrap();
    let mut rng = Rng::new(0x1234_5678_9ABC_DEF0);
    let mut r = move || rng.uniform() - 0.5;
    let p = m
        .positions()
        .iter()
        .map(|p| {
            let n = p.normalize();
            let d = DVec3::new(r(), r(), r());
            *p + (d - n * n.dot(d)) * 0.01
        })
        .collect();
    (p, m.triangles())
}

fn bench(c: &mut Criterion) {
    let (p, t) = perturbed_sphere();
    assert_eq!(count_self_intersections(&p, &t), 0);
    c.bench_function("self_intersections_82k_faces_clean", |b| {
        b.iter(|| count_self_intersections(&p, &t))
    });
    // Push a cap of the sphere through to the other side.
    let dented: Vec<DVec3> = p
        .iter()
        .map(|q| {
            if q.z > 0.9 {
                DVec3::new(q.x, q.y, -q.z)
            } else {
                *q
            }
        })
        .collect();
    println!(
        "dented: {} intersecting pairs",
        count_self_intersections(&dented, &t)
    );
    c.bench_function("self_intersections_82k_faces_dented", |b| {
        b.iter(|| count_self_intersections(&dented, &t))
    });
}

criterion_group! {
    name = benches;
    config = Criterion::default().sample_size(20);
    targets = bench
}
criterion_main!(benches);
