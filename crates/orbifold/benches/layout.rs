//! Benchmarks of polygon layout. Run with `cargo bench -p orbifold --bench layout`.
#![allow(missing_docs)] // criterion_group! generates undocumented functions.

use std::hint::black_box;

use criterion::{Criterion, criterion_group, criterion_main};
use orbifold::layout::{Layout, LayoutOptions, Shape};
use orbifold::pairing::FundamentalPolygon;
use orbifold::{OrbifoldSymbol, Order, Signature};

fn layouts(c: &mut Criterion) {
    let hundred = Signature::new((0..100).map(|i| Order::integer(2 + i % 7))).unwrap();
    let seed: Signature = "*23456789(10)(11)".parse().unwrap();
    let cases = [
        ("*23456789(10)(11) default", &seed, Shape::Default),
        ("*23456789(10)(11) incircle", &seed, Shape::Incircle),
        ("100-gon default", &hundred, Shape::Default),
        ("100-gon incircle", &hundred, Shape::Incircle),
    ];
    for (name, sig, shape) in cases {
        let options = LayoutOptions {
            shape,
            ..LayoutOptions::default()
        };
        c.bench_function(&format!("layout {name}"), |b| {
            b.iter(|| Layout::new(black_box(sig), &options).unwrap())
        });
    }
    let triangle: Signature = "*237".parse().unwrap();
    c.bench_function("layout *237", |b| {
        b.iter(|| Layout::new(black_box(&triangle), &LayoutOptions::default()).unwrap())
    });
}

/// The hyperbolic star: its default (which chooses the words) and deformed to every parameter
/// (docs/orbifolds.md, "Shape parameters of the star").
fn deformed_stars(c: &mut Criterion) {
    for name in ["oo", "o*2", "2223"] {
        let symbol: OrbifoldSymbol = name.parse().unwrap();
        let star = FundamentalPolygon::new(&symbol, &LayoutOptions::default()).unwrap();
        c.bench_function(&format!("polygon {name} default"), |b| {
            b.iter(|| FundamentalPolygon::new(black_box(&symbol), &LayoutOptions::default()))
        });
        let factors = (0..star.parameters.len())
            .map(|k| if k % 2 == 0 { 0.981 } else { 1.019 })
            .collect();
        let options = LayoutOptions {
            shape: Shape::Parameters(factors),
            ..LayoutOptions::default()
        };
        c.bench_function(&format!("polygon {name} deformed"), |b| {
            b.iter(|| FundamentalPolygon::new(black_box(&symbol), &options).unwrap())
        });
    }
}

criterion_group!(benches, layouts, deformed_stars);
criterion_main!(benches);
