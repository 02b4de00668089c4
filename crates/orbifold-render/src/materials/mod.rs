//! Materials: what a scene's description of a surface becomes at a point of it. A
//! `SurfaceMaterial` looks its textures up there ([`crate::textures`]) and gives the BSDF
//! ([`bsdf`]) that scatters light at that point.

pub mod bsdf;
mod material;

pub(crate) use self::material::SurfaceMaterial;
