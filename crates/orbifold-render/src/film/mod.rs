//! The HDR film: per-pixel accumulation of radiance samples, noise estimates, and output as
//! OpenEXR (linear) or PNG (tone-mapped).
//!
//! Pixel (0, 0) is the top-left corner; x grows to the right and y downwards, as in the image
//! files. Every sample belongs to the pixel it was taken for; a pixel's value is its own samples'
//! mean under the box filter ([`Film::add`]), or under a wider reconstruction filter
//! ([`Film::splat`], [`PixelFilter`]) the filter's weighted mean of its
//! neighbours' means, each an unbiased estimate whatever its pixel's number of samples.
//!
//! **Parallel use.** A [`Film`] is plain data: each rayon task can fill a film of its own (or a
//! whole-image film it owns) and the results are combined with [`Film::merge`]; or the tasks
//! return rows of radiance that are added in a fixed order with [`Film::add_row`], which keeps
//! the image bit-for-bit independent of the thread schedule.
//!
//! **Noise.** Beside the weighted RGB sums the film keeps, per pixel, the sums of the weights and
//! of their squares, and the weighted running mean and sum of squared deviations of the sample
//! luminance (West's weighted form of Welford's method, merged with Chan et al.'s formula), from
//! which [`Film::standard_error`] and [`Film::relative_noise`] are computed: the variance of a
//! weighted mean of independent samples is s²·Σw²/(Σw)².

mod accumulator;
pub mod filter;
mod output;
mod statistics;
mod tone;

use orbifold_scene::color::luminance;
use rayon::prelude::*;

use accumulator::Accumulator;
pub use filter::PixelFilter;
pub(crate) use statistics::RunningStats;
pub use tone::{tone_curve, tone_map};

/// The offset in the denominator of [`Film::relative_noise`], so that black pixels do not
/// dominate the mean.
pub const NOISE_LUMINANCE_OFFSET: f64 = 1e-2;

/// An HDR image being accumulated from radiance samples.
///
/// ```
/// use orbifold_render::film::Film;
///
/// let mut film = Film::new(4, 3);
/// film.add(1, 2, [1.0, 2.0, 3.0]);
/// film.add(1, 2, [3.0, 2.0, 1.0]);
/// assert_eq!(film.pixel(1, 2), [2.0, 2.0, 2.0]);
/// assert_eq!(film.samples(1, 2), 2);
/// assert_eq!(film.pixel(0, 0), [0.0, 0.0, 0.0]);
/// ```
#[derive(Clone, Debug, PartialEq)]
pub struct Film {
    width: u32,
    height: u32,
    /// What each pixel has summed of its own samples.
    own: Vec<Accumulator>,
    /// The same under the reconstruction filter: what the pixel's value and error are read from.
    pixels: Vec<Accumulator>,
    /// The reconstruction filter.
    filter: PixelFilter,
    /// The number of (finite) samples taken for each pixel (whatever other pixels they count for).
    count: Vec<u64>,
    /// Samples with a non-finite component, counted and not stored.
    dropped: u64,
}

/// A radiance sample for [`Film::splat_all`]: taken for pixel (`x`, `y`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Splat {
    /// The pixel's column.
    pub x: u32,
    /// The pixel's row.
    pub y: u32,
    /// Its radiance.
    pub radiance: [f64; 3],
}

impl Film {
    /// An empty (black, sample-free) film of `width` × `height` pixels.
    ///
    /// ```
    /// use orbifold_render::film::Film;
    ///
    /// let film = Film::new(8, 6);
    /// assert_eq!((film.width(), film.height()), (8, 6));
    /// ```
    pub fn new(width: u32, height: u32) -> Film {
        let n = width as usize * height as usize;
        Film {
            width,
            height,
            own: vec![Accumulator::default(); n],
            pixels: vec![Accumulator::default(); n],
            filter: PixelFilter::Box,
            count: vec![0; n],
            dropped: 0,
        }
    }

    /// A film holding `pixels` (row by row, top row first) as one sample each: what a filter
    /// such as the denoiser makes of a film.
    ///
    /// # Panics
    ///
    /// If there are not `width × height` pixels.
    ///
    /// ```
    /// use orbifold_render::film::Film;
    ///
    /// let film = Film::from_pixels(2, 1, &[[0.5; 3], [1.0, 0.0, 0.0]]);
    /// assert_eq!(film.pixel(1, 0), [1.0, 0.0, 0.0]);
    /// assert_eq!(film.samples(0, 0), 1);
    /// ```
    pub fn from_pixels(width: u32, height: u32, pixels: &[[f64; 3]]) -> Film {
        assert_eq!(
            pixels.len(),
            width as usize * height as usize,
            "one value per pixel"
        );
        let mut film = Film::new(width, height);
        for (i, p) in pixels.iter().enumerate() {
            film.add_at(i, *p);
        }
        film
    }

