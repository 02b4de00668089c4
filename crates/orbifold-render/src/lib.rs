//! Light transport in orbifold mirror rooms, on the curved-ray tracing core of
//! `orbifold-trace`: lights and their mirror images ([`light`]), materials and textures
//! ([`bsdf`], `texture`), the path tracer ([`integrator`]), the radiance cache for far mirror
//! images and indirect light ([`radiance_cache`]), samplers ([`sampler`]), the pixel filter and
//! film ([`filter`], [`film`]), the guided denoiser ([`denoise`]), the progressive render loop
//! ([`render`]) and straight rays for comparison ([`flat`]). See ARCHITECTURE.md.

pub mod film;
pub mod filter;
pub mod sampler;

pub mod bsdf;
pub mod denoise;
pub mod flat;
pub mod integrator;
pub mod light;
pub mod radiance_cache;
pub mod render;
mod texture;

pub use orbifold;
pub use orbifold_scene;
pub use orbifold_trace;
