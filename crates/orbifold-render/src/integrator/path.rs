//! The path loop: a camera path's radiance estimate, traced from the camera
//! ([`Integrator::sample_pixel_cached`]), and what it saw first, for the denoiser ([`FirstHit`]).
//!
//! A camera path runs along exact geodesics. Mirrors are followed deterministically, their
//! reflectance multiplying the path's throughput ([`Integrator::follow_mirrors`]); at every other
//! surface the path gathers direct light ([`Integrator::direct`]) and then scatters by its BSDF,
//! for at most [`Settings::max_depth`](super::Settings::max_depth) scattering vertices. Russian
//! roulette ends dim paths: on the throughput after the third bounce, and within a mirror segment
//! once the throughput falls below [`ROULETTE_LEVEL`] ([`FOOTPRINT_ROULETTE_LEVEL`] for a camera
//! ray that carries its pixel's footprint). That footprint goes through the mirrors to the first
//! surface, where it filters textures, and a ray that leaves a diffuse bounce carries one of its
//! own ([`super::ray_footprint`]). With a radiance cache, far mirror images and surfaces reached
//! by a diffuse bounce read their reflected light from it instead of tracing it
//! ([`super::radiance_cache_use`]).

use glam::DVec3;
use orbifold_scene::color::luminance;
use orbifold_trace::footprint::Footprint;
use orbifold_trace::geodesic::Ray;

use super::light_sampler::Normal;
use super::mirror_segment::{HitKind, SegmentEnd, rays_so_far};
use super::radiance_cache_use::PendingDeposit;
use super::ray_footprint::{BOUNCE_FOOTPRINT, RayFootprint, SurfaceFootprint};
use super::surface::{GeometricSides, bent_shading_normal};
use super::{Integrator, RAY_EPSILON, add, mul, scale};
use crate::lights::{Rgb, TangentFrame, travel_direction};
use crate::materials::bsdf::Bsdf;
use crate::radiance_cache::{self, Deposit, Reader};
use crate::sampler::{Frame, Sampler, power_heuristic};

/// Below this luminance of a path's throughput, mirror chains play Russian roulette.
const ROULETTE_LEVEL: f64 = 0.1;

/// The level for a camera ray that carries its pixel's footprint, much lower: every stretch of
/// it gathers the light images near it ([`orbifold_trace::footprint`]), so that a mirror segment
/// cut short early loses a long tail of them, and the paths that survive carry that tail
/// weighted up: at [`ROULETTE_LEVEL`], that roulette would be most of the noise of the band of
/// far light images at the horizon of a hyperbolic room (docs/benchmarks.md).
const FOOTPRINT_ROULETTE_LEVEL: f64 = 0.01;

/// What a camera path saw first — the first surface that is not a mirror — as guides for the
/// denoiser ([`crate::denoise`]), and the two parts of its radiance that the denoiser treats
/// apart: the light seen directly, and the first surface's light sample.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct FirstHit {
    /// The surface's reflectance colour ([`Bsdf::albedo`]); 1 for a light or nothing.
    pub albedo: Rgb,
    /// Its unit normal facing the camera, in the hit point's tangent frame; 0 for nothing.
    pub normal: DVec3,
    /// Arc length from the camera, through the mirrors; 0 for nothing.
    pub depth: f64,
    /// The light the camera saw directly, through mirrors only: the images of lights that the
    /// path hit, or that its pixel's footprint glimpsed, before its first surface. It is part
    /// of the path's radiance; the denoiser leaves it as it is and smooths only the rest, so
    /// that a bright light image neither bleeds into the surfaces around it nor lends them its
    /// noise.
    pub emitted: Rgb,
    /// The light that the first surface reflected straight from a light sample there (next-event
    /// estimation): part of the path's radiance, smooth and well sampled where a light image is
    /// near, which the denoiser filters apart from the rest (the light of longer paths, far
    /// noisier) with its own variance, as SVGF filters direct and indirect light apart.
    pub direct: Rgb,
}

