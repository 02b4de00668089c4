//! Playing a dry sound through the room: its convolution with the impulse response, by the
//! fast Fourier transform (overlap-free: one transform of the whole length, which for sounds of
//! seconds is a few million points at most).

use rustfft::FftPlanner;
use rustfft::num_complex::Complex32;

use crate::error::SoundError;

/// The most samples a convolution may have (2²⁶, a quarter of an hour at 48 kHz).
pub const MAX_SAMPLES: usize = 1 << 26;

/// The full convolution of `dry` with `response` (length |dry| + |response| − 1).
///
/// ```
/// use orbifold_sound::convolve::convolve;
/// let out = convolve(&[1.0, 2.0], &[0.0, 1.0, 0.5]).unwrap();
/// let expected = [0.0, 1.0, 2.5, 1.0];
/// assert!(out.iter().zip(expected).all(|(a, b)| (a - b).abs() < 1e-5));
/// ```
pub fn convolve(dry: &[f32], response: &[f32]) -> Result<Vec<f32>, SoundError> {
    if dry.is_empty() || response.is_empty() {
        return Ok(Vec::new());
    }
    let n = dry.len() + response.len() - 1;
    if n > MAX_SAMPLES {
        return Err(SoundError::TooLong(n));
    }
    let size = n.next_power_of_two();
    let mut planner = FftPlanner::<f32>::new();
    let forward = planner.plan_fft_forward(size);
    let inverse = planner.plan_fft_inverse(size);
    let spectrum = |signal: &[f32]| {
        let mut buffer: Vec<Complex32> = signal.iter().map(|&x| Complex32::new(x, 0.0)).collect();
        buffer.resize(size, Complex32::new(0.0, 0.0));
        forward.process(&mut buffer);
        buffer
    };
    let mut product = spectrum(dry);
    let other = spectrum(response);
    product.iter_mut().zip(&other).for_each(|(a, b)| *a *= b);
    inverse.process(&mut product);
    let scale = 1.0 / size as f32;
    Ok(product[..n].iter().map(|c| c.re * scale).collect())
}
