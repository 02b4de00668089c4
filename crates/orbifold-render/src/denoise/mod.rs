//! An edge-avoiding à-trous wavelet denoiser guided by what each pixel saw first (its albedo,
//! normal and geodesic depth through the mirrors) and by its own variance (Dammertz et al.
//! 2010, "Edge-avoiding À-Trous Wavelet Transform for fast Global Illumination Filtering";
//! the variance guide as in Schied et al. 2017, SVGF).
//!
//! The image is divided by the albedo first, so that the filter smooths lighting and not
//! texture (the checkerboard floor, marble veins), and multiplied back at the end. The light is
//! filtered in three parts under the same guides, each with its own variance and so its own
//! lighting tolerance (as SVGF filters direct and indirect light apart):
//!
//! - the light a pixel saw directly (lights' images through the mirrors, [`FirstHit::emitted`]),
//!   in the image's own units, averaged only between pixels whose paths disagree on what they
//!   saw. Filtered with the rest, a small bright light image would lend the ceiling around it
//!   its brightness (a halo) and its noise (the partial coverage of its edge pixels), and the
//!   pixels beside it would take its variance as their own tolerance; left unfiltered
//!   everywhere, the band above a hyperbolic room's horizon, where the far light images shrink
//!   below a pixel and merge, would keep all its noise;
//! - the first surface's light sample ([`FirstHit::direct`]), over the albedo: smooth and well
//!   sampled where a light image is near, such as the glow a light throws on a ceiling;
//! - the rest of the reflected light (the light of longer paths), over the albedo: far noisier,
//!   so that its tolerance would flatten that glow if the two were one part. It also listens
//!   less to the normals ([`DenoiseOptions::sigma_normal_rest`]).
//!
//! Denoising trades noise for bias (blur where the guides cannot tell surfaces apart); the
//! renderer's tests check its estimates before any filtering.
//!
//! The denoiser is split by concept:
//!
//! - here: the entry points [`denoise`] and [`denoise_with_reduction`], which split the film's
//!   light into its parts, divide by the albedo, and propagate the variance through the filter;
//! - `guides.rs`: [`Guides`], what the render fills per pixel for the denoiser (albedo, normal,
//!   depth, the parts of the light and their running statistics);
//! - `options.rs`: [`DenoiseOptions`];
//! - `atrous/`: the à-trous filter itself, its passes and their SIMD row filter (`mod.rs`), the
//!   per-part planes and row sums the passes read and write (`planes.rs`), and the check
//!   against a filter written one pixel at a time (`tests.rs`).

mod atrous;
mod guides;
mod options;

use glam::DVec3;
use rayon::prelude::*;

use self::atrous::{AtrousFilter, Part, PartRule};
use crate::film::{Film, RunningStats};
use crate::lights::Rgb;
use orbifold_scene::color::luminance;

#[cfg(doc)]
use crate::integrator::FirstHit;

pub use self::guides::Guides;
pub use self::options::DenoiseOptions;

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
/// where that is unknown (fewer than two samples). The denoised pixel's variance is that of its
/// three filtered parts (the light seen directly, which the filter leaves as it is where the
/// pixel's paths agree on what they saw, and the reflected light), propagated through the
/// passes as if the inputs of each pass were independent (as in SVGF).
/// Adaptive sampling uses it to spend samples where the denoised image will be noisy rather
/// than where the raw one is: a pixel whose noise is mostly a crowd of tiny light images keeps
/// that noise after denoising, however smooth the wall behind them.
///
/// The propagation ignores the correlation that each pass gives its outputs, so on smooth
/// surfaces the factor is far smaller than the true one; it orders pixels well. Two seeds'
/// denoised pixels differ in proportion to the square root of the factor times the raw
/// variance (`docs/benchmarks.md`), which is why adaptive sampling weighs pixels by the
/// factor's square root.
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
    let filter = AtrousFilter::new(
        (width as usize, height as usize),
        &albedo,
        &normal,
        &depth,
        &coherence,
        options,
    );
    // The reflected light in two parts, each over the albedo with the variance of its
    // luminance: the first surface's light sample, and the rest (the film's mean less it and
    // less the light seen directly, which is filtered apart, in the image's own units).
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
    let parts = filter.smooth(
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
