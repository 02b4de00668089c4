//! Adaptive sampling: which pixels a round of the render loop samples.
//!
//! **Adaptive sampling** (on by default): after [`WARMUP_ROUNDS`](super::WARMUP_ROUNDS) rounds over the whole image,
//! most rounds sample only the pixels whose noise on screen matters most, and every
//! [`FULL_ROUND_EVERY`](super::FULL_ROUND_EVERY)th round ([`FULL_ROUND_EVERY_DENOISED`](super::FULL_ROUND_EVERY_DENOISED)th for a denoised image) is
//! again over the whole image. A pixel's score is its squared
//! display error ([`Film::display_errors`]), taken as the largest in its 3×3 neighbourhood so
//! that a pixel whose few samples happened to agree is not left out, and so that how many
//! samples a pixel gets depends little on its own samples' values (scored by its own samples
//! alone, a pixel whose samples came out low stops early while one with a high outlier gets
//! more that dilute it, and a uniform furnace comes out dark; see `tests/materials.rs`):
//!
//! - for an image shown as it is, the score is divided by the pixel's sample count (the
//!   greedy order for the least summed squared error), and a round gives one sample to every
//!   pixel whose score is at least the image's mean;
//! - for an image that will be denoised ([`RenderOptions::denoised`](super::RenderOptions::denoised)), the score is the noise
//!   the denoiser will leave: the squared display error times the square root of the filter's
//!   variance reduction at that pixel ([`crate::denoise::denoise_with_reduction`], recomputed
//!   at rounds 4, 8, 16, …; the root because the propagated reduction overstates what the
//!   filter does on smooth surfaces), and a pixel gets as many samples in a round as its score
//!   is multiples of the mean, up to [`MOST_SAMPLES_PER_ROUND`]. The samples go to what the
//!   filter cannot smooth — the horizon's crowd of sub-pixel mirror images, silhouettes —
//!   rather than to walls that it averages anyway.
//!
//! Far mirror images crowd into a few pixels (the horizon of a hyperbolic room holds thousands
//! of copies of the room); they get the samples, while smooth walls do not.

use rayon::prelude::*;

use super::options::MOST_SAMPLES_PER_ROUND;
use crate::film::Film;

/// What adaptive sampling aims at.
#[derive(Clone, Copy, Debug)]
pub(super) enum Target<'a> {
    /// The image as it is.
    Raw,
    /// The image after denoising, with the denoiser's variance reduction per pixel.
    Denoised(&'a [f64]),
}

