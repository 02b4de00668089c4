//! Geodesic connections between two points of the product space, and their geometric term.
//!
//! Two points (x, h₁) and (y, h₂) of S²×R, E²×R or H²×R are joined by the geodesic whose
//! horizontal part runs the geodesic of the plane from x to y (horizontal length σ, direction
//! `log(x, y)`) and whose height is linear in arc length: length ℓ = √(σ² + Δh²), elevation
//! α = atan2(Δh, σ). On the sphere there is also the geodesic that goes the other way round
//! (σ′ = 2π − σ), and those that go round once more ([`turned`]). The light that leaves a point
//! into a small solid angle dω covers the area J·dω at distance ℓ, with
//! J(ℓ, α) = ℓ·S_κ(ℓ cos α)/cos α = ℓ²·S_κ(σ)/σ (ℓ² for κ = 0) — the area density of geodesic
//! spheres ([`spread`]) — so the geometric term of a connection is |cos θ₁||cos θ₂| / J. On the
//! sphere J vanishes at the antipode, where light refocuses.
//!
//! [`connect`] builds the geodesic as a ray, for the shadow ray that follows it; [`aim_at`]
//! gives only its first direction and J, for weighing a connection before it is traced.

use std::f64::consts::PI;

use glam::DVec3;
use orbifold::space::Space;
use orbifold_trace::geodesic::Ray;

use super::frame::TangentFrame;

/// J(ℓ, α) = ℓ²·S_κ(σ)/σ for horizontal length σ = ℓ cos α: the area that a unit solid angle
/// covers at arc length ℓ (ℓ² in E²×R). Its absolute value (the sphere's S is negative past π).
///
/// ```
/// use orbifold::{Geometry, space::Space};
/// use orbifold_render::lights::spread;
/// let h2 = Space::new(Geometry::Hyperbolic);
/// // Vertical: like flat space; horizontal: the circumference density ℓ sinh ℓ.
/// assert!((spread(h2, 2.0, 0.0) - 4.0).abs() < 1e-12);
/// assert!((spread(h2, 2.0, 2.0) - 2.0 * 2f64.sinh()).abs() < 1e-12);
/// ```
pub fn spread(space: Space, length: f64, sigma: f64) -> f64 {
    let ratio = if sigma < 1e-8 {
        1.0 - space.kappa() * sigma * sigma / 6.0
    } else {
        space.sin(sigma) / sigma
    };
    length * length * ratio.abs()
}

/// A geodesic from one point to another.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Connection {
    /// The geodesic, starting at the first point.
    pub ray: Ray,
    /// Its arc length.
    pub length: f64,
    /// Its horizontal length σ.
    pub sigma: f64,
    /// J: see [`spread`].
    pub spread: f64,
}

/// The horizontal length of the geodesic from one point of the sphere to another at distance
/// `d` ≤ π that makes `turns` half-turns past it, and whether it leaves along the way back
/// (−u for the direction u of the short way). Half-turn 0 is the short way (σ = d), 1 the long
/// way round (2π − d), 2 the short way once more round the sphere (2π + d), and so on: σ lies
/// in [πt, π(t + 1)], so `turns` = ⌊σ/π⌋ of a geodesic's own horizontal length.
///
/// ```
/// use orbifold_render::lights::turned;
/// use std::f64::consts::PI;
/// assert_eq!(turned(1.0, 0), (1.0, false));
/// assert_eq!(turned(1.0, 1), (2.0 * PI - 1.0, true));
/// assert_eq!(turned(1.0, 2), (2.0 * PI + 1.0, false));
/// assert_eq!(turned(1.0, 3), (4.0 * PI - 1.0, true));
/// ```
pub fn turned(d: f64, turns: u32) -> (f64, bool) {
    let t = f64::from(turns);
    if turns.is_multiple_of(2) {
        (d + PI * t, false)
    } else {
        (PI * (t + 1.0) - d, true)
    }
}

