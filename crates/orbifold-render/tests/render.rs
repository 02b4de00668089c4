//! Light transport checks: light sampling through mirror images against brute-force path
//! tracing, determinism, finite pixels everywhere, and the geometric term against the geodesic
//! flow.

use glam::DVec3;
use orbifold::Geometry;
use orbifold::space::Space;
use orbifold_render::denoise::{DenoiseOptions, denoise_with_reduction};
use orbifold_render::film::Film;
use orbifold_render::film::PixelFilter;
use orbifold_render::integrator::Settings;
use orbifold_render::lights::{TangentFrame, spread};
use orbifold_render::render::{RenderOptions, render_scene};
use orbifold_scene::{LightKind, Material, Mirror, Scene, Wall};

/// A room of `signature` with grey walls, one partial mirror per wall of reflectance 0.8, a
/// sphere light and the camera looking across the room from beside the light (outside it: a
/// camera inside an emitter sees its inner faces).
fn scene(signature: &str, light: LightKind) -> Scene {
    let mut scene = Scene::default();
    scene.orbifold.signature = signature.into();
    scene.objects.clear();
    let layout = scene.layout().unwrap();
    let c = [layout.centre.re, layout.centre.im];
    scene.room.mirrors = orbifold_scene::MirrorDefault::None;
    scene.room.wall_material = Material::Color {
        color: [0.6, 0.6, 0.6],
    };
    scene.walls = (0..layout.vertices.len())
        .map(|i| Wall {
            index: i,
            material: None,
            mirrors: vec![Mirror {
                from: 0.2,
                to: 0.8,
                bottom: 0.2,
                top: Some(0.9),
                reflectance: [0.8, 0.8, 0.8],
            }],
        })
        .collect();
    scene.lights[0].kind = light;
    scene.lights[0].at = c;
    scene.lights[0].height = 0.6;
    scene.lights[0].radius = 0.12;
    scene.lights[0].power = 20.0;
    scene.camera.at = [c[0] - 0.3, c[1]];
    scene.camera.pitch = -30.0;
    scene.camera.fov = 100.0;
    scene
}

fn image(scene: &Scene, nee: bool, samples: u32, seed: u64) -> Film {
    sized_image(scene, cached(nee), (8, 6), samples, seed)
}

/// Light transport with at most 3 bounces, with or without next-event estimation, and with the
/// radiance cache where the renderer would use it (with next-event estimation).
fn cached(nee: bool) -> Settings {
    Settings {
        max_depth: 3,
        nee,
        ..Settings::default()
    }
}

/// Every path traced in full: the unbiased estimator.
fn in_full(nee: bool) -> Settings {
    Settings {
        radiance_cache: false,
        ..cached(nee)
    }
}

/// A `width` × `height` image with the box filter: each pixel the mean of its own samples, so
/// that pixels are independent and [`mean_and_error`]'s error is the image mean's. (A filter
/// that shares samples between neighbours correlates them: summing their errors as independent
/// would understate the mean's by about half with the default Gaussian.)
fn sized_image(
    scene: &Scene,
    settings: Settings,
    (width, height): (u32, u32),
    samples: u32,
    seed: u64,
) -> Film {
    let options = RenderOptions {
        filter: PixelFilter::Box,
        ..RenderOptions::new(width, height, samples, seed)
    };
    render_scene(scene, None, settings, &options).unwrap().film
}

/// The mean of `value` over renders with each of `seeds`, and its standard error from their
/// spread. What a radiance cache needs: a cell's mean is shared by every sample that reads it,
/// so its noise is in no pixel's standard error, only between renders with other seeds.
fn mean_over_seeds(seeds: &[u64], value: impl Fn(u64) -> f64) -> (f64, f64) {
    mean_over_renders(&seeds.iter().map(|&seed| value(seed)).collect::<Vec<_>>())
}

/// The mean of one value from several renders, and its standard error from their spread.
fn mean_over_renders(values: &[f64]) -> (f64, f64) {
    let n = values.len() as f64;
    let mean = values.iter().sum::<f64>() / n;
    let variance = values.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / (n - 1.0);
    (mean, (variance / n).sqrt())
}

use orbifold_render::orbifold_scene::color::luminance;

/// Mean luminance of the image and its standard error (pixels are independent).
fn mean_and_error(film: &Film) -> (f64, f64) {
    let (w, h) = (film.width(), film.height());
    let n = f64::from(w * h);
    let mut mean = 0.0;
    let mut variance = 0.0;
    for y in 0..h {
        for x in 0..w {
            mean += luminance(film.pixel(x, y)) / n;
            variance += film.standard_error(x, y).powi(2) / (n * n);
        }
    }
    (mean, variance.sqrt())
}

