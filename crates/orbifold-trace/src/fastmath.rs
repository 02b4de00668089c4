//! Elementary functions where libm's full accuracy costs more than the hot paths can afford:
//! the BVH's disc test calls a logarithm (H²) or an arc tangent (S²) for every node it tests,
//! and the per-point weights of light images a logarithm (H²) or an arc sine (S²) for every near
//! image at every path vertex. Being straight-line code (selects, no branches), they also let a
//! node's eight bound tests run side by side. Each has a stated absolute error bound, which the
//! callers widen their bounds by (or, for sampling weights, which only need to agree with
//! themselves, ignore).

/// Absolute error bound of [`ln_fast`] and so of [`asinh_fast`] (what bounds are widened by).
pub const LN_FAST_ERROR: f64 = 1e-10;

/// ln x for finite normal x > 0 (x ≥ 1 is what [`asinh_fast`] takes; the denoiser's cosines are
/// in (0, 1]) to within [`LN_FAST_ERROR`]: x = 2^e·m with
/// m in [√½, √2), ln m = 2 artanh z for z = (m − 1)/(m + 1), |z| ≤ 0.172, by its series to z¹¹
/// (the rest is below 2e-11). Inlined and branch-light, it costs a fraction of libm's `ln`, and
/// a bound test does two of them.
#[inline(always)]
pub fn ln_fast(x: f64) -> f64 {
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

/// Relative error bound of [`exp_fast`] (what its test holds it to).
#[cfg_attr(not(test), allow(dead_code))]
pub const EXP_FAST_ERROR: f64 = 1e-11;

/// eˣ for x ≤ 709 to within a relative [`EXP_FAST_ERROR`]; 0 below −708 (where eˣ nears the
/// smallest normal number), NaN for NaN. x = n·ln 2 + r with n an integer and |r| ≤ ½ ln 2
/// (ln 2 in two parts, so that n·ln 2 is exact), eʳ by its Taylor series to r⁹ (the rest is
/// below 1e-11), and 2ⁿ from its bits. Straight-line code: the denoiser's weights of a row of
/// pixels run side by side in SIMD lanes, where a call into libm runs one at a time.
#[inline(always)]
pub fn exp_fast(x: f64) -> f64 {
    // 1.5·2⁵²: adding it and taking it away rounds to the nearest integer (|v| < 2⁵¹).
    const SHIFTER: f64 = 6_755_399_441_055_744.0;
    // fdlibm's split of ln 2: the high part has 11 trailing zero bits, so n·LN2_HI is exact.
    const LN2_HI: f64 = f64::from_bits(0x3fe6_2e42_fee0_0000);
    const LN2_LO: f64 = f64::from_bits(0x3dea_39ef_3579_3c76);
    // The comparison is false for NaN, which so stays NaN.
    let clamped = if x < -708.0 { -708.0 } else { x };
    let shifted = clamped * std::f64::consts::LOG2_E + SHIFTER;
    let n = shifted - SHIFTER;
    let r = (clamped - n * LN2_HI) - n * LN2_LO;
    // 1 + r(1 + r/2(1 + r/3(… (1 + r/9)))): the series to r⁹/9!.
    const INVERSES: [f64; 9] = [
        1.0,
        1.0 / 2.0,
        1.0 / 3.0,
        1.0 / 4.0,
        1.0 / 5.0,
        1.0 / 6.0,
        1.0 / 7.0,
        1.0 / 8.0,
        1.0 / 9.0,
    ];
    let mut series = 1.0;
    for inverse in INVERSES.iter().rev() {
        series = 1.0 + r * series * inverse;
    }
    // 2ⁿ for n in [−1022, 1023], from the low bits of `shifted`'s mantissa, which hold n (in
    // two's complement, under 2⁵¹): integer shifts and adds, which SIMD lanes have, where
    // a float's conversion to an integer has none in AVX2. (For NaN the scale is whatever; the
    // series is NaN.)
    let scale = f64::from_bits((shifted.to_bits() << 52).wrapping_add(1023 << 52));
    if x < -708.0 { 0.0 } else { series * scale }
}

/// Absolute error bound of [`atan2_fast`] and so of [`asin_fast`].
pub const ATAN_FAST_ERROR: f64 = 2e-11;

/// tan(π/8) = √2 − 1: above it, the arc tangent's argument is reduced through π/4.
const TAN_PI_8: f64 = std::f64::consts::SQRT_2 - 1.0;

/// atan2(y, x) to within [`ATAN_FAST_ERROR`] (0 for y = x = 0). The octant reduction leaves
/// t = min(|x|, |y|)/max(|x|, |y|) in [0, 1]; above tan(π/8), atan t = π/4 + atan z with
/// z = (t − 1)/(t + 1), so |z| ≤ tan(π/8) ≈ 0.414, where atan z = z·P(z²) for a degree-6
/// polynomial P fitted to atan z / z at Chebyshev nodes (least squares on the absolute error;
/// it stays within 5e-12). One division, no branch.
#[inline(always)]
pub fn atan2_fast(y: f64, x: f64) -> f64 {
    use std::f64::consts::{FRAC_PI_2, FRAC_PI_4, PI};
    const P: [f64; 7] = [
        0.999_999_999_885_366_4,
        -0.333_333_304_857_840_7,
        0.199_998_067_596_376_6,
        -0.142_800_265_562_431_64,
        0.110_251_824_057_219_28,
        -0.083_844_063_965_209_66,
        0.045_780_773_044_384_21,
    ];
    let (ax, ay) = (x.abs(), y.abs());
    let (lo, hi) = (ax.min(ay), ax.max(ay));
    let reduced = lo > TAN_PI_8 * hi;
    let (num, den) = if reduced {
        (lo - hi, lo + hi)
    } else {
        (lo, hi)
    };
    let z = if den > 0.0 { num / den } else { 0.0 };
    let z2 = z * z;
    let series = P.iter().rev().fold(0.0, |acc, &c| c + z2 * acc);
    let mut angle = z * series + if reduced { FRAC_PI_4 } else { 0.0 };
    if ay > ax {
        angle = FRAC_PI_2 - angle;
    }
    if x < 0.0 {
        angle = PI - angle;
    }
    angle.copysign(y)
}

/// asin(x) for x in [−1, 1] to within [`ATAN_FAST_ERROR`] (as atan2(x, √(1 − x²)), with
/// 1 − x² = (1 − x)(1 + x) to keep the digits near ±1).
#[inline(always)]
pub fn asin_fast(x: f64) -> f64 {
    atan2_fast(x, ((1.0 - x) * (1.0 + x)).max(0.0).sqrt())
}

/// asinh(x) = sign(x)·ln(|x| + √(x² + 1)) to within [`LN_FAST_ERROR`] in absolute terms (its
/// relative error near 0 does not matter for bounds, which are widened by that much).
#[inline(always)]
pub fn asinh_fast(x: f64) -> f64 {
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
    fn fast_atan2_is_within_its_bound() {
        // Every direction around the circle, at radii from 1e-300 to 1e300, and the axes.
        let mut worst: f64 = 0.0;
        for i in 0..200_000 {
            let t = f64::from(i) / 200_000.0 * std::f64::consts::TAU;
            for r in [1e-300, 1e-3, 1.0, 7.5, 1e300] {
                let (y, x) = (r * t.sin(), r * t.cos());
                worst = worst.max((atan2_fast(y, x) - y.atan2(x)).abs());
            }
        }
        for (y, x) in [
            (0.0, 1.0),
            (1.0, 0.0),
            (0.0, -1.0),
            (-1.0, 0.0),
            (0.0, 0.0),
            (2.0, 2.0),
        ] {
            worst = worst.max((atan2_fast(y, x) - f64::atan2(y, x)).abs());
        }
        assert!(worst < ATAN_FAST_ERROR, "{worst:e}");
    }

    #[test]
    fn fast_asin_is_within_its_bound() {
        let mut worst: f64 = 0.0;
        for i in -100_000..=100_000 {
            let x = f64::from(i) / 100_000.0;
            for x in [x, x.next_up().min(1.0), x.next_down().max(-1.0)] {
                worst = worst.max((asin_fast(x) - x.asin()).abs());
            }
        }
        assert!(worst < ATAN_FAST_ERROR, "{worst:e}");
    }

    #[test]
    fn fast_exp_is_within_its_bound() {
        // Densely over [−708, 709], and at the seams of the range reduction (odd multiples of
        // ½ ln 2), relative to libm's.
        let mut worst: f64 = 0.0;
        for i in 0..=1_417_000 {
            let x = -708.0 + f64::from(i) * 1e-3;
            worst = worst.max(((exp_fast(x) - x.exp()) / x.exp()).abs());
        }
        for k in -2041..2045 {
            let seam = f64::from(k) * 0.5 * std::f64::consts::LN_2;
            for x in [seam.next_down(), seam, seam.next_up()] {
                if (-708.0..=709.0).contains(&x) {
                    worst = worst.max(((exp_fast(x) - x.exp()) / x.exp()).abs());
                }
            }
        }
        assert!(worst < EXP_FAST_ERROR, "{worst:e}");
        assert_eq!(exp_fast(0.0), 1.0);
        assert_eq!(exp_fast(-708.5), 0.0);
        assert_eq!(exp_fast(f64::NEG_INFINITY), 0.0);
        assert!(exp_fast(f64::NAN).is_nan());
    }

    #[test]
    fn fast_ln_is_within_its_bound_below_one() {
        // The denoiser takes the logarithm of cosines in (0, 1].
        let mut worst: f64 = 0.0;
        for e in 1..1000 {
            for i in 0..200 {
                let x = 2f64.powi(-e) * (1.0 + f64::from(i) / 200.0);
                worst = worst.max((ln_fast(x) - x.ln()).abs());
            }
        }
        assert!(worst < LN_FAST_ERROR, "{worst:e}");
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
