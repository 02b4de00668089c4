//! Hear an orbifold: the echoes of a mirror room along the geodesics of S²×R, E²×R and H²×R,
//! as an impulse response (docs/sound.md).
//!
//! In a room whose walls reflect, the echoes of a sound are the mirror images of its source, as
//! a light's are ([`image_source`]): the image-source method of Allen & Berkley ("Image method
//! for efficiently simulating small-room acoustics", J. Acoust. Soc. Am. 65(4), 1979), with the
//! room's reflection group in place of a shoebox's. Each echo's delay is the length of its
//! geodesic over the speed of sound; its pressure falls as 1/√J with the area density J of
//! geodesic spheres, and by the reflection coefficient √(1 − α) of every surface it meets
//! ([`arrival`]; Kuttruff, *Room Acoustics*, 6th ed., 2016). A `*2222` room sounds like a
//! shoebox; a hyperbolic room thins its echoes out exponentially; a spherical one refocuses them
//! at the antipode and brings them back round the sphere.
//!
//! One concept per module: the `[sound]` table's values ([`settings`]), absorption
//! ([`absorption`]), the cover's tiles ([`image_source`]), an echo's horizontal path through the
//! walls ([`path`]), an echo ([`arrival`]), all echoes ([`response`]), a scene heard
//! ([`hearing`]), the signal ([`impulse`], [`octave_filter`]), WAV files ([`wav`]), convolution
//! ([`convolve`]), a built-in clap ([`clap`]) and the echogram ([`echogram`]).
//!
//! ```
//! use orbifold_scene::Scene;
//! use orbifold_sound::Hearing;
//! let mut scene = Scene::default();
//! scene.orbifold.signature = "*444".into();
//! scene.objects.clear();
//! // The camera (the listener) and the light (the source) inside this smaller room.
//! scene.camera.at = [0.1, 0.0];
//! scene.lights[0].at = [-0.05, 0.05];
//! scene.sound.seconds = 0.2;
//! let hearing = Hearing::from_scene(&scene, None)?;
//! let response = hearing.mono(&|_, _| {});
//! let ir = hearing.samples(&response);
//! assert_eq!(ir.len(), 9600);
//! assert!(response.arrivals.windows(2).all(|w| w[0].time <= w[1].time));
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

pub mod absorption;
pub mod arrival;
pub mod clap;
pub mod convolve;
pub mod echogram;
pub mod error;
pub mod hearing;
pub mod image_source;
pub mod impulse;
pub mod octave_filter;
pub mod path;
pub mod response;
pub mod settings;
pub mod wav;

pub use arrival::{Arrival, Bounce};
pub use error::SoundError;
pub use hearing::Hearing;
pub use response::Response;
