//! What to render: the image's size, samples, seed, when to stop, adaptive sampling and the
//! pixel filter.

use std::time::Duration;

use crate::film::PixelFilter;

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
    /// Stop once the film's relative noise ([`Film::relative_noise`](crate::film::Film::relative_noise)) is at most this (checked
    /// after every round from the second on).
    pub noise_target: Option<f64>,
    /// Spend the samples where the image is noisiest, without bias (the adaptive sampler of
    /// [`crate::render`]); without it, every pixel gets exactly `samples` samples.
    pub adaptive: bool,
    /// The image will be denoised ([`crate::denoise`]): adaptive sampling aims at the noise the
    /// denoiser leaves rather than at the raw image's (see the module documentation).
    pub denoised: bool,
    /// How each sample counts for the pixels around it ([`PixelFilter`]; by default the
    /// Gaussian of pbrt and Mitsuba).
    pub filter: PixelFilter,
}

/// Rounds over the whole image before adaptive sampling starts (its first stage).
pub const WARMUP_ROUNDS: u32 = 4;
/// With adaptive sampling, the most samples a pixel gets in a stage, in multiples of the mean.
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
