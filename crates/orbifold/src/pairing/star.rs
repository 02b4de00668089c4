//! The star: a fundamental polygon for every orbifold from one construction (docs/orbifolds.md).
//!
//! Cut the orbifold along arcs from one ordinary point v to every feature (the cut system of the
//! classification of surfaces; Conway, Burgiel, Goodman-Strauss, *The Symmetries of Things*,
//! 2008, ch. 8; Maskit 1971 for the gluing). Unrolled, the copies of v lie on a circle of radius
//! R about a centre O, and every feature owns a sector of the circle between two copies:
//!
//! - a **cone** of order a: two edges meeting at the cone point with angle 2π/a (on the sector's
//!   axis; at infinity for a = ∞), paired by the rotation about it;
//! - a **handle**: four sectors x y x̄ ȳ with one edge each, x̄ paired with x and ȳ with y by
//!   orientation-preserving isometries (translations along their axes);
//! - a **cross-cap**: two sectors z z, the second paired with the first by a glide reflection;
//! - a **mirror boundary** `*b₁…bₙ`: an edge d out to the boundary, ending at P₀, the mirror
//!   edges through the corners (angle π/bᵢ), and an edge d̄ back from P_{n+1}, paired with d;
//!   P₀ and P_{n+1} form one cycle of angle π. Without corners the mirror is one edge
//!   perpendicular to the sector's axis, d meets it at a right angle at P₀ and d̄ is d's mirror
//!   image across the axis, paired with it by r_d ∘ r_axis (π/2 + π/2 = π).
//!
//! Pairing a sector with its partner needs only that the two chords have the same length, so
//! paired sectors have the same width. All the other vertex cycles have their angle sums by
//! construction; the copies of v form one cycle, whose angle sum is 2π when R is right: in E² for
//! every R (R = 1 sets the scale), in H² for one R, found by bisection (the sum falls as R grows).
//!
//! A symbol with a boundary that has corners gets the **balanced star** instead: the same
//! corners, in the same order and with the same pairings, placed as the polygon with an inscribed
//! circle and the cycles' angles (2π/N at each of the N copies of v, π/2 at P₀ and P_{n+1}). In a
//! polygon with an inscribed circle the tangent lengths depend only on the angles (the two
//! tangent segments from a corner are legs of congruent right triangles), so every paired edge
//! has its partner's length; the polygon is the one of `--shape incircle` (layout/incircle.rs).
//! It is rigid but exists for every good hyperbolic symbol; the circle of radius R with both
//! ends of a cut at right angles does not (docs/orbifolds.md).
//!
//! In H² both are the default of [`super::deform`], which offers every free parameter (lengths
//! of closed geodesics) by deforming them; the cut and width parameters here are E²'s.

use std::f64::consts::{FRAC_1_SQRT_2, FRAC_PI_2, PI, SQRT_2, TAU};

use glam::DVec3;
use num_complex::Complex64;

use super::geometry::{bisect, corner_angle, foot, ideal_at, polar};
use super::textbook::take_parameters;
use super::{Construction, Draft, Glue};
use crate::conway::OrbifoldSymbol;
use crate::euler::Geometry;
use crate::isometry::Isometry;
use crate::layout::{LayoutError, incircle};
use crate::order::Order;
use crate::space::Space;

/// The largest cut of a boundary without corners: longer cut edges put the mirror so far out
/// (cosh of the distance beyond 10⁴ in H²) that its corners' right angles lose digits.
pub const CUT_MAX: f64 = 2.0;

/// The valid range of a sector-width parameter: any two widths differ by less than a factor 2,
/// so that every sector is narrower than π when there are three sectors or more.
pub const WIDTH_RANGE: (f64, f64) = (FRAC_1_SQRT_2, SQRT_2);

/// What a sector holds.
#[derive(Clone, Debug, PartialEq)]
enum Kind {
    /// One edge of a handle or a cross-cap.
    Plain,
    /// A cone point of this order.
    Cone(Order),
    /// A mirror boundary with these corners.
    Boundary(Vec<Order>),
}

#[derive(Clone, Debug)]
struct Sector {
    kind: Kind,
    /// Sectors of one group have the same width (a handle's x and x̄, a cross-cap's z z).
    group: usize,
}

/// The sectors of a symbol, their width groups and the pairs of plain sectors.
#[derive(Clone, Debug)]
struct Plan {
    sectors: Vec<Sector>,
    /// A name for each width group.
    groups: Vec<String>,
    /// (sector, partner sector, orientation-reversing).
    pairs: Vec<(usize, usize, bool)>,
}