    /// The width in pixels.
    ///
    /// ```
    /// use orbifold_render::film::Film;
    ///
    /// assert_eq!(Film::new(8, 6).width(), 8);
    /// ```
    pub fn width(&self) -> u32 {
        self.width
    }

    /// The height in pixels.
    ///
    /// ```
    /// use orbifold_render::film::Film;
    ///
    /// assert_eq!(Film::new(8, 6).height(), 6);
    /// ```
    pub fn height(&self) -> u32 {
        self.height
    }

    fn index(&self, x: u32, y: u32) -> usize {
        assert!(
            x < self.width && y < self.height,
            "pixel ({x}, {y}) outside a {}×{} film",
            self.width,
            self.height
        );
        y as usize * self.width as usize + x as usize
    }

    /// Adds one radiance sample to pixel (x, y), for that pixel only (the box filter). A sample
    /// with a NaN or infinite component is not stored (the pixel is unchanged, its sample count
    /// too) and is counted in [`Film::dropped`].
    ///
    /// # Panics
    ///
    /// If (x, y) is outside the film.
    ///
    /// ```
    /// use orbifold_render::film::Film;
    ///
    /// let mut film = Film::new(2, 2);
    /// film.add(0, 1, [0.5, 0.5, 0.5]);
    /// film.add(0, 1, [f64::NAN, 0.0, 0.0]);
    /// assert_eq!(film.pixel(0, 1), [0.5, 0.5, 0.5]);
    /// assert_eq!(film.dropped(), 1);
    /// ```
    pub fn add(&mut self, x: u32, y: u32, radiance: [f64; 3]) {
        let i = self.index(x, y);
        self.add_at(i, radiance);
    }

    fn add_at(&mut self, i: usize, radiance: [f64; 3]) {
        if !radiance.iter().all(|c| c.is_finite()) {
            self.dropped += 1;
            return;
        }
        self.count[i] += 1;
        self.own[i].add(radiance, 1.0);
        self.filter_around(i);
    }

    /// The pixels' filtered sums afresh from their own (after a batch of samples).
    fn filter_all(&mut self) {
        let size = (self.width, self.height);
        self.filter.filter_all(
            &self.own,
            &mut self.pixels,
            size,
            |p| p.weight,
            |into, from, factor| into.merge(&from.scaled(factor)),
        );
    }

    /// The filtered sums afresh of the pixels that pixel index `i`'s own samples count for.
    fn filter_around(&mut self, i: usize) {
        let w = self.width as usize;
        let at = ((i % w) as u32, (i / w) as u32);
        self.filter.filter_around(
            &self.own,
            &mut self.pixels,
            (self.width, self.height),
            at,
            |p| p.weight,
            |into, from, factor| into.merge(&from.scaled(factor)),
        );
    }

    /// Uses `filter` from now on (all pixels are filtered afresh if it changes).
    fn set_filter(&mut self, filter: PixelFilter) {
        if filter != self.filter {
            self.filter = filter;
            self.filter_all();
        }
    }

    /// Adds a sample taken for pixel (x, y) under the reconstruction filter `filter`: it is one
    /// more of pixel (x, y)'s samples ([`Film::samples`]), and the filter counts that pixel's
    /// mean for the pixels near it. Non-finite samples are dropped as by [`Film::add`]. With
    /// [`PixelFilter::Box`] this is [`Film::add`].
    ///
    /// # Panics
    ///
    /// If (x, y) is outside the film.
    ///
    /// ```
    /// use orbifold_render::film::Film;
    /// use orbifold_render::film::PixelFilter;
    ///
    /// let mut film = Film::new(3, 3);
    /// film.splat(1, 1, [1.0; 3], PixelFilter::GAUSSIAN);
    /// // Every pixel now has the sample's value; only the middle one has a sample of its own.
    /// assert_eq!(film.pixel(0, 2), [1.0; 3]);
    /// assert_eq!((film.samples(1, 1), film.samples(0, 2)), (1, 0));
    /// // A neighbour's many samples count no more than its one sample did.
    /// for _ in 0..99 {
    ///     film.splat(0, 1, [4.0; 3], PixelFilter::GAUSSIAN);
    /// }
    /// film.splat(1, 0, [4.0; 3], PixelFilter::GAUSSIAN);
    /// // The middle pixel: its own 1 and its two sampled neighbours' 4, weighted alike.
    /// let middle = film.pixel(1, 1)[0];
    /// assert!(middle > 1.5 && middle < 2.0, "{middle}");
    /// ```
    pub fn splat(&mut self, x: u32, y: u32, radiance: [f64; 3], filter: PixelFilter) {
        let own = self.index(x, y);
        self.set_filter(filter);
        self.add_at(own, radiance);
    }

