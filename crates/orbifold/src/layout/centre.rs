//! The centre of a polygon without an inscribed circle: the centre of its largest inscribed disk.

use glam::DVec3;
use num_complex::Complex64;

use crate::space::Space;

/// The point farthest from every wall (maximising the smallest distance to a wall), found by a
/// compass search in model coordinates from the centroid of the corners. The distance to wall ν
/// is asinh(ν·p) (hyperbolic), so the search compares ν·p directly.
pub(crate) fn largest_inscribed_disk(
    space: Space,
    walls: &[DVec3],
    corners: &[Complex64],
) -> Complex64 {
    let clearance = |z: Complex64| {
        let p = space.to_ambient(z);
        walls.iter().map(|w| w.dot(p)).fold(f64::INFINITY, f64::min)
    };
    // Start from the centroid of the corners in the Klein model, where the polygon is a convex
    // Euclidean polygon (so the centroid is inside); ideal corners count like the others.
    let klein = |z: Complex64| 2.0 * z / (1.0 + z.norm_sqr());
    let mean = corners.iter().map(|&z| klein(z)).sum::<Complex64>() / corners.len() as f64;
    let mut z = mean / (1.0 + (1.0 - mean.norm_sqr()).max(0.0).sqrt());
    let mut best = clearance(z);
    let mut step = 0.25 * (1.0 - z.norm());
    let directions: Vec<Complex64> = (0..8)
        .map(|k| Complex64::from_polar(1.0, k as f64 * std::f64::consts::FRAC_PI_4))
        .collect();
    while step > 1e-13 {
        let improved = directions
            .iter()
            .map(|&d| z + d * step)
            .filter(|c| c.norm() < 1.0)
            .find_map(|c| {
                let value = clearance(c);
                (value > best).then_some((c, value))
            });
        match improved {
            Some((c, value)) => {
                z = c;
                best = value;
            }
            None => step *= 0.5,
        }
    }
    z
}
