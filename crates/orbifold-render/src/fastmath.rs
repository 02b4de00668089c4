//! Elementary functions where libm's full accuracy costs more than the hot paths can afford:
//! the bound test of the hyperbolic BVH and the per-point weights of light images call a
//! logarithm for every node and every near image. Each has a stated absolute error bound, which
//! the callers widen their bounds by (or, for sampling weights, which only need to agree with
//! themselves, ignore).

/// Absolute error bound of [`ln_fast`] and so of [`asinh_fast`] (what bounds are widened by).
pub(crate) const LN_FAST_ERROR: f64 = 1e-10;

/// ln x for finite x ≥ 1 (what [`asinh_fast`] takes) to within [`LN_FAST_ERROR`]: x = 2^e·m with
/// m in [√½, √2), ln m = 2 artanh z for z = (m − 1)/(m + 1), |z| ≤ 0.172, by its series to z¹¹
/// (the rest is below 2e-11). Inlined and branch-light, it costs a fraction of libm's `ln`, and
/// a bound test does two of them.
#[inline(always)]
pub(crate) fn ln_fast(x: f64) -> f64 {
    const MANTISSA: u64 = (1 << 52) - 1;
    let bits = x.to_bits();
    let mut exponent = ((bits >> 52) & 0x7ff) as i64 - 1023;
    let mut m = f64::from_bits((bits & MANTISSA) | 1f64.to_bits());
    if m > std::f64::consts::SQRT_2 {
        m *= 0.5;
        exponent += 1;
    }
    let z = (m - 1.0) / (m + 1.0);
    let z2 = z * z;
    let series = 1.0
        + z2 * (1.0 / 3.0
            + z2 * (1.0 / 5.0 + z2 * (1.0 / 7.0 + z2 * (1.0 / 9.0 + z2 * (1.0 / 11.0)))));
    exponent as f64 * std::f64::consts::LN_2 + 2.0 * z * series
}

/// asinh(x) = sign(x)·ln(|x| + √(x² + 1)) to within [`LN_FAST_ERROR`] in absolute terms (its
/// relative error near 0 does not matter for bounds, which are widened by that much).
#[inline(always)]
pub(crate) fn asinh_fast(x: f64) -> f64 {
    let a = x.abs();
    ln_fast(a + (a * a + 1.0).sqrt()).copysign(x)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fast_asinh_is_accurate() {
        for i in -20_000..=20_000 {
            let x = f64::from(i) * 1e-3;
            assert!((asinh_fast(x) - x.asinh()).abs() < LN_FAST_ERROR, "{x}");
        }
        assert_eq!(asinh_fast(-0.0), 0.0);
        assert!((asinh_fast(1e12) - 1e12f64.asinh()).abs() < LN_FAST_ERROR);
    }

    #[test]
    fn fast_ln_is_within_its_bound() {
        // Every binade from 1 to 2^600, densely around the reduction's seam at √2.
        let mut worst: f64 = 0.0;
        for e in 0..600 {
            for i in 0..2000 {
                let x = 2f64.powi(e) * (1.0 + f64::from(i) / 2000.0);
                worst = worst.max((ln_fast(x) - x.ln()).abs());
            }
            let seam = 2f64.powi(e) * std::f64::consts::SQRT_2;
            for x in [seam.next_down(), seam, seam.next_up()] {
                worst = worst.max((ln_fast(x) - x.ln()).abs());
            }
        }
        assert!(worst < LN_FAST_ERROR, "{worst:e}");
        assert_eq!(ln_fast(1.0), 0.0);
    }
}
