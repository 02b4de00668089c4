//! Random numbers and sampling helpers for the path tracer.
//!
//! - [`Sampler`]: a deterministic random stream per (seed, pixel, sample), so that an image
//!   depends only on the seed, never on how the work was scheduled across threads. Camera
//!   paths use its stratified form ([`Sampler::stratified`]): an Owen-scrambled Sobol sequence
//!   per pixel (Burley 2020, the `sobol_burley` crate) for the dimensions that matter most — the
//!   pixel position and, at each bounce, the light choice, the point on the light and the
//!   scattering direction — so that the samples of a pixel cover those domains evenly.
//! - Warping functions from the unit square to directions and points, each with its density:
//!   [`cosine_hemisphere`], [`uniform_sphere`], [`uniform_cone`], [`uniform_disk_concentric`].
//! - [`power_heuristic`], the multiple-importance-sampling weight (β = 2).
//! - [`Distribution1d`]: picking one of N items with probability ∝ its weight.
//! - [`Frame`] and [`frame_from_normal`]: orthonormal shading frames (Duff et al. 2017).
//!
//! Local frames have the normal along +z; the warping functions take uniforms `u` in [0, 1)².

use std::f64::consts::{FRAC_PI_4, PI};

use glam::DVec3;
use rand::Rng;
use rand_pcg::Pcg64Mcg;

/// The SplitMix64 step: adds the golden-ratio increment and applies the finalizer of
/// Steele, Lea & Flood (2014). A bijection of `u64` with good avalanche.
fn splitmix64(x: u64) -> u64 {
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
    sobol: Option<Sobol>,
}

/// Where a stratified sampler is in its pixel's Sobol sequence.
#[derive(Clone, Copy, Debug)]
struct Sobol {
    /// The sample's index in the sequence (< 2¹⁶).
    index: u32,
    /// The pixel's scramble.
    seed: u32,
    /// The next dimension to hand out.
    dimension: u32,
    /// The set of four dimensions last computed (`u32::MAX`: none) and its values: the Sobol
    /// points are computed four dimensions at a time (SIMD in `sobol_burley`), about as fast as one.
    set: u32,
    values: [f32; 4],
}

