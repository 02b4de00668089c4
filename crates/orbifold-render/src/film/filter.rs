//! Pixel reconstruction filters: how much a radiance sample taken at a point of the image counts
//! for each pixel near it (pbrt-v4 §8.8, "Image Reconstruction").
//!
//! The **box** of one pixel takes each pixel's value as the mean of its own samples. The
//! **Gaussian** (σ = 0.5 pixel, cut off at 1.5 pixels: the default of pbrt-v4; Mitsuba 3's
//! default is the same Gaussian cut off at 2 pixels) lets a pixel's value take in its
//! neighbours' samples too, by how near they are to its centre: for independent noise its
//! variance is about 0.28 of the box's, and detail finer than a pixel — the crowd of far
//! mirror images at a hyperbolic room's horizon — is filtered out rather than aliased into
//! grain. The price is a softer image (a response of 0.25 at the Nyquist frequency, the box's
//! 0.64).
//!
//! **Each pixel's samples count as a whole, whatever their number.** pbrt splats every sample
//! into the pixels near it with the filter's weight at its position, and takes the weighted
//! mean. With adaptive sampling that mean is biased: a pixel whose neighbour got ten times its
//! samples takes ten times that neighbour's weight, so the bright side of an edge — a light's
//! silhouette, which the adaptive sampler favours — bleeds into the dark side, several times too
//! bright beside a sphere light. Here a pixel's value is instead Σⱼ Kⱼ mⱼ / Σⱼ Kⱼ over the
//! pixels j around it that have samples, where mⱼ is the mean of pixel j's own samples and Kⱼ
//! the filter's weight averaged over pixel j (what a sample there gets on average,
//! [`PixelFilter::pixel_weights`]). Each mⱼ is an unbiased estimate of its pixel whatever its
//! number of samples, so the value is too. It is computed by merging the neighbours' running
//! sums, each sample of pixel j weighted Kⱼ/nⱼ, so the weighted standard error of
//! [`crate::film::Film::standard_error`] keeps its meaning.

use arrayvec::ArrayVec;
use orbifold_scene::ReconstructionFilter;
use rayon::prelude::*;

/// Most pixels along one axis that a pixel's value takes in: a radius of at most two pixels
/// reaches two pixels either side.
pub const MOST_PIXELS: usize = 5;

