//! Pixel reconstruction filters: how much a radiance sample taken at a point of the image counts
//! for each pixel near it (pbrt-v4 §8.8, "Image Reconstruction").
//!
//! A pixel's value is the weighted mean Σ w(xᵢ − c) Lᵢ / Σ w(xᵢ − c) of the samples xᵢ around its
//! centre c. The **box** of one pixel counts every sample for its own pixel only. The
//! **Gaussian** (σ = 0.5 pixel, cut off at 1.5 pixels: the default of pbrt-v4; Mitsuba 3's
//! default is the same Gaussian cut off at 2 pixels) lets a sample count for the pixels within
//! 1.5 pixels of it, by how near it is to their centres.
//! Each pixel then averages the samples of about π·1.5² pixels: for independent noise its
//! variance is about a third of the box's (1/(4πσ²) for the untruncated Gaussian), and detail
//! finer than a pixel — the crowd of far mirror images at a hyperbolic room's horizon — is
//! filtered out rather than aliased into grain. The price is a slightly softer image (the
//! Gaussian's response at the Nyquist frequency is 0.29, the box's 0.64).
//!
//! Both filters are non-negative, so the weighted means stay convex combinations of samples and
//! their standard errors keep their meaning ([`crate::film::Film::standard_error`]).

use arrayvec::ArrayVec;
use orbifold_scene::ReconstructionFilter;
use rayon::prelude::*;

/// Most pixels one sample counts for: a radius of at most two pixels reaches at most four pixel
/// centres along each axis (the default Gaussian's 1.5 pixels, three).
pub const MOST_PIXELS: usize = 16;

/// A pixel reconstruction filter.
///
/// ```
/// use orbifold_render::filter::PixelFilter;
///
/// // A sample at the centre of pixel (4, 4) counts most for that pixel, and a little for its
/// // neighbours.
/// let weights = PixelFilter::default().footprint(4, 4, (0.5, 0.5), 16, 16);
/// let own = weights.iter().find(|&&(x, y, _)| (x, y) == (4, 4)).unwrap().2;
/// assert!(weights.len() == 9 && weights.iter().all(|&(_, _, w)| w <= own));
/// // The box counts it for its own pixel only.
/// assert_eq!(PixelFilter::Box.footprint(4, 4, (0.5, 0.5), 16, 16).as_slice(), &[(4, 4, 1.0)]);
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum PixelFilter {
    /// Every sample counts for its own pixel only, with weight 1.
    Box,
    /// exp(−d²/2σ²) − exp(−r²/2σ²) along each axis (zero beyond the radius r), in pixels.
    Gaussian {
        /// Standard deviation in pixels.
        sigma: f64,
        /// Where the filter is cut off, in pixels: more than ½ (so that a sample always counts
        /// for its own pixel) and at most 2 (pixels beyond four along an axis are left out).
        radius: f64,
    },
}

impl Default for PixelFilter {
    /// The Gaussian of σ = 0.5 and radius 1.5 pixels ([`PixelFilter::GAUSSIAN`]).
    fn default() -> Self {
        PixelFilter::GAUSSIAN
    }
}

impl From<ReconstructionFilter> for PixelFilter {
    /// The filter a scene's `[render]` table names.
    ///
    /// ```
    /// use orbifold_render::filter::PixelFilter;
    /// use orbifold_scene::ReconstructionFilter;
    ///
    /// assert_eq!(PixelFilter::from(ReconstructionFilter::Box), PixelFilter::Box);
    /// assert_eq!(PixelFilter::from(ReconstructionFilter::default()), PixelFilter::GAUSSIAN);
    /// ```
    fn from(filter: ReconstructionFilter) -> Self {
        match filter {
            ReconstructionFilter::Gaussian => PixelFilter::GAUSSIAN,
            ReconstructionFilter::Box => PixelFilter::Box,
        }
    }
}

impl PixelFilter {
    /// The Gaussian of pbrt-v4: σ = 0.5 pixel, cut off at 1.5 pixels.
    pub const GAUSSIAN: PixelFilter = PixelFilter::Gaussian {
        sigma: 0.5,
        radius: 1.5,
    };

    /// The filter named `name`: `box` or `gaussian` ([`PixelFilter::GAUSSIAN`]).
    ///
    /// ```
    /// use orbifold_render::filter::PixelFilter;
    ///
    /// assert_eq!(PixelFilter::from_name("box"), Ok(PixelFilter::Box));
    /// assert!(PixelFilter::from_name("mitchell").unwrap_err().contains("box, gaussian"));
    /// ```
    pub fn from_name(name: &str) -> Result<PixelFilter, String> {
        match name {
            "box" => Ok(PixelFilter::Box),
            "gaussian" => Ok(PixelFilter::GAUSSIAN),
            other => Err(format!(
                "unknown pixel filter '{other}' (the filters are: box, gaussian)"
            )),
        }
    }

