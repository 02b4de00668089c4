//! Bidirectional scattering distribution functions (BSDFs): how a surface scatters light at a
//! point, once its material has been looked up there ([`crate::materials`]).
//!
//! The renderer traces curved rays, but scattering happens in the tangent space of the hit
//! point, which is Euclidean; so everything here is ordinary pbrt-style BSDF code in a **local
//! shading frame**:
//!
//! - +z is the shading normal; x and y span the tangent plane. All directions are unit vectors.
//! - `wo` points away from the surface towards the viewer (the previous path vertex); `wi`
//!   points away from the surface towards the light (the next path vertex).
//! - [`Bsdf::eval`] returns f(wo, wi) **only**: the cosine |cos θi| = |wi.z| is *not* included.
//!   Delta (perfectly specular) components are never returned by `eval` and have no density in
//!   [`Bsdf::pdf`]; they appear only through [`Bsdf::sample`], flagged [`BsdfSample::delta`].
//! - [`BsdfSample::weight`] is f·|cos θi| / pdf for a non-delta sample, and the corresponding
//!   ratio (reflectance over the probability of the discrete choice) for a delta sample: the
//!   factor by which a path's throughput is multiplied.
//! - Transport mode: paths are traced **from the camera** and carry radiance (pbrt's
//!   `TransportMode::Radiance`). Refraction therefore scales the weight by 1/η′², where η′ is
//!   the index on the far side over the index on `wo`'s side: entering a medium of relative
//!   index η the weight is T/η², leaving it T·η² (radiance / n² is what is conserved).
//! - Opaque materials ([`Bsdf::Diffuse`], [`Bsdf::Conductor`], [`Bsdf::Plastic`]) are
//!   one-sided: with `wo.z <= 0` they return zero, a zero pdf and no sample, and they only
//!   scatter into `wi.z > 0`. The caller faces the normal towards `wo` for two-sided surfaces.
//!
//! Sampling functions take their uniforms as arguments — `u` in [0, 1)² for a continuous
//! direction and `uc` in [0, 1) for a discrete choice (which lobe, reflect or refract) — so the
//! module has no random state. Every function is NaN-free for all unit inputs, including
//! grazing directions (z = 0) and directions below the surface, and for roughness at both
//! extremes; weights are never negative or non-finite.
//!
//! Microfacet lobes use the GGX (Trowbridge–Reitz) distribution with roughness α (the GGX
//! α itself, not its square root), clamped to [0, 1]; below [`DELTA_ROUGHNESS`] a lobe is a
//! perfect mirror.
//!
//! This module holds what the integrator sees, the [`Bsdf`] enum and [`BsdfSample`]; `Bsdf`'s
//! methods dispatch to a file per kind of surface, as in pbrt-v4 (see [`crate::materials`]).

use glam::DVec3;

use super::microfacet::{ggx_alpha, is_effectively_smooth};
use super::{conductor, dielectric, diffuse, plastic};

pub use orbifold_scene::color::Rgb;

pub use super::fresnel::{fresnel_conductor, fresnel_dielectric};
pub use super::microfacet::DELTA_ROUGHNESS;
pub use super::plastic::PLASTIC_ETA;

/// The marble texture ([`crate::textures::marble`]), which gives a diffuse BSDF its albedo.
#[doc(no_inline)]
pub use crate::textures::marble;

