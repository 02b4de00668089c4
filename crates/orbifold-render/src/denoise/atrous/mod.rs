//! The edge-avoiding à-trous filter (Dammertz et al. 2010) over the parts of the light, under
//! one set of guides whose weights are worked out once for all parts.
//!
//! Passes of a 5×5 B3-spline kernel with holes (by default five: steps 1, 2, 4, 8, 16, a 61×61
//! footprint; [`DenoiseOptions::passes`]) weigh each neighbour by how alike the two pixels' normals and depths are (and albedos, if
//! asked: [`DenoiseOptions::sigma_albedo`]), and by how far its lighting is from the pixel's in
//! units of the standard error around it (the variance blurred over 3×3 pixels, as in SVGF) —
//! so that edges, mirror-image boundaries and well-converged detail survive while noise is
//! averaged away. A pixel whose paths disagree on what they saw (its coherence is low: its mean
//! normal is short, its depths spread; sub-pixel detail such as the crowd of far mirror images
//! at a hyperbolic room's horizon) trusts its guides only as much as its paths agree — its
//! guides are noise too — and is smoothed by its lighting tolerance.
//!
//! Each part has its rule ([`PartRule`]). The light seen directly is averaged only between
//! pixels whose paths disagree on what they saw: each neighbour weighs (1 − coherence) of both
//! pixels, and a pixel whose coherence is above [`SEEN_COHERENT`] keeps its own. The light of
//! longer paths listens less to the normals than the first surface's light sample: light that
//! arrives after a bounce comes from all round and turns slowly with the normal, so on a bumpy
//! mesh it is averaged over neighbours whose normals differ by tens of degrees
//! ([`DenoiseOptions::sigma_normal_rest`]).
//!
//! The passes filter a row at a time: the quantities are kept as planes (`planes.rs`), so that
//! at one tap of the kernel the row's pixels and their neighbours are contiguous runs, which
//! [`AtrousFilter::filter_row`] weighs side by side in SIMD lanes (in copies compiled for AVX2
//! and AVX-512 by `orbifold_trace::with_avx512!`, chosen at run time).

mod planes;
#[cfg(test)]
mod tests;

use glam::DVec3;
use rayon::prelude::*;

use self::planes::{Planes, PlanesRow, RowSums, TapRuns};
use super::DenoiseOptions;
use crate::lights::Rgb;
use orbifold_trace::fastmath::{exp_fast, ln_fast};

/// The B3-spline kernel of the à-trous transform.
const KERNEL: [f64; 5] = [1.0 / 16.0, 1.0 / 4.0, 3.0 / 8.0, 1.0 / 4.0, 1.0 / 16.0];

/// One part of the light being filtered: per pixel its value (over the albedo for reflected
/// light), and the variance of that value's luminance (infinite where unknown).
pub(super) struct Part {
    pub(super) lighting: Vec<Rgb>,
    pub(super) variance: Vec<f64>,
}

/// A pixel's *openness*: how much its light seen directly is averaged with its neighbours', by
/// how little its paths agree on what they saw first: 1 − coherence, and 0 above a coherence of
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
pub(super) enum PartRule {
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

/// The à-trous filter of one denoising run: its guides, one plane per quantity (at one tap of
/// the kernel, a row of pixels and their neighbours are two contiguous runs, which the filter
/// weighs side by side in SIMD lanes: [`AtrousFilter::filter_row`]), and its options.
pub(super) struct AtrousFilter<'a> {
    /// The image's size in pixels.
    width: usize,
    height: usize,
    /// The mean albedos (not below the floor the lighting was divided by).
    albedo: &'a [Rgb],
    /// The mean normals' x, y and z.
    normal: [Vec<f64>; 3],
    /// The mean geodesic depths.
    depth: &'a [f64],
    /// How much each pixel's paths agree on what they saw first, in [0, 1]: how far its guides
    /// are to be trusted.
    coherence: &'a [f64],
    /// [`seen_openness`] of each pixel.
    openness: Vec<f64>,
    options: &'a DenoiseOptions,
}

/// The number of parts being filtered: the light sample, the rest and the light seen directly.
const PARTS: usize = 3;

impl<'a> AtrousFilter<'a> {
    /// The filter under the guides of a `width` × `height` image, per pixel row by row.
    pub(super) fn new(
        (width, height): (usize, usize),
        albedo: &'a [Rgb],
        normal: &[DVec3],
        depth: &'a [f64],
        coherence: &'a [f64],
        options: &'a DenoiseOptions,
    ) -> AtrousFilter<'a> {
        AtrousFilter {
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
    pub(super) fn smooth(&self, parts: [Part; PARTS], rules: [PartRule; PARTS]) -> [Part; PARTS] {
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
                    *t = self.options.sigma_lighting
                        * self.blurred_variance(i, &part.variance).sqrt()
                        + 1e-6;
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
    fn blurred_variance(&self, i: usize, variance: &[f64]) -> f64 {
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
        orbifold_trace::with_avx512!(AtrousFilter<'_>, self.filter_row_portable(
            y: usize,
            step: usize,
            planes: &[Planes; PARTS],
            rules: &[PartRule; PARTS],
            tolerance: &[Vec<f64>; PARTS],
            scratch: &mut ([RowSums; PARTS], TapRuns),
        ) -> ())
    }

    /// [`AtrousFilter::filter_row`] in straight-line loops over runs of pixels (see the struct).
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
        // its own exponent; NaN where the normals face apart: no weight) and that of the
        // falloffs in depth and albedo.
        let TapRuns {
            normal_log,
            depth_albedo_log,
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
                    &mut depth_albedo_log[..run],
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
                        let (normal_log, depth_albedo_log) = (
                            &normal_log[skip..skip + run],
                            &depth_albedo_log[skip..skip + run],
                        );
                        for t in 0..run {
                            let light = -(centre[t] - near_luminance[t]).abs() / tolerance[t];
                            let open = if seen { open[t] * near_open[t] } else { 1.0 };
                            let weight = open
                                * kernel
                                * exp_fast(sharpness * normal_log[t] + depth_albedo_log[t] + light);
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
        depth_albedo_log: &mut [f64],
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
        let (normal_log, depth_albedo_log) = (&mut normal_log[..run], &mut depth_albedo_log[..run]);
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
            depth_albedo_log[t] = -(zi - zj).abs() / (depth_scale * zi.max(zj) + 1e-9) * trust[t];
        }
        if o.sigma_albedo.is_finite() {
            let scale = o.sigma_albedo * o.sigma_albedo;
            for t in 0..run {
                let (a, b) = (self.albedo[at + t], self.albedo[near + t]);
                let da: f64 = (0..3).map(|c| (a[c] - b[c]).powi(2)).sum();
                depth_albedo_log[t] -= da / scale * trust[t];
            }
        }
    }
}
