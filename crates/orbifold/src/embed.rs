//! Objects in curved rooms (ARCHITECTURE.md §7): a Euclidean mesh is embedded at the origin through
//! the exponential map — distances and bearings from its centre of mass are kept, its up axis
//! becomes height — and then moved rigidly by an instance transform, an isometry of the plane
//! with a height offset. Isometries are linear maps of ambient coordinates, so a moved object is
//! exactly congruent to the embedded one.

use glam::{DMat3, DVec3};
use num_complex::Complex64;

use crate::isometry::Isometry;
use crate::space::Space;

/// Where an object stands: the model position of its centre of mass, the height of its lowest
/// point, and its turn about the vertical (radians, counter-clockwise seen from above).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Placement {
    /// Model coordinates of the centre of mass.
    pub at: Complex64,
    /// Height of the lowest point above the floor.
    pub height: f64,
    /// Turn about the vertical, radians.
    pub yaw: f64,
}

impl Placement {
    /// The isometry of the plane that takes the origin to `at`, turned by `yaw`.
    pub fn isometry(&self, space: Space) -> Isometry {
        Isometry::translation(space, self.at).compose(&Isometry::rotation(space, self.yaw))
    }
}

/// An object embedded at the origin: ambient horizontal points and heights, lowest point at 0.
#[derive(Clone, Debug, PartialEq)]
pub struct Embedded {
    /// Ambient coordinates of the vertices' horizontal positions.
    pub points: Vec<DVec3>,
    /// Heights of the vertices (the lowest is 0).
    pub heights: Vec<f64>,
}

/// Embeds object-space vertices (Euclidean, **Y up**, right-handed) at the origin of `space`.
///
/// The vertices are centred on `centre` (the centre of mass, see [`centre_of_mass`]) and scaled
/// by `scale`; then (x, z) goes through the exponential map at the origin as the tangent vector
/// (x, −z) — so that seen from above the object is not mirrored — and y becomes height, shifted
/// so that the lowest vertex is at height 0.
///
/// ```
/// use orbifold::embed::embed;
/// use orbifold::space::Space;
/// use orbifold::Geometry;
/// use glam::DVec3;
/// let h = Space::new(Geometry::Hyperbolic);
/// let e = embed(h, &[[1.0, 0.0, 0.0], [0.0, 2.0, 0.0]], DVec3::ZERO, 1.0);
/// // The first vertex is at intrinsic distance 1 from the origin, the second straight above it.
/// assert!((h.ambient_distance(e.points[0], DVec3::Z) - 1.0).abs() < 1e-15);
/// assert_eq!(e.heights, vec![0.0, 2.0]);
/// ```
pub fn embed(space: Space, positions: &[[f64; 3]], centre: DVec3, scale: f64) -> Embedded {
    let lowest = positions
        .iter()
        .map(|p| (p[1] - centre.y) * scale)
        .fold(f64::INFINITY, f64::min);
    let mut points = Vec::with_capacity(positions.len());
    let mut heights = Vec::with_capacity(positions.len());
    for p in positions {
        let v = DVec3::new((p[0] - centre.x) * scale, -(p[2] - centre.z) * scale, 0.0);
        points.push(space.exp(DVec3::Z, v));
        heights.push((p[1] - centre.y) * scale - lowest);
    }
    Embedded { points, heights }
}

/// The centre of mass of a closed triangle mesh (of the solid it bounds), or of its surface when
/// the enclosed volume vanishes (an open or flat mesh), or of its vertices when that vanishes too.
pub fn centre_of_mass(positions: &[[f64; 3]], triangles: &[[u32; 3]]) -> DVec3 {
    // Sums relative to the first vertex stay accurate for meshes far from their file's origin.
    let origin = positions.first().map_or(DVec3::ZERO, |p| DVec3::from(*p));
    let corner = |t: &[u32; 3], k: usize| DVec3::from(positions[t[k] as usize]) - origin;
    let (mut volume, mut moment) = (0.0, DVec3::ZERO);
    let (mut area, mut area_moment) = (0.0, DVec3::ZERO);
    for t in triangles {
        let (a, b, c) = (corner(t, 0), corner(t, 1), corner(t, 2));
        // The signed tetrahedron (0, a, b, c) has volume det/6 and centroid (a + b + c)/4.
        let v = DMat3::from_cols(a, b, c).determinant() / 6.0;
        volume += v;
        moment += v * (a + b + c) / 4.0;
        let s = 0.5 * (b - a).cross(c - a).length();
        area += s;
        area_moment += s * (a + b + c) / 3.0;
    }
    let extent = positions
        .iter()
        .map(|p| (DVec3::from(*p) - origin).abs().max_element())
        .fold(0.0, f64::max);
    if volume.abs() > 1e-9 * extent.powi(3) {
        origin + moment / volume
    } else if area > 1e-12 * extent.powi(2) {
        origin + area_moment / area
    } else {
        positions.iter().map(|p| DVec3::from(*p)).sum::<DVec3>() / positions.len().max(1) as f64
    }
}

/// Moves an embedded object: every point by the placement's isometry, every height up by its
/// height. Returns the moved points and heights.
pub fn place(space: Space, object: &Embedded, placement: &Placement) -> Embedded {
    let m = placement.isometry(space).matrix();
    Embedded {
        points: object.points.iter().map(|&p| m * p).collect(),
        heights: object
            .heights
            .iter()
            .map(|&h| h + placement.height)
            .collect(),
    }
}
