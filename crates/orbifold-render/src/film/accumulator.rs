//! What a pixel of the film has summed of the samples that count for it: the weighted RGB sums,
//! the sums of the weights and of their squares, and the running statistics of the samples'
//! luminance from which the film's noise estimates come.

use orbifold_scene::color::luminance;

use super::statistics::RunningStats;

/// What a pixel has summed of the samples that count for it, with their weights.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub(super) struct Accumulator {
    /// Σ weight × radiance.
    pub(super) sum: [f64; 3],
    /// Σ weight and Σ weight².
    pub(super) weight: f64,
    pub(super) weight2: f64,
    /// The weighted running mean and M₂ of the sample luminance.
    luminance: RunningStats,
    /// Under a reconstruction filter: Σ Kⱼ² vⱼ over the pixels j merged in, with Kⱼ the weight
    /// of pixel j's mean and vⱼ the variance of that mean from its own samples (+∞ when some
    /// pixel j has fewer than two); unused for a pixel's own samples.
    pub(super) mean_variance: f64,
}

impl Accumulator {
    /// Counts a finite sample with weight `w` > 0.
    pub(super) fn add(&mut self, radiance: [f64; 3], w: f64) {
        for (acc, c) in self.sum.iter_mut().zip(radiance) {
            *acc += w * c;
        }
        self.weight += w;
        self.weight2 += w * w;
        self.luminance.add(luminance(radiance), w, self.weight);
    }

    /// The same samples, each weighted `factor` times as much; `mean_variance` is that of a
    /// pixel's own samples so weighted (their mean's weight is K = `factor` · Σ weight).
    pub(super) fn scaled(&self, factor: f64) -> Accumulator {
        let weight = self.weight * factor;
        Accumulator {
            sum: self.sum.map(|s| s * factor),
            weight,
            weight2: self.weight2 * factor * factor,
            luminance: self.luminance.scaled(factor),
            mean_variance: self.own_mean_variance().unwrap_or(f64::INFINITY) * weight * weight,
        }
    }

    /// The variance of the weighted mean luminance, s²·Σw²/(Σw)², with s² the weighted sample
    /// variance of the samples summed here; `None` for fewer than two (effective) samples.
    pub(super) fn own_mean_variance(&self) -> Option<f64> {
        self.luminance.mean_variance(self.weight, self.weight2)
    }

    /// The weighted sample variance of the luminance of the samples summed here (how far one
    /// of them strays); `None` for fewer than two (effective) samples.
    pub(super) fn sample_variance(&self) -> Option<f64> {
        self.luminance.variance(self.weight, self.weight2)
    }

    /// The weighted mean luminance of the samples summed here (0 without samples).
    pub(super) fn mean_luminance(&self) -> f64 {
        if self.weight > 0.0 {
            luminance(self.sum.map(|s| s / self.weight))
        } else {
            0.0
        }
    }

    /// Adds another pixel's sums.
    pub(super) fn merge(&mut self, other: &Accumulator) {
        let (wa, wb) = (self.weight, other.weight);
        if wb == 0.0 {
            return;
        }
        for (acc, c) in self.sum.iter_mut().zip(other.sum) {
            *acc += c;
        }
        self.luminance.merge(&other.luminance, wa, wb);
        self.weight = wa + wb;
        self.weight2 += other.weight2;
        self.mean_variance += other.mean_variance;
    }
}
