//! Mirror-room scenes: the document that the command line, the renderer, the preview and the
//! studio all read and write — the orbifold and its layout, the room (height, mirrors,
//! materials), objects, lights, the camera, render settings and the sound (`[sound]`) — its TOML file format
//! (`docs/scene-format.md`), and its validation, with errors that give file, line, column and key.
//! See ARCHITECTURE.md §7.
//!
//! ```
//! use orbifold_scene::Scene;
//! let scene = Scene::default();
//! assert_eq!(scene.orbifold.signature, "*22222");
//! let text = scene.to_toml();
//! assert_eq!(Scene::from_toml(&text, None).unwrap(), scene);
//! ```

pub mod animation;
pub mod base64;
pub mod color;
pub mod document;
pub mod export;
pub mod file;
pub mod files;
pub mod geometry;
pub mod mesh;
pub mod part;
pub mod placement;
pub mod sound;
pub mod texture;
pub mod validate;

pub use document::*;
pub use file::{SceneError, write_atomic};
pub use orbifold;
