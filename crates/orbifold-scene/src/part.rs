//! The named parts of a meshed room — floor, ceiling, plain wall strips, mirrors, objects —
//! each an intrinsically flat triangle mesh with what exports and the preview need to know of
//! it (name, kind, representative colour, reflectance, crease angle).

use orbifold::room::Surface;

use crate::document::Color;

/// What a part of the room is.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PartKind {
    /// The floor.
    Floor,
    /// The ceiling.
    Ceiling,
    /// The parts of a wall without a mirror.
    Wall(usize),
    /// Mirror `mirror` of wall `wall`.
    Mirror {
        /// The wall's index.
        wall: usize,
        /// The mirror's index on it.
        mirror: usize,
    },
    /// Object `i` of the scene.
    Object(usize),
}

/// One named part of the room's geometry.
#[derive(Clone, Debug, PartialEq)]
pub struct Part {
    /// `floor`, `ceiling`, `wall 0`, `mirror 0.1`, or an object's name.
    pub name: String,
    /// What it is.
    pub kind: PartKind,
    /// A representative colour (a checkerboard's mean, grey for a texture).
    pub color: Color,
    /// For a mirror, its reflectance.
    pub reflectance: Option<Color>,
    /// The crease angle of its smooth shading, in degrees: an object's own, [`ROOM_CREASE`]
    /// for the room's parts.
    pub crease: f64,
    /// The mesh.
    pub surface: Surface,
}

/// The crease angle (degrees) of the room's own parts: each is smooth within itself (a floor,
/// a ceiling, a wall's strip), so any angle well below the walls' corners does.
pub const ROOM_CREASE: f64 = 60.0;
