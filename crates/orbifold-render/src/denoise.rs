//! An edge-avoiding à-trous wavelet denoiser guided by what each pixel saw first (its albedo,
//! normal and geodesic depth through the mirrors) and by its own variance (Dammertz et al.
//! 2010, "Edge-avoiding À-Trous Wavelet Transform for fast Global Illumination Filtering";
//! the variance guide as in Schied et al. 2017, SVGF).
//!
//! The image is divided by the albedo first, so that the filter smooths lighting and not
//! texture (the checkerboard floor, marble veins), and multiplied back at the end. Five passes
//! of a 5×5 B3-spline kernel with holes (steps 1, 2, 4, 8, 16: a 61×61 footprint) weigh each
//! neighbour by how alike the two pixels' normals, depths and albedos are, and by how far its
//! lighting is from the pixel's in units of the standard error around it (the variance blurred
//! over 3×3 pixels) — so that edges, mirror-image boundaries and well-converged detail survive
//! while noise is averaged away. A pixel whose paths disagree on what they saw (its mean
//! normal is short, its depths spread: sub-pixel detail such as the crowd of far mirror images
//! at a hyperbolic room's horizon) trusts its guides only as much as its paths agree — its
//! guides are noise too — and is smoothed by its lighting tolerance.
//!
//! Denoising trades noise for bias (blur where the guides cannot tell surfaces apart); the
//! renderer's tests check its estimates before any filtering.

use glam::DVec3;
use rayon::prelude::*;

use crate::film::{Film, luminance};
use crate::integrator::FirstHit;
use crate::light::Rgb;

/// The per-pixel means of what camera paths saw first.
#[derive(Clone, Debug)]
pub struct Guides {
    width: u32,
    height: u32,
    albedo: Vec<Rgb>,
    normal: Vec<DVec3>,
    depth: Vec<f64>,
    depth2: Vec<f64>,
    count: Vec<u32>,
}

impl Guides {
    /// Empty guides for a `width` × `height` image.
    ///
    /// ```
    /// use orbifold_render::denoise::Guides;
    /// use orbifold_render::integrator::FirstHit;
    ///
    /// let mut guides = Guides::new(2, 1);
    /// guides.add(1, 0, &FirstHit { albedo: [0.5; 3], depth: 2.0, ..FirstHit::default() });
    /// assert_eq!(guides.albedo(1, 0), [0.5; 3]);
    /// ```
    pub fn new(width: u32, height: u32) -> Guides {
        let n = width as usize * height as usize;
        Guides {
            width,
            height,
            albedo: vec![[0.0; 3]; n],
            normal: vec![DVec3::ZERO; n],
            depth: vec![0.0; n],
            depth2: vec![0.0; n],
            count: vec![0; n],
        }
    }

    fn index(&self, x: u32, y: u32) -> usize {
        assert!(
            x < self.width && y < self.height,
            "pixel ({x}, {y}) outside the guides"
        );
        y as usize * self.width as usize + x as usize
    }

    /// Adds what one path through pixel (x, y) saw first (non-finite values are skipped).
    pub fn add(&mut self, x: u32, y: u32, first: &FirstHit) {
        let finite = first.albedo.iter().all(|a| a.is_finite())
            && first.normal.is_finite()
            && first.depth.is_finite();
        if !finite {
            return;
        }
        let i = self.index(x, y);
        for (a, b) in self.albedo[i].iter_mut().zip(first.albedo) {
            *a += b;
        }
        self.normal[i] += first.normal;
        self.depth[i] += first.depth;
        self.depth2[i] += first.depth * first.depth;
        self.count[i] += 1;
    }

    /// The mean albedo at pixel (x, y).
    pub fn albedo(&self, x: u32, y: u32) -> Rgb {
        let i = self.index(x, y);
        self.mean_albedo(i)
    }

    fn mean_albedo(&self, i: usize) -> Rgb {
        let n = f64::from(self.count[i].max(1));
        self.albedo[i].map(|a| a / n)
    }

