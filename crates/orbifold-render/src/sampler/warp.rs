//! Warps from the unit square to points of the disk and to directions of the hemisphere, the
//! sphere and a cone, each with its density (pbrt's `SampleUniformDiskConcentric`,
//! `SampleCosineHemisphere`, …): they turn the uniforms `u` in [0, 1)² of a
//! [`Sampler`](super::Sampler) into points and directions (the Lambertian BSDFs draw theirs
//! with [`cosine_hemisphere`]), with maps that keep stratified uniforms evenly spread.
//! Directions are in a local frame with +z the axis (the normal for the hemisphere).

use std::f64::consts::{FRAC_PI_4, PI};

use glam::DVec3;

/// A point of the unit disk from `u` in [0, 1)², uniform in area (density 1/π), by Shirley and
/// Chiu's concentric map, which keeps strata compact and has low distortion.
///
/// ```
/// use orbifold_render::sampler::uniform_disk_concentric;
///
/// let (x, y) = uniform_disk_concentric((0.9, 0.3));
/// assert!(x * x + y * y <= 1.0);
/// assert_eq!(uniform_disk_concentric((0.5, 0.5)), (0.0, 0.0));
/// ```
pub fn uniform_disk_concentric(u: (f64, f64)) -> (f64, f64) {
    let a = 2.0 * u.0 - 1.0;
    let b = 2.0 * u.1 - 1.0;
    if a == 0.0 && b == 0.0 {
        return (0.0, 0.0);
    }
    let (r, theta) = if a.abs() > b.abs() {
        (a, FRAC_PI_4 * (b / a))
    } else {
        (b, 2.0 * FRAC_PI_4 - FRAC_PI_4 * (a / b))
    };
    (r * theta.cos(), r * theta.sin())
}

/// A unit direction of the upper hemisphere (z ≥ 0) from `u` in [0, 1)², with density
/// [`cosine_hemisphere_pdf`]`(z)` = z/π in solid angle (Malley's method on the concentric disk).
///
/// ```
/// use orbifold_render::sampler::cosine_hemisphere;
///
/// let w = cosine_hemisphere((0.25, 0.75));
/// assert!((w.length() - 1.0).abs() < 1e-12 && w.z >= 0.0);
/// ```
pub fn cosine_hemisphere(u: (f64, f64)) -> DVec3 {
    let (x, y) = uniform_disk_concentric(u);
    let z = (1.0 - x * x - y * y).max(0.0).sqrt();
    DVec3::new(x, y, z)
}

/// The solid-angle density of [`cosine_hemisphere`] at a direction with z component `cos_theta`:
/// `max(cos_theta, 0)/π`.
///
/// ```
/// use orbifold_render::sampler::cosine_hemisphere_pdf;
///
/// assert_eq!(cosine_hemisphere_pdf(-0.5), 0.0);
/// assert!((cosine_hemisphere_pdf(1.0) - std::f64::consts::FRAC_1_PI).abs() < 1e-15);
/// ```
pub fn cosine_hemisphere_pdf(cos_theta: f64) -> f64 {
    cos_theta.max(0.0) / PI
}

/// A uniform unit direction of the whole sphere from `u` in [0, 1)²; density 1/(4π)
/// ([`uniform_sphere_pdf`]).
///
/// ```
/// use orbifold_render::sampler::uniform_sphere;
///
/// let w = uniform_sphere((0.1, 0.6));
/// assert!((w.length() - 1.0).abs() < 1e-12);
/// ```
pub fn uniform_sphere(u: (f64, f64)) -> DVec3 {
    let z = 1.0 - 2.0 * u.0;
    let r = (1.0 - z * z).max(0.0).sqrt();
    let phi = 2.0 * PI * u.1;
    DVec3::new(r * phi.cos(), r * phi.sin(), z)
}

/// The solid-angle density of [`uniform_sphere`]: 1/(4π).
///
/// ```
/// use orbifold_render::sampler::uniform_sphere_pdf;
///
/// assert!((uniform_sphere_pdf() * 4.0 * std::f64::consts::PI - 1.0).abs() < 1e-15);
/// ```
pub fn uniform_sphere_pdf() -> f64 {
    1.0 / (4.0 * PI)
}

/// A unit direction uniform in the cone of directions around +z whose z component is at least
/// `cos_max` (in [−1, 1]); density [`uniform_cone_pdf`]`(cos_max)` = 1/(2π(1 − cos_max)).
///
/// ```
/// use orbifold_render::sampler::uniform_cone;
///
/// let w = uniform_cone((0.3, 0.8), 0.9);
/// assert!((w.length() - 1.0).abs() < 1e-12 && w.z >= 0.9 - 1e-12);
/// ```
pub fn uniform_cone(u: (f64, f64), cos_max: f64) -> DVec3 {
    let cos_theta = (1.0 - u.0) + u.0 * cos_max;
    let sin_theta = (1.0 - cos_theta * cos_theta).max(0.0).sqrt();
    let phi = 2.0 * PI * u.1;
    DVec3::new(sin_theta * phi.cos(), sin_theta * phi.sin(), cos_theta)
}

/// The solid-angle density of [`uniform_cone`]: 1/(2π(1 − cos_max)); infinite for a
/// degenerate cone (`cos_max` = 1).
///
/// ```
/// use orbifold_render::sampler::{uniform_cone_pdf, uniform_sphere_pdf};
///
/// assert!((uniform_cone_pdf(-1.0) - uniform_sphere_pdf()).abs() < 1e-15);
/// ```
pub fn uniform_cone_pdf(cos_max: f64) -> f64 {
    1.0 / (2.0 * PI * (1.0 - cos_max))
}
