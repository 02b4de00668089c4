//! The render loop: progressive rounds of one sample per pixel, in parallel, into an HDR
//! [`Film`]; stops after the wanted samples, at a time limit, or when asked to.
//!
//! **Adaptive sampling** (on by default): after [`WARMUP_ROUNDS`] rounds over the whole image,
//! most rounds sample only the pixels whose noise on screen matters most — those whose
//! squared display error over their sample count ([`Film::display_errors`]; the largest in
//! their 3×3 neighbourhood, so that a pixel whose few samples happened to agree is not left
//! out) is at least the image's mean — and every [`FULL_ROUND_EVERY`]th round is again over
//! the whole image. Far mirror images crowd into a few pixels (the horizon of a hyperbolic
//! room holds thousands of copies of the room); they get the samples, while smooth walls do not.
//!
//! Every sample's random numbers depend only on (seed, pixel, the pixel's sample index), and
//! each round is added to the film in pixel order, so an image is the same for a given seed
//! whatever the number of threads.

use std::path::Path;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

use orbifold_scene::Scene;
use rayon::prelude::*;

use crate::camera::Camera;
use crate::denoise::Guides;
use crate::film::Film;
use crate::integrator::{Integrator, PathSample, Settings};
use crate::sampler::Sampler;

/// What to render.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RenderOptions {
    /// Image width in pixels.
    pub width: u32,
    /// Image height in pixels.
    pub height: u32,
    /// Samples per pixel wanted.
    pub samples: u32,
    /// Seed of the random numbers.
    pub seed: u64,
    /// Stop after the pass during which this much time has passed.
    pub time_limit: Option<Duration>,
    /// Stop once the film's relative noise ([`Film::relative_noise`]) is at most this (checked
    /// after every round from the second on).
    pub noise_target: Option<f64>,
    /// Spend the samples where the image is noisiest (see the module documentation); without
    /// it, every pixel gets exactly `samples` samples.
    pub adaptive: bool,
}

/// Rounds over the whole image before adaptive sampling starts.
pub const WARMUP_ROUNDS: u32 = 4;
/// With adaptive sampling, every this many rounds one is over the whole image.
pub const FULL_ROUND_EVERY: u32 = 8;

impl RenderOptions {
    /// `samples` samples per pixel (on average: adaptive sampling is on) over a `width` ×
    /// `height` image with `seed`, without a time limit or a noise target.
    ///
    /// ```
    /// use orbifold_render::render::RenderOptions;
    ///
    /// let options = RenderOptions::new(8, 6, 4, 1);
    /// assert_eq!((options.width, options.samples, options.time_limit), (8, 4, None));
    /// ```
    pub fn new(width: u32, height: u32, samples: u32, seed: u64) -> RenderOptions {
        RenderOptions {
            width,
            height,
            samples,
            seed,
            time_limit: None,
            noise_target: None,
            adaptive: true,
        }
    }
}

/// What a render did.
#[derive(Clone, Debug)]
pub struct Rendered {
    /// The image.
    pub film: Film,
    /// Samples per pixel taken (the mean, rounded down, with adaptive sampling).
    pub samples: u32,
    /// Samples taken in all (camera paths traced).
    pub paths: u64,
    /// Wall-clock time.
    pub elapsed: Duration,
    /// Whether it stopped before taking every sample (time limit, noise target or cancellation).
    pub stopped_early: bool,
    /// What each pixel's paths saw first, for the denoiser.
    pub guides: Guides,
}

/// Renders a scene from its camera to the end (no cancellation): its integrator with
/// `settings` (`base` resolves file names), then [`render`].
///
/// ```
/// use orbifold_render::integrator::Settings;
/// use orbifold_render::render::{RenderOptions, render_scene};
///
/// let scene = orbifold_scene::Scene::default();
/// let image = render_scene(&scene, None, Settings::default(), &RenderOptions::new(8, 6, 2, 1))?;
/// assert_eq!(image.film.width(), 8);
/// # Ok::<(), String>(())
/// ```
pub fn render_scene(
    scene: &Scene,
    base: Option<&Path>,
    settings: Settings,
    options: &RenderOptions,
) -> Result<Rendered, String> {
    let integrator = Integrator::from_scene(scene, base, settings)?;
    let camera = Camera::new(integrator.space(), &scene.camera);
    Ok(render(
        &integrator,
        &camera,
        options,
        &AtomicBool::new(false),
        &|_, _| {},
    ))
}

