//! The studio's render tab makes its picture with the library's one render pipeline, as
//! `orbifold render` does: the background job's finished picture is, byte for byte, the
//! pipeline's denoised picture of the same scene and camera.

use std::sync::atomic::AtomicBool;
use std::time::{Duration, Instant};

use orbifold_render::integrator::{Integrator, Settings};
use orbifold_render::render::{RenderOptions, render_picture};
use orbifold_scene::Scene;
use orbifold_studio::render_job::RenderJob;
use orbifold_trace::camera::Camera;

#[test]
fn the_render_tab_s_picture_is_the_command_line_s() {
    let scene = Scene::default();
    let (size, samples) = ((40, 30), 4);
    let job = RenderJob::start(&scene, None, &scene.camera, size, samples);
    let start = Instant::now();
    while !job.is_done() {
        assert!(
            start.elapsed() < Duration::from_secs(600),
            "the render never finished"
        );
        std::thread::sleep(Duration::from_millis(20));
    }
    assert_eq!(job.error(), None);
    assert_eq!(job.passes(), samples);

    let integrator = Integrator::from_scene(&scene, None, Settings::of_scene(&scene)).unwrap();
    let camera = Camera::new(integrator.space(), &scene.camera);
    let options = RenderOptions {
        denoised: true,
        filter: scene.render.filter.into(),
        ..RenderOptions::new(size.0, size.1, samples, 0)
    };
    let stop = AtomicBool::new(false);
    let picture = render_picture(&integrator, &camera, &options, None, &stop, &|_, _| {});
    let (width, height, rgba) = job.picture().expect("a finished picture");
    assert_eq!((width, height), size);
    assert!(
        rgba == picture.rgba8(),
        "the studio's picture differs from the pipeline's"
    );

    let dir = tempfile::Builder::new()
        .prefix("orbifold-render-job-")
        .tempdir()
        .unwrap();
    let (studio, library) = (
        dir.path().join("studio.exr"),
        dir.path().join("library.exr"),
    );
    job.save(&studio).unwrap();
    picture.write(&library).unwrap();
    assert!(std::fs::read(&studio).unwrap() == std::fs::read(&library).unwrap());
}