/// Next-event estimation (64 spp) and brute force (512 spp) give the same whole-image mean
/// luminance, within 4 standard errors + 1 % (every path traced in full: no radiance cache).
fn assert_nee_agrees_with_brute_force(scene: &Scene, what: &str) {
    let nee = sized_image(scene, in_full(true), (8, 6), 64, 1);
    let brute = sized_image(scene, in_full(false), (8, 6), 512, 2);
    let (a, ea) = mean_and_error(&nee);
    let (b, eb) = mean_and_error(&brute);
    assert!(a > 0.0 && b > 0.0, "{what}: {a} {b}");
    let tolerance = 4.0 * (ea * ea + eb * eb).sqrt() + 0.01 * a;
    assert!(
        (a - b).abs() < tolerance,
        "{what}: NEE {a} ± {ea}, brute force {b} ± {eb}"
    );
}

#[test]
fn light_sampling_through_mirrors_agrees_with_brute_force() {
    // The same estimate two ways: next-event estimation through mirror images with MIS, and
    // paths that find the light by chance; spherical, Euclidean and hyperbolic rooms.
    for signature in ["*235", "*2222", "*2223"] {
        assert_nee_agrees_with_brute_force(&scene(signature, LightKind::Sphere), signature);
    }
}

/// A room of an orbifold with side pairings: grey mirror walls without mirrors, open portals
/// (with their frames), the sphere light and camera of [`scene`]; with `partial_mirrors`, the
/// partial mirror of [`scene`] on every wall, portals included, and portals passing on 70 %.
fn portal_scene(symbol: &str, partial_mirrors: bool) -> Scene {
    let mut scene = scene(symbol, LightKind::Sphere);
    if !partial_mirrors {
        scene.walls.clear();
    } else {
        scene.room.portal_transmittance = [0.7; 3];
    }
    scene
}

#[test]
fn light_sampling_through_portals_agrees_with_brute_force() {
    // Light reaches the room through portals as through mirrors: light sampling draws the
    // light's images under the group's pairings, and brute force finds the light by chance
    // through the same portals. Cone points (632, 3*2 on the sphere, 4*3 in H²) and glides
    // (22×), with portals open and with mirrors hung on them.
    for (symbol, partial_mirrors) in [("632", false), ("22×", true), ("3*2", false), ("4*3", true)]
    {
        let what = format!("{symbol}, mirrors on the portals: {partial_mirrors}");
        assert_nee_agrees_with_brute_force(&portal_scene(symbol, partial_mirrors), &what);
    }
}

#[test]
fn point_lights_light_the_room_through_portals() {
    // Only light sampling finds a point light, so only its images under the group's pairings
    // carry its light through the portals: closed portals (transmittance 0) leave the room
    // darker, and with open ones the point light lights the room as a tiny sphere light of the
    // same power does (found both ways).
    for symbol in ["632", "22×", "3*2", "4*3"] {
        let mut open = portal_scene(symbol, false);
        open.lights[0].kind = LightKind::Point;
        open.room.wall_material = Material::Color { color: [0.0; 3] };
        let mut closed = open.clone();
        closed.room.portal_transmittance = [0.0; 3];
        let (a, _) = mean_and_error(&image(&open, true, 16, 3));
        let (b, _) = mean_and_error(&image(&closed, true, 16, 3));
        assert!(a > 1.2 * b && b > 0.0, "{symbol}: open {a}, closed {b}");
        assert_point_light_lights_as_a_tiny_sphere(open, symbol, 128);
    }
}

#[test]
fn light_sampling_agrees_with_brute_force_on_smooth_shaded_objects() {
    // Smooth shading normals differ from the faces' own: both estimators must treat the
    // directions that the two normals put on different sides alike.
    for signature in ["*235", "*2222", "*2223"] {
        assert_nee_agrees_with_brute_force(&scene_with_objects(signature), signature);
    }
}

/// A room with a smooth sphere and torus beside the light (they cast shadows and are lit
/// unevenly: what a cache would blur).
fn scene_with_objects(signature: &str) -> Scene {
    let mut scene = scene(signature, LightKind::Sphere);
    let c = scene.lights[0].at;
    for (shape, dx, crease) in [("sphere", 0.12, 90.0), ("torus", -0.12, 60.0)] {
        scene.objects.push(orbifold_scene::Object {
            shape: shape.into(),
            at: [c[0] + dx, c[1]],
            size: 0.2,
            crease,
            ..Default::default()
        });
    }
    scene
}

