//! The interactive designer for orbifold mirror rooms (eframe/egui): design panel, layout
//! view, room design, 3D preview and rendering. See the seed's chapter 5.
//!
//! Not yet written: the studio issue builds it, last.

pub use orbifold;
