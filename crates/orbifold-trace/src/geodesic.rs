//! Geodesics of the product spaces S²×ℝ, E²×ℝ and H²×ℝ, written once for every curvature
//! (ARCHITECTURE.md §8).
//!
//! A unit-speed geodesic from (p, h) with unit horizontal direction u and elevation α is
//!
//! ```text
//! x(s) = C_κ(s cos α)·p + S_κ(s cos α)·u,    h(s) = h + s sin α,
//! ```
//!
//! so its height is linear in the *intrinsic* arc length s, and its horizontal part is a geodesic
//! of the plane traversed at speed cos α. (The seed's spiral, with height linear in the model-space
//! angle, is not a geodesic.) Points are ambient coordinates (`orbifold::space`).

use glam::{DMat3, DVec3};
use num_complex::Complex64;
use orbifold::space::Space;

/// A unit-speed geodesic ray of the product space.
///
/// ```
/// use orbifold_trace::geodesic::Ray;
/// use orbifold::{Geometry, space::Space};
/// use num_complex::Complex64;
/// let h2 = Space::new(Geometry::Hyperbolic);
/// // From the centre, heading along +x, 30° up.
/// let ray = Ray::from_model(h2, Complex64::new(0.0, 0.0), 0.5, 0.0, 30f64.to_radians());
/// let (x, h) = ray.point_at(h2, 2.0);
/// // Horizontal distance travelled is s cos α; height grows by s sin α.
/// assert!((h2.ambient_distance(ray.origin, x) - 2.0 * 30f64.to_radians().cos()).abs() < 1e-12);
/// assert!((h - 1.5).abs() < 1e-12);
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Ray {
    /// Ambient coordinates of the start's horizontal position.
    pub origin: DVec3,
    /// Unit horizontal tangent at `origin` (⟨p, u⟩ = 0, ⟨u, u⟩ = 1 in the space's form).
    pub direction: DVec3,
    /// Height of the start.
    pub height: f64,
    /// cos α: horizontal speed.
    pub cos_elevation: f64,
    /// sin α: vertical speed.
    pub sin_elevation: f64,
}

impl Ray {
    /// A ray from an ambient point along a horizontal tangent (any nonzero length; it is made
    /// tangent and unit) with elevation `elevation` radians.
    pub fn new(space: Space, origin: DVec3, horizontal: DVec3, height: f64, elevation: f64) -> Ray {
        let (sin_elevation, cos_elevation) = elevation.sin_cos();
        Ray {
            origin,
            direction: horizontal,
            height,
            cos_elevation,
            sin_elevation,
        }
        .renormalized(space)
    }

    /// A ray from an ambient point along a horizontal tangent (any nonzero length) that climbs
    /// `rise` for every `run` it goes horizontally (`run` ≥ 0, not both 0): the elevation by
    /// its cosine and sine, with no arc tangent to take.
    ///
    /// ```
    /// use glam::DVec3;
    /// use orbifold::{Geometry, space::Space};
    /// use orbifold_trace::geodesic::Ray;
    /// let h2 = Space::new(Geometry::Hyperbolic);
    /// let ray = Ray::climbing(h2, DVec3::Z, DVec3::X, 0.5, 3.0, 4.0);
    /// assert!((ray.cos_elevation - 0.6).abs() < 1e-15 && (ray.sin_elevation - 0.8).abs() < 1e-15);
    /// ```
    pub fn climbing(
        space: Space,
        origin: DVec3,
        horizontal: DVec3,
        height: f64,
        run: f64,
        rise: f64,
    ) -> Ray {
        // `renormalized` scales them to a unit pair.
        Ray {
            origin,
            direction: horizontal,
            height,
            cos_elevation: run,
            sin_elevation: rise,
        }
        .renormalized(space)
    }

    /// A ray from the model point `z` at `height` with bearing `yaw` (radians, counter-clockwise
    /// from the model's +x direction) and elevation `pitch` (radians), as cameras use them
    /// (ARCHITECTURE.md §8).
    pub fn from_model(space: Space, z: Complex64, height: f64, yaw: f64, pitch: f64) -> Ray {
        let origin = space.to_ambient(z);
        let direction = space.model_tangent(z, Complex64::from_polar(1.0, yaw));
        Ray::new(space, origin, direction, height, pitch)
    }

