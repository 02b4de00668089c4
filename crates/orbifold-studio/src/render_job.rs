//! Rendering in the background: the photo-realistic renderer's one pipeline
//! (`orbifold_render::render`, as `orbifold render` uses it) on the 3D view's camera, one round
//! (a sample for every pixel, or for the noisiest ones) at a time, so the picture refines while
//! the studio stays responsive. The picture shown is finished as the command line finishes a PNG:
//! denoised and tone-mapped at the raw image's log-average exposure. It can be cancelled, and
//! the result shown and saved.
//!
//! On the desktop the rounds run on a thread of their own (and each round on rayon's threads).
//! In the browser (`wasm32`) there are no threads: the studio calls [`RenderJob::step`] every
//! frame, which takes rounds for at most [`STEP_BUDGET`] and returns, so that the page keeps
//! drawing between them.

use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Mutex};
#[cfg(not(target_arch = "wasm32"))]
use std::thread::JoinHandle;
use std::time::Duration;

use web_time::Instant;

use orbifold_render::integrator::{Integrator, Settings};
use orbifold_render::render::{Picture, Progressive, RenderOptions};
use orbifold_scene::Scene;
use orbifold_trace::camera::Camera;

/// How often a running render's picture is finished (denoised) to be shown.
const SHOW_EVERY: Duration = Duration::from_millis(500);

/// How long one [`RenderJob::step`] goes on taking rounds in the browser (one round at least):
/// short enough that the page still answers, long enough that most of the time is rendering.
pub const STEP_BUDGET: Duration = Duration::from_millis(60);

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
    #[cfg(not(target_arch = "wasm32"))]
    thread: Option<JoinHandle<()>>,
    /// The render under way, stepped by the studio's frames (no threads in the browser).
    #[cfg(target_arch = "wasm32")]
    stepper: Option<(web::Stepper, Showing)>,
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
        #[cfg(not(target_arch = "wasm32"))]
        let thread = {
            let (scene, base, camera) =
                (scene.clone(), base.map(Path::to_path_buf), camera.clone());
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
        #[cfg(target_arch = "wasm32")]
        let stepper = match prepare(scene, base, camera, size, samples) {
            Ok(parts) => Some((web::Stepper::start(parts), Showing::new())),
            Err(e) => {
                finish(&shared, Some(e));
                None
            }
        };
        RenderJob {
            shared,
            cancel,
            #[cfg(not(target_arch = "wasm32"))]
            thread: Some(thread),
            #[cfg(target_arch = "wasm32")]
            stepper,
            samples,
            size,
        }
    }

    /// Takes the next rounds of a render that runs in the studio's frames (the browser): for
    /// at most [`STEP_BUDGET`], one round at least. On the desktop the render has its own
    /// thread and this does nothing.
    pub fn step(&mut self) {
        #[cfg(target_arch = "wasm32")]
        if let Some((stepper, showing)) = &mut self.stepper {
            let begun = Instant::now();
            let finished = loop {
                let done = stepper.round(|progressive| {
                    showing.after_round(progressive, &self.shared, &self.cancel)
                });
                if done || begun.elapsed() >= STEP_BUDGET {
                    break done;
                }
            };
            if finished {
                self.stepper = None;
                finish(&self.shared, None);
            }
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
        #[cfg(not(target_arch = "wasm32"))]
        if let Some(thread) = self.thread.take() {
            let _ = thread.join();
        }
    }
}

/// Marks the render finished, with its error if it failed.
fn finish(shared: &Mutex<Shared>, error: Option<String>) {
    if let Ok(mut s) = shared.lock() {
        s.error = error;
        s.done = true;
    }
}

/// What a render needs before its first round: the integrator of the scene, the camera and
/// the options of `orbifold render` for a PNG of this scene (seed 0, denoised), so that the
/// studio's picture is the command line's.
fn prepare(
    scene: &Scene,
    base: Option<&Path>,
    camera: &orbifold_scene::Camera,
    size: (u32, u32),
    samples: u32,
) -> Result<(Integrator, Camera, RenderOptions), String> {
    let integrator = Integrator::from_scene(scene, base, Settings::of_scene(scene))?;
    let camera = Camera::new(integrator.space(), camera);
    let options = RenderOptions {
        filter: scene.render.filter.into(),
        denoised: true,
        ..RenderOptions::new(size.0, size.1, samples, 0)
    };
    Ok((integrator, camera, options))
}

