//! The CPU projection (the shader's twin) against the tracer: the pixel a point projects to is
//! the one whose camera ray, followed along the true geodesic, reaches the point.

use glam::DVec3;
use num_complex::Complex64;
use orbifold::space::Space;
use orbifold::{Geometry, Layout, LayoutOptions};
use orbifold_preview::copies::{Words, copies};
use orbifold_preview::projection::{Projection, View};
use orbifold_scene::{Attenuation, Camera as CameraSettings};
use orbifold_trace::camera::Camera;
use proptest::prelude::*;

const WIDTH: u32 = 640;
const HEIGHT: u32 = 480;

fn geometry(index: usize) -> Geometry {
    [
        Geometry::Spherical,
        Geometry::Euclidean,
        Geometry::Hyperbolic,
    ][index]
}

/// A point of the plane within `reach` of the model point `z`, in the direction `angle`.
fn point_near(space: Space, z: Complex64, angle: f64, reach: f64) -> DVec3 {
    let p = space.to_ambient(z);
    let v = space.model_tangent(z, Complex64::from_polar(1.0, angle));
    space.exp(p, v * reach)
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(400))]

    #[test]
    fn projected_pixels_are_where_the_camera_rays_reach_the_points(
        g in 0usize..3,
        eye in (-0.3f64..0.3, -0.3f64..0.3, 0.05f64..1.0),
        look in (-180.0f64..180.0, -60.0f64..60.0, 30.0f64..100.0),
        target in (0.0f64..std::f64::consts::TAU, 0.01f64..3.0, -0.5f64..1.5),
    ) {
        let space = Space::new(geometry(g));
        let settings = CameraSettings {
            at: [eye.0, eye.1],
            height: eye.2,
            yaw: look.0,
            pitch: look.1,
            fov: look.2,
            ..CameraSettings::default()
        };
        let view = View::new(space, &settings, Projection::Curved);
        let camera = Camera::new(space, &settings);
        let p = point_near(space, Complex64::new(eye.0, eye.1), target.0, target.1);
        for image in 0..view.images() {
            let Some(at) = view.project(p, target.2, image, WIDTH, HEIGHT) else { continue };
            if !(0.0..f64::from(WIDTH)).contains(&at.x) || !(0.0..f64::from(HEIGHT)).contains(&at.y) {
                continue;
            }
            let (i, j) = (at.x.floor(), at.y.floor());
            let ray = camera.ray(i as u32, j as u32, WIDTH, HEIGHT, (at.x - i, at.y - j));
            let (reached, height) = ray.point_at(space, at.distance);
            prop_assert!(
                space.ambient_distance(reached, p) < 1e-7 && (height - target.2).abs() < 1e-7,
                "image {image}: the ray through ({:.3}, {:.3}) reaches {reached:?} at {height}, \
                 not {p:?} at {}", at.x, at.y, target.2
            );
        }
    }

    #[test]
    fn words_multiply_back_to_the_tiles(sig in prop::sample::select(vec![
        "*235", "*2223", "*333", "*244", "*2222", "*22222", "*2352", "*237", "*∞∞∞", "*23∞",
    ]), depth in 1u32..6) {
        let layout = Layout::new(&sig.parse().unwrap(), &LayoutOptions::default()).unwrap();
        let space = layout.space();
        let reflections: Vec<_> = layout
            .edges
            .iter()
            .map(|e| orbifold::cover::reflection(space, e.wall))
            .collect();
        let cover = orbifold::cover::Cover::enumerate_layout(
            layout.clone(),
            orbifold::cover::Bound::Depth(depth as usize),
            true,
        ).unwrap();
        let words = Words::new(&layout);
        for tile in &cover.tiles {
            let word = words.word(tile);
            prop_assert_eq!(word.len(), tile.depth as usize);
            let product = word
                .iter()
                .rev()
                .fold(glam::DMat3::IDENTITY, |m, &w| m * reflections[w as usize]);
            let error = (product - tile.matrix).to_cols_array().iter().fold(0.0f64, |e, v| e.max(v.abs()));
            let scale = tile.matrix.to_cols_array().iter().fold(1.0f64, |e, v| e.max(v.abs()));
            prop_assert!(error < 1e-9 * scale, "{sig} depth {}: error {error}", tile.depth);
        }
    }
}

#[test]
fn the_long_way_round_is_the_other_half_of_the_great_circle() {
    let space = Space::new(Geometry::Spherical);
    let settings = CameraSettings {
        at: [0.0, 0.0],
        height: 0.5,
        yaw: 0.0,
        pitch: 0.0,
        ..CameraSettings::default()
    };
    let view = View::new(space, &settings, Projection::Curved);
    // A point straight behind the eye at eye height, a quarter turn away, is seen straight
    // ahead the long way round, three quarters of a turn away.
    let behind = space.to_ambient(Complex64::new(-1.0, 0.0));
    assert!(view.project(behind, 0.5, 0, 64, 48).is_none());
    let ahead = view.project(behind, 0.5, 1, 64, 48).unwrap();
    assert!((ahead.x - 32.0).abs() < 1e-9 && (ahead.y - 24.0).abs() < 1e-9);
    assert!((ahead.distance - 1.5 * std::f64::consts::PI).abs() < 1e-12);
    assert_eq!(view.images(), 2);
}

