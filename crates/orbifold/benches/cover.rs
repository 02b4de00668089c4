//! Benchmarks of universal-cover enumeration. Run with `cargo bench -p orbifold --bench cover`.
#![allow(missing_docs)] // criterion_group! generates undocumented functions.

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use orbifold::cover::{Bound, Cover};
use orbifold::pairing::FundamentalPolygon;
use orbifold::pairing::cover::GroupCover;
use orbifold::{OrbifoldSymbol, Signature};

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

/// The certified geometric enumeration of any orbifold group (`orbifold::pairing::cover`) against
/// the combinatorial kaleidoscopic cover, at the same number of tiles: the same reflection groups
/// enumerated both ways, then groups with side pairings at about that many tiles.
fn group_covers(c: &mut Criterion) {
    let mut group = c.benchmark_group("group cover");
    group.sample_size(10);
    for (sig, depth) in [("*2222222", 6), ("*237", 24), ("*2323", 8)] {
        let s: Signature = sig.parse().unwrap();
        let tiles: u64 = Cover::enumerate(&s, Bound::Depth(depth), false)
            .unwrap()
            .counts_by_depth
            .iter()
            .sum();
        let symbol: OrbifoldSymbol = sig.parse().unwrap();
        let polygon = FundamentalPolygon::new(&symbol, &Default::default()).unwrap();
        group.throughput(Throughput::Elements(tiles));
        group.bench_function(format!("{sig} combinatorial ({tiles} tiles)"), |b| {
            b.iter(|| Cover::enumerate(&s, Bound::Depth(depth), false).unwrap())
        });
        group.bench_function(format!("{sig} geometric ({tiles} tiles)"), |b| {
            b.iter(|| {
                GroupCover::enumerate_polygon(polygon.clone(), Bound::Depth(depth), false).unwrap()
            })
        });
    }
    // Groups with side pairings against a related reflection group's combinatorial cover, each
    // bounded by the deepest whole depths within 30 000 tiles (so the counts differ a little; the
    // ratio is per tile); the group cover also under the tile bound itself, where it builds part
    // of the layer that does not fit before abandoning it.
    let capped = Bound::Tiles(30_000);
    for (sig, reflections) in [
        ("632", "*632"),
        ("22×", "*2222"),
        ("2223", "*2223"),
        ("oo", "*22222222"),
    ] {
        let s: Signature = reflections.parse().unwrap();
        let depth = Cover::enumerate(&s, capped, false)
            .unwrap()
            .counts_by_depth
            .len()
            - 1;
        let bound = Bound::Depth(depth);
        let count: u64 = Cover::enumerate(&s, bound, false)
            .unwrap()
            .counts_by_depth
            .iter()
            .sum();
        group.throughput(Throughput::Elements(count));
        group.bench_function(
            format!("{reflections} combinatorial depth {depth} ({count} tiles)"),
            |b| b.iter(|| Cover::enumerate(&s, bound, false).unwrap()),
        );
        let symbol: OrbifoldSymbol = sig.parse().unwrap();
        let polygon = FundamentalPolygon::new(&symbol, &Default::default()).unwrap();
        let enumerate = |bound| GroupCover::enumerate_polygon(polygon.clone(), bound, false);
        let depth = enumerate(capped).unwrap().counts_by_depth.len() - 1;
        let bound = Bound::Depth(depth);
        let count: u64 = enumerate(bound).unwrap().counts_by_depth.iter().sum();
        group.throughput(Throughput::Elements(count));
        group.bench_function(
            format!("{sig} geometric depth {depth} ({count} tiles)"),
            |b| b.iter(|| enumerate(bound).unwrap()),
        );
        group.bench_function(format!("{sig} geometric --max-tiles 30000"), |b| {
            b.iter(|| enumerate(capped).unwrap())
        });
    }
    group.finish();
}

criterion_group!(benches, covers, group_covers);
criterion_main!(benches);
