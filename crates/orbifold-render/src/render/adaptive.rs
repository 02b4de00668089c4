//! Adaptive sampling without bias: how many samples each pixel gets, stage by stage.
//!
//! **Stages.** An adaptive render runs in stages of whole rounds: the first
//! [`WARMUP_ROUNDS`](super::WARMUP_ROUNDS) rounds give every pixel one sample each; then each
//! stage is as long as all the rounds before it (4, 8, 16, … rounds), at most
//! [`LONGEST_STAGE`] rounds, and the last one ends at the wanted sample count. At the start of a
//! stage of `L` rounds the image so far decides how many samples nⱼ each pixel j gets in it, `L`
//! per pixel on average, spread evenly over the stage's rounds; each pixel's samples go on along
//! its own stratified sequence, as without adaptive sampling.
//!
//! **Without bias: a pixel's samples never decide how many it gets.** Choosing a pixel's number
//! of samples from the values of the samples whose mean is then shown biases that mean: a pixel
//! whose samples came out high looks noisy, gets more samples and its outlier is diluted, while
//! one whose samples came out low stops early (the mean of a sequential sample is not the mean of
//! the distribution: this made the raw image of a grey room 0.44 % dark at 16 samples a pixel,
//! `docs/rendering.md`). So a pixel's count is decided from its eight **neighbours' own
//! samples** alone ([`Film::sample_display_noise`]: not from the filtered film, whose pixels mix
//! in their neighbours' samples), which are independent of its own: its mean of a number of
//! samples fixed independently of their values is unbiased, and so is the filter's fixed
//! weighting of such means. (A neighbour's count depends on this pixel's samples, and the
//! neighbour's noise estimate on its count; that second-order link leaves no bias that 32 seeds
//! of paired renders can see: the measurements are in docs/benchmarks.md.) The samples go on
//! along each pixel's stratified sequence, whose first n points are spread evenly for any n;
//! drawing a stage's samples from a fresh sequence instead would have cost twice the variance in
//! a well-stratified room.
//!
//! **Allocation.** For an image shown as it is, the summed squared error on screen,
//! Σⱼ σⱼ² / nⱼ for a pixel whose single sample moves it by σⱼ display levels, is least with nⱼ
//! proportional to σⱼ (Lagrange); σⱼ is estimated as the largest of the neighbours' ones
//! ([`Film::sample_display_noise`]). For an image that will be denoised
//! ([`RenderOptions::denoised`](super::RenderOptions::denoised)) the error that counts is what
//! the denoiser leaves, σⱼ² √rⱼ / nⱼ with rⱼ the filter's variance reduction at the pixel
//! ([`crate::denoise::denoise_with_reduction`]; the root because the propagated reduction
//! overstates what the filter does on smooth surfaces), so nⱼ ∝ σⱼ rⱼ^¼ (both from the
//! neighbours): the samples go to what the filter cannot smooth — the horizon's crowd of
//! sub-pixel mirror images, silhouettes — rather than to walls that it averages anyway. Every
//! pixel gets at least an eighth of the mean (a quarter for a denoised image, whose filter needs
//! estimates everywhere) and at most [`MOST_SAMPLES_PER_ROUND`] times it.
//!
//! Far mirror images crowd into a few pixels (the horizon of a hyperbolic room holds thousands
//! of copies of the room); they get the samples, while smooth walls do not.

use rayon::prelude::*;

use super::options::{MOST_SAMPLES_PER_ROUND, WARMUP_ROUNDS};
use crate::film::Film;

/// The most rounds in one stage: the allocation is decided afresh at least this often.
pub const LONGEST_STAGE: u32 = 64;

/// What adaptive sampling aims at.
#[derive(Clone, Copy, Debug)]
pub(super) enum Target<'a> {
    /// The image as it is.
    Raw,
    /// The image after denoising, with the denoiser's variance reduction per pixel.
    Denoised(&'a [f64]),
}

/// The number of rounds of the stage that starts at round `start`, for a render of `samples`
/// samples a pixel (see the module documentation): the warm-up, then as many rounds as came
/// before (at most [`LONGEST_STAGE`]), and a last stage that ends at `samples`; one that would
/// leave less than half a stage behind it takes the rest too. Never 0: a render that goes on
/// past `samples` (with a time limit or a noise target) keeps adding stages.
pub(super) fn stage_length(start: u32, samples: u32) -> u32 {
    let length = if start < WARMUP_ROUNDS {
        WARMUP_ROUNDS - start
    } else {
        start.min(LONGEST_STAGE)
    };
    let left = samples.saturating_sub(start);
    if left == 0 {
        length
    } else if left < length + length / 2 {
        left
    } else {
        length
    }
}

