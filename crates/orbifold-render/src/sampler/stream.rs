//! The per-pixel random stream of the path tracer ([`Sampler`]): a deterministic stream for
//! each (seed, pixel, sample), so that an image depends only on the seed, never on how the
//! work was scheduled across threads. Its stratified form takes the dimensions that matter
//! most from the pixel's Sobol sequence ([`super::sobol`]) and everything else from the
//! stream.

use rand::Rng;
use rand_pcg::Pcg64Mcg;

use super::sobol::{SOBOL_STEP, SobolState};

/// The SplitMix64 step: adds the golden-ratio increment and applies the finalizer of
/// Steele, Lea & Flood (2014). A bijection of `u64` with good avalanche.
pub(super) fn splitmix64(x: u64) -> u64 {
    let mut z = x.wrapping_add(0x9E37_79B9_7F4A_7C15);
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^ (z >> 31)
}

/// A deterministic random stream for one sample of one pixel.
///
/// The generator is a 128-bit multiplicative PCG ([`Pcg64Mcg`]) whose state is a SplitMix64
/// hash of `(seed, pixel_index, sample_index)`, chained so that every input changes every
/// bit of the state. Streams of different pixels or samples are therefore decorrelated, and a
/// render is reproducible for a given seed whatever the thread scheduling.
///
/// ```
/// use orbifold_render::sampler::Sampler;
///
/// let mut a = Sampler::new(7, 42, 0);
/// let mut b = Sampler::new(7, 42, 0);
/// let x = a.next_f64();
/// assert_eq!(x, b.next_f64());
/// assert!((0.0..1.0).contains(&x));
/// ```
#[derive(Clone, Debug)]
pub struct Sampler {
    rng: Pcg64Mcg,
    /// Where a stratified sampler is in its pixel's Sobol sequence (`None`: not stratified,
    /// or past the end of the tables).
    sobol: Option<SobolState>,
}

impl Sampler {
    /// The stream for sample `sample_index` of pixel `pixel_index` under `seed`.
    ///
    /// ```
    /// use orbifold_render::sampler::Sampler;
    ///
    /// let mut a = Sampler::new(1, 0, 0);
    /// let mut b = Sampler::new(1, 1, 0);
    /// assert_ne!(a.next_u64(), b.next_u64());
    /// ```
    pub fn new(seed: u64, pixel_index: u64, sample_index: u64) -> Sampler {
        let k = splitmix64(splitmix64(splitmix64(seed) ^ pixel_index) ^ sample_index);
        let hi = splitmix64(k ^ 0x6A09_E667_F3BC_C908);
        let lo = splitmix64(k ^ 0xBB67_AE85_84CA_A73B);
        // `Pcg64Mcg::new` forces the state odd, as a multiplicative generator needs.
        Sampler {
            rng: Pcg64Mcg::new((u128::from(hi) << 64) | u128::from(lo)),
            sobol: None,
        }
    }

    /// The stream for sample `sample_index` of pixel `pixel_index` under `seed`, stratified:
    /// the first [`CAMERA_DIMENSIONS`](super::CAMERA_DIMENSIONS) numbers, and
    /// [`BOUNCE_DIMENSIONS`](super::BOUNCE_DIMENSIONS) per bounce after
    /// [`Sampler::start_bounce`], come from the pixel's Owen-scrambled Sobol sequence (jittered
    /// below its f32 resolution by the random stream), so that the first N samples of a pixel
    /// are spread evenly over those dimensions whatever N. Beyond 2¹⁶ samples, or 256
    /// dimensions, the numbers are independent random ones.
    ///
    /// ```
    /// use orbifold_render::sampler::Sampler;
    ///
    /// // The first 16 samples of a pixel put one camera offset in each of 4×4 strata.
    /// let mut strata = [false; 16];
    /// for k in 0..16 {
    ///     let (x, y) = Sampler::stratified(5, 77, k).next_2d();
    ///     strata[(4.0 * y) as usize * 4 + (4.0 * x) as usize] = true;
    /// }
    /// assert!(strata.iter().all(|&s| s));
    /// ```
    pub fn stratified(seed: u64, pixel_index: u64, sample_index: u64) -> Sampler {
        let mut sampler = Sampler::new(seed, pixel_index, sample_index);
        sampler.sobol = SobolState::new(seed, pixel_index, sample_index);
        sampler
    }

