//! Textbook fundamental domains of the small families (Conway, Burgiel, Goodman-Strauss, *The
//! Symmetries of Things*, 2008, chapters 4 and 6): lunes for `NN` and `N×`, the doubled triangle
//! for three cones, the isosceles triangle for `k*m`, the folded triangle for `2*mn`, the folded
//! polygon for the rest of `2*k₁…kₙ`. Each is exact where the star would be degenerate (two
//! sectors of width π on the sphere; the cone on both copies of the star's centre for
//! `2*k₁…kₙ`) and has the fewest edges.

use glam::DVec3;

use super::{Construction, Draft, Glue};
use crate::conway::OrbifoldSymbol;
use crate::cover::reflection;
use crate::euler::Geometry;
use crate::layout::{DEFAULT_PARAMETER, Layout, LayoutOptions, Shape};
use crate::layout::{LayoutError, incircle};
use crate::order::Order;
use crate::signature::Signature;
use crate::space::Space;

/// The textbook draft of `symbol`, or `None` when its family is left to the star.
pub(crate) fn draft(
    symbol: &OrbifoldSymbol,
    space: Space,
    parameters: Option<&[f64]>,
) -> Result<Option<Draft>, LayoutError> {
    let geometry = space.geometry();
    let all_orders = symbol
        .cones()
        .iter()
        .chain(symbol.boundaries().iter().flatten());
    if geometry == Geometry::Euclidean && all_orders.clone().any(Order::is_infinite) {
        return Err(LayoutError::Unsupported(format!(
            "{symbol} is a frieze group (a Euclidean strip with a point at infinity); only compact \
             Euclidean orbifolds, the 17 wallpaper groups, are built"
        )));
    }
    let (handles, crosscaps) = (symbol.handles(), symbol.crosscaps());
    let cones = symbol.cones();
    let boundaries = symbol.boundaries();
    if handles == 1 && cones.is_empty() && boundaries.is_empty() && crosscaps == 0 {
        // `o`, the torus: Euclidean, so a parallelogram of any shape.
        return parallelogram(space, parameters).map(Some);
    }
    if handles > 0 {
        return Ok(None);
    }
    let two = Order::integer(2);
    if geometry == Geometry::Euclidean
        && crosscaps == 0
        && boundaries.is_empty()
        && cones.len() == 4
        && cones.iter().all(|&k| k == two)
    {
        // `2222` (p2): half of the lattice's parallelogram, of any shape.
        return folded_parallelogram(space, parameters).map(Some);
    }
    let draft = match (cones, boundaries, crosscaps) {
        ([], [], 0) => {
            return Err(LayoutError::Unsupported(
                "1 is the sphere itself: the trivial group's fundamental domain is the whole \
                 sphere, with no edge to pair"
                    .into(),
            ));
        }
        ([a, b], [], 0) if a == b => lune(*a, false, parameters)?,
        ([], [], 1) => lune(Order::integer(1), true, parameters)?,
        ([a], [], 1) => lune(*a, true, parameters)?,
        ([p, q, r], [], 0) => doubled_triangle(space, [*p, *q, *r], parameters)?,
        ([k], [corners], 0) if corners.len() <= 1 && k.as_integer() != Some(2) => {
            let m = corners.first().copied().unwrap_or(Order::integer(1));
            if k.is_infinite() && m.is_infinite() {
                return Ok(None);
            }
            cone_and_mirror(space, *k, m, parameters)?
        }
        ([k], [corners], 0) if k.as_integer() == Some(2) => match corners.as_slice() {
            [] => folded_on_sphere(space, Order::integer(1), parameters)?,
            [m] => folded_on_sphere(space, *m, parameters)?,
            [m, n] if !n.is_infinite() => folded(space, *m, *n, parameters)?,
            [_, _, ..] => folded_polygon(space, corners, parameters)?,
        },
        _ => return Ok(None),
    };
    Ok(Some(draft))
}

