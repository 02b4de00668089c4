//! Benchmarks of the renderer. Run with `cargo bench -p orbifold-render --bench render`.
//!
//! One pass (one path per pixel) of a 64×48 image from the scene's camera, all threads: the
//! built-in default room `*22222` (H²×R, every wall a mirror of reflectance 0.9, a figure and a
//! point light), and the default rooms of a spherical and a Euclidean orbifold. The denoiser
//! over a 256×256 image of the default room (8 samples a pixel), which adaptive sampling for a
//! denoised image also runs at rounds 4, 8, 16, …. The pixel footprint's test of a sphere light
//! along one straight stretch of a camera ray (`footprint::sphere_coverage`, run for every
//! stretch between mirrors), over 1 024 rays in each geometry. The radiance cache: 16 passes
//! of the default room with and without it (the cache is read from the second pass on), and
//! adding and looking up 100 000 estimates. One round of a 896×896 image added to the film and
//! the guides under the box and the Gaussian pixel filter.
#![allow(missing_docs)] // criterion_group! generates undocumented functions.

use std::sync::atomic::AtomicBool;

use criterion::measurement::WallTime;
use criterion::{BenchmarkGroup, Criterion, Throughput, criterion_group, criterion_main};
use glam::DVec3;
use orbifold::Geometry;
use orbifold::space::Space;
use orbifold_render::denoise::{DenoiseOptions, Guides, denoise_with_reduction};
use orbifold_render::film::PixelFilter;
use orbifold_render::film::{Film, Splat};
use orbifold_render::integrator::{FirstHit, Integrator, Settings};
use orbifold_render::radiance_cache::{Deposit, RadianceCache};
use orbifold_render::render::{RenderOptions, render};
use orbifold_render::sampler::Sampler;
use orbifold_scene::Scene;
use orbifold_trace::camera::Camera;
use orbifold_trace::footprint::{Footprint, Glimpse, Sphere, sphere_coverage};
use orbifold_trace::geodesic::Ray;

fn default_room(signature: &str) -> Scene {
    let mut scene = Scene::default();
    scene.orbifold.signature = signature.into();
    let layout = scene.layout().unwrap();
    let centre = [layout.centre.re, layout.centre.im];
    scene.objects.iter_mut().for_each(|o| o.at = centre);
    scene.lights.iter_mut().for_each(|l| l.at = centre);
    // Three quarters of the way to the wall on the −x side, as `orbifold scene new` does.
    scene.camera.at = [centre[0] - 0.15, centre[1]];
    scene
}

/// Benchmarks `passes` passes of a 64×48 image of `signature`'s default room, every pixel alike.
fn bench_passes(
    group: &mut BenchmarkGroup<'_, WallTime>,
    name: &str,
    signature: &str,
    settings: Settings,
    passes: u32,
) {
    let scene = default_room(signature);
    let integrator = Integrator::from_scene(&scene, None, settings).unwrap();
    let camera = Camera::new(integrator.space(), &scene.camera);
    let options = RenderOptions {
        adaptive: false,
        ..RenderOptions::new(64, 48, passes, 1)
    };
    group.throughput(Throughput::Elements(64 * 48 * u64::from(passes)));
    group.bench_function(name, |b| {
        b.iter(|| {
            render(
                &integrator,
                &camera,
                &options,
                &AtomicBool::new(false),
                &|_, _| {},
            )
        })
    });
}

fn passes(c: &mut Criterion) {
    let mut group = c.benchmark_group("render");
    group.sample_size(10);
    for signature in ["*22222", "*235", "*333"] {
        let name = format!("pass 64x48 {signature}");
        bench_passes(&mut group, &name, signature, Settings::default(), 1);
    }
    group.finish();
}

fn cached_passes(c: &mut Criterion) {
    let mut group = c.benchmark_group("render");
    group.sample_size(10);
    for (name, radiance_cache) in [("cached", true), ("in full", false)] {
        let settings = Settings {
            radiance_cache,
            ..Settings::default()
        };
        let name = format!("16 passes 64x48 *22222 {name}");
        bench_passes(&mut group, &name, "*22222", settings, 16);
    }
    group.finish();
}

