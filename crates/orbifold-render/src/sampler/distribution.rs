//! A discrete distribution: picking one of N items with probability ∝ its weight, by inverting
//! its cumulative distribution (pbrt's `PiecewiseConstant1D`, over items rather than an
//! interval). It picks a light among a room's thousands of light images, and a triangle of a
//! mesh light in proportion to its area, so the inversion starts from a guide table rather than
//! a binary search over the whole cdf.

/// A piecewise-constant distribution over `0..len()`: picks item i with probability
/// `weights[i] / Σ weights` by inverting the cumulative distribution.
///
/// ```
/// use orbifold_render::sampler::Distribution1d;
///
/// let d = Distribution1d::new(&[1.0, 0.0, 3.0]).unwrap();
/// assert_eq!(d.sample(0.1), (0, 0.25));
/// assert_eq!(d.sample(0.5), (2, 0.75));
/// assert_eq!(d.pmf(1), 0.0);
/// ```
#[derive(Clone, Debug)]
pub struct Distribution1d {
    /// The cumulative distribution: `cdf[0] = 0`, `cdf[len] = 1`, nondecreasing.
    cdf: Vec<f64>,
    /// The probability of each item.
    pmf: Vec<f64>,
    /// Σ weights.
    total: f64,
    /// The last item of nonzero weight (what u ≥ 1 maps to).
    last_positive: usize,
    /// A guide table (Chen and Asau's cutpoints) over M = 2ᵏ equal intervals of u: entry j is
    /// the first index whose cdf exceeds j/M, so that a `u` in [j/M, (j + 1)/M) is looked for
    /// only between entries j and j + 1 — a step or two instead of a binary search over all
    /// the cdf, a chain of a dozen reads each waiting on the one before for a room's thousands
    /// of light images. (M is a power of two so that ⌊u·M⌋ = j is exact.)
    guide: Vec<u32>,
}

/// The guide table of a cdf ([`Distribution1d`]): for j = 0..=M, the first index whose cdf
/// exceeds j/M, with M the power of two at or above the number of items (at most 2²⁰).
fn guide_table(cdf: &[f64]) -> Vec<u32> {
    let intervals = (cdf.len().saturating_sub(1))
        .next_power_of_two()
        .min(1 << 20);
    let mut guide = Vec::with_capacity(intervals + 1);
    let mut first = 0;
    for j in 0..=intervals {
        let x = j as f64 / intervals as f64;
        while first < cdf.len() && cdf[first] <= x {
            first += 1;
        }
        guide.push(first as u32);
    }
    guide
}

impl Distribution1d {
    /// The distribution ∝ `weights`; `None` when there are no weights, any is negative or not
    /// finite (NaN, ±∞), the sum overflows, or all are zero.
    ///
    /// ```
    /// use orbifold_render::sampler::Distribution1d;
    ///
    /// assert!(Distribution1d::new(&[0.0, 0.0]).is_none());
    /// assert!(Distribution1d::new(&[1.0, -1.0]).is_none());
    /// assert!(Distribution1d::new(&[1.0, f64::NAN]).is_none());
    /// assert!(Distribution1d::new(&[]).is_none());
    /// assert!(Distribution1d::new(&[2.0]).is_some());
    /// ```
    pub fn new(weights: &[f64]) -> Option<Self> {
        if weights.iter().any(|w| !w.is_finite() || *w < 0.0) {
            return None;
        }
        let total: f64 = weights.iter().sum();
        if !(total.is_finite() && total > 0.0) {
            return None;
        }
        let pmf: Vec<f64> = weights.iter().map(|w| w / total).collect();
        let mut cdf = Vec::with_capacity(weights.len() + 1);
        let mut running = 0.0;
        cdf.push(0.0);
        for w in weights {
            running += w;
            cdf.push(running / total);
        }
        let last_positive = weights.iter().rposition(|w| *w > 0.0)?;
        // Items after the last positive one end exactly at 1, so none can be reached.
        for c in &mut cdf[last_positive + 1..] {
            *c = 1.0;
        }
        let guide = guide_table(&cdf);
        Some(Distribution1d {
            cdf,
            pmf,
            total,
            last_positive,
            guide,
        })
    }