    /// The ray with origin put back on the surface and direction made unit and tangent again, to
    /// stop rounding from accumulating over many bounces.
    pub fn renormalized(mut self, space: Space) -> Ray {
        self.origin = space.normalize_point(self.origin);
        let p = self.origin;
        let k = space.kappa();
        // Remove the component along p: ⟨p, p⟩ = κ for κ ≠ 0; for κ = 0 tangents have no z.
        let u = if k == 0.0 {
            DVec3::new(self.direction.x, self.direction.y, 0.0)
        } else {
            self.direction - p * (space.point_dot(p, self.direction) / k)
        };
        let norm = space.point_dot(u, u).max(0.0).sqrt();
        if norm > 0.0 {
            self.direction = u / norm;
        }
        // Both are at most 1 in size: no overflow for `hypot` to guard against, and it is slow.
        let speed = (self.cos_elevation * self.cos_elevation
            + self.sin_elevation * self.sin_elevation)
            .sqrt();
        if speed > 0.0 {
            self.cos_elevation /= speed;
            self.sin_elevation /= speed;
        }
        self
    }

    /// The horizontal position after horizontal distance `sigma`.
    #[inline]
    pub fn horizontal_at(&self, space: Space, sigma: f64) -> DVec3 {
        let (c, s) = space.cos_sin(sigma);
        self.origin * c + self.direction * s
    }

    /// The unit horizontal tangent after horizontal distance `sigma`: −κ S(σ)·p + C(σ)·u.
    #[inline]
    pub fn tangent_at(&self, space: Space, sigma: f64) -> DVec3 {
        let (c, s) = space.cos_sin(sigma);
        self.direction * c - self.origin * (space.kappa() * s)
    }

    /// The point (ambient horizontal position, height) at arc length `s`.
    #[inline]
    pub fn point_at(&self, space: Space, s: f64) -> (DVec3, f64) {
        (
            self.horizontal_at(space, s * self.cos_elevation),
            self.height + s * self.sin_elevation,
        )
    }

    /// The point at arc length `s` (ambient horizontal position, height) and the unit
    /// horizontal tangent there, with one C_κ, S_κ pair for both: what a mirror bounce needs
    /// ([`Ray::continued`]) besides where it is.
    #[inline]
    pub fn point_and_tangent_at(&self, space: Space, s: f64) -> (DVec3, DVec3, f64) {
        let (c, sn) = space.cos_sin(s * self.cos_elevation);
        (
            self.origin * c + self.direction * sn,
            self.direction * c - self.origin * (space.kappa() * sn),
            self.height + s * self.sin_elevation,
        )
    }

    /// The same geodesic started at arc length `s`, given its point and tangent there from
    /// [`Ray::point_and_tangent_at`]: [`Ray::advanced`] without computing them again.
    ///
    /// ```
    /// use orbifold_trace::geodesic::Ray;
    /// use orbifold::{Geometry, space::Space};
    /// use num_complex::Complex64;
    /// let h2 = Space::new(Geometry::Hyperbolic);
    /// let ray = Ray::from_model(h2, Complex64::new(0.1, 0.2), 0.5, 1.0, 0.3);
    /// let (point, tangent, _) = ray.point_and_tangent_at(h2, 1.7);
    /// let (a, b) = (ray.continued(h2, 1.7, point, tangent), ray.advanced(h2, 1.7));
    /// assert!((a.origin - b.origin).length() < 1e-15 && (a.direction - b.direction).length() < 1e-15);
    /// ```
    #[inline]
    pub fn continued(&self, space: Space, s: f64, point: DVec3, tangent: DVec3) -> Ray {
        Ray {
            origin: point,
            direction: tangent,
            height: self.height + s * self.sin_elevation,
            ..*self
        }
        .renormalized(space)
    }

    /// The same geodesic started at arc length `s`.
    pub fn advanced(&self, space: Space, s: f64) -> Ray {
        let (c, sn) = space.cos_sin(s * self.cos_elevation);
        Ray {
            origin: self.origin * c + self.direction * sn,
            direction: self.direction * c - self.origin * (space.kappa() * sn),
            height: self.height + s * self.sin_elevation,
            ..*self
        }
        .renormalized(space)
    }

    /// The ray reflected in a wall (a normalised linear form): the horizontal position and
    /// direction are reflected, the elevation is kept.
    pub fn reflected(&self, space: Space, wall: DVec3) -> Ray {
        Ray {
            origin: space.reflect(wall, self.origin),
            direction: space.reflect(wall, self.direction),
            ..*self
        }
    }

    /// The ray going on past a mirror or a portal it has reached
    /// ([`AnalyticRoom::passage`](crate::room::AnalyticRoom::passage)): reflected in the mirror,
    /// or moved by the portal's pairing onto the partner wall (and renormalised, so that rounding
    /// does not pile up over many crossings).
    #[inline]
    pub fn passed(&self, space: Space, passage: &crate::room::Passage) -> Ray {
        if passage.mirror.is_some() {
            return self.reflected(space, passage.mirror_form);
        }
        self.transformed(&passage.back, 0.0).renormalized(space)
    }

