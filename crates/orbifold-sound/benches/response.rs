//! A 2-second response at 48 kHz (the default `[sound]` settings: 4 m a unit, −60 dB limit) in
//! a Euclidean, a hyperbolic and a spherical room of mirrors, and in two rooms with portals (the
//! cone points of `632` and `2223`): the echoes and their signal.
//! `cargo bench -p orbifold-sound --bench response`.

#![allow(missing_docs)] // criterion_group! generates undocumented functions.

use criterion::{Criterion, criterion_group, criterion_main};
use orbifold_scene::Scene;
use orbifold_sound::Hearing;

/// The default scene of a signature, with the source at the room's centre and the listener half
/// way to the first corner.
fn hearing(signature: &str) -> Hearing {
    let mut scene = Scene::default();
    scene.orbifold.signature = signature.into();
    scene.objects.clear();
    let layout = scene.layout().expect("a room");
    let c = layout.centre;
    let v = layout.vertices[0].position;
    scene.lights[0].at = [c.re, c.im];
    let l = c + (v - c) * 0.5;
    scene.camera.at = [l.re, l.im];
    Hearing::from_scene(&scene, None).expect("a scene that can be heard")
}

fn responses(c: &mut Criterion) {
    let mut group = c.benchmark_group("response_2s_48kHz");
    group.sample_size(10);
    for signature in ["*444", "*2222", "*235", "632", "2223"] {
        let hearing = hearing(signature);
        group.bench_function(signature, |b| {
            b.iter(|| {
                let response = hearing.mono(&|_, _| {});
                hearing.samples(&response)
            })
        });
    }
    group.finish();
}

criterion_group!(benches, responses);
criterion_main!(benches);
