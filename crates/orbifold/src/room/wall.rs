//! Wall tessellation (seed 6.2.2): a wall is a geodesic arc × [0, height], meshed as a grid in
//! intrinsic arc length and height.

use glam::DVec3;

use super::RoomMesher;
use super::surface::Surface;

/// A rectangle of a wall in its own coordinates: arc length along the wall from its first corner,
/// as fractions of its length, and height.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct WallRect {
    /// Where it starts and ends along the wall (fractions, 0 ≤ from < to ≤ 1).
    pub along: [f64; 2],
    /// Its lower and upper edges (0 ≤ bottom < top ≤ the room's height).
    pub heights: [f64; 2],
}

impl RoomMesher {
    /// The intrinsic length of a wall as meshed (ideal walls end at the cusp cuts), or `None` if
    /// the layout has no such wall.
    pub fn wall_length(&self, wall: usize) -> Option<f64> {
        let sides = self.boundary.wall_sides(wall);
        (!sides.is_empty()).then(|| sides.iter().map(|&i| self.boundary.sides[i].length).sum())
    }

    /// The point of a wall at a fraction `t` of its length (measured from its first corner).
    pub fn wall_point(&self, wall: usize, t: f64) -> Option<DVec3> {
        let sides = self.boundary.wall_sides(wall);
        let total: f64 = sides.iter().map(|&i| self.boundary.sides[i].length).sum();
        let mut s = t.clamp(0.0, 1.0) * total;
        for (k, &i) in sides.iter().enumerate() {
            let length = self.boundary.sides[i].length;
            if s <= length || k + 1 == sides.len() {
                let fraction = if length > 0.0 {
                    (s / length).min(1.0)
                } else {
                    0.0
                };
                return Some(self.boundary.point_on_side(i, fraction));
            }
            s -= length;
        }
        None
    }

    /// The mesh of a rectangle of a wall: a grid of (⌈width / resolution⌉ × ⌈height /
    /// resolution⌉) cells in arc length and height, each cut into two triangles, facing into
    /// the room. Grids of neighbouring rectangles that share an edge share its vertices'
    /// positions, so parts of one wall fit without cracks. `None` if there is no such wall.
    pub fn wall(&self, wall: usize, rect: WallRect) -> Option<Surface> {
        let length = self.wall_length(wall)?;
        let resolution = self.options.resolution;
        let [from, to] = rect.along;
        let [bottom, top] = rect.heights;
        let columns = (((to - from) * length / resolution).ceil() as usize).max(1);
        let rows = (((top - bottom) / resolution).ceil() as usize).max(1);
        let mut surface = Surface::default();
        for c in 0..=columns {
            // The last column at `to` itself, which (to − from)·c/c need not round to: the
            // neighbouring rectangle's first column is there, and the two must coincide.
            let t = if c == columns {
                to
            } else {
                from + (to - from) * c as f64 / columns as f64
            };
            let point = self.wall_point(wall, t)?;
            for r in 0..=rows {
                let height = if r == rows {
                    top
                } else {
                    bottom + (top - bottom) * r as f64 / rows as f64
                };
                surface.push(point, height);
            }
        }
        let index = |c: usize, r: usize| (c * (rows + 1) + r) as u32;
        for c in 0..columns {
            for r in 0..rows {
                // Seen from inside, the wall runs from right to left as the arc length grows
                // (the polygon is counter-clockwise), so (c, r), (c, r+1), (c+1, r) turns
                // counter-clockwise for a viewer inside.
                surface
                    .triangles
                    .push([index(c, r), index(c, r + 1), index(c + 1, r)]);
                surface
                    .triangles
                    .push([index(c + 1, r), index(c, r + 1), index(c + 1, r + 1)]);
            }
        }
        Some(surface)
    }

    /// The whole wall, floor to ceiling.
    pub fn whole_wall(&self, wall: usize) -> Option<Surface> {
        self.wall(
            wall,
            WallRect {
                along: [0.0, 1.0],
                heights: [0.0, self.options.height],
            },
        )
    }
}