/// A material's scattering function, in the local shading frame (see the module docs).
///
/// ```
/// use glam::DVec3;
/// use orbifold_render::materials::bsdf::Bsdf;
///
/// let matte = Bsdf::Diffuse { albedo: [0.8, 0.5, 0.2] };
/// let (wo, wi) = (DVec3::Z, DVec3::new(0.6, 0.0, 0.8));
/// let f = matte.eval(wo, wi);
/// assert!((f[0] - 0.8 / std::f64::consts::PI).abs() < 1e-12);
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Bsdf {
    /// Lambertian reflection: f = albedo / π on the upper hemisphere.
    Diffuse {
        /// Hemispherical reflectance per channel (in [0, 1] to conserve energy; negative or
        /// NaN values are read as 0).
        albedo: Rgb,
    },
    /// A smooth dielectric interface (glass, water): Fresnel-weighted specular reflection and
    /// refraction, both delta. `wo.z > 0` is outside, `wo.z < 0` inside.
    Dielectric {
        /// Relative index of refraction, inside over outside (1.5 for glass in air). Values that
        /// are not positive and finite are read as 1.
        eta: f64,
        /// Colour filter applied to refracted light (1 = clear); reflection is not tinted.
        tint: Rgb,
    },
    /// A metal: the conductor Fresnel term of a complex index η + ik over a GGX microfacet
    /// distribution; a perfect mirror when `roughness` < [`DELTA_ROUGHNESS`].
    Conductor {
        /// Real part of the complex index of refraction, per channel.
        eta: Rgb,
        /// Imaginary part (absorption coefficient) of the complex index, per channel.
        k: Rgb,
        /// GGX α, clamped to [0, 1].
        roughness: f64,
    },
    /// Rough plastic: a GGX dielectric coat over a Lambertian base (Mitsuba's `roughplastic` in
    /// its `nonlinear` mode — the light's bounces between base and coat sum to ρ/(1 − ρ F̄ᵢₙₜ) —
    /// with smooth-interface transmittance factors where Mitsuba tabulates rough ones; see
    /// [`Bsdf::eval`]).
    Plastic {
        /// Reflectance of the Lambertian base, clamped to [0, 1].
        albedo: Rgb,
        /// GGX α of the coat, clamped to [0, 1]; a smooth (delta) coat below
        /// [`DELTA_ROUGHNESS`].
        roughness: f64,
        /// Index of refraction of the coat (1.5 by default); clamped to [1, 10].
        eta: f64,
    },
}

/// One direction drawn by [`Bsdf::sample`].
///
/// ```
/// use glam::DVec3;
/// use orbifold_render::materials::bsdf::Bsdf;
///
/// let s = Bsdf::Diffuse { albedo: [0.5; 3] }.sample(DVec3::Z, (0.3, 0.7), 0.5).unwrap();
/// assert!(s.wi.z > 0.0 && !s.delta);
/// assert!((s.pdf - s.wi.z / std::f64::consts::PI).abs() < 1e-12);
/// assert_eq!(s.weight, [0.5; 3]);
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BsdfSample {
    /// The sampled incident direction (unit, local frame, pointing away from the surface).
    pub wi: DVec3,
    /// The throughput factor: f·|cos θi| / pdf for a non-delta sample, or the delta lobe's
    /// reflectance (or transmittance) divided by the probability of having chosen it. Finite
    /// and non-negative.
    pub weight: Rgb,
    /// For a non-delta sample the solid-angle density of `wi` (equal to [`Bsdf::pdf`]); for a
    /// delta sample the probability of the discrete choice that produced it.
    pub pdf: f64,
    /// Whether `wi` came from a delta (perfectly specular) component.
    pub delta: bool,
}

impl Bsdf {
    /// A Lambertian material.
    ///
    /// ```
    /// use orbifold_render::materials::bsdf::Bsdf;
    ///
    /// assert_eq!(Bsdf::diffuse([0.5; 3]), Bsdf::Diffuse { albedo: [0.5; 3] });
    /// ```
    pub fn diffuse(albedo: Rgb) -> Bsdf {
        Bsdf::Diffuse { albedo }
    }

    /// A clear smooth dielectric of relative index `eta` (inside over outside).
    ///
    /// ```
    /// use orbifold_render::materials::bsdf::Bsdf;
    ///
    /// assert!(Bsdf::dielectric(1.5).is_delta());
    /// ```
    pub fn dielectric(eta: f64) -> Bsdf {
        Bsdf::Dielectric {
            eta,
            tint: [1.0; 3],
        }
    }

    /// A conductor with complex index `eta` + i`k` and GGX roughness α.
    ///
    /// ```
    /// use orbifold_render::materials::bsdf::Bsdf;
    ///
    /// let steelish = Bsdf::conductor([2.9, 2.9, 2.6], [3.0, 2.9, 2.8], 0.2);
    /// assert!(!steelish.is_delta());
    /// ```
    pub fn conductor(eta: Rgb, k: Rgb, roughness: f64) -> Bsdf {
        Bsdf::Conductor { eta, k, roughness }
    }