    /// The ray moved by an ambient isometry matrix and raised by `height`.
    #[inline]
    pub fn transformed(&self, matrix: &DMat3, height: f64) -> Ray {
        Ray {
            origin: *matrix * self.origin,
            direction: *matrix * self.direction,
            height: self.height + height,
            ..*self
        }
    }
}

/// The first horizontal distance σ > 0 (or σ = 0 when already on the line and moving across it)
/// at which a geodesic x(σ) = C(σ)p + S(σ)u crosses the line of the linear form ν from its
/// positive side, given a = ν·p (clamped to ≥ 0) and b = ν·u: the smallest root of
/// a C(σ) + b S(σ) = 0. `None` when the geodesic never reaches the line (κ ≤ 0).
#[inline]
pub fn line_crossing(space: Space, a: f64, b: f64) -> Option<f64> {
    let a = a.max(0.0);
    let k = space.kappa();
    if k > 0.0 {
        // a cos σ + b sin σ = 0 with σ = atan2(a, −b) ∈ [0, π]; every great circle meets the line.
        return Some(a.atan2(-b));
    }
    if b >= 0.0 {
        return None;
    }
    if k == 0.0 {
        return Some(a / -b);
    }
    // tanh σ = a/|b| < 1; ½ ln((|b| + a)/(|b| − a)) avoids atanh's cancellation near 1 no better,
    // so keep atanh but refuse ratios that round to 1 (the geodesic is asymptotic to the line).
    let ratio = a / -b;
    (ratio < 1.0).then(|| artanh(ratio))
}

/// artanh x for x in [0, 1), to a few ulps like `f64::atanh`, in two thirds of its time (every
/// stretch of a path between two mirrors of an H² room takes one): artanh x = ½ ln(1 + y) with
/// y = 2x/(1 − x), and ln(1 + y) = ln(u)·y/(u − 1) with u = 1 + y rounded, which cancels the
/// rounding of u (Goldberg's trick) with libm's `ln`, where `atanh` calls the slower `log1p`.
#[inline]
fn artanh(x: f64) -> f64 {
    let y = 2.0 * x / (1.0 - x);
    let u = 1.0 + y;
    let rounded = u - 1.0;
    0.5 * if rounded == 0.0 {
        y
    } else {
        u.ln() * (y / rounded)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use orbifold::Geometry;

    const GEOMETRIES: [Geometry; 3] = [
        Geometry::Spherical,
        Geometry::Euclidean,
        Geometry::Hyperbolic,
    ];

    proptest::proptest! {
        /// [`artanh`] is `f64::atanh` to a few ulps on [0, 1), from the tiny to the nearly 1.
        #[test]
        fn artanh_matches_atanh(exponent in -300.0f64..0.0, near_one in proptest::bool::ANY) {
            let t = 10f64.powf(exponent);
            let x = if near_one { 1.0 - t.max(f64::EPSILON) } else { t };
            let (ours, std) = (artanh(x), x.atanh());
            proptest::prop_assert!((ours - std).abs() <= 4.0 * f64::EPSILON * std, "{x}: {ours} {std}");
        }
    }

    #[test]
    fn artanh_is_exact_at_zero() {
        assert_eq!(artanh(0.0), 0.0);
    }

    #[test]
    fn line_crossing_solves_the_equation() {
        for g in GEOMETRIES {
            let space = Space::new(g);
            for &(a, b) in &[(0.3, -0.7), (0.0, -1.0), (0.5, -0.6), (0.2, 0.4)] {
                if let Some(s) = line_crossing(space, a, b) {
                    assert!(s >= 0.0);
                    let f = a * space.cos(s) + b * space.sin(s);
                    assert!(f.abs() < 1e-12, "{g:?} {a} {b} {s} {f}");
                }
            }
        }
    }

    #[test]
    fn advancing_twice_is_advancing_once() {
        for g in GEOMETRIES {
            let space = Space::new(g);
            let ray = Ray::from_model(space, Complex64::new(0.2, -0.1), 0.3, 1.0, 0.4);
            let (x, h) = ray.advanced(space, 0.7).point_at(space, 0.5);
            let (y, k) = ray.point_at(space, 1.2);
            assert!((x - y).length() < 1e-12 && (h - k).abs() < 1e-12, "{g:?}");
        }
    }
}
