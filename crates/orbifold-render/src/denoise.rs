//! An edge-avoiding à-trous wavelet denoiser guided by what each pixel saw first (its albedo,
//! normal and geodesic depth through the mirrors) and by its own variance (Dammertz et al.
//! 2010, "Edge-avoiding À-Trous Wavelet Transform for fast Global Illumination Filtering";
//! the variance guide as in Schied et al. 2017, SVGF).
//!
//! The image is divided by the albedo first, so that the filter smooths lighting and not
//! texture (the checkerboard floor, marble veins), and multiplied back at the end. Five passes
//! of a 5×5 B3-spline kernel with holes (steps 1, 2, 4, 8, 16: a 61×61 footprint) weigh each
//! neighbour by how alike the two pixels' normals and depths are (and albedos, if asked:
//! [`DenoiseOptions::sigma_albedo`]), and by how far its
//! lighting is from the pixel's in units of the standard error around it (the variance blurred
//! over 3×3 pixels) — so that edges, mirror-image boundaries and well-converged detail survive
//! while noise is averaged away. A pixel whose paths disagree on what they saw (its mean
//! normal is short, its depths spread: sub-pixel detail such as the crowd of far mirror images
//! at a hyperbolic room's horizon) trusts its guides only as much as its paths agree — its
//! guides are noise too — and is smoothed by its lighting tolerance.
//!
//! The light a pixel saw directly (lights' images through the mirrors, [`FirstHit::emitted`]) is
//! filtered apart, in the image's own units, and only between pixels whose paths disagree on what
//! they saw: each neighbour weighs (1 − coherence) of both pixels, and a pixel whose coherence is
//! above 0.95 keeps its own. Filtered with the rest, a small bright light image lent
//! the ceiling around it its brightness (a halo) and its noise (the partial coverage of its edge
//! pixels), and the pixels beside it took its variance as their own tolerance; left unfiltered
//! everywhere, the band above a hyperbolic room's horizon, where the far light images shrink
//! below a pixel and merge, kept all its noise. The rest is
//! filtered in two parts under the same guides, each with its own variance and so its own
//! lighting tolerance (as SVGF filters direct and indirect light apart): the first surface's
//! light sample ([`FirstHit::direct`]; smooth and well sampled where a light image is near, such
//! as the glow a light throws on a ceiling), and the light of longer paths, far noisier, whose
//! tolerance would otherwise flatten that glow. The second part also listens less to the
//! normals: light that arrives after a bounce comes from all round and turns slowly with the
//! normal, so on a bumpy mesh it is averaged over neighbours whose normals differ by tens of
//! degrees ([`DenoiseOptions::sigma_normal_rest`]).
//!
//! Denoising trades noise for bias (blur where the guides cannot tell surfaces apart); the
//! renderer's tests check its estimates before any filtering.

use glam::DVec3;
use rayon::prelude::*;

use crate::film::{Film, Splat, luminance};
use crate::filter::PixelFilter;
use crate::integrator::FirstHit;
use crate::light::Rgb;

/// The per-pixel means of what camera paths saw first, and the parts of their radiance that the
/// denoiser treats apart: the light seen directly, and the mean and variance of the first
/// surface's light sample and of the rest. The means are weighted by the film's reconstruction
/// filter as the film's are ([`Guides::splat`]), so that the parts add up to the film's pixel.
#[derive(Clone, Debug)]
pub struct Guides {
    width: u32,
    height: u32,
    /// Each pixel's own paths.
    own: Vec<GuideSums>,
    /// The same under the reconstruction filter (as [`Film`]'s): what the denoiser reads.
    pixels: Vec<GuideSums>,
    filter: PixelFilter,
}

/// What one pixel has summed of the paths that count for it, each times its weight.
#[derive(Clone, Copy, Debug, Default)]
struct GuideSums {
    albedo: Rgb,
    normal: DVec3,
    depth: f64,
    depth2: f64,
    /// Σ of the light seen directly.
    emitted: Rgb,
    /// Σ of the first surface's light sample.
    direct: Rgb,
    /// The luminance statistics of the light seen directly (which the filter leaves as it is:
    /// its noise stays in the denoised image), of the light sample and of the rest of the
    /// reflected light.
    emitted_stats: Welford,
    direct_stats: Welford,
    rest_stats: Welford,
    /// Σ weight and Σ weight².
    weight: f64,
    weight2: f64,
}

/// What a path adds to the guides, worked out once for all the pixels it counts for.
#[derive(Clone, Copy, Debug)]
struct GuidePath<'a> {
    first: &'a FirstHit,
    /// The luminance of the light seen directly, of the light sample, and of the rest of the
    /// reflected light.
    emitted: f64,
    direct: f64,
    rest: f64,
}

