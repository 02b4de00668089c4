//! The render loop: progressive rounds of one sample per pixel (or, with adaptive sampling, as
//! many for each pixel as its stage's allocation gives it in that round: `adaptive.rs`), in
//! parallel, into an HDR [`Film`]; stops after the wanted samples, at a time limit, at a noise
//! target, or when asked to.
//!
//! With a radiance cache ([`crate::radiance_cache`]), the first round is taken in two halves, a
//! checkerboard: with no cache to read, its paths are traced in full, about twice a later
//! round's work, so the first half fills the cache and the second reads it.

use std::path::Path;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

use orbifold_scene::Scene;
use orbifold_trace::camera::Camera;
use rayon::prelude::*;

use super::adaptive::{Target, allocate, samples_in_round, stage_length};
use super::options::{RenderOptions, WARMUP_ROUNDS};
use crate::denoise::{DenoiseOptions, Guides, denoise_with_reduction};
use crate::film::{Film, Splat};
use crate::integrator::{FirstHit, Integrator, PathSample, Settings};
use crate::radiance_cache::{Deposit, RadianceCache};
use crate::sampler::Sampler;

/// What a render did.
#[derive(Clone, Debug)]
pub struct Rendered {
    /// The image.
    pub film: Film,
    /// Samples per pixel taken (the mean, rounded down, with adaptive sampling).
    pub samples: u32,
    /// Samples taken in all (camera paths traced).
    pub paths: u64,
    /// Rays traced in all: the paths' geodesic stretches between mirrors, nearest-hit searches
    /// and shadow tests alike ([`PathSample::rays`]).
    pub rays: u64,
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
/// use orbifold_render::integrator::{Integrator, Settings};
/// use orbifold_trace::camera::Camera;
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
/// use orbifold_render::integrator::{Integrator, Settings};
/// use orbifold_trace::camera::Camera;
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
    rays: u64,
    rounds: u32,
    /// The denoiser's variance reduction per pixel, when adaptive sampling aims at a denoised
    /// image (refreshed at the start of every stage).
    reduction: Option<Vec<f64>>,
    /// The stage of adaptive sampling this round belongs to.
    stage: Stage,
    /// The radiance cache for far mirror images, filled from the rounds so far
    /// ([`crate::radiance_cache`]).
    cache: Option<RadianceCache>,
    /// The last round's paths and what they add to the film, the guides and the cache, kept
    /// from round to round: a large round holds hundreds of megabytes, and fresh memory each
    /// round costs more in page faults than the bookkeeping itself.
    buffers: RoundBuffers,
}

/// A stage of adaptive sampling (`adaptive.rs`): `rounds` rounds from `first_round`, in which
/// pixel j takes `counts[j]` samples; without `counts`, one a round each.
struct Stage {
    first_round: u32,
    rounds: u32,
    counts: Option<Vec<u32>>,
}

