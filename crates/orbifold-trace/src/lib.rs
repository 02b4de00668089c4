//! The curved-ray tracing core of the orbifold mirror rooms: rays that follow the exact
//! geodesics of S²×R, E²×R and H²×R, and what they meet.
//!
//! - [`geodesic`]: a ray as a geodesic of the product space, in closed form.
//! - [`room`]: the analytic mirror room — floor, ceiling and walls of the orbifold's polygon,
//!   and reflection in a wall.
//! - `ray_frame`: what the bound and triangle tests read of a ray, computed once a ray, and
//!   where a ray's horizontal geodesic is inside a geodesic disc (the bound of nodes, objects
//!   and triangles).
//! - [`triangle`], [`shading_normal`]: intrinsically flat triangles of curved meshes and their
//!   smooth shading normals.
//! - [`accel`]: the bounding volume hierarchy for curved rays, and instances: meshes placed in
//!   the room by isometries, sharing one BVH.
//! - [`tracer`]: follows a ray through the mirrors to the first surface it meets.
//! - [`camera`], [`footprint`]: pinhole and panorama cameras, and the footprint a ray carries.
//! - [`aov`]: arbitrary output variables (depth, position, normal, id) of a whole image.
//! - [`fastmath`], [`cpu`]: branch-free transcendental functions with stated errors, and the
//!   run-time choice of SIMD copies, shared with `orbifold-render`.
//!
//! The light transport built on it is `orbifold-render`; see ARCHITECTURE.md for how the crates
//! fit together.

pub mod accel;
pub mod aov;
pub mod camera;
pub mod cpu;
pub mod fastmath;
pub mod footprint;
pub mod geodesic;
pub(crate) mod ray_frame;
pub mod room;
pub mod shading_normal;
#[cfg(test)]
mod test_util;
pub mod tracer;
pub mod triangle;

pub use orbifold;
pub use orbifold_scene;
