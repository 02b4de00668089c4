//! The three constant-curvature planes, written once for κ ∈ {+1, 0, −1} (ARCHITECTURE.md §3).
//!
//! Points have model coordinates z ∈ ℂ (stereographic plane, Euclidean plane, Poincaré disk,
//! metric λ(z)|dz| with λ = 2/(1 + κ|z|²)) and ambient coordinates
//! p = (2x, 2y, 1 − κ|z|²)/(1 + κ|z|²) ∈ ℝ³. A geodesic line (a wall) is the zero set of a linear
//! form ν on ambient coordinates, normalised so that ν₁² + ν₂² + κν₃² = 1; then S_κ(d) = ν·p is
//! the signed distance d from the wall to p, positive on the wall's inner side.

use glam::{DMat3, DVec3};
use num_complex::Complex64;

use crate::euler::Geometry;

/// A plane of constant curvature κ ∈ {+1, 0, −1}.
///
/// ```
/// use orbifold::space::Space;
/// use orbifold::Geometry;
/// use num_complex::Complex64;
/// let h = Space::new(Geometry::Hyperbolic);
/// // The intrinsic distance from 0 to z is 2·artanh|z| in the Poincaré disk.
/// let z = Complex64::new(0.5, 0.0);
/// assert!((h.distance(Complex64::new(0.0, 0.0), z) - 2.0 * 0.5f64.atanh()).abs() < 1e-15);
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Space {
    kappa: f64,
}

/// A geodesic drawn in model coordinates: a circle, or a straight line.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum ModelGeodesic {
    /// The circle with this centre and radius.
    Circle {
        /// Centre in model coordinates.
        centre: Complex64,
        /// Radius in model coordinates.
        radius: f64,
    },
    /// The straight line through `point` with unit direction `direction`.
    Line {
        /// A point of the line (the one closest to the origin).
        point: Complex64,
        /// A unit direction.
        direction: Complex64,
    },
}

impl Space {
    /// The plane of the given geometry.
    pub fn new(geometry: Geometry) -> Self {
        Space {
            kappa: f64::from(geometry.curvature()),
        }
    }

    /// The curvature κ.
    #[inline]
    pub fn kappa(&self) -> f64 {
        self.kappa
    }

    /// The geometry.
    pub fn geometry(&self) -> Geometry {
        match self.kappa {
            k if k > 0.0 => Geometry::Spherical,
            k if k < 0.0 => Geometry::Hyperbolic,
            _ => Geometry::Euclidean,
        }
    }

    /// C_κ(s): cos s, 1, cosh s (the latter as [`Space::cos_sin`] computes it).
    #[inline]
    pub fn cos(&self, s: f64) -> f64 {
        match self.kappa {
            k if k > 0.0 => s.cos(),
            k if k < 0.0 => self.cos_sin(s).0,
            _ => 1.0,
        }
    }

    /// S_κ(s): sin s, s, sinh s (the latter as [`Space::cos_sin`] computes it, in half the time
    /// of libm's `sinh`).
    #[inline]
    pub fn sin(&self, s: f64) -> f64 {
        match self.kappa {
            k if k > 0.0 => s.sin(),
            k if k < 0.0 => self.cos_sin(s).1,
            _ => s,
        }
    }