impl GuidePath<'_> {
    /// The path, or `None` if anything it carries is not finite.
    fn new(first: &FirstHit, radiance: Rgb) -> Option<GuidePath<'_>> {
        let finite = first.albedo.iter().all(|a| a.is_finite())
            && first.normal.is_finite()
            && first.depth.is_finite()
            && (first.emitted.iter())
                .chain(&first.direct)
                .chain(&radiance)
                .all(|v| v.is_finite());
        let (emitted, direct) = (luminance(first.emitted), luminance(first.direct));
        finite.then(|| GuidePath {
            first,
            emitted,
            direct,
            rest: luminance(radiance) - emitted - direct,
        })
    }
}

impl GuideSums {
    /// Counts a path with weight `w` > 0.
    fn add(&mut self, path: &GuidePath<'_>, w: f64) {
        let first = path.first;
        for c in 0..3 {
            self.emitted[c] += w * first.emitted[c];
            self.direct[c] += w * first.direct[c];
            self.albedo[c] += w * first.albedo[c];
        }
        self.weight += w;
        self.weight2 += w * w;
        let share = w / self.weight;
        self.emitted_stats.add(path.emitted, w, share);
        self.direct_stats.add(path.direct, w, share);
        self.rest_stats.add(path.rest, w, share);
        self.normal += w * first.normal;
        self.depth += w * first.depth;
        self.depth2 += w * first.depth * first.depth;
    }

    /// Merges `other`'s paths into these, each weighted `factor` times as much as in `other`.
    fn merge_scaled(&mut self, other: &GuideSums, factor: f64) {
        let (wa, wb) = (self.weight, other.weight * factor);
        for c in 0..3 {
            self.albedo[c] += factor * other.albedo[c];
            self.emitted[c] += factor * other.emitted[c];
            self.direct[c] += factor * other.direct[c];
        }
        self.normal += factor * other.normal;
        self.depth += factor * other.depth;
        self.depth2 += factor * other.depth2;
        for (mine, theirs) in [
            (&mut self.emitted_stats, &other.emitted_stats),
            (&mut self.direct_stats, &other.direct_stats),
            (&mut self.rest_stats, &other.rest_stats),
        ] {
            let scaled = Welford {
                mean: theirs.mean,
                m2: theirs.m2 * factor,
            };
            mine.merge(&scaled, wa, wb);
        }
        self.weight = wa + wb;
        self.weight2 += other.weight2 * factor * factor;
    }

    /// The weighted mean of a sum.
    fn mean(&self, sum: Rgb) -> Rgb {
        if self.weight > 0.0 {
            sum.map(|s| s / self.weight)
        } else {
            [0.0; 3]
        }
    }

    fn mean_depth(&self) -> f64 {
        if self.weight > 0.0 {
            self.depth / self.weight
        } else {
            0.0
        }
    }

    /// The standard error of the weighted mean of the values that `stats` follows.
    fn standard_error(&self, stats: &Welford) -> f64 {
        stats.standard_error(self.weight, self.weight2)
    }

    /// How much the paths agree on what they saw first, in [0, 1]: the length of their mean
    /// normal times a falloff with the spread of their depths (1: one surface; near 0: the
    /// pixel covers many things smaller than itself, such as far mirror images). 1 below two
    /// paths (effectively: (Σw)²/Σw² < 2).
    fn coherence(&self) -> f64 {
        let (w, w2) = (self.weight, self.weight2);
        if w2 <= 0.0 || w * w < (2.0 - 1e-9) * w2 {
            return 1.0;
        }
        let mean = self.depth / w;
        let spread = (self.depth2 / w - mean * mean).max(0.0).sqrt();
        let normals = (self.normal.length() / w).min(1.0);
        normals / (1.0 + COHERENCE_DEPTH * spread / mean.max(1e-9))
    }
}

impl Guides {
    /// Empty guides for a `width` × `height` image.
    ///
    /// ```
    /// use orbifold_render::denoise::Guides;
    /// use orbifold_render::integrator::FirstHit;
    ///
    /// let mut guides = Guides::new(2, 1);
    /// let first = FirstHit { albedo: [0.5; 3], depth: 2.0, emitted: [1.0; 3], ..FirstHit::default() };
    /// guides.add(1, 0, &first, [1.2; 3]);
    /// assert_eq!(guides.albedo(1, 0), [0.5; 3]);
    /// assert_eq!(guides.emitted(1, 0), [1.0; 3]);
    /// ```
    pub fn new(width: u32, height: u32) -> Guides {
        let n = width as usize * height as usize;
        Guides {
            width,
            height,
            own: vec![GuideSums::default(); n],
            pixels: vec![GuideSums::default(); n],
            filter: PixelFilter::Box,
        }
    }

