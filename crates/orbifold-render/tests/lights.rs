//! Area lights: a shadow ray to a point of a sphere light that faces the lit point does not meet
//! the light before it (so the renderer leaves the light's own mesh out of that ray's tests).

use num_complex::Complex64;
use orbifold_render::lights::{Emitter, Light, TangentFrame, aim_at, connect, travel_direction};
use orbifold_scene::{LightKind, Scene};
use proptest::prelude::*;

/// The default room of `signature` with a sphere light of radius 0.1 at height 0.6 over the
/// centre, its lights, and the centre (model).
fn lights(signature: &str) -> (orbifold::space::Space, Vec<Light>, Complex64) {
    let mut scene = Scene::default();
    scene.orbifold.signature = signature.into();
    let layout = scene.layout().unwrap();
    scene.lights[0].kind = LightKind::Sphere;
    scene.lights[0].at = [layout.centre.re, layout.centre.im];
    scene.lights[0].height = 0.6;
    scene.lights[0].radius = 0.1;
    let space = layout.space();
    (
        space,
        Light::from_scene(space, &scene).unwrap(),
        layout.centre,
    )
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(300))]
    #[test]
    fn shadow_rays_to_the_facing_side_of_a_sphere_light_meet_it_only_at_the_end(
        g in 0usize..3,
        (dx, dy, h) in (-0.5f64..0.5, -0.5f64..0.5, 0.0f64..1.0),
        u in 0.0f64..1.0,
        v in (0.0f64..1.0, 0.0f64..1.0),
    ) {
        let (space, lights, centre) = lights(["*235", "*2222", "*2223"][g]);
        let light = &lights[0];
        let Emitter::Area { instance, .. } = &light.emitter else { panic!("a sphere light") };
        let z = centre + Complex64::new(0.4 * dx, 0.4 * dy);
        let x = space.to_ambient(z);
        // Points inside the light's reach are not asked about.
        prop_assume!((space.ambient_distance(x, light.position).powi(2) + (h - 0.6f64).powi(2)).sqrt() > 0.15);
        let from = Some((x, h));
        let point = light.sample_point(space, u, v, from).unwrap();
        let (triangle, _) = point.triangle.unwrap();
        if light.reaches_unobstructed(space, triangle, from) {
            let frame = TangentFrame::at(space, x);
            let link = connect(space, &frame, (x, h), (point.x, point.h), 0).unwrap();
            let hit = instance.intersect(space, &link.ray, 0.0, f64::INFINITY).unwrap();
            prop_assert!(
                hit.s > link.length * (1.0 - 1e-7) - 1e-9,
                "met the light at {} of {}", hit.s, link.length
            );
        }
    }
}

