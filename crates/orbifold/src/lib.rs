//! The mathematics of two-dimensional kaleidoscopic orbifolds.
//!
//! A kaleidoscopic orbifold is a polygon whose walls are mirrors and whose corner angles are
//! π/k. Its signature, such as `*2333`, `*23456789(10)(11)` or `*∞∞∞`, determines an Euler
//! characteristic χ whose sign says whether the polygon and its mirror images tile the sphere,
//! the Euclidean plane or the hyperbolic plane.
//!
//! This crate reads and writes signatures ([`Signature`], and [`OrbifoldSymbol`] for Conway's
//! notation of every 2D orbifold), computes χ exactly ([`EulerCharacteristic`]), classifies
//! ([`Geometry`], [`Kind`], [`SymmetryGroup`], the seed's Table 4.1 in [`table`]) and enumerates
//! ([`enumerate`]).
//!
//! ```
//! use orbifold::{Geometry, Signature};
//!
//! let sig: Signature = "*2333".parse()?;
//! assert_eq!(sig.euler_characteristic().to_string(), "-1/4");
//! assert_eq!(sig.geometry(), Geometry::Hyperbolic);
//! assert_eq!(sig.free_parameters(), 1);
//! # Ok::<(), orbifold::ParseError>(())
//! ```

pub mod conway;
pub mod cover;
pub mod embed;
pub mod enumerate;
pub mod euler;
pub mod groups;
pub mod growth;
pub mod isometry;
pub mod layout;
pub mod necklace;
pub mod notation;
pub mod order;
pub mod pairing;
pub mod room;
pub mod signature;
pub mod space;
pub mod table;

pub use conway::OrbifoldSymbol;
pub use enumerate::{Enumeration, EnumerationOptions};
pub use euler::{EulerCharacteristic, Geometry};
pub use groups::{GroupFamily, SymmetryGroup};
pub use layout::{Layout, LayoutError, LayoutOptions, Shape};
pub use notation::{ParseError, ParseErrorKind};
pub use order::Order;
pub use signature::{InvalidOrder, Kind, Signature};
pub use table::Family;
