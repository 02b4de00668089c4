//! Camera rays that carry their pixel's footprint (`orbifold_trace::footprint`): the tiny mirror
//! images of a sphere light are counted by the share of the pixel they cover. The image's mean
//! must not change, and its noise must fall.

use orbifold_render::integrator::{Integrator, Settings};
use orbifold_render::sampler::Sampler;
use orbifold_scene::{Coordinates, LightKind, Material, Scene};
use orbifold_trace::camera::Camera;

/// A room of `signature` whose walls are all mirrors, with a small sphere light near the
/// ceiling, seen by a camera that looks along the room so that the light's images shrink below
/// a pixel towards the horizon (with a field of view `fov` degrees wide, pitched up `pitch`).
fn scene(signature: &str, fov: f64, pitch: f64) -> Scene {
    let mut scene = Scene::default();
    scene.orbifold.signature = signature.into();
    scene.objects.clear();
    let layout = scene.layout().unwrap();
    let c = [layout.centre.re, layout.centre.im];
    scene.room.reflectance = [0.9; 3];
    let light = &mut scene.lights[0];
    light.kind = LightKind::Sphere;
    light.at = c;
    light.height = 0.8;
    light.radius = 0.1;
    light.power = 10.0;
    scene.camera.at = [c[0] + 0.05, c[1] + 0.03];
    scene.camera.height = 0.5;
    scene.camera.pitch = pitch;
    scene.camera.fov = fov;
    scene
}

use orbifold_render::orbifold_scene::color::luminance;

/// Per pixel of a `size`×`size` image: the mean of `n` samples and their variance, with or
/// without the footprint (the same sub-pixel positions and random numbers both ways).
fn pixels(scene: &Scene, size: u32, n: u64, footprint: bool) -> Vec<(f64, f64)> {
    let settings = Settings {
        max_depth: 1,
        ..Settings::default()
    };
    let integrator = Integrator::from_scene(scene, None, settings).unwrap();
    let camera = Camera::new(integrator.space(), &scene.camera);
    (0..size * size)
        .map(|p| {
            let (i, j) = (p % size, p / size);
            let values: Vec<f64> = (0..n)
                .map(|k| {
                    let mut sampler = Sampler::stratified(3, u64::from(p), k);
                    let offset = sampler.next_2d();
                    let ray = camera.ray(i, j, size, size, offset);
                    let f = footprint.then(|| camera.footprint(i, j, size, size, offset));
                    luminance(integrator.sample_pixel(&ray, f, &mut sampler).radiance)
                })
                .collect();
            let mean = values.iter().sum::<f64>() / n as f64;
            let variance =
                values.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / (n as f64 - 1.0);
            (mean, variance)
        })
        .collect()
}

/// Renders `scene` both ways and checks that the means agree within their noise and that the
/// footprint removes at least half the variance summed over pixels.
fn check_mean_kept_and_noise_lost(signature: &str, scene: &Scene) {
    let (size, n) = (6, 512);
    let hits = pixels(scene, size, n, false);
    let covered = pixels(scene, size, n, true);
    let total = |p: &[(f64, f64)]| p.iter().map(|(m, _)| m).sum::<f64>();
    let error = |p: &[(f64, f64)]| (p.iter().map(|(_, v)| v).sum::<f64>() / n as f64).sqrt();
    let (a, ea) = (total(&hits), error(&hits));
    let (b, eb) = (total(&covered), error(&covered));
    assert!(a > 0.0, "{signature}: the light is seen");
    assert!(
        (a - b).abs() < 4.0 * (ea * ea + eb * eb).sqrt() + 0.01 * a,
        "{signature}: hits {a} ± {ea}, footprint {b} ± {eb}"
    );
    // The variance summed over pixels: the images' hit-or-miss noise is gone.
    let variance = |p: &[(f64, f64)]| p.iter().map(|(_, v)| v).sum::<f64>();
    assert!(
        variance(&covered) < 0.5 * variance(&hits),
        "{signature}: variance {} with the footprint, {} without",
        variance(&covered),
        variance(&hits)
    );
}

