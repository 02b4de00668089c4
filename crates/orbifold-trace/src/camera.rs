//! Cameras in the tangent space at the eye (ARCHITECTURE.md §8): a pinhole camera and an
//! equirectangular panorama.
//!
//! The eye's orthonormal frame is (model +x, model +y, up); the model is conformal, so these
//! are true directions. Pinhole: pixel (i, j) of a W×H image looks along
//! normalise(forward + a·right + b·up) with a = (2(i+½)/W − 1)·tan(φ/2)·W/H,
//! b = (1 − 2(j+½)/H)·tan(φ/2), forward = (cos pitch cos yaw, cos pitch sin yaw, sin pitch),
//! right = normalise(forward × up_world), up = right × forward. Panorama: column i is the bearing
//! yaw + π − 2π(i+½)/W (so the middle column looks along `yaw`, left to right turning clockwise
//! as in a photograph), row j the elevation π/2 − π(j+½)/H.

use std::f64::consts::PI;

use glam::DVec3;
use num_complex::Complex64;
use orbifold::space::Space;
use orbifold_scene::{Camera as CameraSettings, CameraKind};

use crate::footprint::Footprint;
use crate::geodesic::Ray;

/// A camera placed in a plane of curvature κ.
///
/// ```
/// use orbifold::{Geometry, space::Space};
/// use orbifold_trace::camera::Camera;
/// use orbifold_scene::Camera as Settings;
/// let settings = Settings { pitch: -20.0, ..Settings::default() };
/// let camera = Camera::new(Space::new(Geometry::Hyperbolic), &settings);
/// // The centre of an odd-sized image looks straight ahead (here 20° down).
/// let ray = camera.ray(1, 1, 3, 3, (0.5, 0.5));
/// assert!((ray.sin_elevation - (-20f64).to_radians().sin()).abs() < 1e-15);
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Camera {
    space: Space,
    eye: DVec3,
    height: f64,
    /// Unit ambient tangents of the model's +x and +y at the eye.
    frame: [DVec3; 2],
    kind: CameraKind,
    yaw: f64,
    /// Left and right swapped ([`CameraSettings::mirrored`]).
    mirrored: bool,
    forward: DVec3,
    right: DVec3,
    up: DVec3,
    tan_half_fov: f64,
}

impl Camera {
    /// The camera of a scene's `[camera]` settings (angles in degrees).
    pub fn new(space: Space, settings: &CameraSettings) -> Camera {
        let z = Complex64::new(settings.at[0], settings.at[1]);
        let yaw = settings.yaw.to_radians();
        let [forward, right, up] = settings.basis();
        Camera {
            space,
            eye: space.to_ambient(z),
            height: settings.height,
            frame: [
                space.model_tangent(z, Complex64::new(1.0, 0.0)),
                space.model_tangent(z, Complex64::new(0.0, 1.0)),
            ],
            kind: settings.kind,
            yaw,
            mirrored: settings.mirrored,
            forward,
            right,
            up,
            tan_half_fov: (0.5 * settings.fov.to_radians()).tan(),
        }
    }

    /// The ray through the point (i + dx, j + dy) of a `width`×`height` image, with (dx, dy) in
    /// [0, 1)² (½, ½ for the pixel's centre).
    pub fn ray(&self, i: u32, j: u32, width: u32, height: u32, offset: (f64, f64)) -> Ray {
        let (u, v) = (
            (f64::from(i) + offset.0) / f64::from(width),
            (f64::from(j) + offset.1) / f64::from(height),
        );
        self.ray_along(self.local_direction(u, v, width, height))
    }

