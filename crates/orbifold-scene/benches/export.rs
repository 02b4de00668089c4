//! Benchmarks of mesh export: smooth vertex normals and the three formats, for the default
//! scene's room and for a room with its copies. Run with `cargo bench -p orbifold-scene --bench
//! export`.
#![allow(missing_docs)] // criterion_group! generates undocumented functions.

use std::hint::black_box;

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use orbifold::cover::{Bound, Cover};
use orbifold_scene::Scene;
use orbifold_scene::export::{smooth_normals, to_glb, to_obj, to_ply};
use orbifold_scene::geometry::MeshGroup;

/// The default scene's room and objects, and with `depth > 0` its copies up to that depth.
fn groups(depth: usize) -> Vec<MeshGroup> {
    let scene = Scene::default();
    let geometry = scene.geometry(None).expect("the default scene meshes");
    let cover = Cover::enumerate_layout(geometry.layout.clone(), Bound::Depth(depth), true)
        .expect("the cover is enumerated");
    geometry.groups(&cover.tiles).0
}

fn export(c: &mut Criterion) {
    let mut group = c.benchmark_group("export");
    group.sample_size(10);
    for depth in [0, 2] {
        let groups = groups(depth);
        let triangles: usize = groups.iter().map(|g| g.triangles.len()).sum();
        group.throughput(Throughput::Elements(triangles as u64));
        let what = format!("depth {depth} ({triangles} triangles)");
        group.bench_function(format!("smooth normals, {what}"), |b| {
            b.iter(|| {
                black_box(&groups)
                    .iter()
                    .map(|g| smooth_normals(g).positions.len())
                    .sum::<usize>()
            })
        });
        group.bench_function(format!("OBJ, {what}"), |b| {
            b.iter(|| to_obj(black_box(&groups), "room.mtl", "bench").len())
        });
        group.bench_function(format!("PLY, {what}"), |b| {
            b.iter(|| to_ply(black_box(&groups), "bench").len())
        });
        group.bench_function(format!("GLB, {what}"), |b| {
            b.iter(|| to_glb(black_box(&groups), "bench").len())
        });
    }
    group.finish();
}

criterion_group!(benches, export);
criterion_main!(benches);