#[test]
fn tiny_light_images_keep_the_image_s_mean_and_lose_their_noise() {
    // Euclidean and hyperbolic rooms (a spherical room has few, large images).
    for signature in ["*2222", "*444"] {
        check_mean_kept_and_noise_lost(signature, &scene(signature, 60.0, 5.0));
    }
}

#[test]
fn light_images_a_few_pixels_wide_keep_their_mean_and_lose_the_noise_of_their_rims() {
    // Pixels of 2°: the near images of the light are 2-6 pixels wide, counted by the share of
    // the footprint that their disc covers rather than hit or missed.
    for signature in ["*2222", "*444"] {
        let scene = scene(signature, 12.0, 8.0);
        check_mean_kept_and_noise_lost(signature, &scene);
    }
}

#[test]
fn each_pixel_counts_the_light_images_in_it_as_ray_hits_do() {
    // Ray hits filter the image with the pixel's own box: a sample's footprint centred on the
    // pixel (not on the sample's ray, which would blur each image over the neighbouring pixels
    // too) gives every pixel the same mean, pixel by pixel. (Pixels of 2°, whose footprints
    // stay clear of the walls: a capped footprint is centred on the ray.)
    for signature in ["*2222", "*444"] {
        let (fov, pitch) = (12.0, 8.0);
        let scene = scene(signature, fov, pitch);
        let n = 512;
        let hits = pixels(&scene, 6, n, false);
        let covered = pixels(&scene, 6, n, true);
        for (p, (&(a, va), &(b, vb))) in hits.iter().zip(&covered).enumerate() {
            let error = ((va + vb) / n as f64).sqrt();
            assert!(
                (a - b).abs() < 4.0 * error + 0.01 * a.max(b),
                "{signature} ({fov}°) pixel {p}: hits {a} ± {}, footprint {b} ± {}",
                (va / n as f64).sqrt(),
                (vb / n as f64).sqrt()
            );
        }
        // The samples of a pixel agree: what is left is the rims of the images that ray hits
        // hide behind them (0.06-0.10 of the variance; 0.26-0.31 with footprints centred on
        // the rays).
        let variance = |p: &[(f64, f64)]| p.iter().map(|(_, v)| v).sum::<f64>();
        let ratio = variance(&covered) / variance(&hits);
        assert!(ratio < 0.15, "{signature}: {ratio} of the variance left");
    }
}

#[test]
fn an_image_of_a_checkerboard_is_filtered_like_the_checkerboard() {
    // A 2×2 image of black and white laid out at twice the checker's size is the same pattern;
    // filtered over the pixels' footprints (closed form for the checker, a summed-area table for
    // the image) the two floors must render alike, far floor and all.
    let tmp = tempfile::Builder::new()
        .prefix("orbifold-footprint-")
        .tempdir()
        .unwrap();
    let dir = tmp.path();
    let path = dir.join("checker.png");
    // Texel (i, j), row j from the top, is white when i + j is odd: the checker's colour 0 where
    // ⌊x/size⌋ + ⌊y/size⌋ is even.
    let image = image::RgbImage::from_fn(2, 2, |i, j| {
        image::Rgb(if (i + j) % 2 == 1 { [255; 3] } else { [0; 3] })
    });
    image.save(&path).unwrap();
    let mut checker = scene("*2222", 60.0, 5.0);
    checker.camera.pitch = -10.0;
    checker.room.floor = Material::Checker {
        colors: [[1.0; 3], [0.0; 3]],
        size: 0.1,
        coordinates: Coordinates::Intrinsic,
    };
    let mut textured = checker.clone();
    textured.room.floor = Material::Texture {
        path: path.to_str().unwrap().into(),
        scale: 0.2,
        coordinates: Coordinates::Intrinsic,
    };
    let render = |scene: &Scene| {
        let integrator = Integrator::from_scene(scene, None, Settings::default()).unwrap();
        let camera = Camera::new(integrator.space(), &scene.camera);
        let size = 16;
        (0..size * size)
            .map(|p| {
                let (i, j) = (p % size, p / size);
                let mut sampler = Sampler::stratified(5, u64::from(p), 0);
                let offset = sampler.next_2d();
                let ray = camera.ray(i, j, size, size, offset);
                let f = Some(camera.footprint(i, j, size, size, offset));
                integrator.sample_pixel(&ray, f, &mut sampler).first.albedo
            })
            .collect::<Vec<_>>()
    };
    let (a, b) = (render(&checker), render(&textured));
    // The first surface's albedo, filtered: the same wherever the floor is seen.
    let alike = a
        .iter()
        .zip(&b)
        .filter(|(x, y)| (0..3).all(|k| (x[k] - y[k]).abs() < 1e-6))
        .count();
    assert!(alike * 100 >= a.len() * 99, "{alike} of {} alike", a.len());
    // Some pixels see the far floor as a blend, not black or white.
    let grey = a.iter().filter(|c| c[0] > 0.05 && c[0] < 0.95).count();
    assert!(grey > 0, "no filtered pixel");
}

