//! What the integrator finds where a ray meets a surface that is not a mirror: the surface's
//! normals and its BSDF there, with its textures looked up in the coordinates the scene asks for
//! and filtered over a camera ray's pixel footprint (pbrt's `SurfaceInteraction` and its
//! `GetBSDF`).
//!
//! Objects may be smooth-shaded: their interpolated shading normal differs from the triangle's
//! own, geometric, normal. Two guards keep that from blackening or leaking light, as in pbrt: the
//! shading normal is bent towards the geometric one where the eye would be below it
//! ([`bent_shading_normal`]), and directions that the two normals put on different sides of the
//! surface carry no light ([`GeometricSides`]).

use glam::DVec3;
use orbifold_trace::tracer::SurfaceId;
use orbifold_trace::triangle::TriangleHit;

use super::Integrator;
use super::mirror_segment::{HitKind, Intersection};
use super::ray_footprint::SurfaceFootprint;
use crate::lights::{Emitter, TangentFrame};
use crate::materials::bsdf::Bsdf;
use crate::textures::TextureEvalContext;

/// How far above a shading normal's horizon the outgoing direction is kept (cosine).
const SHADING_HORIZON: f64 = 0.02;

/// The shading normal `shading`, bent towards the surface's own normal `geometric` (both on the
/// same side of the surface) just enough that the outgoing direction `wo` stays at least
/// [`SHADING_HORIZON`] above it: interpolated normals tilt away from a viewer near a silhouette,
/// and a BSDF would see the eye below its surface there and go black. Where `wo` grazes the
/// surface itself, the surface's own normal.
pub(super) fn bent_shading_normal(shading: DVec3, geometric: DVec3, wo: DVec3) -> DVec3 {
    if shading == geometric {
        return shading;
    }
    // The side of the surface wo is on (a dielectric's normals may face away from it).
    let side = if wo.dot(geometric) < 0.0 { -1.0 } else { 1.0 };
    let (g, n) = (geometric * side, shading * side);
    let (above, above_g) = (wo.dot(n), wo.dot(g));
    if n.dot(g) <= 0.0 || above_g <= SHADING_HORIZON {
        return geometric;
    }
    if above >= SHADING_HORIZON {
        return shading;
    }
    // (n + t g)·wo ≥ ε|n + t g|, with |n + t g| ≤ 1 + t.
    let t = (SHADING_HORIZON - above) / (above_g - SHADING_HORIZON);
    (n + g * t).normalize() * side
}

/// Which side of a surface directions are on, by its own normal: with a smooth shading normal a
/// direction can look reflected to the BSDF and yet go into the surface, or the other way round.
/// Such directions carry no light (as in pbrt), which keeps the surface opaque.
pub(super) struct GeometricSides {
    /// The surface's own unit normal.
    pub(super) geometric: DVec3,
    /// The direction towards where the path came from.
    pub(super) wo: DVec3,
}

impl GeometricSides {
    /// Whether `wi` is on the same side of the shading normal `normal` as of the surface itself
    /// (relative to `wo`).
    pub(super) fn agree(&self, normal: DVec3, wi: DVec3) -> bool {
        let reflected_by_shading = wi.dot(normal) * self.wo.dot(normal) > 0.0;
        let reflected = wi.dot(self.geometric) * self.wo.dot(self.geometric) > 0.0;
        reflected_by_shading == reflected
    }
}