fn plan(symbol: &OrbifoldSymbol) -> Plan {
    let mut plan = Plan {
        sectors: Vec::new(),
        groups: Vec::new(),
        pairs: Vec::new(),
    };
    let group = |plan: &mut Plan, name: String| {
        plan.groups.push(name);
        plan.groups.len() - 1
    };
    for h in 0..symbol.handles() as usize {
        let x = group(&mut plan, format!("handle {}'s edge x", h + 1));
        let y = group(&mut plan, format!("handle {}'s edge y", h + 1));
        let s = plan.sectors.len();
        for g in [x, y, x, y] {
            plan.sectors.push(Sector {
                kind: Kind::Plain,
                group: g,
            });
        }
        plan.pairs.push((s, s + 2, false));
        plan.pairs.push((s + 1, s + 3, false));
    }
    for (i, &k) in symbol.cones().iter().enumerate() {
        let g = group(&mut plan, format!("cone {} (order {k})", i + 1));
        plan.sectors.push(Sector {
            kind: Kind::Cone(k),
            group: g,
        });
    }
    for (i, corners) in symbol.boundaries().iter().enumerate() {
        let g = group(&mut plan, format!("mirror boundary {}", i + 1));
        plan.sectors.push(Sector {
            kind: Kind::Boundary(corners.clone()),
            group: g,
        });
    }
    for c in 0..symbol.crosscaps() as usize {
        let g = group(&mut plan, format!("cross-cap {}", c + 1));
        let s = plan.sectors.len();
        for _ in 0..2 {
            plan.sectors.push(Sector {
                kind: Kind::Plain,
                group: g,
            });
        }
        plan.pairs.push((s, s + 1, true));
    }
    plan
}

/// The shape: a width weight per group and a cut parameter per boundary.
#[derive(Clone, Debug)]
struct Shape {
    weights: Vec<f64>,
    cuts: Vec<f64>,
}

/// The star's draft for `symbol` (E² and H²): the balanced star when a boundary has corners.
pub(crate) fn draft(
    symbol: &OrbifoldSymbol,
    space: Space,
    parameters: Option<&[f64]>,
) -> Result<Draft, LayoutError> {
    if space.geometry() == Geometry::Spherical {
        return Err(LayoutError::Unsupported(format!(
            "{symbol}: no spherical family is built by the star"
        )));
    }
    let plan = plan(symbol);
    if symbol.boundaries().iter().any(|c| !c.is_empty()) {
        return balanced_draft(space, &plan, parameters);
    }
    let boundaries = symbol.boundaries().len();
    let widths = if plan.sectors.len() >= 3 {
        plan.groups.len() - 1
    } else {
        0
    };
    let supported = (boundaries + widths).min(symbol.free_parameters());
    let mut ranges = vec![(0.0, CUT_MAX); boundaries];
    ranges.extend(vec![WIDTH_RANGE; widths]);
    ranges.truncate(supported);
    let defaults = vec![1.0; supported];
    let values = take_parameters(parameters, &defaults, &ranges)?;
    let mut shape = Shape {
        weights: vec![1.0; plan.groups.len()],
        cuts: vec![1.0; boundaries],
    };
    for (i, &v) in values.iter().enumerate() {
        if i < boundaries {
            shape.cuts[i] = v;
        } else {
            shape.weights[i - boundaries + 1] = v;
        }
    }
    let star = close(space, &plan, &shape)?;
    let meanings = meanings(symbol, &plan, supported);
    Ok(Draft {
        points: star.points,
        ideal: star.ideal,
        orders: star.orders,
        walls: None,
        neighbours: None,
        glue: star.glue,
        centre: DVec3::Z,
        parameters: values,
        ranges,
        meanings,
        construction: Construction::Star,
    })
}

fn meanings(symbol: &OrbifoldSymbol, plan: &Plan, supported: usize) -> Vec<String> {
    let mut out: Vec<String> = (1..=symbol.boundaries().len())
        .map(|i| {
            format!(
                "mirror boundary {i}: the length of the cut edge d from the circle of v to the \
                 mirror, in units of the distance from v to the sector's axis; in (0, 2), default 1"
            )
        })
        .collect();
    out.extend(plan.groups.iter().skip(1).map(|g| {
        format!(
            "the width of the sector(s) of {g}, relative to those of {}; in (1/√2, √2), default 1",
            plan.groups[0]
        )
    }));
    out.truncate(supported);
    out
}