    /// [`Film::splat`] for many samples at once (the pixels near the samples' pixels are
    /// filtered afresh once, in parallel over rows, at the end; the others keep their value).
    ///
    /// # Panics
    ///
    /// If a sample's pixel is outside the film.
    ///
    /// ```
    /// use orbifold_render::film::{Film, Splat};
    /// use orbifold_render::film::PixelFilter;
    ///
    /// let samples = [
    ///     Splat { x: 1, y: 0, radiance: [1.0; 3] },
    ///     Splat { x: 0, y: 1, radiance: [3.0; 3] },
    /// ];
    /// let (mut one_by_one, mut at_once) = (Film::new(3, 2), Film::new(3, 2));
    /// for s in &samples {
    ///     one_by_one.splat(s.x, s.y, s.radiance, PixelFilter::GAUSSIAN);
    /// }
    /// at_once.splat_all(&samples, PixelFilter::GAUSSIAN);
    /// assert_eq!(one_by_one, at_once);
    /// ```
    pub fn splat_all(&mut self, samples: &[Splat], filter: PixelFilter) {
        for s in samples {
            self.index(s.x, s.y);
        }
        let mut changed = (filter == self.filter).then(|| vec![false; self.own.len()]);
        self.filter = filter;
        for s in samples {
            if !s.radiance.iter().all(|c| c.is_finite()) {
                self.dropped += 1;
                continue;
            }
            let i = self.index(s.x, s.y);
            self.count[i] += 1;
            self.own[i].add(s.radiance, 1.0);
            if let Some(changed) = &mut changed {
                changed[i] = true;
            }
        }
        self.filter.filter_changed(
            &self.own,
            &mut self.pixels,
            (self.width, self.height),
            changed.as_deref(),
            |p| p.weight,
            |into, from, factor| into.merge(&from.scaled(factor)),
        );
    }

    /// Adds one sample to every pixel of row `y`: `row[x]` goes to pixel (x, y). Convenient with
    /// rayon: compute rows in parallel, then add them in order (see the module documentation).
    ///
    /// # Panics
    ///
    /// If `y` is outside the film or `row.len()` is not the width.
    ///
    /// ```
    /// use orbifold_render::film::Film;
    ///
    /// let mut film = Film::new(3, 2);
    /// film.add_row(1, &[[1.0; 3], [2.0; 3], [3.0; 3]]);
    /// assert_eq!(film.pixel(2, 1), [3.0; 3]);
    /// assert_eq!(film.samples(0, 0), 0);
    /// ```
    pub fn add_row(&mut self, y: u32, row: &[[f64; 3]]) {
        assert_eq!(
            row.len(),
            self.width as usize,
            "a row of {} samples for a film {} pixels wide",
            row.len(),
            self.width
        );
        if self.width == 0 {
            return;
        }
        let start = self.index(0, y);
        for (k, radiance) in row.iter().enumerate() {
            self.add_at(start + k, *radiance);
        }
    }

    /// Adds all the samples of `other` (a film of the same size, e.g. one thread's share):
    /// afterwards the means, sample counts, standard errors and dropped count are those of a
    /// film that received both sets of samples (up to rounding).
    ///
    /// # Panics
    ///
    /// If the sizes differ.
    ///
    /// ```
    /// use orbifold_render::film::Film;
    ///
    /// let mut a = Film::new(1, 1);
    /// let mut b = Film::new(1, 1);
    /// a.add(0, 0, [1.0; 3]);
    /// b.add(0, 0, [3.0; 3]);
    /// a.merge(&b);
    /// assert_eq!(a.pixel(0, 0), [2.0; 3]);
    /// assert_eq!(a.samples(0, 0), 2);
    /// ```
    pub fn merge(&mut self, other: &Film) {
        assert!(
            self.width == other.width && self.height == other.height,
            "merging a {}×{} film into a {}×{} one",
            other.width,
            other.height,
            self.width,
            self.height
        );
        for (i, pixel) in self.own.iter_mut().enumerate() {
            self.count[i] += other.count[i];
            pixel.merge(&other.own[i]);
        }
        self.dropped += other.dropped;
        if other.filter != PixelFilter::Box {
            self.filter = other.filter;
        }
        self.filter_all();
    }