impl Integrator {
    /// The unit normals (local coordinates in `frame`: the surface's own, then the shading
    /// normal, which differs on smooth-shaded objects) and the BSDF where a mirror segment
    /// ended; with the camera ray's `footprint` there, textures are averaged over its pixel's
    /// footprint.
    pub(super) fn surface(
        &self,
        hit: &Intersection,
        frame: &TangentFrame,
        footprint: Option<&SurfaceFootprint>,
    ) -> Option<(DVec3, DVec3, Bsdf)> {
        let space = self.space();
        let moved = |offset: DVec3| {
            if offset == DVec3::ZERO {
                return (hit.point, hit.height);
            }
            let (v, up) = frame.to_ambient(offset);
            (space.exp(hit.point, v), hit.height + up)
        };
        let coords = |intrinsic: bool, offset: DVec3| {
            let (x, h) = moved(offset);
            if intrinsic {
                let v = space.log(self.centre, x);
                [
                    space.point_dot(v, self.centre_frame.e1),
                    space.point_dot(v, self.centre_frame.e2),
                    h,
                ]
            } else {
                let z = space.to_model(x);
                [z.re, z.im, h]
            }
        };
        let lookup = |n: DVec3| TextureEvalContext {
            coords: &coords,
            footprint: footprint.map(|s| s.axes(n)),
        };
        match hit.kind {
            HitKind::Surface(SurfaceId::Floor, _) => {
                Some((DVec3::Z, DVec3::Z, self.floor.bsdf(&lookup(DVec3::Z))))
            }
            HitKind::Surface(SurfaceId::Ceiling, _) => {
                let n = -DVec3::Z;
                Some((n, n, self.ceiling.bsdf(&lookup(n))))
            }
            HitKind::Surface(SurfaceId::Wall(w), _) => {
                let room = &self.tracer.room;
                let nu = room.wall_form_at(w, hit.point);
                let n = frame
                    .to_local(space, DVec3::new(nu.x, nu.y, space.kappa() * nu.z), 0.0)
                    .try_normalize()?;
                // Walls are laid out by (length along the wall, height).
                let wall = |_: bool, offset: DVec3| {
                    let (x, h) = moved(offset);
                    [room.along(w, x) * room.walls[w].length, h, 0.0]
                };
                let lookup = TextureEvalContext {
                    coords: &wall,
                    footprint: footprint.map(|s| s.axes(n)),
                };
                Some((n, n, self.walls[w].bsdf(&lookup)))
            }
            HitKind::Surface(SurfaceId::Object(i), triangle) => {
                let (triangle, barycentric) = triangle?;
                let triangle_hit = TriangleHit {
                    s: 0.0,
                    triangle,
                    barycentric,
                };
                let instance = &self.tracer.objects.instances()[i];
                let (h, v) = instance.normal(space, &triangle_hit)?;
                let n = frame.to_local(space, h, v).try_normalize()?;
                let (h, v) = instance.shading_normal(space, &triangle_hit)?;
                let shading = frame.to_local(space, h, v).try_normalize().unwrap_or(n);
                Some((n, shading, self.objects[i].bsdf(&lookup(n))))
            }
            HitKind::Light { .. } => None,
        }
    }

    /// The unit normal of an area light's triangle at barycentrics `w`, local in `frame`.
    pub(super) fn light_normal(
        &self,
        light: usize,
        triangle: u32,
        w: [f64; 3],
        frame: &TangentFrame,
    ) -> Option<DVec3> {
        let Emitter::Area { instance, .. } = &self.lights[light].emitter else {
            return None;
        };
        let hit = TriangleHit {
            s: 0.0,
            triangle,
            barycentric: w,
        };
        let (h, v) = instance.normal(self.space(), &hit)?;
        frame.to_local(self.space(), h, v).try_normalize()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    fn unit_vector() -> impl Strategy<Value = DVec3> {
        (-1.0f64..1.0, -1.0f64..1.0, -1.0f64..1.0)
            .prop_filter("not too short", |v| {
                DVec3::new(v.0, v.1, v.2).length() > 0.1
            })
            .prop_map(|v| DVec3::new(v.0, v.1, v.2).normalize())
    }

    proptest! {
        /// A bent shading normal is unit, on the surface's side of the geometric one, keeps the
        /// outgoing direction above its horizon, and is the shading normal itself whenever that
        /// already does.
        #[test]
        fn a_bent_shading_normal_keeps_the_eye_above_it(
            geometric in unit_vector(),
            tilt in unit_vector(),
            wo in unit_vector(),
            amount in 0.0f64..1.5,
            outward in any::<bool>(),
        ) {
            let geometric = if outward { geometric } else { -geometric };
            let shading = (geometric + tilt * amount).normalize();
            prop_assume!(shading.dot(geometric) > 0.0);
            let bent = bent_shading_normal(shading, geometric, wo);
            prop_assert!((bent.length() - 1.0).abs() < 1e-12);
            prop_assert!(bent.dot(geometric) > 0.0);
            let side = wo.dot(geometric).signum();
            if (wo.dot(geometric) * side) > SHADING_HORIZON {
                prop_assert!(wo.dot(bent) * side >= SHADING_HORIZON - 1e-12);
            } else {
                prop_assert_eq!(bent, geometric);
            }
            if wo.dot(shading) * side >= SHADING_HORIZON && wo.dot(geometric) * side > SHADING_HORIZON {
                prop_assert_eq!(bent, shading);
            }
        }

        /// With the geometric normal as shading normal every direction agrees; with a tilted one,
        /// a direction agrees exactly when it is on the same side of both (relative to wo).
        #[test]
        fn sides_agree_when_both_normals_say_the_same(
            geometric in unit_vector(),
            tilt in unit_vector(),
            wo in unit_vector(),
            wi in unit_vector(),
        ) {
            let sides = GeometricSides { geometric, wo };
            prop_assert!(sides.agree(geometric, wi));
            let shading = (geometric + tilt * 0.5).normalize();
            let same = |n: DVec3| (wi.dot(n) > 0.0) == (wo.dot(n) > 0.0);
            prop_assert_eq!(sides.agree(shading, wi), same(shading) == same(geometric));
        }
    }
}