#[test]
fn every_sample_of_a_pixel_sees_the_checkerboard_filtered_over_that_pixel() {
    // A checkered floor under a camera looking down at it, pixels of 5°. Point-sampled, the
    // first surface's albedo averages, pixel by pixel, to the checker's box filter over the
    // pixel; filtered over a footprint centred on the pixel, every sample gets about that
    // value (up to how the projection changes across the pixel). Footprints centred on each
    // sample's ray blurred each pixel with its neighbours and differed from sample to sample:
    // 0.17 and 0.16 of the point samples' variance left in `*2222` and `*444`, and 28 of the
    // 48 pixels compared failed; now 0.008 and 0.02, and none. (Where the floor is seen far away through mirrors, the
    // filter is an approximation: the box in texture coordinates that has the footprint's
    // second moments, of a footprint linearised at the sample. Those pixels are not compared.)
    for signature in ["*2222", "*444"] {
        let mut scene = scene(signature, 40.0, -35.0);
        scene.room.floor = Material::Checker {
            colors: [[1.0; 3], [0.0; 3]],
            size: 0.2,
            coordinates: Coordinates::Intrinsic,
        };
        let integrator = Integrator::from_scene(&scene, None, Settings::default()).unwrap();
        let camera = Camera::new(integrator.space(), &scene.camera);
        let (size, n) = (8u32, 256u64);
        let albedo = |p: u32, k: u64, footprint: bool| {
            let (i, j) = (p % size, p / size);
            let mut sampler = Sampler::stratified(7, u64::from(p), k);
            let offset = sampler.next_2d();
            let ray = camera.ray(i, j, size, size, offset);
            let f = footprint.then(|| camera.footprint(i, j, size, size, offset));
            integrator.sample_pixel(&ray, f, &mut sampler).first.albedo[0]
        };
        let stats = |values: Vec<f64>| {
            let mean = values.iter().sum::<f64>() / values.len() as f64;
            let variance = values.iter().map(|v| (v - mean).powi(2)).sum::<f64>()
                / (values.len() as f64 - 1.0);
            (mean, variance)
        };
        let (mut spread_points, mut spread_filtered) = (0.0, 0.0);
        for p in 0..size * size {
            let (a, va) = stats((0..4 * n).map(|k| albedo(p, k, false)).collect());
            let (b, vb) = stats((0..n).map(|k| albedo(p, k, true)).collect());
            let error = (va / (4 * n) as f64).sqrt();
            // The lowest three rows: the floor near the camera, seen directly.
            assert!(
                p < 5 * size || (a - b).abs() < 4.0 * error + 0.02,
                "{signature} pixel {p}: point samples {a} ± {error}, filtered {b} (spread {})",
                vb.sqrt()
            );
            spread_points += va;
            spread_filtered += vb;
        }
        let ratio = spread_filtered / spread_points;
        assert!(ratio < 0.05, "{signature}: {ratio} of the variance left");
    }
}

