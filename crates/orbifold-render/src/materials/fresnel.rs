//! The Fresnel equations: how much light a smooth interface between two media reflects, for
//! unpolarised light. The dielectric's reflectance chooses between reflection and refraction in
//! glass ([`Bsdf::Dielectric`](super::bsdf::Bsdf::Dielectric)) and weighs the plastic's coat;
//! the conductor's, with a complex index, colours a metal
//! ([`Bsdf::Conductor`](super::bsdf::Bsdf::Conductor)); and the dielectric's hemispherical
//! average gives the light that the plastic's base and coat reflect back and forth
//! ([`Bsdf::Plastic`](super::bsdf::Bsdf::Plastic)).

use super::bsdf::Rgb;

/// The Fresnel reflectance of a smooth dielectric interface for unpolarised light.
///
/// `cos_i` is the cosine of the angle between the incident direction and the normal, and
/// `eta` the relative index (inside over outside). A negative `cos_i` means the light arrives
/// from inside, and then the index ratio is inverted. Returns 1 under total internal
/// reflection and at grazing incidence. `eta` not positive and finite is read as 1.
///
/// ```
/// use orbifold_render::materials::bsdf::fresnel_dielectric;
///
/// let r0 = fresnel_dielectric(1.0, 1.5);
/// assert!((r0 - 0.04).abs() < 1e-12); // ((η − 1)/(η + 1))²
/// assert_eq!(fresnel_dielectric(0.0, 1.5), 1.0);
/// assert_eq!(fresnel_dielectric(-0.3, 1.5), 1.0); // total internal reflection
/// ```
pub fn fresnel_dielectric(cos_i: f64, eta: f64) -> f64 {
    let mut eta = if eta.is_finite() && eta > 0.0 {
        eta
    } else {
        1.0
    };
    let mut cos_i = if cos_i.is_nan() {
        0.0
    } else {
        cos_i.clamp(-1.0, 1.0)
    };
    if cos_i < 0.0 {
        eta = 1.0 / eta;
        cos_i = -cos_i;
    }
    let sin2_i = (1.0 - cos_i * cos_i).max(0.0);
    let sin2_t = sin2_i / (eta * eta);
    if sin2_t >= 1.0 {
        return 1.0;
    }
    let cos_t = (1.0 - sin2_t).max(0.0).sqrt();
    let r_parallel = (eta * cos_i - cos_t) / (eta * cos_i + cos_t);
    let r_perpendicular = (cos_i - eta * cos_t) / (cos_i + eta * cos_t);
    let r = 0.5 * (r_parallel * r_parallel + r_perpendicular * r_perpendicular);
    if r.is_finite() {
        r.clamp(0.0, 1.0)
    } else {
        1.0
    }
}

/// The Fresnel reflectance of a conductor with complex index η + ik (relative to the outside
/// medium) for unpolarised light, per channel: the exact formula (pbrt-v3's `FrConductor`).
///
/// `cos_i` is the cosine of the incidence angle; its absolute value is used (a conductor has
/// no inside). Each channel lies in [0, 1] and tends to 1 at grazing incidence. With k = 0 it
/// coincides with [`fresnel_dielectric`].
///
/// ```
/// use orbifold_render::materials::bsdf::fresnel_conductor;
///
/// let (eta, k) = ([0.2, 0.9, 1.1], [3.9, 2.5, 2.1]);
/// let r = fresnel_conductor(1.0, eta, k);
/// // Normal incidence: ((η − 1)² + k²) / ((η + 1)² + k²).
/// let expected = (0.8f64.powi(2) + 3.9f64.powi(2)) / (1.2f64.powi(2) + 3.9f64.powi(2));
/// assert!((r[0] - expected).abs() < 1e-12);
/// assert!(fresnel_conductor(0.0, eta, k).iter().all(|&x| (x - 1.0).abs() < 1e-12));
/// ```
pub fn fresnel_conductor(cos_i: f64, eta: Rgb, k: Rgb) -> Rgb {
    let cos_i = if cos_i.is_nan() {
        0.0
    } else {
        cos_i.abs().min(1.0)
    };
    std::array::from_fn(|c| fresnel_conductor_channel(cos_i, eta[c], k[c]))
}

/// One channel of [`fresnel_conductor`], for `cos_i` in [0, 1]. The names of the intermediate
/// terms (`a2_plus_b2`, `t0` to `t4`, `rs`, `rp`) are those of pbrt-v3's `FrConductor`.
fn fresnel_conductor_channel(cos_i: f64, eta: f64, k: f64) -> f64 {
    let eta = if eta.is_finite() { eta.abs() } else { 1.0 };
    let k = if k.is_finite() { k.abs() } else { 0.0 };
    let cos2 = cos_i * cos_i;
    let sin2 = (1.0 - cos2).max(0.0);
    let eta2 = eta * eta;
    let k2 = k * k;
    let t0 = eta2 - k2 - sin2;
    let a2_plus_b2 = (t0 * t0 + 4.0 * eta2 * k2).sqrt();
    let t1 = a2_plus_b2 + cos2;
    let a = (0.5 * (a2_plus_b2 + t0)).max(0.0).sqrt();
    let t2 = 2.0 * cos_i * a;
    let rs = if t1 + t2 > 0.0 {
        (t1 - t2) / (t1 + t2)
    } else {
        1.0
    };
    let t3 = cos2 * a2_plus_b2 + sin2 * sin2;
    let t4 = t2 * sin2;
    let rp = if t3 + t4 > 0.0 {
        rs * (t3 - t4) / (t3 + t4)
    } else {
        rs
    };
    let r = 0.5 * (rp + rs);
    if r.is_finite() {
        r.clamp(0.0, 1.0)
    } else {
        1.0
    }
}

/// The hemispherical (cosine-weighted) Fresnel reflectance of a dielectric of index `eta`
/// ≥ 1 lit from outside: the fit of d'Eon & Irving (2011), as in Mitsuba (relative error
/// below 0.2 % for η in [1, 10]).
pub(super) fn fresnel_diffuse_reflectance(eta: f64) -> f64 {
    let x = 1.0 / eta;
    let r = 0.919_317
        + x * (-3.4793 + x * (6.753_35 + x * (-7.809_89 + x * (4.985_54 - x * 1.368_81))));
    r.clamp(0.0, 1.0)
}
