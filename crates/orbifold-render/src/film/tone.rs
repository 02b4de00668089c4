//! Exposure and tone mapping: from the film's linear radiance to display values — the
//! automatic exposure from the image's log-average luminance, the filmic curve of Narkowicz
//! (2015), and the sRGB encoding.

use orbifold_scene::color::luminance;

use super::Film;

impl Film {
    /// Exposure (stops) that takes the image's log-average luminance to middle grey
    /// (Reinhard's key 0.18), within ±12 stops; 0 for a black image.
    ///
    /// ```
    /// use orbifold_render::film::Film;
    ///
    /// let mut film = Film::new(2, 1);
    /// film.add(0, 0, [0.72; 3]);
    /// film.add(1, 0, [0.72; 3]);
    /// assert!((film.auto_exposure() + 2.0).abs() < 1e-3);
    /// assert_eq!(Film::new(2, 2).auto_exposure(), 0.0);
    /// ```
    pub fn auto_exposure(&self) -> f64 {
        let (mut sum, mut count) = (0.0, 0.0);
        for i in 0..self.count.len() {
            let l = luminance(self.mean_at(i));
            if l.is_finite() && l > 0.0 {
                sum += (1e-4 + l).ln();
                count += 1.0;
            }
        }
        if count == 0.0 {
            return 0.0;
        }
        (0.18 / (sum / count).exp()).log2().clamp(-12.0, 12.0)
    }
}

/// The filmic curve of Narkowicz (2015), "ACES Filmic Tone Mapping Curve": a fit of the ACES
/// reference rendering transform, x(2.51x + 0.03) / (x(2.43x + 0.59) + 0.14), clamped to [0, 1].
/// Increasing on [0, ∞), 0 at 0, and 1 from x ≈ 8.5 on.
fn aces_narkowicz(x: f64) -> f64 {
    ((x * (2.51 * x + 0.03)) / (x * (2.43 * x + 0.59) + 0.14)).clamp(0.0, 1.0)
}

/// The tone curve of [`tone_map`] for one channel, before rounding: linear radiance `x` at
/// `exposure` stops to the encoded display value in [0, 1].
///
/// ```
/// use orbifold_render::film::{tone_curve, tone_map};
///
/// let x = 0.3;
/// assert_eq!((tone_curve(x, 0.5) * 255.0).round() as u8, tone_map([x; 3], 0.5)[0]);
/// ```
pub fn tone_curve(x: f64, exposure: f64) -> f64 {
    let x = (x * exposure.exp2()).max(0.0);
    if x.is_infinite() {
        1.0
    } else {
        orbifold_scene::color::srgb_encode(aces_narkowicz(x))
    }
}

/// Tone-maps linear radiance to 8-bit sRGB: each channel is multiplied by 2^`exposure`
/// (`exposure` in stops), mapped by the ACES filmic fit of Narkowicz (2015),
/// x(2.51x + 0.03)/(x(2.43x + 0.59) + 0.14) clamped to [0, 1] (applied per channel, without
/// the 0.6 pre-exposure of the original article), encoded with the sRGB OETF and rounded to
/// 0..=255. Negative and NaN values give 0, +∞ gives 255. Nondecreasing in each channel.
///
/// ```
/// use orbifold_render::film::tone_map;
///
/// assert_eq!(tone_map([0.0; 3], 0.0), [0, 0, 0]);
/// assert_eq!(tone_map([1e9; 3], 0.0), [255, 255, 255]);
/// let [r, _, _] = tone_map([0.18, 0.0, 0.0], 0.0);
/// let [brighter, _, _] = tone_map([0.18, 0.0, 0.0], 1.0);
/// assert!(brighter > r);
/// ```
pub fn tone_map(rgb: [f64; 3], exposure: f64) -> [u8; 3] {
    // `f64::max` in `tone_curve` maps NaN to 0 too.
    rgb.map(|c| (tone_curve(c, exposure) * 255.0).round().clamp(0.0, 255.0) as u8)
}
