//! The render loop: progressive passes of one sample per pixel over the whole image, in parallel
//! rows, into an HDR [`Film`]; stops after the wanted samples, at a time limit, or when asked to.
//!
//! Every sample's random numbers depend only on (seed, pixel, sample index), and the passes are
//! added to the film in pixel order, so an image is the same for a given seed whatever the
//! number of threads.

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
    /// after every pass from the second on).
    pub noise_target: Option<f64>,
}

impl RenderOptions {
    /// `samples` passes over a `width` × `height` image with `seed`, without a time limit or
    /// a noise target.
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
        }
    }
}

/// What a render did.
#[derive(Clone, Debug)]
pub struct Rendered {
    /// The image.
    pub film: Film,
    /// Samples per pixel taken.
    pub samples: u32,
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
    let (width, height) = (options.width, options.height);
    let mut film = Film::new(width, height);
    let mut guides = Guides::new(width, height);
    let mut done = 0;
    while done < options.samples {
        let pass = done;
        let rows: Vec<Vec<PathSample>> = (0..height)
            .into_par_iter()
            .map(|j| {
                (0..width)
                    .map(|i| {
                        let pixel = u64::from(j) * u64::from(width) + u64::from(i);
                        let mut sampler = Sampler::stratified(options.seed, pixel, u64::from(pass));
                        let offset = sampler.next_2d();
                        let ray = camera.ray(i, j, width, height, offset);
                        integrator.sample(&ray, &mut sampler)
                    })
                    .collect()
            })
            .collect();
        for (j, row) in rows.iter().enumerate() {
            for (i, value) in row.iter().enumerate() {
                film.add(i as u32, j as u32, value.radiance);
                guides.add(i as u32, j as u32, &value.first);
            }
        }
        done += 1;
        progress(done, options.samples);
        let out_of_time = options.time_limit.is_some_and(|t| start.elapsed() >= t);
        let quiet = done >= 2
            && options
                .noise_target
                .is_some_and(|t| film.relative_noise() <= t);
        if cancel.load(Ordering::Relaxed) || out_of_time || quiet {
            break;
        }
    }
    Rendered {
        film,
        samples: done,
        elapsed: start.elapsed(),
        stopped_early: done < options.samples,
        guides,
    }
}
