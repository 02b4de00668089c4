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
//! perfect mirror. Masking-shadowing is Smith's height-correlated form, and directions are
//! drawn from the distribution of visible normals (Heitz 2018, "Sampling the GGX Distribution
//! of Visible Normals", JCGT 7(4)).

use std::f64::consts::{FRAC_1_PI, PI};

use glam::DVec3;

use crate::sampler::cosine_hemisphere;

pub use orbifold_scene::color::Rgb;

/// The marble texture ([`crate::textures::marble`]), which gives a diffuse BSDF its albedo.
#[doc(no_inline)]
pub use crate::textures::marble;

/// Microfacet roughness α below which a lobe is treated as a perfect (delta) mirror.
///
/// ```
/// use orbifold_render::materials::bsdf::{Bsdf, DELTA_ROUGHNESS};
///
/// assert!(Bsdf::gold(0.5 * DELTA_ROUGHNESS).is_delta());
/// assert!(!Bsdf::gold(2.0 * DELTA_ROUGHNESS).is_delta());
/// ```
pub const DELTA_ROUGHNESS: f64 = 1e-3;

/// The index of refraction used by [`Bsdf::plastic`] for the dielectric coat.
///
/// ```
/// use orbifold_render::materials::bsdf::{Bsdf, PLASTIC_ETA};
///
/// let Bsdf::Plastic { eta, .. } = Bsdf::plastic([0.5; 3], 0.2) else { unreachable!() };
/// assert_eq!(eta, PLASTIC_ETA);
/// ```
pub const PLASTIC_ETA: f64 = 1.5;

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
            Bsdf::Conductor { roughness, .. } => is_smooth(alpha(roughness)),
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
            Bsdf::Plastic { albedo, .. } => unit(albedo),
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
        let f = match *self {
            Bsdf::Dielectric { .. } => return [0.0; 3],
            Bsdf::Diffuse { albedo } => {
                if !upper(wo, wi) {
                    return [0.0; 3];
                }
                scale(nonneg(albedo), FRAC_1_PI)
            }
            Bsdf::Conductor { eta, k, roughness } => {
                let a = alpha(roughness);
                if is_smooth(a) || !upper(wo, wi) {
                    return [0.0; 3];
                }
                let Some(h) = (wo + wi).try_normalize() else {
                    return [0.0; 3];
                };
                let ggx = Ggx { alpha: a };
                let s = ggx.d(h) * ggx.g2(wo, wi) / (4.0 * wo.z * wi.z);
                scale(fresnel_conductor(wo.dot(h), eta, k), s)
            }
            Bsdf::Plastic {
                albedo,
                roughness,
                eta,
            } => {
                if !upper(wo, wi) {
                    return [0.0; 3];
                }
                let plastic = PlasticParts::new(albedo, roughness, eta);
                let mut f = plastic.diffuse(wo.z, wi.z);
                if !is_smooth(plastic.alpha)
                    && let Some(h) = (wo + wi).try_normalize()
                {
                    let ggx = Ggx {
                        alpha: plastic.alpha,
                    };
                    let spec =
                        ggx.d(h) * ggx.g2(wo, wi) * fresnel_dielectric(wo.dot(h), plastic.eta)
                            / (4.0 * wo.z * wi.z);
                    f = f.map(|c| c + spec);
                }
                f
            }
        };
        sanitize(f)
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
        let p = match *self {
            Bsdf::Dielectric { .. } => 0.0,
            Bsdf::Diffuse { .. } => {
                if !upper(wo, wi) {
                    return 0.0;
                }
                wi.z * FRAC_1_PI
            }
            Bsdf::Conductor { roughness, .. } => {
                let a = alpha(roughness);
                if is_smooth(a) || !upper(wo, wi) {
                    return 0.0;
                }
                Ggx { alpha: a }.pdf_reflect(wo, wi)
            }
            Bsdf::Plastic {
                albedo,
                roughness,
                eta,
            } => {
                if !upper(wo, wi) {
                    return 0.0;
                }
                let plastic = PlasticParts::new(albedo, roughness, eta);
                let p_spec = plastic.specular_probability(wo.z);
                let diffuse = (1.0 - p_spec) * wi.z * FRAC_1_PI;
                if is_smooth(plastic.alpha) {
                    diffuse
                } else {
                    let spec = Ggx {
                        alpha: plastic.alpha,
                    }
                    .pdf_reflect(wo, wi);
                    p_spec * spec + diffuse
                }
            }
        };
        if p.is_finite() && p > 0.0 { p } else { 0.0 }
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
            Bsdf::Diffuse { albedo } => {
                if wo.z <= 0.0 {
                    return None;
                }
                let wi = cosine_hemisphere(u);
                if wi.z <= 0.0 {
                    return None;
                }
                BsdfSample {
                    wi,
                    weight: nonneg(albedo),
                    pdf: wi.z * FRAC_1_PI,
                    delta: false,
                }
            }
            Bsdf::Dielectric { eta, tint } => sample_dielectric(wo, eta, tint, uc)?,
            Bsdf::Conductor { eta, k, roughness } => {
                if wo.z <= 0.0 {
                    return None;
                }
                let a = alpha(roughness);
                if is_smooth(a) {
                    BsdfSample {
                        wi: mirror(wo),
                        weight: fresnel_conductor(wo.z, eta, k),
                        pdf: 1.0,
                        delta: true,
                    }
                } else {
                    let h = Ggx { alpha: a }.sample_visible_normal(wo, u)?;
                    self.sample_from(wo, reflect(wo, h))?
                }
            }
            Bsdf::Plastic {
                albedo,
                roughness,
                eta,
            } => {
                if wo.z <= 0.0 {
                    return None;
                }
                let plastic = PlasticParts::new(albedo, roughness, eta);
                let p_spec = plastic.specular_probability(wo.z);
                if uc < p_spec {
                    if is_smooth(plastic.alpha) {
                        let reflectance = fresnel_dielectric(wo.z, plastic.eta) / p_spec;
                        BsdfSample {
                            wi: mirror(wo),
                            weight: [reflectance; 3],
                            pdf: p_spec,
                            delta: true,
                        }
                    } else {
                        let ggx = Ggx {
                            alpha: plastic.alpha,
                        };
                        let h = ggx.sample_visible_normal(wo, u)?;
                        self.sample_from(wo, reflect(wo, h))?
                    }
                } else {
                    self.sample_from(wo, cosine_hemisphere(u))?
                }
            }
        };
        let ok = sample.wi.is_finite()
            && sample.pdf.is_finite()
            && sample.pdf > 0.0
            && sample.weight.iter().all(|w| w.is_finite() && *w >= 0.0);
        ok.then_some(sample)
    }

    /// A non-delta sample for a direction `wi` already drawn: weight = f·cos/pdf with the
    /// full mixture pdf.
    fn sample_from(&self, wo: DVec3, wi: DVec3) -> Option<BsdfSample> {
        let wi = wi.try_normalize()?;
        if wi.z <= 0.0 {
            return None;
        }
        let pdf = self.pdf(wo, wi);
        if pdf <= 0.0 {
            return None;
        }
        let f = self.eval(wo, wi);
        Some(BsdfSample {
            wi,
            weight: sanitize(scale(f, wi.z / pdf)),
            pdf,
            delta: false,
        })
    }
}

