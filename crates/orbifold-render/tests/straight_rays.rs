//! Straight rays: the flattened room's walls are the model curves of the curved walls, rays
//! leave it where those curves are crossed and mirrors reflect across their tangents; in a
//! Euclidean room straight rays and geodesics give the same picture.

use glam::DVec3;
use num_complex::Complex64;
use orbifold::{Layout, LayoutOptions};
use orbifold_render::film::Film;
use orbifold_render::integrator::Settings;
use orbifold_render::render::{RenderOptions, render_scene};
use orbifold_scene::{LightKind, Scene};
use orbifold_trace::geodesic::Ray;
use orbifold_trace::room::{AnalyticRoom, RoomSurface};
use proptest::prelude::*;

fn flat_room(signature: &str) -> (Layout, AnalyticRoom) {
    let layout = Layout::new(&signature.parse().unwrap(), &LayoutOptions::default()).unwrap();
    let room = AnalyticRoom::all_mirrors(&layout, 1.0, [0.9; 3]).unwrap();
    (layout, room.flattened())
}

/// The model curve of wall ν of the curved plane (positive inside).
fn curve(kappa: f64, nu: DVec3, z: Complex64) -> f64 {
    -kappa * nu.z * z.norm_sqr() + 2.0 * (nu.x * z.re + nu.y * z.im) + nu.z
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(if cfg!(debug_assertions) { 64 } else { 512 }))]

    #[test]
    fn flat_rays_leave_across_the_model_curves_and_reflect_inwards(
        which in 0usize..6,
        r in 0.0f64..0.8,
        angle in 0.0f64..std::f64::consts::TAU,
        bearing in 0.0f64..std::f64::consts::TAU,
        elevation in -0.6f64..0.6,
    ) {
        let signature = ["*235", "*2223", "*∞∞∞", "*22222", "*333", "*2345"][which];
        let (layout, room) = flat_room(signature);
        let curved = layout.space();
        let kappa = curved.kappa();
        // A start inside: part of the way from the centre (the model's origin, from which
        // geodesics are straight in the model) to a corner.
        let k = (angle * 7.0) as usize % layout.vertices.len();
        let z0 = layout.centre + (layout.vertices[k].position - layout.centre) * r;
        prop_assume!(layout.edges.iter().all(|e| curve(kappa, e.wall, z0) > 1e-6));
        let flat = room.space;
        let mut ray = Ray::from_model(flat, z0, 0.5, bearing, elevation);
        for _ in 0..8 {
            let Some(hit) = room.exit(&ray) else { break };
            prop_assert!(room.contains(hit.point, hit.height, 1e-7), "{signature}: exit outside the room");
            let RoomSurface::Wall(w) = hit.surface else { break };
            let z = flat.to_model(hit.point);
            let g = curve(kappa, layout.edges[w].wall, z);
            prop_assert!(g.abs() < 1e-7 * (1.0 + z.norm_sqr()), "{signature}: wall {w} missed by {g}");
            // Reflected across the tangent line: heading back in.
            let form = room.wall_form_at(w, hit.point);
            prop_assert!(form.dot(hit.point).abs() < 1e-9);
            let next = ray.advanced(flat, hit.s).reflected(flat, form);
            prop_assert!(form.dot(next.direction) >= -1e-9, "{signature}: reflected outwards");
            ray = next;
        }
    }
}

fn image(scene: &Scene, straight_rays: bool) -> Film {
    let settings = Settings {
        max_depth: 3,
        nee: false,
        straight_rays,
        // Straight rays never carry the pixel's footprint: compare like with like.
        pixel_footprint: false,
        ..Settings::default()
    };
    render_scene(scene, None, settings, &RenderOptions::new(12, 8, 16, 3))
        .unwrap()
        .film
}

