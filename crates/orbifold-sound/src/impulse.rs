//! The impulse response as a signal: each echo an impulse of its amplitude at the sample
//! nearest its arrival (Allen & Berkley 1979 round the same way).
//!
//! When every surface and the air absorb alike at all frequencies each echo is one impulse of
//! its amplitude. Otherwise each octave band gets its own train of impulses, filtered by that
//! band's filter ([`crate::octave_filter`]), and the bands are summed.

use crate::absorption::BANDS;
use crate::arrival::Arrival;
use crate::octave_filter::band_filter;

/// The response as `seconds × sample_rate` samples (pressure; the direct sound at one metre is
/// 1/(4π)).
///
/// ```
/// use orbifold_sound::arrival::Arrival;
/// use orbifold_sound::impulse::impulse_response;
/// let echo = Arrival { time: 0.01, length: 3.43, amplitude: 0.5, bands: [0.5; 7],
///     reflections: 0, path: 0, slab: 0 };
/// let ir = impulse_response(&[echo], 1000, 0.1);
/// assert_eq!(ir.len(), 100);
/// assert_eq!(ir[10], 0.5);
/// ```
pub fn impulse_response(arrivals: &[Arrival], sample_rate: u32, seconds: f64) -> Vec<f32> {
    let n = (seconds * f64::from(sample_rate)).round().max(1.0) as usize;
    let rate = f64::from(sample_rate);
    let index = |a: &Arrival| {
        let i = (a.time * rate).round();
        (i >= 0.0 && (i as usize) < n).then_some(i as usize)
    };
    let flat = arrivals
        .iter()
        .all(|a| a.bands.iter().all(|&b| b == a.bands[0]));
    if flat {
        let mut out = vec![0.0f64; n];
        for a in arrivals {
            if let Some(i) = index(a) {
                out[i] += a.amplitude;
            }
        }
        return out.into_iter().map(|x| x as f32).collect();
    }
    let mut out = vec![0.0f64; n];
    for band in 0..BANDS {
        let Some(filter) = band_filter(band, rate) else {
            continue;
        };
        let mut signal = vec![0.0f64; n];
        for a in arrivals {
            if let Some(i) = index(a) {
                signal[i] += f64::from(a.bands[band]);
            }
        }
        filter.apply(&mut signal);
        out.iter_mut().zip(&signal).for_each(|(o, s)| *o += s);
    }
    out.into_iter().map(|x| x as f32).collect()
}
