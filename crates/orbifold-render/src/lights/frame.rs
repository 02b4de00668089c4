//! Tangent frames of the product space: at a point of S²×R, E²×R or H²×R, two horizontal unit
//! tangents and the vertical, in which shading, emission and light sampling work in local
//! coordinates (e₁, e₂, up); and the direction a ray travels in, expressed in such a frame.

use glam::DVec3;
use orbifold::space::Space;
use orbifold_trace::geodesic::Ray;

/// An orthonormal frame of the tangent space of the product space at a point: two unit
/// horizontal ambient tangents and the vertical. Local coordinates are (e₁, e₂, up).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TangentFrame {
    /// First horizontal unit tangent (ambient).
    pub e1: DVec3,
    /// Second horizontal unit tangent, a quarter turn from `e1`.
    pub e2: DVec3,
}

impl TangentFrame {
    /// A frame at the ambient point `x` ([`Space::tangent_frame`]: shading needs any frame,
    /// textures in intrinsic coordinates this one).
    ///
    /// ```
    /// use orbifold::{Geometry, space::Space};
    /// use orbifold_render::lights::TangentFrame;
    /// use glam::DVec3;
    /// let h2 = Space::new(Geometry::Hyperbolic);
    /// let x = h2.exp(DVec3::Z, DVec3::new(0.3, -1.2, 0.0));
    /// let f = TangentFrame::at(h2, x);
    /// assert!((h2.point_dot(f.e1, f.e1) - 1.0).abs() < 1e-12 && h2.point_dot(f.e1, f.e2).abs() < 1e-12);
    /// ```
    pub fn at(space: Space, x: DVec3) -> TangentFrame {
        let [e1, e2] = space.tangent_frame(x);
        TangentFrame { e1, e2 }
    }

    /// Local coordinates of a tangent vector (horizontal ambient part, vertical part).
    #[inline]
    pub fn to_local(&self, space: Space, horizontal: DVec3, vertical: f64) -> DVec3 {
        DVec3::new(
            space.point_dot(horizontal, self.e1),
            space.point_dot(horizontal, self.e2),
            vertical,
        )
    }

    /// The tangent vector (horizontal ambient part, vertical part) of local coordinates.
    #[inline]
    pub fn to_ambient(&self, v: DVec3) -> (DVec3, f64) {
        (self.e1 * v.x + self.e2 * v.y, v.z)
    }

    /// The ray from (x, h) in the local direction `v` (unit).
    pub fn ray(&self, space: Space, x: DVec3, h: f64, v: DVec3) -> Ray {
        let horizontal = (v.x * v.x + v.y * v.y).sqrt();
        if horizontal < 1e-12 {
            // Straight up or down: any horizontal direction will do.
            return Ray::climbing(space, x, self.e1, h, 0.0, v.z.signum());
        }
        let u = (self.e1 * v.x + self.e2 * v.y) / horizontal;
        Ray::climbing(space, x, u, h, horizontal, v.z)
    }
}

/// The local direction of travel of a ray at arc length `s` (unit, in `frame` at that point).
pub fn travel_direction(space: Space, frame: &TangentFrame, ray: &Ray, s: f64) -> DVec3 {
    let u = ray.tangent_at(space, s * ray.cos_elevation);
    frame.to_local(space, u * ray.cos_elevation, ray.sin_elevation)
}