    fn index(&self, x: u32, y: u32) -> usize {
        assert!(
            x < self.width && y < self.height,
            "pixel ({x}, {y}) outside the guides"
        );
        y as usize * self.width as usize + x as usize
    }

    /// Adds what one path through pixel (x, y) saw first, with its `radiance` (of which
    /// `first.emitted` is the part seen directly; non-finite values are skipped), for that pixel
    /// only (the box filter, as [`Film::add`]).
    pub fn add(&mut self, x: u32, y: u32, first: &FirstHit, radiance: Rgb) {
        self.splat(x, y, first, radiance, PixelFilter::Box);
    }

    /// Adds what a path taken for pixel (x, y) saw first, under the reconstruction filter
    /// `filter` (as [`Film::splat`]).
    ///
    /// ```
    /// use orbifold_render::denoise::Guides;
    /// use orbifold_render::filter::PixelFilter;
    /// use orbifold_render::integrator::FirstHit;
    ///
    /// let mut guides = Guides::new(3, 3);
    /// let first = FirstHit { albedo: [0.5; 3], ..FirstHit::default() };
    /// guides.splat(1, 1, &first, [1.0; 3], PixelFilter::GAUSSIAN);
    /// assert_eq!(guides.albedo(2, 0), [0.5; 3]);
    /// ```
    pub fn splat(&mut self, x: u32, y: u32, first: &FirstHit, radiance: Rgb, filter: PixelFilter) {
        let i = self.index(x, y);
        if filter != self.filter {
            self.filter = filter;
            self.filter_all();
        }
        if let Some(path) = GuidePath::new(first, radiance) {
            self.own[i].add(&path, 1.0);
        }
        self.filter.filter_around(
            &self.own,
            &mut self.pixels,
            (self.width, self.height),
            (x, y),
            |p| p.weight,
            GuideSums::merge_scaled,
        );
    }

    /// [`Guides::splat`] for many paths at once, as [`Film::splat_all`]: each sample's pixel
    /// and radiance, with what its path saw first.
    ///
    /// # Panics
    ///
    /// If a sample's pixel is outside the guides.
    pub fn splat_all(&mut self, samples: &[(Splat, FirstHit)], filter: PixelFilter) {
        for (s, _) in samples {
            self.index(s.x, s.y);
        }
        let mut changed = (filter == self.filter).then(|| vec![false; self.own.len()]);
        self.filter = filter;
        for (s, first) in samples {
            let i = self.index(s.x, s.y);
            if let Some(path) = GuidePath::new(first, s.radiance) {
                self.own[i].add(&path, 1.0);
                if let Some(changed) = &mut changed {
                    changed[i] = true;
                }
            }
        }
        self.filter.filter_changed(
            &self.own,
            &mut self.pixels,
            (self.width, self.height),
            changed.as_deref(),
            |p| p.weight,
            GuideSums::merge_scaled,
        );
    }

    /// The pixels' filtered sums afresh from their own.
    fn filter_all(&mut self) {
        let size = (self.width, self.height);
        self.filter.filter_all(
            &self.own,
            &mut self.pixels,
            size,
            |p| p.weight,
            GuideSums::merge_scaled,
        );
    }

    /// The mean albedo at pixel (x, y).
    pub fn albedo(&self, x: u32, y: u32) -> Rgb {
        let i = self.index(x, y);
        self.mean_albedo(i)
    }

    /// The mean light seen directly at pixel (x, y) ([`FirstHit::emitted`]).
    pub fn emitted(&self, x: u32, y: u32) -> Rgb {
        let i = self.index(x, y);
        self.mean_emitted(i)
    }

    fn mean_emitted(&self, i: usize) -> Rgb {
        let p = &self.pixels[i];
        p.mean(p.emitted)
    }

    /// The mean of the first surface's light sample at pixel (x, y) ([`FirstHit::direct`]).
    pub fn direct(&self, x: u32, y: u32) -> Rgb {
        let i = self.index(x, y);
        self.mean_direct(i)
    }

    fn mean_direct(&self, i: usize) -> Rgb {
        let p = &self.pixels[i];
        p.mean(p.direct)
    }