/// Solves R and checks that the star is convex at the copies of v.
fn close(space: Space, plan: &Plan, shape: &Shape) -> Result<Star, LayoutError> {
    let r = solve_radius(space, plan, shape)?;
    let star = assemble(space, plan, shape, r)?;
    if convex_at_copies(space, &star) {
        Ok(star)
    } else {
        Err(LayoutError::Unrealisable(
            "the star is not convex at v".into(),
        ))
    }
}

/// Whether every copy of v has an interior angle below π.
fn convex_at_copies(space: Space, star: &Star) -> bool {
    let n = star.points.len();
    star.copies.iter().all(|&v| {
        corner_angle(
            space,
            star.points[v],
            star.points[(v + 1) % n],
            star.points[(v + n - 1) % n],
        ) < PI + 1e-9
    })
}

/// The star polygon at radius R.
struct Star {
    points: Vec<DVec3>,
    ideal: Vec<bool>,
    orders: Vec<Order>,
    glue: Vec<Glue>,
    /// The indices of the copies of v.
    copies: Vec<usize>,
}

/// The sectors' widths: their groups' weights, scaled to add up to 2π.
fn widths(plan: &Plan, shape: &Shape) -> Vec<f64> {
    let weight = |g: usize| shape.weights[g];
    let total: f64 = plan.sectors.iter().map(|s| weight(s.group)).sum();
    plan.sectors
        .iter()
        .map(|s| TAU * weight(s.group) / total)
        .collect()
}

fn assemble(space: Space, plan: &Plan, shape: &Shape, r: f64) -> Result<Star, LayoutError> {
    let widths = widths(plan, shape);
    let mut star = Star {
        points: Vec::new(),
        ideal: Vec::new(),
        orders: Vec::new(),
        glue: Vec::new(),
        copies: Vec::new(),
    };
    let mut first_edge = Vec::new();
    let mut bearing = 0.0;
    let mut boundary = 0;
    for (sector, &delta) in plan.sectors.iter().zip(&widths) {
        let e = star.points.len();
        first_edge.push(e);
        star.copies.push(e);
        star.points.push(polar(space, r, bearing));
        star.ideal.push(false);
        star.orders.push(Order::integer(1));
        star.glue.push(Glue::Mirror);
        let inner: Vec<(DVec3, bool, Order)> = match &sector.kind {
            Kind::Plain => vec![],
            Kind::Cone(k) => {
                let (p, ideal) = cone_apex(space, r, delta, *k)?;
                vec![(p, ideal, *k)]
            }
            Kind::Boundary(_) => {
                boundary += 1;
                boundary_chain(space, r, delta, shape.cuts[boundary - 1])?
            }
        };
        let turn = Isometry::rotation(space, bearing + delta / 2.0);
        for (p, ideal, order) in &inner {
            star.points.push(turn.apply_ambient(*p));
            star.ideal.push(*ideal);
            star.orders.push(*order);
            star.glue.push(Glue::Mirror);
        }
        let last = star.points.len() - 1;
        match sector.kind {
            Kind::Plain => {}
            // The cone's two edges, and a boundary's d and d̄, are paired with each other.
            _ => pair(&mut star.glue, e, last, false),
        }
        bearing += delta;
    }
    for &(a, b, reverses) in &plan.pairs {
        pair(&mut star.glue, first_edge[a], first_edge[b], reverses);
    }
    Ok(star)
}

fn pair(glue: &mut [Glue], a: usize, b: usize, reverses: bool) {
    glue[a] = Glue::Paired {
        partner: b,
        reverses,
    };
    glue[b] = Glue::Paired {
        partner: a,
        reverses,
    };
}

/// The sum of the interior angles at the copies of v.
fn copies_angle_sum(space: Space, star: &Star) -> f64 {
    let n = star.points.len();
    star.copies
        .iter()
        .map(|&v| {
            corner_angle(
                space,
                star.points[v],
                star.points[(v + 1) % n],
                star.points[(v + n - 1) % n],
            )
        })
        .sum()
}

