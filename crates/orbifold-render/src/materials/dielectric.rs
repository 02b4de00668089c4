//! The smooth dielectric ([`Bsdf::Dielectric`](super::bsdf::Bsdf::Dielectric)): glass, water.
//! Both of its lobes are delta, so it has no value or density to evaluate, only samples
//! (pbrt-v4's `DielectricBxDF` with zero roughness). A sample reflects with probability F (the
//! exact unpolarised Fresnel reflectance) and otherwise refracts by Snell's law; total internal
//! reflection always reflects. `wo.z > 0` is outside, `wo.z < 0` inside.
//!
//! A refracted sample's weight is tint/η′², where η′ is the index on the far side over the
//! index on `wo`'s side (η entering, 1/η leaving): paths carry radiance, and radiance / n² is
//! what crosses the interface unchanged.

use glam::DVec3;

use super::bsdf::{BsdfSample, Rgb, nonneg, reflect_about_normal, scale};
use super::fresnel::fresnel_dielectric;

/// [`Bsdf::sample`](super::bsdf::Bsdf::sample) of a smooth dielectric, before its final check:
/// reflection with probability F, else refraction.
pub(super) fn sample(wo: DVec3, eta: f64, tint: Rgb, uc: f64) -> Option<BsdfSample> {
    let eta = if eta.is_finite() && eta > 0.0 {
        eta
    } else {
        1.0
    };
    let cos_o = wo.z.clamp(-1.0, 1.0);
    let f = fresnel_dielectric(cos_o, eta);
    if uc < f || f >= 1.0 {
        return Some(BsdfSample {
            wi: reflect_about_normal(wo),
            weight: [1.0; 3],
            pdf: f,
            delta: true,
        });
    }
    // Refraction: η′ is the index ratio across the interface as seen from `wo`'s side, and
    // the normal is flipped to `wo`'s side.
    let (etap, n, cos_i) = if cos_o >= 0.0 {
        (eta, DVec3::Z, cos_o)
    } else {
        (1.0 / eta, -DVec3::Z, -cos_o)
    };
    let sin2_t = (1.0 - cos_i * cos_i).max(0.0) / (etap * etap);
    let cos_t = (1.0 - sin2_t).max(0.0).sqrt();
    let wi = (-wo / etap + (cos_i / etap - cos_t) * n).try_normalize()?;
    Some(BsdfSample {
        wi,
        weight: scale(nonneg(tint), 1.0 / (etap * etap)),
        pdf: 1.0 - f,
        delta: true,
    })
}
