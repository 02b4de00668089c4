//! Benchmarks of the signature hot paths: reading, canonical form, χ, classification and
//! enumeration. Run with `cargo bench -p orbifold --bench signature`.

#![allow(missing_docs)] // criterion_group! generates undocumented functions.

use std::hint::black_box;

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use orbifold::{Enumeration, EnumerationOptions, Geometry, OrbifoldSymbol, Signature};

const LONG: &str = "*(11)23456789(10)";

fn signatures(c: &mut Criterion) {
    let sig: Signature = LONG.parse().unwrap();
    c.bench_function("parse *(11)23456789(10)", |b| {
        b.iter(|| black_box(LONG).parse::<Signature>().unwrap())
    });
    c.bench_function("canonical 10 corners", |b| {
        b.iter(|| black_box(&sig).canonical())
    });
    c.bench_function("euler_characteristic 10 corners", |b| {
        b.iter(|| black_box(&sig).euler_characteristic())
    });
    c.bench_function("classify 10 corners (kind, geometry, family)", |b| {
        b.iter(|| {
            let s = black_box(&sig);
            (s.kind(), s.geometry(), s.family().map(|f| f.pattern))
        })
    });
    let conway: OrbifoldSymbol = "2*2(12)3*45×".parse().unwrap();
    c.bench_function("canonical Conway 2*2(12)3*45×", |b| {
        b.iter(|| black_box(&conway).canonical())
    });
}

fn enumeration(c: &mut Criterion) {
    let mut group = c.benchmark_group("enumerate");
    for (corners, max_order) in [(3, 40), (6, 7), (8, 5)] {
        let options = EnumerationOptions {
            corners,
            max_order,
            ideal: true,
            geometry: None,
        };
        let count = Enumeration::new(options.clone()).unwrap().count() as u64;
        group.throughput(Throughput::Elements(count));
        group.bench_function(
            format!("N={corners} K={max_order} +∞ ({count} orbifolds)"),
            |b| {
                b.iter(|| {
                    Enumeration::new(options.clone())
                        .unwrap()
                        .filter(|s| s.geometry() == Geometry::Hyperbolic)
                        .count()
                })
            },
        );
    }
    group.finish();
}

criterion_group!(benches, signatures, enumeration);
criterion_main!(benches);
