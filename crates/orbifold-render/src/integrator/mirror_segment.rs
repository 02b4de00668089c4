//! Following a ray through the room's mirrors and portals. A **mirror segment** is the part of a
//! path from one scattering vertex (or the camera) to the next thing that is not a mirror or a
//! portal: geodesic stretches joined by mirror reflections and portal crossings. Both are
//! isometries of the plane ([`orbifold_trace::room::Passage`]), so they are not path vertices:
//! the ray is followed through them deterministically, each one's reflectance or transmittance
//! multiplying the segment's throughput and its group element g its `chain`, the product that
//! says which tile of the universal cover the segment ends in (the light sampler finds the
//! light's image from it).
//!
//! Camera and bounce rays look for the nearest hit; a light sample's connection is a shadow
//! segment, which only asks whether anything but mirrors is in the way (an any-hit search).
//! Long chains of dim reflections end by Russian roulette, and a ray that runs into an ideal
//! corner, where it bounces ever faster, ends after [`MAX_MIRROR_BOUNCES`]. Each stretch
//! between mirrors is one ray traced, which is what [`PathSample::rays`](super::PathSample::rays)
//! counts.

use glam::{DMat3, DVec3};
use orbifold_scene::color::luminance;
use orbifold_trace::geodesic::Ray;
use orbifold_trace::tracer::SurfaceId;

use super::ray_footprint::RayFootprint;
use super::{Integrator, mul, scale};
use crate::lights::{Emitter, Rgb};
use crate::sampler::Sampler;

/// The most mirror reflections on one straight stretch of a path (rays that run into an ideal
/// corner bounce ever faster; they end here, dark).
pub const MAX_MIRROR_BOUNCES: usize = 256;

/// What a ray hit.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) enum HitKind {
    /// A room surface or an object, with the object's triangle and the barycentrics in it.
    Surface(SurfaceId, Option<(u32, [f64; 3])>),
    /// An area light's mesh.
    Light {
        /// The light's index.
        light: usize,
        /// The triangle of its mesh.
        triangle: u32,
        /// Barycentric coordinates in the triangle.
        barycentric: [f64; 3],
    },
}

/// The nearest thing along a ray.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct Intersection {
    /// Arc length along the ray.
    pub(super) s: f64,
    pub(super) kind: HitKind,
    /// The point hit (ambient coordinates).
    pub(super) point: DVec3,
    /// The ray's horizontal tangent at `point`, to go on from a mirror ([`Ray::continued`]).
    pub(super) tangent: DVec3,
    /// The height of the point hit.
    pub(super) height: f64,
}

/// How a mirror segment ended.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) enum SegmentEnd {
    /// At something that is not a mirror.
    Hit(Intersection),
    /// At the requested length, with nothing in the way.
    Reached,
    /// A shadow segment stopped by something that is not a mirror (what, it does not find).
    Blocked,
    /// Out through a cusp, or at the mirror-bounce limit.
    Lost,
}

/// Something other than a mirror in the way of a shadow segment.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
struct Blocked;

/// A mirror segment: a ray followed through mirrors to the first thing that is not one (or to
/// a given length).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct MirrorSegment {
    pub(super) end: SegmentEnd,
    /// Product of the mirrors' reflectances.
    pub(super) throughput: Rgb,
    /// Product of the walls' reflections, first wall first.
    pub(super) chain: DMat3,
    /// Arc length travelled (to the hit, or the requested length).
    pub(super) length: f64,
    /// The ray after the last mirror; the end is at arc length `rest` along it.
    pub(super) ray: Ray,
    /// Arc length along `ray` to the end.
    pub(super) rest: f64,
    /// Light of sphere lights whose images were counted by the footprint, passed on the way
    /// (with the mirrors' reflectances up to each).
    pub(super) glimpsed: Rgb,
    /// The sphere light the segment ended on, when the footprint counted its image: already
    /// counted in `glimpsed`.
    pub(super) glimpsed_end: Option<usize>,
}

thread_local! {
    /// Rays traced on this thread so far ([`Integrator::follow_mirrors`]): a path runs on one
    /// thread, so the difference before and after it is its count, at the cost of a
    /// thread-local add.
    static RAYS: std::cell::Cell<u32> = const { std::cell::Cell::new(0) };
}

pub(super) fn rays_so_far() -> u32 {
    RAYS.with(std::cell::Cell::get)
}

impl Integrator {
    /// The nearest room surface, object or area light along a ray, leaving out light `skip`.
    fn nearest(&self, ray: &Ray, skip: Option<usize>) -> Option<Intersection> {
        let space = self.space();
        let hit = self.tracer.nearest(ray);
        let mut best = hit.map(|h| Intersection {
            s: h.s,
            kind: HitKind::Surface(h.surface, h.triangle),
            point: h.point,
            tangent: h.tangent,
            height: h.height,
        });
        for (l, light) in self.lights.iter().enumerate() {
            if skip == Some(l) {
                continue;
            }
            if let Emitter::Area { instance, .. } = &light.emitter {
                let limit = best.map_or(f64::INFINITY, |b| b.s);
                if let Some(t) = instance.intersect(space, ray, 0.0, limit) {
                    let (point, tangent, height) = ray.point_and_tangent_at(space, t.s);
                    best = Some(Intersection {
                        s: t.s,
                        kind: HitKind::Light {
                            light: l,
                            triangle: t.triangle,
                            barycentric: t.barycentric,
                        },
                        point,
                        tangent,
                        height,
                    });
                }
            }
        }
        best
    }