#[test]
fn the_light_seen_directly_and_the_first_light_sample_are_parts_of_the_radiance() {
    // The denoiser filters these two parts apart from the rest (`FirstHit::emitted`,
    // `FirstHit::direct`): they must be shares of the sample's radiance, never more.
    for (signature, pitch) in [("*333", 10.0), ("*22", 15.0), ("*444", 5.0)] {
        let scene = scene(signature, 90.0, pitch);
        let integrator = Integrator::from_scene(&scene, None, Settings::default()).unwrap();
        let camera = Camera::new(integrator.space(), &scene.camera);
        let size = 12;
        let (mut seen, mut lit) = (0, 0);
        for p in 0..size * size {
            let (i, j) = (p % size, p / size);
            for k in 0..8 {
                let mut sampler = Sampler::stratified(5, u64::from(p), k);
                let offset = sampler.next_2d();
                let ray = camera.ray(i, j, size, size, offset);
                let f = (k % 2 == 0).then(|| camera.footprint(i, j, size, size, offset));
                let sample = integrator.sample_pixel(&ray, f, &mut sampler);
                let (e, d, r) = (sample.first.emitted, sample.first.direct, sample.radiance);
                for c in 0..3 {
                    assert!(
                        e[c] >= 0.0 && d[c] >= 0.0 && e[c] + d[c] <= r[c] * (1.0 + 1e-9) + 1e-12,
                        "{signature}, pixel ({i}, {j}): emitted {e:?} + direct {d:?} > radiance {r:?}"
                    );
                }
                seen += usize::from(luminance(e) > 0.0);
                lit += usize::from(luminance(d) > 0.0);
            }
        }
        assert!(
            seen > 0 && lit > 0,
            "{signature}: {seen} samples saw the light, {lit} lit by it"
        );
    }
}

/// The light that a bounce finds (the sample's radiance less the light seen directly and the
/// first surface's light sample) for `n` camera rays at the floor of `scene`, with or without
/// the bounce footprint (the same random numbers both ways): the mean and the variance.
fn bounce_light(scene: &Scene, n: u64, bounce_footprint: bool) -> (f64, f64) {
    let settings = Settings {
        max_depth: 1,
        bounce_footprint,
        ..Settings::default()
    };
    let integrator = Integrator::from_scene(scene, None, settings).unwrap();
    let camera = Camera::new(integrator.space(), &scene.camera);
    let size = 16;
    let values: Vec<f64> = (0..n)
        .map(|k| {
            let p = (k % (size * size)) as u32;
            let (i, j) = (p % size as u32, p / size as u32);
            let mut sampler = Sampler::stratified(11, u64::from(p), k / (size * size));
            let offset = sampler.next_2d();
            let ray = camera.ray(i, j, size as u32, size as u32, offset);
            let f = camera.footprint(i, j, size as u32, size as u32, offset);
            let sample = integrator.sample_pixel(&ray, Some(f), &mut sampler);
            let (e, d, r) = (sample.first.emitted, sample.first.direct, sample.radiance);
            luminance(r) - luminance(e) - luminance(d)
        })
        .collect();
    let mean = values.iter().sum::<f64>() / n as f64;
    let variance = values.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / (n as f64 - 1.0);
    (mean, variance)
}

#[test]
fn far_light_images_seen_after_a_bounce_keep_their_mean_and_lose_their_noise() {
    // Light sampling draws a hyperbolic room's light images only up to the image set's cutoff;
    // beyond it are thousands more, each far smaller than the spread of a diffuse bounce (with
    // mirrors that lose nothing, they carry a good share of the light). A bounce counts them by
    // the share of its footprint they cover rather than by rare hits: the same light, less noise.
    for (signature, most) in [("*444", 0.75), ("*3333", 0.5)] {
        let mut scene = scene(signature, 60.0, -40.0);
        scene.room.reflectance = [1.0; 3];
        let n = 1 << 13;
        let (a, va) = bounce_light(&scene, n, false);
        let (b, vb) = bounce_light(&scene, n, true);
        let error = ((va + vb) / n as f64).sqrt();
        assert!(
            a > 0.0 && (a - b).abs() < 4.0 * error + 0.01 * a,
            "{signature}: hits {a} ± {}, footprint {b} ± {}",
            (va / n as f64).sqrt(),
            (vb / n as f64).sqrt()
        );
        assert!(
            vb < most * va,
            "{signature}: variance {vb} with the bounce footprint, {va} without"
        );
    }
}
