//! Polygons with an inscribed circle: every triangle, and the balanced shape of every hyperbolic
//! polygon (`--shape incircle`).
//!
//! Drop perpendiculars from the incircle's centre O to the walls. The right triangle O, foot,
//! corner has the inradius r at O's side, angle φ at O and α/2 at the corner, so
//! cos(α/2) = C_κ(r)·sin φ. The half-gaps φᵢ between feet must add up to π, which fixes r: in the
//! hyperbolic plane Σφᵢ falls from Σ(π/2 − αᵢ/2) > π at r = 0 towards 0, on the sphere it rises;
//! the Euclidean φᵢ do not depend on r, whose value sets the scale.

use std::f64::consts::PI;

use glam::DVec3;
use num_complex::Complex64;

use super::{LayoutError, ParameterMeaning, RawPolygon};
use crate::space::Space;

/// The polygon with the given corner angles (counter-clockwise) and an inscribed circle centred
/// at the origin, with corner 0 on the positive real axis.
pub(crate) fn polygon(
    space: Space,
    angles: &[f64],
    ideal: &[bool],
) -> Result<RawPolygon, LayoutError> {
    let r = inradius(space, angles)?;
    let half_gaps: Vec<f64> = angles.iter().map(|&a| half_gap(space, r, a)).collect();
    let n = angles.len();
    // Wall i touches the circle at bearing θᵢ; corner i sits midway between walls i − 1 and i.
    let bearings: Vec<f64> = half_gaps
        .iter()
        .scan(-half_gaps[0], |theta, &phi| {
            *theta += 2.0 * phi;
            Some(*theta)
        })
        .collect();
    let (c, s) = (space.cos(r), space.sin(r));
    let walls = bearings
        .iter()
        .map(|&t| DVec3::new(-c * t.cos(), -c * t.sin(), s))
        .collect();
    let mut corner_bearing = 0.0;
    let corners = (0..n)
        .map(|i| {
            if i > 0 {
                corner_bearing += half_gaps[i - 1] + half_gaps[i];
            }
            let direction = Complex64::from_polar(1.0, corner_bearing);
            if ideal[i] {
                return direction;
            }
            // T_κ(d) = T_κ(r)/cos φ, and the model radius is T_κ(d/2) = x/(1 + √(1 + κx²)).
            let x = space.tan(r) / half_gaps[i].cos();
            direction * (x / (1.0 + (1.0 + space.kappa() * x * x).max(0.0).sqrt()))
        })
        .collect();
    let parameters = Vec::new();
    let mut raw = RawPolygon {
        walls,
        corners,
        parameters,
        meaning: ParameterMeaning::None,
        centre: Complex64::new(0.0, 0.0),
    };
    if n >= 4 {
        // The balanced polygon is where every relative comb distance is 1.
        raw.parameters = vec![1.0; n - 3];
        raw.meaning = ParameterMeaning::WallDistances;
    }
    Ok(raw)
}

/// φ with cos(α/2) = C_κ(r)·sin φ.
fn half_gap(space: Space, r: f64, angle: f64) -> f64 {
    ((angle / 2.0).cos() / space.cos(r)).clamp(-1.0, 1.0).asin()
}

fn gap_excess(space: Space, r: f64, angles: &[f64]) -> f64 {
    angles.iter().map(|&a| half_gap(space, r, a)).sum::<f64>() - PI
}

/// The inradius: r with Σφᵢ(r) = π, by bisection (monotone in r for κ ≠ 0).
fn inradius(space: Space, angles: &[f64]) -> Result<f64, LayoutError> {
    if space.kappa() == 0.0 {
        // Any r works; choose the scale at which the farthest corner is 2 from the centre
        // (model radius 1): d = r / cos φ.
        let min_cos = angles
            .iter()
            .map(|&a| (PI / 2.0 - a / 2.0).cos())
            .fold(f64::INFINITY, f64::min);
        return Ok(2.0 * min_cos);
    }
    let (mut lo, mut hi) = if space.kappa() > 0.0 {
        // cos(α/2) ≤ cos r for every corner: r ≤ min α/2.
        let hi = angles.iter().fold(f64::INFINITY, |m, &a| m.min(a / 2.0));
        if gap_excess(space, hi, angles) < 0.0 {
            return Err(LayoutError::Unrealisable(
                "no spherical triangle has these angles: each angle must be less than π minus the difference of the other two".into(),
            ));
        }
        (0.0, hi)
    } else {
        let mut hi = 1.0;
        while gap_excess(space, hi, angles) > 0.0 {
            hi *= 2.0;
        }
        (0.0, hi)
    };
    let increasing = space.kappa() > 0.0;
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if mid <= lo || mid >= hi {
            break;
        }
        let above = gap_excess(space, mid, angles) > 0.0;
        if above == increasing {
            hi = mid;
        } else {
            lo = mid;
        }
    }
    Ok(0.5 * (lo + hi))
}