/// The lattice's shape (`o`, `2222`): |b|/|a| and the angle between a and b in degrees.
const LATTICE_RANGES: [(f64, f64); 2] = [(0.0, f64::INFINITY), (0.0, 180.0)];

/// `2*mn`: the angle at B as a fraction of π/n.
const FOLD_RANGE: (f64, f64) = (0.0, 1.0);

/// Checks user parameters against a construction's defaults and open ranges.
pub(crate) fn take_parameters(
    given: Option<&[f64]>,
    defaults: &[f64],
    ranges: &[(f64, f64)],
) -> Result<Vec<f64>, LayoutError> {
    let Some(values) = given else {
        return Ok(defaults.to_vec());
    };
    if values.len() != defaults.len() {
        return Err(LayoutError::ParameterCount {
            expected: defaults.len(),
            given: values.len(),
        });
    }
    for (index, (&value, &(low, high))) in values.iter().zip(ranges).enumerate() {
        if !value.is_finite() {
            return Err(LayoutError::InvalidParameter { index, value });
        }
        if !(value > low && value < high) {
            return Err(LayoutError::ParameterOutOfRange {
                index,
                value,
                low,
                high,
            });
        }
    }
    Ok(values.to_vec())
}

fn ambient(space: Space, z: num_complex::Complex64, ideal: bool) -> DVec3 {
    if ideal {
        DVec3::new(z.re, z.im, 1.0)
    } else {
        space.to_ambient(z)
    }
}

/// The normalised sum of the corners: a point inside any convex polygon (in the gnomonic chart
/// it is a positive combination of the corners).
fn inner_point(space: Space, points: &[DVec3]) -> DVec3 {
    space.normalize_point(points.iter().map(|p| *p / p.z.abs().max(1.0)).sum())
}

/// `NN` (pairing by the rotation about the lune's corners, angle 2π/N) and `N×`, `×` (by the
/// rotatory reflection that swaps them, angle π/N): the lune with corners ±1 of the model.
fn lune(order: Order, crosscap: bool, parameters: Option<&[f64]>) -> Result<Draft, LayoutError> {
    take_parameters(parameters, &[], &[])?;
    let angle = if crosscap {
        order.corner_angle()
    } else {
        2.0 * order.corner_angle()
    };
    let (s, c) = (angle / 2.0).sin_cos();
    Ok(Draft {
        points: vec![DVec3::X, -DVec3::X],
        ideal: vec![false, false],
        orders: vec![order, order],
        walls: Some(vec![DVec3::new(0.0, -c, s), DVec3::new(0.0, c, s)]),
        neighbours: None,
        glue: vec![
            Glue::Paired {
                partner: 1,
                reverses: crosscap,
            },
            Glue::Paired {
                partner: 0,
                reverses: crosscap,
            },
        ],
        centre: DVec3::Z,
        parameters: vec![],
        ranges: vec![],
        meanings: vec![],
        construction: Construction::Lune,
    })
}

/// `o` (p1): the parallelogram 0, a, a + b, b with |a| = 1 (model units) and b = ρ·e^{iθ}; the
/// opposite sides are paired by the translations a and b. Both lattice parameters, ρ = |b|/|a|
/// and θ, are free; every value is valid.
fn parallelogram(space: Space, parameters: Option<&[f64]>) -> Result<Draft, LayoutError> {
    let values = take_parameters(parameters, &[1.0, 90.0], &LATTICE_RANGES)?;
    let (ratio, theta) = (values[0], values[1].to_radians());
    let corners = [
        num_complex::Complex64::new(0.0, 0.0),
        num_complex::Complex64::new(1.0, 0.0),
        num_complex::Complex64::new(1.0 + ratio * theta.cos(), ratio * theta.sin()),
        num_complex::Complex64::from_polar(ratio, theta),
    ];
    let points: Vec<DVec3> = corners.iter().map(|&z| space.to_ambient(z)).collect();
    Ok(Draft {
        centre: inner_point(space, &points),
        points,
        ideal: vec![false; 4],
        orders: vec![Order::integer(1); 4],
        walls: None,
        neighbours: None,
        glue: vec![paired(2), paired(3), paired(0), paired(1)],
        parameters: values,
        ranges: LATTICE_RANGES.to_vec(),
        meanings: vec![
            "the length of the second pair of sides divided by the first's (|b|/|a|); in (0, ∞), default 1".into(),
            "the angle between the two pairs of sides, in degrees; in (0, 180), default 90 (a rectangle)".into(),
        ],
        construction: Construction::Parallelogram,
    })
}

