//! Acceleration structures for curved rays: a bounding volume hierarchy over each mesh, built
//! once in the mesh's own frame ([`Bvh`]), and the instances that place meshes in the room by
//! isometries and share their hierarchies ([`Instance`], [`Instances`]).
//!
//! The hierarchy's parts, one a file:
//!
//! - `bvh`: the [`Bvh`] type and its public methods;
//! - `node`: the 8-wide nodes — their children's chart boxes and heights in f32 side by side,
//!   and beside them the children's geodesic discs;
//! - `chart`: the mesh's gnomonic chart, in which geodesics are straight lines, and a ray seen
//!   in it;
//! - `chart_lanes`: the test of a node's eight chart boxes in f32 lanes;
//! - `disc_lanes`: the test of a node's eight discs in f64 lanes, where there is no chart;
//! - `traverse`: the nearest-hit and any-hit traversals;
//! - `build`: binned SAH, and the binary tree collapsed into 8-wide nodes.
//!
//! The per-ray frame and the disc test that the hierarchy shares with the instances and the
//! triangles are in `crate::ray_frame`.

mod build;
mod bvh;
mod chart;
mod chart_lanes;
mod disc_lanes;
mod instance;
mod node;
mod traverse;

pub use bvh::Bvh;
pub use instance::{Instance, Instances};