/// The samples of an adaptive round, in pixel order, as (pixel, index among its new samples):
/// see the module documentation for the score. `None` (a round over the whole image) when that
/// picks every pixel or none.
pub(super) fn noisiest(film: &Film, taken: &[u32], target: Target) -> Option<Vec<(u64, u32)>> {
    let (width, height) = (film.width() as usize, film.height() as usize);
    let errors = film.display_errors(film.auto_exposure());
    let score: Vec<f64> = errors
        .iter()
        .zip(taken)
        .enumerate()
        .map(|(i, (e, &n))| match target {
            Target::Raw => e * e / f64::from(n.max(1)),
            Target::Denoised(reduction) => e * e * reduction[i].sqrt(),
        })
        .collect();
    if score.iter().any(|s| !s.is_finite()) {
        return None;
    }
    let spread: Vec<f64> = (0..height)
        .into_par_iter()
        .flat_map_iter(|y| {
            let score = &score;
            (0..width).map(move |x| {
                let mut most = 0.0f64;
                for yy in y.saturating_sub(1)..(y + 2).min(height) {
                    for xx in x.saturating_sub(1)..(x + 2).min(width) {
                        most = most.max(score[yy * width + xx]);
                    }
                }
                most
            })
        })
        .collect();
    let mean = spread.iter().sum::<f64>() / spread.len() as f64;
    let most = match target {
        Target::Raw => 1.0,
        Target::Denoised(_) => f64::from(MOST_SAMPLES_PER_ROUND),
    };
    // Σ ⌊score/mean⌋ over the chosen pixels is at most the pixel count: a round is never
    // longer than one over the whole image.
    let chosen: Vec<(u64, u32)> = (0..spread.len() as u64)
        .filter(|&p| spread[p as usize] >= mean && spread[p as usize] > 0.0)
        .flat_map(|p| {
            let k = (spread[p as usize] / mean).min(most) as u32;
            (0..k.max(1)).map(move |i| (p, i))
        })
        .collect();
    let distinct = chosen.iter().filter(|&&(_, i)| i == 0).count();
    (distinct > 0 && distinct < spread.len()).then_some(chosen)
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    /// A `width` × 1 film whose pixels have the given (mean, spread) over four samples.
    fn film(pixels: &[(f64, f64)]) -> Film {
        let mut film = Film::new(pixels.len() as u32, 1);
        for (x, &(mean, spread)) in pixels.iter().enumerate() {
            for k in 0..4 {
                let v = if k % 2 == 0 {
                    mean - spread
                } else {
                    mean + spread
                };
                film.add(x as u32, 0, [v; 3]);
            }
        }
        film
    }

    #[test]
    fn a_denoised_target_samples_what_the_filter_cannot_smooth() {
        // Sixteen equally noisy pixels: for the raw image every one is as noisy as the mean
        // (a round over the whole image); for a denoised one, only those that the filter
        // leaves alone, and their neighbours, several samples each.
        let film = film(&[(0.3, 0.1); 16]);
        let taken = [4; 16];
        assert_eq!(noisiest(&film, &taken, Target::Raw), None);
        let mut reduction = [1e-4; 16];
        reduction[..4].fill(1.0);
        let chosen = noisiest(&film, &taken, Target::Denoised(&reduction)).unwrap();
        // Scores: e² for pixels 0-4 (4 by its neighbour), e²/100 for the others; the mean is
        // (5 + 11/100)/16 e², so each chosen pixel gets ⌊16/5.11⌋ = 3 samples.
        let expected: Vec<(u64, u32)> = (0..5).flat_map(|p| (0..3).map(move |k| (p, k))).collect();
        assert_eq!(chosen, expected);
    }

    #[test]
    fn a_pixel_whose_samples_agree_beside_a_noisy_one_is_still_sampled() {
        // Pixel 0's four samples agree (they all missed a light image's rim, say); pixel 1's
        // disagree wildly; the rest are a little noisy. Pixel 0 is sampled for its neighbour,
        // the far pixels are not.
        let mut pixels = [(0.5, 0.01); 16];
        pixels[0] = (0.5, 0.0);
        pixels[1] = (0.5, 0.4);
        let film = film(&pixels);
        let taken = [4; 16];
        for target in [Target::Raw, Target::Denoised(&[1.0; 16])] {
            let chosen = noisiest(&film, &taken, target).unwrap();
            let pixels: Vec<u64> = chosen.iter().map(|&(p, _)| p).collect();
            assert!(pixels.contains(&0) && pixels.contains(&1), "{pixels:?}");
            assert!(pixels.iter().all(|&p| p <= 2), "{pixels:?}");
        }
    }

    proptest! {
        #[test]
        fn an_adaptive_round_is_never_longer_than_a_full_one(
            pixels in prop::collection::vec((0.0f64..2.0, 0.0f64..1.0), 2..40),
            reduction in prop::collection::vec(0.0f64..=1.0, 40),
            denoised in any::<bool>(),
        ) {
            let film = film(&pixels);
            let taken = vec![4; pixels.len()];
            let target = if denoised {
                Target::Denoised(&reduction[..pixels.len()])
            } else {
                Target::Raw
            };
            if let Some(chosen) = noisiest(&film, &taken, target) {
                prop_assert!(chosen.len() <= pixels.len());
                // In pixel order, each pixel's new samples numbered from 0.
                for pair in chosen.windows(2) {
                    let ((p, i), (q, j)) = (pair[0], pair[1]);
                    prop_assert!((q == p && j == i + 1) || (q > p && j == 0));
                }
                prop_assert_eq!(chosen[0].1, 0);
            }
        }
    }
}
