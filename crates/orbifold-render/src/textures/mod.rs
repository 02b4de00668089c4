//! Textures: what a diffuse surface's albedo is at a point (`Texture`), looked up in the
//! texture coordinates the scene asks for (`TextureEvalContext`).
//!
//! A texture is one colour, a checkerboard (`checker.rs`), an image that repeats over the plane
//! (`image.rs`) or procedural marble ([`marble`]). Patterns are laid out in model coordinates
//! (the model picture's) or intrinsic ones (normal coordinates about the room's centre, through
//! the exponential map), with the height as third coordinate; walls use their own (length along
//! the wall, height). Seen by a camera ray,
//! checkerboards and images are averaged over the ray's pixel footprint
//! ([`orbifold_trace::footprint`]) with box filters, in closed form and through a summed-area
//! table: a far mirror image of a pattern is the pattern's mean colour there, not the aliasing
//! of one ray per pixel. Marble is point-sampled.

mod checker;
mod image;
mod marble;

use glam::DVec3;
use orbifold_scene::geometry::representative;
use orbifold_scene::{Coordinates, Material};

use self::image::ImageTexture;
use crate::lights::Rgb;

pub use self::marble::marble;

/// A texture: what a diffuse surface's albedo is at a point.
#[derive(Clone, Debug)]
pub(crate) enum Texture {
    /// One colour.
    Solid(Rgb),
    /// A checkerboard of squares `size` across (cubes on an object).
    Checker {
        colors: [Rgb; 2],
        size: f64,
        intrinsic: bool,
    },
    /// An image repeated every `scale` in both directions.
    Image {
        image: ImageTexture,
        scale: f64,
        intrinsic: bool,
    },
    /// Procedural marble: veins of `vein` in a `ground` (the scene's `base`), features about
    /// `scale` across.
    Marble {
        ground: Rgb,
        vein: Rgb,
        scale: f64,
        intrinsic: bool,
    },
}

impl Texture {
    /// The texture of a scene material; `base` resolves image file names. Materials that are
    /// not patterns (metal, glass, plastic: [`crate::materials`] handles those) get the colour
    /// that stands for them.
    pub(crate) fn new(
        material: &Material,
        base: Option<&std::path::Path>,
    ) -> Result<Texture, String> {
        Ok(match material {
            Material::Color { color } => Texture::Solid(*color),
            Material::Checker {
                colors,
                size,
                coordinates,
            } => Texture::Checker {
                colors: *colors,
                size: *size,
                intrinsic: *coordinates == Coordinates::Intrinsic,
            },
            Material::Texture {
                path,
                scale,
                coordinates,
            } => {
                let file = base.map_or_else(|| path.into(), |b| b.join(path));
                Texture::Image {
                    image: ImageTexture::read(&file)?,
                    scale: *scale,
                    intrinsic: *coordinates == Coordinates::Intrinsic,
                }
            }
            Material::Marble {
                base: ground,
                vein,
                scale,
                coordinates,
            } => Texture::Marble {
                ground: *ground,
                vein: *vein,
                scale: *scale,
                intrinsic: *coordinates == Coordinates::Intrinsic,
            },
            // Not a pattern: the colour that stands for it.
            other => Texture::Solid(representative(other)),
        })
    }

    /// The albedo where `lookup` says. Seen by a camera ray, checkerboards and images are
    /// averaged over the pixel's footprint (box filters: in closed form, and by a summed-area
    /// table); marble is point-sampled.
    pub(crate) fn albedo(&self, lookup: &TextureEvalContext) -> Rgb {
        match self {
            Texture::Solid(c) => *c,
            Texture::Checker {
                colors,
                size,
                intrinsic,
            } => checker::albedo(colors, *size, *intrinsic, lookup),
            Texture::Image {
                image,
                scale,
                intrinsic,
            } => image.albedo(*scale, *intrinsic, lookup),
            Texture::Marble {
                ground,
                vein,
                scale,
                intrinsic,
            } => {
                let p = (lookup.coords)(*intrinsic, DVec3::ZERO);
                // `marble` takes a frequency; the scene gives the features' size.
                marble(DVec3::from(p), *ground, *vein, 1.0 / scale)
            }
        }
    }
}

/// Where a texture is looked up (pbrt's `TextureEvalContext`).
pub(crate) struct TextureEvalContext<'a> {
    /// The texture coordinates (intrinsic or model, as asked) of the point moved by a tangent
    /// vector (local frame; zero for the point itself).
    pub(crate) coords: &'a dyn Fn(bool, DVec3) -> [f64; 3],
    /// For a camera ray's first surface: its pixel's footprint there, as the tangent vector
    /// from the point to where the pixel's centre is seen and two half-axes (local frame), all
    /// in the surface.
    pub(crate) footprint: Option<[DVec3; 3]>,
}
