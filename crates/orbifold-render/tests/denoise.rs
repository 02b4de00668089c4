//! The denoiser: closer to a converged render than the noisy input, edges kept, textures kept,
//! finite everywhere.

use glam::DVec3;
use orbifold_render::denoise::{DenoiseOptions, Guides, denoise, denoise_with_reduction};
use orbifold_render::film::PixelFilter;
use orbifold_render::film::{Film, tone_map};
use orbifold_render::integrator::{FirstHit, Settings};
use orbifold_render::render::{RenderOptions, Rendered, render_scene};
use orbifold_render::sampler::Sampler;
use orbifold_scene::{LightKind, Scene};

fn rendered(scene: &Scene, samples: u32, seed: u64) -> Rendered {
    let options = RenderOptions::new(40, 30, samples, seed);
    render_scene(scene, None, Settings::default(), &options).unwrap()
}

/// The median over pixels of the difference of the two films as shown on screen (tone-mapped
/// 8-bit values at the reference's exposure, the largest of the three channels): what the eye
/// compares. (The median, not the mean: a few pixels — the tiny, bright images of the light,
/// which a 256-sample reference has not converged either — would decide a mean.)
fn error(a: &Film, reference: &Film) -> f64 {
    let exposure = reference.auto_exposure();
    let mut differences = Vec::new();
    for y in 0..a.height() {
        for x in 0..a.width() {
            let (p, q) = (
                tone_map(a.pixel(x, y), exposure),
                tone_map(reference.pixel(x, y), exposure),
            );
            differences.push((0..3).map(|c| p[c].abs_diff(q[c])).max().unwrap_or(0));
        }
    }
    differences.sort_unstable();
    f64::from(differences[differences.len() / 2])
}

#[test]
fn denoising_brings_a_noisy_render_closer_to_a_converged_one() {
    // The reference has noise of its own (128 samples), so the gain shows diluted: 24 → 14 grey
    // levels at 16 samples against 256 in a 48×36 release run, about 10 % here.
    for signature in ["*22222", "*235"] {
        let mut scene = Scene::default();
        scene.orbifold.signature = signature.into();
        let layout = scene.layout().unwrap();
        let c = [layout.centre.re, layout.centre.im];
        scene.objects[0].at = c;
        scene.lights[0].at = c;
        scene.lights[0].kind = LightKind::Sphere;
        scene.lights[0].radius = 0.08;
        scene.camera.at = [c[0] - 0.1, c[1]];
        let reference = rendered(&scene, 128, 1).film;
        let noisy = rendered(&scene, 8, 2);
        let clean = denoise(&noisy.film, &noisy.guides, &DenoiseOptions::default());
        let (before, after) = (error(&noisy.film, &reference), error(&clean, &reference));
        assert!(
            after < 0.9 * before,
            "{signature}: {before:.1} grey levels off before denoising, {after:.1} after"
        );
    }
}

/// A two-sided test card: left half one surface, right half another, with noise.
fn card(width: u32, height: u32, right: FirstHit, left: FirstHit) -> (Film, Guides) {
    let mut film = Film::new(width, height);
    let mut guides = Guides::new(width, height);
    for y in 0..height {
        for x in 0..width {
            let first = if x < width / 2 { left } else { right };
            for k in 0..8u32 {
                let noise = 0.05 * (f64::from((x * 7 + y * 13 + k * 5) % 11) - 5.0) / 5.0;
                let value = first.albedo.map(|a| a * (0.5 + noise));
                film.add(x, y, value);
                guides.add(x, y, &first, value);
            }
        }
    }
    (film, guides)
}

#[test]
fn edges_between_surfaces_and_albedos_are_kept() {
    let floor = FirstHit {
        albedo: [0.8; 3],
        normal: DVec3::Z,
        depth: 1.0,
        ..FirstHit::default()
    };
    let wall = FirstHit {
        albedo: [0.1, 0.2, 0.6],
        normal: DVec3::X,
        depth: 1.2,
        ..FirstHit::default()
    };
    let (film, guides) = card(32, 8, wall, floor);
    let clean = denoise(&film, &guides, &DenoiseOptions::default());
    for y in 0..8 {
        for (x, expected) in [(15, floor.albedo), (16, wall.albedo)] {
            let p = clean.pixel(x, y);
            for c in 0..3 {
                assert!(
                    (p[c] - 0.5 * expected[c]).abs() < 0.03 * expected[c] + 1e-3,
                    "pixel ({x}, {y}) = {p:?}, expected half of {expected:?}"
                );
            }
        }
    }
    // The same normal and depth but another albedo (a checkerboard): the texture survives,
    // because lighting is filtered, not colour.
    let dark = FirstHit {
        albedo: [0.1; 3],
        ..floor
    };
    let (film, guides) = card(32, 8, dark, floor);
    let clean = denoise(&film, &guides, &DenoiseOptions::default());
    assert!((clean.pixel(15, 3)[0] - 0.4).abs() < 0.02);
    assert!((clean.pixel(16, 3)[0] - 0.05).abs() < 0.005);
}

