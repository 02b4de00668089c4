//! Ray footprints: how wide a camera ray's pixel, or a diffuse bounce's lobe, is along the ray
//! (what ray differentials or cones are to a flat-space tracer; [`orbifold_trace::footprint`]
//! carries the widths through curved space and mirrors), and what the integrator does with it.
//!
//! Along a mirror segment, a footprint counts the mirror images of sphere lights that are at most
//! a few footprints wide by the share of the footprint they cover, not by whether the ray hits
//! them: it *glimpses* them ([`Integrator::glimpse`]; our word, after the tracer's [`Glimpse`]).
//! Far light images smaller than a pixel then come out as their coverage rather than as rare hits
//! of enormous radiance. A camera ray glimpses every image; a ray that leaves a diffuse bounce
//! ([`BOUNCE_FOOTPRINT`]) only those that light sampling cannot draw, the others being weighed
//! against light sampling by MIS when a ray hits them.
//!
//! Where a camera ray meets its first surface, its footprint there ([`SurfaceFootprint`]) filters
//! the surface's textures over the pixel ([`crate::textures`]) and sets how wide the
//! radiance cache's cells that the surface reads may be.

use glam::DVec3;
use orbifold::space::Space;
use orbifold_trace::footprint::{Footprint, Glimpse, Sphere, sphere_coverage};

use super::mirror_segment::{HitKind, Intersection, MirrorSegment};
use super::{Integrator, add, mul, scale};
use crate::lights::Rgb;
use crate::radiance_cache;

/// The footprint that a ray leaving a diffuse bounce carries to count the far mirror images of
/// sphere lights that light sampling cannot draw (beyond the image set's cutoff, thousands of
/// them in a hyperbolic room) by the share of it they cover, rather than by rare hits of
/// enormous radiance: a box of ±0.1 rad around the ray (the radiance cache's
/// [`radiance_cache::DIFFUSE_SPREAD`]), over which a Lambertian lobe hardly changes (a glossy
/// one could, so glossy bounces leave those images to ray hits). Capped at each light as a
/// camera's footprint is ([`orbifold_trace::footprint`]). Not on the sphere, whose images are few
/// and all drawn.
pub(super) const BOUNCE_FOOTPRINT: Footprint = Footprint {
    across: radiance_cache::DIFFUSE_SPREAD,
    up: radiance_cache::DIFFUSE_SPREAD,
    centre: [0.0; 2],
};

/// The footprint a mirror segment counts small sphere-light images with
/// ([`orbifold_trace::footprint`]).
#[derive(Clone, Copy, Debug)]
pub(super) enum RayFootprint<'a> {
    /// A camera ray's pixel: every image.
    Camera(&'a Footprint),
    /// A ray from a diffuse bounce: only the images that light sampling cannot draw.
    Bounce(&'a Footprint),
}

impl RayFootprint<'_> {
    /// The footprint itself.
    pub(super) fn footprint(&self) -> &Footprint {
        match self {
            RayFootprint::Camera(f) | RayFootprint::Bounce(f) => f,
        }
    }
}

/// A camera ray's pixel footprint where it meets its first surface.
#[derive(Clone, Copy, Debug)]
pub(super) struct SurfaceFootprint {
    /// Widths across the ray and up (perpendicular to it in its vertical plane).
    widths: (f64, f64),
    /// How far the pixel's centre is seen from the ray, across (to the left) and up: the
    /// footprint's turns to it ([`Footprint::centre`]), grown as the widths have.
    centre: (f64, f64),
    /// The ray's direction of travel (local frame).
    travel: DVec3,
    /// The widest cells of the radiance cache that the surface may read
    /// ([`SurfaceFootprint::cache_width`]).
    pub(super) cache_width: f64,
}

