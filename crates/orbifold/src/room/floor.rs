//! Floor tessellations (seed 6.2.1): the contour-based one and a geodesic subdivision.

use std::collections::HashMap;

use glam::DVec3;

use super::boundary::Boundary;
use super::surface::Surface;
use crate::space::Space;

/// A boundary sample: its ambient point, the side it starts on, and whether it is a corner.
#[derive(Clone, Copy, Debug)]
pub struct Sample {
    /// Ambient coordinates.
    pub point: DVec3,
    /// The side of the loop it lies on (from its start, inclusive).
    pub side: usize,
    /// Whether it is the side's first corner (and so also on the previous side).
    pub corner: bool,
}

/// The boundary sampled so that no piece is longer than `resolution`: every side cut into equal
/// intrinsic lengths, with an even number of samples in all.
pub fn boundary_samples(boundary: &Boundary, resolution: f64) -> Vec<Sample> {
    let mut counts: Vec<usize> = boundary
        .sides
        .iter()
        .map(|s| ((s.length / resolution).ceil() as usize).max(1))
        .collect();
    if counts.iter().sum::<usize>() % 2 == 1 {
        // One more piece on the side whose pieces are longest keeps the pairing symmetric.
        let longest = (0..counts.len())
            .max_by(|&a, &b| {
                let pa = boundary.sides[a].length / counts[a] as f64;
                let pb = boundary.sides[b].length / counts[b] as f64;
                pa.total_cmp(&pb)
            })
            .unwrap_or(0);
        counts[longest] += 1;
    }
    let mut samples = Vec::with_capacity(counts.iter().sum());
    for (i, &n) in counts.iter().enumerate() {
        samples.extend((0..n).map(|k| Sample {
            point: boundary.point_on_side(i, k as f64 / n as f64),
            side: i,
            corner: k == 0,
        }));
    }
    samples
}

/// Whether two samples lie on one geodesic of the boundary (one wall, or one cusp chord), so
/// that the geodesic between them runs along the boundary.
fn on_one_side(boundary: &Boundary, a: Sample, b: Sample) -> bool {
    let n = boundary.len();
    let key = |side: usize| boundary.sides[side].wall.map_or(usize::MAX - side, |w| w);
    let keys = |s: Sample| {
        let previous = (s.side + n - 1) % n;
        [Some(key(s.side)), s.corner.then(|| key(previous))]
    };
    let (ka, kb) = (keys(a), keys(b));
    ka.iter()
        .flatten()
        .any(|k| kb.iter().flatten().any(|l| k == l))
}

/// The seed's contour-based tessellation: sample s₀ … s_{M−1} pairs with s_{M−i}; each pair is
/// joined by a rung sampled at the resolution, and consecutive rungs are zipped into triangles.
/// The starting sample is the one whose longest rung is shortest. For `*` (a hemisphere, whose
/// boundary samples all lie on one great circle) the rungs are the half small circles through
/// the interior, as the seed's straight lines are.
pub fn contour(boundary: &Boundary, resolution: f64) -> Surface {
    let samples = boundary_samples(boundary, resolution);
    let m = samples.len();
    let hemisphere = is_hemisphere(boundary);
    // Start at a corner, so that the first rung does not run along a wall. Of (up to 8 of)
    // those, keep the mesh whose smallest angle is largest.
    let corners: Vec<usize> = (0..m)
        .filter(|&k| {
            let (before, after) = (samples[(k + m - 1) % m], samples[(k + 1) % m]);
            samples[k].corner && (hemisphere || !on_one_side(boundary, before, after))
        })
        .collect();
    let step = corners.len().div_ceil(8).max(1);
    corners
        .iter()
        .step_by(step)
        .map(|&start| contour_from(boundary, &samples, start, resolution))
        .map(|surface| {
            let smallest = surface
                .triangles
                .iter()
                .map(|t| {
                    let [p, q, r] = t.map(|i| surface.points[i as usize]);
                    chord_smallest_angle(boundary.space, p, q, r)
                })
                .fold(f64::INFINITY, f64::min);
            (surface, smallest)
        })
        .max_by(|a, b| a.1.total_cmp(&b.1))
        .map(|(surface, _)| surface)
        .unwrap_or_else(|| contour_from(boundary, &samples, 0, resolution))
}

