//! Running statistics of weighted samples, written once for the film's per-pixel noise and the
//! denoiser's per-pixel guides: the weighted mean and the sum of squared deviations, updated one
//! sample at a time by West's weighted form of Welford's method, and merged by Chan, Golub and
//! LeVeque's formula.
//!
//! - D. H. D. West, "Updating mean and variance estimates: an improved method", Communications
//!   of the ACM 22(9), 1979.
//! - T. F. Chan, G. H. Golub, R. J. LeVeque, "Updating formulae and a pairwise algorithm for
//!   computing sample variances", Stanford CS report STAN-CS-79-773, 1979.
//!
//! The sums of the weights (Σw, Σw²) are kept by the caller, which usually shares them between
//! several statistics of the same samples.

/// The weighted running mean of some values and their weighted sum of squared deviations
/// (M₂ = Σ w (x − mean)²).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub(crate) struct RunningStats {
    /// The weighted mean.
    pub mean: f64,
    /// Σ w (x − mean)².
    pub m2: f64,
}

impl RunningStats {
    /// Adds `value` with weight `w` > 0; `weight_sum` is Σw with it.
    #[inline]
    pub fn add(&mut self, value: f64, w: f64, weight_sum: f64) {
        let delta = value - self.mean;
        self.mean += delta * w / weight_sum;
        self.m2 += w * delta * (value - self.mean);
    }

    /// Merges `other`, whose values weigh `wb` in all, into these, which weigh `wa` (Chan et
    /// al.'s formula). Nothing to merge when `wb` is 0.
    #[inline]
    pub fn merge(&mut self, other: &RunningStats, wa: f64, wb: f64) {
        let w = wa + wb;
        if wb <= 0.0 || w <= 0.0 {
            return;
        }
        let delta = other.mean - self.mean;
        self.mean += delta * wb / w;
        self.m2 += other.m2 + delta * delta * wa * wb / w;
    }

    /// The same values, each weighted `factor` times as much (the mean is unchanged).
    #[inline]
    pub fn scaled(&self, factor: f64) -> RunningStats {
        RunningStats {
            mean: self.mean,
            m2: self.m2 * factor,
        }
    }

    /// The weighted sample variance s² = M₂ / (Σw − Σw²/Σw), with Σw = `w` and Σw² = `w2`
    /// (the unbiased estimate for reliability weights), or `None` while the effective number of
    /// samples (Σw)²/Σw² is at most one.
    #[inline]
    pub fn variance(&self, w: f64, w2: f64) -> Option<f64> {
        let effective = if w2 > 0.0 { w * w / w2 } else { 0.0 };
        (effective > 1.0 + 1e-9).then(|| (self.m2 / (w - w2 / w)).max(0.0))
    }

    /// The variance of the weighted mean, s²·Σw²/(Σw)² (for unit weights s²/n).
    #[inline]
    pub fn mean_variance(&self, w: f64, w2: f64) -> Option<f64> {
        self.variance(w, w2).map(|s2| s2 * w2 / (w * w))
    }

    /// The standard error of the weighted mean, √(s²·Σw²)/Σw; infinite while there is no
    /// variance ([`RunningStats::variance`]).
    #[inline]
    pub fn standard_error(&self, w: f64, w2: f64) -> f64 {
        self.variance(w, w2)
            .map_or(f64::INFINITY, |s2| (s2 * w2).sqrt() / w)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    /// The two-pass weighted mean and M₂ of some (value, weight) pairs.
    fn two_pass(samples: &[(f64, f64)]) -> (f64, f64) {
        let w: f64 = samples.iter().map(|s| s.1).sum();
        let mean = samples.iter().map(|(x, v)| x * v).sum::<f64>() / w;
        let m2 = samples
            .iter()
            .map(|(x, v)| v * (x - mean) * (x - mean))
            .sum();
        (mean, m2)
    }

    proptest! {
        /// One at a time, or two halves merged: the two-pass mean and M₂.
        #[test]
        fn updates_and_merges_agree_with_two_passes(
            samples in prop::collection::vec((-10.0f64..10.0, 0.01f64..5.0), 2..40),
            cut in 0usize..40,
        ) {
            let (mean, m2) = two_pass(&samples);
            let run = |part: &[(f64, f64)]| {
                let (mut stats, mut w) = (RunningStats::default(), 0.0);
                for &(x, v) in part {
                    w += v;
                    stats.add(x, v, w);
                }
                (stats, w)
            };
            let (all, _) = run(&samples);
            let cut = cut.min(samples.len());
            let (mut a, wa) = run(&samples[..cut]);
            let (b, wb) = run(&samples[cut..]);
            a.merge(&b, wa, wb);
            for stats in [all, a] {
                prop_assert!((stats.mean - mean).abs() < 1e-9 * (1.0 + mean.abs()));
                prop_assert!((stats.m2 - m2).abs() < 1e-8 * (1.0 + m2));
            }
        }
    }

    #[test]
    fn one_sample_has_no_variance() {
        let mut stats = RunningStats::default();
        stats.add(3.0, 2.0, 2.0);
        assert_eq!(stats.variance(2.0, 4.0), None);
        assert_eq!(stats.standard_error(2.0, 4.0), f64::INFINITY);
        stats.add(5.0, 2.0, 4.0);
        // Two equal weights: s² = M₂/(Σw − Σw²/Σw) = 4/(4 − 2) = 2; the mean's variance s²/2.
        assert_eq!(stats.m2, 4.0);
        assert_eq!(stats.variance(4.0, 8.0), Some(2.0));
        assert_eq!(stats.mean_variance(4.0, 8.0), Some(1.0));
        assert_eq!(stats.standard_error(4.0, 8.0), 1.0);
    }
}