/// Samples the smooth dielectric (see [`Bsdf::sample`]).
fn sample_dielectric(wo: DVec3, eta: f64, tint: Rgb, uc: f64) -> Option<BsdfSample> {
    let eta = if eta.is_finite() && eta > 0.0 {
        eta
    } else {
        1.0
    };
    let cos_o = wo.z.clamp(-1.0, 1.0);
    let f = fresnel_dielectric(cos_o, eta);
    if uc < f || f >= 1.0 {
        return Some(BsdfSample {
            wi: mirror(wo),
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

/// One channel of [`fresnel_conductor`], for `cos_i` in [0, 1].
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

/// The isotropic GGX (Trowbridge–Reitz) microfacet distribution with Smith masking.
#[derive(Clone, Copy, Debug)]
struct Ggx {
    alpha: f64,
}

impl Ggx {
    /// The distribution of normals D(h) for a unit `h` (zero below the surface).
    fn d(&self, h: DVec3) -> f64 {
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
    fn g2(&self, wo: DVec3, wi: DVec3) -> f64 {
        1.0 / (1.0 + self.lambda(wo) + self.lambda(wi))
    }

    /// The solid-angle density of `wi` = reflect(`wo`, h) with h drawn from the visible normals
    /// of `wo`: D_wo(h) / (4 wo·h) = G₁(wo) D(h) / (4 cos θo). Both must be above the surface.
    fn pdf_reflect(&self, wo: DVec3, wi: DVec3) -> f64 {
        let Some(h) = (wo + wi).try_normalize() else {
            return 0.0;
        };
        if wo.dot(h) <= 0.0 {
            return 0.0;
        }
        self.g1(wo) * self.d(h) / (4.0 * wo.z)
    }

    /// A microfacet normal drawn from the distribution of normals visible from `wo` (Heitz
    /// 2018, listing 1). `wo.z > 0`.
    fn sample_visible_normal(&self, wo: DVec3, u: (f64, f64)) -> Option<DVec3> {
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

/// The parameters of [`Bsdf::Plastic`], sanitised, with the derived coat constants.
#[derive(Clone, Copy, Debug)]
struct PlasticParts {
    albedo: Rgb,
    alpha: f64,
    eta: f64,
    /// Hemispherical (cosine-weighted) reflectance of the coat seen from inside.
    fdr_internal: f64,
}

impl PlasticParts {
    fn new(albedo: Rgb, roughness: f64, eta: f64) -> PlasticParts {
        let eta = if eta.is_nan() {
            1.0
        } else {
            eta.clamp(1.0, 10.0)
        };
        // Diffuse transmittance through the interface from outside is 1 − F̄ₑₓₜ; from inside
        // it is smaller by η² (reciprocity of radiance/η²): 1 − F̄ᵢₙₜ = (1 − F̄ₑₓₜ) / η².
        let fdr_internal = 1.0 - (1.0 - fresnel_diffuse_reflectance(eta)) / (eta * eta);
        PlasticParts {
            albedo: unit(albedo),
            alpha: alpha(roughness),
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

/// The hemispherical (cosine-weighted) Fresnel reflectance of a dielectric of index `eta`
/// ≥ 1 lit from outside: the fit of d'Eon & Irving (2011), as in Mitsuba (relative error
/// below 0.2 % for η in [1, 10]).
fn fresnel_diffuse_reflectance(eta: f64) -> f64 {
    let x = 1.0 / eta;
    let r = 0.919_317
        + x * (-3.4793 + x * (6.753_35 + x * (-7.809_89 + x * (4.985_54 - x * 1.368_81))));
    r.clamp(0.0, 1.0)
}

/// The GGX α of a roughness parameter: clamped to [0, 1], NaN read as 0.
fn alpha(roughness: f64) -> f64 {
    if roughness.is_nan() {
        0.0
    } else {
        roughness.clamp(0.0, 1.0)
    }
}

/// Whether a lobe of GGX α is treated as a delta mirror.
fn is_smooth(alpha: f64) -> bool {
    alpha < DELTA_ROUGHNESS
}

/// Both directions strictly above the surface.
fn upper(wo: DVec3, wi: DVec3) -> bool {
    wo.z > 0.0 && wi.z > 0.0
}

/// The mirror direction of `wo` about the normal +z.
fn mirror(wo: DVec3) -> DVec3 {
    DVec3::new(-wo.x, -wo.y, wo.z)
}

/// The mirror direction of `wo` about the unit normal `h`.
fn reflect(wo: DVec3, h: DVec3) -> DVec3 {
    2.0 * wo.dot(h) * h - wo
}

fn scale(c: Rgb, s: f64) -> Rgb {
    c.map(|x| x * s)
}

/// Negative and NaN channels read as 0.
fn nonneg(c: Rgb) -> Rgb {
    c.map(|x| if x > 0.0 { x } else { 0.0 })
}

/// Channels clamped to [0, 1], NaN read as 0.
fn unit(c: Rgb) -> Rgb {
    c.map(|x| if x > 0.0 { x.min(1.0) } else { 0.0 })
}

/// Non-finite or negative channels read as 0.
fn sanitize(c: Rgb) -> Rgb {
    c.map(|x| if x.is_finite() && x > 0.0 { x } else { 0.0 })
}
