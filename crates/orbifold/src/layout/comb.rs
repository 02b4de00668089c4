//! Hyperbolic polygons with N ≥ 4 corners and their N − 3 free parameters: the comb.
//!
//! Wall N−1 is the base line L. For j = 1 … N−3, wall j is perpendicular to a geodesic that
//! leaves L perpendicularly and has length cⱼ, the j-th free parameter: cⱼ is the distance between
//! wall N−1 and wall j (their common perpendicular). Cutting the polygon along these N − 3
//! perpendiculars gives the seed's building blocks: two quadrilaterals with two right angles at
//! the ends (corners 0, 1 and corners N−2, N−1) and a pentagon with four right angles for each
//! corner j = 2 … N−3. Each block exists for every positive cⱼ, and the blocks glue into a convex
//! polygon because the angles at the cut ends add up to π; so every positive value of every
//! parameter gives a valid polygon, with no equations left to solve.
//!
//! In the hyperboloid model with L the real axis, the wall at foot position t and distance c is
//! ν = (−sinh c sinh t, −cosh c, sinh c cosh t). Consecutive walls j−1 and j meet at the angle αⱼ
//! of corner j when cosh(tⱼ₋₁ − tⱼ) = (cos αⱼ + cosh cⱼ₋₁ cosh cⱼ)/(sinh cⱼ₋₁ sinh cⱼ). Walls 0 and
//! N−2 make prescribed angles with two known walls: a linear system and one quadratic.

use glam::DVec3;
use num_complex::Complex64;

use super::{LayoutError, ParameterMeaning, RawPolygon, centre, corner_of};
use crate::euler::Geometry;
use crate::isometry::Isometry;
use crate::space::Space;

fn space() -> Space {
    Space::new(Geometry::Hyperbolic)
}

/// The wall at distance `c` from the base line, perpendicular to the geodesic that leaves the
/// base at position `t`; positive on the base's side.
fn cut_wall(t: f64, c: f64) -> DVec3 {
    DVec3::new(-c.sinh() * t.sinh(), -c.cosh(), c.sinh() * t.cosh())
}

/// How strongly a parameter scales its distance: cⱼ = c⁰ⱼ · pⱼ^EXPONENT.
///
/// Distances themselves make poor parameters: independent values spread over two orders of
/// magnitude give polygons whose far corners lie 20 or more from the centre, where model
/// coordinates in double precision can no longer tell neighbouring corners apart. Scaling the
/// balanced polygon's distances by the eighth root keeps every polygon with parameters in
/// (0.05, 10) and up to 30 corners within about 9 of its centre (corner angles then check to
/// 2·10⁻¹⁰ from the corner positions alone; see `examples/layout_stats.rs`), and still reaches
/// every polygon as pⱼ runs over (0, ∞).
pub const EXPONENT: f64 = 0.125;

/// The polygon whose comb distances are those of the balanced (incircle) polygon scaled by the
/// parameters: cⱼ = c⁰ⱼ · pⱼ^[`EXPONENT`]; all parameters 1 give the balanced polygon.
pub(crate) fn polygon_relative(
    angles: &[f64],
    ideal: &[bool],
    parameters: &[f64],
) -> Result<RawPolygon, LayoutError> {
    let balanced = super::incircle::polygon(space(), angles, ideal)?;
    let reference = parameters_of(space(), &balanced.walls);
    let distances: Vec<f64> = reference
        .iter()
        .zip(parameters)
        .map(|(c0, p)| c0 * p.powf(EXPONENT))
        .collect();
    let mut raw = polygon(angles, ideal, &distances)?;
    raw.parameters = parameters.to_vec();
    Ok(raw)
}

/// Whether the comb can build these angles: every corner at most a right angle, which every
/// orbifold satisfies. (An obtuse corner can put two walls' meeting point on the wrong side of
/// the cut perpendiculars, so non-orbifold rooms with one are built around their incircle.)
pub(crate) fn accepts(angles: &[f64]) -> bool {
    angles.iter().all(|&a| a <= std::f64::consts::FRAC_PI_2)
}