    /// (C_κ(s), S_κ(s)) at once: cheaper than libm's functions apart (one `sin_cos`; one `exp`
    /// for both hyperbolic functions, or their Taylor series below |s| = ½), as accurate to a
    /// few ulps.
    ///
    /// ```
    /// use orbifold::{Geometry, space::Space};
    /// let h2 = Space::new(Geometry::Hyperbolic);
    /// let (c, s) = h2.cos_sin(0.7);
    /// assert!((c - 0.7f64.cosh()).abs() < 1e-15 && (s - 0.7f64.sinh()).abs() < 1e-15);
    /// ```
    #[inline]
    pub fn cos_sin(&self, s: f64) -> (f64, f64) {
        match self.kappa {
            k if k > 0.0 => {
                let (sin, cos) = s.sin_cos();
                (cos, sin)
            }
            k if k < 0.0 => {
                let a = s.abs();
                if a > 700.0 {
                    return (s.cosh(), s.sinh()); // e^s overflows: let each saturate alone
                }
                if a >= 0.5 {
                    // Far from 0, e^|s| itself (libm's `exp`, about half the cost of `exp_m1`):
                    // sinh = ½(e − 1/e) loses under 1.4 ulp to the subtraction for |s| ≥ ½.
                    let e = a.exp();
                    let inv = 1.0 / e;
                    return (0.5 * (e + inv), (0.5 * (e - inv)).copysign(s));
                }
                // Near 0, their Taylor series to s¹⁵ (the first term left out is below 10⁻¹⁹
                // of the sum for |s| < ½): accurate to the last bit or so, with no division and
                // no call (`exp_m1` and a division took twice as long).
                let z = s * s;
                let sinh = s + s * z * SINH_SERIES.iter().rev().fold(0.0, |acc, c| acc * z + c);
                let cosh = 1.0 + z * COSH_SERIES.iter().rev().fold(0.0, |acc, c| acc * z + c);
                (cosh, sinh)
            }
            _ => (1.0, s),
        }
    }

    /// T_κ(s): tan s, s, tanh s.
    #[inline]
    pub fn tan(&self, s: f64) -> f64 {
        match self.kappa {
            k if k > 0.0 => s.tan(),
            k if k < 0.0 => s.tanh(),
            _ => s,
        }
    }

    /// The inverse of T_κ: atan, identity, artanh.
    #[inline]
    pub fn atan(&self, x: f64) -> f64 {
        match self.kappa {
            k if k > 0.0 => x.atan(),
            k if k < 0.0 => x.atanh(),
            _ => x,
        }
    }

    /// The inverse of S_κ: asin, identity, arsinh.
    #[inline]
    pub fn asin(&self, x: f64) -> f64 {
        match self.kappa {
            k if k > 0.0 => x.clamp(-1.0, 1.0).asin(),
            k if k < 0.0 => arsinh(x),
            _ => x,
        }
    }

    /// The conformal factor λ(z) = 2/(1 + κ|z|²).
    #[inline]
    pub fn conformal_factor(&self, z: Complex64) -> f64 {
        2.0 / (1.0 + self.kappa * z.norm_sqr())
    }

    /// Ambient coordinates of a model point.
    #[inline]
    pub fn to_ambient(&self, z: Complex64) -> DVec3 {
        let r2 = z.norm_sqr();
        let d = 1.0 + self.kappa * r2;
        DVec3::new(2.0 * z.re / d, 2.0 * z.im / d, (1.0 - self.kappa * r2) / d)
    }

    /// Model coordinates of an ambient point: z = (p₁ + i p₂)/(1 + p₃). For a null direction of
    /// the hyperboloid (an ideal point) pass [`Space::ideal_to_model`] instead.
    #[inline]
    pub fn to_model(&self, p: DVec3) -> Complex64 {
        Complex64::new(p.x, p.y) / (1.0 + p.z)
    }

    /// The ideal point (on the unit circle) in the direction of a future-pointing null vector.
    pub fn ideal_to_model(&self, q: DVec3) -> Complex64 {
        let z = Complex64::new(q.x, q.y);
        z / z.norm()
    }

    /// The bilinear form on ambient points: p₁q₁ + p₂q₂ + κp₃q₃ (the dot product on the sphere,
    /// the Minkowski form on the hyperboloid).
    #[inline]
    pub fn point_dot(&self, p: DVec3, q: DVec3) -> f64 {
        p.x * q.x + p.y * q.y + self.kappa * p.z * q.z
    }

    /// The dual form on walls (linear forms): ν₁μ₁ + ν₂μ₂ + κν₃μ₃. For two walls with inner
    /// normals that meet, the inner angle α between them has cos α = −dual_dot(ν, μ); for
    /// ultraparallel hyperbolic walls −dual_dot = cosh(distance).
    #[inline]
    pub fn wall_dot(&self, nu: DVec3, mu: DVec3) -> f64 {
        nu.x * mu.x + nu.y * mu.y + self.kappa * nu.z * mu.z
    }

