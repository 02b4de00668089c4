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

use crate::film::PixelFilter;
use crate::film::{Film, RunningStats, Splat};
use crate::integrator::FirstHit;
use crate::lights::Rgb;
use orbifold_scene::color::luminance;
use orbifold_trace::fastmath::{exp_fast, ln_fast};

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
    emitted_stats: RunningStats,
    direct_stats: RunningStats,
    rest_stats: RunningStats,
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
        self.emitted_stats.add(path.emitted, w, self.weight);
        self.direct_stats.add(path.direct, w, self.weight);
        self.rest_stats.add(path.rest, w, self.weight);
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
            mine.merge(&theirs.scaled(factor), wa, wb);
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
    fn standard_error(&self, stats: &RunningStats) -> f64 {
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
    /// use orbifold_render::film::PixelFilter;
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
    /// from pixel to pixel, the light sample's exponent would let nothing be averaged there (the
    /// trade of noise for bias is measured in `docs/benchmarks.md`).
    pub sigma_normal_rest: f64,
    /// Relative depth difference that halves the weight about e-fold.
    pub sigma_depth: f64,
    /// Albedo difference scale; infinite (the default) for no albedo guide. The lighting is
    /// filtered divided by the albedo, so a texture's edge is no lighting edge; and where a
    /// checkerboard's checks shrink towards a pixel, each pixel's footprint-averaged albedo
    /// differs from its neighbours' (a moiré), so an albedo guide would stop the filter just where
    /// the far floor's noise is worst.
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
/// surfaces the factor is far smaller than the true one; it orders pixels well. Two seeds'
/// denoised pixels differ by roughly 0.6·√ of the factor times the raw variance, which is why
/// adaptive sampling weighs pixels by its square root (`docs/benchmarks.md`).
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
        .into_par_iter()
        .map(|i| guides.mean_albedo(i).map(|a| a.max(ALBEDO_FLOOR)))
        .collect();
    let normal: Vec<DVec3> = (0..n)
        .into_par_iter()
        .map(|i| guides.mean_normal(i))
        .collect();
    let depth: Vec<f64> = (0..n)
        .into_par_iter()
        .map(|i| guides.mean_depth(i))
        .collect();
    let coherence: Vec<f64> = (0..n)
        .into_par_iter()
        .map(|i| guides.coherence(i))
        .collect();
    let guide = Guide::new(
        (width as usize, height as usize),
        &albedo,
        &normal,
        &depth,
        &coherence,
        options,
    );
    // The reflected light in two parts, each over the albedo with the variance of its
    // luminance: the first surface's light sample, and the rest (the film's mean less it and
    // less the light seen directly, which is added back unfiltered).
    let emitted: Vec<Rgb> = (0..n)
        .into_par_iter()
        .map(|i| guides.mean_emitted(i))
        .collect();
    let over_albedo = |i: usize, value: Rgb, stats: &RunningStats| {
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
        .into_par_iter()
        .map(|i| over_albedo(i, guides.mean_direct(i), &guides.pixels[i].direct_stats))
        .unzip();
    let direct = Part { lighting, variance };
    let (lighting, variance) = (0..n)
        .into_par_iter()
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
        .into_par_iter()
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
            .into_par_iter()
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
        .into_par_iter()
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

/// The guides of one denoising run, one plane per quantity: at one tap of the kernel, a row of
/// pixels and their neighbours are two contiguous runs, which the filter weighs side by side in
/// SIMD lanes ([`Guide::filter_row`]).
struct Guide<'a> {
    width: usize,
    height: usize,
    albedo: &'a [Rgb],
    /// The mean normals' x, y and z.
    normal: [Vec<f64>; 3],
    depth: &'a [f64],
    coherence: &'a [f64],
    /// [`seen_openness`] of each pixel.
    openness: Vec<f64>,
    options: &'a DenoiseOptions,
}

/// The parts being filtered, all of them.
const PARTS: usize = 3;

/// One part during the passes, one plane per quantity.
struct Planes {
    lighting: [Vec<f64>; 3],
    luminance: Vec<f64>,
    variance: Vec<f64>,
    /// The variance where it is finite, 0 elsewhere (where the pixel is no neighbour's), so
    /// that weights of 0 can be added without a branch or a masked load.
    finite_variance: Vec<f64>,
}

impl Planes {
    fn new(part: &Part) -> Planes {
        Planes::from_planes(
            [0, 1, 2].map(|c| part.lighting.iter().map(|l| l[c]).collect()),
            part.variance.clone(),
        )
    }

    /// Planes of `lighting` and `variance`. A pixel whose lighting is not finite is no
    /// neighbour's (its luminance is not finite, and neither is its weight) and counts as 0 for
    /// itself, so that sums of weights of 0 need no branch.
    fn from_planes(mut lighting: [Vec<f64>; 3], variance: Vec<f64>) -> Planes {
        let luminance = (0..variance.len())
            .map(|i| luminance([lighting[0][i], lighting[1][i], lighting[2][i]]))
            .collect();
        for plane in &mut lighting {
            for l in plane.iter_mut().filter(|l| !l.is_finite()) {
                *l = 0.0;
            }
        }
        let finite_variance = variance
            .iter()
            .map(|&v| if v.is_finite() { v } else { 0.0 })
            .collect();
        Planes {
            lighting,
            luminance,
            variance,
            finite_variance,
        }
    }

    /// Planes of `n` pixels, all 0 (to be written by a pass).
    fn zeroed(n: usize) -> Planes {
        Planes {
            lighting: [0, 1, 2].map(|_| vec![0.0; n]),
            luminance: vec![0.0; n],
            variance: vec![0.0; n],
            finite_variance: vec![0.0; n],
        }
    }

    /// The planes' rows of `width` pixels, each writable on its own.
    fn rows_mut(&mut self, width: usize) -> impl Iterator<Item = PlanesRow<'_>> {
        let [r, g, b] = &mut self.lighting;
        (r.chunks_mut(width))
            .zip(g.chunks_mut(width))
            .zip(b.chunks_mut(width))
            .zip(self.luminance.chunks_mut(width))
            .zip(self.variance.chunks_mut(width))
            .zip(self.finite_variance.chunks_mut(width))
            .map(
                |(((((r, g), b), luminance), variance), finite_variance)| PlanesRow {
                    lighting: [r, g, b],
                    luminance,
                    variance,
                    finite_variance,
                },
            )
    }

    fn part(&self) -> Part {
        let [r, g, b] = &self.lighting;
        Part {
            lighting: (0..r.len()).map(|i| [r[i], g[i], b[i]]).collect(),
            variance: self.variance.clone(),
        }
    }
}