#[test]
fn the_radiance_cache_agrees_with_tracing_in_full() {
    // The cache replaces far and indirect light by the mean of earlier paths' estimates over a
    // cell no wider than the light's spread there: a blur below the pixel, not a change of
    // brightness. Blocks of 4×4 pixels of a 24×16 image agree with the full estimate within
    // 5 % (and 4 standard errors), and the whole image within 0.3 % and 4 standard errors (a
    // cache 10 % too bright is 2.9 % too bright in `*235`; measured apart: −0.5 ± 0.3 % in
    // `*235`, −0.2 ± 0.2 % in `*2223`, −0.06 ± 0.06 % in `*2222`; over 200 seeds the cache's
    // own bias shows, −0.22 ± 0.07 %, −0.27 ± 0.05 %, +0.05 ± 0.02 %: the blur of the reads
    // after a bounce, see docs/rendering.md).
    //
    // A cell's mean is shared by every sample that reads it, so the cache's noise is not in
    // the pixels' standard errors: the cached image is rendered with several seeds (several
    // caches), and the spread of a block over them is its error.
    const SEEDS: [u64; 12] = [3, 5, 7, 9, 11, 13, 15, 17, 19, 21, 23, 25];
    for signature in ["*235", "*2222", "*2223"] {
        let scene = scene_with_objects(signature);
        // Deep paths: the cache holds light of up to max_depth bounces *after* the surface it
        // is read at, so it differs from a shallow limit by the light of those extra bounces.
        let deep = |settings| Settings {
            max_depth: 20,
            ..settings
        };
        let cached: Vec<Film> = SEEDS
            .iter()
            .map(|&seed| sized_image(&scene, deep(cached(true)), (24, 16), 64, seed))
            .collect();
        let over_seeds = |value: &dyn Fn(&Film) -> f64| {
            mean_over_renders(&cached.iter().map(value).collect::<Vec<_>>())
        };
        let full = sized_image(&scene, deep(in_full(true)), (24, 16), 512, 4);
        let block = |film: &Film, bx: u32, by: u32| {
            let (mut mean, mut variance) = (0.0, 0.0);
            for y in 4 * by..4 * by + 4 {
                for x in 4 * bx..4 * bx + 4 {
                    mean += luminance(film.pixel(x, y)) / 16.0;
                    variance += film.standard_error(x, y).powi(2) / 256.0;
                }
            }
            (mean, variance.sqrt())
        };
        for by in 0..4 {
            for bx in 0..6 {
                let (a, ea) = over_seeds(&|film| block(film, bx, by).0);
                let (b, eb) = block(&full, bx, by);
                let tolerance = 4.0 * (ea * ea + eb * eb).sqrt() + 0.05 * b;
                assert!(
                    (a - b).abs() < tolerance,
                    "{signature}, block ({bx}, {by}): cached {a} ± {ea}, in full {b} ± {eb}"
                );
            }
        }
        let (a, ea) = over_seeds(&|film| mean_and_error(film).0);
        let (b, eb) = mean_and_error(&full);
        let tolerance = 4.0 * (ea * ea + eb * eb).sqrt() + 0.003 * b;
        assert!(
            (a - b).abs() < tolerance,
            "{signature}: cached {a} ± {ea}, in full {b} ± {eb}"
        );
    }
}

#[test]
fn the_radiance_cache_keeps_a_shallow_depth_limit() {
    // The cache's estimates hold the light of paths with the whole depth limit ahead of them;
    // read after a bounce, they would count bounces that the path may not take. With a shallow
    // limit only the first surfaces read the cache, whose estimates have the same limit ahead,
    // and the image is the truncated one. White surfaces make the missing bounce count.
    for signature in ["*235", "*2222", "*2223"] {
        let mut scene = scene_with_objects(signature);
        let white = Material::Color { color: [0.9; 3] };
        scene.room.wall_material = white.clone();
        scene.room.floor = white.clone();
        scene.room.ceiling = white;
        let shallow = |settings| Settings {
            max_depth: 2,
            ..settings
        };
        // (The cached image over several seeds: see `mean_over_seeds`.)
        let (a, ea) = mean_over_seeds(&[3, 5, 7, 9], |seed| {
            let film = sized_image(&scene, shallow(cached(true)), (24, 16), 16, seed);
            mean_and_error(&film).0
        });
        let full = sized_image(&scene, shallow(in_full(true)), (24, 16), 256, 4);
        let (b, eb) = mean_and_error(&full);
        let tolerance = 4.0 * (ea * ea + eb * eb).sqrt() + 0.01 * b;
        assert!(
            (a - b).abs() < tolerance,
            "{signature}: cached {a} ± {ea}, in full {b} ± {eb}"
        );
    }
}