    fn mean_normal(&self, i: usize) -> DVec3 {
        self.normal[i].normalize_or_zero()
    }

    fn mean_depth(&self, i: usize) -> f64 {
        self.depth[i] / f64::from(self.count[i].max(1))
    }

    /// How much the paths through pixel `i` agree on what they saw first, in [0, 1]: the length
    /// of their mean normal times a falloff with the spread of their depths (1: one surface; near
    /// 0: the pixel covers many things smaller than itself, such as far mirror images).
    fn coherence(&self, i: usize) -> f64 {
        let n = f64::from(self.count[i]);
        if n < 2.0 {
            return 1.0;
        }
        let mean = self.depth[i] / n;
        let spread = (self.depth2[i] / n - mean * mean).max(0.0).sqrt();
        let normals = (self.normal[i].length() / n).min(1.0);
        normals / (1.0 + COHERENCE_DEPTH * spread / mean.max(1e-9))
    }
}

/// How strongly a pixel's relative depth spread lowers its coherence.
const COHERENCE_DEPTH: f64 = 4.0;

/// How strongly each guide stops the filter.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DenoiseOptions {
    /// Number of à-trous passes (the footprint is 4·2^passes − 3 pixels wide).
    pub passes: u32,
    /// Exponent of the normal weight max(0, n·n′)^σ.
    pub sigma_normal: f64,
    /// Relative depth difference that halves the weight about e-fold.
    pub sigma_depth: f64,
    /// Albedo difference scale.
    pub sigma_albedo: f64,
    /// Lighting difference, in standard errors, that the weight tolerates.
    pub sigma_lighting: f64,
}

