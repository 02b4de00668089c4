//! Walking through portals: the view just after a portal is the view just before it, moved by
//! the pairing, so the picture goes on without a jump; through a glide only if the camera comes
//! out mirrored. Checked with the tracer's surface positions (room coordinates, so the same
//! surface point whichever side of the portal the eye is on).

use orbifold::{Layout, LayoutOptions};
use orbifold_scene::{Camera, Scene};
use orbifold_studio::view3d::walk_through_portals;
use orbifold_trace::aov;
use orbifold_trace::camera::Camera as TraceCamera;
use orbifold_trace::tracer::Tracer;

/// The share of pixels whose first surface point (model x, y and height) is the same, to 1e-3.
fn same_view(tracer: &Tracer, a: &Camera, b: &Camera) -> f64 {
    let (w, h) = (48, 36);
    let render = |c: &Camera| aov::render(tracer, &TraceCamera::new(tracer.space(), c), w, h, 16);
    let (x, y) = (render(a), render(b));
    let same = x
        .position
        .iter()
        .zip(&y.position)
        .filter(|(p, q)| (0..3).all(|k| (p[k] - q[k]).abs() < 1e-3))
        .count();
    same as f64 / x.position.len() as f64
}

/// Walks from the centre along `yaw` in steps of `step` until the camera first passes a portal;
/// returns the camera just before and just after, and the step taken between them.
fn through_a_portal(layout: &Layout, yaw: f64, step: f64) -> (Camera, Camera) {
    let c = layout.centre;
    let mut camera = Camera {
        at: [c.re, c.im],
        yaw,
        pitch: -10.0,
        height: 0.5,
        ..Camera::default()
    };
    for _ in 0..20_000 {
        let before = camera.clone();
        walk_through_portals(layout, &mut camera, step);
        let jumped = (camera.at[0] - before.at[0]).hypot(camera.at[1] - before.at[1]) > 5.0 * step;
        if jumped || camera.mirrored != before.mirrored {
            return (before, camera);
        }
    }
    panic!("never reached a portal");
}

#[test]
fn the_view_goes_on_through_a_portal_and_a_glide_mirrors_it() {
    for (symbol, yaw) in [
        ("632", 20.0),
        ("22×", 30.0),
        ("22×", 225.0),
        ("××", 80.0),
        ("××", 200.0),
    ] {
        let mut scene = Scene::default();
        scene.orbifold.signature = symbol.into();
        let layout =
            Layout::of_symbol(&symbol.parse().unwrap(), &LayoutOptions::default()).unwrap();
        let tracer = Tracer::mirror_room(layout.clone(), 1.0).unwrap();
        // A step of 1e-3: the eye moves a hair, so the two views differ only where that shows.
        let (before, mut after) = through_a_portal(&layout, yaw, 1e-3);
        let agreement = same_view(&tracer, &before, &after);
        eprintln!(
            "{symbol} yaw {yaw}: mirrored {} agreement {agreement:.4}",
            after.mirrored
        );
        assert!(
            agreement > 0.9,
            "{symbol} yaw {yaw}: only {agreement} of the view goes on"
        );
        if after.mirrored {
            // Without the mirror the picture would jump: swapped left for right.
            after.mirrored = false;
            let unmirrored = same_view(&tracer, &before, &after);
            assert!(
                unmirrored < agreement - 0.2,
                "{symbol}: {unmirrored} vs {agreement}"
            );
        }
    }
}
