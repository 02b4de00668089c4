//! Light transport in orbifold mirror rooms, on the curved-ray tracing core of `orbifold-trace`
//! (ARCHITECTURE.md §2, §8). One folder or file a concept, as in pbrt-v4:
//!
//! - [`lights`]: point, spot, sphere and rectangle lights, their mirror images, and the
//!   geodesic connections from a surface to them;
//! - [`materials`]: the BSDFs (diffuse, conductor, dielectric, plastic; Fresnel, GGX) and the
//!   scene's surface materials; [`textures`]: checker, image and marble albedo;
//! - [`integrator`]: the path tracer — the path loop, mirrors, footprints, light sampling;
//! - [`radiance_cache`]: cached radiance for far mirror images and indirect light;
//! - [`sampler`]: sample streams (Sobol), warps, MIS, discrete distributions, shading frames;
//! - [`film`]: the HDR film, its pixel filter, noise statistics, output and tone mapping;
//! - [`denoise`]: the guided à-trous denoiser;
//! - [`render`]: the render loop, adaptive sampling, and **the one render pipeline**
//!   ([`render::render_picture`]) that the command line and the studio call;
//! - [`straight_rays`]: the room lit and seen as if space were flat, for comparison.

pub mod denoise;
pub mod film;
pub mod integrator;
pub mod lights;
pub mod materials;
pub mod radiance_cache;
pub mod render;
pub mod sampler;
pub mod straight_rays;
pub mod textures;

pub use orbifold;
pub use orbifold_scene;
pub use orbifold_trace;
