//! Benchmarks of room tessellation. Run with `cargo bench -p orbifold --bench room`.
#![allow(missing_docs)] // criterion_group! generates undocumented functions.

use std::hint::black_box;

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use orbifold::room::{FloorMethod, RoomMesher, RoomOptions};
use orbifold::{Layout, LayoutOptions, Signature};

fn floors(c: &mut Criterion) {
    let mut group = c.benchmark_group("room floor");
    group.sample_size(20);
    for sig in ["*2223", "*22222", "*∞∞∞", "*23456789(10)(11)", "*235"] {
        let s: Signature = sig.parse().unwrap();
        let layout = Layout::new(&s, &LayoutOptions::default()).unwrap();
        for (method, name) in [
            (FloorMethod::Contour, "contour"),
            (FloorMethod::Geodesic, "geodesic"),
        ] {
            let options = RoomOptions {
                resolution: 0.02,
                method,
                ..RoomOptions::default()
            };
            let mesher = RoomMesher::new(&layout, &options).unwrap();
            let triangles = mesher.floor().triangles.len() as u64;
            group.throughput(Throughput::Elements(triangles));
            group.bench_function(
                format!("{sig} {name} L=0.02 ({triangles} triangles)"),
                |b| b.iter(|| black_box(&mesher).floor()),
            );
        }
    }
    group.finish();
}

fn walls(c: &mut Criterion) {
    let s: Signature = "*22222".parse().unwrap();
    let layout = Layout::new(&s, &LayoutOptions::default()).unwrap();
    let mesher = RoomMesher::new(
        &layout,
        &RoomOptions {
            resolution: 0.02,
            ..RoomOptions::default()
        },
    )
    .unwrap();
    let triangles: usize = (0..5)
        .map(|i| mesher.whole_wall(i).unwrap().triangles.len())
        .sum();
    let mut group = c.benchmark_group("room walls");
    group.throughput(Throughput::Elements(triangles as u64));
    group.bench_function(
        format!("*22222 all walls L=0.02 ({triangles} triangles)"),
        |b| {
            b.iter(|| {
                (0..5)
                    .map(|i| black_box(&mesher).whole_wall(i).unwrap().triangles.len())
                    .sum::<usize>()
            })
        },
    );
    group.finish();
}

criterion_group!(benches, floors, walls);
criterion_main!(benches);