/// `2222` (p2): the half 0, a, a + b/2, b/2 of the lattice's parallelogram spanned by a and b,
/// with the fold points a/2 and (a + b)/2 as corners of angle π. The bottom side is folded about
/// a/2 and the top side about (a + b)/2 by the half-turns there; the left side is paired with the
/// right by the translation a. The corners 0 and a, and b/2 and a + b/2, form the other two cones
/// of order 2 (angles θ + (π − θ) = π). Every lattice is reached, as for `o`.
fn folded_parallelogram(space: Space, parameters: Option<&[f64]>) -> Result<Draft, LayoutError> {
    let values = take_parameters(parameters, &[1.0, 90.0], &LATTICE_RANGES)?;
    let (ratio, theta) = (values[0], values[1].to_radians());
    let a = num_complex::Complex64::new(1.0, 0.0);
    let b = num_complex::Complex64::from_polar(ratio, theta);
    let corners = [
        num_complex::Complex64::new(0.0, 0.0),
        a / 2.0,
        a,
        a + b / 2.0,
        (a + b) / 2.0,
        b / 2.0,
    ];
    let points: Vec<DVec3> = corners.iter().map(|&z| space.to_ambient(z)).collect();
    Ok(Draft {
        centre: inner_point(space, &points),
        points,
        ideal: vec![false; 6],
        orders: vec![Order::integer(2); 6],
        walls: None,
        neighbours: None,
        glue: vec![
            paired(1),
            paired(0),
            paired(5),
            paired(4),
            paired(3),
            paired(2),
        ],
        parameters: values,
        ranges: LATTICE_RANGES.to_vec(),
        meanings: vec![
            "the length of the lattice's second translation divided by the first's (|b|/|a|); \
             in (0, ∞), default 1"
                .into(),
            "the angle between the lattice's two translations, in degrees; in (0, 180), default \
             90 (a rectangular lattice)"
                .into(),
        ],
        construction: Construction::FoldedParallelogram,
    })
}

/// The triangle with these corner angles, built around its inscribed circle as `*pqr` is.
fn triangle(space: Space, angles: [f64; 3], ideal: [bool; 3]) -> Result<[DVec3; 3], LayoutError> {
    let raw = incircle::polygon(space, &angles, &ideal)?;
    Ok([0, 1, 2].map(|i| ambient(space, raw.corners[i], ideal[i])))
}

