//! Isometries of the three planes as 3×3 linear maps of ambient coordinates (ARCHITECTURE.md §3):
//! rotations, translations, reflections and their compositions, written once for every κ.

use glam::{DMat3, DVec3};
use num_complex::Complex64;

use crate::space::Space;

/// An isometry of a constant-curvature plane, possibly orientation-reversing, acting linearly on
/// ambient coordinates: points p ↦ M p, walls (linear forms) ν ↦ ν M⁻¹.
///
/// ```
/// use orbifold::isometry::Isometry;
/// use orbifold::space::Space;
/// use orbifold::Geometry;
/// use num_complex::Complex64;
/// let h = Space::new(Geometry::Hyperbolic);
/// let w = Complex64::new(0.3, -0.2);
/// let t = Isometry::translation(h, w);
/// assert!((t.apply(Complex64::new(0.0, 0.0)) - w).norm() < 1e-15);
/// let back = t.inverse().apply(w);
/// assert!(back.norm() < 1e-15);
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Isometry {
    space: Space,
    matrix: DMat3,
}

impl Isometry {
    /// The identity.
    pub fn identity(space: Space) -> Self {
        Isometry {
            space,
            matrix: DMat3::IDENTITY,
        }
    }

    /// The isometry with this ambient matrix, which must preserve the form ⟨·,·⟩ of `space`
    /// (a product of the other constructors, or a side pairing).
    ///
    /// ```
    /// use orbifold::isometry::Isometry;
    /// use orbifold::{space::Space, Geometry};
    /// let s = Space::new(Geometry::Spherical);
    /// let r = Isometry::rotation(s, 0.5);
    /// assert_eq!(Isometry::from_matrix(s, r.matrix()), r);
    /// ```
    pub fn from_matrix(space: Space, matrix: glam::DMat3) -> Self {
        Isometry { space, matrix }
    }

    /// The rotation by `angle` radians (counter-clockwise) about the origin.
    pub fn rotation(space: Space, angle: f64) -> Self {
        let (s, c) = angle.sin_cos();
        Isometry {
            space,
            matrix: DMat3::from_cols(DVec3::new(c, s, 0.0), DVec3::new(-s, c, 0.0), DVec3::Z),
        }
    }

    /// The reflection in the real axis of the model, z ↦ z̄.
    pub fn conjugation(space: Space) -> Self {
        Isometry {
            space,
            matrix: DMat3::from_diagonal(DVec3::new(1.0, -1.0, 1.0)),
        }
    }

    /// The translation along the geodesic through the origin that takes the origin to `w`.
    pub fn translation(space: Space, w: Complex64) -> Self {
        let r = w.norm();
        if r == 0.0 {
            return Isometry::identity(space);
        }
        Isometry::translation_by(space, 2.0 * space.atan(r), w / r)
    }

    /// The translation by intrinsic distance `distance` in the unit model direction `direction`
    /// from the origin. Prefer it to [`Isometry::translation`] when the distance is known: far
    /// from the origin a model point no longer pins down its distance to full precision.
    pub fn translation_by(space: Space, distance: f64, direction: Complex64) -> Self {
        let (u1, u2) = (direction.re, direction.im);
        let (c, s, k) = (space.cos(distance), space.sin(distance), space.kappa());
        // O ↦ (S u, C); the unit vector (u, 0) ↦ (C u, −κ S); the perpendicular direction is fixed.
        let matrix = DMat3::from_cols(
            DVec3::new(1.0 + (c - 1.0) * u1 * u1, (c - 1.0) * u1 * u2, -k * s * u1),
            DVec3::new((c - 1.0) * u1 * u2, 1.0 + (c - 1.0) * u2 * u2, -k * s * u2),
            DVec3::new(s * u1, s * u2, c),
        );
        Isometry { space, matrix }
    }

    /// The ambient matrix.
    pub fn matrix(&self) -> DMat3 {
        self.matrix
    }

    /// First `other`, then `self`.
    pub fn compose(&self, other: &Isometry) -> Isometry {
        Isometry {
            space: self.space,
            matrix: self.matrix * other.matrix,
        }
    }

    /// The inverse isometry. For κ = ±1 the map preserves the form G = diag(1, 1, κ), so
    /// M⁻¹ = G Mᵀ G exactly, with no rounding from a general inverse.
    pub fn inverse(&self) -> Isometry {
        let k = self.space.kappa();
        let matrix = if k == 0.0 {
            self.matrix.inverse()
        } else {
            let g = DMat3::from_diagonal(DVec3::new(1.0, 1.0, k));
            g * self.matrix.transpose() * g
        };
        Isometry {
            space: self.space,
            matrix,
        }
    }

    /// Whether the isometry reverses orientation (a reflection or glide).
    pub fn reverses_orientation(&self) -> bool {
        self.matrix.determinant() < 0.0
    }

    /// The image of an ambient point (or of an ideal point's null direction).
    pub fn apply_ambient(&self, p: DVec3) -> DVec3 {
        self.matrix * p
    }

    /// The image of a model point.
    pub fn apply(&self, z: Complex64) -> Complex64 {
        self.space
            .to_model(self.apply_ambient(self.space.to_ambient(z)))
    }

    /// The image of an ideal point of the hyperbolic plane (on the unit circle).
    pub fn apply_ideal(&self, z: Complex64) -> Complex64 {
        let q = self.apply_ambient(DVec3::new(z.re, z.im, 1.0));
        self.space.ideal_to_model(q)
    }

    /// The image of a wall (a linear form on ambient coordinates): ν ↦ ν M⁻¹. An isometry keeps a
    /// normalised wall normalised; renormalising would only add error, because for a far wall
    /// ν₁² + ν₂² + κν₃² cancels large terms.
    pub fn apply_wall(&self, nu: DVec3) -> DVec3 {
        self.inverse().matrix.transpose() * nu
    }
}