#[test]
fn the_radiance_cache_lowers_the_noise_for_the_same_work() {
    // The cache makes a path cheaper (far and indirect light is read, not traced); its reads
    // are noisier than tracing, since a cell's mean holds only the estimates of the paths that
    // fed it. What it buys is less noise for the same work: noise² × rays traced is lower. The
    // noise is each pixel's spread over renders with several seeds, which holds the cache's own
    // noise (in no pixel's standard error). Deep paths, where the reads after a diffuse bounce
    // count. Measured ratios: 0.65, 0.59, 0.67. (With 3 bounces, only the camera's first
    // surfaces may read the cache: about 1.0, since in a picture this small every pixel's
    // footprint is wide enough to read it and few pixels share a cell; at 896² near surfaces do
    // not read it, and the far images that do share cells with many pixels.)
    const SEEDS: [u64; 6] = [5, 6, 7, 8, 9, 10];
    let deep = |settings| Settings {
        max_depth: 20,
        ..settings
    };
    for signature in ["*235", "*2222", "*2223"] {
        let scene = scene_with_objects(signature);
        let noise_and_rays = |settings: Settings| {
            let mut rays = 0;
            let films: Vec<Film> = SEEDS
                .iter()
                .map(|&seed| {
                    let options = RenderOptions {
                        filter: PixelFilter::Box,
                        ..RenderOptions::new(24, 16, 32, seed)
                    };
                    let rendered = render_scene(&scene, None, settings, &options).unwrap();
                    rays += rendered.rays;
                    rendered.film
                })
                .collect();
            (noise_between(&films), rays as f64)
        };
        let (a, rays_a) = noise_and_rays(deep(cached(true)));
        let (b, rays_b) = noise_and_rays(deep(in_full(true)));
        let ratio = a * a * rays_a / (b * b * rays_b);
        assert!(
            ratio < 0.85,
            "{signature}: noise² × rays {ratio} of full tracing's (noise {a} with the cache, {b} \
             without; rays {rays_a}, {rays_b})"
        );
    }
}

/// The mean over pixels of each pixel's luminance spread between `films` (of the same size)
/// relative to its mean (plus 0.01, so that dark pixels count by their absolute noise).
fn noise_between(films: &[Film]) -> f64 {
    let (w, h) = (films[0].width(), films[0].height());
    let n = films.len() as f64;
    let mut total = 0.0;
    for y in 0..h {
        for x in 0..w {
            let values: Vec<f64> = films.iter().map(|f| luminance(f.pixel(x, y))).collect();
            let mean = values.iter().sum::<f64>() / n;
            let variance = values.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / (n - 1.0);
            total += variance.sqrt() / (mean.max(0.0) + 0.01);
        }
    }
    total / f64::from(w * h)
}

/// Every path in full, with next-event estimation and `candidates` per light sample.
fn resampled(candidates: u32) -> Settings {
    Settings {
        light_candidates: Some(candidates),
        ..in_full(true)
    }
}

/// All mirrors of reflectance 0.9 (many images of the light), objects that cast shadows.
fn mirrored_scene_with_objects(signature: &str, light: LightKind) -> Scene {
    let mut scene = scene_with_objects(signature);
    scene.walls.clear();
    scene.room.mirrors = orbifold_scene::MirrorDefault::All;
    scene.room.reflectance = [0.9; 3];
    scene.lights[0].kind = light;
    scene
}

#[test]
fn resampled_light_samples_agree_with_plain_ones() {
    // Keeping one of several candidates ∝ its unblocked light, and weighting it by the
    // candidates' mean, is unbiased: the same mean as one plain light sample, in every geometry,
    // for sphere and point lights, with shadows.
    for signature in ["*235", "*2222", "*2223", "*444"] {
        for light in [LightKind::Sphere, LightKind::Point] {
            let scene = mirrored_scene_with_objects(signature, light);
            let plain = sized_image(&scene, resampled(1), (12, 8), 64, 7);
            let four = sized_image(&scene, resampled(4), (12, 8), 64, 8);
            let (a, ea) = mean_and_error(&plain);
            let (b, eb) = mean_and_error(&four);
            assert!(a > 0.0 && b > 0.0, "{signature} {light:?}: {a} {b}");
            let tolerance = 4.0 * (ea * ea + eb * eb).sqrt() + 0.01 * a;
            assert!(
                (a - b).abs() < tolerance,
                "{signature} {light:?}: plain {a} ± {ea}, four candidates {b} ± {eb}"
            );
        }
    }
}

#[test]
fn resampled_light_samples_lower_the_noise() {
    // At equal samples, four candidates leave less noise than one where there are many images
    // of the light to choose among (a Euclidean and a hyperbolic room of mirrors).
    for signature in ["*2222", "*444"] {
        let scene = mirrored_scene_with_objects(signature, LightKind::Sphere);
        let plain = sized_image(&scene, resampled(1), (24, 16), 32, 9);
        let four = sized_image(&scene, resampled(4), (24, 16), 32, 9);
        let (a, b) = (four.relative_noise(), plain.relative_noise());
        assert!(
            a < 0.9 * b,
            "{signature}: relative noise {a} with four candidates, {b} with one"
        );
    }
}

/// A spherical room whose walls are all mirrors of reflectance 0.9 and whose floor and ceiling
/// are grey, with no objects: light goes round the sphere again and again.
fn spherical_mirror_room(signature: &str, light: LightKind) -> Scene {
    let mut scene = scene(signature, light);
    scene.walls.clear();
    scene.room.mirrors = orbifold_scene::MirrorDefault::All;
    scene.room.reflectance = [0.9; 3];
    scene.lights[0].radius = 0.05;
    scene
}