#[test]
fn in_a_euclidean_room_straight_rays_are_the_geodesics() {
    // The same estimator (paths that hit the light) on the same geometry: the same picture, up
    // to rounding in where the walls are crossed. Through portals too: the model map of a
    // pairing of the Euclidean plane is the pairing itself (rotations, glides, translations).
    for signature in ["*333", "*2222", "*236", "632", "22×", "o", "4*2"] {
        let mut scene = Scene::default();
        scene.orbifold.signature = signature.into();
        let layout = scene.layout().unwrap();
        let c = [layout.centre.re, layout.centre.im];
        scene.objects[0].at = c;
        scene.lights[0].kind = LightKind::Sphere;
        scene.lights[0].at = c;
        scene.lights[0].radius = 0.15;
        scene.camera.at = [c[0] - 0.1, c[1]];
        let (a, b) = (image(&scene, false), image(&scene, true));
        let mut same = 0;
        let total = a.width() * a.height();
        for y in 0..a.height() {
            for x in 0..a.width() {
                let (p, q) = (a.pixel(x, y), b.pixel(x, y));
                if (0..3).all(|k| (p[k] - q[k]).abs() <= 1e-6 * (1.0 + p[k].abs())) {
                    same += 1;
                }
            }
        }
        assert!(
            same * 10 >= total * 9,
            "{signature}: {same} of {total} pixels agree"
        );
    }
}

#[test]
fn straight_rays_show_a_hyperbolic_room_differently() {
    let mut scene = Scene::default();
    scene.orbifold.signature = "*2223".into();
    scene.lights[0].kind = LightKind::Sphere;
    scene.lights[0].radius = 0.1;
    let (a, b) = (image(&scene, false), image(&scene, true));
    let differ = (0..a.height())
        .flat_map(|y| (0..a.width()).map(move |x| (x, y)))
        .filter(|&(x, y)| a.pixel(x, y) != b.pixel(x, y))
        .count();
    let lit = (0..b.height())
        .flat_map(|y| (0..b.width()).map(move |x| (x, y)))
        .filter(|&(x, y)| b.pixel(x, y)[1] > 0.0)
        .count();
    assert!(lit > 0 && differ > 0, "{lit} lit, {differ} differ");
    assert_eq!(b.dropped(), 0);
}

#[test]
fn straight_rays_pass_the_portals_of_curved_rooms_by_their_model_maps() {
    // A portal sends a straight ray on from the partner wall's model point: on the sphere and in
    // H², through cone points and a glide, a ray that enters a portal comes out inside the room,
    // heading in, and the pictures are lit and finite.
    for signature in ["532", "2223", "4*3"] {
        let layout =
            Layout::of_symbol(&signature.parse().unwrap(), &LayoutOptions::default()).unwrap();
        let room = AnalyticRoom::all_mirrors(&layout, 1.0, [0.9; 3])
            .unwrap()
            .flattened();
        let flat = room.space;
        let mut passed = 0;
        for k in 0..64 {
            let bearing = k as f64 * 0.1;
            let mut ray = Ray::from_model(
                flat,
                layout.centre,
                0.5,
                bearing,
                0.1 * (k % 5) as f64 - 0.2,
            );
            for _ in 0..6 {
                let Some(hit) = room.exit(&ray) else { break };
                let RoomSurface::Wall(w) = hit.surface else {
                    break;
                };
                let Some(passage) = room.passage(w, hit.point, hit.height) else {
                    break;
                };
                let next = ray
                    .continued(flat, hit.s, hit.point, hit.tangent)
                    .passed(flat, &passage);
                if let Some(to) = passage.portal_to {
                    passed += 1;
                    assert!(
                        room.contains(next.origin, next.height, 1e-7),
                        "{signature}: out of the room"
                    );
                    let form = room.wall_form_at(to, next.origin);
                    assert!(
                        form.dot(next.origin).abs() < 1e-7,
                        "{signature}: not on wall {to}"
                    );
                    assert!(
                        form.dot(next.direction) > -1e-9,
                        "{signature}: heading out of wall {to}"
                    );
                }
                ray = next;
            }
        }
        assert!(passed > 20, "{signature}: {passed} portals passed");
        let mut scene = Scene::default();
        scene.orbifold.signature = signature.into();
        scene.lights[0].kind = LightKind::Sphere;
        scene.lights[0].radius = 0.1;
        let film = image(&scene, true);
        let lit = (0..film.height())
            .flat_map(|y| (0..film.width()).map(move |x| (x, y)))
            .filter(|&(x, y)| film.pixel(x, y)[1] > 0.0)
            .count();
        assert!(lit > 0, "{signature}: nothing lit");
        assert_eq!(film.dropped(), 0, "{signature}");
    }
}
