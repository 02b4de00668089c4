//! The response as a signal: no NaN, the same on every run, stereo ears that hear the room
//! from either side, frequency-dependent absorption through the octave filters, and the files.

mod common;

use orbifold_scene::sound::Absorption;
use orbifold_sound::{Hearing, clap, convolve, echogram, wav};
use proptest::prelude::*;

#[test]
fn responses_are_finite_and_the_same_on_every_run() {
    for signature in ["*2222", "*444", "*235", "*2333"] {
        let scene = common::scene(signature, 0.1);
        let hearing = Hearing::from_scene(&scene, None).unwrap();
        let a = hearing.mono(&|_, _| {});
        let b = hearing.mono(&|_, _| {});
        assert_eq!(a.arrivals, b.arrivals, "{signature}");
        assert!(a.arrivals.iter().all(|x| x.time.is_finite()
            && x.amplitude.is_finite()
            && x.amplitude > 0.0
            && x.bands.iter().all(|b| b.is_finite())));
        let samples = hearing.samples(&a);
        assert!(samples.iter().all(|x| x.is_finite()), "{signature}");
        assert!(samples.iter().any(|&x| x != 0.0), "{signature}");
    }
}

#[test]
fn the_ears_hear_a_source_on_the_right_first_on_the_right() {
    let mut scene = common::scene("*2222", 0.05);
    // The camera looks along +x: its right is −y. The source straight to its right.
    scene.camera.yaw = 0.0;
    scene.camera.pitch = 0.0;
    let [cx, cy] = scene.camera.at;
    scene.sound.source = Some(orbifold_scene::sound::Place {
        at: [cx, cy - 0.2],
        height: scene.camera.height,
    });
    let hearing = Hearing::from_scene(&scene, None).unwrap();
    let [left, right] = hearing.stereo(&|_, _| {});
    let first = |r: &orbifold_sound::Response| r.arrivals[0].time;
    let gap = first(&left) - first(&right);
    // The path difference is the ear distance.
    let expected = hearing.settings.ear_distance / hearing.settings.speed;
    assert!((gap - expected).abs() < 1e-9, "{gap} {expected}");
}

#[test]
fn absorption_by_band_and_air_filter_the_response() {
    let mut scene = common::scene("*2222", 0.2);
    scene.sound.wall_absorption = Absorption::Bands([0.1, 0.15, 0.2, 0.3, 0.4, 0.5, 0.6]);
    scene.sound.air = true;
    let hearing = Hearing::from_scene(&scene, None).unwrap();
    let response = hearing.mono(&|_, _| {});
    // High bands lose more on every reflection and in the air.
    for a in response.arrivals.iter().filter(|a| a.reflections > 0) {
        assert!(a.bands[6] < a.bands[0]);
    }
    let samples = hearing.samples(&response);
    assert!(samples.iter().all(|x| x.is_finite()));
    // The filtered response carries energy near the broadband one's (the octave filters pass
    // every frequency to within a few decibels).
    let energy = |s: &[f32]| s.iter().map(|x| f64::from(*x).powi(2)).sum::<f64>();
    let broadband: Vec<f32> = {
        let flat: Vec<_> = response
            .arrivals
            .iter()
            .map(|a| orbifold_sound::Arrival {
                bands: [a.amplitude as f32; 7],
                ..*a
            })
            .collect();
        orbifold_sound::impulse::impulse_response(&flat, 48_000, 0.2)
    };
    let ratio = energy(&samples) / energy(&broadband);
    assert!((0.3..3.0).contains(&ratio), "{ratio}");
}

#[test]
fn a_dry_clap_through_the_room_is_written_and_read_back() {
    let scene = common::scene("*444", 0.1);
    let hearing = Hearing::from_scene(&scene, None).unwrap();
    let ir = hearing.samples(&hearing.mono(&|_, _| {}));
    let dry = clap::clap(48_000);
    let wet = convolve::convolve(&dry, &ir).unwrap();
    assert_eq!(wet.len(), dry.len() + ir.len() - 1);
    let (bytes, _) = wav::encode(&[wet.clone(), wet], 48_000).unwrap();
    let (back, rate) = wav::decode_mono(&bytes).unwrap();
    assert_eq!(rate, 48_000);
    let peak = back.iter().fold(0.0f32, |m, x| m.max(x.abs()));
    assert!((peak - wav::PEAK).abs() < 1e-3);
    assert!(wav::decode_mono(b"not a wav file").is_err());
}

