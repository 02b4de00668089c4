//! The render loop: progressive rounds of one sample per pixel, in parallel, into an HDR
//! [`Film`]; stops after the wanted samples, at a time limit, or when asked to.
//!
//! **Adaptive sampling** (on by default): after [`WARMUP_ROUNDS`] rounds over the whole image,
//! most rounds sample only the pixels whose noise on screen matters most, and every
//! [`FULL_ROUND_EVERY`]th round ([`FULL_ROUND_EVERY_DENOISED`]th for a denoised image) is
//! again over the whole image. A pixel's score is its squared
//! display error ([`Film::display_errors`]), taken as the largest in its 3×3 neighbourhood so
//! that a pixel whose few samples happened to agree is not left out, and so that how many
//! samples a pixel gets depends little on its own samples' values (scored by its own samples
//! alone, a pixel whose samples came out low stops early while one with a high outlier gets
//! more that dilute it: the furnace in `tests/materials.rs` came out 2.7 % dark):
//!
//! - for an image shown as it is, the score is divided by the pixel's sample count (the
//!   greedy order for the least summed squared error), and a round gives one sample to every
//!   pixel whose score is at least the image's mean;
//! - for an image that will be denoised ([`RenderOptions::denoised`]), the score is the noise
//!   the denoiser will leave: the squared display error times the square root of the filter's
//!   variance reduction at that pixel ([`crate::denoise::denoise_with_reduction`], recomputed
//!   at rounds 4, 8, 16, …; the root because the propagated reduction overstates what the
//!   filter does on smooth surfaces), and a pixel gets as many samples in a round as its score
//!   is multiples of the mean, up to [`MOST_SAMPLES_PER_ROUND`]. The samples go to what the
//!   filter cannot smooth — the horizon's crowd of sub-pixel mirror images, silhouettes —
//!   rather than to walls that it averages anyway (measured in `docs/benchmarks.md`).
//!
//! Far mirror images crowd into a few pixels (the horizon of a hyperbolic room holds thousands
//! of copies of the room); they get the samples, while smooth walls do not.
//!
//! With a radiance cache ([`crate::radiance_cache`]), the first round is taken in two halves, a
//! checkerboard: with no cache to read, its paths are traced in full, about twice a later
//! round's work, so the first half fills the cache and the second reads it (at 896² in the
//! hyperbolic `*444`, 6.0 s instead of 7.8 s).
//!
//! Every sample's random numbers depend only on (seed, pixel, the pixel's sample index), and
//! each round (each half of the first) is added to the film and the cache in pixel order, so an
//! image is the same for a given seed whatever the number of threads.

use std::path::Path;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

use orbifold_scene::Scene;
use rayon::prelude::*;

use crate::denoise::{DenoiseOptions, Guides, denoise_with_reduction};
use crate::film::{Film, Splat};
use crate::filter::PixelFilter;
use crate::integrator::{FirstHit, Integrator, PathSample, Settings};
use crate::radiance_cache::{Deposit, RadianceCache};
use crate::sampler::Sampler;
use orbifold_trace::camera::Camera;

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
    /// The image will be denoised ([`crate::denoise`]): adaptive sampling aims at the noise the
    /// denoiser leaves rather than at the raw image's (see the module documentation).
    pub denoised: bool,
    /// How each sample counts for the pixels around it ([`PixelFilter`]; by default the
    /// Gaussian of pbrt and Mitsuba).
    pub filter: PixelFilter,
}

/// Rounds over the whole image before adaptive sampling starts.
pub const WARMUP_ROUNDS: u32 = 4;
/// With adaptive sampling, every this many rounds one is over the whole image.
pub const FULL_ROUND_EVERY: u32 = 8;
/// With adaptive sampling for a denoised image, every this many rounds one is over the whole
/// image: the surfaces that the filter smooths still need samples enough for its estimates.
pub const FULL_ROUND_EVERY_DENOISED: u32 = 4;
/// With adaptive sampling for a denoised image, the most samples a pixel gets in one round.
pub const MOST_SAMPLES_PER_ROUND: u32 = 16;