/// A cheap measure of a small triangle's smallest angle: |det(p, q, r)| (twice its area, to
/// first order, and exactly zero when the three points lie on one geodesic) over the product of
/// its two longer chords — the sine of the smallest angle, to first order. Invariant under
/// isometries; no transcendental functions.
fn chord_smallest_angle(space: Space, p: DVec3, q: DVec3, r: DVec3) -> f64 {
    let square = |d: DVec3| space.point_dot(d, d).max(0.0);
    let mut sides = [square(q - r), square(r - p), square(p - q)];
    sides.sort_by(f64::total_cmp);
    let denominator = (sides[1] * sides[2]).sqrt();
    if denominator == 0.0 {
        return 0.0;
    }
    glam::DMat3::from_cols(p, q, r).determinant().abs() / denominator
}

/// `*`: every boundary sample lies on the one great circle.
fn is_hemisphere(boundary: &Boundary) -> bool {
    boundary.sides.iter().all(|s| s.wall == Some(0)) && boundary.len() == 4
}

/// The contour tessellation pairing sample `start + i` with sample `start − i`.
fn contour_from(boundary: &Boundary, samples: &[Sample], start: usize, resolution: f64) -> Surface {
    let space = boundary.space;
    let m = samples.len();
    let half = m / 2;
    let sample = |i: usize| samples[(start + i) % m];
    let hemisphere = is_hemisphere(boundary);
    // The rungs that cross the polygon: from i = 1 up to (not including) the first pair on one
    // side — after it the rest of the boundary closes the strip.
    let rungs = (1..half)
        .take_while(|&i| hemisphere || !on_one_side(boundary, sample(i), sample(m - i)))
        .count();
    let mut surface = Surface::default();
    let mut previous: Vec<u32> = vec![surface.push(sample(0).point, 0.0)];
    for i in 1..=rungs {
        let (a, b) = (sample(i).point, sample(m - i).point);
        let n = ((rung_length(boundary, a, b, hemisphere) / resolution).ceil() as usize).max(1);
        let rung: Vec<u32> = (0..=n)
            .map(|k| {
                let t = k as f64 / n as f64;
                let p = if hemisphere {
                    small_circle_point(boundary.centre, a, b, t)
                } else {
                    space.interpolate(a, b, t)
                };
                surface.push(p, 0.0)
            })
            .collect();
        zip(&mut surface, &previous, &rung, space);
        previous = rung;
    }
    // The rest of the boundary, from the top side round to the bottom side, closes the strip.
    let rest: Vec<u32> = (rungs + 1..=m - rungs - 1)
        .map(|i| surface.push(sample(i).point, 0.0))
        .collect();
    zip(&mut surface, &previous, &rest, space);
    surface
}

fn rung_length(boundary: &Boundary, a: DVec3, b: DVec3, hemisphere: bool) -> f64 {
    if hemisphere {
        // Half of the small circle with diameter the chord a b.
        std::f64::consts::PI * 0.5 * (a - b).length()
    } else {
        boundary.space.ambient_distance(a, b)
    }
}

/// The point at fraction `t` of the half small circle from `a` to `b` (both on the great circle
/// with pole `pole`) that passes over the pole's side: centre (a + b)/2, in the plane spanned by
/// b − a and the pole.
fn small_circle_point(pole: DVec3, a: DVec3, b: DVec3, t: f64) -> DVec3 {
    let centre = 0.5 * (a + b);
    let radius = 0.5 * (b - a).length();
    let e = (b - a) / (2.0 * radius);
    let theta = std::f64::consts::PI * (1.0 - t);
    (centre + radius * (theta.cos() * e + theta.sin() * pole)).normalize()
}

