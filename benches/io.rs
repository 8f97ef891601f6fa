//! Parse time of the readers on generated 1 M-point inputs: binary little-endian PLY (target
//! ≤ 0.2 s) and ASCII XYZ (target ≤ 1 s), both through `read_bytes` (detection, parsing and the
//! `Target` checks and bounding box), plus the binary PLY writer.
//! Run: `cargo bench --bench io`. Results go to benches/RESULTS.md.

use criterion::{criterion_group, criterion_main, Criterion};
use lsw::io::{read_bytes, write_bytes, Format, WriteInput};
use lsw::DVec3;
use std::fmt::Write as _;
use std::hint::black_box;

const N: usize = 1_000_000;

/// Deterministic points in the unit cube (xorshift), so every run parses the same bytes.
fn points(n: usize) -> Vec<DVec3> {
    let mut s = 0x2545_F491_4F6C_DD1Du64;
    let mut u = || {
        s ^= s << 13;
        s ^= s >> 7;
        s ^= s << 17;
        (s >> 11) as f64 / (1u64 << 53) as f64
    };
    (0..n).map(|_| DVec3::new(u(), u(), u())).collect()
}

fn bench_io(c: &mut Criterion) {
    let p = points(N);
    let ply = write_bytes(Format::Ply, &WriteInput::new(&p, &[])).unwrap();
    let mut xyz = String::with_capacity(N * 30);
    for q in &p {
        let _ = writeln!(xyz, "{:.6} {:.6} {:.6}", q.x, q.y, q.z);
    }
    let mut g = c.benchmark_group("io_1M_points");
    g.sample_size(10);
    g.bench_function("read_binary_ply", |b| {
        b.iter(|| {
            let r = read_bytes(black_box(&ply), None).unwrap();
            assert_eq!(r.target.points.len(), N);
        })
    });
    g.bench_function("read_ascii_xyz", |b| {
        b.iter(|| {
            let r = read_bytes(black_box(xyz.as_bytes()), Some("cloud.xyz")).unwrap();
            assert_eq!(r.target.points.len(), N);
        })
    });
    g.bench_function("write_binary_ply", |b| {
        b.iter(|| write_bytes(Format::Ply, &WriteInput::new(black_box(&p), &[])).unwrap())
    });
    g.finish();
}

criterion_group!(benches, bench_io);
criterion_main!(benches);
