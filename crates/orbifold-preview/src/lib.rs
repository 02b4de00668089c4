//! The real-time rasteriser (wgpu) that draws a mirror room and its mirror copies with the
//! non-Euclidean projection (ARCHITECTURE.md §9, seed §6.3 and §8.1.1.1).
//!
//! Mirrors are not traced: every copy of the room under the reflection group, up to a word
//! length, is drawn as a GPU instance carrying its group element and the product of the mirrors'
//! reflectances along its word, and the vertex shader maps each vertex by the logarithm map of
//! S²×R, E²×R or H²×R at the eye before an ordinary perspective projection. What a person inside
//! the mirror room would see is then what the rasteriser draws, with no ray tracing.
//!
//! - [`projection`]: the projection on the CPU (the shader's twin), for tests and picking.
//! - [`copies`]: the copies of the room and their brightness.
//! - [`mesh`]: the room and objects as vertex buffers and the part table.
//! - [`textures`]: the scene's image files, one layer each of the GPU's array texture.
//! - [`Preview`]: the renderer; [`Gpu`]: the device it draws on; [`Frame`]: what it returns.
//!
//! ```no_run
//! use orbifold_preview::{Gpu, Preview};
//! let mut preview = Preview::new(Gpu::headless()?);
//! preview.load(&orbifold_scene::Scene::default(), None)?;
//! let frame = preview.render(320, 240)?;
//! println!("{} copies drawn", preview.stats().instances);
//! # let _ = frame;
//! # Ok::<(), orbifold_preview::PreviewError>(())
//! ```

pub mod copies;
pub mod frame;
pub mod gpu;
pub mod mesh;
pub mod projection;
pub mod renderer;
pub mod textures;

pub use frame::Frame;
pub use gpu::Gpu;
pub use orbifold;
pub use orbifold_scene;
pub use projection::{Projection, View};
pub use renderer::{Preview, Settings, Stats};

/// Why the preview cannot draw.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum PreviewError {
    /// No GPU and no software adapter.
    NoAdapter(String),
    /// The GPU failed.
    Gpu(String),
    /// The scene cannot be previewed.
    Scene(String),
    /// Nothing loaded yet.
    NoScene,
    /// An image size of zero or beyond the GPU's limit.
    Size(u32, u32),
    /// The picture cannot be written.
    Output(String),
}

impl std::fmt::Display for PreviewError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            PreviewError::NoAdapter(why) => write!(f, "no GPU adapter for the preview: {why}"),
            PreviewError::Gpu(why) => write!(f, "the GPU failed: {why}"),
            PreviewError::Scene(why) => write!(f, "{why}"),
            PreviewError::NoScene => write!(f, "the preview has no scene loaded"),
            PreviewError::Size(w, h) => write!(
                f,
                "cannot draw a {w}×{h} preview: the size must be positive and within the GPU's \
                 texture limit"
            ),
            PreviewError::Output(why) => write!(f, "{why}"),
        }
    }
}

impl std::error::Error for PreviewError {}