/// R: 1 in E² (the scale); in H² the root of (angle sum at v) = 2π, which falls as R grows.
fn solve_radius(space: Space, plan: &Plan, shape: &Shape) -> Result<f64, LayoutError> {
    if space.kappa() == 0.0 {
        return Ok(1.0);
    }
    let excess = |r: f64| {
        assemble(space, plan, shape, r).map_or(f64::NAN, |s| copies_angle_sum(space, &s) - TAU)
    };
    // On a geometric grid of radii, the first change of sign between two radii where the
    // construction exists (it may exist only on an interval of R). A jump across π (a corner turning reflex) is not a root: the root's
    // polygon is checked for convexity afterwards.
    let grid: Vec<f64> = (0..=120).map(|i| 1e-3 * 1.08f64.powi(i)).collect();
    let values: Vec<f64> = grid.iter().map(|&r| excess(r)).collect();
    let Some(i) = (0..grid.len() - 1)
        .find(|&i| values[i] * values[i + 1] < 0.0 && (values[i] - values[i + 1]).abs() < PI)
    else {
        return Err(LayoutError::Unrealisable(
            "the star's corner circle has no radius at which the angles at v add up to 2π".into(),
        ));
    };
    let (lo, hi) = (grid[i], grid[i + 1]);
    Ok(bisect(lo, hi, excess))
}

/// The cone point of a sector of width Δ between copies of v at radius R, on the sector's axis
/// (the positive real axis), where the sector's two edges meet at 2π/a.
fn cone_apex(space: Space, r: f64, delta: f64, order: Order) -> Result<(DVec3, bool), LayoutError> {
    if order.is_infinite() {
        return Ok((ideal_at(0.0), true));
    }
    // In the triangle O, v, C: the angle Δ/2 at O, half the cone angle at C, the side R = Ov
    // opposite C. The four-part cotangent formula, C(b)·cos A = S(b)·C(R)/S(R) − sin A·cot γ,
    // gives b = OC in closed form in each geometry.
    let (a, gamma) = (delta / 2.0, order.corner_angle());
    let (x, k) = (a.cos(), a.sin() / gamma.tan());
    let (c, s) = space.cos_sin(r);
    let y = c / s;
    let b = match space.kappa() {
        kappa if kappa < 0.0 => {
            let norm = (y * y - x * x).sqrt();
            (x / y).atanh() + (k / norm).asinh()
        }
        kappa if kappa > 0.0 => {
            let norm = (y * y + x * x).sqrt();
            x.atan2(y) + (k / norm).clamp(-1.0, 1.0).asin()
        }
        _ => r * (x + k),
    };
    if !(b.is_finite() && b > 0.0) {
        return Err(LayoutError::Unrealisable(format!(
            "no point on a sector's axis sees its chord at 2π/{order}"
        )));
    }
    Ok((polar(space, b, 0.0), false))
}

/// The distance from the copies of v at radius R to the axis of a sector of width Δ.
fn axis_offset(space: Space, r: f64, delta: f64) -> f64 {
    space.asin(space.sin(r) * (delta / 2.0).sin())
}

/// The points P₀, P₁ of a boundary sector without corners (local frame: the axis is the positive
/// real axis), each with its ideal flag and its cycle's order.
fn boundary_chain(
    space: Space,
    r: f64,
    delta: f64,
    cut: f64,
) -> Result<Vec<(DVec3, bool, Order)>, LayoutError> {
    let below = polar(space, r, -delta / 2.0);
    let offset = axis_offset(space, r, delta);
    let one = Order::integer(1);
    let p0 = mirror_foot(space, r, delta, below, cut * offset)?;
    let p1 = DVec3::new(p0.x, -p0.y, p0.z);
    Ok(vec![(p0, false, one), (p1, false, one)])
}

/// n = 0: the foot P₀ on the mirror perpendicular to the axis at the distance that makes the cut
/// edge from v (at `below`) to it `length` long.
fn mirror_foot(
    space: Space,
    r: f64,
    delta: f64,
    below: DVec3,
    length: f64,
) -> Result<DVec3, LayoutError> {
    let wall =
        |t: f64| -Isometry::translation_by(space, t, Complex64::new(1.0, 0.0)).apply_wall(DVec3::X);
    let start = space.atan(space.tan(r) * (delta / 2.0).cos());
    let distance = |t: f64| space.asin(wall(t).dot(below)) - length;
    let mut hi = start + 2.0 * length + 1.0;
    while distance(hi) < 0.0 && hi < 60.0 {
        hi *= 2.0;
    }
    if distance(hi).is_nan() || distance(hi) <= 0.0 {
        return Err(LayoutError::Unrealisable(
            "the mirror of a boundary without corners cannot be that far out".into(),
        ));
    }
    let t = bisect(start, hi, distance);
    Ok(foot(space, wall(t), below))
}