fn radiance_cache(c: &mut Criterion) {
    let mut group = c.benchmark_group("render");
    // Estimates on the floor and two walls of a unit room in E², as a render deposits them.
    let deposits: Vec<Deposit> = (0..100_000)
        .map(|i| {
            let t = f64::from(i);
            let (u, v) = ((t * 0.618_034).fract(), (t * 0.754_877).fract());
            let (point, height, facing) = match i % 3 {
                0 => (DVec3::new(u, v, 1.0), 0.0, 6),
                1 => (DVec3::new(0.0, u, 1.0), v, 0),
                _ => (DVec3::new(u, 0.0, 1.0), v, 2),
            };
            Deposit {
                point,
                height,
                facing,
                total: [u, v, 0.5],
            }
        })
        .collect();
    group.throughput(Throughput::Elements(deposits.len() as u64));
    group.bench_function("radiance cache add 100k", |b| {
        b.iter(|| {
            let mut cache = RadianceCache::new();
            cache.add_all(&deposits);
            cache.cells()
        })
    });
    let mut cache = RadianceCache::new();
    cache.add_all(&deposits);
    let floor = [(DVec3::X, 0.0), (DVec3::Y, 0.0)];
    group.bench_function("radiance cache lookup 100k", |b| {
        b.iter(|| {
            deposits
                .iter()
                .filter_map(|d| cache.lookup(d.point, d.height, d.facing, 0.05, floor, [0.3, 0.7]))
                .map(|c| c[0])
                .sum::<f64>()
        })
    });
    group.finish();
}

fn denoiser(c: &mut Criterion) {
    let mut group = c.benchmark_group("render");
    group.sample_size(10);
    let scene = default_room("*22222");
    let integrator = Integrator::from_scene(&scene, None, Settings::default()).unwrap();
    let camera = Camera::new(integrator.space(), &scene.camera);
    let options = RenderOptions::new(256, 256, 8, 1);
    let image = render(
        &integrator,
        &camera,
        &options,
        &AtomicBool::new(false),
        &|_, _| {},
    );
    group.throughput(Throughput::Elements(256 * 256));
    group.bench_function("denoise 256x256", |b| {
        b.iter(|| denoise_with_reduction(&image.film, &image.guides, &DenoiseOptions::default()))
    });
    group.finish();
}

fn footprint(c: &mut Criterion) {
    let mut group = c.benchmark_group("render");
    let footprint = Footprint {
        across: 2e-3,
        up: 2e-3,
        centre: [0.0; 2],
    };
    for (name, geometry) in [
        ("S2", Geometry::Spherical),
        ("E2", Geometry::Euclidean),
        ("H2", Geometry::Hyperbolic),
    ] {
        let space = Space::new(geometry);
        // Rays from points of a small disc in every direction, slightly tilted.
        let rays: Vec<Ray> = (0..1024)
            .map(|i| {
                let t = f64::from(i);
                let z = num_complex::Complex64::from_polar(0.3 * (t * 0.618).fract(), t * 2.4);
                Ray::from_model(space, z, 0.5, t * 0.37, 0.2 * (t * 0.31).sin())
            })
            .collect();
        let centre = space.to_ambient(num_complex::Complex64::new(0.05, -0.02));
        let sphere = Sphere::new(space, centre, 0.85, 0.05, 0.4, 0.15);
        group.throughput(Throughput::Elements(rays.len() as u64));
        group.bench_function(format!("sphere coverage {name}"), |b| {
            b.iter(|| {
                rays.iter()
                    .map(|ray| {
                        match sphere_coverage(space, ray, 3.0, &footprint, &sphere, 1.0, 0.0) {
                            Glimpse::Covered(share) => share,
                            Glimpse::Unresolved => 0.0,
                        }
                    })
                    .sum::<f64>()
            })
        });
    }
    group.finish();
}

/// One round of a 896×896 image added to the film and the denoiser's guides (802 816 samples,
/// one a pixel) and the pixels filtered afresh, with each filter.
fn splatting(c: &mut Criterion) {
    let mut group = c.benchmark_group("render");
    group.sample_size(10);
    let size = 896u32;
    let samples: Vec<(Splat, FirstHit)> = (0..size * size)
        .map(|p| {
            let mut s = Sampler::stratified(1, u64::from(p), 0);
            let splat = Splat {
                x: p % size,
                y: p / size,
                radiance: [s.next_f64(), 0.5, 0.25],
            };
            let first = FirstHit {
                albedo: [0.5; 3],
                normal: DVec3::Z,
                depth: 1.0 + s.next_f64(),
                emitted: [0.0; 3],
                direct: [0.1; 3],
            };
            (splat, first)
        })
        .collect();
    let splats: Vec<Splat> = samples.iter().map(|(s, _)| *s).collect();
    group.throughput(Throughput::Elements(u64::from(size * size)));
    for (name, filter) in [
        ("box", PixelFilter::Box),
        ("gaussian", PixelFilter::GAUSSIAN),
    ] {
        group.bench_function(format!("splat 896x896 {name}"), |b| {
            let (mut film, mut guides) = (Film::new(size, size), Guides::new(size, size));
            b.iter(|| {
                film.splat_all(&splats, filter);
                guides.splat_all(&samples, filter);
            })
        });
    }
    group.finish();
}

criterion_group!(
    benches,
    passes,
    cached_passes,
    radiance_cache,
    denoiser,
    splatting,
    footprint
);
criterion_main!(benches);
