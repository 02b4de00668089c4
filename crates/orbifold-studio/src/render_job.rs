//! Rendering in the background: the photo-realistic renderer's one pipeline
//! (`orbifold_render::render`, as `orbifold render` uses it) on the 3D view's camera, one round
//! (a sample for every pixel, or for the noisiest ones) at a time, so the picture refines while
//! the studio stays responsive. The picture shown is finished as the command line finishes a PNG:
//! denoised and tone-mapped at the raw image's log-average exposure. It can be cancelled, and
//! the result shown and saved.

use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Mutex};
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

use orbifold_render::integrator::{Integrator, Settings};
use orbifold_render::render::{Picture, Progressive, RenderOptions};
use orbifold_scene::Scene;
use orbifold_trace::camera::Camera;

/// How often a running render's picture is finished (denoised) to be shown.
const SHOW_EVERY: Duration = Duration::from_millis(500);

/// What a running render shares with the studio.
#[derive(Default)]
struct Shared {
    /// The picture so far, and its display form (RGBA8).
    picture: Option<(Picture, Vec<u8>)>,
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

    /// The picture so far, denoised and tone-mapped (RGBA8), if a round has finished.
    pub fn picture(&self) -> Option<(u32, u32, Vec<u8>)> {
        let shared = self.shared.lock().ok()?;
        let (picture, rgba) = shared.picture.as_ref()?;
        let (width, height) = picture.size();
        Some((width, height, rgba.clone()))
    }

    /// Writes the picture so far as shown (PNG or JPEG), or its HDR image (EXR), by the
    /// extension.
    pub fn save(&self, path: &Path) -> Result<(), String> {
        let shared = self.shared.lock().map_err(|e| e.to_string())?;
        let (picture, _) = shared.picture.as_ref().ok_or("nothing rendered yet")?;
        picture.write(path)
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
    // The options of `orbifold render` for a PNG of this scene (seed 0, denoised), so that
    // the studio's picture is the command line's.
    let options = RenderOptions {
        filter: scene.render.filter.into(),
        denoised: true,
        ..RenderOptions::new(size.0, size.1, samples, 0)
    };
    let start = Instant::now();
    let mut progressive = Progressive::new(&integrator, &camera, &options);
    // When the picture was last finished, and how long finishing it took.
    let mut shown: Option<(Instant, Duration)> = None;
    while progressive.paths() < progressive.budget() && !cancel.load(Ordering::Relaxed) {
        progressive.round();
        let last = progressive.paths() >= progressive.budget() || cancel.load(Ordering::Relaxed);
        if let Ok(mut s) = shared.lock() {
            s.passes = progressive.samples();
        }
        // Denoising a large picture takes about a round, and that time is taken from the
        // render: the picture is finished after the first round, then after at least
        // SHOW_EVERY and twice the last finish's time (so that at most a third of the time
        // goes to showing it), and at the end.
        let due = shown.is_none_or(|(at, took)| at.elapsed() >= SHOW_EVERY.max(2 * took));
        if last || due {
            let begun = Instant::now();
            let picture = progressive.picture(start.elapsed(), None);
            let rgba = picture.rgba8();
            if let Ok(mut s) = shared.lock() {
                s.picture = Some((picture, rgba));
            }
            shown = Some((Instant::now(), begun.elapsed()));
        }
    }
    finish(None);
}

/// A default file name for a rendered picture next to the document.
pub fn default_output(document: Option<&Path>) -> PathBuf {
    document.map_or_else(|| PathBuf::from("render.png"), |p| p.with_extension("png"))
}