/// When the picture of a render was last finished for showing.
struct Showing {
    start: Instant,
    /// When the picture was last finished, and how long finishing it took.
    shown: Option<(Instant, Duration)>,
}

impl Showing {
    fn new() -> Showing {
        Showing {
            start: Instant::now(),
            shown: None,
        }
    }

    /// After a round: counts the samples, finishes the picture when it is due, and says
    /// whether the render is over (every sample taken, or cancelled).
    fn after_round(
        &mut self,
        progressive: &Progressive,
        shared: &Mutex<Shared>,
        cancel: &AtomicBool,
    ) -> bool {
        let last = progressive.paths() >= progressive.budget() || cancel.load(Ordering::Relaxed);
        if let Ok(mut s) = shared.lock() {
            s.passes = progressive.samples();
        }
        // Denoising a large picture takes about a round, and that time is taken from the
        // render: the picture is finished after the first round, then after at least
        // SHOW_EVERY and twice the last finish's time (so that at most a third of the time
        // goes to showing it), and at the end.
        let due = self
            .shown
            .is_none_or(|(at, took)| at.elapsed() >= SHOW_EVERY.max(2 * took));
        if last || due {
            let begun = Instant::now();
            let picture = progressive.picture(self.start.elapsed(), None);
            let rgba = picture.rgba8();
            if let Ok(mut s) = shared.lock() {
                s.picture = Some((picture, rgba));
            }
            self.shown = Some((Instant::now(), begun.elapsed()));
        }
        last
    }
}

#[cfg(not(target_arch = "wasm32"))]
fn run(
    scene: &Scene,
    base: Option<&Path>,
    camera: &orbifold_scene::Camera,
    size: (u32, u32),
    samples: u32,
    shared: &Mutex<Shared>,
    cancel: &AtomicBool,
) {
    let (integrator, camera, options) = match prepare(scene, base, camera, size, samples) {
        Ok(parts) => parts,
        Err(e) => return finish(shared, Some(e)),
    };
    let mut showing = Showing::new();
    let mut progressive = Progressive::new(&integrator, &camera, &options);
    while progressive.paths() < progressive.budget() && !cancel.load(Ordering::Relaxed) {
        progressive.round();
        if showing.after_round(&progressive, shared, cancel) {
            break;
        }
    }
    finish(shared, None);
}

/// The render as the browser runs it: the progressive loop kept between frames together with
/// the integrator and camera it borrows.
#[cfg(target_arch = "wasm32")]
mod web {
    use orbifold_render::integrator::Integrator;
    use orbifold_render::render::{Progressive, RenderOptions};
    use orbifold_trace::camera::Camera;

    self_cell::self_cell!(
        /// A [`Progressive`] render with the integrator and camera it borrows, kept together
        /// so that it can live from one frame to the next.
        pub(super) struct Stepper {
            owner: (Integrator, Camera, RenderOptions),
            #[not_covariant]
            dependent: Progressive,
        }
    );

    impl Stepper {
        /// A render that has taken no round yet.
        pub(super) fn start(parts: (Integrator, Camera, RenderOptions)) -> Stepper {
            Stepper::new(parts, |(integrator, camera, options)| {
                Progressive::new(integrator, camera, options)
            })
        }

        /// Takes one round, then `after(progressive)`; returns what `after` says (whether the
        /// render is over). A render that has every sample takes no round.
        pub(super) fn round(&mut self, after: impl FnOnce(&Progressive) -> bool) -> bool {
            self.with_dependent_mut(|_, progressive| {
                if progressive.paths() < progressive.budget() {
                    progressive.round();
                }
                after(progressive)
            })
        }
    }
}

/// A default file name for a rendered picture next to the document.
pub fn default_output(document: Option<&Path>) -> PathBuf {
    document.map_or_else(|| PathBuf::from("render.png"), |p| p.with_extension("png"))
}