#[test]
fn unsampled_pixels_black_surfaces_and_nothing_seen_stay_finite() {
    let (w, h) = (9, 7);
    let mut film = Film::new(w, h);
    let mut guides = Guides::new(w, h);
    for y in 0..h {
        for x in 0..w {
            if (x + y) % 3 == 0 {
                continue; // no sample at all
            }
            let albedo = if x % 2 == 0 { [0.0; 3] } else { [1.0; 3] };
            let value = [f64::from(x) * 0.1; 3];
            film.add(x, y, value);
            let first = FirstHit {
                albedo,
                normal: DVec3::ZERO,
                depth: 0.0,
                ..FirstHit::default()
            };
            guides.add(x, y, &first, value);
        }
    }
    let clean = denoise(&film, &guides, &DenoiseOptions::default());
    for y in 0..h {
        for x in 0..w {
            let p = clean.pixel(x, y);
            assert!(
                p.iter().all(|c| c.is_finite() && *c >= 0.0),
                "({x}, {y}): {p:?}"
            );
        }
    }
}

#[test]
fn pixels_whose_paths_saw_many_things_are_smoothed_by_their_lighting_alone() {
    // Every path of every pixel sees one of many tiny, differently oriented surfaces at
    // different depths (the crowd of far mirror images at a horizon): each pixel's mean normal
    // and depth are noise, and must not stop the filter. The lighting is 0.3 ± 0.2. (Guides
    // trusted as if coherent take the noise only from 0.073 to 0.064 here; as they are, to 0.036.)
    let (w, h) = (24u32, 24u32);
    let mut film = Film::new(w, h);
    let mut guides = Guides::new(w, h);
    let mut next = uniform(12345);
    for y in 0..h {
        for x in 0..w {
            for _ in 0..8 {
                let noise = if next() < 0.5 { 0.2 } else { -0.2 };
                let value = [0.3 + noise; 3];
                film.add(x, y, value);
                let angle = std::f64::consts::TAU * next();
                let first = FirstHit {
                    albedo: [0.8; 3],
                    normal: DVec3::new(angle.cos(), angle.sin(), 0.3).normalize(),
                    depth: 5.0 + 10.0 * next(),
                    ..FirstHit::default()
                };
                guides.add(x, y, &first, value);
            }
        }
    }
    let clean = denoise(&film, &guides, &DenoiseOptions::default());
    let rms = |f: &Film| {
        let sum: f64 = (4..h - 4)
            .flat_map(|y| (4..w - 4).map(move |x| (x, y)))
            .map(|(x, y)| (f.pixel(x, y)[1] - 0.3).powi(2))
            .sum();
        (sum / f64::from((w - 8) * (h - 8))).sqrt()
    };
    assert!(
        rms(&clean) < 0.6 * rms(&film),
        "noise {:.4} before denoising, {:.4} after",
        rms(&film),
        rms(&clean)
    );
}

#[test]
fn a_far_checkerboard_s_albedo_does_not_stop_the_filter() {
    // A floor far away: one surface (one normal, one depth), lit evenly (0.4 ± 0.2 noise), whose
    // checkerboard, averaged over each pixel's footprint, gives every pixel another albedo
    // between 0.2 and 0.8 (the moiré near a horizon). The lighting is filtered divided by the
    // albedo, so an albedo step is no lighting edge: the noise must fall as on a plain floor.
    // (It falls from 0.075 to 0.003; with the albedo as a guide, σ = 0.1, only to 0.026.)
    let (w, h) = (24u32, 24u32);
    let mut film = Film::new(w, h);
    let mut guides = Guides::new(w, h);
    let mut next = uniform(777);
    let mut albedos = Vec::new();
    for y in 0..h {
        for x in 0..w {
            let albedo = 0.2 + 0.6 * next();
            albedos.push(albedo);
            let first = FirstHit {
                albedo: [albedo; 3],
                normal: DVec3::Z,
                depth: 8.0,
                ..FirstHit::default()
            };
            for _ in 0..8 {
                let noise = if next() < 0.5 { 0.2 } else { -0.2 };
                let value = [albedo * (0.4 + noise); 3];
                film.add(x, y, value);
                guides.add(x, y, &first, value);
            }
        }
    }
    let clean = denoise(&film, &guides, &DenoiseOptions::default());
    let rms = |f: &Film| {
        let sum: f64 = (4..h - 4)
            .flat_map(|y| (4..w - 4).map(move |x| (x, y)))
            .map(|(x, y)| (f.pixel(x, y)[1] / albedos[(y * w + x) as usize] - 0.4).powi(2))
            .sum();
        (sum / f64::from((w - 8) * (h - 8))).sqrt()
    };
    assert!(
        rms(&clean) < 0.15 * rms(&film),
        "lighting noise {:.4} before denoising, {:.4} after",
        rms(&film),
        rms(&clean)
    );
}