#[test]
fn straight_and_curved_agree_in_euclidean_rooms() {
    let space = Space::new(Geometry::Euclidean);
    let settings = CameraSettings {
        at: [0.1, -0.2],
        yaw: 30.0,
        ..CameraSettings::default()
    };
    let curved = View::new(space, &settings, Projection::Curved);
    let straight = View::new(space, &settings, Projection::Straight);
    for k in 0..50 {
        let angle = f64::from(k) * 0.7;
        let p = point_near(
            space,
            Complex64::new(0.1, -0.2),
            angle,
            0.05 * f64::from(k + 1),
        );
        let (a, b) = (curved.log(p, 0.3, 0), straight.log(p, 0.3, 0));
        assert!((a - b).length() < 1e-12, "{a} vs {b}");
    }
}

#[test]
fn straight_projection_bends_hyperbolic_distances() {
    // In the model picture a far point looks nearer than it is: the flat picture shrinks
    // distances by the conformal factor.
    let space = Space::new(Geometry::Hyperbolic);
    let settings = CameraSettings {
        at: [0.0, 0.0],
        ..CameraSettings::default()
    };
    let curved = View::new(space, &settings, Projection::Curved);
    let straight = View::new(space, &settings, Projection::Straight);
    let p = space.to_ambient(Complex64::new(0.8, 0.0));
    let (a, b) = (curved.log(p, 0.5, 0), straight.log(p, 0.5, 0));
    assert!((a.x - 2.0 * 0.8f64.atanh()).abs() < 1e-12);
    assert!((b.x - 1.6).abs() < 1e-12);
}

#[test]
fn attenuation_settings_tint_copies_as_documented() {
    let layout = Layout::new(&"*2222".parse().unwrap(), &LayoutOptions::default()).unwrap();
    let reflectances = [
        [0.5, 0.5, 0.5],
        [0.9, 0.8, 0.7],
        [1.0, 1.0, 1.0],
        [0.25, 0.25, 0.25],
    ];
    let all = copies(&layout, 3, &reflectances, Attenuation::Reflectance).unwrap();
    let words = Words::new(&layout);
    let cover = orbifold::cover::Cover::enumerate_layout(
        layout.clone(),
        orbifold::cover::Bound::Depth(3),
        true,
    )
    .unwrap();
    assert_eq!(all.len(), cover.tiles.len());
    for (copy, tile) in all.iter().zip(&cover.tiles) {
        // In *2222 each wall's line is made of copies of that wall only, so the product is the
        // same along every gallery: count the crossings of each wall.
        let mut expected = [1.0f64; 3];
        for &w in &words.word(tile) {
            (0..3).for_each(|k| expected[k] *= reflectances[w as usize][k]);
        }
        assert_eq!(copy.matrix, tile.matrix);
        for (got, want) in copy.tint.iter().zip(expected) {
            assert!((got - want).abs() < 1e-12);
        }
    }
    let room = all.iter().find(|c| c.depth == 0).unwrap();
    assert_eq!(room.tint, [1.0; 3]);
    let brightness = |a: Attenuation| copies(&layout, 2, &reflectances, a).unwrap();
    assert!(
        brightness(Attenuation::Universal)
            .iter()
            .all(|c| c.tint == [1.0; 3])
    );
    for c in brightness(Attenuation::Orbifold) {
        assert_eq!(c.tint[0] == 1.0, c.depth == 0);
    }
    for c in brightness(Attenuation::Translations) {
        assert_eq!(c.tint[0] == 1.0, !c.reflected);
    }
}

#[test]
fn a_non_orbifold_room_gets_its_images_along_every_word() {
    // *(2.5)55: a corner of angle 2π/5, not π/k: no discrete group, so every word without a
    // letter repeated next to itself is an image: 1 + 3 + 6 + 12 + 24 up to four letters.
    let layout = Layout::new(&"*(2.5)55".parse().unwrap(), &LayoutOptions::default()).unwrap();
    let images = copies(&layout, 4, &[[0.5; 3]; 3], Attenuation::Reflectance).unwrap();
    assert_eq!(images.len(), 1 + 3 + 6 + 12 + 24);
    for image in &images {
        let expected = 0.5f64.powi(image.depth as i32);
        assert!((image.tint[0] - expected).abs() < 1e-12);
        assert_eq!(image.reflected, image.matrix.determinant() < 0.0);
    }
}