/// The samples each pixel gets in a stage of `rounds` rounds, in pixel order, summing to
/// `rounds` × pixels exactly (see the module documentation); `None` (every pixel `rounds`)
/// when the film cannot tell the pixels apart: some pixel's noise unknown or all of it 0.
pub(super) fn allocate(film: &Film, target: Target, rounds: u32) -> Option<Vec<u32>> {
    let noise = neighbours_most(&sample_noise(film, target)?, film.width() as usize);
    let least = match target {
        Target::Raw => rounds / 8,
        Target::Denoised(_) => rounds / 4,
    }
    .max(1);
    let most = rounds.saturating_mul(MOST_SAMPLES_PER_ROUND);
    let budget = u64::from(rounds) * noise.len() as u64;
    let shares = proportional_shares(&noise, budget as f64, f64::from(least), f64::from(most))?;
    Some(whole_counts(&shares, budget))
}

/// How far one sample moves each pixel on screen ([`Film::sample_display_noise`]), times the
/// root of the root of the denoiser's variance reduction for a denoised target; `None` if some
/// pixel's is unknown or not finite.
fn sample_noise(film: &Film, target: Target) -> Option<Vec<f64>> {
    let noise: Vec<f64> = film
        .sample_display_noise(film.auto_exposure())
        .into_iter()
        .enumerate()
        .map(|(i, sigma)| match target {
            Target::Raw => sigma,
            Target::Denoised(reduction) => sigma * reduction[i].sqrt().sqrt(),
        })
        .collect();
    noise.iter().all(|s| s.is_finite()).then_some(noise)
}

/// Each value replaced by the largest of its neighbours' (the 3×3 neighbourhood without the
/// value itself; rows of `width`).
fn neighbours_most(values: &[f64], width: usize) -> Vec<f64> {
    let height = values.len().checked_div(width).unwrap_or(0);
    (0..height)
        .into_par_iter()
        .flat_map_iter(|y| {
            (0..width).map(move |x| {
                let mut most = 0.0f64;
                for yy in y.saturating_sub(1)..(y + 2).min(height) {
                    for xx in x.saturating_sub(1)..(x + 2).min(width) {
                        if (xx, yy) != (x, y) {
                            most = most.max(values[yy * width + xx]);
                        }
                    }
                }
                most
            })
        })
        .collect()
}

/// Shares clamp(c·wⱼ, least, most) summing to `budget`, with c found by bisection (the sum is
/// continuous and increasing in c); `None` when every weight is 0 or the budget cannot be met.
fn proportional_shares(weights: &[f64], budget: f64, least: f64, most: f64) -> Option<Vec<f64>> {
    let n = weights.len() as f64;
    if weights.iter().all(|&w| w <= 0.0) || budget < least * n || budget > most * n {
        return None;
    }
    let total = |c: f64| -> f64 { weights.iter().map(|&w| (c * w).clamp(least, most)).sum() };
    let (mut low, mut high) = (0.0f64, 1.0f64);
    while total(high) < budget {
        high *= 2.0;
        if !high.is_finite() {
            return None;
        }
    }
    for _ in 0..100 {
        let mid = 0.5 * (low + high);
        if total(mid) < budget {
            low = mid;
        } else {
            high = mid;
        }
    }
    Some(
        weights
            .iter()
            .map(|&w| (high * w).clamp(least, most))
            .collect(),
    )
}

/// Whole numbers as near as can be to `shares`, summing to `budget` exactly: each share rounded
/// down, then one more for the largest remainders (ties to the earlier pixel).
fn whole_counts(shares: &[f64], budget: u64) -> Vec<u32> {
    let mut counts: Vec<u32> = shares.iter().map(|s| s.floor() as u32).collect();
    let given: u64 = counts.iter().map(|&c| u64::from(c)).sum();
    let mut order: Vec<usize> = (0..shares.len()).collect();
    order.sort_by(|&a, &b| {
        let (ra, rb) = (shares[a] - shares[a].floor(), shares[b] - shares[b].floor());
        rb.total_cmp(&ra).then(a.cmp(&b))
    });
    let missing = budget.saturating_sub(given) as usize;
    for &i in order.iter().cycle().take(missing) {
        counts[i] += 1;
    }
    counts
}