    /// For a shadow segment: the room surface where `ray` leaves the room before arc length
    /// `limit` (`None` if it does not), or `Err(Blocked)` if an object or an area light other
    /// than `skip` is in the way first. An any-hit search: it stops at the first triangle
    /// found, where [`Integrator::nearest`] must go on looking for a nearer one.
    fn unblocked_exit(
        &self,
        ray: &Ray,
        skip: Option<usize>,
        limit: f64,
    ) -> Result<Option<Intersection>, Blocked> {
        let space = self.space();
        let exit = self.tracer.room.exit(ray).filter(|e| e.s < limit);
        let reach = exit.as_ref().map_or(limit, |e| e.s);
        if self.tracer.objects.occluded(space, ray, 0.0, reach) {
            return Err(Blocked);
        }
        for (l, light) in self.lights.iter().enumerate() {
            if let Emitter::Area { instance, .. } = &light.emitter
                && skip != Some(l)
                && instance.occluded(space, ray, 0.0, reach)
            {
                return Err(Blocked);
            }
        }
        Ok(exit.map(|e| Intersection {
            s: e.s,
            kind: HitKind::Surface(e.surface.into(), None),
            point: e.point,
            tangent: e.tangent,
            height: e.height,
        }))
    }

    /// Follows a ray through mirrors for at most `length`, not meeting light `skip`.
    ///
    /// With `roulette` (a sampler, the luminance of the path's throughput so far, and a level:
    /// `ROULETTE_LEVEL` or `FOOTPRINT_ROULETTE_LEVEL`), a path
    /// whose throughput falls below the level after a mirror goes on with probability
    /// ∝ its throughput and is weighted up when it does (Russian roulette: unbiased, and long
    /// chains of dim reflections stop early).
    ///
    /// With a `ray_footprint` (a camera ray's pixel, or a diffuse bounce's), sphere lights whose
    /// images are smaller than the footprint are counted by the share of it that they cover
    /// ([`orbifold_trace::footprint`]; [`Integrator::glimpse`]).
    ///
    /// With `visibility_only` (a connection to a light), the segment only needs to know whether
    /// it gets through: it ends `Blocked` at the first thing in the way that is not a mirror.
    pub(super) fn follow_mirrors(
        &self,
        ray: &Ray,
        length: f64,
        skip: Option<usize>,
        mut roulette: Option<(&mut Sampler, f64, f64)>,
        ray_footprint: Option<RayFootprint<'_>>,
        visibility_only: bool,
    ) -> MirrorSegment {
        let space = self.space();
        // The footprint as it is carried: mirrors swap left and right.
        let mut carried = ray_footprint.map(|g| *g.footprint());
        let unsampled_only = matches!(ray_footprint, Some(RayFootprint::Bounce(_)));
        let mut segment = MirrorSegment {
            end: SegmentEnd::Lost,
            throughput: [1.0; 3],
            chain: DMat3::IDENTITY,
            length: 0.0,
            ray: *ray,
            rest: 0.0,
            glimpsed: [0.0; 3],
            glimpsed_end: None,
        };
        for _ in 0..=MAX_MIRROR_BOUNCES {
            RAYS.with(|r| r.set(r.get().wrapping_add(1)));
            let remaining = length - segment.length;
            let hit = if visibility_only {
                match self.unblocked_exit(&segment.ray, skip, remaining) {
                    Ok(hit) => hit,
                    Err(Blocked) => {
                        segment.end = SegmentEnd::Blocked;
                        return segment;
                    }
                }
            } else {
                self.nearest(&segment.ray, skip).filter(|n| n.s < remaining)
            };
            if let Some(footprint) = &carried {
                self.glimpse(
                    &mut segment,
                    footprint,
                    hit.as_ref(),
                    remaining,
                    unsampled_only,
                );
            }
            let Some(hit) = hit else {
                if remaining.is_finite() {
                    segment.end = SegmentEnd::Reached;
                    segment.rest = remaining;
                    segment.length = length;
                }
                return segment;
            };
            let passage = match hit.kind {
                HitKind::Surface(SurfaceId::Wall(w), _) => {
                    self.tracer.room.passage(w, hit.point, hit.height)
                }
                _ => None,
            };
            let Some(passage) = passage else {
                segment.end = SegmentEnd::Hit(hit);
                segment.rest = hit.s;
                segment.length += hit.s;
                return segment;
            };
            let reflectance = passage.throughput;
            segment.throughput = mul(segment.throughput, reflectance);
            if let Some((sampler, beta, level)) = roulette.as_mut() {
                let carried = *beta * luminance(segment.throughput);
                if carried < *level {
                    let survive = carried / *level;
                    if survive.is_nan()
                        || survive <= 0.0
                        || sampler.next_independent_f64() >= survive
                    {
                        return segment;
                    }
                    segment.throughput = scale(segment.throughput, 1.0 / survive);
                }
            }
            if passage.reverses {
                carried = carried.map(|f| f.reflected());
            }
            segment.chain *= passage.across;
            segment.length += hit.s;
            segment.ray = (segment.ray)
                .continued(space, hit.s, hit.point, hit.tangent)
                .passed(space, &passage);
        }
        segment
    }
}
