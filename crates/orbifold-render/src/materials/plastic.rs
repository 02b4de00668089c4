//! The plastic ([`Bsdf::Plastic`](super::bsdf::Bsdf::Plastic)): two layers, a Lambertian base
//! under a dielectric coat that is smooth or GGX-rough — Mitsuba's `roughplastic` in its
//! `nonlinear` mode, with smooth-interface transmittances where Mitsuba tabulates rough ones, so
//! that f needs no tables and stays reciprocal. Opaque: it scatters only when both directions
//! are above the surface.
//!
//! The coat reflects like a microfacet mirror with the dielectric Fresnel term. What it
//! transmits reaches the base, whose reflectance ρ sends light back up, where the coat reflects
//! the fraction F̄ᵢₙₜ (its hemispherical internal reflectance) down again: the bounces between
//! the layers sum to ρ/(1 − ρ·F̄ᵢₙₜ). Crossing the coat in and out weighs the base by
//! (1 − F(cos θi))(1 − F(cos θo)) / η², the η² because radiance / n² is what is conserved as
//! the base's light leaves the coat. Sampling chooses the coat in proportion to its Fresnel reflectance against what the
//! base gives back, so that bright bases and grazing views each get the lobe that dominates.

use std::f64::consts::{FRAC_1_PI, PI};

use glam::DVec3;

use super::bsdf::{
    BsdfSample, Rgb, both_above, density, reflect, reflect_about_normal, sanitize, saturate,
};
use super::fresnel::{fresnel_dielectric, fresnel_diffuse_reflectance};
use super::microfacet::{Ggx, ggx_alpha, is_effectively_smooth};
use crate::sampler::cosine_hemisphere;

/// The index of refraction used by [`Bsdf::plastic`](super::bsdf::Bsdf::plastic) for the
/// dielectric coat.
///
/// ```
/// use orbifold_render::materials::bsdf::{Bsdf, PLASTIC_ETA};
///
/// let Bsdf::Plastic { eta, .. } = Bsdf::plastic([0.5; 3], 0.2) else { unreachable!() };
/// assert_eq!(eta, PLASTIC_ETA);
/// ```
pub const PLASTIC_ETA: f64 = 1.5;

/// The two layers of a plastic: its parameters sanitised, with the coat's derived constant.
#[derive(Clone, Copy, Debug)]
struct PlasticLayers {
    /// Reflectance of the Lambertian base, in [0, 1].
    albedo: Rgb,
    /// GGX α of the coat, in [0, 1].
    alpha: f64,
    /// Index of refraction of the coat, in [1, 10].
    eta: f64,
    /// Hemispherical (cosine-weighted) reflectance of the coat seen from inside.
    fdr_internal: f64,
}

impl PlasticLayers {
    fn new(albedo: Rgb, roughness: f64, eta: f64) -> PlasticLayers {
        let eta = if eta.is_nan() {
            1.0
        } else {
            eta.clamp(1.0, 10.0)
        };
        // Diffuse transmittance through the interface from outside is 1 − F̄ₑₓₜ; from inside
        // it is smaller by η² (reciprocity of radiance/η²): 1 − F̄ᵢₙₜ = (1 − F̄ₑₓₜ) / η².
        let fdr_internal = 1.0 - (1.0 - fresnel_diffuse_reflectance(eta)) / (eta * eta);
        PlasticLayers {
            albedo: saturate(albedo),
            alpha: ggx_alpha(roughness),
            eta,
            fdr_internal: fdr_internal.clamp(0.0, 1.0),
        }
    }

    /// The Lambertian base seen through the coat, f without the cosine.
    fn diffuse(&self, cos_o: f64, cos_i: f64) -> Rgb {
        let transmit = (1.0 - fresnel_dielectric(cos_o, self.eta))
            * (1.0 - fresnel_dielectric(cos_i, self.eta))
            / (PI * self.eta * self.eta);
        self.albedo
            .map(|a| a / (1.0 - a * self.fdr_internal).max(1e-12) * transmit)
    }

    /// The probability of sampling the coat rather than the base.
    fn specular_probability(&self, cos_o: f64) -> f64 {
        let f = fresnel_dielectric(cos_o, self.eta);
        let mean = (self.albedo[0] + self.albedo[1] + self.albedo[2]) / 3.0;
        let total = f + (1.0 - f) * mean;
        if total > 0.0 {
            (f / total).clamp(0.0, 1.0)
        } else {
            1.0
        }
    }
}

/// [`Bsdf::eval`](super::bsdf::Bsdf::eval) of a plastic: the base, plus the coat's reflection
/// unless the coat is smooth (a delta lobe).
pub(super) fn eval(albedo: Rgb, roughness: f64, eta: f64, wo: DVec3, wi: DVec3) -> Rgb {
    if !both_above(wo, wi) {
        return [0.0; 3];
    }
    let plastic = PlasticLayers::new(albedo, roughness, eta);
    let mut f = plastic.diffuse(wo.z, wi.z);
    if !is_effectively_smooth(plastic.alpha)
        && let Some(h) = (wo + wi).try_normalize()
    {
        let ggx = Ggx {
            alpha: plastic.alpha,
        };
        let spec = ggx.d(h) * ggx.g2(wo, wi) * fresnel_dielectric(wo.dot(h), plastic.eta)
            / (4.0 * wo.z * wi.z);
        f = f.map(|c| c + spec);
    }
    sanitize(f)
}

/// [`Bsdf::pdf`](super::bsdf::Bsdf::pdf) of a plastic: the mixture of the cosine-weighted base
/// and, unless the coat is smooth, its visible-normal reflection.
pub(super) fn pdf(albedo: Rgb, roughness: f64, eta: f64, wo: DVec3, wi: DVec3) -> f64 {
    if !both_above(wo, wi) {
        return 0.0;
    }
    let plastic = PlasticLayers::new(albedo, roughness, eta);
    let p_spec = plastic.specular_probability(wo.z);
    let diffuse = (1.0 - p_spec) * wi.z * FRAC_1_PI;
    let p = if is_effectively_smooth(plastic.alpha) {
        diffuse
    } else {
        let spec = Ggx {
            alpha: plastic.alpha,
        }
        .pdf_reflect(wo, wi);
        p_spec * spec + diffuse
    };
    density(p)
}

/// [`Bsdf::sample`](super::bsdf::Bsdf::sample) of a plastic, before its final check: the coat
/// (a mirror if smooth) with probability `p_spec`, else the base.
pub(super) fn sample(
    albedo: Rgb,
    roughness: f64,
    eta: f64,
    wo: DVec3,
    u: (f64, f64),
    uc: f64,
) -> Option<BsdfSample> {
    if wo.z <= 0.0 {
        return None;
    }
    let from_direction = |wi| {
        BsdfSample::from_direction(
            wi,
            |wi| pdf(albedo, roughness, eta, wo, wi),
            |wi| eval(albedo, roughness, eta, wo, wi),
        )
    };
    let plastic = PlasticLayers::new(albedo, roughness, eta);
    let p_spec = plastic.specular_probability(wo.z);
    if uc < p_spec {
        if is_effectively_smooth(plastic.alpha) {
            let reflectance = fresnel_dielectric(wo.z, plastic.eta) / p_spec;
            Some(BsdfSample {
                wi: reflect_about_normal(wo),
                weight: [reflectance; 3],
                pdf: p_spec,
                delta: true,
            })
        } else {
            let ggx = Ggx {
                alpha: plastic.alpha,
            };
            let h = ggx.sample_visible_normal(wo, u)?;
            from_direction(reflect(wo, h))
        }
    } else {
        from_direction(cosine_hemisphere(u))
    }
}