#[test]
fn light_sampling_round_the_sphere_agrees_with_brute_force() {
    // Light sampling follows the geodesics to each light image that go round the sphere once
    // and more (half-turns), and bounces that reach a light that way are weighed against it by
    // MIS: the two estimates must still agree where that light matters most.
    for signature in ["*", "*22", "*222"] {
        let scene = spherical_mirror_room(signature, LightKind::Sphere);
        assert_nee_agrees_with_brute_force(&scene, signature);
    }
}

#[test]
fn light_sampling_in_a_spherical_room_whose_walls_block_the_ways_round_agrees_with_brute_force() {
    // Black walls, and one partial mirror on one wall: the room and its images fit in a
    // hemisphere, so light sampling spends nothing on the ways round the sphere. Brute force
    // still follows every way: if any carried light, the two would differ.
    for mirrors in [0, 1] {
        let mut scene = scene("*222", LightKind::Sphere);
        scene.room.wall_material = Material::Color { color: [0.0; 3] };
        scene.walls.truncate(mirrors);
        assert_nee_agrees_with_brute_force(&scene, &format!("*222, {mirrors} mirrors"));
    }
}

#[test]
fn a_point_light_lights_a_spherical_mirror_room_as_a_tiny_sphere_light_does() {
    // Only light sampling finds a point light, so the geodesics that go round the sphere again
    // are its only way there; a sphere light's come partly from bounces weighed against them.
    // Both must light a spherical room of mirrors alike. (On the floor seen from above, light
    // that has gone round again arrives grazing, a few per cent of the whole at most: this
    // checks that following it adds no light that is not there, not that it is needed.) As in
    // `a_point_light_lights_the_room_as_a_tiny_sphere_light_of_the_same_power`, the camera
    // looks straight down at the floor beside the light.
    for signature in ["*", "*22"] {
        let point = spherical_mirror_room(signature, LightKind::Point);
        assert_point_light_lights_as_a_tiny_sphere(point, signature, 256);
    }
}

/// The room `point` (with a point light) seen straight down at the floor beside the light, and
/// the same room with a sphere light of radius 0.01 and the same power instead, give the same
/// image mean within 4 standard errors + 2 % (every path traced in full, at most 2 bounces,
/// 16×12 pixels with `samples` each).
fn assert_point_light_lights_as_a_tiny_sphere(mut point: Scene, what: &str, samples: u32) {
    point.camera.pitch = -89.0;
    point.camera.fov = 60.0;
    let mut sphere = point.clone();
    sphere.lights[0].kind = LightKind::Sphere;
    sphere.lights[0].radius = 0.01;
    let render = |scene: &Scene, seed| {
        let settings = Settings {
            max_depth: 2,
            ..in_full(true)
        };
        sized_image(scene, settings, (16, 12), samples, seed)
    };
    let (a, ea) = mean_and_error(&render(&point, 5));
    let (b, eb) = mean_and_error(&render(&sphere, 6));
    assert!(a > 0.0 && b > 0.0, "{what}: {a} {b}");
    let tolerance = 4.0 * (ea * ea + eb * eb).sqrt() + 0.02 * a;
    assert!(
        (a - b).abs() < tolerance,
        "{what}: point light {a} ± {ea}, sphere light {b} ± {eb}"
    );
}

#[test]
fn point_lights_light_the_room_through_mirrors() {
    // With the direct view of a point light blocked by nothing, mirrors add light: the same
    // room with mirrors is brighter than without.
    // Black walls: without mirrors they add nothing; as mirrors of reflectance 0.8 they show
    // the light's images, which light the floor. (Brute force cannot find a point light.)
    for signature in ["*2222", "*333", "*2223", "*235"] {
        let mut plain = scene(signature, LightKind::Point);
        plain.room.wall_material = Material::Color { color: [0.0; 3] };
        plain.walls.clear();
        let mut mirrored = plain.clone();
        mirrored.room.mirrors = orbifold_scene::MirrorDefault::All;
        mirrored.room.reflectance = [0.8; 3];
        let (a, _) = mean_and_error(&image(&mirrored, true, 16, 3));
        let (b, _) = mean_and_error(&image(&plain, true, 16, 3));
        assert!(
            a > 1.2 * b && b > 0.0,
            "{signature}: mirrored {a}, plain {b}"
        );
        let (c, _) = mean_and_error(&image(&mirrored, false, 16, 3));
        assert_eq!(c, 0.0, "{signature}: brute force found a point light");
    }
}

