//! Mirror-room scenes: the document that the command line, the renderer, the preview and the
//! studio all read and write (signature, layout, room, mirrors, materials, objects, lights,
//! cameras), its file format and its validation. See `DESIGN.md` §7.
//!
//! Not yet written: the scene issue builds it. The crate exists so that the workspace has its
//! final shape and dependencies point one way from the start.

pub use orbifold;