impl Default for DenoiseOptions {
    fn default() -> Self {
        DenoiseOptions {
            passes: 5,
            sigma_normal: 64.0,
            sigma_depth: 0.05,
            sigma_albedo: 0.1,
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
/// let first = FirstHit { albedo: [0.5; 3], normal: glam::DVec3::Z, depth: 1.0 };
/// for y in 0..h {
///     for x in 0..w {
///         for k in 0..4u32 {
///             let noise = if (x + y + k) % 2 == 0 { 0.1 } else { -0.1 };
///             film.add(x, y, [0.3 + noise; 3]);
///             guides.add(x, y, &first);
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
/// estimate, in [0, 1]: the variance of the filtered lighting, propagated through the passes as
/// if the inputs of each pass were independent (as in SVGF), over the variance of the pixel's
/// own mean; 1 where that is unknown (fewer than two samples). Adaptive sampling uses it to
/// spend samples where the denoised image will be noisy rather than where the raw one is.
///
/// The propagation ignores the correlation that each pass gives its outputs, so on smooth
/// surfaces the factor is far smaller than the true one; it orders pixels well.
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
///             film.add(x, y, [0.3 + 0.1 * f64::from(k % 2); 3]);
///             guides.add(x, y, &FirstHit { albedo, normal: glam::DVec3::Z, depth: 1.0 });
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
    // Lighting (the image over the albedo) and the variance of its luminance.
    let mut lighting: Vec<Rgb> = Vec::with_capacity(n);
    let mut variance: Vec<f64> = Vec::with_capacity(n);
    for y in 0..height {
        for x in 0..width {
            let i = y as usize * width as usize + x as usize;
            let a = albedo[i];
            let c = film.pixel(x, y);
            lighting.push([c[0] / a[0], c[1] / a[1], c[2] / a[2]]);
            let se = film.standard_error(x, y);
            let scale = luminance(a).max(ALBEDO_FLOOR);
            variance.push(if se.is_finite() {
                (se / scale).powi(2)
            } else {
                f64::INFINITY
            });
        }
    }
    let guide = Guide {
        width: width as usize,
        height: height as usize,
        albedo: &albedo,
        normal: &normal,
        depth: &depth,
        coherence: &coherence,
        options,
    };
    let before = variance.clone();
    for pass in 0..options.passes {
        let step = 1usize << pass;
        // The lighting tolerance comes from the variance blurred over 3×3 pixels (as in SVGF):
        // a pixel whose few samples happened to agree — all zero, say — has a variance estimate
        // near 0 and would otherwise refuse every neighbour and stay a dark or bright speck.
        let tolerance: Vec<f64> = (0..n)
            .into_par_iter()
            .map(|i| guide.blurred(i, &variance))
            .collect();
        let (next, next_variance): (Vec<Rgb>, Vec<f64>) = (0..n)
            .into_par_iter()
            .map(|i| guide.filter(i, step, &lighting, &variance, tolerance[i]))
            .unzip();
        lighting = next;
        variance = next_variance;
    }
    let pixels: Vec<Rgb> = (0..n)
        .map(|i| {
            let (l, a) = (lighting[i], albedo[i]);
            [l[0] * a[0], l[1] * a[1], l[2] * a[2]]
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

    /// How much neighbour `j` counts for pixel `i` (before the kernel's weight): a product of
    /// falloffs in their normals' angle, depths, albedos and lighting, computed as one
    /// exponential of the sum of their logarithms (the filter's hot path). The guides' terms are
    /// scaled by how much pixel `i`'s paths agree (its coherence).
    fn edge_stop(
        &self,
        i: usize,
        j: usize,
        step: usize,
        lighting_i: f64,
        lighting_j: f64,
        tolerance: f64,
    ) -> f64 {
        let o = self.options;
        let trust = self.coherence[i];
        let cos = self.normal[i].dot(self.normal[j]);
        // max(0, cos)^(σ·trust), with 0^0 = 1 as `powf` has it.
        let normal = if trust <= 0.0 {
            0.0
        } else if cos > 0.0 {
            o.sigma_normal * trust * cos.ln()
        } else {
            return 0.0;
        };
        let (zi, zj) = (self.depth[i], self.depth[j]);
        let depth = -(zi - zj).abs() / (o.sigma_depth * zi.max(zj) * step as f64 + 1e-9) * trust;
        let da: f64 = (0..3)
            .map(|c| (self.albedo[i][c] - self.albedo[j][c]).powi(2))
            .sum();
        let albedo = -da / (o.sigma_albedo * o.sigma_albedo) * trust;
        let light = -(lighting_i - lighting_j).abs() / tolerance;
        (normal + depth + albedo + light).exp()
    }

    /// One à-trous tap set around pixel `i` with holes of `step`: the filtered lighting and its
    /// variance. `variance_around` is the (blurred) variance that sets the lighting tolerance.
    fn filter(
        &self,
        i: usize,
        step: usize,
        lighting: &[Rgb],
        variance: &[f64],
        variance_around: f64,
    ) -> (Rgb, f64) {
        let o = self.options;
        let (x, y) = ((i % self.width) as isize, (i / self.width) as isize);
        let centre = lighting[i];
        let centre_l = luminance(centre);
        // The lighting tolerance: a few standard errors (an infinite variance — nothing
        // sampled around — accepts everything).
        let tolerance = o.sigma_lighting * variance_around.sqrt() + 1e-6;
        // A pixel whose paths saw many different things (sub-pixel detail: the crowd of far
        // mirror images at a hyperbolic room's horizon) has guides that are themselves noise:
        // it listens to them only as much as its paths agree (`edge_stop`), and to its
        // lighting tolerance.
        let (mut sum, mut weights, mut var) = ([0.0; 3], 0.0, 0.0);
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
                let w = if j == i {
                    kx * ky
                } else {
                    kx * ky
                        * self.edge_stop(i, j, step, centre_l, luminance(lighting[j]), tolerance)
                };
                // NaN weights (from NaN guides) and unsampled neighbours are skipped.
                let usable = w > 0.0 && (j == i || variance[j].is_finite());
                if !usable {
                    continue;
                }
                for (s, l) in sum.iter_mut().zip(lighting[j]) {
                    *s += w * l;
                }
                weights += w;
                var += w * w * variance[j];
            }
        }
        if weights <= 0.0 {
            return (centre, variance[i]);
        }
        (sum.map(|s| s / weights), var / (weights * weights))
    }
}