    /// The mean radiance of pixel (x, y); black when it has no samples.
    ///
    /// # Panics
    ///
    /// If (x, y) is outside the film.
    ///
    /// ```
    /// use orbifold_render::film::Film;
    ///
    /// let mut film = Film::new(1, 1);
    /// film.add(0, 0, [1.0, 0.0, 0.0]);
    /// film.add(0, 0, [0.0, 0.0, 0.0]);
    /// assert_eq!(film.pixel(0, 0), [0.5, 0.0, 0.0]);
    /// ```
    pub fn pixel(&self, x: u32, y: u32) -> [f64; 3] {
        self.mean_at(self.index(x, y))
    }

    fn mean_at(&self, i: usize) -> [f64; 3] {
        let p = &self.pixels[i];
        if p.weight == 0.0 {
            return [0.0; 3];
        }
        p.sum.map(|s| s / p.weight)
    }

    /// The number of samples taken for pixel (x, y) (dropped ones are not counted); with a
    /// filter wider than the box, samples of its neighbours count for it too.
    ///
    /// # Panics
    ///
    /// If (x, y) is outside the film.
    ///
    /// ```
    /// use orbifold_render::film::Film;
    ///
    /// let mut film = Film::new(1, 1);
    /// film.add(0, 0, [1.0; 3]);
    /// film.add(0, 0, [f64::INFINITY; 3]);
    /// assert_eq!(film.samples(0, 0), 1);
    /// ```
    pub fn samples(&self, x: u32, y: u32) -> u64 {
        self.count[self.index(x, y)]
    }

    /// The number of non-finite samples that were dropped (including those of merged films).
    ///
    /// ```
    /// use orbifold_render::film::Film;
    ///
    /// let mut film = Film::new(1, 1);
    /// film.add(0, 0, [0.0, f64::NEG_INFINITY, 0.0]);
    /// assert_eq!(film.dropped(), 1);
    /// ```
    pub fn dropped(&self) -> u64 {
        self.dropped
    }

    /// The variance of the weighted mean luminance at pixel index `i`: s²·Σw²/(Σw)², with the
    /// unbiased weighted sample variance s² = M2/(Σw − Σw²/Σw) (for unit weights M2/(n − 1) and
    /// s²/n); `None` while the samples' effective number (Σw)²/Σw² is at most one.
    /// The variance of pixel `i`'s mean luminance. Under a reconstruction filter the pixel is a
    /// fixed weighted mean Σ Kⱼ mⱼ / Σ Kⱼ of its neighbours' means, each from its own samples,
    /// so its variance is Σ Kⱼ² vⱼ / (Σ Kⱼ)². Pooling the neighbours' samples into one variance
    /// instead would count the difference between their means — an edge, a light image's rim —
    /// as noise that no number of samples takes away (measured in docs/benchmarks.md). Where a
    /// neighbour has fewer than two samples, the pooled variance stands in.
    fn mean_variance_at(&self, i: usize) -> Option<f64> {
        let p = &self.pixels[i];
        if self.filter != PixelFilter::Box && p.mean_variance.is_finite() && p.weight > 0.0 {
            return Some(p.mean_variance / (p.weight * p.weight));
        }
        p.own_mean_variance()
    }

    /// The standard error of the mean luminance of pixel (x, y): √(s²/n), with s² the unbiased
    /// sample variance of the luminance (Rec. 709 weights, see [`luminance`]) of its n samples;
    /// under a reconstruction filter, whose pixel is the weighted mean Σ Kⱼ mⱼ / Σ Kⱼ of its
    /// neighbours' means, √(Σ Kⱼ² sⱼ²/nⱼ)/Σ Kⱼ (or, where a neighbour has a single sample, that
    /// of all the samples pooled, √(s²·Σw²)/Σw). Infinite when the pixel has fewer than two
    /// samples (the error is then unknown).
    ///
    /// # Panics
    ///
    /// If (x, y) is outside the film.
    ///
    /// ```
    /// use orbifold_render::film::Film;
    ///
    /// let mut film = Film::new(1, 1);
    /// film.add(0, 0, [0.0; 3]);
    /// assert_eq!(film.standard_error(0, 0), f64::INFINITY);
    /// film.add(0, 0, [2.0; 3]);
    /// // s² = 2, n = 2: standard error 1.
    /// assert!((film.standard_error(0, 0) - 1.0).abs() < 1e-12);
    /// ```
    pub fn standard_error(&self, x: u32, y: u32) -> f64 {
        let i = self.index(x, y);
        self.standard_error_at(i)
    }

