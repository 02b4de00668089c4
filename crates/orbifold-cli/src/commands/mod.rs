//! One module per subcommand.

pub mod animate;
pub mod cover;
pub mod enumerate;
pub mod info;
pub mod layout;
pub mod listen;
pub mod preview;
pub mod render;
pub mod room;
pub mod scene;
pub mod tiling;
pub mod trace;
