//! In curved rooms every echo is a geodesic of the product space through the surfaces it names:
//! the tracer, launched from the listener in the echo's first direction and reflected at every
//! surface it meets (walls in closed form, the floor and ceiling by turning its elevation),
//! meets exactly those surfaces in that order and reaches the source after the echo's length.
//! Where the geodesic goes the short way, its length is also the product-space distance to the
//! image that the named surfaces' reflections make of the source.

mod common;

use glam::DMat3;
use orbifold::cover::reflection;
use orbifold_sound::{Bounce, Hearing};
use orbifold_trace::geodesic::Ray;
use orbifold_trace::room::{AnalyticRoom, RoomSurface};

/// What a geodesic meets in the room over arc length `length`, reflecting at every surface and
/// passing every portal (moved by its pairing onto the partner wall).
struct Traced {
    /// The surfaces it reflects off, in order (no portals).
    met: Vec<RoomSurface>,
    /// Where it ends (ambient, height).
    end: (glam::DVec3, f64),
    /// The group element g whose tile g(P) of the universal cover the unfolded path ends in:
    /// the product of the walls' `neighbour`s in the order crossed.
    tile: DMat3,
}

fn trace(room: &AnalyticRoom, mut ray: Ray, length: f64) -> Traced {
    let space = room.space;
    let mut left = length;
    let mut met = Vec::new();
    let mut tile = DMat3::IDENTITY;
    loop {
        let hit = room.exit(&ray).filter(|h| h.s < left);
        let Some(hit) = hit else {
            let end = ray.point_at(space, left);
            return Traced { met, end, tile };
        };
        left -= hit.s;
        ray = ray.continued(space, hit.s, hit.point, hit.tangent);
        match hit.surface {
            RoomSurface::Wall(w) => match room.walls[w].portal {
                Some(portal) => {
                    tile *= portal.across;
                    ray = ray.transformed(&portal.back, 0.0).renormalized(space);
                }
                None => {
                    met.push(hit.surface);
                    tile *= reflection(space, room.walls[w].form);
                    ray = ray.reflected(space, room.walls[w].form);
                }
            },
            RoomSurface::Floor | RoomSurface::Ceiling => {
                met.push(hit.surface);
                ray.sin_elevation = -ray.sin_elevation;
            }
        }
        assert!(met.len() < 10_000);
    }
}

fn check(signature: &str, seconds: f64, max_checked: usize) {
    check_scene(&common::scene(signature, seconds), max_checked);
}

/// [`check`] for any scene: every echo (up to `max_checked`, spread over the response) is traced.
fn check_scene(scene: &orbifold_scene::Scene, max_checked: usize) {
    let signature = scene.orbifold.signature.as_str();
    let hearing = Hearing::from_scene(scene, None).unwrap();
    let response = hearing.mono(&|_, _| {});
    let room = &hearing.room;
    let space = room.space;
    let r = hearing.settings.metres_per_unit;
    let (source, listener) = (hearing.source, hearing.listener);
    assert!(
        response.arrivals.len() > 50,
        "{signature}: {}",
        response.arrivals.len()
    );
    let mut short_way = 0;
    let step = (response.arrivals.len() / max_checked).max(1);
    for a in response.arrivals.iter().step_by(step) {
        let bounces: Vec<Bounce> = response.bounces(room, a);
        let path = &response.paths[a.path as usize];
        let length = a.length / r;
        // The first direction: the path's horizontal direction, climbing to the image.
        let rise = (length * length - path.sigma * path.sigma).max(0.0).sqrt();
        let vertical: i32 = bounces
            .iter()
            .map(|b| match b.surface {
                RoomSurface::Ceiling => 1,
                RoomSurface::Floor => -1,
                RoomSurface::Wall(_) => 0,
            })
            .find(|&v| v != 0)
            .unwrap_or(0);
        let up = match vertical {
            0 => source.height >= listener.height,
            v => v > 0,
        };
        let ray = Ray::climbing(
            space,
            listener.at,
            path.direction,
            listener.height,
            path.sigma,
            if up { rise } else { -rise },
        );
        let traced = trace(room, ray, length);
        let (end, h) = traced.end;
        let named: Vec<RoomSurface> = bounces.iter().map(|b| b.surface).collect();
        assert_eq!(traced.met, named, "{signature}: echo at {} s", a.time);
        assert!(
            space.ambient_distance(end, source.at) < 1e-6 && (h - source.height).abs() < 1e-6,
            "{signature}: the echo at {} s ends {} from the source",
            a.time,
            space.ambient_distance(end, source.at)
        );
        // The image of the source in the tile the unfolded path ends in (through mirrors and
        // portals alike), and by the floor and ceiling, first met outermost.
        let g = traced.tile;
        let mut z = source.height;
        for b in bounces.iter().rev() {
            match b.surface {
                RoomSurface::Wall(_) => {}
                RoomSurface::Floor => z = -z,
                RoomSurface::Ceiling => z = 2.0 * room.height - z,
            }
        }
        let d = space.ambient_distance(listener.at, g * source.at);
        if (d - path.sigma).abs() < 1e-9 {
            short_way += 1;
            let expected = (d * d + (z - listener.height).powi(2)).sqrt() * r;
            assert!(
                (a.length - expected).abs() < 1e-9 * expected,
                "{signature}: {} m, expected {expected} m",
                a.length
            );
            let time = expected / hearing.settings.speed;
            assert!((a.time - time).abs() < 1e-12, "{signature}");
            // Its amplitude: 1/(4π√J), J = ℓ²·S_κ(σ)/σ in square metres, times every
            // surface's reflection coefficient (flat absorption: any band).
            let reflection = &hearing.settings.reflection;
            let surfaces: f64 = bounces
                .iter()
                .map(|b| match (b.surface, b.mirror) {
                    (RoomSurface::Floor, _) => reflection.floor[0],
                    (RoomSurface::Ceiling, _) => reflection.ceiling[0],
                    (RoomSurface::Wall(_), true) => reflection.mirror[0],
                    (RoomSurface::Wall(_), false) => reflection.wall[0],
                })
                .product();
            let focus = 0.5 * hearing.settings.listener_size / r;
            let away_from_focus = space.kappa() <= 0.0 || (std::f64::consts::PI - d) > focus;
            if away_from_focus && d > 1e-6 {
                let j = expected * expected * space.sin(d).abs() / d;
                let amplitude = surfaces / (4.0 * std::f64::consts::PI * j.sqrt());
                assert!(
                    (a.amplitude - amplitude).abs() < 1e-9 * amplitude,
                    "{signature}: amplitude {} expected {amplitude}",
                    a.amplitude
                );
            }
        }
    }
    assert!(short_way > 0, "{signature}");
}