#[test]
fn a_seed_gives_the_same_image_whatever_the_threads() {
    let scene = scene("*333", LightKind::Sphere);
    let one = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .unwrap()
        .install(|| image(&scene, true, 12, 9));
    // (12 samples: adaptive rounds, which choose pixels from the film so far, are included.)
    let two = rayon::ThreadPoolBuilder::new()
        .num_threads(2)
        .build()
        .unwrap()
        .install(|| image(&scene, true, 12, 9));
    for y in 0..one.height() {
        for x in 0..one.width() {
            assert_eq!(one.pixel(x, y), two.pixel(x, y));
        }
    }
    let other = image(&scene, true, 12, 10);
    assert!((0..6).any(|y| (0..8).any(|x| other.pixel(x, y) != one.pixel(x, y))));
}

#[test]
fn every_pixel_is_finite() {
    // Ideal corners, full mirrors (rays that bounce until the limit), the sphere's antipodal
    // focusing, spot and rectangle lights.
    let mut cases = Vec::new();
    for (signature, light) in [
        ("*∞∞∞", LightKind::Point),
        ("*22", LightKind::Spot),
        ("*235", LightKind::Rectangle),
        ("*2223", LightKind::Sphere),
    ] {
        let mut s = scene(signature, light);
        s.room.mirrors = orbifold_scene::MirrorDefault::All;
        s.room.reflectance = [1.0; 3];
        s.walls.clear();
        cases.push(s);
    }
    cases.push(Scene::default());
    for scene in &cases {
        let film = image(scene, true, 2, 5);
        assert_eq!(film.dropped(), 0, "{}", scene.orbifold.signature);
        for y in 0..film.height() {
            for x in 0..film.width() {
                assert!(film.pixel(x, y).iter().all(|v| v.is_finite() && *v >= 0.0));
            }
        }
    }
}

#[test]
fn the_spread_is_the_area_density_of_geodesic_spheres() {
    // J(ℓ, α) against the geodesic flow: the area swept by the ends of geodesics of length ℓ
    // from one point, per unit solid angle, by finite differences in (α, φ).
    for geometry in [
        Geometry::Spherical,
        Geometry::Euclidean,
        Geometry::Hyperbolic,
    ] {
        let space = Space::new(geometry);
        let x = space.exp(DVec3::Z, DVec3::new(0.2, -0.1, 0.0));
        let frame = TangentFrame::at(space, x);
        for (length, alpha, phi) in [(0.7, 0.3, 0.4), (1.9, -0.8, 2.0), (2.5, 0.05, -1.0)] {
            let end = |a: f64, f: f64| {
                let v = DVec3::new(a.cos() * f.cos(), a.cos() * f.sin(), a.sin());
                frame.ray(space, x, 0.3, v).point_at(space, length)
            };
            let e = 1e-6;
            let (p, hp) = end(alpha, phi);
            let (pa, ha) = end(alpha + e, phi);
            let (pf, hf) = end(alpha, phi + e);
            let da = (pa - p, ha - hp);
            let df = (pf - p, hf - hp);
            let dot = |u: (DVec3, f64), v: (DVec3, f64)| space.point_dot(u.0, v.0) + u.1 * v.1;
            let area = (dot(da, da) * dot(df, df) - dot(da, df).powi(2)).sqrt();
            let solid_angle = alpha.cos() * e * e;
            let measured = area / solid_angle;
            let expected = spread(space, length, length * alpha.cos());
            assert!(
                (measured - expected).abs() < 1e-4 * expected,
                "{geometry:?} ℓ={length} α={alpha}: {measured} vs {expected}"
            );
        }
    }
}

#[test]
fn adaptive_sampling_spends_the_samples_where_the_screen_is_noisy() {
    let scene = scene("*2222", LightKind::Sphere);
    let settings = Settings {
        max_depth: 3,
        ..Settings::default()
    };
    let (w, h, spp) = (32u32, 24u32, 24u32);
    let pixels = u64::from(w * h);
    let run = |adaptive: bool| {
        let options = RenderOptions {
            adaptive,
            ..RenderOptions::new(w, h, spp, 4)
        };
        render_scene(&scene, None, settings, &options).unwrap()
    };
    let (uniform, adaptive) = (run(false), run(true));
    // Without it every pixel gets the same count; with it, the same budget in all.
    assert_eq!(uniform.paths, u64::from(spp) * pixels);
    assert!((0..h).all(|y| (0..w).all(|x| uniform.film.samples(x, y) == u64::from(spp))));
    assert!(adaptive.paths >= u64::from(spp) * pixels);
    assert!(adaptive.paths < u64::from(spp + 1) * pixels);
    assert_eq!(adaptive.samples, spp);
    // The quarter of the pixels that got the most samples is the noisiest on screen (as the
    // uniform render measures it): 1.9 times the least sampled quarter's error. (A pixel's
    // count comes from its neighbours' noise, never its own, which keeps the image unbiased;
    // counted by its own too, the ratio was over 2.)
    let errors = uniform.film.display_errors(uniform.film.auto_exposure());
    let mut by_count: Vec<(u64, f64)> = (0..h)
        .flat_map(|y| (0..w).map(move |x| (x, y)))
        .map(|(x, y)| (adaptive.film.samples(x, y), errors[(y * w + x) as usize]))
        .collect();
    by_count.sort_by(|a, b| a.0.cmp(&b.0).then(a.1.total_cmp(&b.1)));
    let quarter = by_count.len() / 4;
    let mean = |s: &[(u64, f64)]| s.iter().map(|p| p.1).sum::<f64>() / s.len() as f64;
    let (fewest, most) = (&by_count[..quarter], &by_count[by_count.len() - quarter..]);
    assert!(most[0].0 > fewest[quarter - 1].0, "the counts differ");
    assert!(
        mean(most) > 1.5 * mean(fewest),
        "display error of the most sampled {:.2}, of the least {:.2}",
        mean(most),
        mean(fewest)
    );
}

