//! Octave-band filters: second-order sections (Bristow-Johnson's "Audio EQ Cookbook"), a
//! low-pass for the lowest band, band-passes of one octave for the middle ones and a high-pass
//! for the highest, which together pass every frequency to within a few decibels. They turn an
//! impulse response given per octave band (when absorption depends on frequency) into one
//! signal ([`crate::impulse`]).

use std::f64::consts::PI;

use crate::absorption::{BANDS, OCTAVE_BANDS};

/// A biquad filter, direct form I.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Biquad {
    b: [f64; 3],
    a: [f64; 2],
}

impl Biquad {
    fn normalised(b: [f64; 3], a0: f64, a: [f64; 2]) -> Biquad {
        Biquad {
            b: b.map(|x| x / a0),
            a: a.map(|x| x / a0),
        }
    }

    /// A band-pass of centre `f0` and quality `q` (0 dB at the centre).
    pub fn band_pass(f0: f64, q: f64, rate: f64) -> Biquad {
        let w = 2.0 * PI * f0 / rate;
        let alpha = w.sin() / (2.0 * q);
        Biquad::normalised(
            [alpha, 0.0, -alpha],
            1.0 + alpha,
            [-2.0 * w.cos(), 1.0 - alpha],
        )
    }

    /// A Butterworth low-pass at `f0`.
    pub fn low_pass(f0: f64, rate: f64) -> Biquad {
        let w = 2.0 * PI * f0 / rate;
        let alpha = w.sin() / std::f64::consts::SQRT_2;
        let c = w.cos();
        Biquad::normalised(
            [(1.0 - c) / 2.0, 1.0 - c, (1.0 - c) / 2.0],
            1.0 + alpha,
            [-2.0 * c, 1.0 - alpha],
        )
    }

    /// A Butterworth high-pass at `f0`.
    pub fn high_pass(f0: f64, rate: f64) -> Biquad {
        let w = 2.0 * PI * f0 / rate;
        let alpha = w.sin() / std::f64::consts::SQRT_2;
        let c = w.cos();
        Biquad::normalised(
            [(1.0 + c) / 2.0, -(1.0 + c), (1.0 + c) / 2.0],
            1.0 + alpha,
            [-2.0 * c, 1.0 - alpha],
        )
    }

    /// Filters a signal in place.
    ///
    /// ```
    /// use orbifold_sound::octave_filter::Biquad;
    /// // A low-pass passes a constant signal unchanged once it has settled.
    /// let mut x = vec![1.0f64; 4000];
    /// Biquad::low_pass(100.0, 48_000.0).apply(&mut x);
    /// assert!((x[3999] - 1.0).abs() < 1e-6);
    /// ```
    pub fn apply(&self, signal: &mut [f64]) {
        let (mut x1, mut x2, mut y1, mut y2) = (0.0, 0.0, 0.0, 0.0);
        for v in signal.iter_mut() {
            let x = *v;
            let y =
                self.b[0] * x + self.b[1] * x1 + self.b[2] * x2 - self.a[0] * y1 - self.a[1] * y2;
            (x2, x1, y2, y1) = (x1, x, y1, y);
            *v = y;
        }
    }
}

/// The filter of octave band `band` at a sample rate; `None` for bands at or above the Nyquist
/// frequency, which a response at that rate cannot hold.
pub fn band_filter(band: usize, rate: f64) -> Option<Biquad> {
    let f0 = OCTAVE_BANDS[band];
    // The edges of an octave band are a half-octave either side of its centre.
    let edge = std::f64::consts::SQRT_2;
    if f0 >= 0.45 * rate {
        return None;
    }
    Some(if band == 0 {
        Biquad::low_pass(f0 * edge, rate)
    } else if band + 1 == BANDS {
        Biquad::high_pass(f0 / edge, rate)
    } else {
        Biquad::band_pass(f0, std::f64::consts::SQRT_2, rate)
    })
}
