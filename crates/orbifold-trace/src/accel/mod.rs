//! Acceleration structures for curved rays: a bounding volume hierarchy over each mesh, built
//! once in the mesh's own frame ([`Bvh`]), and the instances that place meshes in the room by
//! isometries and share their hierarchies ([`Instance`], [`Instances`]).

mod bvh;
mod instance;

pub use bvh::Bvh;
pub(crate) use bvh::{Bound, Disc, RayFrame, disc_around};
pub use instance::{Instance, Instances};
