//! A surface's material as the integrator uses it: the scene's [`Material`] made ready to give
//! the BSDF at any point of the surface, its textures loaded (pbrt's `Material`, which the
//! integrator asks for a BSDF at each hit).

use orbifold_scene::{Material, MetalName};

use super::bsdf::Bsdf;
use crate::textures::{Texture, TextureEvalContext};

/// A surface's material, ready to give the BSDF at a point.
#[derive(Clone, Debug)]
pub(crate) enum SurfaceMaterial {
    /// Lambertian with a texture (one colour, a checkerboard, an image or marble).
    Diffuse(Texture),
    /// Anything whose BSDF is the same everywhere (glass, metal).
    Uniform(Bsdf),
    /// Rough plastic over a textured base.
    Plastic { base: Texture, roughness: f64 },
}

impl SurfaceMaterial {
    /// The material a scene describes; `base` resolves the file names of image textures.
    pub(crate) fn new(
        material: &Material,
        base: Option<&std::path::Path>,
    ) -> Result<SurfaceMaterial, String> {
        Ok(match material {
            Material::Glass { tint, ior } => SurfaceMaterial::Uniform(Bsdf::Dielectric {
                eta: *ior,
                tint: *tint,
            }),
            Material::Metal { metal, roughness } => SurfaceMaterial::Uniform(match metal {
                MetalName::Silver => Bsdf::silver(*roughness),
                MetalName::Gold => Bsdf::gold(*roughness),
                MetalName::Copper => Bsdf::copper(*roughness),
                MetalName::Aluminium => Bsdf::aluminium(*roughness),
            }),
            Material::Plastic { color, roughness } => SurfaceMaterial::Plastic {
                base: Texture::Solid(*color),
                roughness: *roughness,
            },
            _ => SurfaceMaterial::Diffuse(Texture::new(material, base)?),
        })
    }

    /// The BSDF where `lookup` says.
    pub(crate) fn bsdf(&self, lookup: &TextureEvalContext) -> Bsdf {
        match self {
            SurfaceMaterial::Diffuse(texture) => Bsdf::diffuse(texture.albedo(lookup)),
            SurfaceMaterial::Uniform(bsdf) => *bsdf,
            SurfaceMaterial::Plastic { base, roughness } => {
                Bsdf::plastic(base.albedo(lookup), *roughness)
            }
        }
    }
}
