//! Multiple importance sampling (Veach's thesis, 1997, ch. 9): the weight that lets two
//! strategies estimate the same light — a direction drawn from the BSDF and a point drawn on the
//! light — and be added into one estimator whose variance is close to that of the better
//! strategy for each path.

/// The power heuristic (β = 2) of Veach for multiple importance sampling: the weight of a sample
/// drawn `nf` times from a strategy with density `f_pdf`, against `ng` samples of a strategy with
/// density `g_pdf`: (nf·f_pdf)² / ((nf·f_pdf)² + (ng·g_pdf)²).
///
/// Robust at the edges: 0 when `f_pdf` is 0 (or anything is NaN); otherwise 1 when `g_pdf` is
/// 0; an infinite density (a delta strategy) takes all the weight (1/2 if both are infinite);
/// no overflow for huge finite densities. The result is always in [0, 1].
///
/// ```
/// use orbifold_render::sampler::power_heuristic;
///
/// assert_eq!(power_heuristic(1.0, 2.0, 1.0, 2.0), 0.5);
/// assert_eq!(power_heuristic(1.0, 3.0, 1.0, 0.0), 1.0);
/// assert_eq!(power_heuristic(1.0, 0.0, 1.0, 3.0), 0.0);
/// assert_eq!(power_heuristic(1.0, f64::INFINITY, 1.0, 3.0), 1.0);
/// ```
pub fn power_heuristic(nf: f64, f_pdf: f64, ng: f64, g_pdf: f64) -> f64 {
    let f = (nf * f_pdf).abs();
    let g = (ng * g_pdf).abs();
    if f.is_nan() || g.is_nan() || f == 0.0 {
        return 0.0;
    }
    if g == 0.0 {
        return 1.0;
    }
    if f.is_infinite() && g.is_infinite() {
        return 0.5;
    }
    // (g/f) is in [0, ∞]; 1/(1 + r²) never overflows into NaN.
    let r = g / f;
    1.0 / (1.0 + r * r)
}