    /// The standard errors of pixel (x, y)'s mean luminance in its three parts — the light seen
    /// directly, the first surface's light sample, the rest — and how much its paths agree on
    /// what they saw first (1: one surface; near 0: many things smaller than the pixel). What
    /// the denoiser weighs each part by; for finding where a picture's noise comes from.
    ///
    /// ```
    /// use orbifold_render::denoise::Guides;
    /// use orbifold_render::integrator::FirstHit;
    ///
    /// let mut guides = Guides::new(1, 1);
    /// let first = FirstHit { albedo: [0.5; 3], normal: glam::DVec3::Z, depth: 1.0, ..FirstHit::default() };
    /// for radiance in [0.2, 0.4, 0.2, 0.4] {
    ///     guides.add(0, 0, &first, [radiance; 3]);
    /// }
    /// let ([emitted, direct, rest], coherence) = guides.part_errors(0, 0);
    /// assert_eq!((emitted, direct), (0.0, 0.0));
    /// // Four values 0.1 from their mean: s² = 4 · 0.01 / 3, and the standard error √(s²/4).
    /// assert!((rest - (0.01f64 / 3.0).sqrt()).abs() < 1e-12 && coherence == 1.0);
    /// ```
    pub fn part_errors(&self, x: u32, y: u32) -> ([f64; 3], f64) {
        let p = &self.pixels[self.index(x, y)];
        let errors =
            [&p.emitted_stats, &p.direct_stats, &p.rest_stats].map(|stats| p.standard_error(stats));
        (errors, p.coherence())
    }

    fn mean_albedo(&self, i: usize) -> Rgb {
        let p = &self.pixels[i];
        p.mean(p.albedo)
    }

    fn mean_normal(&self, i: usize) -> DVec3 {
        self.pixels[i].normal.normalize_or_zero()
    }

    fn mean_depth(&self, i: usize) -> f64 {
        self.pixels[i].mean_depth()
    }

    fn coherence(&self, i: usize) -> f64 {
        self.pixels[i].coherence()
    }
}

/// A weighted running mean and sum of squared deviations (West's weighted form of Welford's
/// algorithm), for a standard error.
#[derive(Clone, Copy, Debug, Default)]
struct Welford {
    mean: f64,
    m2: f64,
}

impl Welford {
    /// Merges `other`, whose values weigh `wb` in all, into these, which weigh `wa` (Chan et
    /// al.'s formula).
    fn merge(&mut self, other: &Welford, wa: f64, wb: f64) {
        let w = wa + wb;
        if wb <= 0.0 || w <= 0.0 {
            return;
        }
        let delta = other.mean - self.mean;
        self.mean += delta * wb / w;
        self.m2 += other.m2 + delta * delta * wa * wb / w;
    }

    /// Adds `value` with weight `w`, whose share of the weights' sum (with it) is `share`.
    fn add(&mut self, value: f64, w: f64, share: f64) {
        let delta = value - self.mean;
        self.mean += delta * share;
        self.m2 += w * delta * (value - self.mean);
    }

    /// The standard error of the weighted mean, with Σw = `w` and Σw² = `w2` (for unit weights
    /// √(s²/n)); infinite while the effective number of samples (Σw)²/Σw² is at most one.
    fn standard_error(&self, w: f64, w2: f64) -> f64 {
        if w2 <= 0.0 || w * w <= w2 * (1.0 + 1e-9) {
            return f64::INFINITY;
        }
        let s2 = (self.m2 / (w - w2 / w)).max(0.0);
        (s2 * w2).sqrt() / w
    }
}

/// How strongly a pixel's relative depth spread lowers its coherence.
const COHERENCE_DEPTH: f64 = 4.0;

/// How strongly each guide stops the filter.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DenoiseOptions {
    /// Number of à-trous passes (the footprint is 4·2^passes − 3 pixels wide).
    pub passes: u32,
    /// Exponent of the normal weight max(0, n·n′)^σ for the first surface's light sample.
    pub sigma_normal: f64,
    /// Exponent of the normal weight for the rest of the reflected light (the light of longer
    /// paths). Lower than [`DenoiseOptions::sigma_normal`]: light that arrives after a bounce
    /// comes from all round and changes slowly with the normal, while a light sample follows
    /// the normal's cosine to the light. On a bumpy mesh, whose normals turn by tens of degrees
    /// from pixel to pixel, the light sample's exponent let nothing be averaged there; with 8
    /// instead of 64 the denoised 99th percentile of `*444`'s dragons at 896² fell by 6 % for a
    /// bias that moved by 0.05 levels RMS (`docs/benchmarks.md`).
    pub sigma_normal_rest: f64,
    /// Relative depth difference that halves the weight about e-fold.
    pub sigma_depth: f64,
    /// Albedo difference scale; infinite (the default) for no albedo guide. The lighting is
    /// filtered divided by the albedo, so a texture's edge is no lighting edge; and where a
    /// checkerboard's checks shrink towards a pixel, each pixel's footprint-averaged albedo
    /// differs from its neighbours' (a moiré), so an albedo guide stopped the filter just where
    /// the far floor's noise was worst (the denoised 99th percentile 6-10 % higher in every
    /// Table 8.1 room; `docs/benchmarks.md`).
    pub sigma_albedo: f64,
    /// Lighting difference, in standard errors, that the weight tolerates.
    pub sigma_lighting: f64,
}

