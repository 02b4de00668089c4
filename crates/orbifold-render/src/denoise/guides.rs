//! The guides that the render fills per pixel for the denoiser: the means of what camera paths
//! saw first (albedo, normal, geodesic depth through the mirrors), and the parts of their light
//! that the filter treats apart — the light seen directly ([`FirstHit::emitted`]), the first
//! surface's light sample ([`FirstHit::direct`]) and the rest — each with the running statistics
//! of its luminance, from which the filter takes its variance.
//!
//! Like the film, the guides keep each pixel's sums twice: of its own paths, and under the
//! render's reconstruction filter, so that the parts add up to the film's pixel and the guides
//! blur as the image does.
//!
//! A pixel's *coherence* ([`GuideSums::coherence`]) says how much its paths agree on what they
//! saw first: 1 where they all saw one surface, near 0 where the pixel covers many things
//! smaller than itself (the crowd of far mirror images at a hyperbolic room's horizon), whose
//! mean normal is short and whose depths spread. The filter trusts a pixel's guides only as much
//! as its paths agree.

use glam::DVec3;

use crate::film::{PixelFilter, RunningStats, Splat};
use crate::integrator::FirstHit;
use crate::lights::Rgb;
use orbifold_scene::color::luminance;

#[cfg(doc)]
use crate::film::Film;

/// The per-pixel means of what camera paths saw first, and the parts of their radiance that the
/// denoiser treats apart: the light seen directly, and the mean and variance of the first
/// surface's light sample and of the rest. The means are weighted by the film's reconstruction
/// filter as the film's are ([`Guides::splat`]), so that the parts add up to the film's pixel.
#[derive(Clone, Debug)]
pub struct Guides {
    /// The image's size in pixels.
    pub(super) width: u32,
    pub(super) height: u32,
    /// Each pixel's own paths.
    own: Vec<GuideSums>,
    /// The same under the reconstruction filter (as [`Film`]'s): what the denoiser reads.
    pub(super) pixels: Vec<GuideSums>,
    /// The reconstruction filter that `pixels` are under.
    filter: PixelFilter,
}

/// What one pixel has summed of the paths that count for it, each times its weight.
#[derive(Clone, Copy, Debug, Default)]
pub(super) struct GuideSums {
    albedo: Rgb,
    normal: DVec3,
    /// Σ of the depth and of its square.
    depth: f64,
    depth2: f64,
    /// Σ of the light seen directly.
    emitted: Rgb,
    /// Σ of the first surface's light sample.
    direct: Rgb,
    /// The luminance statistics of the light seen directly (which the filter leaves as it is
    /// where the pixel's paths agree on what they saw: there its noise stays in the denoised
    /// image), of the light sample and of the rest of the reflected light.
    pub(super) emitted_stats: RunningStats,
    pub(super) direct_stats: RunningStats,
    pub(super) rest_stats: RunningStats,
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

    /// The weighted mean depth.
    fn mean_depth(&self) -> f64 {
        if self.weight > 0.0 {
            self.depth / self.weight
        } else {
            0.0
        }
    }

    /// The standard error of the weighted mean of the values that `stats` follows.
    pub(super) fn standard_error(&self, stats: &RunningStats) -> f64 {
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

    /// [`Guides::emitted`] of the pixel at index `i` (row by row), as the denoiser reads it.
    pub(super) fn mean_emitted(&self, i: usize) -> Rgb {
        let p = &self.pixels[i];
        p.mean(p.emitted)
    }

    /// The mean of the first surface's light sample at pixel (x, y) ([`FirstHit::direct`]).
    pub fn direct(&self, x: u32, y: u32) -> Rgb {
        let i = self.index(x, y);
        self.mean_direct(i)
    }

    /// [`Guides::direct`] of the pixel at index `i` (row by row).
    pub(super) fn mean_direct(&self, i: usize) -> Rgb {
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

    /// [`Guides::albedo`] of the pixel at index `i` (row by row).
    pub(super) fn mean_albedo(&self, i: usize) -> Rgb {
        let p = &self.pixels[i];
        p.mean(p.albedo)
    }

    /// The direction of the mean normal at the pixel at index `i` (row by row); zero where the
    /// normals cancel or nothing was seen.
    pub(super) fn mean_normal(&self, i: usize) -> DVec3 {
        self.pixels[i].normal.normalize_or_zero()
    }

    /// The mean geodesic depth at the pixel at index `i` (row by row).
    pub(super) fn mean_depth(&self, i: usize) -> f64 {
        self.pixels[i].mean_depth()
    }

    /// [`GuideSums::coherence`] of the pixel at index `i` (row by row).
    pub(super) fn coherence(&self, i: usize) -> f64 {
        self.pixels[i].coherence()
    }
}

/// How strongly a pixel's relative depth spread lowers its coherence.
const COHERENCE_DEPTH: f64 = 4.0;
