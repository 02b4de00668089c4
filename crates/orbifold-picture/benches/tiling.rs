//! Benchmark of the raster tiling renderer. Run with `cargo bench -p orbifold-picture --bench tiling`.
#![allow(missing_docs)] // criterion_group! generates undocumented functions.

use criterion::{Criterion, criterion_group, criterion_main};
use orbifold::layout::{Layout, LayoutOptions};
use orbifold::pairing::FundamentalPolygon;
use orbifold_picture::group::render_group;
use orbifold_picture::tiling::{View, render};

fn tilings(c: &mut Criterion) {
    let mut group = c.benchmark_group("tiling");
    group.sample_size(10);
    for (sig, size) in [
        ("*237", 4096),
        ("*2222222", 4096),
        ("*∞∞∞", 1024),
        ("*235", 1024),
        ("*2223", 1024),
    ] {
        let layout = Layout::new(&sig.parse().unwrap(), &LayoutOptions::default()).unwrap();
        let view = View::new(layout.geometry, size);
        group.bench_function(format!("{sig} {size}x{size}"), |b| {
            b.iter(|| render(&layout, &view, None).unwrap())
        });
    }
    group.finish();
}

/// Orbifolds with cones, glides and handles, folded through their side pairings.
fn group_tilings(c: &mut Criterion) {
    let mut group = c.benchmark_group("group tiling");
    group.sample_size(10);
    for (symbol, size) in [("2223", 1024), ("22×", 1024), ("oo", 1024)] {
        let polygon =
            FundamentalPolygon::new(&symbol.parse().unwrap(), &LayoutOptions::default()).unwrap();
        let view = View::new(polygon.geometry, size);
        group.bench_function(format!("{symbol} {size}x{size}"), |b| {
            b.iter(|| render_group(&polygon, &view, None).unwrap())
        });
    }
    group.finish();
}

criterion_group!(benches, tilings, group_tilings);
criterion_main!(benches);
