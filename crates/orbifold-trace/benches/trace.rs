//! Benchmarks of the curved-ray tracing core. Run with `cargo bench -p orbifold-trace --bench trace`.
//!
//! - `room exit`: where a camera ray leaves the analytic room (closed form).
//! - `follow`: a ray through up to 16 mirror reflections (or portal crossings, in the rooms of
//!   `632`, `22×`, `2223` and `oo`, whose walls are portals).
//! - `bvh build` and `bvh traverse`: a model of `../shared/models/` (the teapot and the bunny when
//!   present, else the built-in torus), embedded 1 unit across, with the 89,644 rays of the seed's
//!   Table 8.2, single-threaded; κ = 0 is the same code with straight rays.
#![allow(missing_docs)] // criterion_group! generates undocumented functions.

#[path = "table_rays/mod.rs"]
mod table_rays;

use std::hint::black_box;

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use orbifold::space::Space;
use orbifold::{Geometry, Layout, LayoutOptions};
use orbifold_scene::Camera as CameraSettings;
use orbifold_scene::mesh::procedural::builtin;
use orbifold_trace::accel::Bvh;
use orbifold_trace::camera::Camera;
use orbifold_trace::tracer::Tracer;

fn camera_rays(tracer: &Tracer, n: u32) -> Vec<orbifold_trace::geodesic::Ray> {
    let c = tracer.layout.centre;
    let settings = CameraSettings {
        at: [c.re, c.im],
        pitch: 10.0,
        ..CameraSettings::default()
    };
    let camera = Camera::new(tracer.space(), &settings);
    (0..n * n)
        .map(|k| camera.ray(k % n, k / n, n, n, (0.5, 0.5)))
        .collect()
}

fn rooms(c: &mut Criterion) {
    let mut group = c.benchmark_group("room");
    for sig in [
        "*2222",
        "*333",
        "*235",
        "*2223",
        "*∞∞∞",
        "*23456789(10)(11)",
        "632",
        "22×",
        "2223",
        "oo",
    ] {
        let layout = Layout::of_symbol(&sig.parse().unwrap(), &LayoutOptions::default()).unwrap();
        let tracer = Tracer::mirror_room(layout, 1.0).unwrap();
        let rays = camera_rays(&tracer, 64);
        group.throughput(Throughput::Elements(rays.len() as u64));
        group.bench_function(format!("exit {sig}"), |b| {
            b.iter(|| rays.iter().filter_map(|r| tracer.room.exit(r)).count())
        });
        group.bench_function(format!("follow 16 bounces {sig}"), |b| {
            b.iter(|| {
                rays.iter()
                    .map(|r| tracer.follow(black_box(r), 16).hits.len())
                    .sum::<usize>()
            })
        });
    }
    group.finish();
}

fn hierarchies(c: &mut Criterion) {
    let models: Vec<(String, orbifold_scene::mesh::TriangleMesh)> =
        ["teapot.obj", "bunny.obj", "dragon.ply"]
            .iter()
            .filter_map(|n| table_rays::load(n).map(|m| (n.to_string(), m)))
            .collect();
    let models = if models.is_empty() {
        vec![("torus".to_string(), builtin("torus").unwrap())]
    } else {
        models
    };
    let mut group = c.benchmark_group("bvh");
    group.sample_size(10);
    for (name, mesh) in &models {
        for geometry in [
            Geometry::Spherical,
            Geometry::Euclidean,
            Geometry::Hyperbolic,
        ] {
            let space = Space::new(geometry);
            let (points, heights) = table_rays::embedded(space, mesh);
            let label = format!("{name} {geometry:?}");
            group.throughput(Throughput::Elements(mesh.triangles.len() as u64));
            group.bench_function(format!("build {label}"), |b| {
                b.iter(|| Bvh::build(space, &points, &heights, &mesh.triangles))
            });
            let bvh = Bvh::build(space, &points, &heights, &mesh.triangles);
            let top = heights.iter().copied().fold(0.0, f64::max);
            let rays = table_rays::rays(space, top);
            group.throughput(Throughput::Elements(rays.len() as u64));
            group.bench_function(format!("traverse {label}"), |b| {
                b.iter(|| {
                    rays.iter()
                        .filter(|r| bvh.intersect(space, r, 0.0, f64::INFINITY).is_some())
                        .count()
                })
            });
        }
    }
    group.finish();
}

criterion_group!(benches, rooms, hierarchies);
criterion_main!(benches);
