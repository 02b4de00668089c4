//! The mirror copies of the room: one per element of the reflection group up to a word length,
//! each with the brightness its attenuation setting gives it (seed Fig. 8.6).
//!
//! In a real mirror room a copy is seen through the mirrors its light crossed, so it is as bright
//! as the product of their reflectances. The preview gives each copy the product along one
//! reduced word of its group element (the walls crossed, in order, by a gallery from the room).
//! Where two walls meet at an odd corner, a line of the tiling is made of copies of both, so
//! rays to one copy may cross different mirrors; the preview's brightness is then that of one
//! of them, which is what a preview needs.

use glam::{DMat3, DVec3};
use orbifold::cover::{Bound, Cover, CoverError, Tile, reflection};
use orbifold::pairing::FundamentalPolygon;
use orbifold::pairing::cover::GroupCover;
use orbifold::{Geometry, Layout};
use orbifold_scene::{Attenuation, Color};

/// How faint the copies that an emphasis setting plays down are.
pub const FAINT: f64 = 0.22;

/// One copy of the room.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Copy {
    /// The group element, as a 3×3 matrix on ambient coordinates.
    pub matrix: DMat3,
    /// Its word length (0 for the room itself).
    pub depth: u32,
    /// Whether it is a mirror image (odd word length).
    pub reflected: bool,
    /// Its brightness per colour channel.
    pub tint: Color,
}

/// Every copy of the room up to word length `depth` (every copy for a finite spherical group,
/// whatever the depth), tinted by `attenuation`. `reflectances[i]` is what wall i's mirrors
/// reflect (1 for a wall without a mirror, whose copies it hides anyway).
///
/// ```
/// use orbifold::{Layout, LayoutOptions};
/// use orbifold_preview::copies::copies;
/// use orbifold_scene::Attenuation;
/// let layout = Layout::new(&"*2222222".parse()?, &LayoutOptions::default())?;
/// let all = copies(&layout, 2, &[[0.5; 3]; 7], Attenuation::Reflectance)?;
/// assert_eq!(all.len(), 1 + 7 + 35);
/// // Two reflections at 0.5 each.
/// assert!(all.iter().filter(|c| c.depth == 2).all(|c| (c.tint[0] - 0.25).abs() < 1e-12));
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn copies(
    layout: &Layout,
    depth: u32,
    reflectances: &[Color],
    attenuation: Attenuation,
) -> Result<Vec<Copy>, CoverError> {
    let bound = match layout.space().geometry() {
        Geometry::Spherical => Bound::All,
        _ => Bound::Depth(depth as usize),
    };
    let Some(signature) = layout.signature() else {
        return group_copies(layout, bound, reflectances, attenuation);
    };
    if signature.kind() != orbifold::Kind::Orbifold {
        return Ok(images(layout, depth, reflectances, attenuation));
    }
    let cover = Cover::enumerate_layout(layout.clone(), bound, true)?;
    let words = Words::new(layout);
    Ok(cover
        .tiles
        .iter()
        .map(|tile| Copy {
            matrix: tile.matrix,
            depth: tile.depth,
            reflected: tile.reflected,
            tint: tint(&words, tile, reflectances, attenuation),
        })
        .collect())
}

/// The copies of a room whose walls include portals: the tiles of its group (cone points,
/// glides, handles, cross-caps), from the certified enumeration of
/// [`GroupCover`](orbifold::pairing::cover::GroupCover). `reflectances[i]` is what wall i
/// passes on: its mirrors' reflectance, or its portal's transmittance.
fn group_copies(
    layout: &Layout,
    bound: Bound,
    reflectances: &[Color],
    attenuation: Attenuation,
) -> Result<Vec<Copy>, CoverError> {
    let polygon = FundamentalPolygon::from_layout(layout.symbol.clone(), layout.clone());
    let cover = GroupCover::enumerate_polygon(polygon, bound, true)?;
    let words = Words::new(layout);
    Ok(cover
        .tiles
        .iter()
        .map(|tile| {
            let as_tile = Tile {
                matrix: tile.matrix,
                depth: tile.depth,
                reflected: tile.reflected,
                wall: tile.edge,
            };
            Copy {
                matrix: tile.matrix,
                depth: tile.depth,
                reflected: tile.reflected,
                tint: tint(&words, &as_tile, reflectances, attenuation),
            }
        })
        .collect())
}

/// The most images drawn of a room that is not an orbifold.
pub const MAX_IMAGES: usize = 20_000;

