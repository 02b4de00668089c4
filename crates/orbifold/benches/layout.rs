//! Benchmarks of polygon layout. Run with `cargo bench -p orbifold --bench layout`.
#![allow(missing_docs)] // criterion_group! generates undocumented functions.

use std::hint::black_box;

use criterion::{Criterion, criterion_group, criterion_main};
use orbifold::layout::{Layout, LayoutOptions, Shape};
use orbifold::{Order, Signature};

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

criterion_group!(benches, layouts);
criterion_main!(benches);