    /// A plastic with base colour `albedo`, coat roughness α and the coat index
    /// [`PLASTIC_ETA`] (1.5).
    ///
    /// ```
    /// use orbifold_render::materials::bsdf::Bsdf;
    ///
    /// let red = Bsdf::plastic([0.8, 0.1, 0.1], 0.1);
    /// assert!(red.has_diffuse() && !red.is_delta());
    /// ```
    pub fn plastic(albedo: Rgb, roughness: f64) -> Bsdf {
        Bsdf::Plastic {
            albedo,
            roughness,
            eta: PLASTIC_ETA,
        }
    }

    // The RGB complex indices below are the measured spectral data shipped with pbrt and
    // Mitsuba, integrated against the CIE matching functions and converted to linear sRGB, as
    // tabulated in Tungsten's `ComplexIorData.hpp` (B. Bitterli) and reused by many renderers.

    /// Gold (Au), with GGX roughness α. RGB η, k: pbrt/Mitsuba spectral data converted to
    /// linear sRGB (Tungsten's `ComplexIorData`).
    ///
    /// ```
    /// use orbifold_render::materials::bsdf::{Bsdf, fresnel_conductor};
    ///
    /// let Bsdf::Conductor { eta, k, .. } = Bsdf::gold(0.0) else { unreachable!() };
    /// let f0 = fresnel_conductor(1.0, eta, k);
    /// assert!(f0[0] > f0[1] && f0[1] > f0[2]); // yellow
    /// ```
    pub fn gold(roughness: f64) -> Bsdf {
        Bsdf::Conductor {
            eta: [0.143_118_955_7, 0.374_957_043_2, 1.442_478_557_1],
            k: [3.983_160_424_7, 2.385_720_747_8, 1.603_215_289_9],
            roughness,
        }
    }

    /// Silver (Ag), with GGX roughness α. RGB η, k: pbrt/Mitsuba spectral data converted to
    /// linear sRGB (Tungsten's `ComplexIorData`).
    ///
    /// ```
    /// use orbifold_render::materials::bsdf::{Bsdf, fresnel_conductor};
    ///
    /// let Bsdf::Conductor { eta, k, .. } = Bsdf::silver(0.0) else { unreachable!() };
    /// assert!(fresnel_conductor(1.0, eta, k).iter().all(|&r| r > 0.9));
    /// ```
    pub fn silver(roughness: f64) -> Bsdf {
        Bsdf::Conductor {
            eta: [0.155_264_648_9, 0.116_723_296_5, 0.138_380_695_9],
            k: [4.828_343_322_4, 3.122_245_927_8, 2.146_950_445_5],
            roughness,
        }
    }

    /// Copper (Cu), with GGX roughness α. RGB η, k: pbrt/Mitsuba spectral data converted to
    /// linear sRGB (Tungsten's `ComplexIorData`).
    ///
    /// ```
    /// use orbifold_render::materials::bsdf::{Bsdf, fresnel_conductor};
    ///
    /// let Bsdf::Conductor { eta, k, .. } = Bsdf::copper(0.0) else { unreachable!() };
    /// let f0 = fresnel_conductor(1.0, eta, k);
    /// assert!(f0[0] > f0[2]); // reddish
    /// ```
    pub fn copper(roughness: f64) -> Bsdf {
        Bsdf::Conductor {
            eta: [0.200_437_697_0, 0.924_033_430_4, 1.102_211_952_7],
            k: [3.912_948_503_3, 2.452_847_701_5, 2.142_187_955_2],
            roughness,
        }
    }

    /// Aluminium (Al), with GGX roughness α. RGB η, k: pbrt/Mitsuba spectral data converted to
    /// linear sRGB (Tungsten's `ComplexIorData`).
    ///
    /// ```
    /// use orbifold_render::materials::bsdf::{Bsdf, fresnel_conductor};
    ///
    /// let Bsdf::Conductor { eta, k, .. } = Bsdf::aluminium(0.0) else { unreachable!() };
    /// assert!(fresnel_conductor(1.0, eta, k).iter().all(|&r| r > 0.85));
    /// ```
    pub fn aluminium(roughness: f64) -> Bsdf {
        Bsdf::Conductor {
            eta: [1.657_459_959_5, 0.880_368_957_9, 0.521_228_734_6],
            k: [9.223_869_199_6, 6.269_523_247_7, 4.837_001_228_1],
            roughness,
        }
    }

