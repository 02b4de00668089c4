//! Orthonormal shading frames. The BSDFs work in a local frame whose +z is the shading normal
//! ([`crate::materials::bsdf`]); these build that frame around a normal and carry vectors
//! between it and the world (the tangent space of the hit point).

use glam::DVec3;

/// A tangent and a bitangent completing the unit normal `n` to a right-handed orthonormal basis
/// (tangent × bitangent = n), by the branchless method of Duff et al., "Building an orthonormal
/// basis, revisited" (JCGT 2017). Continuous except where n.z changes sign.
///
/// ```
/// use glam::DVec3;
/// use orbifold_render::sampler::frame_from_normal;
///
/// let n = DVec3::new(1.0, 2.0, -2.0) / 3.0;
/// let (t, b) = frame_from_normal(n);
/// assert!(t.dot(n).abs() < 1e-12 && b.dot(n).abs() < 1e-12 && t.dot(b).abs() < 1e-12);
/// assert!((t.cross(b) - n).length() < 1e-12);
/// ```
pub fn frame_from_normal(n: DVec3) -> (DVec3, DVec3) {
    let sign = 1.0_f64.copysign(n.z);
    let a = -1.0 / (sign + n.z);
    let b = n.x * n.y * a;
    let tangent = DVec3::new(1.0 + sign * n.x * n.x * a, sign * b, -sign * n.x);
    let bitangent = DVec3::new(b, sign + n.y * n.y * a, -n.y);
    (tangent, bitangent)
}

/// The coordinates of the world vector `v` in the frame (tangent `t`, bitangent `b`, normal
/// `n`): (v·t, v·b, v·n).
///
/// ```
/// use glam::DVec3;
/// use orbifold_render::sampler::{frame_from_normal, to_local};
///
/// let n = DVec3::Y;
/// let (t, b) = frame_from_normal(n);
/// assert!((to_local(n, t, b, n) - DVec3::Z).length() < 1e-12);
/// ```
pub fn to_local(n: DVec3, t: DVec3, b: DVec3, v: DVec3) -> DVec3 {
    DVec3::new(v.dot(t), v.dot(b), v.dot(n))
}

/// The world vector with coordinates `v` in the frame (tangent `t`, bitangent `b`, normal `n`):
/// v.x·t + v.y·b + v.z·n.
///
/// ```
/// use glam::DVec3;
/// use orbifold_render::sampler::{frame_from_normal, to_world};
///
/// let n = DVec3::Y;
/// let (t, b) = frame_from_normal(n);
/// assert!((to_world(n, t, b, DVec3::Z) - n).length() < 1e-12);
/// ```
pub fn to_world(n: DVec3, t: DVec3, b: DVec3, v: DVec3) -> DVec3 {
    v.x * t + v.y * b + v.z * n
}

/// A right-handed orthonormal shading frame: local x = tangent, y = bitangent, z = normal.
///
/// ```
/// use glam::DVec3;
/// use orbifold_render::sampler::Frame;
///
/// let f = Frame::from_normal(DVec3::X);
/// let v = DVec3::new(0.3, -0.4, 0.5);
/// assert!((f.to_world(f.to_local(v)) - v).length() < 1e-12);
/// assert!((f.to_local(DVec3::X) - DVec3::Z).length() < 1e-12);
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Frame {
    tangent: DVec3,
    bitangent: DVec3,
    normal: DVec3,
}

impl Frame {
    /// The frame around the unit normal `n` (see [`frame_from_normal`]).
    ///
    /// ```
    /// use glam::DVec3;
    /// use orbifold_render::sampler::Frame;
    ///
    /// let f = Frame::from_normal(DVec3::Z);
    /// assert_eq!((f.tangent(), f.bitangent(), f.normal()), (DVec3::X, DVec3::Y, DVec3::Z));
    /// ```
    pub fn from_normal(n: DVec3) -> Frame {
        let (tangent, bitangent) = frame_from_normal(n);
        Frame {
            tangent,
            bitangent,
            normal: n,
        }
    }

    /// The local coordinates (v·t, v·b, v·n) of the world vector `v`.
    ///
    /// ```
    /// use glam::DVec3;
    /// use orbifold_render::sampler::Frame;
    ///
    /// let f = Frame::from_normal(DVec3::NEG_Z);
    /// assert!((f.to_local(DVec3::NEG_Z) - DVec3::Z).length() < 1e-12);
    /// ```
    pub fn to_local(&self, v: DVec3) -> DVec3 {
        to_local(self.normal, self.tangent, self.bitangent, v)
    }

    /// The world vector of the local coordinates `v`.
    ///
    /// ```
    /// use glam::DVec3;
    /// use orbifold_render::sampler::Frame;
    ///
    /// let f = Frame::from_normal(DVec3::NEG_Z);
    /// assert!((f.to_world(DVec3::Z) - DVec3::NEG_Z).length() < 1e-12);
    /// ```
    pub fn to_world(&self, v: DVec3) -> DVec3 {
        to_world(self.normal, self.tangent, self.bitangent, v)
    }

    /// The normal (local +z).
    ///
    /// ```
    /// use glam::DVec3;
    /// use orbifold_render::sampler::Frame;
    ///
    /// assert_eq!(Frame::from_normal(DVec3::Y).normal(), DVec3::Y);
    /// ```
    pub fn normal(&self) -> DVec3 {
        self.normal
    }

    /// The tangent (local +x).
    ///
    /// ```
    /// use glam::DVec3;
    /// use orbifold_render::sampler::Frame;
    ///
    /// let f = Frame::from_normal(DVec3::Y);
    /// assert!(f.tangent().dot(DVec3::Y).abs() < 1e-12);
    /// ```
    pub fn tangent(&self) -> DVec3 {
        self.tangent
    }

    /// The bitangent (local +y) = normal × tangent.
    ///
    /// ```
    /// use glam::DVec3;
    /// use orbifold_render::sampler::Frame;
    ///
    /// let f = Frame::from_normal(DVec3::Y);
    /// assert!((f.normal().cross(f.tangent()) - f.bitangent()).length() < 1e-12);
    /// ```
    pub fn bitangent(&self) -> DVec3 {
        self.bitangent
    }
}
