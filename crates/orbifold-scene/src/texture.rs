//! Texture coordinates for mesh exports: where a checkerboard or an image lies on each part of
//! the room, laid out as the renderer lays it (docs/scene-format.md, "Where a pattern lies"),
//! so that other tools show the room's textures.
//!
//! A part gets a texture when its material is an image, or a checkerboard on the floor, the
//! ceiling or a wall (there the checker's third coordinate is constant, so a 2D image of 2×2
//! squares holds it). A checkerboard on an object is a solid 3D checker and marble a solid
//! function: those parts keep their representative colour.

use std::path::{Path, PathBuf};

use glam::DVec3;
use orbifold::Layout;
use orbifold::room::RoomMesher;
use orbifold::space::Space;

use crate::document::{Color, Coordinates, Material, Scene};
use crate::part::{Part, PartKind};

/// The image of a textured part.
#[derive(Clone, Debug, PartialEq)]
pub enum TextureImage {
    /// An image file: the material's path, resolved against the scene's folder.
    File(PathBuf),
    /// A checkerboard of 2×2 squares, `colors[0]` at the bottom left (linear colours).
    Checker([Color; 2]),
}

/// A part's texture: an image and a texture coordinate per vertex of the part's surface, as OBJ
/// has them (u along the image's rows, v upwards from its bottom row; it repeats).
#[derive(Clone, Debug, PartialEq)]
pub struct PartTexture {
    /// (u, v) per vertex.
    pub uv: Vec<[f64; 2]>,
    /// The image.
    pub image: TextureImage,
}

/// Pixels of a side of a checker image (two squares a side).
const CHECKER_PIXELS: u32 = 64;

impl TextureImage {
    /// The PNG bytes of a checker image (64×64 pixels, sRGB); `None` for a file, which is copied
    /// as it is.
    ///
    /// ```
    /// use orbifold_scene::texture::TextureImage;
    /// let png = TextureImage::Checker([[1.0; 3], [0.0; 3]]).checker_png().unwrap();
    /// assert_eq!(&png[1..4], b"PNG");
    /// ```
    pub fn checker_png(&self) -> Option<Vec<u8>> {
        let TextureImage::Checker(colors) = self else {
            return None;
        };
        let half = CHECKER_PIXELS / 2;
        let encode = colors.map(|c| c.map(crate::color::srgb8_from_linear));
        let image = image::RgbImage::from_fn(CHECKER_PIXELS, CHECKER_PIXELS, |x, y| {
            // Row 0 is the top: the bottom half is v ∈ [0, ½).
            let (i, j) = (x / half, 1 - y / half);
            image::Rgb(encode[((i + j) % 2) as usize])
        });
        let mut bytes = Vec::new();
        image
            .write_to(
                &mut std::io::Cursor::new(&mut bytes),
                image::ImageFormat::Png,
            )
            .ok()?;
        Some(bytes)
    }
}

/// The texture coordinates p of the renderer at an ambient point and height of a part, before
/// the material's scale: on a wall (length along it, height, 0); elsewhere the model's (x, y,
/// height), or the logarithm map at the polygon's centre in [`Space::tangent_frame`] there.
struct Coords<'a> {
    space: Space,
    centre: DVec3,
    frame: [DVec3; 2],
    layout: &'a Layout,
    mesher: &'a RoomMesher,
}

impl Coords<'_> {
    fn at(&self, kind: PartKind, intrinsic: bool, p: DVec3, h: f64) -> Option<[f64; 3]> {
        let space = self.space;
        match kind {
            PartKind::Wall(w) | PartKind::Mirror { wall: w, .. } => {
                Some([self.along_wall(w, p)?, h, 0.0])
            }
            _ if intrinsic => {
                let v = space.log(self.centre, p);
                Some([
                    space.point_dot(v, self.frame[0]),
                    space.point_dot(v, self.frame[1]),
                    h,
                ])
            }
            _ => {
                let z = space.to_model(p);
                Some([z.re, z.im, h])
            }
        }
    }

    /// The arc length along wall `w` from its first corner (or its cusp cut) to its point `p`:
    /// the renderer's wall coordinate, from the same mesher's start point.
    fn along_wall(&self, w: usize, p: DVec3) -> Option<f64> {
        let space = self.space;
        let start = self.mesher.wall_point(w, 0.0)?;
        // A point a quarter of the way gives the direction (half way round, the single wall of
        // `*` would reach the antipode).
        let toward = space.log(start, self.mesher.wall_point(w, 0.25)?);
        let tangent = toward / space.point_dot(toward, toward).sqrt();
        let s = space.geodesic_parameter(start, tangent, p);
        // As the renderer's room (orbifold_trace::room): a polygon without corners is one
        // closed wall, `*`, whose arc length runs on past the antipode.
        let closed = self.layout.vertices.is_empty();
        Some(if closed && s < 0.0 {
            s + std::f64::consts::TAU
        } else {
            s
        })
    }
}

