//! A meshed surface of a room: intrinsically flat triangles on ambient points with heights.

use glam::{DMat3, DVec3};

use crate::space::Space;

/// An indexed triangle mesh in the product space (plane × height): vertex `i` is the ambient
/// point `points[i]` at height `heights[i]`.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Surface {
    /// Ambient coordinates of the vertices' horizontal positions.
    pub points: Vec<DVec3>,
    /// Heights of the vertices.
    pub heights: Vec<f64>,
    /// Triangles, counter-clockwise seen from the side the surface faces.
    pub triangles: Vec<[u32; 3]>,
}

/// Mesh quality, as the seed's chapter 6.2 asks of a tessellation.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Quality {
    /// The number of triangles.
    pub triangles: usize,
    /// The longest edge, in intrinsic length of the product space.
    pub largest_edge: f64,
    /// The smallest corner angle of any triangle, in degrees.
    pub smallest_angle: f64,
}

impl Surface {
    /// Adds a vertex and returns its index.
    pub fn push(&mut self, point: DVec3, height: f64) -> u32 {
        self.points.push(point);
        self.heights.push(height);
        (self.points.len() - 1) as u32
    }

    /// The number of vertices.
    pub fn len(&self) -> usize {
        self.points.len()
    }

    /// Whether there are no vertices.
    pub fn is_empty(&self) -> bool {
        self.points.is_empty()
    }

    /// Appends another surface.
    pub fn append(&mut self, other: &Surface) {
        let offset = self.points.len() as u32;
        self.points.extend_from_slice(&other.points);
        self.heights.extend_from_slice(&other.heights);
        self.triangles.extend(
            other
                .triangles
                .iter()
                .map(|t| [t[0] + offset, t[1] + offset, t[2] + offset]),
        );
    }

    /// Reverses every triangle (the surface faces the other way).
    pub fn flip(&mut self) {
        self.triangles.iter_mut().for_each(|t| t.swap(1, 2));
    }

    /// Adds a triangle of a horizontal surface, turned to be counter-clockwise seen from above
    /// (positive determinant of its ambient corners).
    pub(crate) fn push_upward(&mut self, t: [u32; 3]) {
        let [a, b, c] = t.map(|i| self.points[i as usize]);
        if DMat3::from_cols(a, b, c).determinant() >= 0.0 {
            self.triangles.push(t);
        } else {
            self.triangles.push([t[0], t[2], t[1]]);
        }
    }

    /// The sum of the intrinsic areas of the triangles' horizontal shadows (for a floor, its
    /// area).
    pub fn horizontal_area(&self, space: Space) -> f64 {
        self.triangles
            .iter()
            .map(|t| {
                let [a, b, c] = t.map(|i| self.points[i as usize]);
                space.triangle_area(a, b, c)
            })
            .sum()
    }

    /// Triangle count, longest edge and smallest angle, measured intrinsically in the product
    /// metric (horizontal distance and height).
    pub fn quality(&self, space: Space) -> Quality {
        let mut largest_edge: f64 = 0.0;
        let mut smallest_angle = f64::INFINITY;
        for t in &self.triangles {
            for k in 0..3 {
                let (i, j, l) = (
                    t[k] as usize,
                    t[(k + 1) % 3] as usize,
                    t[(k + 2) % 3] as usize,
                );
                let to_j = self.tangent(space, i, j);
                let to_l = self.tangent(space, i, l);
                largest_edge = largest_edge.max(product_norm(space, to_j));
                smallest_angle =
                    smallest_angle.min(product_angle(space, self.points[i], to_j, to_l));
            }
        }
        Quality {
            triangles: self.triangles.len(),
            largest_edge,
            smallest_angle: smallest_angle.to_degrees(),
        }
    }

    /// The tangent vector of the product space at vertex `i` towards vertex `j`: the horizontal
    /// logarithm and the height difference.
    fn tangent(&self, space: Space, i: usize, j: usize) -> (DVec3, f64) {
        (
            space.log(self.points[i], self.points[j]),
            self.heights[j] - self.heights[i],
        )
    }
}

fn product_dot(space: Space, u: (DVec3, f64), v: (DVec3, f64)) -> f64 {
    space.point_dot(u.0, v.0) + u.1 * v.1
}

fn product_norm(space: Space, u: (DVec3, f64)) -> f64 {
    product_dot(space, u, u).max(0.0).sqrt()
}

/// The angle between two tangent vectors of the product space at the point `at`, as
/// atan2(|U ∧ V|, U·V): the wedge has the horizontal part det(p, u, v) and the mixed part
/// u·h_V − v·h_U, so thin triangles keep their tiny angles (no acos of a number near 1).
fn product_angle(space: Space, at: DVec3, u: (DVec3, f64), v: (DVec3, f64)) -> f64 {
    let horizontal = DMat3::from_cols(at, u.0, v.0).determinant();
    let mixed = u.0 * v.1 - v.0 * u.1;
    let wedge = (horizontal * horizontal + space.point_dot(mixed, mixed).max(0.0)).sqrt();
    wedge.atan2(product_dot(space, u, v))
}

/// The angle at ambient point `at` between the geodesics towards `a` and `b`, as
/// atan2(|det(p, u, v)|, ⟨u, v⟩): for tangent vectors u, v at a point p of the model surface the
/// determinant is |u||v| sin θ in all three geometries, so angles near 0 and π stay accurate.
pub fn angle(space: Space, at: DVec3, a: DVec3, b: DVec3) -> f64 {
    product_angle(space, at, (space.log(at, a), 0.0), (space.log(at, b), 0.0))
}