/// Three cones `pqr`: the triangle P, Q, R of `*pqr` and its reflection R' across PQ; edges
/// PR' and RP are paired by the rotation about P (angle 2π/p), R'Q and QR by the one about Q.
fn doubled_triangle(
    space: Space,
    orders: [Order; 3],
    parameters: Option<&[f64]>,
) -> Result<Draft, LayoutError> {
    take_parameters(parameters, &[], &[])?;
    let [p, q, r] = triangle(
        space,
        orders.map(|k| k.corner_angle()),
        orders.map(|k| k.is_infinite()),
    )?;
    let pq = super::geometry::wall_through(space, p, q, r);
    let qr = super::geometry::wall_through(space, q, r, p);
    let rp = super::geometry::wall_through(space, r, p, q);
    let r2 = space.reflect(pq, r);
    // The rotations about P and Q as products of the triangle's reflections: exact also when
    // both ends of an edge are ideal.
    let (m_pq, m_qr, m_rp) = (
        reflection(space, pq),
        reflection(space, qr),
        reflection(space, rp),
    );
    let about_p = m_pq * m_rp;
    let about_q = m_pq * m_qr;
    let neighbours = vec![about_p, about_q, about_q.inverse(), about_p.inverse()];
    let points = vec![p, r2, q, r];
    let ideal = vec![
        orders[0].is_infinite(),
        orders[2].is_infinite(),
        orders[1].is_infinite(),
        orders[2].is_infinite(),
    ];
    Ok(Draft {
        // The triangle's incentre, so that P, Q, R are exactly the corners of `*pqr`'s layout.
        centre: DVec3::Z,
        points,
        ideal,
        orders: vec![orders[0], orders[2], orders[1], orders[2]],
        walls: None,
        neighbours: Some(neighbours),
        glue: vec![paired(3), paired(2), paired(1), paired(0)],
        parameters: vec![],
        ranges: vec![],
        meanings: vec![],
        construction: Construction::DoubledTriangle,
    })
}

fn paired(partner: usize) -> Glue {
    Glue::Paired {
        partner,
        reverses: false,
    }
}

/// `k*m` and `k*` (k ≥ 3): the isosceles triangle with apex 2π/k at the cone point and base
/// angles π/2m; its legs are paired by the rotation about the apex, its base is a mirror, and
/// the base corners form one corner cycle of angle π/m.
fn cone_and_mirror(
    space: Space,
    k: Order,
    m: Order,
    parameters: Option<&[f64]>,
) -> Result<Draft, LayoutError> {
    take_parameters(parameters, &[], &[])?;
    let base = m.corner_angle() / 2.0;
    let ideal = [k.is_infinite(), m.is_infinite(), m.is_infinite()];
    let points = triangle(space, [2.0 * k.corner_angle(), base, base], ideal)?.to_vec();
    Ok(Draft {
        centre: inner_point(space, &points),
        points,
        ideal: ideal.to_vec(),
        orders: vec![k, m, m],
        walls: None,
        neighbours: None,
        glue: vec![paired(2), Glue::Mirror, paired(0)],
        parameters: vec![],
        ranges: vec![],
        meanings: vec![],
        construction: Construction::ConeAndMirror,
    })
}

/// The glue of a folded triangle A, B, M, C: mirrors AB and CA, and BM, MC paired by the
/// half-turn about M.
fn folded_glue() -> Vec<Glue> {
    vec![Glue::Mirror, paired(2), paired(1), Glue::Mirror]
}

/// `2*m` and `2*` on the sphere: the triangle with the corner π/m at the pole A and two right
/// angles B, C on the equator; the equator arc BC is folded about its midpoint M.
fn folded_on_sphere(
    space: Space,
    m: Order,
    parameters: Option<&[f64]>,
) -> Result<Draft, LayoutError> {
    take_parameters(parameters, &[], &[])?;
    let a = m.corner_angle();
    let on_equator = |t: f64| DVec3::new(t.cos(), t.sin(), 0.0);
    let points = vec![
        DVec3::Z,
        on_equator(0.0),
        on_equator(a / 2.0),
        on_equator(a),
    ];
    Ok(Draft {
        centre: inner_point(space, &points),
        points,
        ideal: vec![false; 4],
        orders: vec![m, Order::integer(1), Order::integer(2), Order::integer(1)],
        walls: None,
        neighbours: None,
        glue: folded_glue(),
        parameters: vec![],
        ranges: vec![],
        meanings: vec![],
        construction: Construction::FoldedTriangle,
    })
}

