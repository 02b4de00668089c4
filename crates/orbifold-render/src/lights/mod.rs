//! Lights, their mirror images, and geodesic connections between two points (ARCHITECTURE.md §8).
//!
//! A point of the room is lit by connecting it along a geodesic of S²×R, E²×R or H²×R to a point
//! of a light or of one of the light's mirror images. One concept to a file:
//!
//! - `frame.rs`: tangent frames at a point ([`TangentFrame`]) and a ray's direction in one
//!   ([`travel_direction`]);
//! - `connection.rs`: the geodesic between two points, every way round the sphere, and its
//!   geometric term ([`connect`], [`aim_at`], [`spread`], [`turned`]);
//! - `images.rs`: a light's mirror images, enumerated across mirror walls ([`ImageSet`]);
//! - `emitter.rs`: the lights of a scene and how each kind emits ([`Light`], [`Emitter`]);
//! - `area.rs`: Lambertian area emitters over triangle meshes (sphere and rectangle lights) and
//!   the area element of their triangles ([`area_jacobian`]);
//! - `facing.rs`: which of a sphere light's triangles face a lit point, and their solid-angle
//!   weights, eight at a time in SIMD ([`Facing`]);
//! - `sampling.rs`: points sampled on a light for a lit point and their densities
//!   ([`LightPoint`], [`AimedLight`]).

mod area;
mod connection;
mod emitter;
mod facing;
mod frame;
mod images;
mod sampling;

pub use area::area_jacobian;
pub(crate) use area::mesh_emitter;
pub use connection::{Connection, aim_at, connect, spread, turned};
pub use emitter::{Emitter, Light};
pub use facing::Facing;
pub use frame::{TangentFrame, travel_direction};
pub use images::{IMAGE_CUTOFF, Image, ImageSet, MAX_IMAGES, reflection_matrix};
pub use orbifold_scene::color::Rgb;
pub use sampling::{AimedLight, LightPoint};