impl SurfaceFootprint {
    /// The footprint of `pixel` carried `s` along a ray of elevation cosine `cos_elevation` and
    /// direction `travel` there.
    pub(super) fn new(
        space: Space,
        pixel: &Footprint,
        s: f64,
        cos_elevation: f64,
        travel: DVec3,
    ) -> SurfaceFootprint {
        let widths = pixel.widths(space, s, cos_elevation);
        let grown = |turn: f64, width: f64, angle: f64| {
            let d = turn * width / angle;
            if d.is_finite() { d } else { 0.0 }
        };
        SurfaceFootprint {
            widths,
            centre: (
                grown(pixel.centre[0], widths.0, pixel.across),
                grown(pixel.centre[1], widths.1, pixel.up),
            ),
            travel,
            cache_width: SurfaceFootprint::cache_width(pixel, widths),
        }
    }

    /// How wide the radiance cache's cells read at the surface may be: the footprint's narrower
    /// width, times the square root of how much wider than in flat space curvature has made it
    /// across the ray (S_κ(σ)/(s cos α), the ratio of the two widths for a square pixel). In H²
    /// that ratio grows like e^σ/σ, and the narrower width alone would keep the first rings of
    /// far images off the cache; the root blurs their lighting by at most that many pixel heights
    /// up and down and by less than a pixel across. In E² and S² it is the narrower width.
    fn cache_width(pixel: &Footprint, (across, up): (f64, f64)) -> f64 {
        let narrow = across.min(up);
        let stretch = (across * pixel.up) / (up * pixel.across);
        if stretch > 1.0 {
            narrow * stretch.sqrt()
        } else {
            narrow
        }
    }

    /// The tangent vector to where the pixel's centre is seen and the footprint's half-axes,
    /// projected along the ray onto the plane with normal `n`, each at most `MAX_FOOTPRINT`
    /// long (beyond, every pattern is averaged out anyway). Centred on the pixel, the box is
    /// the same for every sample of it, up to the change of the projection across the pixel:
    /// each sample gets the pixel's own filtered value, the one its ray hits average to.
    pub(super) fn axes(&self, n: DVec3) -> [DVec3; 3] {
        const MAX_FOOTPRINT: f64 = 10.0;
        let d = self.travel;
        let across = d.cross(DVec3::Z).try_normalize().unwrap_or(DVec3::X);
        let up = across.cross(d);
        let facing = n.dot(d);
        let project = |v: DVec3| {
            let p = if facing.abs() > 1e-6 {
                v - d * (n.dot(v) / facing)
            } else {
                v
            };
            // What rounding leaves along the normal, taken off: on the floor it would move
            // the point a hair below height 0, onto the other side of a 3D checker's layer.
            let p = p - n * n.dot(p);
            p.clamp_length_max(MAX_FOOTPRINT)
        };
        [
            project(up * self.centre.1 - across * self.centre.0),
            project(across * (0.5 * self.widths.0)),
            project(up * (0.5 * self.widths.1)),
        ]
    }
}

impl Integrator {
    /// The sphere lights with their clearance from the walls, the floor and the ceiling.
    pub(super) fn footprint_spheres(&self) -> Vec<(usize, Sphere, Rgb)> {
        let space = self.space();
        let room = &self.tracer.room;
        self.lights
            .iter()
            .enumerate()
            .filter_map(|(l, light)| {
                let (radius, radiance) = light.sphere()?;
                let clearance = room
                    .walls
                    .iter()
                    .map(|w| space.asin(w.form.dot(light.position)).abs())
                    .fold(f64::INFINITY, f64::min);
                let headroom = light.height.min(room.height - light.height);
                let sphere = Sphere::new(
                    space,
                    light.position,
                    light.height,
                    radius,
                    clearance,
                    headroom,
                );
                Some((l, sphere, radiance))
            })
            .collect()
    }