/// A deterministic stream of uniform numbers in [0, 1) for the test cards.
fn uniform(seed: u64) -> impl FnMut() -> f64 {
    let mut state = seed;
    move || {
        state = state
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407);
        (state >> 11) as f64 / (1u64 << 53) as f64
    }
}

#[test]
fn a_light_image_neither_bleeds_into_the_wall_around_it_nor_leaves_its_pixels() {
    // A grey wall (albedo 0.8, lighting 0.3 ± 0.05) with a small, bright mirror image of a light
    // in the middle, which covers half of each of its 2×2 pixels: each sample there either sees
    // the light (40, seen directly) or the wall.
    let (w, h) = (24u32, 24u32);
    let mut film = Film::new(w, h);
    let mut guides = Guides::new(w, h);
    let mut next = uniform(7);
    let wall = FirstHit {
        albedo: [0.8; 3],
        normal: DVec3::Z,
        depth: 1.0,
        ..FirstHit::default()
    };
    let light = FirstHit {
        albedo: [1.0; 3],
        normal: DVec3::Z,
        depth: 0.9,
        emitted: [40.0; 3],
        ..FirstHit::default()
    };
    let on_light = |x: u32, y: u32| (11..13).contains(&x) && (11..13).contains(&y);
    for y in 0..h {
        for x in 0..w {
            for _ in 0..16 {
                let (first, value) = if on_light(x, y) && next() < 0.5 {
                    (light, [40.0; 3])
                } else {
                    (wall, [0.8 * (0.3 + 0.1 * (next() - 0.5)); 3])
                };
                film.add(x, y, value);
                guides.add(x, y, &first, value);
            }
        }
    }
    let clean = denoise(&film, &guides, &DenoiseOptions::default());
    // The light's four pixels, whose paths disagree on what they saw (light or wall), may share
    // their light among themselves, but it stays theirs: their sum is kept, and none is darker
    // or brighter than the four were. The wall's share of each is filtered with the wall (so it
    // may drift towards a whole wall pixel's 0.24, at most 0.3 a pixel).
    let light_pixels = [(11, 11), (11, 12), (12, 11), (12, 12)];
    let seen = light_pixels.map(|(x, y)| guides.emitted(x, y)[0]);
    let (least, most) = (
        seen.iter().copied().fold(f64::INFINITY, f64::min),
        seen.iter().copied().fold(0.0, f64::max),
    );
    let (sum_seen, sum_clean) = (
        seen.iter().sum::<f64>(),
        light_pixels
            .map(|(x, y)| clean.pixel(x, y)[0])
            .iter()
            .sum::<f64>(),
    );
    assert!(
        (0.0..4.0 * 0.3).contains(&(sum_clean - sum_seen)),
        "the light's pixels: {sum_clean:.3} in all, their light {sum_seen:.3}"
    );
    for y in 8..16 {
        for x in 8..16 {
            let p = clean.pixel(x, y)[0];
            if on_light(x, y) {
                assert!(
                    (least..most + 0.3).contains(&p),
                    "light pixel ({x}, {y}): {p:.3}, the light of the four {seen:.3?}"
                );
            } else {
                assert!(
                    (p - 0.24).abs() < 0.01,
                    "wall pixel ({x}, {y}) next to the light: {p:.4}, not 0.24"
                );
            }
        }
    }
}