#[test]
fn echograms_are_drawn() {
    let scene = common::scene("*235", 0.2);
    let hearing = Hearing::from_scene(&scene, None).unwrap();
    let response = hearing.mono(&|_, _| {});
    let svg = echogram::echogram_svg(&response.arrivals, "*235", 0.2, -60.0, (640, 300)).unwrap();
    assert!(svg.contains("time (s)"));
    // At most one line per column and class: small whatever the number of echoes.
    assert!(svg.len() < 640 * 8 * 200, "{}", svg.len());
}

#[test]
fn bad_scenes_are_refused_with_the_key() {
    let mut scene = common::scene("*2222", 0.1);
    scene.sound.speed = -1.0;
    let error = Hearing::from_scene(&scene, None).unwrap_err().to_string();
    assert!(error.contains("sound.speed"), "{error}");
    let text = "[sound]\nsample_rate = 100\nfloor_absorption = 1.5\n";
    let errors = orbifold_scene::Scene::from_toml(text, None).unwrap_err();
    assert_eq!(errors[0].position, Some((2, 15)));
    assert_eq!(errors[1].key.as_deref(), Some("sound.floor_absorption"));
}

#[test]
fn rooms_with_portals_are_heard_and_mirrors_hung_on_portals_refused_by_wall() {
    // A glide next to a mirror: the echoes pass the portals and reflect off the mirrors.
    let scene = common::scene("*×", 0.1);
    let hearing = Hearing::from_scene(&scene, None).unwrap();
    let response = hearing.mono(&|_, _| {});
    assert!(response.paths.iter().any(|p| p.portals > 0));
    assert!(
        response
            .paths
            .iter()
            .any(|p| p.portals > 0 && !p.crossings.is_empty())
    );
    assert_eq!(response.lost, 0);
    let mut scene = common::scene("632", 0.1);
    scene.walls.push(orbifold_scene::Wall {
        index: 1,
        material: None,
        mirrors: vec![orbifold_scene::Mirror {
            from: 0.2,
            to: 0.6,
            bottom: 0.0,
            top: None,
            reflectance: [0.9; 3],
        }],
    });
    let error = Hearing::from_scene(&scene, None).unwrap_err().to_string();
    assert!(
        error.contains("wall 1") && error.contains("portal"),
        "{error}"
    );
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(16))]
    #[test]
    fn the_first_echo_is_the_direct_sound_in_a_hyperbolic_room(
        a in 0.0f64..1.0, b in 0.0f64..1.0, hs in 0.05f64..0.95, hl in 0.05f64..0.95,
    ) {
        let mut scene = common::scene("*444", 0.03);
        let layout = scene.layout().unwrap();
        let space = layout.space();
        let v: Vec<_> = layout.vertices.iter().map(|v| v.position).collect();
        let c = layout.centre;
        // Points inside, as convex combinations towards two corners (the model's straight
        // lines stay inside this convex polygon near its centre).
        let p = c + (v[0] - c) * (0.6 * a);
        let q = c + (v[2] - c) * (0.6 * b);
        scene.sound.source = Some(orbifold_scene::sound::Place { at: [p.re, p.im], height: hs });
        scene.sound.listener = Some(orbifold_scene::sound::Place { at: [q.re, q.im], height: hl });
        let hearing = Hearing::from_scene(&scene, None).unwrap();
        let response = hearing.mono(&|_, _| {});
        let d = space.distance(p, q);
        let direct = (d * d + (hs - hl).powi(2)).sqrt() * hearing.settings.metres_per_unit;
        let first = response.arrivals[0];
        prop_assert_eq!(first.reflections, 0);
        prop_assert!((first.length - direct).abs() < 1e-9 * direct.max(1e-3));
        prop_assert!(response.arrivals.iter().all(|x| x.amplitude.is_finite() && x.time >= first.time));
    }
}