impl Default for DenoiseOptions {
    fn default() -> Self {
        DenoiseOptions {
            passes: 5,
            sigma_normal: 64.0,
            sigma_normal_rest: 8.0,
            sigma_depth: 0.05,
            sigma_albedo: f64::INFINITY,
            sigma_lighting: 4.0,
        }
    }
}

/// The B3-spline kernel of the à-trous transform.
const KERNEL: [f64; 5] = [1.0 / 16.0, 1.0 / 4.0, 3.0 / 8.0, 1.0 / 4.0, 1.0 / 16.0];

/// Albedos below this are treated as this when dividing (black surfaces keep their lighting).
const ALBEDO_FLOOR: f64 = 0.01;

/// The denoised image of `film`, guided by `guides` (of the same size), as a film of one
/// sample per pixel.
///
/// ```
/// use orbifold_render::denoise::{DenoiseOptions, Guides, denoise};
/// use orbifold_render::film::Film;
/// use orbifold_render::integrator::FirstHit;
///
/// // A flat grey wall with noise: denoising brings every pixel close to the mean.
/// let (w, h) = (16, 16);
/// let mut film = Film::new(w, h);
/// let mut guides = Guides::new(w, h);
/// let first = FirstHit { albedo: [0.5; 3], normal: glam::DVec3::Z, depth: 1.0, ..FirstHit::default() };
/// for y in 0..h {
///     for x in 0..w {
///         for k in 0..4u32 {
///             let noise = if (x + y + k) % 2 == 0 { 0.1 } else { -0.1 };
///             film.add(x, y, [0.3 + noise; 3]);
///             guides.add(x, y, &first, [0.3 + noise; 3]);
///         }
///     }
/// }
/// let clean = denoise(&film, &guides, &DenoiseOptions::default());
/// assert!((clean.pixel(5, 7)[0] - 0.3).abs() < 0.02);
/// ```
pub fn denoise(film: &Film, guides: &Guides, options: &DenoiseOptions) -> Film {
    denoise_with_reduction(film, guides, options).0
}