    /// Whether every component is a delta distribution (then [`Bsdf::eval`] and [`Bsdf::pdf`]
    /// are identically zero and next-event estimation is pointless).
    ///
    /// ```
    /// use orbifold_render::materials::bsdf::Bsdf;
    ///
    /// assert!(Bsdf::dielectric(1.5).is_delta());
    /// assert!(Bsdf::silver(0.0).is_delta());
    /// assert!(!Bsdf::silver(0.3).is_delta());
    /// assert!(!Bsdf::plastic([0.5; 3], 0.0).is_delta()); // its base is diffuse
    /// ```
    pub fn is_delta(&self) -> bool {
        match *self {
            Bsdf::Diffuse { .. } | Bsdf::Plastic { .. } => false,
            Bsdf::Dielectric { .. } => true,
            Bsdf::Conductor { roughness, .. } => is_effectively_smooth(ggx_alpha(roughness)),
        }
    }

    /// Whether the material has a Lambertian component (a broad lobe that profits most from
    /// next-event estimation, and that denoisers treat as "diffuse").
    ///
    /// ```
    /// use orbifold_render::materials::bsdf::Bsdf;
    ///
    /// assert!(Bsdf::diffuse([0.5; 3]).has_diffuse());
    /// assert!(Bsdf::plastic([0.5; 3], 0.3).has_diffuse());
    /// assert!(!Bsdf::gold(0.3).has_diffuse());
    /// ```
    pub fn has_diffuse(&self) -> bool {
        matches!(self, Bsdf::Diffuse { .. } | Bsdf::Plastic { .. })
    }

    /// Whether the material transmits light (sampled directions may have `wi.z` of the
    /// opposite sign to `wo.z`).
    ///
    /// ```
    /// use orbifold_render::materials::bsdf::Bsdf;
    ///
    /// assert!(Bsdf::dielectric(1.33).is_transmissive());
    /// assert!(!Bsdf::diffuse([1.0; 3]).is_transmissive());
    /// ```
    pub fn is_transmissive(&self) -> bool {
        matches!(self, Bsdf::Dielectric { .. })
    }

    /// A representative reflectance colour (for albedo AOVs and denoisers): the diffuse albedo,
    /// the conductor's normal-incidence Fresnel reflectance, or the dielectric's tint.
    ///
    /// ```
    /// use orbifold_render::materials::bsdf::Bsdf;
    ///
    /// assert_eq!(Bsdf::diffuse([0.2, 0.4, 0.6]).albedo(), [0.2, 0.4, 0.6]);
    /// assert!(Bsdf::silver(0.1).albedo()[0] > 0.9);
    /// ```
    pub fn albedo(&self) -> Rgb {
        match *self {
            Bsdf::Diffuse { albedo } => nonneg(albedo),
            Bsdf::Plastic { albedo, .. } => saturate(albedo),
            Bsdf::Dielectric { tint, .. } => nonneg(tint),
            Bsdf::Conductor { eta, k, .. } => fresnel_conductor(1.0, eta, k),
        }
    }

