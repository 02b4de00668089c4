//! What a reflection and the air take from a sound, per octave band.
//!
//! A surface of absorption coefficient α reflects the fraction 1 − α of the incident energy, so
//! the pressure of a specular reflection is multiplied by the reflection coefficient √(1 − α)
//! (Kuttruff, *Room Acoustics*, 6th ed., §2.4 and §4.1; Allen & Berkley 1979 call it β). The air
//! takes a share that grows with distance and steeply with frequency (ISO 9613-1; Kuttruff
//! §1.6); it is given in decibels per kilometre at 20 °C and 50 % relative humidity.

pub use orbifold_scene::sound::OCTAVE_BANDS;

/// The number of octave bands.
pub const BANDS: usize = OCTAVE_BANDS.len();

/// One value per octave band (125 Hz to 8 kHz).
pub type Bands = [f64; BANDS];

/// Attenuation by air at 20 °C and 50 % relative humidity, decibels per kilometre, per octave
/// band (ISO 9613-1:1993, Table 1, rounded).
pub const AIR_DB_PER_KM: Bands = [0.44, 1.31, 2.73, 4.66, 9.86, 29.4, 104.0];

/// The pressure reflection coefficients √(1 − α) of absorption coefficients α.
///
/// ```
/// use orbifold_sound::absorption::reflection;
/// assert_eq!(reflection(&[0.75; 7]), [0.5; 7]);
/// ```
pub fn reflection(alpha: &Bands) -> Bands {
    alpha.map(|a| (1.0 - a).clamp(0.0, 1.0).sqrt())
}

/// The pressure factor per band that `metres` of air leave, or 1 in every band without air
/// absorption.
///
/// ```
/// use orbifold_sound::absorption::air_factor;
/// // 1 km at 8 kHz: 104 dB, a factor of 10^(−104/20).
/// assert!((air_factor(1000.0, true)[6] - 10f64.powf(-5.2)).abs() < 1e-12);
/// assert_eq!(air_factor(1000.0, false), [1.0; 7]);
/// ```
pub fn air_factor(metres: f64, air: bool) -> Bands {
    if !air {
        return [1.0; BANDS];
    }
    AIR_DB_PER_KM.map(|db| 10f64.powf(-db * metres / 20_000.0))
}

/// The product of two band values.
pub(crate) fn times(a: &Bands, b: &Bands) -> Bands {
    std::array::from_fn(|i| a[i] * b[i])
}

/// Each band raised to an integer power.
pub(crate) fn powi(a: &Bands, n: u32) -> Bands {
    // Counts of reflections stay far below i32::MAX.
    a.map(|x| x.powi(n.min(i32::MAX as u32) as i32))
}

/// The largest value of any band.
pub(crate) fn largest(a: &Bands) -> f64 {
    a.iter().copied().fold(0.0, f64::max)
}

/// The root mean square over the bands: the broadband pressure amplitude of a sound whose
/// energy is spread evenly over the octaves (exactly the common value when every band has it).
pub(crate) fn broadband(a: &Bands) -> f64 {
    let mean = a.iter().map(|x| x * x).sum::<f64>() / BANDS as f64;
    let flat = a.iter().all(|&x| x == a[0]);
    if flat { a[0] } else { mean.sqrt() }
}
