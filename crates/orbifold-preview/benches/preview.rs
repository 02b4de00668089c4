//! Preview frame time against depth (copies drawn) and triangle count, on whatever adapter
//! `Gpu::headless` finds (a software one without a GPU). Each sample draws one frame and waits
//! for the GPU. `cargo run --release -p orbifold-preview --example frame_table` prints the
//! table of docs/benchmarks.md.
#![allow(missing_docs)] // criterion_group! generates undocumented functions.

use criterion::{BenchmarkId, Criterion, criterion_group, criterion_main};
use orbifold_preview::{Gpu, Preview};
use orbifold_scene::Scene;

fn scene(signature: &str, depth: u32) -> Scene {
    let mut scene = Scene::default();
    scene.orbifold.signature = signature.into();
    scene.preview.depth = depth;
    let centre = scene.layout().expect("a good signature").centre;
    scene.objects[0].at = [centre.re, centre.im];
    scene.camera.at = [centre.re - 0.1, centre.im];
    scene
}

fn frames(c: &mut Criterion) {
    let gpu = match Gpu::headless() {
        Ok(gpu) => gpu,
        Err(e) => {
            eprintln!("no adapter, nothing measured: {e}");
            return;
        }
    };
    eprintln!("adapter: {}", gpu.describe());
    let mut preview = Preview::new(gpu);
    let mut group = c.benchmark_group("preview frame 640x480");
    group.sample_size(10);
    for (signature, depth) in [
        ("*22222", 2),
        ("*22222", 4),
        ("*22222", 6),
        ("*235", 0),
        ("*333", 8),
    ] {
        preview
            .load(&scene(signature, depth), None)
            .expect("the scene loads");
        preview.draw(640, 480).expect("a frame");
        let triangles = preview.stats().triangles;
        let id = BenchmarkId::new(signature, format!("depth {depth}, {triangles} triangles"));
        group.bench_function(id, |b| {
            b.iter(|| {
                // A moved camera rewrites the copies' matrices, as in the studio.
                let mut camera = scene(signature, depth).camera;
                camera.yaw += 1.0;
                preview.set_camera(&camera);
                preview.draw(640, 480).expect("a frame");
                preview.finish().expect("the GPU finishes");
            })
        });
    }
    group.finish();
    read_back(c, &mut preview);
    patterns(c, &mut preview);
}

/// A frame read back to the CPU, as the studio shows it: the colours alone against the colours
/// and the surface ids.
fn read_back(c: &mut Criterion, preview: &mut Preview) {
    let mut group = c.benchmark_group("preview read back 640x480");
    group.sample_size(10);
    preview
        .load(&scene("*22222", 4), None)
        .expect("the scene loads");
    group.bench_function("*22222 depth 4, colours", |b| {
        b.iter(|| preview.render_colors(640, 480).expect("a frame"))
    });
    group.bench_function("*22222 depth 4, colours and ids", |b| {
        b.iter(|| preview.render(640, 480).expect("a frame"))
    });
    group.finish();
}

/// The floor's pattern: one colour, a checkerboard (a floor and a parity), or marble (six
/// octaves of gradient noise, 144 hashes a pixel, in 64-bit arithmetic on 32-bit integers).
fn patterns(c: &mut Criterion, preview: &mut Preview) {
    use orbifold_scene::Material;
    let mut group = c.benchmark_group("preview frame 640x480, the floor's pattern");
    group.sample_size(10);
    let floors = [
        ("one colour", Material::Color { color: [0.8; 3] }),
        (
            "checkerboard",
            Material::Checker {
                colors: [[0.9; 3], [0.2; 3]],
                size: 0.1,
                coordinates: Default::default(),
            },
        ),
        (
            "marble",
            Material::Marble {
                base: [0.9, 0.9, 0.85],
                vein: [0.2, 0.25, 0.3],
                scale: 0.2,
                coordinates: Default::default(),
            },
        ),
    ];
    for (name, floor) in floors {
        let mut scene = scene("*22222", 2);
        scene.room.floor = floor;
        // Looking down: the floor fills most of the picture.
        scene.camera.pitch = -60.0;
        preview.load(&scene, None).expect("the scene loads");
        group.bench_function(format!("*22222 depth 2, {name}"), |b| {
            b.iter(|| {
                preview.draw(640, 480).expect("a frame");
                preview.finish().expect("the GPU finishes");
            })
        });
    }
    group.finish();
}

criterion_group!(benches, frames);
criterion_main!(benches);