impl Scene {
    /// The export texture of each part (`None` where it has none), for
    /// [`crate::geometry::RoomGeometry::groups`]. `base` resolves image file names.
    pub(crate) fn part_textures(
        &self,
        layout: &Layout,
        mesher: &RoomMesher,
        parts: &[Part],
        base: Option<&Path>,
    ) -> Vec<Option<PartTexture>> {
        let space = layout.space();
        let centre = space.to_ambient(layout.centre);
        let coords = Coords {
            space,
            centre,
            frame: space.tangent_frame(centre),
            layout,
            mesher,
        };
        parts
            .iter()
            .map(|part| self.part_texture(&coords, part, base))
            .collect()
    }

    fn part_texture(
        &self,
        coords: &Coords,
        part: &Part,
        base: Option<&Path>,
    ) -> Option<PartTexture> {
        let material = match part.kind {
            PartKind::Floor => &self.room.floor,
            PartKind::Ceiling => &self.room.ceiling,
            PartKind::Wall(w) => self.wall_material(w),
            PartKind::Mirror { .. } => return None,
            PartKind::Object(i) => &self.objects[i].material,
        };
        let surface = &part.surface;
        let points = |intrinsic: bool| -> Option<Vec<[f64; 3]>> {
            let mut p: Vec<[f64; 3]> = surface
                .points
                .iter()
                .zip(&surface.heights)
                .map(|(&p, &h)| coords.at(part.kind, intrinsic, p, h))
                .collect::<Option<_>>()?;
            if coords.layout.vertices.is_empty() && matches!(part.kind, PartKind::Wall(_)) {
                unwrap_closed_wall(&mut p, &surface.triangles);
            }
            Some(p)
        };
        match material {
            Material::Texture {
                path,
                scale,
                coordinates,
            } => {
                let p = points(*coordinates == Coordinates::Intrinsic)?;
                Some(PartTexture {
                    uv: p.iter().map(|q| [q[0] / scale, q[1] / scale]).collect(),
                    image: TextureImage::File(
                        base.map_or_else(|| PathBuf::from(path), |b| b.join(path)),
                    ),
                })
            }
            Material::Checker {
                colors,
                size,
                coordinates,
            } if !matches!(part.kind, PartKind::Object(_)) => {
                let p = points(*coordinates == Coordinates::Intrinsic)?;
                // The third coordinate is constant on the part: a floor's or ceiling's height,
                // 0 on a wall. An odd square there swaps the colours.
                let third = p.first().map_or(0.0, |q| (q[2] / size).floor());
                let odd = third.rem_euclid(2.0) == 1.0;
                Some(PartTexture {
                    uv: p
                        .iter()
                        .map(|q| [q[0] / (2.0 * size), q[1] / (2.0 * size)])
                        .collect(),
                    image: TextureImage::Checker(if odd {
                        [colors[1], colors[0]]
                    } else {
                        *colors
                    }),
                })
            }
            _ => None,
        }
    }
}

/// The single wall of `*` closes on itself: its last column of vertices lies where its first
/// does, at arc length 0, though it ends the wall at 2π. A triangle that spans more than half
/// the wall crosses that seam; its vertices near 0 are the closing ones, moved on by 2π (they
/// belong to no other triangles), so the texture runs on instead of back across the wall.
fn unwrap_closed_wall(p: &mut [[f64; 3]], triangles: &[[u32; 3]]) {
    let period = std::f64::consts::TAU;
    for t in triangles {
        let along = t.map(|i| p[i as usize][0]);
        let (lo, hi) = along
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), &a| {
                (lo.min(a), hi.max(a))
            });
        if hi - lo > 0.5 * period {
            for &i in t {
                if p[i as usize][0] < 0.5 * period {
                    p[i as usize][0] += period;
                }
            }
        }
    }
}
