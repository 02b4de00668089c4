//! The Lambertian lobe ([`Bsdf::Diffuse`](super::bsdf::Bsdf::Diffuse)): f = albedo / π on the
//! upper hemisphere, sampled cosine-weighted so that a sample's weight is the albedo itself
//! (pbrt-v4's `DiffuseBxDF`). Opaque: it scatters only when both directions are above the
//! surface.

use std::f64::consts::FRAC_1_PI;

use glam::DVec3;

use super::bsdf::{BsdfSample, Rgb, both_above, density, nonneg, sanitize, scale};
use crate::sampler::cosine_hemisphere;

/// [`Bsdf::eval`](super::bsdf::Bsdf::eval) of a Lambertian surface.
pub(super) fn eval(albedo: Rgb, wo: DVec3, wi: DVec3) -> Rgb {
    if !both_above(wo, wi) {
        return [0.0; 3];
    }
    sanitize(scale(nonneg(albedo), FRAC_1_PI))
}

/// [`Bsdf::pdf`](super::bsdf::Bsdf::pdf) of a Lambertian surface.
pub(super) fn pdf(wo: DVec3, wi: DVec3) -> f64 {
    if !both_above(wo, wi) {
        return 0.0;
    }
    density(wi.z * FRAC_1_PI)
}

/// [`Bsdf::sample`](super::bsdf::Bsdf::sample) of a Lambertian surface, before its final
/// check: a cosine-weighted direction (Shirley–Chiu concentric mapping).
pub(super) fn sample(albedo: Rgb, wo: DVec3, u: (f64, f64)) -> Option<BsdfSample> {
    if wo.z <= 0.0 {
        return None;
    }
    let wi = cosine_hemisphere(u);
    if wi.z <= 0.0 {
        return None;
    }
    Some(BsdfSample {
        wi,
        weight: nonneg(albedo),
        pdf: wi.z * FRAC_1_PI,
        delta: false,
    })
}
