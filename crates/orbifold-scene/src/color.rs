//! Colour, written once for the scene, the renderer and the preview: linear RGB triples, their
//! luminance, and the sRGB transfer functions between linear light and display values.
//!
//! Luminance uses the Rec. ITU-R BT.709 primaries' weights (the sRGB primaries); the transfer
//! functions are those of IEC 61966-2-1 (sRGB).
//!
//! ```
//! use orbifold_scene::color::{Rgb, luminance, srgb_decode, srgb_encode};
//!
//! let grey: Rgb = [0.5; 3];
//! assert!((luminance(grey) - 0.5).abs() < 1e-15);
//! assert!((srgb_decode(srgb_encode(0.2)) - 0.2).abs() < 1e-12);
//! ```

/// A linear RGB triple: a reflectance, a radiance or a path's throughput, depending on use.
pub type Rgb = [f64; 3];

/// The luminance Y of a linear RGB colour (BT.709 weights, which sum to 1).
#[inline]
pub fn luminance(c: Rgb) -> f64 {
    0.2126 * c[0] + 0.7152 * c[1] + 0.0722 * c[2]
}

/// The sRGB encoding (opto-electronic transfer function) of a linear value in [0, 1].
#[inline]
pub fn srgb_encode(linear: f64) -> f64 {
    if linear <= 0.003_130_8 {
        12.92 * linear
    } else {
        1.055 * linear.powf(1.0 / 2.4) - 0.055
    }
}

/// The linear value of an sRGB-encoded value in [0, 1] (the inverse of [`srgb_encode`]).
#[inline]
pub fn srgb_decode(encoded: f64) -> f64 {
    if encoded <= 0.04045 {
        encoded / 12.92
    } else {
        ((encoded + 0.055) / 1.055).powf(2.4)
    }
}

/// A linear value as an 8-bit sRGB display value (clamped to [0, 1] first).
///
/// ```
/// use orbifold_scene::color::srgb8_from_linear;
/// assert_eq!(srgb8_from_linear(0.0), 0);
/// assert_eq!(srgb8_from_linear(0.216), 128);
/// assert_eq!(srgb8_from_linear(7.0), 255);
/// ```
#[inline]
pub fn srgb8_from_linear(linear: f64) -> u8 {
    (srgb_encode(linear.clamp(0.0, 1.0)) * 255.0).round() as u8
}

/// The linear value of an 8-bit sRGB display value.
#[inline]
pub fn linear_from_srgb8(encoded: u8) -> f64 {
    srgb_decode(f64::from(encoded) / 255.0)
}