/// [`denoise`], and for every pixel (row by row) how much the filter lowers the variance of its
/// estimate, in [0, 1]: the variance of the denoised pixel over that of the pixel's own mean; 1
/// where that is unknown (fewer than two samples). The denoised pixel's variance is that of the
/// light seen directly, which the filter leaves as it is, plus that of the filtered lighting,
/// propagated through the passes as if the inputs of each pass were independent (as in SVGF).
/// Adaptive sampling uses it to spend samples where the denoised image will be noisy rather
/// than where the raw one is: a pixel whose noise is mostly a crowd of tiny light images keeps
/// that noise after denoising, however smooth the wall behind them.
///
/// The propagation ignores the correlation that each pass gives its outputs, so on smooth
/// surfaces the factor is far smaller than the true one; it orders pixels well. (Measured on the
/// rooms of the seed's Table 8.1 at 896²: where it says 10⁻⁴, 10⁻³, 10⁻² and 10⁻¹, two seeds'
/// denoised pixels differ by 0.005, 0.03, 0.08 and 0.2-0.25 of the raw variance — about 0.6·√
/// of it, which is why adaptive sampling weighs pixels by its square root.)
///
/// ```
/// use orbifold_render::denoise::{DenoiseOptions, Guides, denoise_with_reduction};
/// use orbifold_render::film::Film;
/// use orbifold_render::integrator::FirstHit;
///
/// // A noisy flat wall, and one pixel that saw something else (another albedo).
/// let (w, h) = (9, 9);
/// let mut film = Film::new(w, h);
/// let mut guides = Guides::new(w, h);
/// for y in 0..h {
///     for x in 0..w {
///         let albedo = if (x, y) == (4, 4) { [0.9, 0.1, 0.1] } else { [0.5; 3] };
///         for k in 0..4u32 {
///             let radiance = [0.3 + 0.1 * f64::from(k % 2); 3];
///             film.add(x, y, radiance);
///             let first = FirstHit { albedo, normal: glam::DVec3::Z, depth: 1.0, ..FirstHit::default() };
///             guides.add(x, y, &first, radiance);
///         }
///     }
/// }
/// let (_, reduction) = denoise_with_reduction(&film, &guides, &DenoiseOptions::default());
/// assert!(reduction[2 * 9 + 2] < 0.1); // averaged with its neighbours
/// assert!(reduction[4 * 9 + 4] > 0.9); // alone: the filter cannot help it
/// ```
pub fn denoise_with_reduction(
    film: &Film,
    guides: &Guides,
    options: &DenoiseOptions,
) -> (Film, Vec<f64>) {
    let (width, height) = (film.width(), film.height());
    assert_eq!(
        (guides.width, guides.height),
        (width, height),
        "guides of another size"
    );
    let n = width as usize * height as usize;
    let albedo: Vec<Rgb> = (0..n)
        .map(|i| guides.mean_albedo(i).map(|a| a.max(ALBEDO_FLOOR)))
        .collect();
    let normal: Vec<DVec3> = (0..n).map(|i| guides.mean_normal(i)).collect();
    let depth: Vec<f64> = (0..n).map(|i| guides.mean_depth(i)).collect();
    let coherence: Vec<f64> = (0..n).map(|i| guides.coherence(i)).collect();
    let guide = Guide {
        width: width as usize,
        height: height as usize,
        albedo: &albedo,
        normal: &normal,
        depth: &depth,
        coherence: &coherence,
        options,
    };
    // The reflected light in two parts, each over the albedo with the variance of its
    // luminance: the first surface's light sample, and the rest (the film's mean less it and
    // less the light seen directly, which is added back unfiltered).
    let emitted: Vec<Rgb> = (0..n).map(|i| guides.mean_emitted(i)).collect();
    let over_albedo = |i: usize, value: Rgb, stats: &Welford| {
        let a = albedo[i];
        let se = guides.pixels[i].standard_error(stats);
        let scale = luminance(a).max(ALBEDO_FLOOR);
        let variance = if se.is_finite() {
            (se / scale).powi(2)
        } else {
            f64::INFINITY
        };
        (
            [value[0] / a[0], value[1] / a[1], value[2] / a[2]],
            variance,
        )
    };
    let (lighting, variance) = (0..n)
        .map(|i| over_albedo(i, guides.mean_direct(i), &guides.pixels[i].direct_stats))
        .unzip();
    let direct = Part { lighting, variance };
    let (lighting, variance) = (0..n)
        .map(|i| {
            let (x, y) = ((i % width as usize) as u32, (i / width as usize) as u32);
            let (c, e, d) = (film.pixel(x, y), emitted[i], guides.mean_direct(i));
            let value = [0, 1, 2].map(|k| c[k] - e[k] - d[k]);
            over_albedo(i, value, &guides.pixels[i].rest_stats)
        })
        .unzip();
    let rest = Part { lighting, variance };
    // The light seen directly, in the image's own units (not over the albedo).
    let variance = (0..n)
        .map(|i| {
            let p = &guides.pixels[i];
            let se = p.standard_error(&p.emitted_stats);
            if se.is_finite() {
                se * se
            } else {
                f64::INFINITY
            }
        })
        .collect();
    let seen = Part {
        lighting: emitted,
        variance,
    };
    // The variance of each pixel's luminance in the image's own units: the light seen directly
    // and the two parts over the albedo.
    let total_variance = |parts: &[Part; 3]| -> Vec<f64> {
        (0..n)
            .map(|i| {
                let scale = luminance(albedo[i]).max(ALBEDO_FLOOR);
                let emitted = parts[2].variance[i];
                let emitted = if emitted.is_finite() { emitted } else { 0.0 };
                emitted + (parts[0].variance[i] + parts[1].variance[i]) * scale * scale
            })
            .collect()
    };
    let parts = [direct, rest, seen];
    let before = total_variance(&parts);
    let parts = guide.smooth(
        parts,
        [
            PartRule::LightSample,
            PartRule::Rest,
            PartRule::SeenDirectly,
        ],
    );
    let variance = total_variance(&parts);
    let [direct, rest, seen] = parts;
    let pixels: Vec<Rgb> = (0..n)
        .map(|i| {
            let (d, r) = (direct.lighting[i], rest.lighting[i]);
            let (a, e) = (albedo[i], seen.lighting[i]);
            [0, 1, 2].map(|k| (d[k] + r[k]) * a[k] + e[k])
        })
        .collect();
    let reduction = before
        .iter()
        .zip(&variance)
        .map(|(&own, &filtered)| {
            if own.is_finite() && filtered.is_finite() && own > 0.0 {
                (filtered / own).min(1.0)
            } else {
                1.0
            }
        })
        .collect();
    (Film::from_pixels(width, height, &pixels), reduction)
}

