//! The lights of a scene and how each kind emits: point and spot lights, which emit from a point
//! with a radiant intensity (W/sr), and sphere and rectangle lights, Lambertian area lights over
//! a triangle mesh (`area.rs`) that rays can also hit.

use std::f64::consts::{PI, TAU};

use glam::DVec3;
use num_complex::Complex64;
use orbifold::embed::Placement;
use orbifold::space::Space;
use orbifold_scene::color::Rgb;
use orbifold_scene::geometry::Fit;
use orbifold_scene::mesh::procedural::uv_sphere;
use orbifold_scene::{LightKind, Scene};
use orbifold_trace::accel::Instance;

use super::area::{area_emitter, rectangle_mesh};
use super::facing::Facing;
use super::frame::TangentFrame;
use crate::sampler::Distribution1d;

/// How a light emits.
#[derive(Clone, Debug)]
// A scene has a handful of lights: their size does not matter, one indirection per sample does.
#[allow(clippy::large_enum_variant)]
pub enum Emitter {
    /// A point emitting `intensity` (W/sr per channel) in every direction.
    Point {
        /// Radiant intensity.
        intensity: Rgb,
    },
    /// A point emitting `intensity` inside a cone around `axis` (local frame at the light).
    Spot {
        /// Radiant intensity inside the cone.
        intensity: Rgb,
        /// Unit axis in the light's local frame.
        axis: DVec3,
        /// cos of the cone's half-angle.
        cos_cone: f64,
    },
    /// A mesh of intrinsically flat triangles emitting `radiance` (Lambertian).
    Area {
        /// Emitted radiance.
        radiance: Rgb,
        /// The placed mesh (also hit by rays).
        instance: Instance,
        /// Triangle areas (intrinsic).
        areas: Vec<f64>,
        /// Picks a triangle ∝ its area.
        triangle_distribution: Distribution1d,
        /// For a sphere light: which triangles can face a point.
        facing: Option<Facing>,
        /// The triangles' total area.
        total_area: f64,
        /// Emits from both sides (spheres) or only the front (rectangles).
        two_sided: bool,
    },
}

/// A light of the scene.
#[derive(Clone, Debug)]
pub struct Light {
    /// Ambient horizontal position of its centre.
    pub position: DVec3,
    /// Height of its centre.
    pub height: f64,
    /// A tangent frame at its centre.
    pub frame: TangentFrame,
    /// Power (W, per channel: colour × power).
    pub power: Rgb,
    /// How it emits.
    pub emitter: Emitter,
}

impl Light {
    /// The lights of a scene in the room's space.
    pub fn from_scene(space: Space, scene: &Scene) -> Result<Vec<Light>, String> {
        scene
            .lights
            .iter()
            .enumerate()
            .map(|(i, l)| {
                let z = Complex64::new(l.at[0], l.at[1]);
                let position = space.to_ambient(z);
                let frame = TangentFrame::at(space, position);
                let power = l.color.map(|c| c * l.power);
                let (yaw, pitch) = (l.yaw.to_radians(), l.pitch.to_radians());
                // The light's direction in (model +x, model +y, up) at its position, then in
                // the light's own frame.
                let model = [
                    space.model_tangent(z, Complex64::new(1.0, 0.0)),
                    space.model_tangent(z, Complex64::new(0.0, 1.0)),
                ];
                let h = model[0] * (pitch.cos() * yaw.cos()) + model[1] * (pitch.cos() * yaw.sin());
                let axis = frame.to_local(space, h, pitch.sin()).normalize();
                let emitter = match l.kind {
                    LightKind::Point => Emitter::Point {
                        intensity: power.map(|p| p / (4.0 * PI)),
                    },
                    LightKind::Spot => {
                        let cos_cone = l.cone.to_radians().cos();
                        Emitter::Spot {
                            intensity: power.map(|p| p / (TAU * (1.0 - cos_cone))),
                            axis,
                            cos_cone,
                        }
                    }
                    LightKind::Sphere => {
                        // Coarser than the built-in object sphere: light sampling scans the
                        // triangles that face the lit point, 352 here (2 × 16 × 11).
                        let mesh = uv_sphere(0.5, 16, 12);
                        // Its largest extent is its diameter, pole to pole.
                        let fit = Fit::Size(2.0 * l.radius);
                        let placement = Placement {
                            at: z,
                            height: l.height - l.radius,
                            yaw: 0.0,
                        };
                        area_emitter(space, &mesh, fit, &placement, power, true)
                            .map(|e| e.with_facing(space))
                            .map_err(|e| format!("lights[{i}]: {e}"))?
                    }
                    LightKind::Rectangle => {
                        let (mesh, lowest) = rectangle_mesh(axis, l.size);
                        let placement = Placement {
                            at: z,
                            height: l.height + lowest,
                            yaw: 0.0,
                        };
                        area_emitter(space, &mesh, Fit::AsModelled, &placement, power, false)
                            .map_err(|e| format!("lights[{i}]: {e}"))?
                    }
                };
                Ok(Light {
                    position,
                    height: l.height,
                    frame,
                    power,
                    emitter,
                })
            })
            .collect()
    }

    /// For a sphere light: the radius of its mesh's outline and its radiance (what
    /// [`orbifold_trace::footprint`] needs); `None` for other lights.
    pub fn sphere(&self) -> Option<(f64, Rgb)> {
        match &self.emitter {
            Emitter::Area {
                radiance,
                facing: Some(facing),
                ..
            } => Some((facing.radius, *radiance)),
            _ => None,
        }
    }

    /// Whether the light is a point (delta) light.
    pub fn is_point(&self) -> bool {
        !matches!(self.emitter, Emitter::Area { .. })
    }

    /// Radiant intensity (point lights) or radiance (area lights) leaving towards the local
    /// direction `out` (unit, in the light's frame for point lights; for area lights `cos_out` is
    /// the cosine with the surface normal, negative behind).
    pub fn emission(&self, out: DVec3, cos_out: f64) -> Rgb {
        match &self.emitter {
            Emitter::Point { intensity } => *intensity,
            Emitter::Spot {
                intensity,
                axis,
                cos_cone,
            } => {
                if out.dot(*axis) >= *cos_cone {
                    *intensity
                } else {
                    [0.0; 3]
                }
            }
            Emitter::Area {
                radiance,
                two_sided,
                ..
            } => {
                if cos_out > 0.0 || (*two_sided && cos_out < 0.0) {
                    *radiance
                } else {
                    [0.0; 3]
                }
            }
        }
    }
}
