//! The scene's `[sound]` table: what `orbifold listen` and the studio's *listen* button need to
//! hear the room (docs/scene-format.md, docs/sound.md). Every field has a default, so a scene
//! without the table is heard in a room of four-metre units with hard mirrors and softer walls.

use serde::{Deserialize, Serialize};

/// The centre frequencies of the octave bands in which absorption may be given, in hertz.
pub const OCTAVE_BANDS: [f64; 7] = [125.0, 250.0, 500.0, 1000.0, 2000.0, 4000.0, 8000.0];

/// How much of the sound's energy a surface absorbs on each reflection (α, from 0 to 1): one
/// value for every frequency, or one per octave band of [`OCTAVE_BANDS`].
///
/// ```
/// use orbifold_scene::sound::Absorption;
/// assert_eq!(Absorption::Flat(0.2).bands(), [0.2; 7]);
/// let error = orbifold_scene::Scene::from_toml("[sound]\nwall_absorption = [0.1, 0.2]\n", None)
///     .unwrap_err();
/// assert!(error[0].message.contains("seven absorption coefficients"), "{}", error[0]);
/// ```
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
#[serde(untagged)]
pub enum Absorption {
    /// The same α at every frequency.
    Flat(f64),
    /// α per octave band, 125 Hz to 8 kHz.
    Bands([f64; 7]),
}

impl Absorption {
    /// α per octave band.
    pub fn bands(&self) -> [f64; 7] {
        match *self {
            Absorption::Flat(a) => [a; 7],
            Absorption::Bands(b) => b,
        }
    }
}

impl<'de> Deserialize<'de> for Absorption {
    /// A number, or an array of seven, with a message that says so for anything else.
    fn deserialize<D: serde::Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        deserializer.deserialize_any(AbsorptionVisitor)
    }
}

struct AbsorptionVisitor;

impl<'de> serde::de::Visitor<'de> for AbsorptionVisitor {
    type Value = Absorption;

    fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
        f.write_str(
            "an absorption coefficient from 0 to 1, or seven, one per octave band from 125 Hz to 8 kHz",
        )
    }

    fn visit_f64<E: serde::de::Error>(self, v: f64) -> Result<Absorption, E> {
        Ok(Absorption::Flat(v))
    }

    fn visit_i64<E: serde::de::Error>(self, v: i64) -> Result<Absorption, E> {
        Ok(Absorption::Flat(v as f64))
    }

    fn visit_u64<E: serde::de::Error>(self, v: u64) -> Result<Absorption, E> {
        Ok(Absorption::Flat(v as f64))
    }

    fn visit_seq<A: serde::de::SeqAccess<'de>>(self, mut seq: A) -> Result<Absorption, A::Error> {
        let mut values = Vec::new();
        while let Some(v) = seq.next_element::<f64>()? {
            values.push(v);
        }
        let count = values.len();
        <[f64; 7]>::try_from(values).map(Absorption::Bands).map_err(|_| {
            serde::de::Error::custom(format!(
                "expected seven absorption coefficients, one per octave band from 125 Hz to 8 kHz, not {count}"
            ))
        })
    }
}

/// A point of the room: a model position and a height above the floor (intrinsic units).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Place {
    /// Model position.
    pub at: [f64; 2],
    /// Height above the floor.
    pub height: f64,
}

/// The `[sound]` table.
///
/// ```
/// use orbifold_scene::Scene;
/// let text = "[sound]\nmetres_per_unit = 3.0\nwall_absorption = [0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.7]\n";
/// let scene = Scene::from_toml(text, None).unwrap();
/// assert_eq!(scene.sound.metres_per_unit, 3.0);
/// let errors = Scene::from_toml("[sound]\nspeed = -1\n", None).unwrap_err();
/// assert_eq!(errors[0].position, Some((2, 9)));
/// ```
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct Sound {
    /// Metres per intrinsic unit: the curvature radius in S² and H² (in E², the room's scale).
    pub metres_per_unit: f64,
    /// Speed of sound, metres per second.
    pub speed: f64,
    /// Samples per second of the impulse response.
    pub sample_rate: u32,
    /// Length of the impulse response, seconds.
    pub seconds: f64,
    /// Echoes quieter than this many decibels below the direct sound at one metre are left out
    /// (a negative number).
    pub min_level: f64,
    /// The listener's size in metres: the width of the focus at the antipode of the sphere,
    /// where geodesics from the source meet again and the spreading J vanishes.
    pub listener_size: f64,
    /// Distance between the two ears of a stereo response, metres.
    pub ear_distance: f64,
    /// Air absorption (ISO 9613-1 at 20 °C and 50 % humidity), per octave band.
    pub air: bool,
    /// Where the sound starts; by default at the first light (else the room's centre, half way
    /// up).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub source: Option<Place>,
    /// Where it is heard; by default at the camera.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub listener: Option<Place>,
    /// Absorption of a wall where it has a mirror.
    pub mirror_absorption: Absorption,
    /// Absorption of a wall where it has no mirror.
    pub wall_absorption: Absorption,
    /// Absorption of the floor.
    pub floor_absorption: Absorption,
    /// Absorption of the ceiling.
    pub ceiling_absorption: Absorption,
}

impl Sound {
    /// Whether every field has its default (the table is then left out of saved scenes).
    pub fn is_default(&self) -> bool {
        *self == Sound::default()
    }
}

impl Default for Sound {
    fn default() -> Self {
        Sound {
            metres_per_unit: 4.0,
            speed: 343.0,
            sample_rate: 48_000,
            seconds: 2.0,
            min_level: -60.0,
            listener_size: 0.1,
            ear_distance: 0.18,
            air: false,
            source: None,
            listener: None,
            // Glass is acoustically hard; plaster and wood absorb more (Kuttruff, Room
            // Acoustics, table of absorption coefficients, mid frequencies).
            mirror_absorption: Absorption::Flat(0.05),
            wall_absorption: Absorption::Flat(0.25),
            floor_absorption: Absorption::Flat(0.1),
            ceiling_absorption: Absorption::Flat(0.25),
        }
    }
}