/// One part of the light being filtered: per pixel its value (over the albedo for reflected
/// light), and the variance of that value's luminance (infinite where unknown).
struct Part {
    lighting: Vec<Rgb>,
    variance: Vec<f64>,
}

/// How much a pixel's light seen directly is averaged with its neighbours', by how much its
/// paths agree on what they saw first: 1 − coherence, and 0 above a coherence of
/// [`SEEN_COHERENT`] (nearly every pixel of a surface: its depths spread a little over its
/// footprint), where the weights would be too small to matter and not worth their cost.
fn seen_openness(coherence: f64) -> f64 {
    if coherence >= SEEN_COHERENT {
        0.0
    } else {
        1.0 - coherence
    }
}

/// The coherence above which a pixel's light seen directly is left as it is.
const SEEN_COHERENT: f64 = 0.95;

/// How the filter treats a part.
#[derive(Clone, Copy, Debug, PartialEq)]
enum PartRule {
    /// The first surface's light sample: the sharp normal guide.
    LightSample,
    /// The light of longer paths: the soft normal guide.
    Rest,
    /// The light seen directly: averaged only between pixels whose paths disagree on what they
    /// saw (the crowd of sub-pixel light images near a hyperbolic room's horizon), each
    /// neighbour weighed by how little both pixels' paths agree, (1 − coherence) each. A
    /// light image that covers its pixels whole, and the wall around it, keep their own.
    SeenDirectly,
}

/// The guides of one denoising run.
struct Guide<'a> {
    width: usize,
    height: usize,
    albedo: &'a [Rgb],
    normal: &'a [DVec3],
    depth: &'a [f64],
    coherence: &'a [f64],
    options: &'a DenoiseOptions,
}