#[test]
fn a_smooth_light_sample_keeps_its_peak_under_noisy_indirect_light() {
    // The first surface's light sample draws a bright, noiseless spot (the glow of a light
    // image close to a ceiling); the rest of the light is faint and very noisy. Filtered
    // together, the spot would be flattened within the tolerance the noise sets.
    let (w, h) = (40u32, 40u32);
    let mut film = Film::new(w, h);
    let mut guides = Guides::new(w, h);
    let mut next = uniform(11);
    let spot = |x: u32, y: u32| {
        let r2 = (f64::from(x) - 20.0).powi(2) + (f64::from(y) - 20.0).powi(2);
        0.1 + 0.5 * (-r2 / 8.0).exp()
    };
    for y in 0..h {
        for x in 0..w {
            for _ in 0..8 {
                let direct = [spot(x, y); 3];
                let rest = if next() < 0.1 { 2.0 } else { 0.0 };
                let value = direct.map(|d| d + rest);
                let first = FirstHit {
                    albedo: [1.0; 3],
                    normal: DVec3::Z,
                    depth: 1.0,
                    direct,
                    ..FirstHit::default()
                };
                film.add(x, y, value);
                guides.add(x, y, &first, value);
            }
        }
    }
    let clean = denoise(&film, &guides, &DenoiseOptions::default());
    // The peak keeps its height over the rest's mean (0.2), within what the rest's filtered
    // noise leaves.
    let peak = clean.pixel(20, 20)[0] - 0.2;
    assert!(
        (peak - spot(20, 20)).abs() < 0.05,
        "peak {peak:.3} against {:.3}",
        spot(20, 20)
    );
}

#[test]
fn on_a_bumpy_surface_the_light_of_longer_paths_is_averaged_and_the_light_sample_is_kept() {
    // A surface whose normal tilts by up to 25° in a random direction from pixel to pixel
    // (bumps as a dragon's scales are at a pixel or two each). The light sample follows the
    // normal, from 0.2 to 0.6, noiseless. The rest of the light (after a bounce) is the same
    // everywhere on average, 0.3, and noisy.
    let (w, h) = (32u32, 32u32);
    let mut film = Film::new(w, h);
    let mut guides = Guides::new(w, h);
    let mut next = uniform(13);
    let most = 25f64.to_radians();
    let normals: Vec<DVec3> = (0..w * h)
        .map(|_| {
            let (tilt, turn) = (most * next(), std::f64::consts::TAU * next());
            DVec3::new(tilt.sin() * turn.cos(), tilt.sin() * turn.sin(), tilt.cos())
        })
        .collect();
    let normal = |x: u32, y: u32| normals[(y * w + x) as usize];
    let light_sample = |x: u32, y: u32| 0.4 + 0.2 * normal(x, y).x / most.sin();
    for y in 0..h {
        for x in 0..w {
            let direct = [light_sample(x, y); 3];
            let first = FirstHit {
                albedo: [1.0; 3],
                normal: normal(x, y),
                depth: 1.0,
                direct,
                ..FirstHit::default()
            };
            for _ in 0..8 {
                let rest = 0.6 * next();
                let value = direct.map(|d| d + rest);
                film.add(x, y, value);
                guides.add(x, y, &first, value);
            }
        }
    }
    let rest_spread = |film: &Film| -> f64 {
        // The RMS of the rest (the pixel less its light sample) about 0.3, inside the border.
        let mut sum = 0.0;
        let mut count = 0.0;
        for y in 6..h - 6 {
            for x in 6..w - 6 {
                sum += (film.pixel(x, y)[0] - light_sample(x, y) - 0.3).powi(2);
                count += 1.0;
            }
        }
        (sum / count).sqrt()
    };
    let clean = denoise(&film, &guides, &DenoiseOptions::default());
    // The raw rest spreads by about 0.6/√12/√8 ≈ 0.06; averaged over the neighbours whatever
    // their tilt, it falls well below. Had it listened to the normals as the light sample does
    // (neighbours ~20° apart weigh 0.94^64 ≈ 0.02), it would have kept much of its noise.
    let (raw, denoised) = (rest_spread(&film), rest_spread(&clean));
    let strict = denoise(
        &film,
        &guides,
        &DenoiseOptions {
            sigma_normal_rest: DenoiseOptions::default().sigma_normal,
            ..DenoiseOptions::default()
        },
    );
    assert!(
        denoised < 0.5 * rest_spread(&strict) && denoised < 0.25 * raw,
        "rest spread: raw {raw:.4}, denoised {denoised:.4}, with the light sample's exponent {:.4}",
        rest_spread(&strict)
    );
    // The light sample's pattern survives: every pixel keeps its own.
    for y in 6..h - 6 {
        for x in 6..w - 6 {
            let direct = light_sample(x, y);
            let p = clean.pixel(x, y)[0] - 0.3;
            assert!(
                (p - direct).abs() < 0.05,
                "pixel ({x}, {y}): {p:.3} over the rest, its light sample {direct}"
            );
        }
    }
}

