//! Scene files that leave placements out: the camera, the default object and light are placed
//! for the room the file's signature makes, in every geometry; written values are kept, and one
//! outside the room is still an error at its line.

use orbifold::Geometry;
use orbifold::Signature;
use orbifold_scene::Scene;
use orbifold_scene::placement::is_inside;
use proptest::prelude::*;

fn signature_only(signature: &str) -> String {
    format!("[orbifold]\nsignature = \"{signature}\"\n")
}

/// Loads a signature-only file and checks that everything placed is inside the room and under
/// its ceiling, and that the camera looks at the object.
fn check_placed(signature: &str) {
    let scene = Scene::from_toml(&signature_only(signature), None)
        .unwrap_or_else(|e| panic!("{signature}: {}", e[0]));
    let layout = scene.layout().unwrap();
    assert!(
        is_inside(&layout, scene.camera.at),
        "{signature}: camera at {:?}",
        scene.camera.at
    );
    for o in &scene.objects {
        assert!(
            is_inside(&layout, o.at),
            "{signature}: object at {:?}",
            o.at
        );
    }
    for l in &scene.lights {
        assert!(is_inside(&layout, l.at), "{signature}: light at {:?}", l.at);
        assert!(l.height <= scene.room.height);
    }
    assert!(scene.camera.height <= scene.room.height);
    assert!(scene.check(None).is_ok(), "{signature}");
}

#[test]
fn a_signature_only_file_is_a_room_in_every_geometry() {
    for (signature, geometry) in [
        ("*444", Geometry::Hyperbolic),
        ("*442", Geometry::Euclidean),
        ("*333", Geometry::Euclidean),
        ("*236", Geometry::Euclidean),
        ("*2222", Geometry::Euclidean),
        ("*22", Geometry::Spherical),
        ("*235", Geometry::Spherical),
        ("*", Geometry::Spherical),
        ("*2333", Geometry::Hyperbolic),
        ("*∞∞∞", Geometry::Hyperbolic),
        ("*2∞3", Geometry::Hyperbolic),
        ("*∞∞∞∞", Geometry::Hyperbolic),
    ] {
        let parsed: Signature = signature.parse().unwrap();
        assert_eq!(parsed.geometry(), geometry, "{signature}");
        check_placed(signature);
    }
}

#[test]
fn the_rooms_that_were_refused_now_look_at_their_figure() {
    for signature in ["*444", "*235", "*2∞3"] {
        placed_for_the_room(signature);
    }
}

/// The default camera (-0.2, 0) is outside these rooms: everything left out is placed for the
/// room, the camera looking at its centre, as `orbifold scene new SIG` places them.
fn placed_for_the_room(signature: &str) {
    let scene = Scene::from_toml(&signature_only(signature), None).unwrap();
    assert!(
        Scene::default().camera.at.ne(&scene.camera.at),
        "{signature}: the default camera fits"
    );
    let layout = scene.layout().unwrap();
    let centre = [layout.centre.re, layout.centre.im];
    assert_eq!(scene.objects[0].at, centre);
    assert_eq!(scene.lights[0].at, centre);
    assert_eq!(scene.camera.at[1], centre[1]);
    assert!(scene.camera.at[0] < centre[0]);
    assert_eq!(scene.camera.yaw, 0.0, "yaw 0 looks along +x, at the centre");
    assert_eq!(scene, Scene::for_signature(signature).unwrap());
}

#[test]
fn defaults_that_fit_the_room_are_kept() {
    // The default room is the one the defaults were made for; a hyperbolic room around the
    // origin also holds them, so files that loaded before mean what they meant.
    assert_eq!(Scene::from_toml("", None).unwrap(), Scene::default());
    let scene = Scene::from_toml(&signature_only("*2333"), None).unwrap();
    assert_eq!(scene.camera, Scene::default().camera);
    assert_eq!(scene.lights, Scene::default().lights);
}

