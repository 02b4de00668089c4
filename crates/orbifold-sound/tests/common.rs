//! Shared by the integration tests: rooms and scenes to hear.

#![allow(dead_code)]

use orbifold_scene::Scene;
use orbifold_scene::sound::Absorption;

/// A scene of a signature with the source and the listener at model points near the centre.
pub fn scene(signature: &str, seconds: f64) -> Scene {
    let mut scene = Scene::default();
    scene.orbifold.signature = signature.into();
    scene.objects.clear();
    let layout = scene.layout().unwrap();
    let c = layout.centre;
    // Between the centre and the first corner, either side.
    let v = layout.vertices[0].position;
    let w = layout.vertices[1].position;
    let toward = |p: num_complex::Complex64, t: f64| c + (p - c) * t;
    let (s, l) = (toward(v, 0.35), toward(w, 0.45));
    scene.lights[0].at = [s.re, s.im];
    scene.lights[0].height = 0.3;
    scene.camera.at = [l.re, l.im];
    scene.camera.height = 0.55;
    scene.sound.seconds = seconds;
    scene
}

/// The same scene with no absorption anywhere.
pub fn lossless(mut scene: Scene) -> Scene {
    for a in [
        &mut scene.sound.mirror_absorption,
        &mut scene.sound.wall_absorption,
        &mut scene.sound.floor_absorption,
        &mut scene.sound.ceiling_absorption,
    ] {
        *a = Absorption::Flat(0.0);
    }
    scene
}
