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
//! - a **mirror boundary** `*b₁…bₙ`: an edge d out to the boundary, meeting it at a right angle
//!   at P₀, the mirror edges through corners of angle π/bᵢ, and an edge d̄ back from P_{n+1},
//!   the mirror image of d across the sector's axis; d̄ is paired with d by r_d ∘ r_axis, so P₀
//!   and P_{n+1} form one cycle of angle π/2 + π/2 = π. For n ≥ 1 the corners lie on a *cap*: the
//!   polygon with angles φ, π/b₁, …, π/bₙ, φ and an inscribed circle, whose side P_{n+1}P₀ (the
//!   chord) is perpendicular to the axis; for n = 0 the mirror is one edge perpendicular to the
//!   axis.
//!
//! Pairing a sector with its partner needs only that the two chords have the same length, so
//! paired sectors have the same width. All the other vertex cycles have their angle sums by
//! construction; the copies of v form one cycle, whose angle sum is 2π when R is right: in E² for
//! every R (R = 1 sets the scale), in H² for one R, found by bisection (the sum falls as R grows).

use std::f64::consts::{FRAC_1_SQRT_2, PI, SQRT_2, TAU};

use glam::DVec3;
use num_complex::Complex64;

use super::geometry::{bisect, corner_angle, foot, ideal_at, polar, toward};
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
    /// A base weight per group, the construction's own (see [`BASES`]); 1 but for the sectors
    /// of boundaries with corners.
    bases: Vec<f64>,
    cuts: Vec<f64>,
    /// The cap of each boundary with corners, which does not depend on R.
    caps: Vec<Option<Cap>>,
}

/// The star's draft for `symbol` (E² and H²).
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
    let boundaries = symbol.boundaries().len();
    let widths = if plan.sectors.len() >= 3 {
        plan.groups.len() - 1
    } else {
        0
    };
    let supported = (boundaries + widths).min(symbol.free_parameters());
    // A boundary with corners in H² takes its cut in (0, 1) (default ½); the others in (0, ∞)
    // (default 1).
    let cut_ranges: Vec<(f64, f64)> = symbol
        .boundaries()
        .iter()
        .map(|c| {
            if c.is_empty() {
                (0.0, CUT_MAX)
            } else {
                (0.0, 1.0)
            }
        })
        .collect();
    let cut_defaults: Vec<f64> = cut_ranges
        .iter()
        .map(|&(_, high)| if high == 1.0 { 0.5 } else { 1.0 })
        .collect();
    let mut ranges = cut_ranges;
    ranges.extend(vec![WIDTH_RANGE; widths]);
    ranges.truncate(supported);
    let mut defaults = cut_defaults.clone();
    defaults.extend(vec![1.0; widths]);
    defaults.truncate(supported);
    let values = take_parameters(parameters, &defaults, &ranges)?;
    let mut shape = Shape {
        weights: vec![1.0; plan.groups.len()],
        bases: vec![1.0; plan.groups.len()],
        cuts: cut_defaults,
        caps: vec![None; boundaries],
    };
    for (i, &v) in values.iter().enumerate() {
        if i < boundaries {
            shape.cuts[i] = v;
        } else {
            shape.weights[i - boundaries + 1] = v;
        }
    }
    // A boundary with corners closes up only for some cuts and widths (docs/orbifolds.md): its
    // sector's base width is searched, and without given parameters its cut too.
    let with_corners: Vec<bool> = symbol.boundaries().iter().map(|c| !c.is_empty()).collect();
    let boundary_groups: Vec<usize> = plan
        .sectors
        .iter()
        .filter(|s| matches!(s.kind, Kind::Boundary(_)))
        .map(|s| s.group)
        .collect();
    let any = with_corners.iter().any(|&c| c);
    let cuts: &[f64] = if any && parameters.is_none() {
        &CUT_CANDIDATES
    } else {
        &[f64::NAN]
    };
    let bases: &[f64] = if any { &BASES } else { &[1.0] };
    let mut last = None;
    let mut solved = None;
    'search: for &base in bases {
        for &candidate in cuts {
            let mut trial = shape.clone();
            for (b, &corners) in with_corners.iter().enumerate() {
                if !corners {
                    continue;
                }
                trial.bases[boundary_groups[b]] = base;
                if candidate.is_finite() {
                    trial.cuts[b] = candidate;
                }
                match cap(space, &symbol.boundaries()[b], trial.cuts[b]) {
                    Ok(c) => trial.caps[b] = Some(c),
                    Err(e) => {
                        last = Some(e);
                        continue;
                    }
                }
            }
            match close(space, &plan, &trial) {
                Ok(star) => {
                    solved = Some((star, trial));
                    break 'search;
                }
                Err(e) => last = Some(e),
            }
        }
    }
    let Some((star, shape)) = solved else {
        return Err(last.unwrap_or_else(|| LayoutError::Unrealisable("no star".into())));
    };
    let mut values = values;
    for (i, v) in values.iter_mut().enumerate() {
        if i < boundaries {
            *v = shape.cuts[i];
        }
    }
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
        meanings,
        construction: Construction::Star,
    })
}