/// One camera path's estimate and what it saw first.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct PathSample {
    /// The radiance estimate.
    pub radiance: Rgb,
    /// The first surface that is not a mirror.
    pub first: FirstHit,
    /// The path's estimate of the light its first diffuse surface reflects, for a
    /// [`RadianceCache`](crate::radiance_cache::RadianceCache) (only from [`Integrator::sample_pixel_cached`], when that surface was
    /// traced in full).
    pub deposit: Option<Deposit>,
    /// The rays the path traced: geodesic stretches between mirrors, each a search for the
    /// nearest hit or a shadow test (what "rays per second" counts).
    pub rays: u32,
}

impl Integrator {
    /// The radiance arriving along a camera ray (one path sample).
    pub fn radiance(&self, ray: &Ray, sampler: &mut Sampler) -> Rgb {
        self.sample(ray, sampler).radiance
    }

    /// The radiance arriving along a camera ray (one path sample) and the first surface that is
    /// not a mirror.
    pub fn sample(&self, ray: &Ray, sampler: &mut Sampler) -> PathSample {
        self.sample_pixel(ray, None, sampler)
    }

    /// [`Integrator::sample`] for a camera ray that carries its pixel's footprint: sphere lights
    /// whose mirror images are smaller than the pixel are counted by the share of the pixel
    /// they cover, not by the ray's hit or miss ([`orbifold_trace::footprint`]; what renders use).
    pub fn sample_pixel(
        &self,
        ray: &Ray,
        footprint: Option<Footprint>,
        sampler: &mut Sampler,
    ) -> PathSample {
        self.sample_pixel_cached(ray, footprint, None, sampler)
    }

