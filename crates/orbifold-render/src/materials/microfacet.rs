//! The microfacet distribution that the rough metal
//! ([`Bsdf::Conductor`](super::bsdf::Bsdf::Conductor)) and the plastic's coat
//! ([`Bsdf::Plastic`](super::bsdf::Bsdf::Plastic)) share, in one place so that both lobes
//! evaluate, mask and sample the same surface (pbrt-v4's `TrowbridgeReitzDistribution`).
//!
//! Microfacet lobes use the GGX (Trowbridge–Reitz) distribution with roughness α (the GGX
//! α itself, not its square root), clamped to [0, 1]; below [`DELTA_ROUGHNESS`] a lobe is a
//! perfect mirror. Masking-shadowing is Smith's height-correlated form, and directions are
//! drawn from the distribution of visible normals (Heitz 2018, "Sampling the GGX Distribution
//! of Visible Normals", JCGT 7(4)).

use std::f64::consts::PI;

use glam::DVec3;

/// Microfacet roughness α below which a lobe is treated as a perfect (delta) mirror.
///
/// ```
/// use orbifold_render::materials::bsdf::{Bsdf, DELTA_ROUGHNESS};
///
/// assert!(Bsdf::gold(0.5 * DELTA_ROUGHNESS).is_delta());
/// assert!(!Bsdf::gold(2.0 * DELTA_ROUGHNESS).is_delta());
/// ```
pub const DELTA_ROUGHNESS: f64 = 1e-3;

/// The GGX α of a roughness parameter: clamped to [0, 1], NaN read as 0.
pub(super) fn ggx_alpha(roughness: f64) -> f64 {
    if roughness.is_nan() {
        0.0
    } else {
        roughness.clamp(0.0, 1.0)
    }
}

/// Whether a lobe of GGX α is treated as a delta mirror (pbrt-v4's `EffectivelySmooth`).
pub(super) fn is_effectively_smooth(alpha: f64) -> bool {
    alpha < DELTA_ROUGHNESS
}

/// The isotropic GGX (Trowbridge–Reitz) microfacet distribution with Smith masking.
#[derive(Clone, Copy, Debug)]
pub(super) struct Ggx {
    /// GGX α, in [0, 1].
    pub(super) alpha: f64,
}

impl Ggx {
    /// The distribution of normals D(h) for a unit `h` (zero below the surface).
    pub(super) fn d(&self, h: DVec3) -> f64 {
        if h.z <= 0.0 {
            return 0.0;
        }
        let a2 = self.alpha * self.alpha;
        // 1 + tan²θ·α² times cos²θ: sin²θ + α² cos²θ, positive for α > 0.
        let t = h.x * h.x + h.y * h.y + a2 * h.z * h.z;
        let d = a2 / (PI * t * t);
        if d.is_finite() { d } else { 0.0 }
    }

    /// Smith's Λ(w) = (√(1 + α² tan²θ) − 1) / 2, in a form without cancellation.
    fn lambda(&self, w: DVec3) -> f64 {
        let s2 = w.x * w.x + w.y * w.y;
        if s2 == 0.0 {
            return 0.0;
        }
        let t = self.alpha * self.alpha * s2 / (w.z * w.z);
        if !t.is_finite() {
            return f64::INFINITY;
        }
        t / (2.0 * ((1.0 + t).sqrt() + 1.0))
    }

    /// The masking function G₁(w) = 1 / (1 + Λ(w)).
    fn g1(&self, w: DVec3) -> f64 {
        1.0 / (1.0 + self.lambda(w))
    }

    /// Height-correlated masking-shadowing G₂(wo, wi) = 1 / (1 + Λ(wo) + Λ(wi)).
    pub(super) fn g2(&self, wo: DVec3, wi: DVec3) -> f64 {
        1.0 / (1.0 + self.lambda(wo) + self.lambda(wi))
    }

    /// The solid-angle density of `wi` = reflect(`wo`, h) with h drawn from the visible normals
    /// of `wo`: D_wo(h) / (4 wo·h) = G₁(wo) D(h) / (4 cos θo). Both must be above the surface.
    pub(super) fn pdf_reflect(&self, wo: DVec3, wi: DVec3) -> f64 {
        let Some(h) = (wo + wi).try_normalize() else {
            return 0.0;
        };
        if wo.dot(h) <= 0.0 {
            return 0.0;
        }
        self.g1(wo) * self.d(h) / (4.0 * wo.z)
    }

    /// A microfacet normal drawn from the distribution of normals visible from `wo` (Heitz
    /// 2018, listing 1, whose names the variables keep: `vh` the stretched view direction,
    /// `t1_axis` and `t2_axis` the frame around it, `nh` the normal on the hemisphere).
    /// `wo.z > 0`.
    pub(super) fn sample_visible_normal(&self, wo: DVec3, u: (f64, f64)) -> Option<DVec3> {
        let a = self.alpha;
        // Stretch to the hemisphere configuration.
        let vh = DVec3::new(a * wo.x, a * wo.y, wo.z).try_normalize()?;
        let lensq = vh.x * vh.x + vh.y * vh.y;
        let t1_axis = if lensq > 0.0 {
            DVec3::new(-vh.y, vh.x, 0.0) / lensq.sqrt()
        } else {
            DVec3::X
        };
        let t2_axis = vh.cross(t1_axis);
        // Uniform point on the projected disk, warped to the visible half.
        let r = u.0.clamp(0.0, 1.0).sqrt();
        let phi = 2.0 * PI * u.1;
        let t1 = r * phi.cos();
        let mut t2 = r * phi.sin();
        let s = 0.5 * (1.0 + vh.z);
        t2 = (1.0 - s) * (1.0 - t1 * t1).max(0.0).sqrt() + s * t2;
        let nh = t1 * t1_axis + t2 * t2_axis + (1.0 - t1 * t1 - t2 * t2).max(0.0).sqrt() * vh;
        // Unstretch.
        DVec3::new(a * nh.x, a * nh.y, nh.z.max(0.0)).try_normalize()
    }
}
