//! One echo: a geodesic of the product space from the listener to an image of the source, with
//! its delay, its amplitude and the surfaces it reflects off.
//!
//! The floor and ceiling are the two planes h = 0 and h = H of the flat R factor, so their
//! images unfold as a shoebox's do in z (Allen & Berkley 1979): the source's image in the j-th
//! slab [jH, (j+1)H] is at height z_j = jH + h_s for even j and (j+1)H − h_s for odd j, and the
//! path to it crosses the |j| planes between, floors (even k·H) and ceilings (odd) alternating.
//! With the horizontal part of length σ ([`crate::path`]) the geodesic has length
//! ℓ = √(σ² + (z_j − h_l)²).
//!
//! Its pressure amplitude is that of a point source's spherical wave, 1/(4πr) in flat space,
//! with r² replaced by the area density of geodesic spheres J = ℓ²·S_κ(σ)/σ (ARCHITECTURE.md
//! §8; ℓ² in E²×R, where this is 1/(4πℓ)): energy spreads over J·dω, so pressure falls as
//! 1/√J (Kuttruff, *Room Acoustics*, §1.4, for the flat case). It is multiplied by the
//! reflection coefficient √(1 − α) of every surface met and, optionally, by the air's
//! attenuation, per octave band.
//!
//! **The focus at the antipode.** On the sphere S_κ(σ) = sin σ vanishes at σ = π, 2π, …: every
//! geodesic from the source meets again there, and a point listener would hear an infinite
//! pressure. A real listener of size a (`[sound] listener_size`) takes in the sound over its own
//! width, so the focus is taken as wide as the listener: |sin σ| is never less than sin(a/2R),
//! its value half a listener's width from the focus. Lengths shorter than half the listener are
//! likewise lengthened to it (a source at the listener's ear). Both keep every amplitude finite.

use orbifold::space::Space;
use orbifold_trace::room::RoomSurface;

use crate::absorption::{BANDS, Bands, air_factor, broadband, powi, times};

/// One echo.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Arrival {
    /// When it arrives, seconds after the sound starts.
    pub time: f64,
    /// Its path's length, metres.
    pub length: f64,
    /// Its pressure amplitude (broadband: the root mean square over the octave bands, exactly
    /// the common value when they agree), for a source whose sound would have amplitude 1/(4π)
    /// at one metre in free flat space.
    pub amplitude: f64,
    /// Its amplitude per octave band (125 Hz to 8 kHz).
    pub bands: [f32; BANDS],
    /// How many surfaces it reflects off.
    pub reflections: u32,
    /// Which horizontal path it takes (an index into [`crate::response::Response::paths`]).
    pub path: u32,
    /// The slab of its source image (0: the room itself; see the module documentation).
    pub slab: i32,
}

/// A surface that an echo reflects off.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Bounce {
    /// The floor, the ceiling or a wall.
    pub surface: RoomSurface,
    /// Whether it meets a mirror there (walls only).
    pub mirror: bool,
}

impl std::fmt::Display for Bounce {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match (self.surface, self.mirror) {
            (RoomSurface::Floor, _) => f.write_str("floor"),
            (RoomSurface::Ceiling, _) => f.write_str("ceiling"),
            (RoomSurface::Wall(i), true) => write!(f, "mirror {i}"),
            (RoomSurface::Wall(i), false) => write!(f, "wall {i}"),
        }
    }
}

/// The height of the source's image in slab `j`, and how many floors and ceilings the path to
/// it from the room (slab 0) crosses.
///
/// ```
/// use orbifold_sound::arrival::slab_image;
/// // Above the ceiling (H = 1): the source at 0.3 mirrored to 2 − 0.3, one ceiling.
/// assert_eq!(slab_image(1, 0.3, 1.0), (1.7, 0, 1));
/// // Below the floor: −0.3, one floor.
/// assert_eq!(slab_image(-1, 0.3, 1.0), (-0.3, 1, 0));
/// ```
pub fn slab_image(j: i32, source_height: f64, room_height: f64) -> (f64, u32, u32) {
    let jf = f64::from(j);
    let z = if j % 2 == 0 {
        jf * room_height + source_height
    } else {
        (jf + 1.0) * room_height - source_height
    };
    let m = j.unsigned_abs();
    // Planes k = 1…j above (odd: ceilings), k = 0…j+1 below (even: floors).
    let (floors, ceilings) = if j >= 0 {
        (m / 2, m.div_ceil(2))
    } else {
        (m.div_ceil(2), m / 2)
    };
    (z, floors, ceilings)
}

/// The height in the room of the unfolded height `u`.
pub fn fold_height(u: f64, room_height: f64) -> f64 {
    let period = 2.0 * room_height;
    let m = u.rem_euclid(period);
    if m <= room_height { m } else { period - m }
}

/// The area density J of geodesic spheres at length ℓ with horizontal length σ
/// (intrinsic units), with the focus at the sphere's antipodes as wide as `focus`
/// (see the module documentation).
///
/// ```
/// use orbifold::{Geometry, space::Space};
/// use orbifold_sound::arrival::spread;
/// let h2 = Space::new(Geometry::Hyperbolic);
/// assert!((spread(h2, 2.0, 2.0, 0.01) - 2.0 * 2f64.sinh()).abs() < 1e-12);
/// let s2 = Space::new(Geometry::Spherical);
/// // At the antipode: finite.
/// assert!(spread(s2, std::f64::consts::PI, std::f64::consts::PI, 0.01) > 0.0);
/// ```
pub fn spread(space: Space, length: f64, sigma: f64, focus: f64) -> f64 {
    let length = length.max(focus);
    let ratio = if sigma < 1e-8 {
        1.0 - space.kappa() * sigma * sigma / 6.0
    } else if space.kappa() > 0.0 {
        // |sin σ| is the sine of the distance to the nearest focus (σ = kπ).
        let to_focus =
            (sigma - std::f64::consts::PI * (sigma / std::f64::consts::PI).round()).abs();
        let near = if sigma > 0.5 * std::f64::consts::PI {
            to_focus.max(focus)
        } else {
            to_focus
        };
        near.sin() / sigma
    } else {
        space.sin(sigma) / sigma
    };
    length * length * ratio
}

/// What an echo's amplitude is made of.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Echo {
    /// Intrinsic length and horizontal length.
    pub length: f64,
    pub sigma: f64,
    /// Reflection coefficients of the walls met, per band.
    pub walls: Bands,
    /// Floors and ceilings crossed.
    pub floors: u32,
    pub ceilings: u32,
}

/// The amplitude per band of an echo, and its broadband amplitude.
pub(crate) fn amplitude(
    space: Space,
    settings: &crate::settings::Settings,
    echo: &Echo,
) -> (Bands, f64) {
    let r = settings.metres_per_unit;
    let focus = 0.5 * settings.listener_size / r;
    let j = spread(space, echo.length, echo.sigma, focus) * r * r;
    let spreading = 1.0 / (4.0 * std::f64::consts::PI * j.sqrt());
    let surfaces = times(
        &echo.walls,
        &times(
            &powi(&settings.reflection.floor, echo.floors),
            &powi(&settings.reflection.ceiling, echo.ceilings),
        ),
    );
    let air = air_factor(echo.length * r, settings.air);
    let bands = times(&surfaces, &air).map(|x| x * spreading);
    (bands, broadband(&bands))
}