    /// Scales a linear form so that ν₁² + ν₂² + κν₃² = 1.
    #[inline]
    pub fn normalize_wall(&self, nu: DVec3) -> DVec3 {
        nu / self.wall_dot(nu, nu).sqrt()
    }

    /// The intrinsic distance between two model points: 2·atan_κ|(w − z)/(1 + κ z̄ w)|.
    pub fn distance(&self, z: Complex64, w: Complex64) -> f64 {
        let q = (w - z) / (1.0 + self.kappa * z.conj() * w);
        2.0 * self.atan(q.norm())
    }

    /// The signed distance from a wall to a model point (positive on the inner side).
    pub fn signed_distance(&self, nu: DVec3, z: Complex64) -> f64 {
        self.asin(nu.dot(self.to_ambient(z)))
    }

    /// The wall as drawn in model coordinates: −κν₃|z|² + 2(ν₁x + ν₂y) + ν₃ = 0. The wall must be
    /// normalised ([`Space::normalize_wall`]); isometries keep it so.
    pub fn model_geodesic(&self, nu: DVec3) -> ModelGeodesic {
        let a = -self.kappa * nu.z;
        let b = Complex64::new(nu.x, nu.y);
        if a.abs() <= 1e-12 * b.norm() {
            // 2 Re(b̄ z) + ν₃ = 0: the line with normal b̂ at signed offset −ν₃/(2|b|).
            let n = b / b.norm();
            ModelGeodesic::Line {
                point: -n * (nu.z / (2.0 * b.norm())),
                direction: Complex64::new(-n.im, n.re),
            }
        } else {
            // |z|² + 2 Re(b̄ z)/a + ν₃/a = 0: centre −b/a, radius² = |b|²/a² − ν₃/a, which for a
            // normalised wall (|b|² + κν₃² = 1) is 1/ν₃²: no cancellation for far walls.
            let centre = -b / a;
            let radius = 1.0 / nu.z.abs();
            ModelGeodesic::Circle { centre, radius }
        }
    }

    /// Scales a nonzero vector onto the model surface: p/|p| on the sphere, p/√(z² − x² − y²) on
    /// the hyperboloid (for a future-pointing timelike vector), p/p₃ in the plane w = 1. This is
    /// the central projection that makes straight segments of ℝ³ into geodesics, so that
    /// `normalize_point(Σ wᵢ pᵢ)` is an intrinsically flat triangle (ARCHITECTURE.md §7).
    #[inline]
    pub fn normalize_point(&self, p: DVec3) -> DVec3 {
        if self.kappa == 0.0 {
            p / p.z
        } else {
            p / (self.kappa * self.point_dot(p, p)).sqrt()
        }
    }

    /// The intrinsic distance between two ambient points, 2·asin_κ(c/2) with c the chord
    /// √⟨p − q, p − q⟩: accurate for near and far points alike (no acos of a number near 1).
    ///
    /// ```
    /// use orbifold::space::Space;
    /// use orbifold::Geometry;
    /// use num_complex::Complex64;
    /// let s = Space::new(Geometry::Spherical);
    /// let (z, w) = (Complex64::new(0.1, 0.2), Complex64::new(-0.4, 0.3));
    /// let d = s.ambient_distance(s.to_ambient(z), s.to_ambient(w));
    /// assert!((d - s.distance(z, w)).abs() < 1e-14);
    /// ```
    #[inline]
    pub fn ambient_distance(&self, p: DVec3, q: DVec3) -> f64 {
        let d = p - q;
        let chord = self.point_dot(d, d).max(0.0).sqrt();
        2.0 * self.asin(0.5 * chord)
    }

    /// The point at fraction `t` of the intrinsic length along the geodesic from `p` to `q`:
    /// (S_κ((1 − t)d)·p + S_κ(t d)·q)/S_κ(d). A linear combination of `p` and `q`, so it lies
    /// exactly on every wall through both. `p` and `q` must not be antipodal.
    #[inline]
    pub fn interpolate(&self, p: DVec3, q: DVec3, t: f64) -> DVec3 {
        let d = self.ambient_distance(p, q);
        let s = self.sin(d);
        if d < 1e-9 || s.abs() < 1e-300 {
            return self.normalize_point(p * (1.0 - t) + q * t);
        }
        (p * self.sin((1.0 - t) * d) + q * self.sin(t * d)) / s
    }