/// What a row's pass adds up for one part at each pixel: Σw·lighting, Σw and Σw²·variance.
struct RowSums {
    lighting: [Vec<f64>; 3],
    weights: Vec<f64>,
    variance: Vec<f64>,
}

impl RowSums {
    /// A worker's memory for the rows of `width` pixels it filters: every part's sums, and one
    /// tap's runs.
    fn zeroed(width: usize) -> ([RowSums; PARTS], TapRuns) {
        let sums = std::array::from_fn(|_| RowSums {
            lighting: [0, 1, 2].map(|_| vec![0.0; width]),
            weights: vec![0.0; width],
            variance: vec![0.0; width],
        });
        let runs = TapRuns {
            normal_log: vec![0.0; width],
            others: vec![0.0; width],
            weights: vec![0.0; width],
        };
        (sums, runs)
    }

    fn clear(&mut self) {
        for plane in self
            .lighting
            .iter_mut()
            .chain([&mut self.weights, &mut self.variance])
        {
            plane.fill(0.0);
        }
    }
}

/// One tap's runs over a row: the guides' log-weights (the normal's, which each part raises to
/// its own exponent, and the others') and a part's weights.
struct TapRuns {
    normal_log: Vec<f64>,
    others: Vec<f64>,
    weights: Vec<f64>,
}

