//! The real-time rasteriser (wgpu) that draws a mirror room and its mirror copies with the
//! non-Euclidean projection. See `DESIGN.md` §9.
//!
//! Not yet written: the preview issue builds it.

pub use orbifold;
pub use orbifold_scene;