    /// The tangent vector at `p` of the geodesic towards `q`, with length the distance from `p`
    /// to `q` (zero when they coincide). Its inner product with another such vector is
    /// [`Space::point_dot`].
    #[inline]
    pub fn log(&self, p: DVec3, q: DVec3) -> DVec3 {
        let d = self.ambient_distance(p, q);
        let t = q - p * self.cos(d);
        let n = self.point_dot(t, t).max(0.0).sqrt();
        if n == 0.0 { DVec3::ZERO } else { t * (d / n) }
    }

    /// The point reached from `p` by the tangent vector `v`: C_κ(|v|)·p + S_κ(|v|)·v/|v|.
    #[inline]
    pub fn exp(&self, p: DVec3, v: DVec3) -> DVec3 {
        let n = self.point_dot(v, v).max(0.0).sqrt();
        if n == 0.0 {
            return p;
        }
        p * self.cos(n) + v * (self.sin(n) / n)
    }

    /// The intrinsic area of the geodesic triangle with ambient corners `p`, `q`, `r`: for κ ≠ 0
    /// from tan(A/2) = |det(p, q, r)| / (1 + C(a) + C(b) + C(c)) with C(a) = κ⟨p, q⟩ (Van
    /// Oosterom–Strackee, and its hyperbolic twin), for κ = 0 half the cross product. Exact for
    /// tiny triangles, where the angle excess would cancel.
    pub fn triangle_area(&self, p: DVec3, q: DVec3, r: DVec3) -> f64 {
        let det = DMat3::from_cols(p, q, r).determinant().abs();
        if self.kappa == 0.0 {
            return 0.5 * det;
        }
        let c = |a: DVec3, b: DVec3| self.kappa * self.point_dot(a, b);
        2.0 * det.atan2(1.0 + c(p, q) + c(q, r) + c(r, p))
    }

    /// The unit ambient tangent vector at the model point `z` that points in the model direction
    /// `direction` (any nonzero complex number; the model is conformal, so bearings measured in
    /// the model are true bearings).
    ///
    /// ```
    /// use orbifold::space::Space;
    /// use orbifold::Geometry;
    /// use num_complex::Complex64;
    /// let h = Space::new(Geometry::Hyperbolic);
    /// let z = Complex64::new(0.3, 0.4);
    /// let v = h.model_tangent(z, Complex64::new(0.0, 1.0));
    /// let p = h.to_ambient(z);
    /// assert!(h.point_dot(p, v).abs() < 1e-15 && (h.point_dot(v, v) - 1.0).abs() < 1e-15);
    /// ```
    pub fn model_tangent(&self, z: Complex64, direction: Complex64) -> DVec3 {
        // The differential of z ↦ p = (2x, 2y, 1 − κ|z|²)/D with D = 1 + κ|z|².
        let (x, y, k) = (z.re, z.im, self.kappa);
        let d = 1.0 + k * z.norm_sqr();
        let dx = DVec3::new(
            2.0 / d - 4.0 * k * x * x / (d * d),
            -4.0 * k * x * y / (d * d),
            -4.0 * k * x / (d * d),
        );
        let dy = DVec3::new(
            -4.0 * k * x * y / (d * d),
            2.0 / d - 4.0 * k * y * y / (d * d),
            -4.0 * k * y / (d * d),
        );
        let v = dx * direction.re + dy * direction.im;
        v / self.point_dot(v, v).sqrt()
    }

