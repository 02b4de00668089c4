//! Materials and energy balance: the furnace test in rooms of S²×R, E²×R and H²×R (with
//! mirrors, objects and glass), outward normals of the built-in objects (glass needs them),
//! and the geometric term integrated over the floor against the solid angle it covers.

use std::f64::consts::{PI, TAU};

use orbifold::Geometry;
use orbifold::space::Space;
use orbifold_render::film::Film;
use orbifold_render::integrator::Settings;
use orbifold_render::lights::{TangentFrame, connect, spread, travel_direction};
use orbifold_render::render::{RenderOptions, render_scene};
use orbifold_scene::{Material, Mirror, MirrorDefault, Object, Scene, Wall};
use orbifold_trace::tracer::{SurfaceId, Tracer};
use orbifold_trace::triangle::TriangleHit;

const ALBEDO: f64 = 0.5;
const GLOW: f64 = 0.25;

/// A closed room of `signature` whose every opaque surface is white with albedo `ALBEDO`, with
/// a partial mirror of reflectance 1 on every wall and the default figure — or, if `extra` is
/// not empty, those objects instead; no lights.
fn furnace(signature: &str, extra: Vec<Object>) -> Scene {
    let mut scene = Scene::default();
    scene.orbifold.signature = signature.into();
    let layout = scene.layout().unwrap();
    let c = [layout.centre.re, layout.centre.im];
    let white = Material::Color { color: [ALBEDO; 3] };
    scene.lights.clear();
    scene.room.mirrors = MirrorDefault::None;
    scene.room.wall_material = white.clone();
    scene.room.floor = white.clone();
    scene.room.ceiling = white.clone();
    scene.walls = (0..layout.vertices.len())
        .map(|i| Wall {
            index: i,
            material: None,
            mirrors: vec![Mirror {
                from: 0.1,
                to: 0.7,
                bottom: 0.1,
                top: Some(0.8),
                reflectance: [1.0; 3],
            }],
        })
        .collect();
    for object in &mut scene.objects {
        object.at = c;
        object.material = white.clone();
    }
    if !extra.is_empty() {
        scene.objects.clear();
    }
    for mut object in extra {
        object.at = [c[0] + object.at[0], c[1] + object.at[1]];
        scene.objects.push(object);
    }
    scene.camera.at = [c[0] - 0.1, c[1]];
    scene.camera.pitch = -10.0;
    scene.camera.fov = 110.0;
    scene
}

/// The unbiased estimate (every path traced in full), or with the radiance cache.
fn image_with(scene: &Scene, samples: u32, radiance_cache: bool) -> Film {
    let settings = Settings {
        max_depth: 200,
        glow: [GLOW; 3],
        radiance_cache,
        ..Settings::default()
    };
    render_scene(scene, None, settings, &RenderOptions::new(8, 6, samples, 7))
        .unwrap()
        .film
}

fn image(scene: &Scene, samples: u32) -> Film {
    image_with(scene, samples, false)
}

/// The image's mean against the equilibrium radiance glow / (1 − ρ), within 5 standard errors
/// (pixels are independent estimates), and no pixel far from it. (In a furnace every path's
/// weight depends only on how many bounces it survives, so a lost path — one that slips out
/// of the room or ends early — is what would show.)
fn assert_equilibrium(film: &Film, what: &str) {
    let expected = GLOW / (1.0 - ALBEDO);
    let n = f64::from(film.width() * film.height());
    let (mut mean, mut variance) = (0.0, 0.0);
    for y in 0..film.height() {
        for x in 0..film.width() {
            let value = film.pixel(x, y);
            assert!(
                value.iter().all(|v| (v - expected).abs() < 0.3 * expected),
                "{what}: pixel ({x}, {y}) = {value:?}, expected {expected}"
            );
            mean += value[1] / n;
            variance += film.standard_error(x, y).powi(2) / (n * n);
        }
    }
    let error = variance.sqrt();
    assert!(
        (mean - expected).abs() < 5.0 * error + 1e-3 * expected,
        "{what}: mean {mean} ± {error}, expected {expected}"
    );
}

#[test]
fn furnace_reaches_the_analytic_equilibrium() {
    // Mirrors of reflectance 1 neither absorb nor emit, so the equilibrium holds through them.
    for signature in ["*235", "*2222", "*2223", "*∞∞∞"] {
        let film = image(&furnace(signature, Vec::new()), 48);
        assert_equilibrium(&film, signature);
    }
}

