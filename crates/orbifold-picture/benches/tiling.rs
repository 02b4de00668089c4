//! Benchmark of the raster tiling renderer. Run with `cargo bench -p orbifold-picture --bench tiling`.
#![allow(missing_docs)] // criterion_group! generates undocumented functions.

use criterion::{Criterion, criterion_group, criterion_main};
use orbifold::layout::{Layout, LayoutOptions};
use orbifold_picture::tiling::{View, render};

fn tilings(c: &mut Criterion) {
    let mut group = c.benchmark_group("tiling");
    group.sample_size(10);
    for (sig, size) in [
        ("*237", 4096),
        ("*2222222", 4096),
        ("*∞∞∞", 1024),
        ("*235", 1024),
    ] {
        let layout = Layout::new(&sig.parse().unwrap(), &LayoutOptions::default()).unwrap();
        let view = View::new(layout.geometry, size);
        group.bench_function(format!("{sig} {size}x{size}"), |b| {
            b.iter(|| render(&layout, &view, None).unwrap())
        });
    }
    group.finish();
}

criterion_group!(benches, tilings);
criterion_main!(benches);