/// The mirror images of a room that is not an orbifold (a corner order that is not an integer):
/// its walls generate no discrete group, so there is no cover to enumerate. Instead every word
/// in the walls without a letter repeated next to itself, up to `depth` letters (at most
/// [`MAX_IMAGES`] images), is an image, as the mirrors show it along that sequence of
/// reflections. The images overlap: that is what the preview lets a person see of a
/// non-orbifold (seed Fig. 8.9).
fn images(
    layout: &Layout,
    depth: u32,
    reflectances: &[Color],
    attenuation: Attenuation,
) -> Vec<Copy> {
    let space = layout.space();
    let reflections: Vec<DMat3> = layout
        .edges
        .iter()
        .map(|e| reflection(space, e.wall))
        .collect();
    let room = Copy {
        matrix: DMat3::IDENTITY,
        depth: 0,
        reflected: false,
        tint: [1.0; 3],
    };
    let mut out = vec![room];
    // (copy, last wall crossed)
    let mut layer = vec![(room, usize::MAX)];
    for d in 1..=depth {
        let mut next = Vec::new();
        for (copy, last) in &layer {
            for (w, r) in reflections.iter().enumerate() {
                if w == *last || out.len() + next.len() >= MAX_IMAGES {
                    continue;
                }
                let factor = match attenuation {
                    Attenuation::Reflectance => reflectances.get(w).copied().unwrap_or([1.0; 3]),
                    _ => [1.0; 3],
                };
                let reflected = d % 2 == 1;
                let tint = match attenuation {
                    Attenuation::Orbifold => [FAINT; 3],
                    Attenuation::Translations if reflected => [FAINT; 3],
                    Attenuation::Translations | Attenuation::Universal => [1.0; 3],
                    Attenuation::Reflectance => [0, 1, 2].map(|k| copy.tint[k] * factor[k]),
                };
                next.push((
                    Copy {
                        matrix: copy.matrix * *r,
                        depth: d,
                        reflected,
                        tint,
                    },
                    w,
                ));
            }
        }
        out.extend(next.iter().map(|(c, _)| *c));
        layer = next;
    }
    out
}

/// The brightness of a tile under an attenuation setting.
fn tint(words: &Words, tile: &Tile, reflectances: &[Color], attenuation: Attenuation) -> Color {
    let faint = [FAINT; 3];
    match attenuation {
        Attenuation::Universal => [1.0; 3],
        Attenuation::Orbifold if tile.depth > 0 => faint,
        Attenuation::Translations if tile.reflected => faint,
        Attenuation::Orbifold | Attenuation::Translations => [1.0; 3],
        Attenuation::Reflectance => words.word(tile).iter().fold([1.0; 3], |acc, &wall| {
            let r = reflectances.get(wall as usize).copied().unwrap_or([1.0; 3]);
            [acc[0] * r[0], acc[1] * r[1], acc[2] * r[2]]
        }),
    }
}

/// Reduced words of tiles, found by walking back to the room across descents.
///
/// ```
/// use orbifold::cover::{Bound, Cover};
/// use orbifold_preview::copies::Words;
/// let cover = Cover::enumerate(&"*333".parse()?, Bound::Depth(3), true)?;
/// let words = Words::new(&cover.layout);
/// assert!(cover.tiles.iter().all(|t| words.word(t).len() == t.depth as usize));
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub struct Words {
    walls: Vec<DVec3>,
    /// The generators: the reflection in each mirror wall, the pairing of each portal.
    neighbours: Vec<DMat3>,
    kappa: f64,
    /// An interior point of the room (ambient).
    centre: DVec3,
}

impl Words {
    /// The word finder for the group of a polygon's walls and pairings.
    pub fn new(layout: &Layout) -> Words {
        let space = layout.space();
        let walls: Vec<DVec3> = layout.edges.iter().map(|e| e.wall).collect();
        Words {
            neighbours: layout.edges.iter().map(|e| e.neighbour).collect(),
            walls,
            kappa: space.kappa(),
            centre: space.to_ambient(layout.centre),
        }
    }

    /// The walls crossed from the room to `tile`, last first: the tile's own `wall`, then at
    /// each step a wall of the current tile with the room's centre on its far side. The tile's
    /// matrix is the product of the reflections in these walls of the room, the first
    /// letter rightmost.
    pub fn word(&self, tile: &Tile) -> Vec<u32> {
        let mut letters = Vec::with_capacity(tile.depth as usize);
        let mut m = tile.matrix;
        let mut next = tile.wall;
        for _ in 0..tile.depth {
            let Some(wall) = next.or_else(|| self.descent(&m)) else {
                break;
            };
            letters.push(wall);
            // Across wall i of the tile m lies the tile m·gᵢ (gᵢ the reflection or pairing).
            m *= self.neighbours[wall as usize];
            next = None;
        }
        letters
    }

    /// The wall of the tile `m` that is most clearly between it and the room.
    fn descent(&self, m: &DMat3) -> Option<u32> {
        let inverse = if self.kappa == 0.0 {
            m.inverse()
        } else {
            let g = DMat3::from_diagonal(DVec3::new(1.0, 1.0, self.kappa));
            g * m.transpose() * g
        };
        let q = inverse * self.centre;
        self.walls
            .iter()
            .enumerate()
            .map(|(i, nu)| (i, nu.dot(q)))
            .filter(|&(_, v)| v < 0.0)
            .min_by(|a, b| a.1.total_cmp(&b.1))
            .map(|(i, _)| i as u32)
    }
}