    /// Parallel transport of the tangent vector `v` at `p` along the geodesic to `q`:
    /// v − κ⟨q, v⟩/(1 + κ⟨p, q⟩)·(p + q), which is the identity for κ = 0. It keeps
    /// [`Space::point_dot`] and carries the geodesic's own tangent at `p` to its tangent at `q`.
    /// `p` and `q` must not be antipodal.
    ///
    /// ```
    /// use orbifold::space::Space;
    /// use orbifold::Geometry;
    /// use num_complex::Complex64;
    /// let s = Space::new(Geometry::Spherical);
    /// let (p, q) = (s.to_ambient(Complex64::new(0.1, 0.2)), s.to_ambient(Complex64::new(-0.4, 0.3)));
    /// // The direction from p to q arrives as the direction away from p.
    /// let t = s.transport(p, q, s.log(p, q));
    /// assert!((t + s.log(q, p)).length() < 1e-14);
    /// ```
    #[inline]
    pub fn transport(&self, p: DVec3, q: DVec3, v: DVec3) -> DVec3 {
        if self.kappa == 0.0 {
            return v;
        }
        let k = self.kappa;
        v - (p + q) * (k * self.point_dot(q, v) / (1.0 + k * self.point_dot(p, q)))
    }

    /// The tangent vector at `p` turned a quarter turn counter-clockwise (seen from above, the
    /// model's orientation): J v = G(p × v) with G = diag(1, 1, κ), for every κ.
    #[inline]
    pub fn quarter_turn(&self, p: DVec3, v: DVec3) -> DVec3 {
        let c = p.cross(v);
        DVec3::new(c.x, c.y, self.kappa * c.z)
    }

    /// An orthonormal frame (e₁, e₂ = J e₁) of the tangent plane at the ambient point `x`: e₁ is
    /// the ambient x axis projected onto the plane (the y axis where that is too short). At the
    /// model's origin, and everywhere in the Euclidean plane, e₁ is the model's +x direction.
    /// Shading takes any frame; texture coordinates in the logarithm map at a room's centre use
    /// this one, in the renderer and in mesh exports alike.
    ///
    /// ```
    /// use glam::DVec3;
    /// use orbifold::{Geometry, space::Space};
    /// let h2 = Space::new(Geometry::Hyperbolic);
    /// let x = h2.exp(DVec3::Z, DVec3::new(0.3, -1.2, 0.0));
    /// let [e1, e2] = h2.tangent_frame(x);
    /// assert!((h2.point_dot(e1, e1) - 1.0).abs() < 1e-12 && h2.point_dot(e1, e2).abs() < 1e-12);
    /// assert!(h2.point_dot(e1, x).abs() < 1e-12);
    /// ```
    pub fn tangent_frame(&self, x: DVec3) -> [DVec3; 2] {
        let k = self.kappa;
        let tangent = |a: DVec3| {
            if k == 0.0 {
                DVec3::new(a.x, a.y, 0.0)
            } else {
                a - x * (k * self.point_dot(x, a))
            }
        };
        let mut t = tangent(DVec3::X);
        if self.point_dot(t, t) < 0.25 {
            t = tangent(DVec3::Y);
        }
        let e1 = t / self.point_dot(t, t).sqrt();
        [e1, self.quarter_turn(x, e1)]
    }

    /// The reflection of an ambient point or tangent vector in a wall ν (normalised so that
    /// ν₁² + ν₂² + κν₃² = 1): x ↦ x − 2(ν·x)·Gν. Linear, so it maps points, tangent vectors and
    /// geodesics alike.
    #[inline]
    pub fn reflect(&self, nu: DVec3, x: DVec3) -> DVec3 {
        x - 2.0 * nu.dot(x) * DVec3::new(nu.x, nu.y, self.kappa * nu.z)
    }

    /// Angle-like coordinate of a point `x` on the geodesic through `p` with unit tangent `t`:
    /// the σ with x = C_κ(σ)·p + S_κ(σ)·t (for κ = +1 in (−π, π]).
    #[inline]
    pub fn geodesic_parameter(&self, p: DVec3, t: DVec3, x: DVec3) -> f64 {
        let along = self.point_dot(x, t);
        match self.kappa {
            k if k > 0.0 => along.atan2(x.dot(p)),
            k if k < 0.0 => arsinh(along),
            _ => along - self.point_dot(p, t),
        }
    }