#[test]
fn adaptive_sampling_for_a_denoised_image_spends_the_samples_where_the_filter_cannot_help() {
    let scene = scene("*2222", LightKind::Sphere);
    // The plain light sample: resampled ones take out most of the noise that the denoiser
    // smooths (the first surface's light sample), so that what is left of the raw noise is
    // mostly where the filter cannot help, and the two targets would nearly agree (mean root
    // reduction 0.82 against 0.76 with four candidates, 0.69 with one).
    let settings = Settings {
        max_depth: 3,
        light_candidates: Some(1),
        ..Settings::default()
    };
    let (w, h, spp) = (48u32, 36u32, 40u32);
    let pixels = u64::from(w * h);
    let run = |adaptive: bool, threads: usize| {
        let options = RenderOptions {
            adaptive,
            denoised: true,
            ..RenderOptions::new(w, h, spp, 4)
        };
        rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap()
            .install(|| render_scene(&scene, None, settings, &options).unwrap())
    };
    let (uniform, adaptive) = (run(false, 2), run(true, 2));
    assert!(adaptive.paths >= u64::from(spp) * pixels);
    assert!(adaptive.paths < u64::from(spp + 1) * pixels);
    // The denoiser runs inside the loop: still the same image whatever the threads.
    let single = run(true, 1);
    assert!((0..h).all(|y| (0..w).all(|x| single.film.pixel(x, y) == adaptive.film.pixel(x, y))));
    // Against adaptive sampling for the raw image, the samples move to the pixels that the
    // denoiser leaves alone (its variance reduction, measured on the uniform render).
    let raw = {
        let options = RenderOptions::new(w, h, spp, 4);
        render_scene(&scene, None, settings, &options).unwrap()
    };
    let (_, reduction) =
        denoise_with_reduction(&uniform.film, &uniform.guides, &DenoiseOptions::default());
    // The mean over the adaptive rounds' samples (those beyond the full rounds' count, which
    // every pixel has) of the root of the reduction at their pixel.
    let share = |film: &Film| {
        let counts: Vec<f64> = (0..w * h)
            .map(|i| film.samples(i % w, i / w) as f64)
            .collect();
        let fewest = counts.iter().copied().fold(f64::INFINITY, f64::min);
        let (mut sum, mut all) = (0.0, 0.0);
        for (n, r) in counts.iter().zip(&reduction) {
            (sum, all) = (sum + (n - fewest) * r.sqrt(), all + n - fewest);
        }
        sum / all
    };
    let (for_denoised, for_raw) = (share(&adaptive.film), share(&raw.film));
    assert!(
        for_denoised > 1.2 * for_raw,
        "mean root reduction where the adaptive samples went: {for_denoised:.2} aiming at the \
         denoised image, {for_raw:.2} at the raw one"
    );
}

#[test]
fn a_point_light_lights_the_room_as_a_tiny_sphere_light_of_the_same_power() {
    // Brute force cannot find a point light; its light through the mirror images is checked
    // against the limit it stands for: a sphere light of the same power, small against the room
    // (whose own light sampling agrees with brute force, above). Far from the light the two
    // differ by O(r²/d²).
    // The camera looks straight down at the floor beside the light: neither the light nor its
    // images are in view (a tiny sphere seen directly would decide the mean), only the floor lit
    // directly and through the partial mirrors.
    for signature in ["*235", "*2222", "*2223"] {
        assert_point_light_lights_as_a_tiny_sphere(
            scene(signature, LightKind::Point),
            signature,
            512,
        );
    }
}

