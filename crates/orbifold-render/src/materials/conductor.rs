//! The metal lobe ([`Bsdf::Conductor`](super::bsdf::Bsdf::Conductor)): the conductor Fresnel term of a complex index η + ik
//! over GGX microfacets, f = D(h) G₂(wo, wi) F(wo·h) / (4 cos θo cos θi), sampled through the
//! visible normals; a perfect mirror below [`DELTA_ROUGHNESS`](super::bsdf::DELTA_ROUGHNESS)
//! (pbrt-v4's `ConductorBxDF`). Opaque: it scatters only when both directions are above the
//! surface.

use glam::DVec3;

use super::bsdf::{
    BsdfSample, Rgb, both_above, density, reflect, reflect_about_normal, sanitize, scale,
};
use super::fresnel::fresnel_conductor;
use super::microfacet::{Ggx, ggx_alpha, is_effectively_smooth};

/// [`Bsdf::eval`](super::bsdf::Bsdf::eval) of a conductor.
pub(super) fn eval(eta: Rgb, k: Rgb, roughness: f64, wo: DVec3, wi: DVec3) -> Rgb {
    let a = ggx_alpha(roughness);
    if is_effectively_smooth(a) || !both_above(wo, wi) {
        return [0.0; 3];
    }
    let Some(h) = (wo + wi).try_normalize() else {
        return [0.0; 3];
    };
    let ggx = Ggx { alpha: a };
    let s = ggx.d(h) * ggx.g2(wo, wi) / (4.0 * wo.z * wi.z);
    sanitize(scale(fresnel_conductor(wo.dot(h), eta, k), s))
}

/// [`Bsdf::pdf`](super::bsdf::Bsdf::pdf) of a conductor.
pub(super) fn pdf(roughness: f64, wo: DVec3, wi: DVec3) -> f64 {
    let a = ggx_alpha(roughness);
    if is_effectively_smooth(a) || !both_above(wo, wi) {
        return 0.0;
    }
    density(Ggx { alpha: a }.pdf_reflect(wo, wi))
}

/// [`Bsdf::sample`](super::bsdf::Bsdf::sample) of a conductor, before its final check.
pub(super) fn sample(
    eta: Rgb,
    k: Rgb,
    roughness: f64,
    wo: DVec3,
    u: (f64, f64),
) -> Option<BsdfSample> {
    if wo.z <= 0.0 {
        return None;
    }
    let a = ggx_alpha(roughness);
    if is_effectively_smooth(a) {
        return Some(BsdfSample {
            wi: reflect_about_normal(wo),
            weight: fresnel_conductor(wo.z, eta, k),
            pdf: 1.0,
            delta: true,
        });
    }
    let h = Ggx { alpha: a }.sample_visible_normal(wo, u)?;
    BsdfSample::from_direction(
        reflect(wo, h),
        |wi| pdf(roughness, wo, wi),
        |wi| eval(eta, k, roughness, wo, wi),
    )
}
