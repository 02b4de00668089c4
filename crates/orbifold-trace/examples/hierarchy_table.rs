//! Reproduces the seed's Table 8.2 with its method, and its Table 8.1 comparison of the analytic
//! room against tessellated rooms, printing Markdown tables for `docs/benchmarks.md`.
//!
//! ```sh
//! cargo run --release -p orbifold-trace --example hierarchy_table
//! # one model, without the room table:
//! cargo run --release -p orbifold-trace --example hierarchy_table -- buddha.obj --no-room
//! ```
//!
//! Table 8.2: for each model of `../shared/models/` that is present, embedded 1 unit across at
//! the origin, 146 locations × 614 rays (89,644 rays): BVH depth, build time (one thread, and all
//! threads), intersections found, and single-threaded traversal time per ray, in S²×R and H²×R
//! and through the same code with κ = 0 (straight rays), with the ratio curved / straight.
#![allow(missing_docs)]

#[path = "../benches/table_rays/mod.rs"]
mod table_rays;

use std::time::Instant;

use orbifold::space::Space;
use orbifold::{Geometry, Layout, LayoutOptions};
use orbifold_scene::Scene;
use orbifold_trace::accel::Bvh;
use orbifold_trace::camera::Camera;
use orbifold_trace::room::AnalyticRoom;

struct Measured {
    depth: usize,
    build_one_ms: f64,
    build_all_ms: f64,
    hits: usize,
    per_ray_us: f64,
}

fn measure(space: Space, mesh: &orbifold_scene::mesh::TriangleMesh) -> Measured {
    let (points, heights) = table_rays::embedded(space, mesh);
    let one = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .expect("a thread pool");
    let start = Instant::now();
    let bvh = one.install(|| Bvh::build(space, &points, &heights, &mesh.triangles));
    let build_one_ms = start.elapsed().as_secs_f64() * 1e3;
    let start = Instant::now();
    let again = Bvh::build(space, &points, &heights, &mesh.triangles);
    let build_all_ms = start.elapsed().as_secs_f64() * 1e3;
    drop(again);
    let top = heights.iter().copied().fold(0.0, f64::max);
    let rays = table_rays::rays(space, top);
    // Best of three passes, single-threaded.
    let mut best = f64::INFINITY;
    let mut hits = 0;
    for _ in 0..3 {
        let start = Instant::now();
        hits = rays
            .iter()
            .filter(|r| bvh.intersect(space, r, 0.0, f64::INFINITY).is_some())
            .count();
        best = best.min(start.elapsed().as_secs_f64());
    }
    Measured {
        depth: bvh.depth(),
        build_one_ms,
        build_all_ms,
        hits,
        per_ray_us: best * 1e6 / rays.len() as f64,
    }
}

fn hierarchy_table(only: &[String]) {
    let Some(dir) = table_rays::models_dir() else {
        println!("(no ../shared/models: Table 8.2 skipped)");
        return;
    };
    println!("Models from {}\n", dir.display());
    println!(
        "| model | triangles | space | depth | build 1 thread (ms) | build all threads (ms) | intersections | µs/ray | straight µs/ray | curved/straight |"
    );
    println!("|---|---:|---|---:|---:|---:|---:|---:|---:|---:|");
    for name in table_rays::MODELS {
        if !only.is_empty() && !only.iter().any(|o| o == name) {
            continue;
        }
        let Some(mesh) = table_rays::load(name) else {
            println!("| {name} | missing | | | | | | | | |");
            continue;
        };
        let straight = measure(Space::new(Geometry::Euclidean), &mesh);
        for (label, geometry) in [
            ("S²×R", Geometry::Spherical),
            ("H²×R", Geometry::Hyperbolic),
        ] {
            let m = measure(Space::new(geometry), &mesh);
            println!(
                "| {name} | {} | {label} | {} | {:.0} | {:.0} | {} | {:.2} | {:.2} | {:.2} |",
                mesh.triangles.len(),
                m.depth,
                m.build_one_ms,
                m.build_all_ms,
                m.hits,
                m.per_ray_us,
                straight.per_ray_us,
                m.per_ray_us / straight.per_ray_us
            );
        }
        println!(
            "| {name} | {} | E²×R | {} | {:.0} | {:.0} | {} | {:.2} | {:.2} | 1.00 |",
            mesh.triangles.len(),
            straight.depth,
            straight.build_one_ms,
            straight.build_all_ms,
            straight.hits,
            straight.per_ray_us,
            straight.per_ray_us
        );
    }
}

/// Seed Table 8.1's question: the analytic room against the same room meshed at three
/// resolutions, for the camera rays of a 256×256 image from the scene's camera (first surface
/// hit only: the cost of finding where a ray leaves the room).
fn room_table() {
    println!("\n| room | analytic ns/ray | meshed L=0.2: triangles, ns/ray | L=0.1 | L=0.05 |");
    println!("|---|---:|---:|---:|---:|");
    for sig in ["*22", "*222", "*333", "*444", "*2222", "*3333"] {
        let mut scene = Scene::default();
        scene.orbifold.signature = sig.to_string();
        scene.objects.clear();
        let layout = Layout::new(&sig.parse().unwrap(), &LayoutOptions::default()).unwrap();
        scene.camera.at = [layout.centre.re, layout.centre.im];
        let space = layout.space();
        let room = AnalyticRoom::from_scene(&scene, &layout).unwrap();
        let camera = Camera::new(space, &scene.camera);
        let n = 256;
        let rays: Vec<_> = (0..n * n)
            .map(|k| camera.ray(k % n, k / n, n, n, (0.5, 0.5)))
            .collect();
        let time = |f: &dyn Fn() -> usize| {
            let mut best = f64::INFINITY;
            for _ in 0..3 {
                let start = Instant::now();
                std::hint::black_box(f());
                best = best.min(start.elapsed().as_secs_f64());
            }
            best * 1e9 / rays.len() as f64
        };
        let analytic = time(&|| rays.iter().filter(|r| room.exit(r).is_some()).count());
        let mut row = format!("| {sig} | {analytic:.0} |");
        for resolution in [0.2, 0.1, 0.05] {
            scene.room.resolution = resolution;
            let geometry = scene.geometry(None).unwrap();
            let mut points = Vec::new();
            let mut heights = Vec::new();
            let mut triangles = Vec::new();
            for part in &geometry.parts {
                let base = points.len() as u32;
                points.extend_from_slice(&part.surface.points);
                heights.extend_from_slice(&part.surface.heights);
                triangles.extend(part.surface.triangles.iter().map(|t| t.map(|i| i + base)));
            }
            let bvh = Bvh::build(space, &points, &heights, &triangles);
            let meshed = time(&|| {
                rays.iter()
                    .filter(|r| bvh.intersect(space, r, 1e-9, f64::INFINITY).is_some())
                    .count()
            });
            row += &format!(" {}, {meshed:.0} |", triangles.len());
        }
        println!("{row}");
    }
}

/// Arguments: model file names to measure (all by default); `--no-room` skips Table 8.1.
fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let models: Vec<String> = args
        .iter()
        .filter(|a| !a.starts_with("--"))
        .cloned()
        .collect();
    hierarchy_table(&models);
    if !args.iter().any(|a| a == "--no-room") {
        room_table();
    }
}