/// One row of a part's [`Planes`], being written by a pass.
struct PlanesRow<'a> {
    lighting: [&'a mut [f64]; 3],
    luminance: &'a mut [f64],
    variance: &'a mut [f64],
    finite_variance: &'a mut [f64],
}

impl PlanesRow<'_> {
    /// The row's filtered values from its sums (a pixel with no weight keeps its value in
    /// `old`, the planes the pass read; its first pixel is `start` there), with the luminance
    /// and the finite values that [`Planes::from_planes`] derives.
    fn finish(&mut self, sums: &RowSums, old: &Planes, start: usize) {
        for x in 0..self.luminance.len() {
            let (i, weights) = (start + x, sums.weights[x]);
            let lighting = [0, 1, 2].map(|c| {
                if weights > 0.0 {
                    sums.lighting[c][x] / weights
                } else {
                    old.lighting[c][i]
                }
            });
            let variance = if weights > 0.0 {
                sums.variance[x] / (weights * weights)
            } else {
                old.variance[i]
            };
            self.luminance[x] = luminance(lighting);
            for (plane, l) in self.lighting.iter_mut().zip(lighting) {
                plane[x] = if l.is_finite() { l } else { 0.0 };
            }
            self.variance[x] = variance;
            self.finite_variance[x] = if variance.is_finite() { variance } else { 0.0 };
        }
    }
}