#[test]
fn the_radiance_cache_keeps_the_furnace_equilibrium() {
    // Read from the cache, a surface reflects its cell's mean estimate: in a furnace that is the
    // equilibrium too. The cache's cells are shared by many pixels, so its noise is not in the
    // pixels' standard errors: the image mean is held to 1.5 %.
    let expected = GLOW / (1.0 - ALBEDO);
    for signature in ["*235", "*2222", "*2223", "*∞∞∞"] {
        let film = image_with(&furnace(signature, Vec::new()), 256, true);
        let n = f64::from(film.width() * film.height());
        let mut mean = 0.0;
        for y in 0..film.height() {
            for x in 0..film.width() {
                let value = film.pixel(x, y);
                assert!(
                    value.iter().all(|v| (v - expected).abs() < 0.3 * expected),
                    "{signature}: pixel ({x}, {y}) = {value:?}, expected {expected}"
                );
                mean += value[1] / n;
            }
        }
        assert!(
            (mean - expected).abs() < 0.015 * expected,
            "{signature}: mean {mean}, expected {expected}"
        );
    }
}

#[test]
fn clear_glass_in_the_furnace_changes_nothing() {
    // A clear dielectric neither absorbs nor emits: with radiance scaled by 1/η² on the way in
    // and η² on the way out, the furnace stays at its equilibrium behind and inside the glass.
    // (Nothing opaque may touch the glass: a white surface inside it would glow at the
    // outside's radiance, not n² times it. So the sphere must keep clear of the walls: in the
    // small `*235` triangle, whose inscribed circle has radius 0.13, it is smaller and nearer
    // the centre. A sphere of size 0.25 at 0.1 there crosses a wall and renders 3 % dark.)
    for (signature, ahead, size) in [
        ("*235", 0.02, 0.1),
        ("*333", 0.1, 0.25),
        ("*2223", 0.1, 0.25),
    ] {
        let scene = furnace(signature, Vec::new());
        let layout = scene.layout().unwrap();
        let space = Space::new(layout.geometry);
        let centre = layout.centre + num_complex::Complex64::new(ahead, 0.0);
        for edge in &layout.edges {
            let clearance = space.signed_distance(edge.wall, centre);
            assert!(
                clearance > size / 2.0 + 0.02,
                "{signature}: the glass is {clearance} from a wall"
            );
        }
        let glass = Object {
            shape: "sphere".into(),
            // Ahead of the camera, filling much of its view.
            at: [ahead, 0.0],
            height: 0.3,
            size,
            material: Material::Glass {
                tint: [1.0; 3],
                ior: 1.5,
            },
            ..Object::default()
        };
        let film = image(&furnace(signature, vec![glass]), 48);
        assert_equilibrium(&film, &format!("{signature} with glass"));
    }
}

#[test]
fn built_in_objects_have_outward_normals() {
    // Glass tells inside from outside by the normal: rays from outside towards an object must
    // meet it against its normal.
    for shape in ["sphere", "torus", "cube", "figure", "letter-p", "letter-f"] {
        for signature in ["*235", "*333", "*2223"] {
            let mut scene = Scene::default();
            scene.orbifold.signature = signature.into();
            let layout = scene.layout().unwrap();
            let centre = layout.centre;
            scene.objects.truncate(1);
            let object = &mut scene.objects[0];
            object.shape = shape.into();
            object.at = [centre.re, centre.im];
            object.height = 0.2;
            object.size = 0.3;
            let tracer = Tracer::from_scene(&scene, None).unwrap();
            let space = tracer.space();
            let target = space.to_ambient(centre);
            let mut hits = 0;
            for k in 0..24 {
                let angle = TAU * f64::from(k) / 24.0;
                let from = centre + 0.3 * num_complex::Complex64::from_polar(0.4, angle);
                let x = space.to_ambient(from);
                let frame = TangentFrame::at(space, x);
                let aim = 0.2 + 0.15 * f64::from(k % 3);
                let link = connect(space, &frame, (x, 0.35), (target, aim), 0).unwrap();
                let Some(hit) = tracer.nearest(&link.ray) else {
                    continue;
                };
                let (SurfaceId::Object(i), Some((triangle, barycentric))) =
                    (hit.surface, hit.triangle)
                else {
                    continue;
                };
                let instance = &tracer.objects.instances()[i];
                let t = TriangleHit {
                    s: hit.s,
                    triangle,
                    barycentric,
                };
                let (n, up) = instance.normal(space, &t).unwrap();
                let at_hit = TangentFrame::at(space, hit.point);
                let normal = at_hit.to_local(space, n, up);
                let travel = travel_direction(space, &at_hit, &link.ray, hit.s);
                assert!(
                    normal.dot(travel) < 0.0,
                    "{shape} in {signature}: ray {k} meets the object along its normal"
                );
                hits += 1;
            }
            // (Rays aimed at a torus's centre can pass through its hole.)
            assert!(hits >= 6, "{shape} in {signature}: only {hits} hits");
        }
    }
}

