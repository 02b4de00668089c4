//! The values of a scene's `[sound]` table that hearing a room needs, resolved: absorption per
//! band for each kind of surface, and where the source and the listener are (by default at the
//! first light and at the camera). See docs/scene-format.md.

use glam::DVec3;
use num_complex::Complex64;
use orbifold::space::Space;
use orbifold_scene::Scene;
use orbifold_scene::sound::Sound;

use crate::absorption::{Bands, reflection};

/// A point of the room: ambient horizontal position and height (intrinsic units).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Point {
    /// Ambient coordinates of the horizontal position (ARCHITECTURE.md §3).
    pub at: DVec3,
    /// Height above the floor.
    pub height: f64,
}

impl Point {
    /// The point at a model position and height.
    ///
    /// ```
    /// use orbifold::{Geometry, space::Space};
    /// use orbifold_sound::settings::Point;
    /// let p = Point::from_model(Space::new(Geometry::Euclidean), [0.5, 0.0], 0.3);
    /// assert_eq!((p.at.x, p.height), (1.0, 0.3));
    /// ```
    pub fn from_model(space: Space, at: [f64; 2], height: f64) -> Point {
        Point {
            at: space.to_ambient(Complex64::new(at[0], at[1])),
            height,
        }
    }
}

/// The pressure reflection coefficient √(1 − α) per band of each kind of surface.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Reflection {
    /// A wall where it has a mirror.
    pub mirror: Bands,
    /// A wall where it has none.
    pub wall: Bands,
    /// The floor.
    pub floor: Bands,
    /// The ceiling.
    pub ceiling: Bands,
}

/// What hearing a room needs, in the units of the response.
///
/// ```
/// use orbifold_scene::Scene;
/// use orbifold_sound::settings::Settings;
/// let settings = Settings::from_sound(&Scene::default().sound);
/// assert_eq!(settings.sample_rate, 48_000);
/// // Mirrors (α = 0.05) reflect more than plain walls (α = 0.25).
/// assert!(settings.reflection.mirror[0] > settings.reflection.wall[0]);
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Settings {
    /// Metres per intrinsic unit (the curvature radius in S² and H²).
    pub metres_per_unit: f64,
    /// Speed of sound, metres per second.
    pub speed: f64,
    /// Samples per second.
    pub sample_rate: u32,
    /// Length of the response, seconds.
    pub seconds: f64,
    /// The quietest echo kept, as a pressure amplitude (the direct sound at one metre is
    /// 1/(4π)).
    pub min_amplitude: f64,
    /// The listener's size, metres.
    pub listener_size: f64,
    /// The distance between the ears of a stereo response, metres.
    pub ear_distance: f64,
    /// Whether the air absorbs.
    pub air: bool,
    /// Reflection coefficients.
    pub reflection: Reflection,
}

impl Settings {
    /// The settings of a `[sound]` table (validated with the scene).
    pub fn from_sound(sound: &Sound) -> Settings {
        Settings {
            metres_per_unit: sound.metres_per_unit,
            speed: sound.speed,
            sample_rate: sound.sample_rate,
            seconds: sound.seconds,
            min_amplitude: 10f64.powf(sound.min_level / 20.0) / (4.0 * std::f64::consts::PI),
            listener_size: sound.listener_size,
            ear_distance: sound.ear_distance,
            air: sound.air,
            reflection: Reflection {
                mirror: reflection(&sound.mirror_absorption.bands()),
                wall: reflection(&sound.wall_absorption.bands()),
                floor: reflection(&sound.floor_absorption.bands()),
                ceiling: reflection(&sound.ceiling_absorption.bands()),
            },
        }
    }

    /// The longest path a response of this length can hear, in intrinsic units.
    pub fn reach(&self) -> f64 {
        self.seconds * self.speed / self.metres_per_unit
    }
}

/// Where the sound starts and where it is heard in a scene: `[sound]`'s `source` and
/// `listener`, or by default the first light (else the room's centre, half way up) and the
/// camera.
///
/// ```
/// use orbifold_scene::Scene;
/// use orbifold_sound::settings::places;
/// let scene = Scene::default();
/// let (source, listener) = places(&scene).unwrap();
/// assert_eq!(source.height, scene.lights[0].height);
/// assert_eq!(listener.height, scene.camera.height);
/// ```
pub fn places(scene: &Scene) -> Result<(Point, Point), String> {
    let layout = scene.layout()?;
    let space = layout.space();
    let source = match (scene.sound.source, scene.lights.first()) {
        (Some(p), _) => Point::from_model(space, p.at, p.height),
        (None, Some(light)) => Point::from_model(space, light.at, light.height),
        (None, None) => Point::from_model(
            space,
            [layout.centre.re, layout.centre.im],
            0.5 * scene.room.height,
        ),
    };
    let listener = match scene.sound.listener {
        Some(p) => Point::from_model(space, p.at, p.height),
        None => Point::from_model(space, scene.camera.at, scene.camera.height),
    };
    Ok((source, listener))
}
