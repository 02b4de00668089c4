//! Adaptive sampling without bias: with it on (the default), the raw image's mean equals the
//! mean with every pixel sampled alike, within the standard error over many seeds, at 8, 16 and
//! 64 samples a pixel — in a furnace (emitting white surfaces, every path's value set by the
//! bounces it survives) and in a uniform grey room lit by a point light.
//!
//! Each seed renders both ways; the two renders share every pixel's stratified sequence, so
//! their difference varies far less than either image, and a bias like the old sampler's (0.4 %
//! dark at 16 samples a pixel, from choosing a pixel's samples by the values whose mean is
//! shown) stands out by many standard errors even over 16 seeds of a small image
//! (`docs/benchmarks.md` gives the finer measurement, in release builds of a larger image).

use orbifold_render::film::Film;
use orbifold_render::integrator::Settings;
use orbifold_render::orbifold_scene::color::luminance;
use orbifold_render::render::{RenderOptions, render_scene};
use orbifold_scene::{LightKind, Material, MirrorDefault, Scene};

const ALBEDO: f64 = 0.5;

/// A closed room of `signature` whose surfaces are all white of albedo `ALBEDO` and glow, no
/// lights, no mirrors (the furnace of `tests/materials.rs`).
fn furnace(signature: &str) -> Scene {
    let mut scene = grey_room(signature, ALBEDO);
    scene.lights.clear();
    scene
}

/// A room of `signature` whose walls, floor, ceiling and figure are all grey of `albedo`, with
/// a point light at its centre and the camera looking across it.
fn grey_room(signature: &str, albedo: f64) -> Scene {
    let mut scene = Scene::default();
    scene.orbifold.signature = signature.into();
    let layout = scene.layout().unwrap();
    let c = [layout.centre.re, layout.centre.im];
    let grey = Material::Color { color: [albedo; 3] };
    scene.room.mirrors = MirrorDefault::None;
    scene.room.wall_material = grey.clone();
    scene.room.floor = grey.clone();
    scene.room.ceiling = grey.clone();
    scene.walls.clear();
    for object in &mut scene.objects {
        object.at = c;
        object.material = grey.clone();
    }
    scene.lights.truncate(1);
    scene.lights[0].kind = LightKind::Point;
    scene.lights[0].at = [c[0] + 0.15, c[1] + 0.1];
    scene.lights[0].height = 0.7;
    scene.lights[0].power = 10.0;
    scene.camera.at = [c[0] - 0.2, c[1]];
    scene.camera.pitch = -15.0;
    scene.camera.fov = 100.0;
    scene
}

fn mean_luminance(film: &Film) -> f64 {
    let (w, h) = (film.width(), film.height());
    let sum: f64 = (0..h)
        .flat_map(|y| (0..w).map(move |x| (x, y)))
        .map(|(x, y)| luminance(film.pixel(x, y)))
        .sum();
    sum / f64::from(w * h)
}

/// The mean and standard error of `values`.
fn mean_and_error(values: &[f64]) -> (f64, f64) {
    let n = values.len() as f64;
    let mean = values.iter().sum::<f64>() / n;
    let variance = values.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / (n - 1.0);
    (mean, (variance / n).sqrt())
}

/// Over `seeds`, the adaptive render's mean luminance less the uniform one's is zero within 4
/// standard errors; returns the relative difference and its standard error.
fn assert_adaptive_mean_is_unbiased(
    scene: &Scene,
    settings: Settings,
    samples: u32,
    seeds: u64,
    what: &str,
) -> (f64, f64) {
    let render = |seed: u64, adaptive: bool| {
        let options = RenderOptions {
            adaptive,
            ..RenderOptions::new(16, 12, samples, seed)
        };
        let rendered = render_scene(scene, None, settings, &options).unwrap();
        assert_eq!(rendered.paths, u64::from(samples) * 16 * 12);
        mean_luminance(&rendered.film)
    };
    let (mut differences, mut uniform) = (Vec::new(), Vec::new());
    for seed in 0..seeds {
        let plain = render(seed, false);
        differences.push(render(seed, true) - plain);
        uniform.push(plain);
    }
    let (level, _) = mean_and_error(&uniform);
    let (difference, error) = mean_and_error(&differences);
    let (relative, relative_error) = (difference / level, error / level);
    eprintln!(
        "{what}, {samples} spp: adaptive minus uniform {:+.4} ± {:.4} %",
        100.0 * relative,
        100.0 * relative_error
    );
    assert!(
        relative.abs() < 4.0 * relative_error,
        "{what}, {samples} samples a pixel: adaptive minus uniform {:+.3} ± {:.3} %",
        100.0 * relative,
        100.0 * relative_error
    );
    (relative, relative_error)
}

fn traced_in_full(max_depth: u32) -> Settings {
    Settings {
        max_depth,
        radiance_cache: false,
        ..Settings::default()
    }
}

#[test]
fn adaptive_sampling_keeps_the_furnace_mean() {
    let settings = Settings {
        glow: [0.25; 3],
        ..traced_in_full(12)
    };
    let scene = furnace("*2222");
    for samples in [8, 16, 64] {
        let (_, error) =
            assert_adaptive_mean_is_unbiased(&scene, settings, samples, 16, "*2222 furnace");
        // The test can see a bias as large as the old one.
        assert!(error < 0.3e-2, "{samples} spp: standard error {error}");
    }
}

#[test]
fn adaptive_sampling_keeps_the_mean_of_a_room_lit_by_a_point_light() {
    let scene = grey_room("*2222", 0.6);
    for samples in [8, 16, 64] {
        let (_, error) = assert_adaptive_mean_is_unbiased(
            &scene,
            traced_in_full(4),
            samples,
            16,
            "*2222 grey room with a point light",
        );
        assert!(error < 0.3e-2, "{samples} spp: standard error {error}");
    }
}