/// Triangulates the strip between two chains of vertices whose first and last vertices are
/// joined by the boundary. The chains advance in step by their fraction of the way along (so that
/// a diagonal is never much longer than the gap between the chains plus one piece), unless the
/// other choice makes a triangle with a much larger smallest angle (near corners, where three
/// samples of one wall would make a flat triangle).
fn zip(surface: &mut Surface, a: &[u32], b: &[u32], space: Space) {
    let (mut j, mut k) = (0, 0);
    let fraction = |i: usize, chain: &[u32]| i as f64 / (chain.len() - 1).max(1) as f64;
    let smallest_angle = |s: &Surface, t: [u32; 3]| {
        let [p, q, r] = t.map(|i| s.points[i as usize]);
        chord_smallest_angle(space, p, q, r)
    };
    while j + 1 < a.len() || k + 1 < b.len() {
        let along_a = [a[j], a[j + 1.min(a.len() - 1 - j)], b[k]];
        let along_b = [a[j], b[k + 1.min(b.len() - 1 - k)], b[k]];
        let advance_a = if j + 1 == a.len() {
            false
        } else if k + 1 == b.len() {
            true
        } else {
            let in_step = fraction(j + 1, a) <= fraction(k + 1, b);
            let (qa, qb) = (
                smallest_angle(surface, along_a),
                smallest_angle(surface, along_b),
            );
            if in_step {
                qa >= 0.5 * qb
            } else {
                qb < 0.5 * qa
            }
        };
        if advance_a {
            surface.push_upward(along_a);
            j += 1;
        } else {
            surface.push_upward(along_b);
            k += 1;
        }
    }
}

/// The number of midpoint subdivisions after which no edge of the fan is longer than
/// `resolution`.
pub fn geodesic_levels(boundary: &Boundary, resolution: f64) -> u32 {
    let space = boundary.space;
    let radial = boundary
        .corners
        .iter()
        .map(|&c| space.ambient_distance(boundary.centre, c));
    let longest = boundary
        .sides
        .iter()
        .map(|s| s.length)
        .chain(radial)
        .fold(0.0, f64::max);
    let mut levels = 0;
    // Interior edges shrink a little slower than halving in curved space: test, don't assume.
    while longest / f64::from(1u32 << levels.min(30)) > resolution && levels < 30 {
        levels += 1;
    }
    levels
}

/// A fan from the centre to the corners, each triangle split into four at its edges' geodesic
/// midpoints until every edge is at most `resolution` long.
pub fn geodesic(boundary: &Boundary, resolution: f64) -> Surface {
    let space = boundary.space;
    let mut surface = Surface::default();
    let centre = surface.push(boundary.centre, 0.0);
    let corners: Vec<u32> = boundary
        .corners
        .iter()
        .map(|&c| surface.push(c, 0.0))
        .collect();
    let n = corners.len();
    let mut triangles: Vec<[u32; 3]> = (0..n)
        .map(|i| [centre, corners[i], corners[(i + 1) % n]])
        .collect();
    let too_long = |s: &Surface, t: &[[u32; 3]]| {
        t.iter().any(|t| {
            (0..3).any(|k| {
                let (p, q) = (s.points[t[k] as usize], s.points[t[(k + 1) % 3] as usize]);
                space.ambient_distance(p, q) > resolution
            })
        })
    };
    let mut midpoints: HashMap<(u32, u32), u32> = HashMap::new();
    // On the sphere a triangle's midline is a little longer than half its base, so a level or two
    // more than the estimate may be needed; never more.
    let mut levels_left = geodesic_levels(boundary, resolution) + 2;
    while levels_left > 0 && too_long(&surface, &triangles) {
        levels_left -= 1;
        midpoints.clear();
        let mut midpoint = |s: &mut Surface, i: u32, j: u32| {
            *midpoints.entry((i.min(j), i.max(j))).or_insert_with(|| {
                let (p, q) = (s.points[i as usize], s.points[j as usize]);
                s.push(space.interpolate(p, q, 0.5), 0.0)
            })
        };
        triangles = triangles
            .iter()
            .flat_map(|&[a, b, c]| {
                let (ab, bc, ca) = (
                    midpoint(&mut surface, a, b),
                    midpoint(&mut surface, b, c),
                    midpoint(&mut surface, c, a),
                );
                [[a, ab, ca], [ab, b, bc], [ca, bc, c], [ab, bc, ca]]
            })
            .collect();
    }
    for t in triangles {
        surface.push_upward(t);
    }
    surface
}
