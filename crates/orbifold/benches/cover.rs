//! Benchmarks of universal-cover enumeration. Run with `cargo bench -p orbifold --bench cover`.
#![allow(missing_docs)] // criterion_group! generates undocumented functions.

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use orbifold::Signature;
use orbifold::cover::{Bound, Cover};

fn covers(c: &mut Criterion) {
    let mut group = c.benchmark_group("cover");
    group.sample_size(20);
    // *2222222 is the {7,4} tiling of hypertiling; depth 9 there is its 10 layers.
    for (sig, depth) in [("*2222222", 9), ("*237", 40), ("*∞∞∞", 18), ("*2323", 12)] {
        let s: Signature = sig.parse().unwrap();
        let tiles: u64 = Cover::enumerate(&s, Bound::Depth(depth), false)
            .unwrap()
            .counts_by_depth
            .iter()
            .sum();
        group.throughput(Throughput::Elements(tiles));
        group.bench_function(format!("{sig} depth {depth} ({tiles} tiles)"), |b| {
            b.iter(|| Cover::enumerate(&s, Bound::Depth(depth), false).unwrap())
        });
    }
    group.finish();
}

criterion_group!(benches, covers);
criterion_main!(benches);