#[test]
fn echoes_in_a_spherical_room_are_traced_geodesics() {
    check("*235", 0.4, 400);
}

#[test]
fn echoes_in_hyperbolic_rooms_are_traced_geodesics() {
    check("*444", 0.15, 400);
    check("*2333", 0.15, 400);
}

#[test]
fn echoes_through_portals_are_traced_geodesics() {
    // Cone points (rotations), a glide next to mirrors and a cross-cap, on the sphere, in the
    // plane and in H²: each echo passes the portals it meets, moved by their pairings.
    check("532", 0.3, 300);
    check("3*2", 0.3, 300);
    check("632", 0.2, 300);
    check("22×", 0.2, 300);
    check("o", 0.2, 300);
    check("2223", 0.12, 300);
    check("4*3", 0.12, 300);
}

proptest::proptest! {
    #![proptest_config(proptest::prelude::ProptestConfig::with_cases(8))]
    #[test]
    fn echoes_are_traced_geodesics_wherever_source_and_listener_are(
        g in 0usize..3,
        (a, b, c) in (0.0f64..0.9, 0.0f64..0.9, 0.0f64..1.0),
        (hs, hl) in (0.05f64..0.95, 0.05f64..0.95),
    ) {
        let signature = ["*235", "*444", "*2333"][g];
        let mut scene = common::scene(signature, 0.08);
        let layout = scene.layout().unwrap();
        let v: Vec<_> = layout.vertices.iter().map(|v| v.position).collect();
        let centre = layout.centre;
        // Points towards a corner, and between two others, pulled towards the centre until they
        // are inside: a polygon's walls bow inwards in the Poincaré disk, so the model's chord
        // between two corners runs outside the room.
        let space = layout.space();
        let inside = |z: num_complex::Complex64| {
            let x = space.to_ambient(z);
            layout.edges.iter().all(|e| e.wall.dot(x) > 1e-3)
        };
        let pulled_in = |target: num_complex::Complex64| {
            let mut t = 1.0;
            while !inside(centre + (target - centre) * t) {
                t *= 0.8;
            }
            centre + (target - centre) * t
        };
        let p = pulled_in(centre + (v[0] - centre) * a);
        let q = pulled_in(centre + ((v[1] - centre) * c + (v[2] - centre) * (1.0 - c)) * b);
        scene.sound.source = Some(orbifold_scene::sound::Place { at: [p.re, p.im], height: hs });
        scene.sound.listener = Some(orbifold_scene::sound::Place { at: [q.re, q.im], height: hl });
        check_scene(&scene, 60);
    }
}

#[test]
fn the_sphere_brings_echoes_back_round() {
    // Echoes that went the long way round (σ > π) are heard, and among them some that went
    // round more than once.
    let scene = common::scene("*235", 0.6);
    let hearing = Hearing::from_scene(&scene, None).unwrap();
    let response = hearing.mono(&|_, _| {});
    let sigmas: Vec<f64> = response.paths.iter().map(|p| p.sigma).collect();
    assert!(sigmas.iter().any(|&s| s > std::f64::consts::PI));
    assert!(sigmas.iter().any(|&s| s > 2.0 * std::f64::consts::PI));
    assert!(response.arrivals.iter().all(|a| a.amplitude.is_finite()));
}
