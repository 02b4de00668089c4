//! Checkerboards: squares of two colours, of side `size`, in two or three texture coordinates
//! (on an object the checker is solid: its cubes cut the surface). Seen by a camera ray, the
//! board is box-filtered over the pixel's footprint in closed form: the mean of a square wave
//! over an interval is a difference of its integral, a triangle wave, one axis at a time.

use glam::DVec3;

use super::TextureEvalContext;
use crate::lights::Rgb;

/// The checkerboard's albedo where `lookup` says: the colour of the square at the point, or,
/// with a pixel footprint, the board's mean over the box whose second moments are the
/// footprint's.
pub(super) fn albedo(
    colors: &[Rgb; 2],
    size: f64,
    intrinsic: bool,
    lookup: &TextureEvalContext,
) -> Rgb {
    let Some([centre, a, b]) = lookup.footprint else {
        let p = (lookup.coords)(intrinsic, DVec3::ZERO);
        let parity: i64 = p.iter().map(|v| (v / size).floor() as i64).sum();
        return colors[parity.rem_euclid(2) as usize];
    };
    let (p, pa, pb) = (
        (lookup.coords)(intrinsic, centre),
        (lookup.coords)(intrinsic, centre + a),
        (lookup.coords)(intrinsic, centre + b),
    );
    let mut sign = 1.0;
    for i in 0..3 {
        // The box, axis by axis in texture coordinates, whose second moments are the
        // footprint's (the parallelogram ±a ± b around the pixel's centre): a box around the
        // whole parallelogram would blur footprints seen at an angle to the checks over twice
        // their area.
        let half = ((pa[i] - p[i]).powi(2) + (pb[i] - p[i]).powi(2)).sqrt();
        sign *= box_filtered_square_wave(p[i] / size, 2.0 * half / size);
    }
    let (c0, c1) = (colors[0], colors[1]);
    std::array::from_fn(|k| 0.5 * (c0[k] + c1[k]) + 0.5 * (c0[k] - c1[k]) * sign)
}

/// The mean of the square wave (−1)^⌊t⌋ over [x − w/2, x + w/2] (its value at x when w = 0, or
/// when the box is not finite: 0 then, the wave's mean): differences of its integral, the
/// triangle wave.
fn box_filtered_square_wave(x: f64, w: f64) -> f64 {
    let integral = |t: f64| {
        let m = t.rem_euclid(2.0);
        if m < 1.0 { m } else { 2.0 - m }
    };
    if !(x.is_finite() && w.is_finite()) {
        return 0.0;
    }
    if w < 1e-9 {
        return if x.floor().rem_euclid(2.0) == 0.0 {
            1.0
        } else {
            -1.0
        };
    }
    ((integral(x + 0.5 * w) - integral(x - 0.5 * w)) / w).clamp(-1.0, 1.0)
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    proptest! {
        /// The box-filtered square wave is the mean of the wave over the box (midpoint rule
        /// with 20 000 points), and stays in [−1, 1].
        #[test]
        fn the_filtered_checker_is_the_checker_s_mean(x in -5.0f64..5.0, w in 0.0f64..4.0) {
            let n = 20_000;
            let mean = (0..n)
                .map(|i| {
                    let t = x - 0.5 * w + w * (f64::from(i) + 0.5) / f64::from(n);
                    if t.floor().rem_euclid(2.0) == 0.0 { 1.0 } else { -1.0 }
                })
                .sum::<f64>()
                / f64::from(n);
            let filtered = box_filtered_square_wave(x, w);
            prop_assert!((filtered - mean).abs() < 1e-3 + 2e-4 / w.max(1e-9), "{} vs {}", filtered, mean);
            prop_assert!((-1.0..=1.0).contains(&filtered));
        }
    }
}
