//! The listen tab, driven through its button headlessly: a clap at the camera is heard through
//! the room and played (to a recorder in place of the speakers, so no audio device is needed),
//! and its samples are the command line's clap through the same room at the two ears.

use egui_kittest::Harness;
use egui_kittest::kittest::Queryable;
use orbifold_scene::Scene;
use orbifold_sound::{Hearing, clap, convolve};
use orbifold_studio::audio::Recorder;
use orbifold_studio::document::Document;
use orbifold_studio::listen_panel::{ListenPanel, clap_scene};
use orbifold_studio::{Studio, app::Tab};

fn quick_scene() -> Scene {
    let mut scene = Scene::default();
    scene.orbifold.signature = "*2222".into();
    scene.objects.clear();
    scene.camera.at = [0.1, 0.05];
    scene.sound.seconds = 0.1;
    scene
}

#[test]
fn the_listen_button_plays_a_clap_through_the_room() {
    let scene = quick_scene();
    let mut studio = Studio::new(Document::with_scene(scene.clone(), None, None), None);
    let recorder = Recorder::default();
    studio.listen = ListenPanel::with_output(Box::new(recorder.clone()));
    studio.tab = Tab::Listen;
    let camera = studio.view.camera.clone();
    let mut harness = Harness::builder()
        .with_size(egui::vec2(1440.0, 1000.0))
        .build_ui_state(|ui, studio: &mut Studio| studio.ui(ui), studio);
    harness.run();
    harness.get_by_label("Listen").click();
    for _ in 0..600 {
        harness.step();
        if !recorder.played.lock().unwrap().is_empty() {
            break;
        }
        std::thread::sleep(std::time::Duration::from_millis(50));
    }
    harness.run();
    let played = recorder.played.lock().unwrap().clone();
    assert_eq!(played.len(), 1, "{}", harness.state().listen.message);
    let (samples, channels, rate) = &played[0];
    assert_eq!((*channels, *rate), (2, 48_000));
    // The same clap through the same room, as the command line makes it.
    let heard = Hearing::from_scene(&clap_scene(&scene, &camera).unwrap(), None).unwrap();
    let [left, _] = heard.stereo(&|_, _| {});
    let expected = convolve::convolve(&clap::clap(48_000), &heard.samples(&left)).unwrap();
    assert_eq!(samples.len(), 2 * expected.len());
    let ours: Vec<f32> = samples.iter().step_by(2).copied().collect();
    // Equal up to the common scale.
    let scale = ours.iter().fold(0.0f32, |m, x| m.max(x.abs()))
        / expected.iter().fold(0.0f32, |m, x| m.max(x.abs()));
    assert!(
        ours.iter()
            .zip(&expected)
            .all(|(a, b)| (a - b * scale).abs() < 1e-4)
    );
    assert!(
        harness
            .state()
            .listen
            .message
            .contains("echoes at each ear")
    );
}

#[test]
fn a_clap_past_a_portal_comes_back_through_it() {
    // In 632 (every wall a portal) a camera close to a wall and facing it hears the clap from
    // where the hands are once carried through that portal: inside the room, not at the ear.
    let mut scene = quick_scene();
    scene.orbifold.signature = "632".into();
    let layout = scene.layout().unwrap();
    let space = layout.space();
    let (a, b) = (layout.vertices[0].position, layout.vertices[1].position);
    let mid = (a + b) / 2.0;
    let near = layout.centre + (mid - layout.centre) * 0.97;
    let towards = mid - near;
    let camera = orbifold_scene::Camera {
        at: [near.re, near.im],
        yaw: towards.im.atan2(towards.re).to_degrees(),
        pitch: 0.0,
        ..scene.camera.clone()
    };
    let heard = clap_scene(&scene, &camera).unwrap();
    let source = heard.sound.source.unwrap();
    assert_ne!(source.at, camera.at, "the clap fell back to the ear");
    let w = space.to_ambient(num_complex::Complex64::new(source.at[0], source.at[1]));
    assert!(layout.edges.iter().all(|e| e.wall.dot(w) > 0.0));
    let response = Hearing::from_scene(&heard, None).unwrap().mono(&|_, _| {});
    assert!(response.arrivals.len() > 10 && response.lost == 0);
}

#[test]
fn a_clap_is_half_a_metre_in_front_of_the_camera() {
    let scene = quick_scene();
    let camera = orbifold_scene::Camera {
        at: [0.1, 0.05],
        yaw: 90.0,
        ..scene.camera.clone()
    };
    let heard = clap_scene(&scene, &camera).unwrap();
    let (source, listener) = (heard.sound.source.unwrap(), heard.sound.listener.unwrap());
    assert_eq!(listener.at, camera.at);
    // *2222 is flat: model distances are half the intrinsic ones; 0.5 m is 0.125 units.
    let d = ((source.at[0] - 0.1).powi(2) + (source.at[1] - 0.05).powi(2)).sqrt() * 2.0;
    assert!((d - 0.125).abs() < 1e-12 && source.at[1] > 0.05, "{d}");
}