/// Simpson's rule on [a, b] with n (even) intervals.
fn simpson(f: impl Fn(f64) -> f64, a: f64, b: f64, n: usize) -> f64 {
    let step = (b - a) / n as f64;
    let inner: f64 = (1..n)
        .map(|i| {
            let weight = if i % 2 == 1 { 4.0 } else { 2.0 };
            weight * f(a + step * i as f64)
        })
        .sum();
    (f(a) + inner + f(b)) * step / 3.0
}

#[test]
fn geometric_term_integrates_to_the_solid_angle_it_covers() {
    // The light that a point at height h sees from the floor within intrinsic distance σ_max:
    // ∫ cos θ_floor / J(ℓ, σ) dA over the disc, with dA = S_κ(σ) dσ dφ and cos θ_floor = h / ℓ,
    // must be the solid angle of the directions that reach the floor before σ_max,
    // 2π (1 − h / √(σ_max² + h²)) — whatever the curvature.
    for geometry in [
        Geometry::Spherical,
        Geometry::Euclidean,
        Geometry::Hyperbolic,
    ] {
        let space = Space::new(geometry);
        for h in [0.05, 0.5, 2.0] {
            let reach: &[f64] = if geometry == Geometry::Spherical {
                &[0.3, 1.5, PI - 1e-9]
            } else {
                &[0.3, 1.5, 6.0]
            };
            for &sigma_max in reach {
                let integrand = |sigma: f64| {
                    let length = (sigma * sigma + h * h).sqrt();
                    let area = if sigma == 0.0 { 0.0 } else { space.sin(sigma) };
                    TAU * (h / length) * area / spread(space, length, sigma)
                };
                let integral = simpson(integrand, 0.0, sigma_max, 20_000);
                let expected = TAU * (1.0 - h / (sigma_max * sigma_max + h * h).sqrt());
                assert!(
                    (integral - expected).abs() < 1e-6 * TAU,
                    "{geometry:?} h {h} σ {sigma_max}: {integral} against {expected}"
                );
            }
        }
    }
}

#[test]
fn sphere_lights_sample_every_triangle_that_faces_the_point() {
    // Light sampling keeps only the triangles of a sphere light that can face the lit point:
    // each one that does face it (its normal against the geodesic to the point, measured
    // exactly) must keep a positive density, and the kept triangles' probabilities add up to 1.
    use orbifold_render::lights::{Emitter, Light};
    use orbifold_scene::LightKind;
    for signature in ["*235", "*333", "*2223"] {
        let mut scene = Scene::default();
        scene.orbifold.signature = signature.into();
        let layout = scene.layout().unwrap();
        let c = layout.centre;
        let light = &mut scene.lights[0];
        light.kind = LightKind::Sphere;
        light.at = [c.re, c.im];
        light.height = 0.6;
        light.radius = 0.15;
        let space = layout.space();
        let lights = Light::from_scene(space, &scene).unwrap();
        let Emitter::Area { instance, .. } = &lights[0].emitter else {
            panic!("a sphere light is an area light")
        };
        let triangles = instance.bvh.triangle_count() as u32;
        for k in 0..12 {
            let angle = TAU * f64::from(k) / 12.0;
            let reach = [0.17, 0.3, 0.6][k as usize % 3];
            let z = c + num_complex::Complex64::from_polar(0.5 * reach, angle);
            let (x, h) = (space.to_ambient(z), [0.1, 0.6, 0.95][k as usize % 3]);
            let third = [1.0 / 3.0; 3];
            let mut total = 0.0;
            for (t, corner) in (0..triangles).flat_map(|t| (0..4).map(move |c| (t, c))) {
                // The centroid and points near each corner.
                let barycentric = match corner {
                    0 => third,
                    c => {
                        let mut w = [0.01; 3];
                        w[c - 1] = 0.98;
                        w
                    }
                };
                let hit = TriangleHit {
                    s: 0.0,
                    triangle: t,
                    barycentric,
                };
                let (p, hp) = instance.point(space, &hit);
                let pdf = lights[0].pdf_area(space, t, barycentric, Some((x, h)));
                if corner == 0 {
                    let triangle = instance.bvh.triangle(t);
                    let jacobian = orbifold_render::lights::area_jacobian(
                        space,
                        &triangle.points,
                        &triangle.heights,
                        third,
                    );
                    total += pdf * 0.5 * jacobian;
                }
                let frame = TangentFrame::at(space, p);
                let Some(link) = connect(space, &frame, (p, hp), (x, h), 0) else {
                    continue;
                };
                let towards = travel_direction(space, &frame, &link.ray, 0.0);
                let (nh, nv) = instance.normal(space, &hit).unwrap();
                let normal = frame.to_local(space, nh, nv);
                if normal.dot(towards) > 1e-9 {
                    assert!(
                        pdf > 0.0,
                        "{signature}: triangle {t} faces point {k} but is never sampled"
                    );
                }
            }
            assert!(
                (total - 1.0).abs() < 1e-9,
                "{signature}: probabilities add up to {total}"
            );
        }
    }
}