/// Dimensions of the Sobol sequence set aside for the camera ray (the position in the pixel
/// takes two; four keep every bounce's dimensions in whole sets of four).
pub const CAMERA_DIMENSIONS: u32 = 4;
/// Dimensions of the Sobol sequence set aside for each bounce of a path (light choice, point on
/// the light, scattering direction and lobe, Russian roulette).
pub const BOUNCE_DIMENSIONS: u32 = 8;
/// Samples of a pixel beyond this index are independent random numbers (the Sobol tables end).
const SOBOL_SAMPLES: u64 = 1 << 16;
/// The spacing of the f32 values of the Sobol sequence; each is jittered within it.
const SOBOL_STEP: f64 = 1.0 / (1u64 << 23) as f64;

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
    /// the first [`CAMERA_DIMENSIONS`] numbers, and [`BOUNCE_DIMENSIONS`] per bounce after
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
        if sample_index < SOBOL_SAMPLES {
            let scramble = splitmix64(splitmix64(seed ^ 0x5851_F42D_4C95_7F2D) ^ pixel_index);
            sampler.sobol = Some(Sobol {
                index: sample_index as u32,
                seed: (scramble >> 32) as u32,
                dimension: 0,
                set: u32::MAX,
                values: [0.0; 4],
            });
        }
        sampler
    }

    /// Moves a stratified sampler to the dimensions of bounce `bounce` (0 for the first surface
    /// a camera path scatters at), so that every sample draws the same dimension for the same
    /// decision however many numbers its earlier bounces used. No effect on a random sampler.
    pub fn start_bounce(&mut self, bounce: u32) {
        if let Some(sobol) = &mut self.sobol {
            sobol.dimension =
                CAMERA_DIMENSIONS.saturating_add(bounce.saturating_mul(BOUNCE_DIMENSIONS));
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
        if let Some(sobol) = &mut self.sobol
            && sobol.dimension < sobol_burley::NUM_DIMENSIONS
        {
            let (set, lane) = (sobol.dimension / 4, sobol.dimension % 4);
            if set != sobol.set {
                sobol.values = sobol_burley::sample_4d(sobol.index, set, sobol.seed);
                sobol.set = set;
            }
            sobol.dimension += 1;
            let value = f64::from(sobol.values[lane as usize]);
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

/// A point of the unit disk from `u` in [0, 1)², uniform in area (density 1/π), by Shirley and
/// Chiu's concentric map, which keeps strata compact and has low distortion.
///
/// ```
/// use orbifold_render::sampler::uniform_disk_concentric;
///
/// let (x, y) = uniform_disk_concentric((0.9, 0.3));
/// assert!(x * x + y * y <= 1.0);
/// assert_eq!(uniform_disk_concentric((0.5, 0.5)), (0.0, 0.0));
/// ```
pub fn uniform_disk_concentric(u: (f64, f64)) -> (f64, f64) {
    let a = 2.0 * u.0 - 1.0;
    let b = 2.0 * u.1 - 1.0;
    if a == 0.0 && b == 0.0 {
        return (0.0, 0.0);
    }
    let (r, theta) = if a.abs() > b.abs() {
        (a, FRAC_PI_4 * (b / a))
    } else {
        (b, 2.0 * FRAC_PI_4 - FRAC_PI_4 * (a / b))
    };
    (r * theta.cos(), r * theta.sin())
}

/// A unit direction of the upper hemisphere (z ≥ 0) from `u` in [0, 1)², with density
/// [`cosine_hemisphere_pdf`]`(z)` = z/π in solid angle (Malley's method on the concentric disk).
///
/// ```
/// use orbifold_render::sampler::cosine_hemisphere;
///
/// let w = cosine_hemisphere((0.25, 0.75));
/// assert!((w.length() - 1.0).abs() < 1e-12 && w.z >= 0.0);
/// ```
pub fn cosine_hemisphere(u: (f64, f64)) -> DVec3 {
    let (x, y) = uniform_disk_concentric(u);
    let z = (1.0 - x * x - y * y).max(0.0).sqrt();
    DVec3::new(x, y, z)
}

/// The solid-angle density of [`cosine_hemisphere`] at a direction with z component `cos_theta`:
/// `max(cos_theta, 0)/π`.
///
/// ```
/// use orbifold_render::sampler::cosine_hemisphere_pdf;
///
/// assert_eq!(cosine_hemisphere_pdf(-0.5), 0.0);
/// assert!((cosine_hemisphere_pdf(1.0) - std::f64::consts::FRAC_1_PI).abs() < 1e-15);
/// ```
pub fn cosine_hemisphere_pdf(cos_theta: f64) -> f64 {
    cos_theta.max(0.0) / PI
}

/// A uniform unit direction of the whole sphere from `u` in [0, 1)²; density 1/(4π)
/// ([`uniform_sphere_pdf`]).
///
/// ```
/// use orbifold_render::sampler::uniform_sphere;
///
/// let w = uniform_sphere((0.1, 0.6));
/// assert!((w.length() - 1.0).abs() < 1e-12);
/// ```
pub fn uniform_sphere(u: (f64, f64)) -> DVec3 {
    let z = 1.0 - 2.0 * u.0;
    let r = (1.0 - z * z).max(0.0).sqrt();
    let phi = 2.0 * PI * u.1;
    DVec3::new(r * phi.cos(), r * phi.sin(), z)
}

/// The solid-angle density of [`uniform_sphere`]: 1/(4π).
///
/// ```
/// use orbifold_render::sampler::uniform_sphere_pdf;
///
/// assert!((uniform_sphere_pdf() * 4.0 * std::f64::consts::PI - 1.0).abs() < 1e-15);
/// ```
pub fn uniform_sphere_pdf() -> f64 {
    1.0 / (4.0 * PI)
}

/// A unit direction uniform in the cone of directions around +z whose z component is at least
/// `cos_max` (in [−1, 1]); density [`uniform_cone_pdf`]`(cos_max)` = 1/(2π(1 − cos_max)).
///
/// ```
/// use orbifold_render::sampler::uniform_cone;
///
/// let w = uniform_cone((0.3, 0.8), 0.9);
/// assert!((w.length() - 1.0).abs() < 1e-12 && w.z >= 0.9 - 1e-12);
/// ```
pub fn uniform_cone(u: (f64, f64), cos_max: f64) -> DVec3 {
    let cos_theta = (1.0 - u.0) + u.0 * cos_max;
    let sin_theta = (1.0 - cos_theta * cos_theta).max(0.0).sqrt();
    let phi = 2.0 * PI * u.1;
    DVec3::new(sin_theta * phi.cos(), sin_theta * phi.sin(), cos_theta)
}

/// The solid-angle density of [`uniform_cone`]: 1/(2π(1 − cos_max)); infinite for a
/// degenerate cone (`cos_max` = 1).
///
/// ```
/// use orbifold_render::sampler::{uniform_cone_pdf, uniform_sphere_pdf};
///
/// assert!((uniform_cone_pdf(-1.0) - uniform_sphere_pdf()).abs() < 1e-15);
/// ```
pub fn uniform_cone_pdf(cos_max: f64) -> f64 {
    1.0 / (2.0 * PI * (1.0 - cos_max))
}

/// The power heuristic (β = 2) of Veach for multiple importance sampling: the weight of a sample
/// drawn `nf` times from a strategy with density `f_pdf`, against `ng` samples of a strategy with
/// density `g_pdf`: (nf·f_pdf)² / ((nf·f_pdf)² + (ng·g_pdf)²).
///
/// Robust at the edges: 0 when `f_pdf` is 0 (or anything is NaN); otherwise 1 when `g_pdf` is
/// 0; an infinite density (a delta strategy) takes all the weight (1/2 if both are infinite);
/// no overflow for huge finite densities. The result is always in [0, 1].
///
/// ```
/// use orbifold_render::sampler::power_heuristic;
///
/// assert_eq!(power_heuristic(1.0, 2.0, 1.0, 2.0), 0.5);
/// assert_eq!(power_heuristic(1.0, 3.0, 1.0, 0.0), 1.0);
/// assert_eq!(power_heuristic(1.0, 0.0, 1.0, 3.0), 0.0);
/// assert_eq!(power_heuristic(1.0, f64::INFINITY, 1.0, 3.0), 1.0);
/// ```
pub fn power_heuristic(nf: f64, f_pdf: f64, ng: f64, g_pdf: f64) -> f64 {
    let f = (nf * f_pdf).abs();
    let g = (ng * g_pdf).abs();
    if f.is_nan() || g.is_nan() || f == 0.0 {
        return 0.0;
    }
    if g == 0.0 {
        return 1.0;
    }
    if f.is_infinite() && g.is_infinite() {
        return 0.5;
    }
    // (g/f) is in [0, ∞]; 1/(1 + r²) never overflows into NaN.
    let r = g / f;
    1.0 / (1.0 + r * r)
}

/// A piecewise-constant distribution over `0..len()`: picks item i with probability
/// `weights[i] / Σ weights` by inverting the cumulative distribution.
///
/// ```
/// use orbifold_render::sampler::Distribution1d;
///
/// let d = Distribution1d::new(&[1.0, 0.0, 3.0]).unwrap();
/// assert_eq!(d.sample(0.1), (0, 0.25));
/// assert_eq!(d.sample(0.5), (2, 0.75));
/// assert_eq!(d.pmf(1), 0.0);
/// ```
#[derive(Clone, Debug)]
pub struct Distribution1d {
    /// The cumulative distribution: `cdf[0] = 0`, `cdf[len] = 1`, nondecreasing.
    cdf: Vec<f64>,
    /// The probability of each item.
    pmf: Vec<f64>,
    /// Σ weights.
    total: f64,
    /// The last item of nonzero weight (what u ≥ 1 maps to).
    last: usize,
    /// A guide table (Chen and Asau's cutpoints) over M = 2ᵏ equal intervals of u: entry j is
    /// the first index whose cdf exceeds j/M, so that a `u` in [j/M, (j + 1)/M) is looked for
    /// only between entries j and j + 1 — a step or two instead of a binary search over all
    /// the cdf, a chain of a dozen reads each waiting on the one before for a room's thousands
    /// of light images. (M is a power of two so that ⌊u·M⌋ = j is exact.)
    guide: Vec<u32>,
}

/// The guide table of a cdf ([`Distribution1d`]): for j = 0..=M, the first index whose cdf
/// exceeds j/M, with M the power of two at or above the number of items (at most 2²⁰).
fn guide_table(cdf: &[f64]) -> Vec<u32> {
    let intervals = (cdf.len().saturating_sub(1))
        .next_power_of_two()
        .min(1 << 20);
    let mut guide = Vec::with_capacity(intervals + 1);
    let mut first = 0;
    for j in 0..=intervals {
        let x = j as f64 / intervals as f64;
        while first < cdf.len() && cdf[first] <= x {
            first += 1;
        }
        guide.push(first as u32);
    }
    guide
}

impl Distribution1d {
    /// The distribution ∝ `weights`; `None` when there are no weights, any is negative or not
    /// finite (NaN, ±∞), the sum overflows, or all are zero.
    ///
    /// ```
    /// use orbifold_render::sampler::Distribution1d;
    ///
    /// assert!(Distribution1d::new(&[0.0, 0.0]).is_none());
    /// assert!(Distribution1d::new(&[1.0, -1.0]).is_none());
    /// assert!(Distribution1d::new(&[1.0, f64::NAN]).is_none());
    /// assert!(Distribution1d::new(&[]).is_none());
    /// assert!(Distribution1d::new(&[2.0]).is_some());
    /// ```
    pub fn new(weights: &[f64]) -> Option<Self> {
        if weights.iter().any(|w| !w.is_finite() || *w < 0.0) {
            return None;
        }
        let total: f64 = weights.iter().sum();
        if !(total.is_finite() && total > 0.0) {
            return None;
        }
        let pmf: Vec<f64> = weights.iter().map(|w| w / total).collect();
        let mut cdf = Vec::with_capacity(weights.len() + 1);
        let mut running = 0.0;
        cdf.push(0.0);
        for w in weights {
            running += w;
            cdf.push(running / total);
        }
        let last = weights.iter().rposition(|w| *w > 0.0)?;
        // Items after the last positive one end exactly at 1, so none can be reached.
        for c in &mut cdf[last + 1..] {
            *c = 1.0;
        }
        let guide = guide_table(&cdf);
        Some(Distribution1d {
            cdf,
            pmf,
            total,
            last,
            guide,
        })
    }

    /// The item for the uniform `u` in [0, 1), and its probability. Items of zero weight are
    /// never returned; `u` outside [0, 1) (or NaN) is clamped.
    ///
    /// ```
    /// use orbifold_render::sampler::Distribution1d;
    ///
    /// let d = Distribution1d::new(&[0.0, 1.0, 1.0, 0.0]).unwrap();
    /// assert_eq!(d.sample(0.0), (1, 0.5));
    /// assert_eq!(d.sample(0.999), (2, 0.5));
    /// assert_eq!(d.sample(1.0), (2, 0.5));
    /// ```
    pub fn sample(&self, u: f64) -> (usize, f64) {
        let u = if u.is_nan() { 0.0 } else { u.max(0.0) };
        // The first index whose cdf exceeds u is one past the item: cdf[i] ≤ u < cdf[i + 1],
        // an interval that is empty for items of zero weight.
        let i = self.first_above(u).saturating_sub(1).min(self.last);
        (i, self.pmf[i])
    }

    /// The first index whose cdf exceeds `u` (≥ 0), as `partition_point` over the whole cdf
    /// finds it, searched between the guide table's two entries around `u`.
    #[inline]
    fn first_above(&self, u: f64) -> usize {
        let intervals = self.guide.len() - 1;
        // Exact: M is a power of two. (The cast saturates; u ≥ 1 goes to the full search.)
        let j = (u * intervals as f64) as usize;
        match (self.guide.get(j), self.guide.get(j + 1)) {
            (Some(&lo), Some(&hi)) => {
                let (lo, hi) = (lo as usize, hi as usize);
                lo + self.cdf[lo..hi].partition_point(|c| *c <= u)
            }
            _ => self.cdf.partition_point(|c| *c <= u),
        }
    }

    /// The probability of item `i` (0 for indices out of range).
    ///
    /// ```
    /// use orbifold_render::sampler::Distribution1d;
    ///
    /// let d = Distribution1d::new(&[1.0, 3.0]).unwrap();
    /// assert_eq!(d.pmf(1), 0.75);
    /// assert_eq!(d.pmf(5), 0.0);
    /// ```
    pub fn pmf(&self, i: usize) -> f64 {
        self.pmf.get(i).copied().unwrap_or(0.0)
    }

    /// The number of items (including those of zero weight).
    ///
    /// ```
    /// use orbifold_render::sampler::Distribution1d;
    ///
    /// assert_eq!(Distribution1d::new(&[1.0, 0.0]).unwrap().len(), 2);
    /// ```
    pub fn len(&self) -> usize {
        self.pmf.len()
    }

    /// Always `false`: a distribution has at least one item of positive weight.
    ///
    /// ```
    /// use orbifold_render::sampler::Distribution1d;
    ///
    /// assert!(!Distribution1d::new(&[1.0]).unwrap().is_empty());
    /// ```
    pub fn is_empty(&self) -> bool {
        self.pmf.is_empty()
    }

    /// The sum of the weights.
    ///
    /// ```
    /// use orbifold_render::sampler::Distribution1d;
    ///
    /// assert_eq!(Distribution1d::new(&[1.0, 2.5]).unwrap().total(), 3.5);
    /// ```
    pub fn total(&self) -> f64 {
        self.total
    }
}

/// A tangent and a bitangent completing the unit normal `n` to a right-handed orthonormal basis
/// (tangent × bitangent = n), by the branchless method of Duff et al., "Building an orthonormal
/// basis, revisited" (JCGT 2017). Continuous except where n.z changes sign.
///
/// ```
/// use glam::DVec3;
/// use orbifold_render::sampler::frame_from_normal;
///
/// let n = DVec3::new(1.0, 2.0, -2.0) / 3.0;
/// let (t, b) = frame_from_normal(n);
/// assert!(t.dot(n).abs() < 1e-12 && b.dot(n).abs() < 1e-12 && t.dot(b).abs() < 1e-12);
/// assert!((t.cross(b) - n).length() < 1e-12);
/// ```
pub fn frame_from_normal(n: DVec3) -> (DVec3, DVec3) {
    let sign = 1.0_f64.copysign(n.z);
    let a = -1.0 / (sign + n.z);
    let b = n.x * n.y * a;
    let tangent = DVec3::new(1.0 + sign * n.x * n.x * a, sign * b, -sign * n.x);
    let bitangent = DVec3::new(b, sign + n.y * n.y * a, -n.y);
    (tangent, bitangent)
}

/// The coordinates of the world vector `v` in the frame (tangent `t`, bitangent `b`, normal
/// `n`): (v·t, v·b, v·n).
///
/// ```
/// use glam::DVec3;
/// use orbifold_render::sampler::{frame_from_normal, to_local};
///
/// let n = DVec3::Y;
/// let (t, b) = frame_from_normal(n);
/// assert!((to_local(n, t, b, n) - DVec3::Z).length() < 1e-12);
/// ```
pub fn to_local(n: DVec3, t: DVec3, b: DVec3, v: DVec3) -> DVec3 {
    DVec3::new(v.dot(t), v.dot(b), v.dot(n))
}

/// The world vector with coordinates `v` in the frame (tangent `t`, bitangent `b`, normal `n`):
/// v.x·t + v.y·b + v.z·n.
///
/// ```
/// use glam::DVec3;
/// use orbifold_render::sampler::{frame_from_normal, to_world};
///
/// let n = DVec3::Y;
/// let (t, b) = frame_from_normal(n);
/// assert!((to_world(n, t, b, DVec3::Z) - n).length() < 1e-12);
/// ```
pub fn to_world(n: DVec3, t: DVec3, b: DVec3, v: DVec3) -> DVec3 {
    v.x * t + v.y * b + v.z * n
}

/// A right-handed orthonormal shading frame: local x = tangent, y = bitangent, z = normal.
///
/// ```
/// use glam::DVec3;
/// use orbifold_render::sampler::Frame;
///
/// let f = Frame::from_normal(DVec3::X);
/// let v = DVec3::new(0.3, -0.4, 0.5);
/// assert!((f.to_world(f.to_local(v)) - v).length() < 1e-12);
/// assert!((f.to_local(DVec3::X) - DVec3::Z).length() < 1e-12);
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Frame {
    tangent: DVec3,
    bitangent: DVec3,
    normal: DVec3,
}

impl Frame {
    /// The frame around the unit normal `n` (see [`frame_from_normal`]).
    ///
    /// ```
    /// use glam::DVec3;
    /// use orbifold_render::sampler::Frame;
    ///
    /// let f = Frame::from_normal(DVec3::Z);
    /// assert_eq!((f.tangent(), f.bitangent(), f.normal()), (DVec3::X, DVec3::Y, DVec3::Z));
    /// ```
    pub fn from_normal(n: DVec3) -> Frame {
        let (tangent, bitangent) = frame_from_normal(n);
        Frame {
            tangent,
            bitangent,
            normal: n,
        }
    }

    /// The local coordinates (v·t, v·b, v·n) of the world vector `v`.
    ///
    /// ```
    /// use glam::DVec3;
    /// use orbifold_render::sampler::Frame;
    ///
    /// let f = Frame::from_normal(DVec3::NEG_Z);
    /// assert!((f.to_local(DVec3::NEG_Z) - DVec3::Z).length() < 1e-12);
    /// ```
    pub fn to_local(&self, v: DVec3) -> DVec3 {
        to_local(self.normal, self.tangent, self.bitangent, v)
    }

    /// The world vector of the local coordinates `v`.
    ///
    /// ```
    /// use glam::DVec3;
    /// use orbifold_render::sampler::Frame;
    ///
    /// let f = Frame::from_normal(DVec3::NEG_Z);
    /// assert!((f.to_world(DVec3::Z) - DVec3::NEG_Z).length() < 1e-12);
    /// ```
    pub fn to_world(&self, v: DVec3) -> DVec3 {
        to_world(self.normal, self.tangent, self.bitangent, v)
    }

    /// The normal (local +z).
    ///
    /// ```
    /// use glam::DVec3;
    /// use orbifold_render::sampler::Frame;
    ///
    /// assert_eq!(Frame::from_normal(DVec3::Y).normal(), DVec3::Y);
    /// ```
    pub fn normal(&self) -> DVec3 {
        self.normal
    }

    /// The tangent (local +x).
    ///
    /// ```
    /// use glam::DVec3;
    /// use orbifold_render::sampler::Frame;
    ///
    /// let f = Frame::from_normal(DVec3::Y);
    /// assert!(f.tangent().dot(DVec3::Y).abs() < 1e-12);
    /// ```
    pub fn tangent(&self) -> DVec3 {
        self.tangent
    }

    /// The bitangent (local +y) = normal × tangent.
    ///
    /// ```
    /// use glam::DVec3;
    /// use orbifold_render::sampler::Frame;
    ///
    /// let f = Frame::from_normal(DVec3::Y);
    /// assert!((f.normal().cross(f.tangent()) - f.bitangent()).length() < 1e-12);
    /// ```
    pub fn bitangent(&self) -> DVec3 {
        self.bitangent
    }
}