    /// The unit tangent direction, in model coordinates, of the geodesic from `z` towards `w`
    /// (towards an ideal point `w` too).
    pub fn direction(&self, z: Complex64, w: Complex64) -> Complex64 {
        // Move z to the origin by the isometry m(ζ) = (ζ − z)/(1 + κ z̄ ζ), whose derivative at z is
        // real and positive; there the geodesic is the ray towards m(w).
        let image = (w - z) / (1.0 + self.kappa * z.conj() * w);
        image / image.norm()
    }
}

/// (sinh s − s)/s³ = Σ zᵏ/(2k + 3)! for k = 0…6, z = s².
const SINH_SERIES: [f64; 7] = [
    1.0 / 6.0,
    1.0 / 120.0,
    1.0 / 5_040.0,
    1.0 / 362_880.0,
    1.0 / 39_916_800.0,
    1.0 / 6_227_020_800.0,
    1.0 / 1_307_674_368_000.0,
];

/// (cosh s − 1)/s² = Σ zᵏ/(2k + 2)! for k = 0…6, z = s².
const COSH_SERIES: [f64; 7] = [
    1.0 / 2.0,
    1.0 / 24.0,
    1.0 / 720.0,
    1.0 / 40_320.0,
    1.0 / 3_628_800.0,
    1.0 / 479_001_600.0,
    1.0 / 87_178_291_200.0,
];

