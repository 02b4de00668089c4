//! The interactive designer for orbifold mirror rooms (eframe/egui), seed chapter 5: the design
//! panel (walls and corner orders, signature, χ, geometry, kind), the layout view (the polygon,
//! its free parameters, presets and placement), room design (mirrors, materials, objects,
//! lights), the real-time 3D preview with walking, the tiling of the cover, background
//! rendering, listening to the room's echoes (a clap at the camera), documents with undo/redo
//! and crash recovery, file dialogs and dropped files, and a browser of the example scenes.
//!
//! [`app::Studio`] is the whole application; `orbifold-studio` (the binary) runs it in a
//! window, and the tests drive it headlessly with egui_kittest.

pub mod app;
pub mod audio;
pub mod design;
pub mod dialogs;
pub mod document;
pub mod drop;
pub mod examples_browser;
pub mod layout_view;
pub mod listen_panel;
pub mod render_job;
pub mod room_panel;
pub mod view3d;

pub use app::Studio;
pub use orbifold;