impl RenderOptions {
    /// `samples` samples per pixel (on average: adaptive sampling is on) over a `width` ×
    /// `height` image with `seed`, without a time limit or a noise target, to be shown without
    /// denoising.
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
            denoised: false,
            filter: PixelFilter::default(),
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
    rays: u64,
    rounds: u32,
    /// The denoiser's variance reduction per pixel, when adaptive sampling aims at a denoised
    /// image (refreshed at rounds 4, 8, 16, …).
    reduction: Option<Vec<f64>>,
    /// The radiance cache for far mirror images, filled from the rounds so far
    /// ([`crate::radiance_cache`]).
    cache: Option<RadianceCache>,
    /// The last round's paths and what they add to the film, the guides and the cache, kept
    /// from round to round: a round at 896² holds a few hundred megabytes, and fresh memory
    /// each round cost more in page faults than the bookkeeping itself.
    buffers: RoundBuffers,
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
            cache: integrator.uses_radiance_cache().then(RadianceCache::new),
            buffers: RoundBuffers::default(),
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
        let full_every = if options.denoised {
            FULL_ROUND_EVERY_DENOISED
        } else {
            FULL_ROUND_EVERY
        };
        let adaptive_round = options.adaptive
            && self.rounds >= WARMUP_ROUNDS
            && !self.rounds.is_multiple_of(full_every);
        let refresh = options.adaptive && options.denoised && self.rounds >= WARMUP_ROUNDS;
        if refresh && self.rounds.is_power_of_two() {
            let (_, reduction) =
                denoise_with_reduction(&self.film, &self.guides, &DenoiseOptions::default());
            self.reduction = Some(reduction);
        }
        let chosen = adaptive_round
            .then(|| {
                let target = match &self.reduction {
                    Some(reduction) if options.denoised => Target::Denoised(reduction),
                    _ => Target::Raw,
                };
                noisiest(&self.film, &self.taken, target)
            })
            .flatten();
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
                self.take(Some(&half(0)));
                self.take(Some(&half(1)));
            }
            None => self.take(None),
        }
        self.rounds += 1;
    }

    /// Traces the samples `chosen` ((pixel, which of its new samples), in pixel order), or one
    /// for every pixel, and adds them to the film, the guides and the radiance cache.
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
            let sample = integrator.sample_pixel_cached(&ray, Some(footprint), cache, &mut sampler);
            (pixel, sample)
        };
        // (pixel, which of its new samples) for an adaptive round; every pixel once otherwise.
        let buffers = &mut self.buffers;
        match chosen {
            Some(list) => list
                .par_iter()
                .map(|&(p, k)| trace(p, taken[p as usize] + k))
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
        // adds. Each is summed in pixel order as before.
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

/// What adaptive sampling aims at.
#[derive(Clone, Copy, Debug)]
enum Target<'a> {
    /// The image as it is.
    Raw,
    /// The image after denoising, with the denoiser's variance reduction per pixel.
    Denoised(&'a [f64]),
}

/// The samples of an adaptive round, in pixel order, as (pixel, index among its new samples):
/// see the module documentation for the score. `None` (a round over the whole image) when that
/// picks every pixel or none.
fn noisiest(film: &Film, taken: &[u32], target: Target) -> Option<Vec<(u64, u32)>> {
    let (width, height) = (film.width() as usize, film.height() as usize);
    let errors = film.display_errors(film.auto_exposure());
    let score: Vec<f64> = errors
        .iter()
        .zip(taken)
        .enumerate()
        .map(|(i, (e, &n))| match target {
            Target::Raw => e * e / f64::from(n.max(1)),
            Target::Denoised(reduction) => e * e * reduction[i].sqrt(),
        })
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
    let most = match target {
        Target::Raw => 1.0,
        Target::Denoised(_) => f64::from(MOST_SAMPLES_PER_ROUND),
    };
    // Σ ⌊score/mean⌋ over the chosen pixels is at most the pixel count: a round is never
    // longer than one over the whole image.
    let chosen: Vec<(u64, u32)> = (0..spread.len() as u64)
        .filter(|&p| spread[p as usize] >= mean && spread[p as usize] > 0.0)
        .flat_map(|p| {
            let k = (spread[p as usize] / mean).min(most) as u32;
            (0..k.max(1)).map(move |i| (p, i))
        })
        .collect();
    let distinct = chosen.iter().filter(|&&(_, i)| i == 0).count();
    (distinct > 0 && distinct < spread.len()).then_some(chosen)
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    /// A `width` × 1 film whose pixels have the given (mean, spread) over four samples.
    fn film(pixels: &[(f64, f64)]) -> Film {
        let mut film = Film::new(pixels.len() as u32, 1);
        for (x, &(mean, spread)) in pixels.iter().enumerate() {
            for k in 0..4 {
                let v = if k % 2 == 0 {
                    mean - spread
                } else {
                    mean + spread
                };
                film.add(x as u32, 0, [v; 3]);
            }
        }
        film
    }

    #[test]
    fn a_denoised_target_samples_what_the_filter_cannot_smooth() {
        // Sixteen equally noisy pixels: for the raw image every one is as noisy as the mean
        // (a round over the whole image); for a denoised one, only those that the filter
        // leaves alone, and their neighbours, several samples each.
        let film = film(&[(0.3, 0.1); 16]);
        let taken = [4; 16];
        assert_eq!(noisiest(&film, &taken, Target::Raw), None);
        let mut reduction = [1e-4; 16];
        reduction[..4].fill(1.0);
        let chosen = noisiest(&film, &taken, Target::Denoised(&reduction)).unwrap();
        // Scores: e² for pixels 0-4 (4 by its neighbour), e²/100 for the others; the mean is
        // (5 + 11/100)/16 e², so each chosen pixel gets ⌊16/5.11⌋ = 3 samples.
        let expected: Vec<(u64, u32)> = (0..5).flat_map(|p| (0..3).map(move |k| (p, k))).collect();
        assert_eq!(chosen, expected);
    }

    #[test]
    fn a_pixel_whose_samples_agree_beside_a_noisy_one_is_still_sampled() {
        // Pixel 0's four samples agree (they all missed a light image's rim, say); pixel 1's
        // disagree wildly; the rest are a little noisy. Pixel 0 is sampled for its neighbour,
        // the far pixels are not.
        let mut pixels = [(0.5, 0.01); 16];
        pixels[0] = (0.5, 0.0);
        pixels[1] = (0.5, 0.4);
        let film = film(&pixels);
        let taken = [4; 16];
        for target in [Target::Raw, Target::Denoised(&[1.0; 16])] {
            let chosen = noisiest(&film, &taken, target).unwrap();
            let pixels: Vec<u64> = chosen.iter().map(|&(p, _)| p).collect();
            assert!(pixels.contains(&0) && pixels.contains(&1), "{pixels:?}");
            assert!(pixels.iter().all(|&p| p <= 2), "{pixels:?}");
        }
    }

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

    proptest! {
        #[test]
        fn an_adaptive_round_is_never_longer_than_a_full_one(
            pixels in prop::collection::vec((0.0f64..2.0, 0.0f64..1.0), 2..40),
            reduction in prop::collection::vec(0.0f64..=1.0, 40),
            denoised in any::<bool>(),
        ) {
            let film = film(&pixels);
            let taken = vec![4; pixels.len()];
            let target = if denoised {
                Target::Denoised(&reduction[..pixels.len()])
            } else {
                Target::Raw
            };
            if let Some(chosen) = noisiest(&film, &taken, target) {
                prop_assert!(chosen.len() <= pixels.len());
                // In pixel order, each pixel's new samples numbered from 0.
                for pair in chosen.windows(2) {
                    let ((p, i), (q, j)) = (pair[0], pair[1]);
                    prop_assert!((q == p && j == i + 1) || (q > p && j == 0));
                }
                prop_assert_eq!(chosen[0].1, 0);
            }
        }
    }
}