    /// Moves a stratified sampler to the dimensions of bounce `bounce` (0 for the first surface
    /// a camera path scatters at), so that every sample draws the same dimension for the same
    /// decision however many numbers its earlier bounces used. No effect on a random sampler.
    pub fn start_bounce(&mut self, bounce: u32) {
        if let Some(sobol) = &mut self.sobol {
            sobol.start_bounce(bounce);
        }
    }

    /// A uniform number in [0, 1) from the random stream alone, never stratified: for decisions
    /// taken a varying number of times (Russian roulette along mirror chains), which would
    /// otherwise shift the dimensions of the decisions after them.
    pub fn next_independent_f64(&mut self) -> f64 {
        const SCALE: f64 = 1.0 / (1u64 << 53) as f64;
        (self.next_u64() >> 11) as f64 * SCALE
    }

    /// The next 64 uniformly random bits.
    ///
    /// ```
    /// use orbifold_render::sampler::Sampler;
    ///
    /// let mut s = Sampler::new(0, 0, 0);
    /// let _bits: u64 = s.next_u64();
    /// ```
    pub fn next_u64(&mut self) -> u64 {
        self.rng.next_u64()
    }

    /// A uniform number in [0, 1) with 53 random bits (every multiple of 2⁻⁵³ equally likely).
    ///
    /// ```
    /// use orbifold_render::sampler::Sampler;
    ///
    /// let mut s = Sampler::new(3, 1, 2);
    /// assert!((0..1000).all(|_| (0.0..1.0).contains(&s.next_f64())));
    /// ```
    pub fn next_f64(&mut self) -> f64 {
        if let Some(value) = self.sobol.as_mut().and_then(SobolState::next_value) {
            let jitter = self.next_independent_f64() * SOBOL_STEP;
            return (value + jitter).min(1.0 - f64::EPSILON / 2.0);
        }
        self.next_independent_f64()
    }

    /// Two uniforms in [0, 1), drawn in order (first, second).
    ///
    /// ```
    /// use orbifold_render::sampler::Sampler;
    ///
    /// let mut s = Sampler::new(3, 1, 2);
    /// let (a, b) = s.next_2d();
    /// assert!((0.0..1.0).contains(&a) && (0.0..1.0).contains(&b));
    /// ```
    pub fn next_2d(&mut self) -> (f64, f64) {
        let a = self.next_f64();
        let b = self.next_f64();
        (a, b)
    }

    /// A uniform integer in `0..n`, without bias (Lemire's multiply-and-reject method).
    ///
    /// # Panics
    ///
    /// If `n` is 0.
    ///
    /// ```
    /// use orbifold_render::sampler::Sampler;
    ///
    /// let mut s = Sampler::new(9, 9, 9);
    /// assert!((0..1000).all(|_| s.next_u32_below(6) < 6));
    /// assert_eq!(s.next_u32_below(1), 0);
    /// ```
    pub fn next_u32_below(&mut self, n: u32) -> u32 {
        assert!(n > 0, "next_u32_below needs n > 0");
        let mut m = u64::from(self.rng.next_u32()) * u64::from(n);
        if (m as u32) < n {
            // Reject the low products that would over-represent some outcomes.
            let threshold = n.wrapping_neg() % n;
            while (m as u32) < threshold {
                m = u64::from(self.rng.next_u32()) * u64::from(n);
            }
        }
        (m >> 32) as u32
    }
}