/// A pixel reconstruction filter.
///
/// ```
/// use orbifold_render::film::PixelFilter;
///
/// // A pixel's own samples count most for it, its neighbours' a little.
/// let weights = PixelFilter::default().pixel_weights();
/// assert_eq!(weights.iter().map(|w| w.0).collect::<Vec<_>>(), [-1, 0, 1]);
/// assert!(weights[1].1 > 4.0 * weights[0].1 && (weights[0].1 - weights[2].1).abs() < 1e-12);
/// // The box: its own samples only.
/// assert_eq!(PixelFilter::Box.pixel_weights().as_slice(), &[(0, 1.0)]);
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
    /// use orbifold_render::film::PixelFilter;
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
    /// use orbifold_render::film::PixelFilter;
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
    /// use orbifold_render::film::PixelFilter;
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

    /// Along one axis, the pixels whose samples count for a pixel, by their offset from it (0:
    /// its own), with the filter's weight averaged over each (the weight a sample there gets
    /// on average; integrated by Simpson's rule). The weights in two dimensions are the
    /// products of two of these.
    pub fn pixel_weights(self) -> ArrayVec<(i32, f64), MOST_PIXELS> {
        let mut weights = ArrayVec::new();
        let reach = self.reach() as i32;
        for d in -reach..=reach {
            const STEPS: usize = 64;
            let at = |k: usize| self.weight_1d(f64::from(d) - 0.5 + k as f64 / STEPS as f64);
            let simpson: f64 = (0..=STEPS)
                .map(|k| {
                    let c = if k == 0 || k == STEPS {
                        1.0
                    } else if k % 2 == 1 {
                        4.0
                    } else {
                        2.0
                    };
                    c * at(k)
                })
                .sum::<f64>()
                / (3.0 * STEPS as f64);
            if simpson > 0.0 {
                weights.push((d, simpson));
            }
        }
        weights
    }

    /// How many pixels either side count for a pixel.
    fn reach(self) -> u32 {
        match self {
            PixelFilter::Box => 0,
            PixelFilter::Gaussian { radius, .. } => (radius - 0.5).max(0.0).ceil() as u32,
        }
    }

    /// The filtered state of pixel (`x`, `y`) of a `width` × `height` image from every pixel's
    /// own state `own`: the merge, over the pixels j around it with samples (`count(j)` > 0),
    /// of pixel j's state with each sample weighted Kⱼ/nⱼ (`merge_scaled(into, from, factor)`
    /// merges `from` scaled by `factor`).
    pub(crate) fn filtered<P: Default>(
        self,
        weights: &[(i32, f64)],
        own: &[P],
        (width, height): (u32, u32),
        (x, y): (u32, u32),
        count: impl Fn(&P) -> f64,
        merge_scaled: impl Fn(&mut P, &P, f64),
    ) -> P {
        let mut state = P::default();
        for &(dy, ky) in weights {
            let j = i64::from(y) + i64::from(dy);
            if j < 0 || j >= i64::from(height) {
                continue;
            }
            for &(dx, kx) in weights {
                let i = i64::from(x) + i64::from(dx);
                if i < 0 || i >= i64::from(width) {
                    continue;
                }
                let from = &own[j as usize * width as usize + i as usize];
                let n = count(from);
                if n > 0.0 {
                    merge_scaled(&mut state, from, kx * ky / n);
                }
            }
        }
        state
    }

    /// [`PixelFilter::filtered`] afresh, into `out`, for the pixels that pixel (`x`, `y`)'s
    /// own samples count for (after a sample was added to it).
    pub(crate) fn filter_around<P: Default + Clone>(
        self,
        own: &[P],
        out: &mut [P],
        (width, height): (u32, u32),
        (x, y): (u32, u32),
        count: impl Fn(&P) -> f64,
        merge_scaled: impl Fn(&mut P, &P, f64),
    ) {
        let index = |px: u32, py: u32| py as usize * width as usize + px as usize;
        if self == PixelFilter::Box {
            out[index(x, y)] = own[index(x, y)].clone();
            return;
        }
        let weights = self.pixel_weights();
        for &(dy, _) in &weights {
            for &(dx, _) in &weights {
                let (px, py) = (i64::from(x) + i64::from(dx), i64::from(y) + i64::from(dy));
                if px < 0 || py < 0 || px >= i64::from(width) || py >= i64::from(height) {
                    continue;
                }
                let (px, py) = (px as u32, py as u32);
                out[index(px, py)] = self.filtered(
                    &weights,
                    own,
                    (width, height),
                    (px, py),
                    &count,
                    &merge_scaled,
                );
            }
        }
    }

    /// [`PixelFilter::filtered`] for every pixel, into `out`, rows in parallel.
    ///
    /// # Panics
    ///
    /// If `own` or `out` does not hold `width` × `height` pixels.
    pub(crate) fn filter_all<P: Default + Clone + Send + Sync>(
        self,
        own: &[P],
        out: &mut [P],
        size: (u32, u32),
        count: impl Fn(&P) -> f64 + Sync,
        merge_scaled: impl Fn(&mut P, &P, f64) + Sync,
    ) {
        self.filter_changed(own, out, size, None, count, merge_scaled);
    }

    /// [`PixelFilter::filtered`] afresh, into `out`, for the pixels that some pixel marked in
    /// `changed` (whose own state changed since `out` was filtered) counts for, or for every
    /// pixel when `changed` is `None`; rows in parallel. The others keep their value, which is
    /// what filtering them again would give to the bit. (An adaptive round of a render samples a
    /// fifth to a third of the pixels: the rest need no work.)
    ///
    /// # Panics
    ///
    /// If `own`, `out` or `changed` does not hold `width` × `height` pixels.
    pub(crate) fn filter_changed<P: Default + Clone + Send + Sync>(
        self,
        own: &[P],
        out: &mut [P],
        (width, height): (u32, u32),
        changed: Option<&[bool]>,
        count: impl Fn(&P) -> f64 + Sync,
        merge_scaled: impl Fn(&mut P, &P, f64) + Sync,
    ) {
        let n = width as usize * height as usize;
        assert!(own.len() == n && out.len() == n, "one state a pixel");
        assert!(changed.is_none_or(|c| c.len() == n), "one mark a pixel");
        if width == 0 {
            return;
        }
        let weights = self.pixel_weights();
        let reach = self.reach() as usize;
        let (w, h) = (width as usize, height as usize);
        // Whether a pixel within the filter's reach of (x, y) changed.
        let touched = |x: usize, y: usize| -> bool {
            let Some(changed) = changed else {
                return true;
            };
            let (x0, x1) = (x.saturating_sub(reach), (x + reach).min(w - 1));
            (y.saturating_sub(reach)..=(y + reach).min(h - 1))
                .any(|yy| changed[yy * w + x0..=yy * w + x1].contains(&true))
        };
        out.par_chunks_mut(w).enumerate().for_each(|(y, row)| {
            for (x, pixel) in row.iter_mut().enumerate() {
                if !touched(x, y) {
                    continue;
                }
                *pixel = if self == PixelFilter::Box {
                    own[y * w + x].clone()
                } else {
                    self.filtered(
                        &weights,
                        own,
                        (width, height),
                        (x as u32, y as u32),
                        &count,
                        &merge_scaled,
                    )
                };
            }
        });
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_gaussian_takes_in_the_pixels_within_its_radius_and_no_others() {
        let weights = PixelFilter::GAUSSIAN.pixel_weights();
        assert_eq!(weights.len(), 3);
        // The weight of a neighbour is the filter averaged over it: ∫ from ½ to 1½ pixels.
        let g = |t: f64| (-2.0 * t * t).exp() - (-4.5f64).exp();
        let n = 10_000;
        let mean = (0..n)
            .map(|k| g(0.5 + (f64::from(k) + 0.5) / f64::from(n)))
            .sum::<f64>()
            / f64::from(n);
        assert!(
            (weights[2].1 - mean).abs() < 1e-6,
            "{} vs {mean}",
            weights[2].1
        );
        let wide = PixelFilter::Gaussian {
            sigma: 0.5,
            radius: 2.0,
        }
        .pixel_weights();
        assert_eq!(wide.len(), 5);
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