fn meanings(symbol: &OrbifoldSymbol, plan: &Plan, supported: usize) -> Vec<String> {
    let mut out: Vec<String> = symbol
        .boundaries()
        .iter()
        .enumerate()
        .map(|(i, corners)| {
            if corners.is_empty() {
                format!(
                    "mirror boundary {}: the length of the cut edge d from the circle of v to the \
                     mirror, in units of the distance from v to the sector's axis; in (0, 2), default 1",
                    i + 1
                )
            } else {
                format!(
                    "mirror boundary {}: where the cut edge meets the first mirror, as a fraction \
                     of the way from the foot of the perpendicular from the centre to the first \
                     corner (or of the shorter such span at the last corner); in (0, 1), default 0.5",
                    i + 1
                )
            }
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

/// The base widths tried, in turn, for the sectors of boundaries with corners.
const BASES: [f64; 6] = [1.0, 0.5, 2.0, 0.25, 4.0, 0.1];

/// The cuts tried, in turn, for boundaries with corners when no parameters are given.
const CUT_CANDIDATES: [f64; 9] = [0.5, 0.7, 0.9, 0.95, 0.98, 0.3, 0.1, 0.99, 0.995];

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
    let weight = |g: usize| shape.bases[g] * shape.weights[g];
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
    let mut cut = 0;
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
            Kind::Boundary(corners) => {
                cut += 1;
                let cap = shape.caps[cut - 1].as_ref();
                boundary_chain(space, r, delta, corners, shape.cuts[cut - 1], cap)?
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
    // construction exists (it may exist only on an interval of R; with a boundary's cap the sum
    // can rise with R). A jump across π (a corner turning reflex) is not a root: the root's
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

/// The points P₀ … P_{n+1} of a boundary sector (local frame: the axis is the positive real
/// axis), each with its ideal flag and its cycle's order.
fn boundary_chain(
    space: Space,
    r: f64,
    delta: f64,
    corners: &[Order],
    cut: f64,
    cap: Option<&Cap>,
) -> Result<Vec<(DVec3, bool, Order)>, LayoutError> {
    let below = polar(space, r, -delta / 2.0);
    let offset = axis_offset(space, r, delta);
    let one = Order::integer(1);
    let ends = |p: DVec3| DVec3::new(p.x, -p.y, p.z);
    if corners.is_empty() {
        let p0 = mirror_foot(space, r, delta, below, cut * offset)?;
        return Ok(vec![(p0, false, one), (ends(p0), false, one)]);
    }
    let cap = cap.ok_or_else(|| LayoutError::Unrealisable("a boundary's cap is missing".into()))?;
    let placed = place_cap(space, cap, below)?;
    Ok(placed
        .iter()
        .enumerate()
        .map(|(i, &p)| {
            let order = if i == 0 || i + 1 == placed.len() {
                one
            } else {
                corners[i - 1]
            };
            (p, cap.ideal[i], order)
        })
        .collect())
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

/// A cap: the polygon of a boundary's corners, centred at the origin.
#[derive(Clone, Debug)]
struct Cap {
    /// Corners P₀ … P_{n+1}, ambient (null directions for ideal ones).
    points: Vec<DVec3>,
    ideal: Vec<bool>,
    /// The bearing of the chord's nearest point from the centre, and the inradius.
    chord_bearing: f64,
    inradius: f64,
}

fn build_cap(space: Space, corners: &[Order], base: f64) -> Result<Cap, LayoutError> {
    let mut angles = vec![base];
    angles.extend(corners.iter().map(Order::corner_angle));
    angles.push(base);
    let mut ideal = vec![false];
    ideal.extend(corners.iter().map(Order::is_infinite));
    ideal.push(false);
    let raw = incircle::polygon(space, &angles, &ideal)?;
    let points: Vec<DVec3> = raw
        .corners
        .iter()
        .zip(&ideal)
        .map(|(&z, &i)| {
            if i {
                DVec3::new(z.re, z.im, 1.0)
            } else {
                space.to_ambient(z)
            }
        })
        .collect();
    let last = points.len() - 1;
    let chord = super::geometry::wall_through(space, points[last], points[0], DVec3::Z);
    Ok(Cap {
        chord_bearing: (-chord.y).atan2(-chord.x),
        inradius: space.asin(chord.dot(DVec3::Z)),
        points,
        ideal,
    })
}

/// The cap of a boundary's corners (H²): the polygon with angles φ, π/b₁, …, π/bₙ, φ and an
/// inscribed circle, whose side P_{n+1}P₀ (the chord) will be perpendicular to the sector's axis.
///
/// The cut edge d is perpendicular to the first mirror at P₀, so it makes the angle π/2 − φ
/// with the chord. The pairing of d̄ with d is r_d ∘ r_axis, which fixes the point where d meets
/// the axis; a group element other than the identity fixes no interior point of the polygon, so
/// d must not meet the axis: C(c)·cos φ > 1 with c half the chord (the cap's size falls as φ
/// grows). `cut` ∈ (0, 1) picks φ = cut·φ_meet, with φ_meet the base angle at which d just
/// becomes asymptotic to the axis.
fn cap(space: Space, corners: &[Order], cut: f64) -> Result<Cap, LayoutError> {
    if space.kappa() >= 0.0 {
        return Err(LayoutError::Unsupported(
            "boundaries with corners are built by the star only in H²; the Euclidean and \
             spherical ones are textbook constructions"
                .into(),
        ));
    }
    let n = corners.len() as f64;
    let sum: f64 = corners.iter().map(Order::corner_angle).sum();
    let top = ((n * PI - sum) / 2.0).min(PI / 2.0) * (1.0 - 1e-9);
    let ultraparallel = |base: f64| {
        build_cap(space, corners, base).map_or(f64::NAN, |c| {
            let half = 0.5 * space.ambient_distance(c.points[0], c.points[c.points.len() - 1]);
            space.cos(half) * base.cos() - 1.0
        })
    };
    let low = 1e-6 * top;
    let meet = if ultraparallel(top) > 0.0 {
        top
    } else {
        bisect(low, top, ultraparallel)
    };
    build_cap(space, corners, cut * meet)
}

/// Turns the cap so that its chord faces the centre across the positive real axis, and slides it
/// along the axis until the perpendicular to its first mirror at P₀ passes through v (`below`).
fn place_cap(space: Space, cap: &Cap, below: DVec3) -> Result<Vec<DVec3>, LayoutError> {
    let turn = Isometry::rotation(space, PI - cap.chord_bearing);
    let moved = |t: f64| {
        let m = Isometry::translation_by(space, t + cap.inradius, Complex64::new(1.0, 0.0))
            .compose(&turn);
        cap.points
            .iter()
            .map(|&p| m.apply_ambient(p))
            .collect::<Vec<_>>()
    };
    // The signed distance from d to v, positive on P₁'s side.
    let side = |t: f64| {
        let p = moved(t);
        let u = toward(space, p[0], p[1]);
        DVec3::new(u.x, u.y, space.kappa() * u.z).dot(below)
    };
    let grid: Vec<f64> = (-40..=40).map(|i| f64::from(i) * 0.25).collect();
    let bracket = grid
        .windows(2)
        .find(|w| side(w[0]) >= 0.0 && side(w[1]) < 0.0)
        .ok_or_else(|| {
            LayoutError::Unrealisable(
                "no position of a boundary's corners lets its cut edge reach v at a right angle"
                    .into(),
            )
        })?;
    Ok(moved(bisect(bracket[0], bracket[1], side)))
}
