//! The non-Euclidean projection (ARCHITECTURE.md §9), on the CPU: the exact twin of the vertex
//! shader, used by tests, culling and picking.
//!
//! A point (p, h) of the product space is taken to the camera's frame by an isometry (the eye
//! goes to the model's origin O = (0, 0, 1), the model's +x and +y at the eye to the ambient
//! axes), then mapped by the logarithm map of the product space: horizontal distance d and
//! bearing, plus the height difference. That tangent vector T is the initial velocity of the
//! geodesic from the eye that reaches the point at arc length |T|, so the pinhole projection of
//! T is exactly the pixel whose camera ray (ARCHITECTURE.md §8) hits the point. In S²×R the point is
//! reached again the long way round the sphere, by the geodesic with horizontal distance 2π − d
//! in the opposite bearing, and then after whole turns: image k = 2w (+1) of a point has
//! horizontal distance d + 2πw (or 2π(w + 1) − d, reversed).
//!
//! The straight projection shows the model picture as if space were flat, as
//! `orbifold render --straight-rays` does: a point keeps its model position z and height, the flat
//! plane has ambient coordinates (2x, 2y, 1), and the camera stands at its own model position.

use std::f64::consts::TAU;

use glam::{DMat3, DVec3};
use num_complex::Complex64;
use orbifold::isometry::Isometry;
use orbifold::space::Space;
use orbifold_scene::Camera as CameraSettings;

/// How points are projected.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Projection {
    /// Along the true geodesics of S²×R, E²×R or H²×R (the logarithm map).
    #[default]
    Curved,
    /// As if the model picture were flat space (the seed's Fig. 8.4, left).
    Straight,
}

/// Where a point lands in the image.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Projected {
    /// Horizontal pixel coordinate (0 at the left edge, `width` at the right).
    pub x: f64,
    /// Vertical pixel coordinate (0 at the top edge).
    pub y: f64,
    /// The length of the geodesic from the eye (the depth the preview tests).
    pub distance: f64,
}

/// A pinhole camera in a plane of curvature κ: where it stands, where it looks, and how it
/// projects.
///
/// ```
/// use orbifold::{Geometry, space::Space};
/// use orbifold_preview::projection::{Projection, View};
/// use orbifold_scene::Camera;
/// let space = Space::new(Geometry::Hyperbolic);
/// let camera = Camera { at: [0.0, 0.0], height: 0.5, yaw: 0.0, pitch: 0.0, ..Camera::default() };
/// let view = View::new(space, &camera, Projection::Curved);
/// // A point straight ahead at eye height lands in the middle of the image.
/// let p = space.to_ambient(num_complex::Complex64::new(0.3, 0.0));
/// let at = view.project(p, 0.5, 0, 64, 48).unwrap();
/// assert!((at.x - 32.0).abs() < 1e-9 && (at.y - 24.0).abs() < 1e-9);
/// assert!((at.distance - 2.0 * 0.3f64.atanh()).abs() < 1e-12);
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct View {
    space: Space,
    projection: Projection,
    /// Takes ambient points to the camera's frame (the eye to O).
    to_eye: DMat3,
    /// The eye's model position, for the straight projection.
    eye_model: Complex64,
    eye_height: f64,
    forward: DVec3,
    right: DVec3,
    up: DVec3,
    tan_half_fov: f64,
    turns: u32,
}

impl View {
    /// The view of a scene's camera settings (angles in degrees). A panorama camera is
    /// previewed as a pinhole camera with the same position, yaw, pitch and field of view.
    pub fn new(space: Space, camera: &CameraSettings, projection: Projection) -> View {
        let eye_model = Complex64::new(camera.at[0], camera.at[1]);
        let [forward, right, up] = camera.basis();
        // The translation from O to the eye has a real positive derivative at O, so it carries
        // the ambient axes at O onto the model's +x and +y at the eye: its inverse is the view.
        let to_eye = Isometry::translation(space, eye_model).inverse().matrix();
        View {
            space,
            projection,
            to_eye,
            eye_model,
            eye_height: camera.height,
            forward,
            right,
            up,
            tan_half_fov: (0.5 * camera.fov.clamp(1.0, 179.0).to_radians()).tan(),
            turns: 1,
        }
    }