/// Under a filter wider than the box, the guides weigh each path as the film does, so that the
/// light seen directly, the light sample and the rest still add up to the film's pixel: an
/// image of light seen directly only (noisy, splatted with the Gaussian) comes out of the
/// denoiser as it went in, since that part is not filtered.
#[test]
fn the_guides_weigh_paths_as_the_film_does() {
    let (w, h) = (12, 10);
    let mut film = Film::new(w, h);
    let mut guides = Guides::new(w, h);
    for y in 0..h {
        for x in 0..w {
            for k in 0..6u32 {
                let mut s = Sampler::stratified(8, u64::from(y * w + x), u64::from(k));
                let light = [1.0 + 4.0 * s.next_f64(), 2.0, 0.5 * f64::from(x % 3)];
                let first = FirstHit {
                    albedo: [0.5; 3],
                    normal: DVec3::Z,
                    depth: 1.0,
                    emitted: light,
                    ..FirstHit::default()
                };
                film.splat(x, y, light, PixelFilter::GAUSSIAN);
                guides.splat(x, y, &first, light, PixelFilter::GAUSSIAN);
            }
        }
    }
    let clean = denoise(&film, &guides, &DenoiseOptions::default());
    for y in 0..h {
        for x in 0..w {
            let (a, b) = (clean.pixel(x, y), film.pixel(x, y));
            assert!(
                (0..3).all(|c| (a[c] - b[c]).abs() < 1e-9 * (1.0 + b[c])),
                "({x}, {y}): {a:?} against {b:?}"
            );
            assert_eq!(guides.emitted(x, y), b);
        }
    }
}

#[test]
fn a_crowd_of_tiny_light_images_is_smoothed_and_keeps_its_brightness() {
    // The band above a hyperbolic room's horizon: every path of the band's pixels sees, through
    // the mirrors, either one of many tiny light images (30 % of them, at scattered depths) or
    // the ceiling between them. What each pixel saw directly is noise of its coverage, which
    // the filter averages between such pixels; the coherent wall below the band keeps its own.
    let (w, h) = (32u32, 32u32);
    let mut film = Film::new(w, h);
    let mut guides = Guides::new(w, h);
    let mut next = uniform(2024);
    let in_band = |y: u32| y < 20;
    let ceiling = |depth: f64| FirstHit {
        albedo: [0.8; 3],
        normal: DVec3::Z,
        depth,
        ..FirstHit::default()
    };
    for y in 0..h {
        for x in 0..w {
            for _ in 0..16 {
                let (first, value) = if in_band(y) {
                    let depth = 20.0 + 20.0 * next();
                    if next() < 0.3 {
                        let light = FirstHit {
                            albedo: [1.0; 3],
                            normal: DVec3::new(next() - 0.5, next() - 0.5, 1.0).normalize(),
                            emitted: [5.0; 3],
                            ..ceiling(depth)
                        };
                        (light, [5.0; 3])
                    } else {
                        (ceiling(depth), [0.8 * 0.3; 3])
                    }
                } else {
                    let lit = 0.8 * (0.3 + 0.1 * (next() - 0.5));
                    (ceiling(2.0), [lit; 3])
                };
                film.add(x, y, value);
                guides.add(x, y, &first, value);
            }
        }
    }
    let clean = denoise(&film, &guides, &DenoiseOptions::default());
    let band: Vec<(u32, u32)> = (4..16)
        .flat_map(|y| (4..w - 4).map(move |x| (x, y)))
        .collect();
    let truth = 0.3 * 5.0 + 0.7 * 0.8 * 0.3;
    let stats = |f: &Film| {
        let values: Vec<f64> = band.iter().map(|&(x, y)| f.pixel(x, y)[0]).collect();
        let mean = values.iter().sum::<f64>() / values.len() as f64;
        let rms =
            (values.iter().map(|v| (v - truth).powi(2)).sum::<f64>() / values.len() as f64).sqrt();
        (mean, rms)
    };
    let ((raw_mean, raw_rms), (mean, rms)) = (stats(&film), stats(&clean));
    assert!(
        rms < 0.5 * raw_rms,
        "the band's noise: {raw_rms:.3} raw, {rms:.3} denoised"
    );
    assert!(
        (mean - raw_mean).abs() < 0.03 * raw_mean,
        "the band's brightness: {raw_mean:.3} raw, {mean:.3} denoised"
    );
    // The wall below takes none of the band's light: two rows from it, as bright as it is lit.
    for x in 0..w {
        let p = clean.pixel(x, 22)[0];
        assert!((p - 0.24).abs() < 0.02, "wall pixel ({x}, 22): {p:.3}");
    }
}