impl<'a> Guide<'a> {
    fn new(
        (width, height): (usize, usize),
        albedo: &'a [Rgb],
        normal: &[DVec3],
        depth: &'a [f64],
        coherence: &'a [f64],
        options: &'a DenoiseOptions,
    ) -> Guide<'a> {
        Guide {
            width,
            height,
            albedo,
            normal: [0, 1, 2].map(|c| normal.iter().map(|n| n[c]).collect()),
            depth,
            coherence,
            openness: coherence.iter().map(|&c| seen_openness(c)).collect(),
            options,
        }
    }

    /// The à-trous passes over parts of the lighting, each with the variance of its luminance
    /// and its own lighting tolerance, under the same guides (whose weights are computed once
    /// for all parts).
    fn smooth(&self, parts: [Part; PARTS], rules: [PartRule; PARTS]) -> [Part; PARTS] {
        let (width, n) = (self.width, self.width * self.height);
        let mut planes = parts.each_ref().map(Planes::new);
        // Every pass reads `planes` and writes `next`, then the two swap: the planes, the
        // tolerances and the rows' sums are allocated once for all passes, because at large sizes
        // fresh memory each pass costs more in page faults than the filtering.
        let mut next = planes.each_ref().map(|_| Planes::zeroed(n));
        let mut tolerance: [Vec<f64>; PARTS] = std::array::from_fn(|_| vec![0.0; n]);
        for pass in 0..self.options.passes {
            let step = 1usize << pass;
            // The lighting tolerance comes from the variance blurred over 3×3 pixels (as in
            // SVGF): a pixel whose few samples happened to agree — all zero, say — has a
            // variance estimate near 0 and would otherwise refuse every neighbour and stay a
            // dark or bright speck. (An infinite variance — nothing sampled around — accepts
            // everything.)
            for (part, tolerance) in planes.iter().zip(&mut tolerance) {
                tolerance.par_iter_mut().enumerate().for_each(|(i, t)| {
                    *t =
                        self.options.sigma_lighting * self.blurred(i, &part.variance).sqrt() + 1e-6;
                });
            }
            let [a, b, c] = &mut next;
            let rows: Vec<[PlanesRow<'_>; PARTS]> = (a.rows_mut(width))
                .zip(b.rows_mut(width))
                .zip(c.rows_mut(width))
                .map(|((a, b), c)| [a, b, c])
                .collect();
            let (planes_in, tolerance) = (&planes, &tolerance);
            rows.into_par_iter().enumerate().for_each_init(
                || RowSums::zeroed(width),
                |scratch, (y, mut out)| {
                    self.filter_row(y, step, planes_in, &rules, tolerance, scratch);
                    for ((sums, out), old) in scratch.0.iter().zip(&mut out).zip(planes_in) {
                        out.finish(sums, old, y * width);
                    }
                },
            );
            std::mem::swap(&mut planes, &mut next);
        }
        planes.each_ref().map(Planes::part)
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

    /// One à-trous pass with holes of `step` over row `y`, for every part: the sums of each
    /// pixel's weighted neighbours. `tolerance` is each part's lighting tolerance per pixel.
    fn filter_row(
        &self,
        y: usize,
        step: usize,
        planes: &[Planes; PARTS],
        rules: &[PartRule; PARTS],
        tolerance: &[Vec<f64>; PARTS],
        scratch: &mut ([RowSums; PARTS], TapRuns),
    ) {
        orbifold_trace::with_avx512!(Guide<'_>, self.filter_row_portable(
            y: usize,
            step: usize,
            planes: &[Planes; PARTS],
            rules: &[PartRule; PARTS],
            tolerance: &[Vec<f64>; PARTS],
            scratch: &mut ([RowSums; PARTS], TapRuns),
        ) -> ())
    }

    /// [`Guide::filter_row`] in straight-line loops over runs of pixels (see the struct).
    ///
    /// A neighbour counts for a pixel by the guides — the normals' cosine to a power
    /// ([`DenoiseOptions::sigma_normal`], [`DenoiseOptions::sigma_normal_rest`]), falloffs in
    /// depth and albedo, each scaled by how much the pixel's paths agree (its coherence: a pixel
    /// whose paths saw many different things, such as the crowd of far mirror images at a
    /// hyperbolic room's horizon, has guides that are themselves noise, and listens to its
    /// lighting tolerance instead) — and by how far its lighting is from the pixel's in units
    /// of the tolerance. Unsampled neighbours, and weights of 0 or NaN, are left out.
    #[inline(always)]
    fn filter_row_portable(
        &self,
        y: usize,
        step: usize,
        planes: &[Planes; PARTS],
        rules: &[PartRule; PARTS],
        tolerance: &[Vec<f64>; PARTS],
        (sums, runs): &mut ([RowSums; PARTS], TapRuns),
    ) {
        let (width, o) = (self.width, self.options);
        let row = y * width;
        sums.iter_mut().for_each(RowSums::clear);
        // The guides' log-weights of one tap's run: the normal's (which each part raises to
        // its own exponent; NaN where the normals face apart: no weight) and the others'.
        let TapRuns {
            normal_log,
            others,
            weights,
        } = runs;
        // The light seen directly is weighed only where the row's pixels listen to their
        // neighbours' (openness > 0): elsewhere its weights are 0, so the part's runs are cut to
        // the row's span of open pixels, and a row with none (a row of surfaces) skips it.
        let openness = &self.openness[row..row + width];
        let open_span = openness.iter().position(|&o| o > 0.0).map(|first| {
            let last = openness.iter().rposition(|&o| o > 0.0).unwrap_or(first);
            first..last + 1
        });
        for (dy, ky) in KERNEL.iter().enumerate() {
            let yy = y as isize + (dy as isize - 2) * step as isize;
            if yy < 0 || yy >= self.height as isize {
                continue;
            }
            let near_row = yy as usize * width;
            for (dx, kx) in KERNEL.iter().enumerate() {
                let kernel = kx * ky;
                let offset = (dx as isize - 2) * step as isize;
                // The pixels x in [x0, x1) whose neighbour x + offset is in the row.
                let x0 = (-offset).max(0) as usize;
                let x1 = (width as isize - offset.max(0)).max(0) as usize;
                if x0 >= x1 {
                    continue;
                }
                let run = x1 - x0;
                let (at, near) = (row + x0, (near_row + x0).wrapping_add_signed(offset));
                if (dx, dy) == (2, 2) {
                    // The pixel itself: every part takes its own value.
                    for (part, sums) in planes.iter().zip(sums.iter_mut()) {
                        for c in 0..3 {
                            let own = &part.lighting[c][at..at + run];
                            for (s, l) in sums.lighting[c][x0..x1].iter_mut().zip(own) {
                                *s += kernel * l;
                            }
                        }
                        for ((w, s), v) in sums.weights[x0..x1]
                            .iter_mut()
                            .zip(&mut sums.variance[x0..x1])
                            .zip(&part.variance[at..at + run])
                        {
                            *w += kernel;
                            *s += kernel * kernel * v;
                        }
                    }
                    continue;
                }
                self.guide_log_weights(
                    (at, near, run),
                    step,
                    &mut normal_log[..run],
                    &mut others[..run],
                );
                for k in 0..PARTS {
                    let (part, sums) = (&planes[k], &mut sums[k]);
                    let sharpness = match rules[k] {
                        PartRule::LightSample | PartRule::SeenDirectly => o.sigma_normal,
                        PartRule::Rest => o.sigma_normal_rest,
                    };
                    let seen = rules[k] == PartRule::SeenDirectly;
                    // The stretch of the run this part weighs: [x0 + skip, x0 + skip + run).
                    let (skip, run) = if seen {
                        let Some(span) = &open_span else { continue };
                        let (from, to) = (span.start.max(x0), span.end.min(x1));
                        if from >= to {
                            continue;
                        }
                        (from - x0, to - from)
                    } else {
                        (0, run)
                    };
                    let (x0, x1, at, near) = (x0 + skip, x0 + skip + run, at + skip, near + skip);
                    let weights = &mut weights[..run];
                    {
                        let centre = &part.luminance[at..at + run];
                        let tolerance = &tolerance[k][at..at + run];
                        let open = &self.openness[at..at + run];
                        let near_luminance = &part.luminance[near..near + run];
                        let near_variance = &part.variance[near..near + run];
                        let near_open = &self.openness[near..near + run];
                        let (normal_log, others) =
                            (&normal_log[skip..skip + run], &others[skip..skip + run]);
                        for t in 0..run {
                            let light = -(centre[t] - near_luminance[t]).abs() / tolerance[t];
                            let open = if seen { open[t] * near_open[t] } else { 1.0 };
                            let weight = open
                                * kernel
                                * exp_fast(sharpness * normal_log[t] + others[t] + light);
                            // Not `&&`: a load behind a comparison becomes a masked load,
                            // slow on some processors. (NaN weights fail the comparison.)
                            let usable = (weight > 0.0) & near_variance[t].is_finite();
                            weights[t] = if usable { weight } else { 0.0 };
                        }
                    }
                    for c in 0..3 {
                        let near_lighting = &part.lighting[c][near..near + run];
                        for ((s, l), w) in sums.lighting[c][x0..x1]
                            .iter_mut()
                            .zip(near_lighting)
                            .zip(&*weights)
                        {
                            *s += w * l;
                        }
                    }
                    let near_variance = &part.finite_variance[near..near + run];
                    for ((sw, sv), (w, v)) in sums.weights[x0..x1]
                        .iter_mut()
                        .zip(&mut sums.variance[x0..x1])
                        .zip(weights.iter().zip(near_variance))
                    {
                        *sw += w;
                        *sv += w * w * v;
                    }
                }
            }
        }
    }

    /// The guides' log-weights of a run of `run` pixels from `at` against as many neighbours
    /// from `near`, scaled by each pixel's coherence: that of the normals' cosine (NaN where it
    /// is not positive: no weight), and that of the falloffs in depth and albedo.
    #[inline(always)]
    fn guide_log_weights(
        &self,
        (at, near, run): (usize, usize, usize),
        step: usize,
        normal_log: &mut [f64],
        others: &mut [f64],
    ) {
        let o = self.options;
        let [nx, ny, nz] = &self.normal;
        let (ax, ay, az) = (&nx[at..at + run], &ny[at..at + run], &nz[at..at + run]);
        let (bx, by, bz) = (
            &nx[near..near + run],
            &ny[near..near + run],
            &nz[near..near + run],
        );
        let (za, zb) = (&self.depth[at..at + run], &self.depth[near..near + run]);
        let trust = &self.coherence[at..at + run];
        let (normal_log, others) = (&mut normal_log[..run], &mut others[..run]);
        let depth_scale = o.sigma_depth * step as f64;
        for t in 0..run {
            let cos = ax[t] * bx[t] + ay[t] * by[t] + az[t] * bz[t];
            // max(0, cos)^(σ·trust), with 0^0 = 1 as `powf` has it.
            normal_log[t] = if trust[t] <= 0.0 {
                0.0
            } else if cos > 0.0 {
                trust[t] * ln_fast(cos.max(f64::MIN_POSITIVE))
            } else {
                f64::NAN
            };
            let (zi, zj) = (za[t], zb[t]);
            others[t] = -(zi - zj).abs() / (depth_scale * zi.max(zj) + 1e-9) * trust[t];
        }
        if o.sigma_albedo.is_finite() {
            let scale = o.sigma_albedo * o.sigma_albedo;
            for t in 0..run {
                let (a, b) = (self.albedo[at + t], self.albedo[near + t]);
                let da: f64 = (0..3).map(|c| (a[c] - b[c]).powi(2)).sum();
                others[t] -= da / scale * trust[t];
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The filter as it was written first, one pixel at a time with libm's `exp` and `ln`: what
    /// the row-wise, SIMD-friendly [`Guide::smooth`] must agree with.
    fn smooth_one_pixel_at_a_time(
        guide: &Guide<'_>,
        mut parts: [Part; PARTS],
        rules: [PartRule; PARTS],
    ) -> [Part; PARTS] {
        let (w, h, o) = (guide.width, guide.height, guide.options);
        let normal =
            |i: usize| DVec3::new(guide.normal[0][i], guide.normal[1][i], guide.normal[2][i]);
        for pass in 0..o.passes {
            let step = 1usize << pass;
            let around: Vec<[f64; PARTS]> = (0..w * h)
                .map(|i| std::array::from_fn(|k| guide.blurred(i, &parts[k].variance)))
                .collect();
            let filtered: Vec<[(Rgb, f64); PARTS]> = (0..w * h)
                .map(|i| {
                    let (x, y) = ((i % w) as isize, (i / w) as isize);
                    let trust = guide.coherence[i];
                    let mut sums = [([0.0; 3], 0.0, 0.0); PARTS];
                    for (dy, ky) in KERNEL.iter().enumerate() {
                        for (dx, kx) in KERNEL.iter().enumerate() {
                            let (xx, yy) = (
                                x + (dx as isize - 2) * step as isize,
                                y + (dy as isize - 2) * step as isize,
                            );
                            if xx < 0 || yy < 0 || xx >= w as isize || yy >= h as isize {
                                continue;
                            }
                            let j = yy as usize * w + xx as usize;
                            let cos = normal(i).dot(normal(j));
                            let guides = if j == i || trust <= 0.0 {
                                Some((0.0, 0.0))
                            } else if cos > 0.0 {
                                Some((trust * cos.ln(), 0.0))
                            } else {
                                None
                            };
                            let Some((normal_log, _)) = guides else {
                                continue;
                            };
                            let (zi, zj) = (guide.depth[i], guide.depth[j]);
                            let depth = if j == i {
                                0.0
                            } else {
                                -(zi - zj).abs() / (o.sigma_depth * zi.max(zj) * step as f64 + 1e-9)
                                    * trust
                            };
                            for k in 0..PARTS {
                                let part = &parts[k];
                                let sharpness = match rules[k] {
                                    PartRule::Rest => o.sigma_normal_rest,
                                    _ => o.sigma_normal,
                                };
                                let tolerance = o.sigma_lighting * around[i][k].sqrt() + 1e-6;
                                let open = match rules[k] {
                                    PartRule::SeenDirectly => guide.openness[i] * guide.openness[j],
                                    _ => 1.0,
                                };
                                let weight = if j == i {
                                    kx * ky
                                } else {
                                    let light = -(luminance(part.lighting[i])
                                        - luminance(part.lighting[j]))
                                    .abs()
                                        / tolerance;
                                    open * kx * ky * (sharpness * normal_log + depth + light).exp()
                                };
                                if !(weight > 0.0 && (j == i || part.variance[j].is_finite())) {
                                    continue;
                                }
                                let (sum, weights, variance) = &mut sums[k];
                                for (s, l) in sum.iter_mut().zip(part.lighting[j]) {
                                    *s += weight * l;
                                }
                                *weights += weight;
                                *variance += weight * weight * part.variance[j];
                            }
                        }
                    }
                    std::array::from_fn(|k| {
                        let (sum, weights, variance) = sums[k];
                        (sum.map(|s| s / weights), variance / (weights * weights))
                    })
                })
                .collect();
            parts = std::array::from_fn(|k| Part {
                lighting: filtered.iter().map(|f| f[k].0).collect(),
                variance: filtered.iter().map(|f| f[k].1).collect(),
            });
        }
        parts
    }

    #[test]
    fn the_rows_in_simd_lanes_filter_as_one_pixel_at_a_time() {
        // Random guides and parts on an image of odd size (so that every tap's run is clipped
        // somewhere), with the cases the weights branch on: normals facing apart and missing
        // (nothing seen), coherences of 0, 1 and above the light's openness threshold,
        // unsampled pixels (infinite variance) and lighting far outside the tolerance.
        let (w, h) = (141usize, 23usize);
        let n = w * h;
        let mut sampler = crate::sampler::Sampler::new(99, 0, 0);
        let mut next = move || sampler.next_f64();
        let normal: Vec<DVec3> = (0..n)
            .map(|_| match (next() * 10.0) as u32 {
                0 => DVec3::ZERO,
                1 => -DVec3::Z,
                _ => DVec3::new(next() - 0.5, next() - 0.5, 2.0).normalize(),
            })
            .collect();
        let depth: Vec<f64> = (0..n).map(|_| 1.0 + 5.0 * next()).collect();
        let coherence: Vec<f64> = (0..n)
            .map(|_| match (next() * 5.0) as u32 {
                0 => 0.0,
                1 => 1.0,
                _ => next(),
            })
            .collect();
        let albedo = vec![[0.5; 3]; n];
        let part = |next: &mut dyn FnMut() -> f64| Part {
            lighting: (0..n)
                .map(|_| {
                    let scale = if next() < 0.1 { 50.0 } else { 1.0 };
                    [next() * scale, next() * scale, next() * scale]
                })
                .collect(),
            variance: (0..n)
                .map(|_| {
                    if next() < 0.05 {
                        f64::INFINITY
                    } else {
                        0.01 * next()
                    }
                })
                .collect(),
        };
        for passes in [1, 3, 5] {
            let options = DenoiseOptions {
                passes,
                ..DenoiseOptions::default()
            };
            let guide = Guide::new((w, h), &albedo, &normal, &depth, &coherence, &options);
            let rules = [
                PartRule::LightSample,
                PartRule::Rest,
                PartRule::SeenDirectly,
            ];
            let parts = [part(&mut next), part(&mut next), part(&mut next)];
            let copy = |parts: &[Part; PARTS]| {
                parts.each_ref().map(|p| Part {
                    lighting: p.lighting.clone(),
                    variance: p.variance.clone(),
                })
            };
            let fast = guide.smooth(copy(&parts), rules);
            let slow = smooth_one_pixel_at_a_time(&guide, parts, rules);
            for k in 0..PARTS {
                for i in 0..n {
                    let close = |a: f64, b: f64| {
                        a == b || (a - b).abs() <= 1e-9 * a.abs().max(b.abs()).max(1e-12)
                    };
                    for c in 0..3 {
                        let (a, b) = (fast[k].lighting[i][c], slow[k].lighting[i][c]);
                        assert!(
                            close(a, b),
                            "{passes} passes, part {k}, pixel {i}: {a} against {b}"
                        );
                    }
                    let (a, b) = (fast[k].variance[i], slow[k].variance[i]);
                    assert!(
                        close(a, b),
                        "{passes} passes, part {k}, pixel {i}'s variance: {a} against {b}"
                    );
                }
            }
        }
    }
}