/// The balanced star of a symbol with a mirror boundary that has corners: the polygon of the
/// star's combinatorics (copies of v, cone points, P₀, corners, P_{n+1}) with the cycles' angles
/// and an inscribed circle, which has no free parameter.
fn balanced_draft(
    space: Space,
    plan: &Plan,
    parameters: Option<&[f64]>,
) -> Result<Draft, LayoutError> {
    let values = take_parameters(parameters, &[], &[])?;
    let star = balanced(space, plan)?;
    Ok(Draft {
        points: star.points,
        ideal: star.ideal,
        orders: star.orders,
        walls: None,
        neighbours: None,
        glue: star.glue,
        centre: DVec3::Z,
        parameters: values,
        ranges: vec![],
        meanings: Vec::new(),
        construction: Construction::Star,
    })
}

/// A corner of the balanced star: its interior angle, whether it is ideal, its cycle's order.
type Corner = (f64, bool, Order);

/// The corners a sector adds after its copy of v.
fn sector_corners(kind: &Kind) -> Vec<Corner> {
    let one = Order::integer(1);
    let corner = |k: &Order| (k.corner_angle(), k.is_infinite(), *k);
    match kind {
        Kind::Plain => vec![],
        // The cone angle 2π/a is twice the corner angle π/a.
        Kind::Cone(k) => vec![(2.0 * k.corner_angle(), k.is_infinite(), *k)],
        Kind::Boundary(corners) => {
            let mut out = vec![(FRAC_PI_2, false, one)];
            out.extend(corners.iter().map(corner));
            out.push((FRAC_PI_2, false, one));
            out
        }
    }
}

/// The balanced star (docs/orbifolds.md): every copy of v gets the angle 2π/N (N sectors), a
/// cone of order a its 2π/a, a corner of order b its π/b, and the ends P₀, P_{n+1} of a cut to a
/// boundary π/2 each; the polygon with these angles and an inscribed circle exists in H² because
/// its angles add up to less than (corners − 2)·π (their defect is the area 2π|χ| > 0).
///
/// Why the pairings are isometries: in a polygon with an inscribed circle the two tangent
/// segments from a corner have the same length, which depends only on the corner's angle
/// (sinh t = tanh r / tan(α/2) in H²). A paired edge runs between a copy of v and a cone point
/// or a cut's end, or between two copies of v, so every edge and its partner are the sums of
/// tangent segments of equal angles: they have equal lengths. At an ideal cone point the two edges'
/// tangency points lie on one horocycle about it, so the pairing is parabolic.
fn balanced(space: Space, plan: &Plan) -> Result<Star, LayoutError> {
    let n = plan.sectors.len();
    if n < 2 {
        return Err(LayoutError::Unrealisable(
            "a balanced star needs two sectors or more".into(),
        ));
    }
    let one = Order::integer(1);
    let v_angle = TAU / n as f64;
    let mut corners: Vec<Corner> = Vec::new();
    let mut star = Star {
        points: Vec::new(),
        ideal: Vec::new(),
        orders: Vec::new(),
        glue: Vec::new(),
        copies: Vec::new(),
    };
    let mut first_edge = Vec::new();
    for sector in &plan.sectors {
        let e = corners.len();
        first_edge.push(e);
        star.copies.push(e);
        corners.push((v_angle, false, one));
        corners.extend(sector_corners(&sector.kind));
        star.glue.resize(corners.len(), Glue::Mirror);
        if sector.kind != Kind::Plain {
            // The cone's two edges, and a boundary's d and d̄, are paired with each other.
            pair(&mut star.glue, e, corners.len() - 1, false);
        }
    }
    for &(a, b, reverses) in &plan.pairs {
        pair(&mut star.glue, first_edge[a], first_edge[b], reverses);
    }
    let angles: Vec<f64> = corners.iter().map(|c| c.0).collect();
    let ideal: Vec<bool> = corners.iter().map(|c| c.1).collect();
    let raw = incircle::polygon(space, &angles, &ideal)?;
    star.points = raw
        .corners
        .iter()
        .zip(&ideal)
        .map(|(&z, &i)| {
            if i {
                ideal_at(z.arg())
            } else {
                space.to_ambient(z)
            }
        })
        .collect();
    star.ideal = ideal;
    star.orders = corners.iter().map(|c| c.2).collect();
    Ok(star)
}