impl Guide<'_> {
    /// The à-trous passes over parts of the lighting, each with the variance of its luminance
    /// and its own lighting tolerance, under the same guides (whose weights are computed once
    /// for all parts).
    fn smooth<const N: usize>(&self, mut parts: [Part; N], rules: [PartRule; N]) -> [Part; N] {
        let n = self.width * self.height;
        for pass in 0..self.options.passes {
            let step = 1usize << pass;
            // The lighting tolerance comes from the variance blurred over 3×3 pixels (as in
            // SVGF): a pixel whose few samples happened to agree — all zero, say — has a
            // variance estimate near 0 and would otherwise refuse every neighbour and stay a
            // dark or bright speck.
            let around: [Vec<f64>; N] = parts.each_ref().map(|part| {
                (0..n)
                    .into_par_iter()
                    .map(|i| self.blurred(i, &part.variance))
                    .collect()
            });
            let filtered: Vec<[(Rgb, f64); N]> = (0..n)
                .into_par_iter()
                .map(|i| self.filter(i, step, &parts, &rules, &around.each_ref().map(|v| v[i])))
                .collect();
            parts = std::array::from_fn(|k| Part {
                lighting: filtered.iter().map(|f| f[k].0).collect(),
                variance: filtered.iter().map(|f| f[k].1).collect(),
            });
        }
        parts
    }

    /// The variance around pixel `i`: a 3×3 Gaussian of the finite variances.
    fn blurred(&self, i: usize, variance: &[f64]) -> f64 {
        const GAUSS: [f64; 3] = [0.25, 0.5, 0.25];
        let (x, y) = ((i % self.width) as isize, (i / self.width) as isize);
        let (mut sum, mut weights) = (0.0, 0.0);
        for (dy, ky) in GAUSS.iter().enumerate() {
            for (dx, kx) in GAUSS.iter().enumerate() {
                let (xx, yy) = (x + dx as isize - 1, y + dy as isize - 1);
                if xx < 0 || yy < 0 || xx >= self.width as isize || yy >= self.height as isize {
                    continue;
                }
                let v = variance[yy as usize * self.width + xx as usize];
                if v.is_finite() {
                    sum += kx * ky * v;
                    weights += kx * ky;
                }
            }
        }
        if weights > 0.0 {
            sum / weights
        } else {
            f64::INFINITY
        }
    }

    /// How much neighbour `j` counts for pixel `i` by the guides (before the kernel's weight and
    /// the lighting's), as logarithms scaled by how much pixel `i`'s paths agree (its
    /// coherence): that of the normals' cosine, which each part raises to its own exponent
    /// ([`DenoiseOptions::sigma_normal`], [`DenoiseOptions::sigma_normal_rest`]), and that of
    /// the falloffs in depth and albedo (the filter's hot path: one logarithm, no exponential);
    /// `None` for a weight of 0.
    fn guide_log_weight(&self, i: usize, j: usize, step: usize) -> Option<(f64, f64)> {
        let o = self.options;
        let trust = self.coherence[i];
        let cos = self.normal[i].dot(self.normal[j]);
        // max(0, cos)^(σ·trust), with 0^0 = 1 as `powf` has it.
        let normal = if trust <= 0.0 {
            0.0
        } else if cos > 0.0 {
            trust * cos.ln()
        } else {
            return None;
        };
        let (zi, zj) = (self.depth[i], self.depth[j]);
        let depth = -(zi - zj).abs() / (o.sigma_depth * zi.max(zj) * step as f64 + 1e-9) * trust;
        let albedo = if o.sigma_albedo.is_finite() {
            let da: f64 = (0..3)
                .map(|c| (self.albedo[i][c] - self.albedo[j][c]).powi(2))
                .sum();
            -da / (o.sigma_albedo * o.sigma_albedo) * trust
        } else {
            0.0
        };
        Some((normal, depth + albedo))
    }

    /// One à-trous tap set around pixel `i` with holes of `step`, for every part: the filtered
    /// lighting and its variance. `variance_around` is each part's (blurred) variance there,
    /// which sets its lighting tolerance.
    fn filter<const N: usize>(
        &self,
        i: usize,
        step: usize,
        parts: &[Part; N],
        rules: &[PartRule; N],
        variance_around: &[f64; N],
    ) -> [(Rgb, f64); N] {
        let o = self.options;
        let (x, y) = ((i % self.width) as isize, (i / self.width) as isize);
        let centre = parts.each_ref().map(|p| luminance(p.lighting[i]));
        // The lighting tolerance: a few standard errors (an infinite variance — nothing
        // sampled around — accepts everything).
        let tolerance = variance_around.map(|v| o.sigma_lighting * v.sqrt() + 1e-6);
        // A pixel whose paths saw many different things (sub-pixel detail: the crowd of far
        // mirror images at a hyperbolic room's horizon) has guides that are themselves noise:
        // it listens to them only as much as its paths agree (`guide_log_weight`), and to its
        // lighting tolerance.
        let mut sums = [([0.0; 3], 0.0, 0.0); N];
        // The normal weight's exponent of each part.
        let sharpness = rules.map(|rule| match rule {
            PartRule::LightSample | PartRule::SeenDirectly => o.sigma_normal,
            PartRule::Rest => o.sigma_normal_rest,
        });
        // How much each part listens to its neighbours at all: the light seen directly only as
        // much as this pixel's paths disagree (0 for one surface: nothing to filter).
        let openness = rules.map(|rule| match rule {
            PartRule::SeenDirectly => seen_openness(self.coherence[i]),
            PartRule::LightSample | PartRule::Rest => 1.0,
        });
        for (dy, ky) in KERNEL.iter().enumerate() {
            let yy = y + (dy as isize - 2) * step as isize;
            if yy < 0 || yy >= self.height as isize {
                continue;
            }
            for (dx, kx) in KERNEL.iter().enumerate() {
                let xx = x + (dx as isize - 2) * step as isize;
                if xx < 0 || xx >= self.width as isize {
                    continue;
                }
                let j = yy as usize * self.width + xx as usize;
                let guides = if j == i {
                    Some((0.0, 0.0))
                } else {
                    self.guide_log_weight(i, j, step)
                };
                let Some((normal, others)) = guides else {
                    continue;
                };
                for (k, part) in parts.iter().enumerate() {
                    let w = if j == i {
                        kx * ky
                    } else if openness[k] <= 0.0 {
                        continue;
                    } else {
                        let light = -(centre[k] - luminance(part.lighting[j])).abs() / tolerance[k];
                        let open = match rules[k] {
                            PartRule::SeenDirectly => {
                                openness[k] * seen_openness(self.coherence[j])
                            }
                            PartRule::LightSample | PartRule::Rest => 1.0,
                        };
                        open * kx * ky * (sharpness[k] * normal + others + light).exp()
                    };
                    // NaN weights (from NaN guides) and unsampled neighbours are skipped.
                    let usable = w > 0.0 && (j == i || part.variance[j].is_finite());
                    if !usable {
                        continue;
                    }
                    let (sum, weights, var) = &mut sums[k];
                    for (s, l) in sum.iter_mut().zip(part.lighting[j]) {
                        *s += w * l;
                    }
                    *weights += w;
                    *var += w * w * part.variance[j];
                }
            }
        }
        std::array::from_fn(|k| {
            let (sum, weights, var) = sums[k];
            if weights <= 0.0 {
                (parts[k].lighting[i], parts[k].variance[i])
            } else {
                (sum.map(|s| s / weights), var / (weights * weights))
            }
        })
    }
}