    /// The BSDF value f(wo, wi), **without** the cosine factor |cos θi|, for unit `wo`, `wi` in
    /// the local frame. Delta components contribute nothing (a smooth [`Bsdf::Dielectric`] or
    /// a mirror [`Bsdf::Conductor`] evaluate to zero everywhere; a smooth-coated
    /// [`Bsdf::Plastic`] evaluates to its diffuse base only).
    ///
    /// - Diffuse: albedo / π.
    /// - Conductor: D(h) G₂(wo, wi) F(wo·h) / (4 cos θo cos θi), h = normalize(wo + wi).
    /// - Plastic: the same specular term with the dielectric Fresnel of the coat, plus the base
    ///   ρ/(1 − ρ·F̄ᵢₙₜ) · (1 − F(cos θi))(1 − F(cos θo)) / (π η²), where F̄ᵢₙₜ is the
    ///   hemispherical internal reflectance of the coat (the series of interreflections
    ///   between base and coat). The smooth-interface transmittances stand in for the rough
    ///   ones (Mitsuba tabulates those instead); the resulting f is still reciprocal, and the
    ///   albedo is ≤ 1 for a white base (≈ 1 for a smooth coat; a rough coat loses energy
    ///   towards grazing `wo`, where 1 − F(cos θo) underestimates what enters the coat).
    ///
    /// Opaque materials return zero unless both `wo.z > 0` and `wi.z > 0`.
    ///
    /// ```
    /// use glam::DVec3;
    /// use orbifold_render::materials::bsdf::Bsdf;
    ///
    /// let metal = Bsdf::gold(0.3);
    /// let (wo, wi) = (DVec3::new(0.6, 0.0, 0.8), DVec3::new(-0.6, 0.0, 0.8));
    /// assert!(metal.eval(wo, wi)[0] > 0.0);
    /// assert_eq!(metal.eval(wo, -wi), [0.0; 3]); // below the surface
    /// assert_eq!(Bsdf::dielectric(1.5).eval(wo, -wi), [0.0; 3]); // delta only
    /// ```
    pub fn eval(&self, wo: DVec3, wi: DVec3) -> Rgb {
        match *self {
            Bsdf::Dielectric { .. } => [0.0; 3],
            Bsdf::Diffuse { albedo } => diffuse::eval(albedo, wo, wi),
            Bsdf::Conductor { eta, k, roughness } => conductor::eval(eta, k, roughness, wo, wi),
            Bsdf::Plastic {
                albedo,
                roughness,
                eta,
            } => plastic::eval(albedo, roughness, eta, wo, wi),
        }
    }

    /// The solid-angle density with which [`Bsdf::sample`] produces `wi` from `wo` through
    /// its non-delta components (zero for delta components and for directions it never
    /// produces). It integrates over the sphere to the probability that `sample` returns a
    /// non-delta direction (≤ 1; < 1 where microfacet samples are rejected below the horizon).
    ///
    /// ```
    /// use glam::DVec3;
    /// use orbifold_render::materials::bsdf::Bsdf;
    ///
    /// let wi = DVec3::new(0.0, 0.6, 0.8);
    /// let p = Bsdf::diffuse([1.0; 3]).pdf(DVec3::Z, wi);
    /// assert!((p - 0.8 / std::f64::consts::PI).abs() < 1e-12);
    /// assert_eq!(Bsdf::dielectric(1.5).pdf(DVec3::Z, -DVec3::Z), 0.0);
    /// ```
    pub fn pdf(&self, wo: DVec3, wi: DVec3) -> f64 {
        match *self {
            Bsdf::Dielectric { .. } => 0.0,
            Bsdf::Diffuse { .. } => diffuse::pdf(wo, wi),
            Bsdf::Conductor { roughness, .. } => conductor::pdf(roughness, wo, wi),
            Bsdf::Plastic {
                albedo,
                roughness,
                eta,
            } => plastic::pdf(albedo, roughness, eta, wo, wi),
        }
    }