/// `2*mn` (E² and H²): the triangle with corners π/m at A, β at B and γ = π/n − β at C, mirrors
/// AB and CA, BC folded about its midpoint M. The free parameter is β/(π/n).
fn folded(
    space: Space,
    m: Order,
    n: Order,
    parameters: Option<&[f64]>,
) -> Result<Draft, LayoutError> {
    let values = take_parameters(parameters, &[0.5], &[FOLD_RANGE])?;
    let share = n.corner_angle();
    let (beta, gamma) = (values[0] * share, (1.0 - values[0]) * share);
    let [a, b, c] = triangle(
        space,
        [m.corner_angle(), beta, gamma],
        [m.is_infinite(), false, false],
    )?;
    let mid = space.interpolate(b, c, 0.5);
    let points = vec![a, b, mid, c];
    Ok(Draft {
        centre: inner_point(space, &points),
        points,
        ideal: vec![m.is_infinite(), false, false, false],
        orders: vec![m, n, Order::integer(2), n],
        walls: None,
        neighbours: None,
        glue: folded_glue(),
        parameters: values,
        ranges: vec![FOLD_RANGE],
        meanings: vec![format!(
            "the angle at B as a fraction of π/{n}, the angle that B and C share (the corner of \
             order {n}); in (0, 1), default 0.5 (an isosceles triangle)"
        )],
        construction: Construction::FoldedTriangle,
    })
}

/// `2*k₁…kₙ` (n ≥ 3, or n = 2 with an ideal second corner; always hyperbolic): the polygon of
/// mirrors of `*k₁…kₙ22`, its side PQ between the two right angles folded about its midpoint M
/// by a half-turn.
///
/// Both have the area 2π|χ| (the right angles at P and Q stand for the cone: ½·½ twice against
/// 1 − ½), and P, Q form one cycle of angle π, a plain mirror point. Every group of the family
/// has such a polygon: the shortest path from the cone to the mirror, followed by its image
/// under the half-turn, meets the mirror at right angles at both ends; cutting along it gives
/// this polygon. So the kaleidoscopic layout's n − 1 parameters, each valid in (0, ∞), are all
/// of the family's (Thurston's −3 + 2 + n).
fn folded_polygon(
    space: Space,
    corners: &[Order],
    parameters: Option<&[f64]>,
) -> Result<Draft, LayoutError> {
    let two = Order::integer(2);
    let signature = Signature::new(corners.iter().copied().chain([two, two]))
        .map_err(|e| LayoutError::Unsupported(e.to_string()))?;
    let options = LayoutOptions {
        shape: parameters.map_or(Shape::Default, |p| Shape::Parameters(p.to_vec())),
        ..LayoutOptions::default()
    };
    let layout = Layout::new(&signature, &options)?;
    let n = corners.len();
    let mut points: Vec<DVec3> = layout
        .vertices
        .iter()
        .map(|v| ambient(space, v.position, v.ideal))
        .collect();
    let (p, q) = (points[n], points[n + 1]);
    points.insert(n + 1, space.interpolate(p, q, 0.5));
    let mut ideal: Vec<bool> = layout.vertices.iter().map(|v| v.ideal).collect();
    ideal.insert(n + 1, false);
    let mut orders = corners.to_vec();
    orders.extend([Order::integer(1), two, Order::integer(1)]);
    let mut glue = vec![Glue::Mirror; n + 3];
    (glue[n], glue[n + 1]) = (paired(n + 1), paired(n));
    // The layout's parameter j (j = 1 … n − 1) sets the distance between its walls N − 1 and
    // j, N = n + 2; the fold splits wall n, so they are edges n + 2 and j here.
    let meanings = (1..=layout.parameters.len())
        .map(|j| {
            format!(
                "the distance between mirror edges {} and {j}, as in {signature}: its value in the \
                 balanced (incircle) polygon times the 8th root of the parameter; in (0, ∞), \
                 default {DEFAULT_PARAMETER} (the seed's shape; 1 is the incircle polygon)",
                n + 2
            )
        })
        .collect();
    Ok(Draft {
        centre: inner_point(space, &points),
        points,
        ideal,
        orders,
        walls: None,
        neighbours: None,
        glue,
        meanings,
        parameters: layout.parameters,
        ranges: layout.parameter_ranges,
        construction: Construction::FoldedPolygon,
    })
}