    fn standard_error_at(&self, i: usize) -> f64 {
        match self.mean_variance_at(i) {
            Some(v) => v.sqrt(),
            None => f64::INFINITY,
        }
    }

    /// The standard error of every pixel as seen on screen, in 8-bit display levels at
    /// `exposure`: how far one standard error of its luminance moves the tone-mapped value
    /// (the larger of the steps up and down; 0 where the tone curve has saturated), row by row.
    /// Infinite for pixels with fewer than two samples.
    ///
    /// ```
    /// use orbifold_render::film::Film;
    ///
    /// let mut film = Film::new(2, 1);
    /// for v in [0.1, 0.3, 0.1, 0.3] {
    ///     film.add(0, 0, [v; 3]);
    ///     film.add(1, 0, [1e3 * v; 3]);
    /// }
    /// let levels = film.display_errors(0.0);
    /// assert!(levels[0] > 5.0 && levels[1] == 0.0);
    /// ```
    pub fn display_errors(&self, exposure: f64) -> Vec<f64> {
        // Each pixel on its own: in parallel, the same values as one after another.
        (0..self.count.len())
            .into_par_iter()
            .map(|i| {
                let se = self.standard_error_at(i);
                if !se.is_finite() {
                    return f64::INFINITY;
                }
                let l = luminance(self.mean_at(i)).max(0.0);
                let at = tone_curve(l, exposure);
                let up = tone_curve(l + se, exposure) - at;
                let down = at - tone_curve((l - se).max(0.0), exposure);
                255.0 * up.max(down)
            })
            .collect()
    }

    /// How far one sample of each pixel's own (not its neighbours', whatever the filter) moves
    /// that pixel's own mean on screen, in 8-bit display levels at `exposure`: the step that one
    /// standard deviation of its samples' luminance makes through the tone curve (the larger
    /// of the steps up and down), row by row. Infinite for pixels with fewer than two samples.
    /// What the adaptive sampler allocates by: it depends on that pixel's samples alone.
    ///
    /// ```
    /// use orbifold_render::film::{Film, PixelFilter};
    ///
    /// let mut film = Film::new(2, 1);
    /// for v in [0.1, 0.3, 0.1, 0.3] {
    ///     film.splat(0, 0, [v; 3], PixelFilter::GAUSSIAN);
    ///     film.splat(1, 0, [0.2; 3], PixelFilter::GAUSSIAN);
    /// }
    /// let levels = film.sample_display_noise(0.0);
    /// // Pixel 1's own samples agree, whatever its neighbour's do.
    /// assert!(levels[0] > 5.0 && levels[1] == 0.0);
    /// ```
    pub fn sample_display_noise(&self, exposure: f64) -> Vec<f64> {
        self.own
            .par_iter()
            .map(|own| {
                let Some(variance) = own.sample_variance() else {
                    return f64::INFINITY;
                };
                let (l, sd) = (own.mean_luminance().max(0.0), variance.sqrt());
                let at = tone_curve(l, exposure);
                let up = tone_curve(l + sd, exposure) - at;
                let down = at - tone_curve((l - sd).max(0.0), exposure);
                255.0 * up.max(down)
            })
            .collect()
    }

    /// A summary of the noise of the image: the mean over all pixels of
    ///
    /// SE(x, y) / (max(L(x, y), 0) + 0.01),
    ///
    /// where L is the luminance of the pixel's mean radiance and SE its standard error (see
    /// [`Film::standard_error`]); the offset is [`NOISE_LUMINANCE_OFFSET`]. Roughly the typical
    /// relative error of a pixel, with dark pixels counted against an absolute error of 0.01.
    /// Infinite when some pixel has fewer than two samples; 0 for a film without pixels.
    ///
    /// ```
    /// use orbifold_render::film::Film;
    ///
    /// let mut film = Film::new(2, 1);
    /// for _ in 0..4 {
    ///     film.add(0, 0, [1.0; 3]);
    ///     film.add(1, 0, [1.0; 3]);
    /// }
    /// assert_eq!(film.relative_noise(), 0.0);
    /// film.add(1, 0, [6.0; 3]);
    /// assert!(film.relative_noise() > 0.0);
    /// ```
    pub fn relative_noise(&self) -> f64 {
        let n = self.count.len();
        if n == 0 {
            return 0.0;
        }
        let total: f64 = (0..n)
            .map(|i| {
                let l = luminance(self.mean_at(i)).max(0.0);
                self.standard_error_at(i) / (l + NOISE_LUMINANCE_OFFSET)
            })
            .sum();
        total / n as f64
    }
}
