//! What a caller chooses and learns about the preview, and the fixed constants of its frames.
//!
//! [`Settings`] are the choices apart from the scene and the camera (depth, attenuation of the
//! seed's Fig. 8.6, projection, culling, turns round the sphere, levels of detail); [`Stats`] is
//! what the last frame drew. The constants fix the images' formats, the antialiasing and the
//! lighting; they are kept together because the shader, the render targets and the tests all
//! depend on the same values.

use orbifold_scene::{Attenuation, Scene};

use crate::projection::Projection;

/// The largest number of parts (objects, floor, ceiling, walls and mirrors) a scene may have:
/// the length of the shader's part table, a uniform array of fixed size.
pub const MAX_PARTS: usize = 256;

/// The colour format of the preview's image.
pub const COLOR_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba8UnormSrgb;

/// Samples a pixel of the colour picture on a GPU (multisample antialiasing); software
/// adapters take one, as multisampling on the CPU multiplies the time of a frame.
pub const GPU_SAMPLES: u32 = 4;

/// The near clipping distance: how close to the eye a surface may come before it is cut away
/// (intrinsic units).
pub(super) const NEAR: f64 = 0.005;

/// The background colour (linear RGB): what lies beyond the copies drawn.
pub const BACKGROUND: [f64; 3] = [0.012, 0.014, 0.02];

/// The ambient term of the shading: the share of light every surface gets whatever its angle
/// to the eye.
pub(super) const AMBIENT: f32 = 0.3;

/// What the preview shows, apart from the scene and the camera.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Settings {
    /// How many reflections deep the copies go (the whole group in S²×R).
    pub depth: u32,
    /// How copies fade (seed Fig. 8.6).
    pub attenuation: Attenuation,
    /// Curved or straight projection.
    pub projection: Projection,
    /// Whether copies that cannot be in view are skipped.
    pub cull: bool,
    /// In S²×R, how many times round the sphere the images go (see
    /// [`View::with_turns`](crate::projection::View::with_turns)).
    pub turns: u32,
    /// Whether far copies draw their objects with fewer triangles (levels of detail).
    pub lod: bool,
}

impl Settings {
    /// The settings a scene's `[preview]` section gives.
    pub fn of_scene(scene: &Scene) -> Settings {
        Settings {
            depth: scene.preview.depth,
            attenuation: scene.preview.attenuation,
            projection: Projection::Curved,
            cull: true,
            turns: DEFAULT_TURNS,
            lod: true,
        }
    }
}

/// Turns round the sphere drawn by default: every floor and ceiling seen more than about 2°
/// from level in a room of height 1.
pub const DEFAULT_TURNS: u32 = 3;

/// What the last frame drew.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Stats {
    /// Copies of the room up to the depth (the room itself included).
    pub copies: usize,
    /// Instances drawn: copies in view, times the images of each point (two in S²×R).
    pub instances: usize,
    /// Triangles of one copy of the room with its objects.
    pub triangles_per_copy: usize,
    /// Triangles drawn: instances times triangles per copy.
    pub triangles: usize,
}