    /// Draws an incident direction for the outgoing direction `wo` from the uniforms `u` (for
    /// the direction) and `uc` (for the choice of lobe, or reflection versus refraction), all in
    /// [0, 1). Returns `None` when nothing is scattered: `wo` below an opaque surface, or a
    /// microfacet reflection that points below the horizon (that probability mass is simply
    /// lost, which [`Bsdf::pdf`] accounts for).
    ///
    /// - Diffuse: cosine-weighted hemisphere (Shirley–Chiu concentric mapping).
    /// - Conductor: visible GGX normals (Heitz 2018), reflected; a mirror when smooth.
    /// - Dielectric: reflection with probability F (the exact unpolarised Fresnel
    ///   reflectance), else refraction (Snell's law) with weight tint/η′² (radiance transport:
    ///   η′ is η entering, 1/η leaving); total internal reflection always reflects.
    /// - Plastic: the coat with probability F(cos θo) / (F(cos θo) + (1 − F(cos θo))·ρ̄)
    ///   (ρ̄ the mean base albedo), else the cosine-weighted base; the weight of a non-delta
    ///   sample uses the full mixture pdf.
    ///
    /// ```
    /// use glam::DVec3;
    /// use orbifold_render::materials::bsdf::{Bsdf, fresnel_dielectric};
    ///
    /// let glass = Bsdf::dielectric(1.5);
    /// let wo = DVec3::new(0.6, 0.0, 0.8);
    /// let f = fresnel_dielectric(0.8, 1.5);
    /// let reflected = glass.sample(wo, (0.5, 0.5), 0.5 * f).unwrap();
    /// assert!(reflected.delta && (reflected.wi - DVec3::new(-0.6, 0.0, 0.8)).length() < 1e-12);
    /// let refracted = glass.sample(wo, (0.5, 0.5), 0.99).unwrap();
    /// assert!(refracted.wi.z < 0.0);
    /// assert!((refracted.weight[0] - 1.0 / 2.25).abs() < 1e-12);
    /// ```
    pub fn sample(&self, wo: DVec3, u: (f64, f64), uc: f64) -> Option<BsdfSample> {
        let sample = match *self {
            Bsdf::Diffuse { albedo } => diffuse::sample(albedo, wo, u)?,
            Bsdf::Dielectric { eta, tint } => dielectric::sample(wo, eta, tint, uc)?,
            Bsdf::Conductor { eta, k, roughness } => conductor::sample(eta, k, roughness, wo, u)?,
            Bsdf::Plastic {
                albedo,
                roughness,
                eta,
            } => plastic::sample(albedo, roughness, eta, wo, u, uc)?,
        };
        let ok = sample.wi.is_finite()
            && sample.pdf.is_finite()
            && sample.pdf > 0.0
            && sample.weight.iter().all(|w| w.is_finite() && *w >= 0.0);
        ok.then_some(sample)
    }
}

impl BsdfSample {
    /// The non-delta sample of a direction `wi` that a lobe has drawn, given the whole BSDF's
    /// density `pdf` and value `f` at a direction. The weight f·cos/pdf uses the full mixture
    /// density, not the drawing lobe's, so that the lobes of a material together make one
    /// estimator.
    pub(super) fn from_direction(
        wi: DVec3,
        pdf: impl FnOnce(DVec3) -> f64,
        f: impl FnOnce(DVec3) -> Rgb,
    ) -> Option<BsdfSample> {
        let wi = wi.try_normalize()?;
        if wi.z <= 0.0 {
            return None;
        }
        let pdf = pdf(wi);
        if pdf <= 0.0 {
            return None;
        }
        let f = f(wi);
        Some(BsdfSample {
            wi,
            weight: sanitize(scale(f, wi.z / pdf)),
            pdf,
            delta: false,
        })
    }
}

/// A density as [`Bsdf::pdf`] returns it: non-finite and negative values read as 0.
pub(super) fn density(p: f64) -> f64 {
    if p.is_finite() && p > 0.0 { p } else { 0.0 }
}

// Directions in the local shading frame (+z the normal), shared by the lobes.

/// Both directions strictly above the surface: where an opaque lobe scatters.
pub(super) fn both_above(wo: DVec3, wi: DVec3) -> bool {
    wo.z > 0.0 && wi.z > 0.0
}

/// The specular reflection of `wo` about the normal +z.
pub(super) fn reflect_about_normal(wo: DVec3) -> DVec3 {
    DVec3::new(-wo.x, -wo.y, wo.z)
}

/// The specular reflection of `wo` about the unit microfacet normal `h`.
pub(super) fn reflect(wo: DVec3, h: DVec3) -> DVec3 {
    2.0 * wo.dot(h) * h - wo
}

// Colours, channel by channel.

/// Every channel times `s`.
pub(super) fn scale(c: Rgb, s: f64) -> Rgb {
    c.map(|x| x * s)
}

/// Negative and NaN channels read as 0.
pub(super) fn nonneg(c: Rgb) -> Rgb {
    c.map(|x| if x > 0.0 { x } else { 0.0 })
}

/// Channels clamped to [0, 1], NaN read as 0 (a shader's `saturate`).
pub(super) fn saturate(c: Rgb) -> Rgb {
    c.map(|x| if x > 0.0 { x.min(1.0) } else { 0.0 })
}

/// Non-finite and negative channels read as 0: what [`Bsdf::eval`] and the sample weights
/// return.
pub(super) fn sanitize(c: Rgb) -> Rgb {
    c.map(|x| if x.is_finite() && x > 0.0 { x } else { 0.0 })
}
