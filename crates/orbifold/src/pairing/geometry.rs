//! The small geometric tools of the side-pairing constructions, written once for every κ
//! (ARCHITECTURE.md §3): points in polar form, walls through two points, directions along a wall,
//! interior angles, and the isometry that carries one edge onto another.

use glam::{DMat3, DVec3};

use crate::space::Space;

/// The ambient point at intrinsic distance `r` from the origin in model bearing `bearing`.
pub(crate) fn polar(space: Space, r: f64, bearing: f64) -> DVec3 {
    let (c, s) = space.cos_sin(r);
    let (sin, cos) = bearing.sin_cos();
    DVec3::new(s * cos, s * sin, c)
}

/// The ideal point (a null direction of the hyperboloid) in model bearing `bearing`.
pub(crate) fn ideal_at(bearing: f64) -> DVec3 {
    let (sin, cos) = bearing.sin_cos();
    DVec3::new(cos, sin, 1.0)
}

/// G·ν: the unit tangent vector normal to the wall ν, pointing to its inner side, at any point of
/// the wall (for a normalised wall, ⟨Gν, Gν⟩ = 1 and ⟨Gν, p⟩ = ν·p = 0 on the wall).
pub(crate) fn inner_normal(space: Space, nu: DVec3) -> DVec3 {
    DVec3::new(nu.x, nu.y, space.kappa() * nu.z)
}

/// The unit tangent at the wall's point `p` along the wall, in the direction that keeps the
/// inner side on the left (the counter-clockwise direction of a polygon's edge).
pub(crate) fn along(space: Space, nu: DVec3, p: DVec3) -> DVec3 {
    -space.quarter_turn(p, inner_normal(space, nu))
}

/// The unit tangent at the finite point `p` towards `q` (finite, or an ideal point's null
/// direction): the part of q orthogonal to p, for κ ≠ 0; q − p in the plane.
pub(crate) fn toward(space: Space, p: DVec3, q: DVec3) -> DVec3 {
    let k = space.kappa();
    let t = if k == 0.0 {
        q / q.z - p / p.z
    } else {
        q - p * (k * space.point_dot(p, q))
    };
    t / space.point_dot(t, t).max(f64::MIN_POSITIVE).sqrt()
}

/// The wall through `a` and `b` (finite or ideal), normalised, with `inside` on its positive side.
pub(crate) fn wall_through(space: Space, a: DVec3, b: DVec3, inside: DVec3) -> DVec3 {
    let nu = space.normalize_wall(a.cross(b));
    if nu.dot(inside) < 0.0 { -nu } else { nu }
}

/// The angle at `p` swept counter-clockwise from the unit tangent `from` to the unit tangent `to`,
/// in [0, 2π).
pub(crate) fn turn(space: Space, p: DVec3, from: DVec3, to: DVec3) -> f64 {
    let j = space.quarter_turn(p, from);
    let angle = space.point_dot(j, to).atan2(space.point_dot(from, to));
    angle.rem_euclid(std::f64::consts::TAU)
}

/// The interior angle at the finite corner `p` of a counter-clockwise polygon whose edges leave
/// along `outgoing` and arrive along `incoming` (both walls with the polygon on the inner side).
pub(crate) fn interior_angle(space: Space, p: DVec3, incoming: DVec3, outgoing: DVec3) -> f64 {
    let next = along(space, outgoing, p);
    let prev = -along(space, incoming, p);
    turn(space, p, next, prev)
}

/// The isometry (an orthonormal frame change) taking the point `p` with unit tangent `u` to the
/// point `q` with unit tangent `w`; orientation-reversing when `reverse`.
pub(crate) fn frame_map(
    space: Space,
    (p, u): (DVec3, DVec3),
    (q, w): (DVec3, DVec3),
    reverse: bool,
) -> DMat3 {
    let from = DMat3::from_cols(u, space.quarter_turn(p, u), p);
    let side = if reverse { -1.0 } else { 1.0 };
    let to = DMat3::from_cols(w, space.quarter_turn(q, w) * side, q);
    to * from.inverse()
}

/// The interior angle at the finite corner `p` between the directions towards `next` and
/// `prev` (finite or ideal), as in a counter-clockwise polygon.
pub(crate) fn corner_angle(space: Space, p: DVec3, next: DVec3, prev: DVec3) -> f64 {
    turn(space, p, toward(space, p, next), toward(space, p, prev))
}

/// The foot of the perpendicular from `p` to the normalised wall `nu`.
pub(crate) fn foot(space: Space, nu: DVec3, p: DVec3) -> DVec3 {
    space.normalize_point(p - inner_normal(space, nu) * nu.dot(p))
}

/// The root of `f` on [lo, hi] by bisection, where f(lo) and f(hi) have opposite signs (or the
/// end nearer to a sign change when they do not).
pub(crate) fn bisect(mut lo: f64, mut hi: f64, f: impl Fn(f64) -> f64) -> f64 {
    let low_sign = f(lo) > 0.0;
    for _ in 0..100 {
        let mid = 0.5 * (lo + hi);
        if mid <= lo || mid >= hi {
            break;
        }
        if (f(mid) > 0.0) == low_sign {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    0.5 * (lo + hi)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::euler::Geometry;

    #[test]
    fn frame_map_takes_the_frame_to_the_frame_in_every_geometry() {
        for g in [
            Geometry::Spherical,
            Geometry::Euclidean,
            Geometry::Hyperbolic,
        ] {
            let space = Space::new(g);
            let (p, q) = (polar(space, 0.7, 0.3), polar(space, 0.4, 2.0));
            let (u, w) = (toward(space, p, q), toward(space, q, p));
            for reverse in [false, true] {
                let m = frame_map(space, (p, u), (q, w), reverse);
                assert!((m * p - q).length() < 1e-12, "{g:?}");
                assert!((m * u - w).length() < 1e-12, "{g:?}");
                assert_eq!(m.determinant() < 0.0, reverse, "{g:?}");
            }
        }
    }

    #[test]
    fn interior_angle_of_a_square_corner_is_a_right_angle() {
        let e2 = Space::new(Geometry::Euclidean);
        let corners = [
            DVec3::new(0.0, 0.0, 1.0),
            DVec3::new(1.0, 0.0, 1.0),
            DVec3::new(0.0, 1.0, 1.0),
        ];
        let inside = DVec3::new(0.2, 0.2, 1.0);
        let outgoing = wall_through(e2, corners[0], corners[1], inside);
        let incoming = wall_through(e2, corners[2], corners[0], inside);
        let a = interior_angle(e2, corners[0], incoming, outgoing);
        assert!((a - std::f64::consts::FRAC_PI_2).abs() < 1e-12, "{a}");
        let b = corner_angle(e2, corners[0], corners[1], corners[2]);
        assert!((b - std::f64::consts::FRAC_PI_2).abs() < 1e-12, "{b}");
    }
}