/// Memory reused by every round ([`Progressive::round`]).
#[derive(Default)]
struct RoundBuffers {
    results: Vec<(u64, PathSample)>,
    samples: Vec<(Splat, FirstHit)>,
    splats: Vec<Splat>,
    deposits: Vec<Deposit>,
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
            rays: 0,
            rounds: 0,
            reduction: None,
            stage: Stage {
                first_round: 0,
                rounds: 0,
                counts: None,
            },
            cache: integrator.uses_radiance_cache().then(RadianceCache::new),
            buffers: RoundBuffers::default(),
        }
    }

    /// The samples `options.samples` asks for in all.
    pub fn budget(&self) -> u64 {
        u64::from(self.options.samples) * self.taken.len() as u64
    }

    /// One more round: one sample for every pixel, or with adaptive sampling after the warm-up,
    /// each pixel's share of its stage's samples (`adaptive.rs`).
    pub fn round(&mut self) {
        let (width, height) = (self.options.width, self.options.height);
        let pixels = u64::from(width) * u64::from(height);
        if pixels == 0 {
            return;
        }
        if self.rounds - self.stage.first_round >= self.stage.rounds {
            self.start_stage();
        }
        let round = self.rounds - self.stage.first_round;
        let chosen = self.stage.counts.as_ref().map(|counts| {
            let (rounds, taken) = (self.stage.rounds, &self.taken);
            counts
                .iter()
                .zip(taken)
                .enumerate()
                .flat_map(|(p, (&count, &taken))| {
                    let new = samples_in_round(count, round, rounds).len() as u32;
                    (taken..taken + new).map(move |index| (p as u64, index))
                })
                .collect::<Vec<_>>()
        });
        match chosen {
            Some(list) => self.take(Some(&list)),
            None if self.rounds == 0 && self.cache.is_some() => {
                // The first round has no radiance cache to read, so every path is traced in
                // full (about twice a later round's work). Half the pixels, a checkerboard,
                // go first and fill the cache that the other half then reads.
                let half = |parity: u64| -> Vec<(u64, u32)> {
                    (0..pixels)
                        .filter(|p| (p % u64::from(width) + p / u64::from(width)) % 2 == parity)
                        .map(|p| (p, 0))
                        .collect()
                };
                // (Sample 0 of each pixel: the first round.)
                self.take(Some(&half(0)));
                self.take(Some(&half(1)));
            }
            None => self.take(None),
        }
        self.rounds += 1;
    }

    /// Starts the next stage: its length, and with adaptive sampling after the warm-up, each
    /// pixel's samples in it, from the image so far (`adaptive.rs`).
    fn start_stage(&mut self) {
        let options = &self.options;
        let first_round = self.rounds;
        if !options.adaptive {
            self.stage = Stage {
                first_round,
                rounds: u32::MAX,
                counts: None,
            };
            return;
        }
        let rounds = stage_length(first_round, options.samples);
        let counts = if first_round >= WARMUP_ROUNDS {
            if options.denoised {
                let (_, reduction) =
                    denoise_with_reduction(&self.film, &self.guides, &DenoiseOptions::default());
                self.reduction = Some(reduction);
            }
            let target = match &self.reduction {
                Some(reduction) if options.denoised => Target::Denoised(reduction),
                _ => Target::Raw,
            };
            allocate(&self.film, target, rounds)
        } else {
            None
        };
        self.stage = Stage {
            first_round,
            rounds,
            counts,
        };
    }

    /// Traces the samples `chosen` ((pixel, the sample's index in the pixel's sequence), in
    /// pixel order), or the next one of every pixel, and adds them to the film, the guides and
    /// the radiance cache.
    fn take(&mut self, chosen: Option<&[(u64, u32)]>) {
        let options = &self.options;
        let (width, height) = (options.width, options.height);
        let taken = &self.taken;
        let cache = self.cache.as_ref();
        let (integrator, camera) = (self.integrator, self.camera);
        let trace = |pixel: u64, index: u32| {
            let (i, j) = (
                (pixel % u64::from(width)) as u32,
                (pixel / u64::from(width)) as u32,
            );
            let mut sampler = Sampler::stratified(options.seed, pixel, u64::from(index));
            let offset = sampler.next_2d();
            let ray = camera.ray(i, j, width, height, offset);
            let footprint = camera.footprint(i, j, width, height, offset);
            // The pixel reads the cache's cells that hold as many estimates as it has samples.
            let reader = cache.map(|c| c.reader(taken[pixel as usize]));
            let sample =
                integrator.sample_pixel_cached(&ray, Some(footprint), reader, &mut sampler);
            (pixel, sample)
        };
        let buffers = &mut self.buffers;
        match chosen {
            Some(list) => list
                .par_iter()
                .map(|&(p, index)| trace(p, index))
                .collect_into_vec(&mut buffers.results),
            None => (0..taken.len())
                .into_par_iter()
                .map(|p| trace(p as u64, taken[p]))
                .collect_into_vec(&mut buffers.results),
        }
        let results = &buffers.results;
        // In pixel order, so in row order as splatting wants.
        // Copied out in parallel (in order: `collect_into_vec` keeps it).
        results
            .par_iter()
            .map(|(pixel, value)| {
                let splat = Splat {
                    x: (pixel % u64::from(width)) as u32,
                    y: (pixel / u64::from(width)) as u32,
                    radiance: value.radiance,
                };
                (splat, value.first)
            })
            .collect_into_vec(&mut buffers.samples);
        for (pixel, _) in results {
            self.taken[*pixel as usize] += 1;
        }
        buffers
            .samples
            .par_iter()
            .map(|(s, _)| *s)
            .collect_into_vec(&mut buffers.splats);
        // The film and the guides on one side, the radiance cache (its levels in parallel) on
        // the other: three independent sums, so that neither thread waits while the other
        // adds. Each is summed in pixel order, so the image does not depend on the threads.
        let (film, guides, cache) = (&mut self.film, &mut self.guides, &mut self.cache);
        let (splats, samples, deposits) =
            (&buffers.splats, &buffers.samples, &mut buffers.deposits);
        rayon::join(
            || {
                film.splat_all(splats, options.filter);
                guides.splat_all(samples, options.filter);
            },
            || {
                if let Some(cache) = cache {
                    deposits.clear();
                    deposits.extend(results.iter().filter_map(|(_, v)| v.deposit));
                    cache.add_all(deposits);
                }
            },
        );
        self.total += results.len() as u64;
        self.rays += results.iter().map(|(_, v)| u64::from(v.rays)).sum::<u64>();
    }

    /// Rounds done.
    pub fn rounds(&self) -> u32 {
        self.rounds
    }

    /// Samples taken in all.
    pub fn paths(&self) -> u64 {
        self.total
    }

    /// Rays traced in all ([`Rendered::rays`]).
    pub fn rays(&self) -> u64 {
        self.rays
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

    /// The options it renders with.
    pub fn options(&self) -> &RenderOptions {
        &self.options
    }

    /// The result so far, after `elapsed` of rendering (the film and the guides copied).
    pub fn snapshot(&self, elapsed: Duration) -> Rendered {
        Rendered {
            samples: self.samples(),
            paths: self.total,
            rays: self.rays,
            elapsed,
            stopped_early: self.total < self.budget(),
            film: self.film.clone(),
            guides: self.guides.clone(),
        }
    }

    /// The result, after `elapsed` of rendering.
    pub fn finish(self, elapsed: Duration) -> Rendered {
        let budget = self.budget();
        Rendered {
            samples: self.samples(),
            paths: self.total,
            rays: self.rays,
            elapsed,
            stopped_early: self.total < budget,
            film: self.film,
            guides: self.guides,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_first_round_fills_the_cache_from_half_the_pixels_for_the_other_half() {
        let scene = Scene::default();
        let integrator = Integrator::from_scene(&scene, None, Settings::default()).unwrap();
        assert!(integrator.uses_radiance_cache());
        let camera = Camera::new(integrator.space(), &scene.camera);
        let options = RenderOptions::new(96, 64, 4, 3);
        let mut progressive = Progressive::new(&integrator, &camera, &options);
        progressive.round();
        // One sample for every pixel, as in any full round.
        assert_eq!(progressive.paths(), 96 * 64);
        assert!(progressive.taken.iter().all(|&n| n == 1));
        // The last half taken (the odd squares of the checkerboard) read the cache that the
        // first half filled, so its paths were shorter.
        let odd = &progressive.buffers.results;
        assert_eq!(odd.len(), 96 * 64 / 2);
        assert!(odd.iter().all(|&(p, _)| (p % 96 + p / 96) % 2 == 1));
        let odd_rays: u64 = odd.iter().map(|(_, s)| u64::from(s.rays)).sum();
        let even_rays = progressive.rays() - odd_rays;
        assert!(
            (odd_rays as f64) < 0.95 * even_rays as f64,
            "rays: {odd_rays} in the second half against {even_rays} in the first"
        );
    }
}