/// Spot and rectangle lights shine where they point. A white floor under a light pointing
/// straight down, seen through a narrow camera with direct light only, has the radiance E/π of
/// the analytic irradiance at the point below the light; pointing up, the floor stays dark.
#[test]
fn spot_and_rectangle_lights_shine_where_they_point() {
    let (height, power, size) = (0.85_f64, 30.0, [0.3_f64, 0.2_f64]);
    // Irradiance under the centre of a w × l Lambertian rectangle of radiance L at distance d:
    // four corner rectangles, each of form factor (1/2π)[x/√(1+x²) atan(y/√(1+x²)) + (x ↔ y)].
    let corner = |x: f64, y: f64| {
        let (sx, sy) = ((1.0 + x * x).sqrt(), (1.0 + y * y).sqrt());
        (x / sx * (y / sx).atan() + y / sy * (x / sy).atan()) / (2.0 * std::f64::consts::PI)
    };
    let radiance = power / (std::f64::consts::PI * size[0] * size[1]);
    let rectangle_e = std::f64::consts::PI
        * radiance
        * 4.0
        * corner(0.5 * size[0] / height, 0.5 * size[1] / height);
    // A spot of power P over the cone of half-angle θ: intensity P / (2π(1 − cos θ)).
    let cone = 40.0_f64;
    let spot_e =
        power / (2.0 * std::f64::consts::PI * (1.0 - cone.to_radians().cos())) / (height * height);
    for (kind, irradiance) in [
        (LightKind::Rectangle, rectangle_e),
        (LightKind::Spot, spot_e),
    ] {
        for pitch in [-90.0, 90.0] {
            let mut scene = Scene::default();
            scene.orbifold.signature = "*2222".into();
            scene.objects.clear();
            scene.room.mirrors = orbifold_scene::MirrorDefault::None;
            let black = Material::Color { color: [0.0; 3] };
            scene.room.wall_material = black.clone();
            scene.room.ceiling = black;
            scene.room.floor = Material::Color { color: [1.0; 3] };
            let light = &mut scene.lights[0];
            (light.kind, light.at, light.height) = (kind, [0.0, 0.0], height);
            (light.power, light.color, light.size) = (power, [1.0; 3], size);
            (light.pitch, light.cone) = (pitch, cone);
            // The camera 0.2 to the side (0.1 in the model) at height 0.5 looks at the floor
            // right under the light through a one-degree pixel.
            scene.camera.at = [-0.1, 0.0];
            scene.camera.height = 0.5;
            scene.camera.yaw = 0.0;
            scene.camera.pitch = -(0.5_f64 / 0.2).atan().to_degrees();
            scene.camera.fov = 1.0;
            let settings = Settings {
                max_depth: 1,
                ..in_full(true)
            };
            let film = sized_image(&scene, settings, (1, 1), 256, 3);
            let seen = luminance(film.pixel(0, 0));
            let expected = if pitch < 0.0 {
                irradiance / std::f64::consts::PI
            } else {
                0.0
            };
            assert!(
                (seen - expected).abs() <= 0.03 * irradiance / std::f64::consts::PI,
                "{kind:?} pointing at pitch {pitch}: floor radiance {seen}, expected {expected}"
            );
        }
    }
}

proptest::proptest! {
    #![proptest_config(proptest::prelude::ProptestConfig::with_cases(48))]
    /// A path's ray count is its stretches between mirrors: with no bounce off a surface, no
    /// light sampling and perfect mirrors (so no roulette), it is the tracer's own count of
    /// hits along the ray (every mirror, then the surface it ends on), in every geometry.
    #[test]
    fn a_path_counts_one_ray_per_stretch_between_mirrors(
        g in 0usize..4, x in -0.2f64..0.2, y in -0.2f64..0.2, h in 0.1f64..0.9,
        yaw in 0.0f64..std::f64::consts::TAU, pitch in -0.4f64..0.4,
    ) {
        use num_complex::Complex64;
        use orbifold_trace::geodesic::Ray;
        use orbifold_render::integrator::Integrator;
        use orbifold_render::sampler::Sampler;
        use orbifold_trace::tracer::Tracer;
        let signature = ["*235", "*2222", "*333", "*2223"][g];
        let mut scene = scene(signature, LightKind::Sphere);
        scene.lights.clear();
        for mirror in scene.walls.iter_mut().flat_map(|w| w.mirrors.iter_mut()) {
            mirror.reflectance = [1.0; 3];
        }
        let settings = Settings { max_depth: 0, nee: false, ..Settings::default() };
        let integrator = Integrator::from_scene(&scene, None, settings).unwrap();
        let tracer = Tracer::from_scene(&scene, None).unwrap();
        let space = integrator.space();
        let centre = integrator.centre();
        let ray = Ray::from_model(space, centre + Complex64::new(x, y) * 0.5, h, yaw, pitch);
        let path = tracer.follow(&ray, orbifold_render::integrator::MAX_MIRROR_BOUNCES);
        proptest::prop_assume!(path.hits.len() < orbifold_render::integrator::MAX_MIRROR_BOUNCES);
        let sample = integrator.sample(&ray, &mut Sampler::new(1, 2, 3));
        proptest::prop_assert_eq!(sample.rays as usize, path.hits.len());
    }
}