    /// The item for the uniform `u` in [0, 1), and its probability. Items of zero weight are
    /// never returned; `u` outside [0, 1) (or NaN) is clamped.
    ///
    /// ```
    /// use orbifold_render::sampler::Distribution1d;
    ///
    /// let d = Distribution1d::new(&[0.0, 1.0, 1.0, 0.0]).unwrap();
    /// assert_eq!(d.sample(0.0), (1, 0.5));
    /// assert_eq!(d.sample(0.999), (2, 0.5));
    /// assert_eq!(d.sample(1.0), (2, 0.5));
    /// ```
    pub fn sample(&self, u: f64) -> (usize, f64) {
        let u = if u.is_nan() { 0.0 } else { u.max(0.0) };
        // The first index whose cdf exceeds u is one past the item: cdf[i] ≤ u < cdf[i + 1],
        // an interval that is empty for items of zero weight.
        let i = self
            .first_above(u)
            .saturating_sub(1)
            .min(self.last_positive);
        (i, self.pmf[i])
    }

    /// The first index whose cdf exceeds `u` (≥ 0), as `partition_point` over the whole cdf
    /// finds it, searched between the guide table's two entries around `u`.
    #[inline]
    fn first_above(&self, u: f64) -> usize {
        let intervals = self.guide.len() - 1;
        // Exact: M is a power of two. (The cast saturates; u ≥ 1 goes to the full search.)
        let j = (u * intervals as f64) as usize;
        // `j + 1` would overflow for a saturated cast (u = ∞): that goes to the full search.
        match (self.guide.get(j), self.guide.get(j.wrapping_add(1))) {
            (Some(&lo), Some(&hi)) => {
                let (lo, hi) = (lo as usize, hi as usize);
                lo + self.cdf[lo..hi].partition_point(|c| *c <= u)
            }
            _ => self.cdf.partition_point(|c| *c <= u),
        }
    }

    /// The probability of item `i` (0 for indices out of range).
    ///
    /// ```
    /// use orbifold_render::sampler::Distribution1d;
    ///
    /// let d = Distribution1d::new(&[1.0, 3.0]).unwrap();
    /// assert_eq!(d.pmf(1), 0.75);
    /// assert_eq!(d.pmf(5), 0.0);
    /// ```
    pub fn pmf(&self, i: usize) -> f64 {
        self.pmf.get(i).copied().unwrap_or(0.0)
    }

    /// The number of items (including those of zero weight).
    ///
    /// ```
    /// use orbifold_render::sampler::Distribution1d;
    ///
    /// assert_eq!(Distribution1d::new(&[1.0, 0.0]).unwrap().len(), 2);
    /// ```
    pub fn len(&self) -> usize {
        self.pmf.len()
    }

    /// Always `false`: a distribution has at least one item of positive weight.
    ///
    /// ```
    /// use orbifold_render::sampler::Distribution1d;
    ///
    /// assert!(!Distribution1d::new(&[1.0]).unwrap().is_empty());
    /// ```
    pub fn is_empty(&self) -> bool {
        self.pmf.is_empty()
    }

    /// The sum of the weights.
    ///
    /// ```
    /// use orbifold_render::sampler::Distribution1d;
    ///
    /// assert_eq!(Distribution1d::new(&[1.0, 2.5]).unwrap().total(), 3.5);
    /// ```
    pub fn total(&self) -> f64 {
        self.total
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn numbers_at_or_past_one_are_searched_without_overflow() {
        let distribution = Distribution1d::new(&[1.0, 2.0, 0.0, 1.0]).unwrap();
        for u in [1.0, 1.5, f64::MAX, f64::INFINITY] {
            assert_eq!(
                distribution.first_above(u),
                distribution.first_above(1.0),
                "u = {u}"
            );
        }
    }
}