/// Renders the camera's view. `progress(done, wanted)` is called after every pass; setting
/// `cancel` stops after the current pass (the image so far is returned).
///
/// ```
/// use std::sync::atomic::AtomicBool;
/// use orbifold_render::{camera::Camera, integrator::{Integrator, Settings}};
/// use orbifold_render::render::{RenderOptions, render};
/// let scene = orbifold_scene::Scene::default();
/// let integrator = Integrator::from_scene(&scene, None, Settings::default())?;
/// let camera = Camera::new(integrator.space(), &scene.camera);
/// let options = RenderOptions::new(8, 6, 2, 1);
/// let image = render(&integrator, &camera, &options, &AtomicBool::new(false), &|_, _| {});
/// assert_eq!(image.samples, 2);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn render(
    integrator: &Integrator,
    camera: &Camera,
    options: &RenderOptions,
    cancel: &AtomicBool,
    progress: &(dyn Fn(u32, u32) + Sync),
) -> Rendered {
    let start = Instant::now();
    let mut progressive = Progressive::new(integrator, camera, options);
    let budget = progressive.budget();
    while progressive.paths() < budget {
        progressive.round();
        progress(progressive.samples().min(options.samples), options.samples);
        let out_of_time = options.time_limit.is_some_and(|t| start.elapsed() >= t);
        let quiet = progressive.rounds() >= 2
            && options
                .noise_target
                .is_some_and(|t| progressive.film().relative_noise() <= t);
        if cancel.load(Ordering::Relaxed) || out_of_time || quiet {
            break;
        }
    }
    progressive.finish(start.elapsed())
}

/// A render that goes on one round at a time, for callers that run their own loop (the
/// studio shows the picture after every round). [`render`] is this loop with a time limit,
/// a noise target and cancellation.
///
/// ```
/// use orbifold_render::{camera::Camera, integrator::{Integrator, Settings}};
/// use orbifold_render::render::{Progressive, RenderOptions};
/// let scene = orbifold_scene::Scene::default();
/// let integrator = Integrator::from_scene(&scene, None, Settings::default())?;
/// let camera = Camera::new(integrator.space(), &scene.camera);
/// let options = RenderOptions::new(8, 6, 2, 1);
/// let mut progressive = Progressive::new(&integrator, &camera, &options);
/// progressive.round();
/// assert_eq!((progressive.samples(), progressive.film().samples(3, 2)), (1, 1));
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub struct Progressive<'a> {
    integrator: &'a Integrator,
    camera: &'a Camera,
    options: RenderOptions,
    film: Film,
    guides: Guides,
    /// Samples taken per pixel: the index of its next sample in its stratified sequence.
    taken: Vec<u32>,
    total: u64,
    rounds: u32,
}

