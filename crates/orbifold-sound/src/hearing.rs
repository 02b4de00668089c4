//! A scene, heard: its room with the `[sound]` table's settings, the source and the listener,
//! and the responses at one ear or at two.

use std::path::Path;

use glam::DVec3;
use num_complex::Complex64;
use orbifold_scene::Scene;
use orbifold_trace::room::AnalyticRoom;

use crate::error::SoundError;
use crate::impulse::impulse_response;
use crate::response::{Listening, Response};
use crate::settings::{Point, Settings, places};

/// Everything needed to hear a scene's room.
///
/// ```
/// use orbifold_scene::Scene;
/// use orbifold_sound::Hearing;
/// let mut scene = Scene::default();
/// scene.orbifold.signature = "*2222".into();
/// scene.sound.seconds = 0.1;
/// let hearing = Hearing::from_scene(&scene, None)?;
/// let response = hearing.mono(&|_, _| {});
/// assert!(response.arrivals.len() > 10);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
#[derive(Clone, Debug)]
pub struct Hearing {
    /// The room, with its mirrors.
    pub room: AnalyticRoom,
    /// The room's centre (ambient).
    pub centre: DVec3,
    /// The settings.
    pub settings: Settings,
    /// The source.
    pub source: Point,
    /// The listener (the middle of the head).
    pub listener: Point,
    /// The unit tangent at the listener towards the right ear (the camera's right axis).
    pub right: DVec3,
    /// The scene's signature, for titles.
    pub signature: String,
}

impl Hearing {
    /// The room, settings, source and listener of a scene, which is checked first; `base` is
    /// the folder its mesh and texture paths are relative to (the scene file's).
    pub fn from_scene(scene: &Scene, base: Option<&Path>) -> Result<Hearing, SoundError> {
        if let Err(errors) = scene.check(base) {
            let all: Vec<String> = errors.iter().map(ToString::to_string).collect();
            return Err(SoundError::Scene(all.join("; ")));
        }
        let layout = scene.layout().map_err(SoundError::Scene)?;
        let room = AnalyticRoom::from_scene(scene, &layout).map_err(SoundError::Scene)?;
        // A mirror hung on a portal would send sound back where the group's images send it on.
        if let Some(wall) = room
            .walls
            .iter()
            .position(|w| w.portal.is_some() && !w.mirrors.is_empty())
        {
            return Err(SoundError::Scene(format!(
                "wall {wall} of {} is a portal with a mirror hung on it; sound is heard through \
                 bare portals only (take the mirror off, or hang it on a mirror wall)",
                layout.symbol
            )));
        }
        let space = room.space;
        let (source, listener) = places(scene).map_err(SoundError::Scene)?;
        let [_, right, _] = scene.camera.basis();
        let z = space.to_model(listener.at);
        let t = space.model_tangent(z, Complex64::new(right.x, right.y));
        let n = space.point_dot(t, t).max(0.0).sqrt();
        let right = if n > 0.0 {
            t / n
        } else {
            space.tangent_frame(listener.at)[1]
        };
        Ok(Hearing {
            centre: space.to_ambient(layout.centre),
            room,
            settings: Settings::from_sound(&scene.sound),
            source,
            listener,
            right,
            signature: scene.orbifold.signature.clone(),
        })
    }

    fn listening(&self) -> Listening<'_> {
        Listening {
            room: &self.room,
            centre: self.centre,
            settings: &self.settings,
        }
    }

    /// The response at the listener.
    pub fn mono(&self, progress: &(dyn Fn(usize, usize) + Sync)) -> Response {
        self.listening()
            .response(self.source, self.listener, progress)
    }

    /// The two ears: half the ear distance either side of the listener along the camera's
    /// right axis, left first.
    pub fn ears(&self) -> [Point; 2] {
        let space = self.room.space;
        let half = 0.5 * self.settings.ear_distance / self.settings.metres_per_unit;
        [-half, half].map(|offset| Point {
            at: space.exp(self.listener.at, self.right * offset),
            height: self.listener.height,
        })
    }

    /// The responses at the left and the right ear. `progress(done, total)` counts both.
    pub fn stereo(&self, progress: &(dyn Fn(usize, usize) + Sync)) -> [Response; 2] {
        let [left, right] = self.ears();
        let listening = self.listening();
        let l = listening.response(self.source, left, &|d, t| progress(d, 2 * t));
        let r = listening.response(self.source, right, &|d, t| progress(t + d, 2 * t));
        [l, r]
    }

    /// A response as samples at the settings' rate and length.
    pub fn samples(&self, response: &Response) -> Vec<f32> {
        impulse_response(
            &response.arrivals,
            self.settings.sample_rate,
            self.settings.seconds,
        )
    }
}
