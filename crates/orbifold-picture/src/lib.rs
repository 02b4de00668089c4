//! Pictures of two-dimensional orbifolds, shared by the `orbifold` command and the studio.
//!
//! - [`tiling`]: raster pictures of the universal cover in six models of the plane, every pixel
//!   folded back into the fundamental polygon (the reverse pixel lookup), with motifs and
//!   colourings by depth, orientation or wall.
//! - [`group`]: the same for any orbifold, every pixel folded through the side pairings of its
//!   fundamental polygon, with a chiral letter that shows rotations, reflections and glides apart.
//! - [`svg`]: vector pictures — a polygon's layout with its walls, corners and placement, a
//!   tiling as geodesic polygons, a room's floor mesh — and their conversion to PNG.

pub mod group;
pub mod svg;
pub mod tiling;