    /// The footprint of the ray through the point (i + dx, j + dy) of pixel (i, j), with
    /// `offset` = (dx, dy) as for [`Camera::ray`]: the pixel's angular size — the angles between
    /// the directions through the middles of its opposite sides — and where its centre is seen
    /// relative to the ray (what [`crate::footprint`] carries along camera rays).
    ///
    /// ```
    /// use orbifold::{Geometry, space::Space};
    /// use orbifold_trace::camera::Camera;
    /// use orbifold_scene::Camera as Settings;
    /// let settings = Settings { fov: 90.0, ..Settings::default() };
    /// let camera = Camera::new(Space::new(Geometry::Euclidean), &settings);
    /// // At the middle of a 100×100 image a pixel is 2·tan 45°/100 radians wide, nearly.
    /// let f = camera.footprint(50, 50, 100, 100, (0.5, 0.5));
    /// assert!((f.across - 0.02).abs() < 1e-4 && (f.up - 0.02).abs() < 1e-4);
    /// assert!(f.centre[0].abs() < 1e-12 && f.centre[1].abs() < 1e-12);
    /// // A ray through the pixel's lower right corner: its centre is up and to the left.
    /// let f = camera.footprint(50, 50, 100, 100, (1.0, 1.0));
    /// assert!((f.centre[0] - 0.01).abs() < 1e-3 && (f.centre[1] - 0.01).abs() < 1e-3);
    /// ```
    pub fn footprint(
        &self,
        i: u32,
        j: u32,
        width: u32,
        height: u32,
        offset: (f64, f64),
    ) -> Footprint {
        let (w, h) = (f64::from(width), f64::from(height));
        let (u, v) = ((f64::from(i) + 0.5) / w, (f64::from(j) + 0.5) / h);
        let angle = |a: DVec3, b: DVec3| a.cross(b).length().atan2(a.dot(b));
        let at = |u: f64, v: f64| self.local_direction(u, v, width, height);
        let (ray, centre) = (
            at(u + (offset.0 - 0.5) / w, v + (offset.1 - 0.5) / h),
            at(u, v),
        );
        let bearing = |d: DVec3| d.y.atan2(d.x);
        let elevation = |d: DVec3| d.z.atan2((d.x * d.x + d.y * d.y).sqrt());
        let turn = (bearing(centre) - bearing(ray) + PI).rem_euclid(2.0 * PI) - PI;
        Footprint {
            across: angle(at(u - 0.5 / w, v), at(u + 0.5 / w, v)),
            up: angle(at(u, v - 0.5 / h), at(u, v + 0.5 / h)),
            centre: [
                turn * elevation(ray).cos(),
                elevation(centre) - elevation(ray),
            ],
        }
    }

    /// The unit direction (local frame) through the image point (u, v) ∈ [0, 1]².
    fn local_direction(&self, u: f64, v: f64, width: u32, height: u32) -> DVec3 {
        match self.kind {
            CameraKind::Pinhole => {
                let aspect = f64::from(width) / f64::from(height);
                let a = (2.0 * u - 1.0) * self.tan_half_fov * aspect;
                let b = (1.0 - 2.0 * v) * self.tan_half_fov;
                (self.forward + a * self.right + b * self.up).normalize()
            }
            CameraKind::Panorama => {
                // Left to right turning clockwise; a mirrored camera's, anticlockwise.
                let turn = PI - 2.0 * PI * u;
                let bearing = self.yaw + if self.mirrored { -turn } else { turn };
                let elevation = 0.5 * PI - PI * v;
                DVec3::new(
                    elevation.cos() * bearing.cos(),
                    elevation.cos() * bearing.sin(),
                    elevation.sin(),
                )
            }
        }
    }

    /// The ray from the eye along a direction of the local frame (model +x, model +y, up).
    pub fn ray_along(&self, local: DVec3) -> Ray {
        let horizontal = self.frame[0] * local.x + self.frame[1] * local.y;
        let run = (local.x * local.x + local.y * local.y).sqrt();
        if run == 0.0 {
            // Straight up or down: any horizontal direction will do.
            let rise = local.z.signum();
            return Ray::climbing(self.space, self.eye, self.frame[0], self.height, 0.0, rise);
        }
        Ray::climbing(self.space, self.eye, horizontal, self.height, run, local.z)
    }

    /// The eye's ambient position and height.
    pub fn eye(&self) -> (DVec3, f64) {
        (self.eye, self.height)
    }
}