    /// The filter's name, as [`PixelFilter::from_name`] reads it (`gaussian` whatever its σ and
    /// radius).
    ///
    /// ```
    /// use orbifold_render::filter::PixelFilter;
    ///
    /// assert_eq!(PixelFilter::default().name(), "gaussian");
    /// assert_eq!(PixelFilter::from_name("box").unwrap().name(), "box");
    /// ```
    pub fn name(self) -> &'static str {
        match self {
            PixelFilter::Box => "box",
            PixelFilter::Gaussian { .. } => "gaussian",
        }
    }

    /// The weight along one axis of a sample `d` pixels from a pixel's centre.
    fn weight_1d(self, d: f64) -> f64 {
        match self {
            PixelFilter::Box => f64::from(u8::from(d.abs() <= 0.5)),
            PixelFilter::Gaussian { sigma, radius } => {
                if d.abs() >= radius {
                    return 0.0;
                }
                let g = |x: f64| (-x * x / (2.0 * sigma * sigma)).exp();
                (g(d) - g(radius)).max(0.0)
            }
        }
    }

    /// The pixels that a sample taken for pixel (`x`, `y`) at `offset` ∈ [0, 1)² within it counts
    /// for, with their weights (positive; the sample's own pixel is always among them), on a
    /// `width` × `height` image.
    pub fn footprint(
        self,
        x: u32,
        y: u32,
        offset: (f64, f64),
        width: u32,
        height: u32,
    ) -> ArrayVec<(u32, u32, f64), MOST_PIXELS> {
        let mut pixels = ArrayVec::new();
        let across = self.axis_weights(x, offset.0, width);
        for (j, wy) in self.axis_weights(y, offset.1, height) {
            for &(i, wx) in &across {
                pixels.push((i, j, wx * wy));
            }
        }
        pixels
    }

    /// Along one axis of `size` pixels, the pixels that a sample at `offset` within pixel
    /// `pixel` counts for, with the filter's weight along that axis (the box: its own, 1).
    fn axis_weights(self, pixel: u32, offset: f64, size: u32) -> ArrayVec<(u32, f64), 4> {
        let mut weights = ArrayVec::new();
        let PixelFilter::Gaussian { radius, .. } = self else {
            weights.push((pixel, 1.0));
            return weights;
        };
        // Pixel k's centre is at k + ½; the sample at pixel + offset.
        let at = f64::from(pixel) + offset;
        let first = (at - radius - 0.5).ceil().max(0.0) as u32;
        let last = ((at + radius - 0.5).floor() as u32).min(size - 1);
        for k in first..=last {
            let w = self.weight_1d(at - (f64::from(k) + 0.5));
            if w > 0.0 && !weights.is_full() {
                weights.push((k, w));
            }
        }
        weights
    }

    /// How many rows above and below its own a sample can count for.
    fn reach(self) -> u32 {
        match self {
            PixelFilter::Box => 0,
            PixelFilter::Gaussian { radius, .. } => (radius - 0.5).max(0.0).ceil() as u32,
        }
    }

    /// Adds `samples` (in row order) to the per-pixel `state` of a `width` × `height` image,
    /// row by row in parallel: `add(pixel, sample, weight)` for every pixel that `place(sample)`
    /// = (column, row, offset) counts for. Each pixel receives its samples in `samples`' order,
    /// so the result does not depend on the number of threads.
    ///
    /// # Panics
    ///
    /// If the samples are not in row order (the rows they count for are found by bisection) or
    /// `state` does not hold `width` × `height` pixels.
    pub(crate) fn splat_rows<S: Sync, P: Send>(
        self,
        state: &mut [P],
        (width, height): (u32, u32),
        samples: &[S],
        place: impl Fn(&S) -> (u32, u32, (f64, f64)) + Sync,
        add: impl Fn(&mut P, &S, f64) + Sync,
    ) {
        assert_eq!(
            state.len(),
            width as usize * height as usize,
            "one state a pixel"
        );
        assert!(
            samples.windows(2).all(|p| place(&p[0]).1 <= place(&p[1]).1),
            "samples to splat must be in row order"
        );
        if width == 0 {
            return;
        }
        let reach = self.reach();
        state
            .par_chunks_mut(width as usize)
            .enumerate()
            .for_each(|(y, row)| {
                let y = y as u32;
                let start = samples.partition_point(|s| place(s).1 + reach < y);
                let end = samples.partition_point(|s| place(s).1 <= y + reach);
                for sample in &samples[start..end] {
                    let (sx, sy, offset) = place(sample);
                    let wy = self.weight_1d(f64::from(sy) + offset.1 - (f64::from(y) + 0.5));
                    if wy <= 0.0 {
                        continue;
                    }
                    for (x, wx) in self.axis_weights(sx, offset.0, width) {
                        add(&mut row[x as usize], sample, wx * wy);
                    }
                }
            });
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_gaussian_reaches_the_pixels_within_its_radius_and_no_others() {
        let filter = PixelFilter::GAUSSIAN;
        for (offset, wanted) in [((0.5, 0.5), 9), ((0.05, 0.95), 9), ((0.0, 0.0), 4)] {
            let pixels = filter.footprint(10, 10, offset, 32, 32);
            assert_eq!(pixels.len(), wanted, "{offset:?}");
            for &(i, j, w) in &pixels {
                let dx = 10.0 + offset.0 - (f64::from(i) + 0.5);
                let dy = 10.0 + offset.1 - (f64::from(j) + 0.5);
                assert!(dx.abs() < 1.5 && dy.abs() < 1.5 && w > 0.0, "{i} {j} {w}");
            }
            assert!(pixels.iter().any(|&(i, j, _)| (i, j) == (10, 10)));
        }
    }

    #[test]
    fn the_footprint_stays_on_the_image() {
        let pixels = PixelFilter::GAUSSIAN.footprint(0, 5, (0.1, 0.9), 6, 6);
        assert!(pixels.iter().all(|&(i, j, _)| i < 6 && j < 6));
        assert_eq!(pixels.len(), 4);
    }

    #[test]
    fn the_weights_fall_with_distance() {
        let filter = PixelFilter::GAUSSIAN;
        let w = |d: f64| filter.weight_1d(d);
        assert!(w(0.0) > w(0.5) && w(0.5) > w(1.0) && w(1.0) > w(1.4));
        assert_eq!(w(1.5), 0.0);
        assert_eq!(w(-0.3), w(0.3));
    }
}