/// The polygon with these corner angles and comb distances (all positive).
pub(crate) fn polygon(
    angles: &[f64],
    ideal: &[bool],
    parameters: &[f64],
) -> Result<RawPolygon, LayoutError> {
    let n = angles.len();
    debug_assert_eq!(parameters.len(), n - 3);
    if !accepts(angles) {
        let j = angles
            .iter()
            .position(|&a| a > std::f64::consts::FRAC_PI_2)
            .unwrap_or(0);
        return Err(LayoutError::Unsupported(format!(
            "corner {j} is obtuse, and the free parameters are defined for corners of at most a right angle; \
             use --shape incircle (the default for such rooms)"
        )));
    }
    let mut feet = vec![0.0; n];
    for j in 2..=n - 3 {
        let (a, b) = (parameters[j - 2], parameters[j - 1]);
        // cosh z − 1 = (cos α + cosh(a − b))/(sinh a sinh b) = 2 sinh²(z/2), without cancellation.
        let half = ((angles[j].cos() + (a - b).cosh()) / (2.0 * a.sinh() * b.sinh()))
            .max(0.0)
            .sqrt();
        feet[j] = feet[j - 1] - 2.0 * half.asinh();
    }
    // Work in the frame whose origin is on the base midway between the outermost feet, and build
    // every wall at the origin and move it along the base by a difference of positions: no
    // large coefficients meet and cancel.
    let middle = 0.5 * (feet[1] + feet[n - 3]);
    let along = |t: f64| Isometry::translation_by(space(), t - middle, Complex64::new(1.0, 0.0));
    let base = DVec3::new(0.0, 1.0, 0.0);
    let mut walls = vec![DVec3::ZERO; n];
    walls[n - 1] = base;
    for j in 1..=n - 3 {
        walls[j] = along(feet[j]).apply_wall(cut_wall(0.0, parameters[j - 1]));
    }
    // Wall 0 meets the base at corner 0 (right of every foot) and wall 1 at corner 1; wall N−2
    // meets wall N−3 at corner N−2 and the base at corner N−1 (left of every foot).
    let first = end_wall(
        base,
        angles[0],
        cut_wall(0.0, parameters[0]),
        angles[1],
        true,
    );
    walls[0] = along(feet[1]).apply_wall(first);
    let last = end_wall(
        cut_wall(0.0, parameters[n - 4]),
        angles[n - 2],
        base,
        angles[n - 1],
        false,
    );
    walls[n - 2] = along(feet[n - 3]).apply_wall(last);
    let corners_of = |walls: &[DVec3]| -> Vec<Complex64> {
        (0..n)
            .map(|i| {
                corner_of(
                    space(),
                    walls[(i + n - 1) % n],
                    walls[i],
                    angles[i],
                    ideal[i],
                )
            })
            .collect()
    };
    // Far along the comb the walls have large coefficients; recompute the corners from the walls
    // moved to the centre, where they are well conditioned.
    let centre = centre::largest_inscribed_disk(space(), &walls, &corners_of(&walls));
    let centring = Isometry::translation(space(), centre).inverse();
    let walls: Vec<DVec3> = walls.iter().map(|&w| centring.apply_wall(w)).collect();
    let corners = corners_of(&walls);
    let origin = Complex64::new(0.0, 0.0);
    Ok(RawPolygon {
        walls,
        corners,
        parameters: parameters.to_vec(),
        meaning: ParameterMeaning::WallDistances,
        centre: origin,
    })
}

/// The wall X with inner angle `alpha` to wall `a` and `beta` to wall `b`, where `a` and `b` are
/// perpendicular to the geodesic that leaves the base at the origin. Of the two solutions, mirror
/// images across that geodesic, take the one whose corner on the base lies right of the origin
/// (`right`) or left of it.
fn end_wall(a: DVec3, alpha: f64, b: DVec3, beta: f64, right: bool) -> DVec3 {
    let g = DVec3::new(1.0, 1.0, -1.0);
    let (ga, gb) = (a * g, b * g);
    // Particular solution in span{ga, gb} of ga·X = −cos α, gb·X = −cos β.
    let (aa, ab, bb) = (ga.dot(ga), ga.dot(gb), gb.dot(gb));
    let det = aa * bb - ab * ab;
    let (ra, rb) = (-alpha.cos(), -beta.cos());
    let s = (ra * bb - rb * ab) / det;
    let t = (rb * aa - ra * ab) / det;
    let x0 = ga * s + gb * t;
    let w = ga.cross(gb);
    let form = |u: DVec3, v: DVec3| u.x * v.x + u.y * v.y - u.z * v.z;
    let (qa, qb, qc) = (form(w, w), 2.0 * form(x0, w), form(x0, x0) - 1.0);
    // The roots of qa λ² + qb λ + qc, without cancellation.
    let root = (qb * qb - 4.0 * qa * qc).max(0.0).sqrt();
    let q = -0.5 * (qb + if qb >= 0.0 { root } else { -root });
    let (l0, l1) = if q == 0.0 {
        (0.0, 0.0)
    } else {
        (q / qa, qc / q)
    };
    let candidates = [x0 + w * l0, x0 + w * l1];
    let base = DVec3::new(0.0, 1.0, 0.0);
    let position = |x: DVec3| {
        let mut q = x.cross(base);
        if q.z < 0.0 {
            q = -q;
        }
        q.x / q.z // tanh of the corner's position along the base
    };
    let sign = if right { 1.0 } else { -1.0 };
    let (p0, p1) = (
        sign * position(candidates[0]),
        sign * position(candidates[1]),
    );
    if (p0 - p1).abs() > 1e-12 {
        return if p0 > p1 {
            candidates[0]
        } else {
            candidates[1]
        };
    }
    // Both corners are right angles: the wall is the perpendicular itself; keep the orientation
    // whose inner side holds the rest of the base.
    let inside = DVec3::new((-sign).sinh(), 0.0, (-sign).cosh());
    if candidates[0].dot(inside) > 0.0 {
        candidates[0]
    } else {
        candidates[1]
    }
}

/// The free parameters of a hyperbolic polygon: the distances from wall N−1 to walls 1 … N−3.
pub(crate) fn parameters_of(space: Space, walls: &[DVec3]) -> Vec<f64> {
    let n = walls.len();
    (1..=n - 3)
        .map(|j| (-space.wall_dot(walls[n - 1], walls[j])).max(1.0).acosh())
        .collect()
}
