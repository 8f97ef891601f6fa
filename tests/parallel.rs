//! The native CLI's parallel loops (issue 16, item 5) must not change a result: a wrap on rayon's
//! pool with one thread and with several gives bit-identical meshes, field and certificate.
//! Native only: the wasm build has no thread pool.
#![cfg(not(target_arch = "wasm32"))]

use lsw::demo::shapes::generate;
use lsw::flow::{Evolver, WrapSettings};
use lsw::metrics::certificate::certify;
use lsw::target::Target;

/// Wraps `name` for a few steps plus the final fit inside a pool of `threads` threads.
fn wrap_with(threads: usize, name: &str) -> (Vec<[u64; 3]>, Vec<[u32; 3]>, String) {
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .unwrap();
    pool.install(|| {
        let (p, t) = generate(name).unwrap();
        let target = Target::new(p, t).unwrap();
        let mut settings = WrapSettings::default();
        settings.stop.steps = 16;
        let mut ev = Evolver::new(&target, settings).unwrap();
        while !ev.is_done() {
            ev.step().unwrap();
        }
        let (pos, tri) = (ev.positions(), ev.triangles());
        let cert = certify(&pos, &tri, Some(&target));
        assert!(cert.valid, "{name}: {cert:?}");
        let bits = pos.iter().map(|p| p.to_array().map(f64::to_bits)).collect();
        (bits, tri, format!("{cert:?}"))
    })
}

#[test]
fn one_thread_and_several_give_the_same_bits() {
    // A cloud (point band, plane fits) and a mesh (triangle band, closest-point fit).
    for name in ["torus-g2-cloud", "dumbbell"] {
        let one = wrap_with(1, name);
        let three = wrap_with(3, name);
        assert!(one.0.len() > 500, "{name}: {} vertices", one.0.len());
        assert_eq!(one.0, three.0, "{name}: positions differ");
        assert_eq!(one.1, three.1, "{name}: triangles differ");
        assert_eq!(one.2, three.2, "{name}: certificates differ");
    }
}