#[test]
fn most_sampled_points_of_a_sphere_light_are_known_to_be_unobstructed() {
    for signature in ["*235", "*2222", "*2223"] {
        let (space, lights, centre) = lights(signature);
        let x = space.to_ambient(centre + Complex64::new(0.3, 0.1));
        let from = Some((x, 0.2));
        let n = 400;
        let known = (0..n)
            .filter(|k| {
                let u = (f64::from(*k) + 0.5) / f64::from(n);
                let point = lights[0].sample_point(space, u, (0.3, 0.6), from).unwrap();
                lights[0].reaches_unobstructed(space, point.triangle.unwrap().0, from)
            })
            .count();
        assert!(known > n as usize * 3 / 4, "{signature}: {known} of {n}");
        // Not for a point light, nor without the lit point.
        assert!(!lights[0].reaches_unobstructed(space, 0, None));
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(400))]
    /// Light sampling from a point picks among the sphere light's triangles that can face it;
    /// every point of the light that a geodesic from there meets first must be among them, or
    /// the bounces that reach it count it unweighted, as light sampling never could. On the
    /// sphere this holds up to the antipode of the light, where geodesics from the point
    /// arrive from every side.
    #[test]
    fn every_point_of_a_sphere_light_met_first_can_be_sampled(
        g in 0usize..3,
        distance in 0.2f64..1.0,
        bearing in 0.0f64..std::f64::consts::TAU,
        h in 0.0f64..1.2,
        u in 0.0f64..1.0,
        v in (0.0f64..1.0, 0.0f64..1.0),
    ) {
        let (space, lights, _) = lights(["*235", "*2222", "*2223"][g]);
        let light = &lights[0];
        let Emitter::Area { instance, .. } = &light.emitter else { panic!("a sphere light") };
        // Up to 3 from the light (just short of the sphere's antipode, π).
        let reach = if space.kappa() > 0.0 { std::f64::consts::PI - 0.01 } else { 3.0 };
        let frame = TangentFrame::at(space, light.position);
        let direction = frame.e1 * bearing.cos() + frame.e2 * bearing.sin();
        let x = space.exp(light.position, direction * (distance * reach));
        prop_assume!((distance * reach).hypot(h - 0.6) > 0.15);
        let point = light.sample_point(space, u, v, None).unwrap();
        let (triangle, w) = point.triangle.unwrap();
        let from_frame = TangentFrame::at(space, x);
        let Some(link) = connect(space, &from_frame, (x, h), (point.x, point.h), 0) else {
            return Ok(());
        };
        let hit = instance.intersect(space, &link.ray, 0.0, f64::INFINITY).unwrap();
        if hit.s > link.length * (1.0 - 1e-7) - 1e-9 && hit.triangle == triangle {
            prop_assert!(
                light.pdf_area(space, triangle, w, Some((x, h))) > 0.0,
                "triangle {triangle} met first from {:.3} away is never sampled",
                distance * reach
            );
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(300))]
    #[test]
    fn aiming_at_a_point_agrees_with_the_connection_to_it(
        geometry in 0usize..3,
        a in (-0.8f64..0.8, -0.8f64..0.8, 0.0f64..1.0),
        b in (-0.8f64..0.8, -0.8f64..0.8, 0.0f64..1.0),
        turns in 0u32..4,
    ) {
        // The light sample's weights aim at a light's centre without building the ray: the
        // same direction and J as the connection's, in every geometry and, on the sphere,
        // every way round.
        let space = orbifold::space::Space::new(
            [orbifold::Geometry::Spherical, orbifold::Geometry::Euclidean, orbifold::Geometry::Hyperbolic][geometry],
        );
        let origin = space.to_ambient(Complex64::new(0.0, 0.0));
        let x = space.exp(origin, glam::DVec3::new(a.0, a.1, 0.0));
        let y = space.exp(origin, glam::DVec3::new(b.0, b.1, 0.0));
        let frame = TangentFrame::at(space, x);
        let aimed = aim_at(space, &frame, (x, a.2), (y, b.2), turns);
        let link = connect(space, &frame, (x, a.2), (y, b.2), turns);
        prop_assert_eq!(aimed.is_some(), link.is_some());
        if let (Some((direction, j)), Some(link)) = (aimed, link) {
            let expected = travel_direction(space, &frame, &link.ray, 0.0);
            prop_assert!((direction - expected).length() < 1e-9, "{direction} {expected}");
            prop_assert!((j - link.spread).abs() <= 1e-9 * (1.0 + j), "{j} {}", link.spread);
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(300))]
    #[test]
    fn a_connection_arrives_at_its_end_every_way_round(
        geometry in 0usize..3,
        a in (-1.2f64..1.2, -1.2f64..1.2, 0.0f64..1.0),
        b in (-1.2f64..1.2, -1.2f64..1.2, 0.0f64..1.0),
        near in proptest::bool::ANY,
        turns in 0u32..4,
    ) {
        // The geodesic `connect` builds reaches (y, hy) after its arc length: the direction it
        // leaves x in and its length agree, in every geometry, every way round the sphere,
        // and for end points a hair apart.
        let space = orbifold::space::Space::new(
            [orbifold::Geometry::Spherical, orbifold::Geometry::Euclidean, orbifold::Geometry::Hyperbolic][geometry],
        );
        let origin = space.to_ambient(Complex64::new(0.0, 0.0));
        let x = space.exp(origin, glam::DVec3::new(a.0, a.1, 0.0));
        let step = if near { 1e-6 } else { 1.0 };
        let y = space.exp(origin, glam::DVec3::new(a.0 + step * b.0, a.1 + step * b.1, 0.0));
        let frame = TangentFrame::at(space, x);
        if let Some(link) = connect(space, &frame, (x, a.2), (y, b.2), turns) {
            let (end, h) = link.ray.point_at(space, link.length);
            let scale = 1e-9 * (1.0 + link.length);
            prop_assert!(space.ambient_distance(end, y) < scale, "{end} {y} ({turns} turns)");
            prop_assert!((h - b.2).abs() < scale, "{h} {}", b.2);
        } else {
            // Only the sphere's geodesics come round; a point is a focus of every way round it.
            let same = space.ambient_distance(x, y) < 1e-12;
            prop_assert!(turns > 0 && (geometry != 0 || same) || same && a.2 == b.2);
        }
    }
}