/// arsinh x = sign(x)·ln(1 + y), y = |x| + x²/(1 + √(1 + x²)), to within an ulp or two like
/// `f64::asinh`, which takes a `hypot` on top: distances in H² are on every ray's path, and the
/// `hypot` is a library call. ln(1 + y) is ln(u)·y/(u − 1) with u = 1 + y rounded, which cancels
/// the rounding of u (Goldberg's trick), with libm's `ln` rather than the slower `ln_1p`. Past
/// 1e150, where x² would overflow, ln 2|x|.
#[inline]
fn arsinh(x: f64) -> f64 {
    let a = x.abs();
    let magnitude = if a < 1e150 {
        let y = a + a * a / (1.0 + (1.0 + a * a).sqrt());
        let u = 1.0 + y;
        let rounded = u - 1.0;
        if rounded == 0.0 {
            y
        } else {
            u.ln() * (y / rounded)
        }
    } else {
        a.ln() + std::f64::consts::LN_2
    };
    magnitude.copysign(x)
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    proptest! {
        /// [`arsinh`] is `f64::asinh` to a few ulps, from the tiny to the huge.
        #[test]
        fn arsinh_matches_asinh(exponent in -300.0f64..300.0, negative in any::<bool>()) {
            let x = 10f64.powf(exponent) * if negative { -1.0 } else { 1.0 };
            let (ours, std) = (arsinh(x), x.asinh());
            prop_assert!((ours - std).abs() <= 4.0 * f64::EPSILON * std.abs(), "{x}: {ours} {std}");
        }

        /// `cos_sin` (and so `cos` and `sin`) is libm's cos and sin, 1 and s, or cosh and sinh,
        /// to a few ulps (relative, and absolute near 0).
        #[test]
        fn cos_sin_matches_cos_and_sin(s in -750.0f64..750.0, g in 0usize..3) {
            let space = Space::new([Geometry::Spherical, Geometry::Euclidean, Geometry::Hyperbolic][g]);
            let s = if g == 2 { s } else { s / 100.0 };
            let (c, sn) = space.cos_sin(s);
            let (cos, sin) = [(s.cos(), s.sin()), (1.0, s), (s.cosh(), s.sinh())][g];
            let close = |a: f64, b: f64| {
                a == b || (a - b).abs() <= 4.0 * f64::EPSILON * b.abs().max(1e-300) + 1e-300
            };
            prop_assert!(close(c, cos), "cos {s}: {c} vs {cos}");
            prop_assert!(close(sn, sin), "sin {s}: {sn} vs {sin}");
            prop_assert!(close(space.cos(s), cos) && close(space.sin(s), sin), "{s}");
        }
    }

    #[test]
    fn cos_sin_is_accurate_on_both_sides_of_its_switch_to_exp() {
        // Densely through |s| = ½, where sinh's subtraction of e^−|s| is worst, and beyond.
        let h2 = Space::new(Geometry::Hyperbolic);
        let mut worst: f64 = 0.0;
        for i in 0..400_000 {
            let s = 0.4 + f64::from(i) * 1e-5;
            for s in [s, -s, 0.5f64.next_down(), 0.5] {
                let (c, sn) = h2.cos_sin(s);
                worst = worst
                    .max((c - s.cosh()).abs() / s.cosh())
                    .max((sn - s.sinh()).abs() / s.sinh().abs());
            }
        }
        assert!(worst <= 4.0 * f64::EPSILON, "{}", worst / f64::EPSILON);
    }

    #[test]
    fn cos_sin_is_accurate_by_its_series_below_a_half() {
        let h2 = Space::new(Geometry::Hyperbolic);
        let mut worst: f64 = 0.0;
        for i in 0..200_000 {
            // Logarithmically from 10⁻¹² to ½.
            let s = 0.5 * 10f64.powf(-12.0 * f64::from(i) / 200_000.0);
            for s in [s, -s] {
                let (c, sn) = h2.cos_sin(s);
                worst = worst
                    .max((c - s.cosh()).abs() / s.cosh())
                    .max((sn - s.sinh()).abs() / s.sinh().abs());
            }
        }
        assert!(worst <= 3.0 * f64::EPSILON, "{}", worst / f64::EPSILON);
    }

    #[test]
    fn cos_sin_is_exact_at_zero_and_small() {
        let h2 = Space::new(Geometry::Hyperbolic);
        assert_eq!(h2.cos_sin(0.0), (1.0, 0.0));
        let (_, s) = h2.cos_sin(1e-10);
        assert!((s - 1e-10).abs() < 1e-25);
        assert_eq!(h2.cos_sin(1e4), (f64::INFINITY, f64::INFINITY));
    }

    proptest! {
        /// Parallel transport keeps inner products, lands in the tangent space at the far end
        /// and is undone by transporting back, in every geometry.
        #[test]
        fn transport_is_an_isometry_between_tangent_spaces(
            g in 0usize..3,
            z in (-0.8f64..0.8, -0.8f64..0.8),
            w in (-0.8f64..0.8, -0.8f64..0.8),
            a in (-2.0f64..2.0, -2.0f64..2.0),
            b in (-2.0f64..2.0, -2.0f64..2.0),
        ) {
            let space = Space::new([Geometry::Spherical, Geometry::Euclidean, Geometry::Hyperbolic][g]);
            // Inside the Poincaré disk with room to spare (|z| < 0.85: at most 2.5 from the
            // centre), where the ambient coordinates keep their precision.
            let scale = if g == 2 { 0.75 } else { 1.0 };
            let (z, w) = (
                Complex64::new(z.0, z.1) * scale,
                Complex64::new(w.0, w.1) * scale,
            );
            let (p, q) = (space.to_ambient(z), space.to_ambient(w));
            let tangent = |c: (f64, f64)| {
                space.model_tangent(z, Complex64::new(1.0, 0.0)) * c.0
                    + space.model_tangent(z, Complex64::new(0.0, 1.0)) * c.1
            };
            let (u, v) = (tangent(a), tangent(b));
            let (tu, tv) = (space.transport(p, q, u), space.transport(p, q, v));
            let scale = 1.0 + u.length() * v.length();
            prop_assert!((space.point_dot(tu, tv) - space.point_dot(u, v)).abs() < 1e-9 * scale);
            prop_assert!(space.point_dot(q, tu).abs() < 1e-9 * (1.0 + u.length()) || g == 1);
            prop_assert!((space.transport(q, p, tu) - u).length() < 1e-9 * (1.0 + u.length()));
            // The geodesic's own direction is carried along it.
            let log = space.log(p, q);
            let there = space.transport(p, q, log);
            prop_assert!((there + space.log(q, p)).length() < 1e-9 * (1.0 + log.length()));
        }
    }
}
