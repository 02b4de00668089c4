//! The stratified dimensions of a camera path: an Owen-scrambled Sobol sequence per pixel
//! (Burley 2020, "Practical Hash-based Owen Scrambling", the `sobol_burley` crate) for the
//! dimensions that matter most — the pixel position and, at each bounce, the light choice, the
//! point on the light and the scattering direction — so that the samples of a pixel cover
//! those domains evenly. [`Sampler::stratified`](super::Sampler::stratified) hands these out
//! and falls back on its random stream past them.
//!
//! Each decision has a fixed dimension: the camera ray takes the first
//! [`CAMERA_DIMENSIONS`], and every bounce the next [`BOUNCE_DIMENSIONS`], whatever the earlier
//! bounces used, so that the same dimension always serves the same decision.

use super::stream::splitmix64;

/// Dimensions of the Sobol sequence set aside for the camera ray (the position in the pixel
/// takes two; four keep every bounce's dimensions in whole sets of four).
pub const CAMERA_DIMENSIONS: u32 = 4;
/// Dimensions of the Sobol sequence set aside for each bounce of a path (light choice, point on
/// the light, scattering direction and lobe, Russian roulette).
pub const BOUNCE_DIMENSIONS: u32 = 8;
/// Samples of a pixel beyond this index are independent random numbers (the Sobol tables end).
const SOBOL_SAMPLES: u64 = 1 << 16;
/// The spacing of the f32 values of the Sobol sequence; each is jittered within it.
pub(super) const SOBOL_STEP: f64 = 1.0 / (1u64 << 23) as f64;

/// Where a stratified sampler is in its pixel's Sobol sequence.
#[derive(Clone, Copy, Debug)]
pub(super) struct SobolState {
    /// The sample's index in the sequence (< 2¹⁶).
    index: u32,
    /// The pixel's scramble.
    seed: u32,
    /// The next dimension to hand out.
    dimension: u32,
    /// The set of four dimensions last computed (`u32::MAX`: none) and its values:
    /// `sobol_burley` computes the points four dimensions at a time (SIMD), so a set is kept
    /// and its four values handed out in turn.
    cached_set: u32,
    cached_values: [f32; 4],
}

impl SobolState {
    /// The start of sample `sample_index` of pixel `pixel_index` under `seed`; `None` past the
    /// end of the Sobol tables.
    pub(super) fn new(seed: u64, pixel_index: u64, sample_index: u64) -> Option<SobolState> {
        if sample_index >= SOBOL_SAMPLES {
            return None;
        }
        let scramble = splitmix64(splitmix64(seed ^ 0x5851_F42D_4C95_7F2D) ^ pixel_index);
        Some(SobolState {
            index: sample_index as u32,
            seed: (scramble >> 32) as u32,
            dimension: 0,
            cached_set: u32::MAX,
            cached_values: [0.0; 4],
        })
    }

    /// Moves to the first dimension of bounce `bounce` (0 for the first surface a camera path
    /// scatters at).
    pub(super) fn start_bounce(&mut self, bounce: u32) {
        self.dimension = CAMERA_DIMENSIONS.saturating_add(bounce.saturating_mul(BOUNCE_DIMENSIONS));
    }

    /// The value of the next dimension, in [0, 1) at f32 resolution; `None` once the tables'
    /// dimensions are used up.
    pub(super) fn next_value(&mut self) -> Option<f64> {
        if self.dimension >= sobol_burley::NUM_DIMENSIONS {
            return None;
        }
        let (set, lane) = (self.dimension / 4, self.dimension % 4);
        if set != self.cached_set {
            self.cached_values = sobol_burley::sample_4d(self.index, set, self.seed);
            self.cached_set = set;
        }
        self.dimension += 1;
        Some(f64::from(self.cached_values[lane as usize]))
    }
}
