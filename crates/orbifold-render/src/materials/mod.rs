//! Materials: what a scene's description of a surface becomes at a point of it. A
//! `SurfaceMaterial` looks its textures up there ([`crate::textures`]) and gives the BSDF
//! ([`bsdf`]) that scatters light at that point.
//!
//! The BSDF is split by concept, as in pbrt-v4: [`bsdf`] holds the enum the integrator uses and
//! dispatches to one file per kind of surface (`diffuse`, `dielectric`, `conductor`,
//! `plastic`), which share the Fresnel equations (`fresnel`) and the GGX microfacet distribution
//! (`microfacet`).

pub mod bsdf;
mod conductor;
mod dielectric;
mod diffuse;
mod fresnel;
mod material;
mod microfacet;
mod plastic;

pub(crate) use self::material::SurfaceMaterial;