#[test]
fn written_positions_stay_and_one_outside_the_room_is_an_error_at_its_line() {
    // Written object position inside: kept, while the unwritten camera is placed.
    let layout = Scene::for_signature("*444").unwrap().layout().unwrap();
    let c = layout.centre;
    let text = format!(
        "[orbifold]\nsignature = \"*444\"\n\n[[objects]]\nshape = \"sphere\"\nat = [{}, {}]\n",
        c.re + 0.05,
        c.im
    );
    let scene = Scene::from_toml(&text, None).unwrap();
    assert_eq!(scene.objects[0].at, [c.re + 0.05, c.im]);
    assert!(is_inside(&layout, scene.camera.at));
    // A written camera outside the room: still refused, at its line.
    let text = "[orbifold]\nsignature = \"*444\"\n\n[camera]\nat = [-0.2, 0.0]\n";
    let errors = Scene::from_toml(text, None).unwrap_err();
    assert_eq!(errors.len(), 1, "{errors:?}");
    assert_eq!(errors[0].key.as_deref(), Some("camera.at"));
    assert_eq!(errors[0].position.map(|p| p.0), Some(5));
    assert!(errors[0].message.contains("not inside the room"));
    // A light written outside, in a later [[lights]] entry.
    let text = "[orbifold]\nsignature = \"*444\"\n\n[[lights]]\nheight = 0.5\n\n[[lights]]\nat = [-5.0, -5.0]\n";
    let errors = Scene::from_toml(text, None).unwrap_err();
    assert_eq!(errors.len(), 1, "{errors:?}");
    assert_eq!(errors[0].key.as_deref(), Some("lights[1].at"));
    assert_eq!(errors[0].position.map(|p| p.0), Some(8));
}

#[test]
fn heights_left_out_follow_a_low_ceiling() {
    let text = "[orbifold]\nsignature = \"*444\"\n\n[room]\nheight = 0.4\n";
    let scene = Scene::from_toml(text, None).unwrap();
    assert!((scene.camera.height - 0.2).abs() < 1e-12);
    assert!((scene.lights[0].height - 0.36).abs() < 1e-12);
    // A written height above the ceiling is still an error.
    let text = "[room]\nheight = 0.4\n\n[camera]\nheight = 0.5\n";
    let errors = Scene::from_toml(text, None).unwrap_err();
    assert_eq!(errors[0].key.as_deref(), Some("camera.height"));
}

/// Corner orders for random signatures: small ones, large ones and ideal corners.
fn order() -> impl Strategy<Value = String> {
    prop_oneof![
        (2u32..=9).prop_map(|k| k.to_string()),
        (10u32..=40).prop_map(|k| format!("({k})")),
        Just("∞".to_string()),
    ]
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(200))]

    /// Any buildable kaleidoscopic signature, written alone in a file, is a valid room with the
    /// camera, the object and the light inside it.
    #[test]
    fn any_signature_alone_is_a_valid_room(orders in prop::collection::vec(order(), 0..=7)) {
        let signature = format!("*{}", orders.concat());
        let parsed: Signature = signature.parse().unwrap();
        // Signatures without a room (bad orbifolds, a Euclidean strip with an ideal corner) are
        // refused for their signature, not for a placement.
        prop_assume!(parsed.is_buildable() && Scene::for_signature(&signature).is_ok());
        check_placed(&signature);
    }
}

/// Conway symbols of every kind: cones, a mirror boundary with corners, cross-caps or handles.
fn symbol() -> impl Strategy<Value = String> {
    (
        prop::collection::vec(order(), 0..=3),
        prop::option::of(prop::collection::vec(order(), 0..=4)),
        prop_oneof![Just(""), Just("x"), Just("xx"), Just("o")],
    )
        .prop_map(|(cones, corners, tail)| {
            let mirror = corners.map_or_else(String::new, |c| format!("*{}", c.concat()));
            format!("{}{mirror}{tail}", cones.concat())
        })
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(200))]

    /// Rooms with portals too: any symbol that has a room, alone in a file, is a valid room
    /// with everything inside it.
    #[test]
    fn any_symbol_alone_is_a_valid_room(symbol in symbol()) {
        prop_assume!(Scene::for_signature(&symbol).is_ok());
        check_placed(&symbol);
    }
}
