//! Room tessellation (seed chapter 6.2): the floor and ceiling of the prism polygon × [0, height]
//! and its walls, meshed at a resolution given in intrinsic length.
//!
//! Meshes are made of intrinsically flat triangles (ARCHITECTURE.md §7): vertices are ambient points
//! with heights, and every mesh edge is a geodesic. Points on a wall are linear combinations of
//! points on it, so they lie on the wall to rounding. Two floor methods:
//!
//! - [`FloorMethod::Contour`], the seed's contour-based tessellation (6.2.1.2): samples along the
//!   boundary are paired across the polygon, joined by geodesic rungs sampled at the resolution,
//!   and neighbouring rungs are zipped into triangles. The pairing is chosen to keep rungs short.
//! - [`FloorMethod::Geodesic`]: a fan from the centre to the corners, refined by splitting every
//!   edge at its exact geodesic midpoint until no edge is longer than the resolution. Unlike the
//!   seed's geodesic grid (6.2.1.1) it keeps every corner (no uncovered contour, seed Fig. 6.8).
//!
//! Ideal corners are cut off along a geodesic chord at [`Boundary::cusp_distance`] from the
//! centre; the lost area, π minus the chord's two angles, is in [`RoomMesher::cusp_area`].
//!
//! ```
//! use orbifold::room::{FloorMethod, RoomMesher, RoomOptions};
//! use orbifold::{Layout, LayoutOptions, Signature};
//! let layout = Layout::new(&"*2223".parse::<Signature>()?, &LayoutOptions::default())?;
//! let options = RoomOptions { resolution: 0.1, method: FloorMethod::Geodesic, ..RoomOptions::default() };
//! let mesher = RoomMesher::new(&layout, &options)?;
//! let floor = mesher.floor();
//! // The floor's triangles add up to the polygon's area 2π|χ| = π/6.
//! assert!((floor.horizontal_area(layout.space()) - std::f64::consts::PI / 6.0).abs() < 1e-9);
//! // The geodesic method meets the resolution; the contour method's diagonals may reach twice it.
//! assert!(floor.quality(layout.space()).largest_edge <= 0.1);
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

pub mod boundary;
pub mod floor;
pub mod surface;
pub mod wall;

pub use boundary::Boundary;
pub use surface::{Quality, Surface};

use crate::layout::Layout;
use crate::space::Space;

/// How the floor and ceiling are meshed.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum FloorMethod {
    /// The seed's contour-based tessellation: rungs between paired boundary samples.
    #[default]
    Contour,
    /// A fan from the centre, refined by geodesic midpoint subdivision.
    Geodesic,
}

/// What to mesh and how finely.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RoomOptions {
    /// The height of the walls (> 0).
    pub height: f64,
    /// The longest intrinsic edge length wanted (> 0).
    pub resolution: f64,
    /// The floor and ceiling method.
    pub method: FloorMethod,
    /// Where ideal corners are cut off: the intrinsic distance from the centre (raised where it
    /// would not clear the finite corners); `None` for the default.
    pub cusp_distance: Option<f64>,
}

impl Default for RoomOptions {
    fn default() -> Self {
        RoomOptions {
            height: 1.0,
            resolution: 0.1,
            method: FloorMethod::Contour,
            cusp_distance: None,
        }
    }
}

/// The most triangles one floor may have; a finer resolution is an error, not an exhausted
/// machine.
pub const MAX_FLOOR_TRIANGLES: f64 = 2.0e7;

/// Why a room cannot be meshed.
#[derive(Clone, Debug, PartialEq)]
pub enum RoomError {
    /// An option out of range, with the reason.
    Options(String),
}

impl std::fmt::Display for RoomError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            RoomError::Options(why) => write!(f, "cannot mesh the room: {why}"),
        }
    }
}

impl std::error::Error for RoomError {}

