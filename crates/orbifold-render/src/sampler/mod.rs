//! Random numbers and sampling helpers for the path tracer, one concept per file:
//!
//! - [`Sampler`] (`stream.rs`): a deterministic random stream per (seed, pixel, sample), so
//!   that an image depends only on the seed, never on how the work was scheduled across
//!   threads. Camera paths use its stratified form ([`Sampler::stratified`]), whose most
//!   important dimensions come from a scrambled Sobol sequence per pixel (`sobol.rs`).
//! - Warping functions from the unit square to directions and points, each with its density
//!   (`warp.rs`): [`cosine_hemisphere`], [`uniform_sphere`], [`uniform_cone`],
//!   [`uniform_disk_concentric`].
//! - [`power_heuristic`], the multiple-importance-sampling weight (β = 2) (`mis.rs`).
//! - [`Distribution1d`]: picking one of N items with probability ∝ its weight
//!   (`distribution.rs`).
//! - [`Frame`] and [`frame_from_normal`]: orthonormal shading frames (Duff et al. 2017)
//!   (`frame.rs`).
//!
//! Local frames have the normal along +z; the warping functions take uniforms `u` in [0, 1)².

mod distribution;
mod frame;
mod mis;
mod sobol;
mod stream;
mod warp;

pub use self::distribution::Distribution1d;
pub use self::frame::{Frame, frame_from_normal, to_local, to_world};
pub use self::mis::power_heuristic;
pub use self::sobol::{BOUNCE_DIMENSIONS, CAMERA_DIMENSIONS};
pub use self::stream::Sampler;
pub use self::warp::{
    cosine_hemisphere, cosine_hemisphere_pdf, uniform_cone, uniform_cone_pdf,
    uniform_disk_concentric, uniform_sphere, uniform_sphere_pdf,
};
