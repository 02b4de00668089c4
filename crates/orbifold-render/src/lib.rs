//! Light transport in orbifold mirror rooms, on the curved-ray tracing core of
//! `orbifold-trace`: lights and their mirror images ([`lights`]), materials and textures
//! ([`materials`], [`textures`]), the path tracer ([`integrator`]), the radiance cache for far mirror
//! images and indirect light ([`radiance_cache`]), samplers ([`sampler`]), the pixel filter and
//! film ([`film`]), the guided denoiser ([`denoise`]), the progressive render loop
//! ([`render`]) and straight rays for comparison ([`straight_rays`]). See ARCHITECTURE.md.

pub mod film;
pub mod sampler;

pub mod denoise;
pub mod integrator;
pub mod lights;
pub mod materials;
pub mod radiance_cache;
pub mod render;
pub mod straight_rays;
pub mod textures;

pub use orbifold;
pub use orbifold_scene;
pub use orbifold_trace;