/// Meshes the parts of one room.
#[derive(Clone, Debug)]
pub struct RoomMesher {
    /// The loop that is meshed (ideal corners cut off).
    pub boundary: Boundary,
    /// The options, as given.
    pub options: RoomOptions,
    /// The polygon's intrinsic area (before cutting cusps).
    pub polygon_area: f64,
}

impl RoomMesher {
    /// Prepares to mesh the room over `layout`; checks the options.
    pub fn new(layout: &Layout, options: &RoomOptions) -> Result<RoomMesher, RoomError> {
        let positive = |x: f64| x.is_finite() && x > 0.0;
        if !positive(options.height) {
            return Err(RoomError::Options(format!(
                "the height must be a positive number, not {}",
                options.height
            )));
        }
        if !positive(options.resolution) {
            return Err(RoomError::Options(format!(
                "the resolution must be a positive number, not {}",
                options.resolution
            )));
        }
        if let Some(d) = options.cusp_distance
            && !positive(d)
        {
            return Err(RoomError::Options(format!(
                "the cusp distance must be a positive number, not {d}"
            )));
        }
        let boundary = Boundary::new(layout, options.cusp_distance);
        let mesher = RoomMesher {
            boundary,
            options: *options,
            polygon_area: layout.area,
        };
        let estimate = mesher.estimated_floor_triangles();
        if estimate > MAX_FLOOR_TRIANGLES {
            return Err(RoomError::Options(format!(
                "resolution {} would need about {estimate:.1e} floor triangles (at most {MAX_FLOOR_TRIANGLES:.0e}); choose a coarser one",
                options.resolution
            )));
        }
        Ok(mesher)
    }

    /// The plane.
    pub fn space(&self) -> Space {
        self.boundary.space
    }

    /// The floor (height 0, triangles counter-clockwise seen from above).
    pub fn floor(&self) -> Surface {
        match self.options.method {
            FloorMethod::Contour => floor::contour(&self.boundary, self.options.resolution),
            FloorMethod::Geodesic => floor::geodesic(&self.boundary, self.options.resolution),
        }
    }

    /// The ceiling: the floor at the room's height, facing down.
    pub fn ceiling(&self) -> Surface {
        let mut s = self.floor();
        s.heights.iter_mut().for_each(|h| *h = self.options.height);
        s.flip();
        s
    }

    /// The area of the floor that was meshed: the polygon's area less the cusps cut off.
    pub fn meshed_area(&self) -> f64 {
        self.polygon_area - self.cusp_area()
    }

    /// The area cut off at the ideal corners: each cusp beyond its chord is a triangle with one
    /// ideal corner, of area π − α − β for the chord's angles α, β with the walls.
    pub fn cusp_area(&self) -> f64 {
        let b = &self.boundary;
        let n = b.len();
        (0..n)
            .filter(|&i| b.sides[i].wall.is_none())
            .map(|i| {
                let (prev, p, q, next) = (
                    b.corners[(i + n - 1) % n],
                    b.corners[i],
                    b.corners[(i + 1) % n],
                    b.corners[(i + 2) % n],
                );
                // The angles outside the meshed polygon: π minus the inner ones.
                let alpha = std::f64::consts::PI - surface::angle(b.space, p, prev, q);
                let beta = std::f64::consts::PI - surface::angle(b.space, q, p, next);
                std::f64::consts::PI - alpha - beta
            })
            .sum()
    }

    fn estimated_floor_triangles(&self) -> f64 {
        let l = self.options.resolution;
        match self.options.method {
            // Equilateral triangles of side l have area √3 l²/4.
            FloorMethod::Contour => {
                4.0 * self.polygon_area.min(1e12) / (3f64.sqrt() * l * l)
                    + 4.0 * self.boundary.sides.iter().map(|s| s.length).sum::<f64>() / l
            }
            FloorMethod::Geodesic => {
                let levels = floor::geodesic_levels(&self.boundary, l);
                self.boundary.len() as f64 * 4f64.powi(levels as i32)
            }
        }
    }
}