    /// The same view drawing the images of `turns` whole turns round the sphere (S²×R only; at
    /// least 1). A ray of elevation α meets a floor or ceiling Δh away after a horizontal
    /// distance Δh/tan α, so `turns` turns show every surface seen more steeply than
    /// atan(Δh/(2π·turns)); flatter rays go round further.
    pub fn with_turns(mut self, turns: u32) -> View {
        self.turns = turns.max(1);
        self
    }

    /// The plane.
    pub fn space(&self) -> Space {
        self.space
    }

    /// The projection.
    pub fn projection(&self) -> Projection {
        self.projection
    }

    /// The matrix that the shader applies to a copy's points: the view times the copy's
    /// isometry `copy` for the curved projection, the copy alone for the straight one.
    pub fn instance_matrix(&self, copy: &DMat3) -> DMat3 {
        match self.projection {
            Projection::Curved => self.to_eye * *copy,
            Projection::Straight => *copy,
        }
    }

    /// The eye's height.
    pub fn eye_height(&self) -> f64 {
        self.eye_height
    }

    /// The eye's model position.
    pub fn eye_model(&self) -> Complex64 {
        self.eye_model
    }

    /// The camera's forward, right and up vectors in the eye's frame (model +x, model +y, up).
    pub fn basis(&self) -> [DVec3; 3] {
        [self.forward, self.right, self.up]
    }

    /// tan(φ/2) for the vertical field of view φ.
    pub fn tan_half_fov(&self) -> f64 {
        self.tan_half_fov
    }

    /// How many images of each point the projection draws: in S²×R two a turn round the sphere
    /// (the short and the long way round; see [`View::with_turns`]), one otherwise.
    pub fn images(&self) -> u32 {
        match self.projection {
            Projection::Curved if self.space.kappa() > 0.0 => 2 * self.turns,
            _ => 1,
        }
    }

    /// The tangent vector at the eye, in its frame (model +x, model +y, up), of the geodesic that
    /// reaches the point with ambient position `p` and height `h` (image `image` of it in
    /// S²×R; see the module's documentation).
    pub fn log(&self, p: DVec3, h: f64, image: u32) -> DVec3 {
        let dh = h - self.eye_height;
        if self.projection == Projection::Straight {
            let z = self.space.to_model(p) - self.eye_model;
            return DVec3::new(2.0 * z.re, 2.0 * z.im, dh);
        }
        eye_log(self.space, self.to_eye * p, dh, image)
    }

    /// Where the point (p, h) lands in a `width`×`height` image, or `None` behind the eye.
    pub fn project(
        &self,
        p: DVec3,
        h: f64,
        image: u32,
        width: u32,
        height: u32,
    ) -> Option<Projected> {
        let t = self.log(p, h, image);
        let (x, y, z) = (t.dot(self.right), t.dot(self.up), t.dot(self.forward));
        if z <= 0.0 {
            return None;
        }
        let aspect = f64::from(width) / f64::from(height);
        let ndc_x = x / (z * self.tan_half_fov * aspect);
        let ndc_y = y / (z * self.tan_half_fov);
        Some(Projected {
            x: 0.5 * (1.0 + ndc_x) * f64::from(width),
            y: 0.5 * (1.0 - ndc_y) * f64::from(height),
            distance: t.length(),
        })
    }
}

/// The logarithm map at the origin O of an ambient point `q` already in the eye's frame, with
/// height difference `dh`, for image `image` (see the module's documentation).
pub fn eye_log(space: Space, q: DVec3, dh: f64, image: u32) -> DVec3 {
    let r = q.x.hypot(q.y);
    let mut d = match space.kappa() {
        k if k > 0.0 => r.atan2(q.z),
        k if k < 0.0 => r.asinh(),
        _ => r / q.z,
    };
    let mut direction = if r > 0.0 {
        [q.x / r, q.y / r]
    } else {
        [1.0, 0.0]
    };
    let turns = f64::from(image / 2);
    if image % 2 == 1 {
        d = TAU * (turns + 1.0) - d;
        direction = [-direction[0], -direction[1]];
    } else {
        d += TAU * turns;
    }
    DVec3::new(d * direction[0], d * direction[1], dh)
}
