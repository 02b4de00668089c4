//! A built-in dry sound: a synthetic hand clap, the classic way to hear a room.
//!
//! A clap is a few bursts of noise a few milliseconds apart as the hands meet, then a short
//! decaying tail, with most of its energy around 1–2 kHz (as in the TR-808's clap and in
//! Peltola et al., "Synthesis of hand clapping sounds", IEEE TASLP 15, 2007). The noise comes
//! from a fixed linear congruential generator, so the clap is the same on every machine.

use crate::octave_filter::Biquad;

/// The clap's length, seconds.
pub const CLAP_SECONDS: f64 = 0.2;

/// The clap at a sample rate, peak 1.
///
/// ```
/// use orbifold_sound::clap::clap;
/// let c = clap(48_000);
/// assert_eq!(c.len(), 9600);
/// assert!((c.iter().fold(0.0f32, |m, x| m.max(x.abs())) - 1.0).abs() < 1e-6);
/// assert_eq!(c, clap(48_000));
/// ```
pub fn clap(sample_rate: u32) -> Vec<f32> {
    let rate = f64::from(sample_rate);
    let n = (CLAP_SECONDS * rate).round() as usize;
    let mut state: u64 = 0x2545_f491_4f6c_dd1d;
    let mut noise = || {
        // Knuth's MMIX constants; the top bits as a uniform number in [−1, 1).
        state = state
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407);
        (state >> 11) as f64 / (1u64 << 52) as f64 - 1.0
    };
    // Bursts at these times (s), each decaying with its time constant, the last the tail.
    let bursts = [
        (0.0, 0.0015),
        (0.008, 0.0015),
        (0.016, 0.0015),
        (0.024, 0.03),
    ];
    let mut signal: Vec<f64> = (0..n)
        .map(|i| {
            let t = i as f64 / rate;
            let envelope: f64 = bursts
                .iter()
                .filter(|(start, _)| t >= *start)
                .map(|(start, tau)| (-(t - start) / tau).exp())
                .sum();
            envelope * noise()
        })
        .collect();
    Biquad::band_pass(1200.0_f64.min(0.4 * rate), 1.2, rate).apply(&mut signal);
    let peak = signal.iter().fold(0.0f64, |m, x| m.max(x.abs()));
    signal
        .iter()
        .map(|x| if peak > 0.0 { (x / peak) as f32 } else { 0.0 })
        .collect()
}