impl<'a> Progressive<'a> {
    /// An empty image of `options`' size, to be rendered with `options`' seed and sampling.
    pub fn new(
        integrator: &'a Integrator,
        camera: &'a Camera,
        options: &RenderOptions,
    ) -> Progressive<'a> {
        let (width, height) = (options.width, options.height);
        Progressive {
            integrator,
            camera,
            options: *options,
            film: Film::new(width, height),
            guides: Guides::new(width, height),
            taken: vec![0; width as usize * height as usize],
            total: 0,
            rounds: 0,
        }
    }

    /// The samples `options.samples` asks for in all.
    pub fn budget(&self) -> u64 {
        u64::from(self.options.samples) * self.taken.len() as u64
    }

    /// One more round: one sample for every pixel, or with adaptive sampling after the first
    /// rounds, for the noisiest ones (see the module documentation).
    pub fn round(&mut self) {
        let options = &self.options;
        let (width, height) = (options.width, options.height);
        let pixels = u64::from(width) * u64::from(height);
        if pixels == 0 {
            return;
        }
        let chosen = if options.adaptive
            && self.rounds >= WARMUP_ROUNDS
            && !self.rounds.is_multiple_of(FULL_ROUND_EVERY)
        {
            noisiest(&self.film, &self.taken)
        } else {
            None
        };
        let taken = &self.taken;
        let (integrator, camera) = (self.integrator, self.camera);
        let trace = |pixel: u64| {
            let (i, j) = (
                (pixel % u64::from(width)) as u32,
                (pixel / u64::from(width)) as u32,
            );
            let index = u64::from(taken[pixel as usize]);
            let mut sampler = Sampler::stratified(options.seed, pixel, index);
            let offset = sampler.next_2d();
            let ray = camera.ray(i, j, width, height, offset);
            integrator.sample(&ray, &mut sampler)
        };
        let results: Vec<(u64, PathSample)> = match &chosen {
            Some(list) => list.par_iter().map(|&p| (p, trace(p))).collect(),
            None => (0..pixels).into_par_iter().map(|p| (p, trace(p))).collect(),
        };
        for (pixel, value) in &results {
            let (i, j) = (
                (pixel % u64::from(width)) as u32,
                (pixel / u64::from(width)) as u32,
            );
            self.film.add(i, j, value.radiance);
            self.guides.add(i, j, &value.first);
            self.taken[*pixel as usize] += 1;
        }
        self.total += results.len() as u64;
        self.rounds += 1;
    }

    /// Rounds done.
    pub fn rounds(&self) -> u32 {
        self.rounds
    }

    /// Samples taken in all.
    pub fn paths(&self) -> u64 {
        self.total
    }

    /// Samples per pixel so far (the mean, rounded down).
    pub fn samples(&self) -> u32 {
        self.total.checked_div(self.taken.len() as u64).unwrap_or(0) as u32
    }

    /// The image so far.
    pub fn film(&self) -> &Film {
        &self.film
    }

    /// What the pixels' paths saw first so far, for the denoiser.
    pub fn guides(&self) -> &Guides {
        &self.guides
    }

    /// The result, after `elapsed` of rendering.
    pub fn finish(self, elapsed: Duration) -> Rendered {
        let budget = self.budget();
        Rendered {
            samples: self.samples(),
            paths: self.total,
            elapsed,
            stopped_early: self.total < budget,
            film: self.film,
            guides: self.guides,
        }
    }
}

/// The pixels that an adaptive round samples, in order: those whose squared display error per
/// sample, the largest in their 3×3 neighbourhood, is at least the mean over the image. `None`
/// (a round over the whole image) when that picks every pixel or none.
fn noisiest(film: &Film, taken: &[u32]) -> Option<Vec<u64>> {
    let (width, height) = (film.width() as usize, film.height() as usize);
    let errors = film.display_errors(film.auto_exposure());
    let score: Vec<f64> = errors
        .iter()
        .zip(taken)
        .map(|(e, &n)| e * e / f64::from(n.max(1)))
        .collect();
    if score.iter().any(|s| !s.is_finite()) {
        return None;
    }
    let spread: Vec<f64> = (0..height)
        .into_par_iter()
        .flat_map_iter(|y| {
            let score = &score;
            (0..width).map(move |x| {
                let mut most = 0.0f64;
                for yy in y.saturating_sub(1)..(y + 2).min(height) {
                    for xx in x.saturating_sub(1)..(x + 2).min(width) {
                        most = most.max(score[yy * width + xx]);
                    }
                }
                most
            })
        })
        .collect();
    let mean = spread.iter().sum::<f64>() / spread.len() as f64;
    let chosen: Vec<u64> = (0..spread.len() as u64)
        .filter(|&p| spread[p as usize] >= mean && spread[p as usize] > 0.0)
        .collect();
    (!chosen.is_empty() && chosen.len() < spread.len()).then_some(chosen)
}