/// The geodesic from (x, hx) to (y, hy) that makes `turns` half-turns round the sphere
/// ([`turned`]; 0, the shortest, in every geometry — the others exist on the sphere only,
/// where every geodesic comes back round). `frame` is a frame at x (for a vertical
/// connection).
pub fn connect(
    space: Space,
    frame: &TangentFrame,
    (x, hx): (DVec3, f64),
    (y, hy): (DVec3, f64),
    turns: u32,
) -> Option<Connection> {
    let segment = Segment::new(space, frame, (x, hx), (y, hy), turns)?;
    Some(Connection {
        ray: Ray::climbing(space, x, segment.direction, hx, segment.sigma, segment.rise),
        length: segment.length,
        sigma: segment.sigma,
        spread: spread(space, segment.length, segment.sigma),
    })
}

/// The geodesic segment of [`connect`] before its ray is built.
struct Segment {
    /// The unit horizontal direction it leaves x in (ambient).
    direction: DVec3,
    /// Its horizontal length σ.
    sigma: f64,
    /// Its rise, Δh.
    rise: f64,
    /// Its arc length.
    length: f64,
}

impl Segment {
    fn new(
        space: Space,
        frame: &TangentFrame,
        (x, hx): (DVec3, f64),
        (y, hy): (DVec3, f64),
        turns: u32,
    ) -> Option<Segment> {
        if turns > 0 && space.kappa() <= 0.0 {
            return None;
        }
        let d = space.ambient_distance(x, y);
        let (u, sigma) = if d < 1e-12 {
            // Every way round leads back to x (a focus): only the straight connection is one.
            if turns > 0 {
                return None;
            }
            (frame.e1, 0.0)
        } else {
            let (sigma, back) = turned(d, turns);
            // The unit tangent towards y, y − C(d)·x normalised, with C(d) = 1 − κV from the
            // chord (V = ½|y − x|²_κ): `Space::log` over d, without its second inverse function
            // for d and its C(d).
            let chord = y - x;
            let t = y - x * (1.0 - 0.5 * space.kappa() * space.point_dot(chord, chord));
            let n = space.point_dot(t, t).max(0.0).sqrt();
            let u = if n == 0.0 {
                DVec3::ZERO
            } else {
                t / if back { -n } else { n }
            };
            (u, sigma)
        };
        let dh = hy - hx;
        let length = (sigma * sigma + dh * dh).sqrt();
        (length > 1e-12 && length.is_finite()).then_some(Segment {
            direction: u,
            sigma,
            rise: dh,
            length,
        })
    }
}

/// What [`connect`] and [`travel_direction`](super::travel_direction) give of the geodesic from
/// (x, hx) to (y, hy) with `turns` half-turns, without building its ray: the direction it leaves
/// x in (unit, local to `frame`) and its J ([`spread`]). `None` where [`connect`] has no
/// geodesic.
///
/// ```
/// use glam::DVec3;
/// use orbifold::{Geometry, space::Space};
/// use orbifold_render::lights::{TangentFrame, aim_at, connect, travel_direction};
/// let h2 = Space::new(Geometry::Hyperbolic);
/// let x = h2.exp(DVec3::Z, DVec3::new(0.3, -0.2, 0.0));
/// let y = h2.exp(DVec3::Z, DVec3::new(-0.5, 0.4, 0.0));
/// let frame = TangentFrame::at(h2, x);
/// let (wi, j) = aim_at(h2, &frame, (x, 0.1), (y, 0.7), 0).unwrap();
/// let link = connect(h2, &frame, (x, 0.1), (y, 0.7), 0).unwrap();
/// assert!((wi - travel_direction(h2, &frame, &link.ray, 0.0)).length() < 1e-12);
/// assert!((j - link.spread).abs() < 1e-12 * j);
/// ```
pub fn aim_at(
    space: Space,
    frame: &TangentFrame,
    (x, hx): (DVec3, f64),
    (y, hy): (DVec3, f64),
    turns: u32,
) -> Option<(DVec3, f64)> {
    let segment = Segment::new(space, frame, (x, hx), (y, hy), turns)?;
    let (cos, sin) = (
        segment.sigma / segment.length,
        segment.rise / segment.length,
    );
    let direction = frame.to_local(space, segment.direction * cos, sin);
    Some((
        direction.normalize(),
        spread(space, segment.length, segment.sigma),
    ))
}