/// The samples that pixel of count `count` takes in round `round` of a stage of `rounds`
/// rounds: its samples spread evenly over the stage, as the indices from
/// ⌊round·count/rounds⌋ up to ⌊(round+1)·count/rounds⌋.
pub(super) fn samples_in_round(count: u32, round: u32, rounds: u32) -> std::ops::Range<u32> {
    let at = |r: u32| (u64::from(r) * u64::from(count) / u64::from(rounds)) as u32;
    at(round)..at(round + 1)
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
    fn stages_double_up_to_the_longest_and_end_at_the_samples() {
        let stages = |samples: u32| {
            let mut start = 0;
            let mut lengths = Vec::new();
            while start < samples {
                let length = stage_length(start, samples);
                lengths.push(length);
                start += length;
            }
            lengths
        };
        assert_eq!(stages(2), vec![2]);
        assert_eq!(stages(5), vec![5]);
        assert_eq!(stages(6), vec![4, 2]);
        assert_eq!(stages(16), vec![4, 4, 8]);
        assert_eq!(stages(64), vec![4, 4, 8, 16, 32]);
        assert_eq!(stages(100), vec![4, 4, 8, 16, 32, 36]);
        assert_eq!(stages(120), vec![4, 4, 8, 16, 32, 56]);
        assert_eq!(stages(300), vec![4, 4, 8, 16, 32, 64, 64, 64, 44]);
        // Past the samples asked for (a time limit), the stages go on.
        assert_eq!(stage_length(16, 16), 16);
    }

    #[test]
    fn a_denoised_target_samples_what_the_filter_cannot_smooth() {
        // Sixteen equally noisy pixels: for the raw image every one gets the same; for a
        // denoised one, those that the filter leaves alone and their neighbours get the most.
        let film = film(&[(0.3, 0.1); 16]);
        assert_eq!(allocate(&film, Target::Raw, 8), Some(vec![8; 16]));
        let mut reduction = [1e-4; 16];
        reduction[..4].fill(1.0);
        let counts = allocate(&film, Target::Denoised(&reduction), 8).unwrap();
        assert_eq!(counts.iter().sum::<u32>(), 8 * 16);
        // Pixels 0-4 (4 by its neighbour) weigh 1, the others 10⁻¹: the latter at their
        // least, a quarter of the mean.
        assert!(
            counts[..5].iter().all(|&c| c == counts[0] && c > 8),
            "{counts:?}"
        );
        assert!(counts[6..].iter().all(|&c| c == 2), "{counts:?}");
    }

    #[test]
    fn a_pixel_gets_the_samples_its_neighbours_noise_asks_for_whatever_its_own() {
        // Pixel 1's samples disagree wildly, the others' a little, pixel 0's not at all (they
        // all missed a light image's rim, say). Its neighbours 0 and 2 get the most samples;
        // pixel 1 itself gets what its quiet neighbours ask for, since its own samples must not
        // decide its count (see the module documentation); pixel 2's neighbour 3 gets as few
        // as the far pixels.
        let mut pixels = [(0.5, 0.01); 16];
        pixels[0] = (0.5, 0.0);
        pixels[1] = (0.5, 0.4);
        let quiet = film(&pixels);
        for target in [Target::Raw, Target::Denoised(&[1.0; 16])] {
            let counts = allocate(&quiet, target, 16).unwrap();
            assert!(counts[0].abs_diff(counts[2]) <= 1, "{counts:?}");
            assert!(
                counts[0] > 16 && counts[1] < 16 && counts[3] < 16,
                "{counts:?}"
            );
            // Calm, pixel 1 asks its neighbours for fewer (through their share of the budget,
            // which all pixels split, it moves its own count a little too).
            pixels[1] = (0.5, 0.0);
            let calm = allocate(&film(&pixels), target, 16).unwrap();
            pixels[1] = (0.5, 0.4);
            assert!(calm[0] < counts[0] && calm[2] < counts[2], "{calm:?}");
        }
    }

    #[test]
    fn a_film_that_cannot_tell_the_pixels_apart_gets_even_samples() {
        assert_eq!(allocate(&film(&[(0.5, 0.0); 4]), Target::Raw, 8), None);
        let mut one_sample = Film::new(2, 1);
        one_sample.add(0, 0, [1.0; 3]);
        one_sample.add(1, 0, [1.0; 3]);
        assert_eq!(allocate(&one_sample, Target::Raw, 8), None);
    }

    proptest! {
        #[test]
        fn a_stage_gives_each_pixel_its_bounds_and_the_budget_exactly(
            pixels in prop::collection::vec((0.0f64..2.0, 0.0f64..1.0), 2..40),
            reduction in prop::collection::vec(0.0f64..=1.0, 40),
            denoised in any::<bool>(),
            rounds in 1u32..100,
        ) {
            let film = film(&pixels);
            let target = if denoised {
                Target::Denoised(&reduction[..pixels.len()])
            } else {
                Target::Raw
            };
            if let Some(counts) = allocate(&film, target, rounds) {
                let sum: u64 = counts.iter().map(|&c| u64::from(c)).sum();
                prop_assert_eq!(sum, u64::from(rounds) * pixels.len() as u64);
                let least = if denoised { rounds / 4 } else { rounds / 8 }.max(1);
                for &c in &counts {
                    prop_assert!(c >= least && c <= rounds * MOST_SAMPLES_PER_ROUND + 1);
                }
                // Spread over the rounds, each pixel's samples are all taken, once each.
                for &c in &counts {
                    let spread: Vec<u32> =
                        (0..rounds).flat_map(|r| samples_in_round(c, r, rounds)).collect();
                    prop_assert_eq!(spread, (0..c).collect::<Vec<u32>>());
                }
            }
        }
    }
}