    /// Adds to `segment.glimpsed` the sphere lights whose images near the stretch of
    /// `segment.ray` up to `hit` (or to `remaining`) are at most a few footprints wide; with
    /// `unsampled_only`, only the images that light sampling cannot draw (the others are
    /// weighed against it by MIS when a ray hits them).
    pub(super) fn glimpse(
        &self,
        segment: &mut MirrorSegment,
        footprint: &Footprint,
        hit: Option<&Intersection>,
        remaining: f64,
        unsampled_only: bool,
    ) {
        let space = self.space();
        let end = hit.map_or(remaining, |n| n.s);
        for &(l, ref sphere, radiance) in &self.spheres {
            let struck = matches!(
                hit,
                Some(Intersection { kind: HitKind::Light { light, .. }, .. }) if *light == l
            );
            let slack = if struck { 2.0 * sphere.radius() } else { 0.0 };
            let glimpse = sphere_coverage(
                space,
                &segment.ray,
                segment.length,
                footprint,
                sphere,
                end,
                slack,
            );
            if let Glimpse::Covered(share) = glimpse {
                if unsampled_only && self.samples_image(l, &segment.chain) {
                    continue;
                }
                add(
                    &mut segment.glimpsed,
                    scale(mul(segment.throughput, radiance), share),
                );
                if struck {
                    segment.glimpsed_end = Some(l);
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cache_reads_widen_only_with_the_curvature_across_the_ray() {
        // In E² a footprint's widths grow alike: the cache width is the narrower one, whatever
        // the pixel's shape. In H² the width across outgrows the height by S(σ)/(s cos α); the
        // cache width is then the geometric mean of the widths for a square pixel. In S² the
        // footprint narrows across: the narrower width again.
        let travel = DVec3::X;
        let square = Footprint {
            across: 1e-3,
            up: 1e-3,
            centre: [0.0; 2],
        };
        let wide = Footprint {
            across: 2e-3,
            up: 1e-3,
            centre: [0.0; 2],
        };
        let e2 = Space::new(orbifold::Geometry::Euclidean);
        for pixel in [square, wide] {
            let spread = SurfaceFootprint::new(e2, &pixel, 5.0, 1.0, travel);
            assert!((spread.cache_width - spread.widths.0.min(spread.widths.1)).abs() < 1e-15);
        }
        let h2 = Space::new(orbifold::Geometry::Hyperbolic);
        for s in [0.5, 3.0, 8.0] {
            let spread = SurfaceFootprint::new(h2, &square, s, 1.0, travel);
            let (across, up) = spread.widths;
            assert!(across > up);
            assert!((spread.cache_width - (across * up).sqrt()).abs() < 1e-12 * across);
        }
        let s2 = Space::new(orbifold::Geometry::Spherical);
        let spread = SurfaceFootprint::new(s2, &square, 2.0, 1.0, travel);
        assert_eq!(spread.cache_width, spread.widths.0.min(spread.widths.1));
    }

    #[test]
    fn a_footprint_on_the_floor_stretches_along_a_grazing_ray() {
        // A ray 10° below the horizon along +x meets the floor: the footprint's height becomes
        // height / sin 10° along x, its width stays across (y).
        let travel = DVec3::new(10f64.to_radians().cos(), 0.0, -10f64.to_radians().sin());
        let spread = SurfaceFootprint {
            widths: (0.02, 0.01),
            centre: (0.004, 0.002),
            travel,
            cache_width: 0.01,
        };
        let [centre, a, b] = spread.axes(DVec3::Z);
        // The pixel's centre is seen 0.004 to the left (+y) and 0.002 up: on the floor, that
        // is further along the ray.
        assert!(
            (centre.y - 0.004).abs() < 1e-12 && centre.z.abs() < 1e-12,
            "{centre}"
        );
        assert!(
            (centre.x - 0.002 / 10f64.to_radians().sin()).abs() < 1e-9,
            "{centre}"
        );
        assert!((a.length() - 0.01).abs() < 1e-12 && a.x.abs() < 1e-12 && a.z.abs() < 1e-12);
        let along = 0.005 / 10f64.to_radians().sin();
        assert!(
            (b.length() - along).abs() < 1e-9 && b.z.abs() < 1e-12,
            "{b}"
        );
    }
}