    /// [`Integrator::sample_pixel`] with a radiance cache ([`crate::radiance_cache`]): where the
    /// path's first diffuse surface is a far mirror image (its pixel's footprint is wider than
    /// a cell of the cache) and the cache holds enough estimates there, the reflected light is
    /// read from the cache instead of traced; so is the light reflected by a diffuse surface
    /// that the path reaches from a diffuse bounce, over a width of
    /// [`radiance_cache::DIFFUSE_SPREAD`] times the distance, where the path may still take
    /// [`radiance_cache::DEPTH_LEFT_FOR_READS`] scatterings. A path that traces its first diffuse
    /// surface in full returns its estimate there as a [`Deposit`] for the cache: those that
    /// could not read it, and a [`radiance_cache::PROBE`] share of those that could, which take
    /// the cache's value all the same.
    pub fn sample_pixel_cached(
        &self,
        ray: &Ray,
        footprint: Option<Footprint>,
        cache: Option<Reader<'_>>,
        sampler: &mut Sampler,
    ) -> PathSample {
        let rays_before = rays_so_far();
        let space = self.space();
        let footprint =
            footprint.filter(|_| self.settings.pixel_footprint && !self.settings.straight_rays);
        let mut first: Option<FirstHit> = None;
        let mut radiance = [0.0; 3];
        let mut beta = [1.0; 3];
        let mut ray = *ray;
        // The previous scattering: specular (or the camera), and its BSDF pdf.
        let mut specular = true;
        let mut pdf_bsdf = 0.0;
        let mut previous = (DVec3::ZERO, 0.0, Normal::default());
        let mut depth = 0;
        // The camera path's first diffuse surface, while its estimate for the cache is traced.
        let mut pending: Option<PendingDeposit> = None;
        let mut previous_diffuse = false;
        // Whether the ray leaves a diffuse bounce, whose small far light images that light
        // sampling cannot draw are counted by their coverage of [`BOUNCE_FOOTPRINT`].
        let mut bounce_glimpses = false;
        // The light seen before the first surface (`FirstHit::emitted`), and the first surface's
        // light sample (`FirstHit::direct`).
        let mut seen = [0.0; 3];
        let mut direct_first = [0.0; 3];
        loop {
            // The pixel's footprint is carried from the camera through mirrors only.
            let carried = footprint.as_ref().filter(|_| first.is_none());
            let level = if carried.is_some() {
                FOOTPRINT_ROULETTE_LEVEL
            } else {
                ROULETTE_LEVEL
            };
            let roulette = Some((&mut *sampler, luminance(beta), level));
            let ray_footprint = match carried {
                Some(footprint) => Some(RayFootprint::Camera(footprint)),
                None => bounce_glimpses.then_some(RayFootprint::Bounce(&BOUNCE_FOOTPRINT)),
            };
            let segment =
                self.follow_mirrors(&ray, f64::INFINITY, None, roulette, ray_footprint, false);
            let before_surfaces = first.is_none();
            add(&mut radiance, mul(beta, segment.glimpsed));
            if before_surfaces {
                add(&mut seen, mul(beta, segment.glimpsed));
            }
            beta = mul(beta, segment.throughput);
            let SegmentEnd::Hit(hit) = segment.end else {
                break;
            };
            let (x, h) = (hit.point, hit.height);
            let frame = TangentFrame::at(space, x);
            let travel = travel_direction(space, &frame, &segment.ray, segment.rest);
            if first.is_none() {
                first = Some(FirstHit {
                    albedo: [1.0; 3],
                    normal: -travel,
                    depth: segment.length,
                    ..FirstHit::default()
                });
            }
            if let HitKind::Light {
                light: l,
                triangle,
                barycentric: w,
            } = hit.kind
            {
                if segment.glimpsed_end == Some(l) {
                    break;
                }
                let Some(n) = self.light_normal(l, triangle, w, &frame) else {
                    break;
                };
                let cos_out = -travel.dot(n);
                let emitted = self.lights[l].emission(-travel, cos_out);
                let weight = if specular || !self.settings.nee {
                    1.0
                } else {
                    let pdf_light = self.light_pdf(previous, l, triangle, w, &segment, cos_out);
                    power_heuristic(1.0, pdf_bsdf, 1.0, pdf_light)
                };
                add(&mut radiance, scale(mul(beta, emitted), weight));
                if before_surfaces {
                    add(&mut seen, scale(mul(beta, emitted), weight));
                }
                break;
            }
            // An odd number of mirrors has swapped left and right (as in the segment's own copy).
            let surface_footprint = carried.map(|f| {
                let f = if segment.chain.determinant() < 0.0 {
                    f.reflected()
                } else {
                    *f
                };
                SurfaceFootprint::new(space, &f, segment.length, segment.ray.cos_elevation, travel)
            });
            let Some((geometric, normal, bsdf)) =
                self.surface(&hit, &frame, surface_footprint.as_ref())
            else {
                break;
            };
            if !bsdf.is_transmissive() {
                add(&mut radiance, mul(beta, self.settings.glow));
            }
            // Opaque surfaces are two-sided: face the normals towards where the path came from.
            // A dielectric keeps its outward normal: which side the path is on matters.
            let wo = -travel;
            let (geometric, normal) = if geometric.dot(wo) < 0.0 && !bsdf.is_transmissive() {
                (-geometric, -normal)
            } else {
                (geometric, normal)
            };
            let normal = bent_shading_normal(normal, geometric, wo);
            let shading = Frame::from_normal(normal);
            if depth == 0 {
                first = Some(FirstHit {
                    albedo: bsdf.albedo(),
                    normal,
                    depth: segment.length,
                    ..FirstHit::default()
                });
            }
            // Light from the radiance cache: all the light that a far image, or a surface reached
            // by a diffuse bounce, reflects. (A probed share of the camera's first surfaces is
            // traced on in full all the same, only to keep their cells growing.)
            if let (Some(cache), Bsdf::Diffuse { albedo }) = (cache, bsdf)
                && depth < self.settings.max_depth
            {
                // How wide the light arriving here is spread: the pixel's footprint for the
                // camera's first surface, a share of the distance after a diffuse bounce.
                let depth_left = self.settings.max_depth - depth;
                let width = match &surface_footprint {
                    Some(s) if depth == 0 => s.cache_width,
                    _ if previous_diffuse && depth_left >= radiance_cache::DEPTH_LEFT_FOR_READS => {
                        radiance_cache::DIFFUSE_SPREAD * segment.length
                    }
                    _ => 0.0,
                };
                let (facing, cached) = self.cached(&cache, x, h, &frame, geometric, width, sampler);
                let weight = mul(beta, albedo);
                // Only the camera's first surface deposits estimates, so only there do probes
                // feed the cache.
                let depositable = depth == 0 && albedo.iter().all(|&a| a > 1e-3);
                let probe = cached.is_some()
                    && depositable
                    && sampler.next_independent_f64() < radiance_cache::PROBE;
                match cached {
                    Some(cached) if !probe => {
                        add(&mut radiance, mul(weight, cached));
                        break;
                    }
                    _ if depositable => {
                        pending = Some(PendingDeposit {
                            point: x,
                            height: h,
                            facing,
                            before: radiance,
                            weight,
                            read: cached.map(|c| mul(weight, c)),
                        });
                    }
                    _ => {}
                }
            }
            // As in pbrt: a path has at most max_depth scattering vertices, whether its last
            // segment to the light comes from light sampling or from a hit.
            if depth == self.settings.max_depth {
                break;
            }
            // Every bounce draws its decisions from its own dimensions of a stratified sampler.
            sampler.start_bounce(depth);
            depth += 1;
            if self.settings.nee && !bsdf.is_delta() {
                let sides = GeometricSides { geometric, wo };
                // Resampled at every bounce, not only the first: a single candidate past the
                // first bounce saves too little time for the noise it adds (docs/benchmarks.md).
                let candidates = self.light_candidates();
                let direct =
                    self.direct(sampler, x, h, &frame, &shading, &sides, &bsdf, candidates);
                add(&mut radiance, mul(beta, direct));
                if depth == 1 {
                    direct_first = mul(beta, direct);
                }
            }
            let Some(sample) =
                bsdf.sample(shading.to_local(wo), sampler.next_2d(), sampler.next_f64())
            else {
                break;
            };
            let wi = shading.to_world(sample.wi);
            if !(GeometricSides { geometric, wo }).agree(normal, wi) {
                break;
            }
            beta = mul(beta, sample.weight);
            specular = sample.delta;
            previous_diffuse = matches!(bsdf, Bsdf::Diffuse { .. });
            bounce_glimpses = footprint.is_some()
                && self.settings.bounce_footprint
                && self.settings.nee
                && previous_diffuse
                && space.kappa() <= 0.0;
            pdf_bsdf = sample.pdf;
            previous = (x, h, Normal::new(&frame, normal));
            if depth >= 3 {
                let survive = luminance(beta).clamp(0.05, 1.0);
                if sampler.next_f64() >= survive {
                    break;
                }
                beta = scale(beta, 1.0 / survive);
            }
            if !beta.iter().all(|b| b.is_finite()) || luminance(beta) <= 0.0 {
                break;
            }
            ray = frame.ray(space, x, h, wi).advanced(space, RAY_EPSILON);
        }
        let deposit = pending.as_ref().map(|p| p.deposit(radiance));
        if let Some(PendingDeposit {
            before,
            read: Some(read),
            ..
        }) = pending
        {
            // A probe takes the cache's value: its own light sample is not in its radiance.
            radiance = before;
            add(&mut radiance, read);
            direct_first = [0.0; 3];
        }
        let finite = radiance
            .iter()
            .chain(&seen)
            .chain(&direct_first)
            .all(|v| v.is_finite());
        let mut first = first.unwrap_or(FirstHit {
            albedo: [1.0; 3],
            ..FirstHit::default()
        });
        (first.emitted, first.direct) = if finite {
            (seen, direct_first)
        } else {
            ([0.0; 3], [0.0; 3])
        };
        PathSample {
            deposit,
            rays: rays_so_far().wrapping_sub(rays_before),
            radiance: if finite { radiance } else { [0.0; 3] },
            first,
        }
    }
}