#[test]
fn the_noise_of_light_seen_directly_counts_as_noise_the_filter_leaves() {
    // A grey wall whose lighting is noisy everywhere, and one pixel whose samples also glimpse a
    // crowd of tiny light images (seen directly, half of them): the filter smooths the wall's
    // lighting there as everywhere, but the light's noise stays, so adaptive sampling must see
    // that pixel's variance as hardly lowered.
    let (w, h) = (15u32, 15u32);
    let mut film = Film::new(w, h);
    let mut guides = Guides::new(w, h);
    let mut next = uniform(11);
    let (crowd, plain) = ((7, 7), (3, 3));
    for y in 0..h {
        for x in 0..w {
            for _ in 0..32 {
                let lit = 0.8 * (0.3 + 0.2 * (next() - 0.5));
                let glimpse = if (x, y) == crowd && next() < 0.5 {
                    2.0
                } else {
                    0.0
                };
                let first = FirstHit {
                    albedo: [0.8; 3],
                    normal: DVec3::Z,
                    depth: 1.0,
                    emitted: [glimpse; 3],
                    ..FirstHit::default()
                };
                film.add(x, y, [lit + glimpse; 3]);
                guides.add(x, y, &first, [lit + glimpse; 3]);
            }
        }
    }
    let (clean, reduction) = denoise_with_reduction(&film, &guides, &DenoiseOptions::default());
    let at = |(x, y): (u32, u32)| (y * w + x) as usize;
    assert!(
        reduction[at(plain)] < 0.1,
        "the plain wall: {}",
        reduction[at(plain)]
    );
    assert!(
        reduction[at(crowd)] > 0.9,
        "the light's noise is left: {}",
        reduction[at(crowd)]
    );
    // And the light seen directly is indeed left as it was.
    let (x, y) = crowd;
    let seen = guides.emitted(x, y)[0];
    assert!((clean.pixel(x, y)[0] - seen - 0.24).abs() < 0.02);
}

/// Rounds of paths added at once, which filter afresh only the pixels near the ones that got
/// paths, leave the guides exactly as the paths added one by one (each refiltering its
/// neighbourhood) do: every pixel's albedo, light seen directly, light sample and standard
/// errors, to the bit, over rounds of a few pixels and of all of them.
#[test]
fn rounds_of_paths_refilter_exactly_the_guides_they_change() {
    let (w, h) = (9u32, 7u32);
    for seed in 0..40u64 {
        let mut rng = Sampler::new(seed, 0, 0);
        let (mut at_once, mut one_by_one) = (Guides::new(w, h), Guides::new(w, h));
        for _ in 0..4 {
            let share = if rng.next_f64() < 0.3 {
                1.0
            } else {
                0.3 * rng.next_f64()
            };
            let mut paths = Vec::new();
            for y in 0..h {
                for x in 0..w {
                    if rng.next_f64() < share || (x, y) == (w / 2, h / 2) {
                        let v = rng.next_f64();
                        let first = FirstHit {
                            albedo: [v, 0.5, 1.0 - v],
                            normal: DVec3::new(v, 1.0, 0.2).normalize(),
                            depth: 1.0 + v,
                            emitted: [0.1 * v; 3],
                            direct: [0.3 * v; 3],
                        };
                        let splat = orbifold_render::film::Splat {
                            x,
                            y,
                            radiance: [2.0 * v; 3],
                        };
                        paths.push((splat, first));
                    }
                }
            }
            at_once.splat_all(&paths, PixelFilter::GAUSSIAN);
            for (s, first) in &paths {
                one_by_one.splat(s.x, s.y, first, s.radiance, PixelFilter::GAUSSIAN);
            }
            for y in 0..h {
                for x in 0..w {
                    let pixel = |g: &Guides| {
                        (
                            g.albedo(x, y),
                            g.emitted(x, y),
                            g.direct(x, y),
                            g.part_errors(x, y),
                        )
                    };
                    assert_eq!(
                        pixel(&at_once),
                        pixel(&one_by_one),
                        "seed {seed}, ({x}, {y})"
                    );
                }
            }
        }
    }
}
