//! Rendering in the background: the photo-realistic renderer (`orbifold-render`) on the view's
//! camera, one round (a sample for every pixel, or for the noisiest ones) at a time, so the
//! picture refines while the studio stays responsive; it can be cancelled, and the result
//! shown and saved.

use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Mutex};
use std::thread::JoinHandle;

use orbifold_render::film::Film;
use orbifold_render::integrator::{Integrator, Settings};
use orbifold_render::render::{Progressive, RenderOptions};
use orbifold_scene::Scene;
use orbifold_trace::camera::Camera;

/// What a running render shares with the studio.
#[derive(Default)]
struct Shared {
    film: Option<Film>,
    passes: u32,
    error: Option<String>,
    done: bool,
}

/// A render in the background.
pub struct RenderJob {
    shared: Arc<Mutex<Shared>>,
    cancel: Arc<AtomicBool>,
    thread: Option<JoinHandle<()>>,
    /// Samples a pixel asked for (the mean: sampling is adaptive).
    pub samples: u32,
    /// The picture's size.
    pub size: (u32, u32),
}

impl RenderJob {
    /// Starts rendering `scene` (meshes relative to `base`) with `camera` at `size`, `samples`
    /// passes.
    pub fn start(
        scene: &Scene,
        base: Option<&Path>,
        camera: &orbifold_scene::Camera,
        size: (u32, u32),
        samples: u32,
    ) -> RenderJob {
        let shared = Arc::new(Mutex::new(Shared::default()));
        let cancel = Arc::new(AtomicBool::new(false));
        let (scene, base, camera) = (scene.clone(), base.map(Path::to_path_buf), camera.clone());
        let thread = {
            let (shared, cancel) = (shared.clone(), cancel.clone());
            std::thread::spawn(move || {
                run(
                    &scene,
                    base.as_deref(),
                    &camera,
                    size,
                    samples,
                    &shared,
                    &cancel,
                )
            })
        };
        RenderJob {
            shared,
            cancel,
            thread: Some(thread),
            samples,
            size,
        }
    }

    /// Samples a pixel so far (the mean over the picture).
    pub fn passes(&self) -> u32 {
        self.shared.lock().map_or(0, |s| s.passes)
    }

    /// Whether it has finished (or stopped).
    pub fn is_done(&self) -> bool {
        self.shared.lock().is_ok_and(|s| s.done)
    }

    /// Why it failed, if it did.
    pub fn error(&self) -> Option<String> {
        self.shared.lock().ok().and_then(|s| s.error.clone())
    }

    /// Stops after the pass under way.
    pub fn cancel(&self) {
        self.cancel.store(true, Ordering::Relaxed);
    }

    /// The picture so far, tone-mapped (RGBA8), if a pass has finished.
    pub fn picture(&self) -> Option<(u32, u32, Vec<u8>)> {
        let shared = self.shared.lock().ok()?;
        let film = shared.film.as_ref()?;
        let exposure = film.auto_exposure();
        let mut rgba = Vec::with_capacity((film.width() * film.height() * 4) as usize);
        for y in 0..film.height() {
            for x in 0..film.width() {
                let [r, g, b] = orbifold_render::film::tone_map(film.pixel(x, y), exposure);
                rgba.extend_from_slice(&[r, g, b, 255]);
            }
        }
        Some((film.width(), film.height(), rgba))
    }

    /// Writes the picture so far (PNG, JPEG or EXR by the extension).
    pub fn save(&self, path: &Path) -> Result<(), String> {
        let shared = self.shared.lock().map_err(|e| e.to_string())?;
        let film = shared.film.as_ref().ok_or("nothing rendered yet")?;
        film.write(path, film.auto_exposure())
    }
}

impl Drop for RenderJob {
    fn drop(&mut self) {
        self.cancel();
        if let Some(thread) = self.thread.take() {
            let _ = thread.join();
        }
    }
}

fn run(
    scene: &Scene,
    base: Option<&Path>,
    camera: &orbifold_scene::Camera,
    size: (u32, u32),
    samples: u32,
    shared: &Mutex<Shared>,
    cancel: &AtomicBool,
) {
    let finish = |error: Option<String>| {
        if let Ok(mut s) = shared.lock() {
            s.error = error;
            s.done = true;
        }
    };
    let integrator = match Integrator::from_scene(scene, base, Settings::of_scene(scene)) {
        Ok(i) => i,
        Err(e) => return finish(Some(e)),
    };
    let camera = Camera::new(integrator.space(), camera);
    // Rounds of the stratified, adaptive sampler; the picture is shared after each.
    let options = RenderOptions {
        filter: scene.render.filter.into(),
        ..RenderOptions::new(size.0, size.1, samples, 0)
    };
    let mut progressive = Progressive::new(&integrator, &camera, &options);
    while progressive.paths() < progressive.budget() && !cancel.load(Ordering::Relaxed) {
        progressive.round();
        if let Ok(mut s) = shared.lock() {
            s.film = Some(progressive.film().clone());
            s.passes = progressive.samples();
        }
    }
    finish(None);
}

/// A default file name for a rendered picture next to the document.
pub fn default_output(document: Option<&Path>) -> PathBuf {
    document.map_or_else(|| PathBuf::from("render.png"), |p| p.with_extension("png"))
}
