//! The polygon of a kaleidoscopic signature, in model coordinates (seed chapter 6.1, ARCHITECTURE.md §5).
//!
//! Every construction works with walls as linear forms on ambient coordinates (see
//! [`crate::space`]): a vertex is the intersection of two walls, an ideal vertex is exactly the
//! point at infinity where two walls are tangent, and placing the polygon is one linear map.
//!
//! | signature | construction |
//! |---|---|
//! | `*` | the unit disk: the equator is the mirror |
//! | `*kk` | a lune with corners at the antipodal pair ±1 |
//! | triangles (every geometry, non-orbifold too) | the unique triangle, built around its inscribed circle |
//! | `*2222` | a rectangle; the free parameter is its aspect ratio (wall 0 : wall 1) |
//! | hyperbolic N ≥ 4 | the comb decomposition ([`comb`]); or, with [`Shape::Incircle`], the polygon with an inscribed circle |
//!
//! ```
//! use orbifold::layout::{Layout, LayoutOptions};
//! let layout = Layout::new(&"*2333".parse().unwrap(), &LayoutOptions::default()).unwrap();
//! assert_eq!(layout.vertices.len(), 4);
//! assert_eq!(layout.parameters, vec![1.4]);
//! assert!((layout.vertices[0].angle - std::f64::consts::FRAC_PI_2).abs() < 1e-12);
//! ```

pub mod centre;
pub mod comb;
pub mod incircle;

use std::f64::consts::PI;
use std::fmt;

use glam::{DMat3, DVec3};
use num_complex::Complex64;

use crate::conway::OrbifoldSymbol;
use crate::cover::reflection;
use crate::euler::Geometry;
use crate::isometry::Isometry;
use crate::order::Order;
use crate::pairing::{EdgeKind, FundamentalPolygon};
use crate::signature::{Kind, Signature};
use crate::space::{ModelGeodesic, Space};

/// The seed's default value of every free shape parameter.
pub const DEFAULT_PARAMETER: f64 = 1.4;

/// Which polygon of the signature to build.
#[derive(Clone, Debug, PartialEq, Default)]
pub enum Shape {
    /// The free parameters, each [`DEFAULT_PARAMETER`] (the seed's default shape).
    #[default]
    Default,
    /// These values of the free parameters, in order.
    Parameters(Vec<f64>),
    /// The unique polygon with an inscribed circle (the most balanced shape).
    Incircle,
}

/// What to build and where to put it.
#[derive(Clone, Debug, PartialEq)]
pub struct LayoutOptions {
    /// The shape.
    pub shape: Shape,
    /// Where the polygon's centre goes, in model coordinates.
    pub at: Complex64,
    /// The turn, in radians counter-clockwise, applied about the centre before moving it.
    pub angle: f64,
}

impl Default for LayoutOptions {
    fn default() -> Self {
        LayoutOptions {
            shape: Shape::Default,
            at: Complex64::new(0.0, 0.0),
            angle: 0.0,
        }
    }
}

/// A request that cannot be laid out.
#[derive(Clone, Debug, PartialEq)]
pub enum LayoutError {
    /// A bad orbifold, or a non-orbifold room that cannot exist for the same reason.
    NotBuildable(String),
    /// A polygon this tool does not construct.
    Unsupported(String),
    /// The wrong number of free parameters.
    ParameterCount {
        /// How many the signature has.
        expected: usize,
        /// How many were given.
        given: usize,
    },
    /// A parameter that is not a positive finite number.
    InvalidParameter {
        /// 0-based index.
        index: usize,
        /// The value.
        value: f64,
    },
    /// A parameter outside the range in which its family is documented to be valid.
    ParameterOutOfRange {
        /// 0-based index.
        index: usize,
        /// The value.
        value: f64,
        /// The smallest valid value (exclusive).
        low: f64,
        /// The largest valid value (exclusive).
        high: f64,
    },
    /// Angles for which no polygon of the geometry exists.
    Unrealisable(String),
    /// A placement outside the model (|at| ≥ 1 in the Poincaré disk, or not finite).
    Placement(String),
}

impl fmt::Display for LayoutError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            LayoutError::NotBuildable(reason) => write!(f, "cannot lay out: {reason}"),
            LayoutError::Unsupported(what) => write!(f, "cannot lay out: {what}"),
            LayoutError::ParameterCount { expected: 0, given } => {
                write!(
                    f,
                    "this polygon is rigid: it has no free parameters, but {given} were given"
                )
            }
            LayoutError::ParameterCount { expected, given } => {
                write!(
                    f,
                    "this polygon has {expected} free parameter(s), but {given} were given"
                )
            }
            LayoutError::InvalidParameter { index, value } => {
                write!(
                    f,
                    "free parameter {} is {value}, but every free parameter must be a positive finite number",
                    index + 1
                )
            }
            LayoutError::ParameterOutOfRange {
                index,
                value,
                low,
                high,
            } => write!(
                f,
                "free parameter {} is {value}, but it must lie strictly between {low} and {high}",
                index + 1
            ),
            LayoutError::Unrealisable(what) => write!(f, "cannot lay out: {what}"),
            LayoutError::Placement(what) => write!(f, "invalid placement: {what}"),
        }
    }
}

impl std::error::Error for LayoutError {}

/// A corner of the polygon.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Vertex {
    /// Model coordinates (on the unit circle for an ideal corner).
    pub position: Complex64,
    /// The corner's order k: for a kaleidoscopic signature the corner's own; for a polygon with
    /// side pairings, the order of the orbifold point the corner lies on (its vertex cycle's).
    pub order: Order,
    /// The corner angle in radians: π/k for a kaleidoscopic signature, 0 for an ideal corner;
    /// for a polygon with side pairings, the corner's own share of its cycle's angle.
    pub angle: f64,
    /// Whether the corner is ideal: at infinity, where its two walls are tangent.
    pub ideal: bool,
}

/// A side of the polygon: wall `i` joins vertex `i` to vertex `i + 1`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Edge {
    /// The vertex it starts at (`None` for the single wall of `*`).
    pub from: Option<usize>,
    /// The vertex it ends at.
    pub to: Option<usize>,
    /// The intrinsic length (infinite when an end is ideal).
    pub length: f64,
    /// The wall as a linear form on ambient coordinates, positive inside the polygon.
    pub wall: DVec3,
    /// The wall as a circle or a line in model coordinates.
    pub geodesic: ModelGeodesic,
    /// A mirror, or paired with another edge (ARCHITECTURE.md §11): every edge of a
    /// kaleidoscopic signature is a mirror.
    pub kind: EdgeKind,
    /// The group element g with g(P) the tile across this edge: the reflection in it for a
    /// mirror; for an edge paired with j, the isometry that takes edge j onto this edge.
    pub neighbour: DMat3,
}

impl Edge {
    /// The partner edge of a paired edge; `None` for a mirror.
    pub fn partner(&self) -> Option<usize> {
        match self.kind {
            EdgeKind::Mirror => None,
            EdgeKind::Paired { partner } => Some(partner),
        }
    }
}

/// What the free parameters of a polygon mean.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ParameterMeaning {
    /// The polygon is rigid.
    None,
    /// `*2222`: the length of wall 0 divided by the length of wall 1.
    AspectRatio,
    /// A polygon with side pairings: the parameters of its fundamental polygon
    /// ([`FundamentalPolygon::parameter_meanings`]).
    SidePairing,
    /// Hyperbolic N ≥ 4: parameter j (1-based, j = 1 … N−3) scales the distance cⱼ between
    /// wall N−1 and wall j (the length of their common perpendicular) relative to the balanced
    /// polygon: cⱼ = c⁰ⱼ · pⱼ^(1/8). All parameters 1 give the incircle polygon.
    WallDistances,
}

impl ParameterMeaning {
    /// A sentence for users.
    pub fn describe(self, corners: usize) -> String {
        match self {
            ParameterMeaning::None => "none: the polygon is rigid".into(),
            ParameterMeaning::AspectRatio => {
                "the length of wall 0 divided by the length of wall 1".into()
            }
            ParameterMeaning::SidePairing => {
                "the fundamental polygon's shape parameters (`orbifold layout SYMBOL` describes each)"
                    .into()
            }
            ParameterMeaning::WallDistances => format!(
                "parameter j (j = 1…{}) sets the distance between wall {} and wall j to its value in the balanced \
                 (incircle) polygon times the 8th root of the parameter; all 1 is the incircle polygon",
                corners - 3,
                corners - 1
            ),
        }
    }
}

/// The polygon of a room: vertices, walls, how the walls are joined (mirrors, or side
/// pairings), free parameters, placed in model coordinates. For a kaleidoscopic signature every
/// wall is a mirror ([`Layout::new`]); for every other orbifold symbol it is the fundamental
/// polygon of [`FundamentalPolygon`], whose paired walls are portals ([`Layout::of_symbol`]).
#[derive(Clone, Debug, PartialEq)]
pub struct Layout {
    /// The symbol, in the reading it was given (for a kaleidoscopic signature, vertex i has the
    /// i-th order).
    pub symbol: OrbifoldSymbol,
    /// Spherical, Euclidean or hyperbolic.
    pub geometry: Geometry,
    /// The corners, counter-clockwise.
    pub vertices: Vec<Vertex>,
    /// The sides; edge i joins vertex i to vertex i + 1 (mod N).
    pub edges: Vec<Edge>,
    /// The values of the free parameters of this polygon (also for the incircle shape).
    pub parameters: Vec<f64>,
    /// Each parameter's open range of valid values: (0, ∞) for a kaleidoscopic polygon's; for a
    /// polygon with side pairings, its construction's ([`FundamentalPolygon::parameter_ranges`]).
    ///
    /// [`FundamentalPolygon::parameter_ranges`]: crate::pairing::FundamentalPolygon::parameter_ranges
    pub parameter_ranges: Vec<(f64, f64)>,
    /// What the parameters mean.
    pub parameter_meaning: ParameterMeaning,
    /// The intrinsic area (2π|χ| for spherical and hyperbolic polygons; for Euclidean ones, the
    /// area at the chosen scale, where the farthest corner is 2 from the centre).
    pub area: f64,
    /// The centre (incircle centre, or the centre of the largest inscribed disk) after placement.
    pub centre: Complex64,
    /// The direction of the placement arrow at the centre, in radians.
    pub heading: f64,
}

impl Layout {
    /// The kaleidoscopic signature, for a polygon of mirrors (`None` for a polygon with side
    /// pairings).
    pub fn signature(&self) -> Option<Signature> {
        self.symbol.as_kaleidoscopic()
    }

    /// Whether every wall is a mirror (a kaleidoscopic signature).
    pub fn is_kaleidoscopic(&self) -> bool {
        self.edges.iter().all(|e| e.kind == EdgeKind::Mirror)
    }

    /// The room's polygon for any orbifold symbol: [`Layout::new`] for a kaleidoscopic one,
    /// otherwise the fundamental polygon of [`FundamentalPolygon::new`] with its side pairings.
    ///
    /// ```
    /// use orbifold::{Layout, LayoutOptions};
    /// let layout = Layout::of_symbol(&"632".parse()?, &LayoutOptions::default())?;
    /// // Two copies of the triangle of *632, glued along their edges by the rotations.
    /// assert_eq!(layout.edges.len(), 4);
    /// assert!(layout.edges.iter().all(|e| e.partner().is_some()));
    /// assert!(layout.signature().is_none());
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn of_symbol(
        symbol: &OrbifoldSymbol,
        options: &LayoutOptions,
    ) -> Result<Layout, LayoutError> {
        match symbol.as_kaleidoscopic() {
            Some(signature) => Layout::new(&signature, options),
            None => Ok(FundamentalPolygon::new(symbol, options)?.room_layout(options.angle)),
        }
    }

    /// A point of the plane and a tangent vector there, brought back into the polygon through
    /// its portals: while the point lies beyond a paired wall (by more than `slack` in the
    /// wall's linear form), both are moved by the pairing that takes that wall onto its partner
    /// (at most once per wall, so that it always ends). What a person walking through a portal
    /// sees happen; mirror walls are left alone. Ambient coordinates. The flag says whether the
    /// pairings applied reverse orientation in all (an odd number of glides): the walker then
    /// sees the world mirrored.
    ///
    /// ```
    /// use orbifold::{Layout, LayoutOptions};
    /// use glam::DVec3;
    /// let layout = Layout::of_symbol(&"o".parse()?, &LayoutOptions::default())?;
    /// let space = layout.space();
    /// let wall = layout.edges[0].wall;
    /// // A step past wall 0, from a point just inside it.
    /// let outside = space.to_ambient(num_complex::Complex64::new(0.0, 0.0)) - DVec3::new(wall.x, wall.y, 0.0) * (wall.z + 0.01);
    /// let (back, _, mirrored) = layout.carried_inside(outside, DVec3::X, 1e-12);
    /// assert!(!mirrored);
    /// assert!(layout.edges.iter().all(|e| e.wall.dot(back) > -1e-9));
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn carried_inside(&self, point: DVec3, tangent: DVec3, slack: f64) -> (DVec3, DVec3, bool) {
        let (mut p, mut v, mut mirrored) = (point, tangent, false);
        for _ in 0..self.edges.len() {
            let beyond = self
                .edges
                .iter()
                .enumerate()
                .filter(|(_, e)| e.partner().is_some())
                .map(|(i, e)| (i, e.wall.dot(p)))
                .filter(|&(_, value)| value < -slack)
                .min_by(|a, b| a.1.total_cmp(&b.1));
            let Some((i, _)) = beyond else {
                break;
            };
            let Some(partner) = self.edges[i].partner() else {
                break;
            };
            let back = self.edges[partner].neighbour;
            (p, v) = (back * p, back * v);
            mirrored ^= back.determinant() < 0.0;
        }
        (p, v, mirrored)
    }

    /// Lays out the polygon of `signature`.
    pub fn new(signature: &Signature, options: &LayoutOptions) -> Result<Layout, LayoutError> {
        if !signature.is_buildable() {
            let reason = signature
                .reason()
                .unwrap_or_else(|| format!("{signature} has no polygon"));
            return Err(LayoutError::NotBuildable(reason));
        }
        let geometry = signature.geometry();
        let space = Space::new(geometry);
        check_placement(space, options)?;
        let angles: Vec<f64> = signature
            .corners()
            .iter()
            .map(Order::corner_angle)
            .collect();
        let ideal: Vec<bool> = signature.corners().iter().map(Order::is_infinite).collect();
        let raw = build(signature, space, &angles, &ideal, &options.shape)?;
        Ok(raw.finish(signature, space, options))
    }

    /// The curvature κ of the model.
    pub fn space(&self) -> Space {
        Space::new(self.geometry)
    }

    /// The model's name: `stereographic`, `euclidean` or `poincare`.
    pub fn model_name(&self) -> &'static str {
        match self.geometry {
            Geometry::Spherical => "stereographic",
            Geometry::Euclidean => "euclidean",
            Geometry::Hyperbolic => "poincare",
        }
    }
}

fn check_placement(space: Space, options: &LayoutOptions) -> Result<(), LayoutError> {
    let at = options.at;
    if !(at.re.is_finite() && at.im.is_finite() && options.angle.is_finite()) {
        return Err(LayoutError::Placement(
            "the position and angle must be finite numbers".into(),
        ));
    }
    if space.kappa() < 0.0 && at.norm() >= 1.0 {
        return Err(LayoutError::Placement(format!(
            "({}, {}) is not inside the Poincaré disk; the centre must satisfy x² + y² < 1",
            at.re, at.im
        )));
    }
    Ok(())
}

/// A polygon before placement: its walls, its corners, its parameters, its centre.
pub(crate) struct RawPolygon {
    pub(crate) walls: Vec<DVec3>,
    /// Corner positions, in model coordinates (ideal ones on the unit circle).
    pub(crate) corners: Vec<Complex64>,
    pub(crate) parameters: Vec<f64>,
    pub(crate) meaning: ParameterMeaning,
    /// The centre in model coordinates (moved to the origin before placement).
    pub(crate) centre: Complex64,
}

fn build(
    signature: &Signature,
    space: Space,
    angles: &[f64],
    ideal: &[bool],
    shape: &Shape,
) -> Result<RawPolygon, LayoutError> {
    let n = angles.len();
    let geometry = space.geometry();
    let expected = signature.free_parameters();
    if let Shape::Parameters(values) = shape {
        if values.len() != expected {
            return Err(LayoutError::ParameterCount {
                expected,
                given: values.len(),
            });
        }
        if let Some((index, &value)) = values
            .iter()
            .enumerate()
            .find(|(_, v)| !(v.is_finite() && **v > 0.0))
        {
            return Err(LayoutError::InvalidParameter { index, value });
        }
    }
    if geometry == Geometry::Euclidean && ideal.iter().any(|&i| i) {
        return Err(LayoutError::Unsupported(format!(
            "{signature} is a Euclidean strip with a corner at infinity; only polygons with finite corners are built in the Euclidean plane"
        )));
    }
    match (geometry, n) {
        (_, 0) => Ok(hemisphere()),
        (_, 2) => Ok(lune(angles[0])),
        (_, 3) => incircle::polygon(space, angles, ideal),
        (Geometry::Euclidean, 4) if signature.kind() == Kind::Orbifold => {
            Ok(rectangle(space, shape))
        }
        (Geometry::Hyperbolic, _) => match shape {
            Shape::Incircle => incircle::polygon(space, angles, ideal),
            // Obtuse corners (non-orbifold rooms) leave the comb undefined; without explicit
            // parameters the balanced polygon is the natural default there.
            Shape::Default if !comb::accepts(angles) => incircle::polygon(space, angles, ideal),
            Shape::Default => {
                comb::polygon_relative(angles, ideal, &vec![DEFAULT_PARAMETER; n - 3])
            }
            Shape::Parameters(values) => comb::polygon_relative(angles, ideal, values),
        },
        (Geometry::Spherical, _) => Err(LayoutError::Unsupported(format!(
            "{signature} would be a spherical polygon with {n} corners; only spherical monogons, lunes and triangles are built"
        ))),
        (Geometry::Euclidean, _) => Err(LayoutError::Unsupported(format!(
            "{signature} would be a Euclidean polygon with {n} corners; among those only the rectangle *2222 is built"
        ))),
    }
}

/// `*`: the unit disk of the stereographic plane, bounded by the equator.
fn hemisphere() -> RawPolygon {
    RawPolygon {
        walls: vec![DVec3::Z],
        corners: vec![],
        parameters: vec![],
        meaning: ParameterMeaning::None,
        centre: Complex64::new(0.0, 0.0),
    }
}

/// `*kk` (and non-orbifold lunes): corners at ±1, walls symmetric about the real axis.
fn lune(angle: f64) -> RawPolygon {
    let (s, c) = (angle / 2.0).sin_cos();
    RawPolygon {
        walls: vec![DVec3::new(0.0, -c, s), DVec3::new(0.0, c, s)],
        corners: vec![Complex64::new(1.0, 0.0), Complex64::new(-1.0, 0.0)],
        parameters: vec![],
        meaning: ParameterMeaning::None,
        centre: Complex64::new(0.0, 0.0),
    }
}

/// `*2222`: a rectangle whose corners lie on the unit circle (farthest corner 2 from the centre).
fn rectangle(space: Space, shape: &Shape) -> RawPolygon {
    let aspect = match shape {
        Shape::Parameters(v) => v[0],
        Shape::Default => DEFAULT_PARAMETER,
        Shape::Incircle => 1.0,
    };
    // Wall 0 is vertical (length 2y), wall 1 horizontal (length 2x): aspect = y / x.
    let x = 1.0 / (1.0 + aspect * aspect).sqrt();
    let y = aspect * x;
    let corners = vec![
        Complex64::new(x, -y),
        Complex64::new(x, y),
        Complex64::new(-x, y),
        Complex64::new(-x, -y),
    ];
    let walls = walls_through_corners(space, &corners);
    RawPolygon {
        walls,
        corners,
        parameters: vec![aspect],
        meaning: ParameterMeaning::AspectRatio,
        centre: Complex64::new(0.0, 0.0),
    }
}

/// The walls through consecutive finite corners of a convex polygon, oriented inwards.
pub(crate) fn walls_through_corners(space: Space, corners: &[Complex64]) -> Vec<DVec3> {
    let n = corners.len();
    let inside = space.to_ambient(corners.iter().sum::<Complex64>() / n as f64);
    (0..n)
        .map(|i| {
            let nu = space.normalize_wall(
                space
                    .to_ambient(corners[i])
                    .cross(space.to_ambient(corners[(i + 1) % n])),
            );
            if nu.dot(inside) < 0.0 { -nu } else { nu }
        })
        .collect()
}

/// The corner where walls `a` and `b` meet at inner angle `angle` (exactly at infinity when ideal).
///
/// The corner is on the line a × b. For unit walls, −⟨a × b, a × b⟩ = 1 − (a·b)² = sin²α on the
/// sphere and the hyperboloid, so dividing by sin α normalises it without the cancellation of
/// computing the form of a large vector.
pub(crate) fn corner_of(space: Space, a: DVec3, b: DVec3, angle: f64, ideal: bool) -> Complex64 {
    let mut q = a.cross(b);
    if q.z < 0.0 {
        q = -q;
    }
    if ideal {
        return space.ideal_to_model(q);
    }
    let p = if space.kappa() == 0.0 {
        q / q.z
    } else {
        q / angle.sin()
    };
    space.to_model(p)
}

impl RawPolygon {
    /// Moves the centre to the origin, turns vertex 0 onto the positive real axis, then applies
    /// the requested placement; measures the result.
    fn finish(self, signature: &Signature, space: Space, options: &LayoutOptions) -> Layout {
        let ideal: Vec<bool> = signature.corners().iter().map(Order::is_infinite).collect();
        let centring = Isometry::translation(space, self.centre).inverse();
        let first = self.corners.first().map(|&z| {
            if ideal[0] {
                centring.apply_ideal(z)
            } else {
                centring.apply(z)
            }
        });
        let turn = first.map_or(0.0, |z| -z.arg());
        let standard = Isometry::rotation(space, turn).compose(&centring);
        let placement = Isometry::translation(space, options.at)
            .compose(&Isometry::rotation(space, options.angle));
        let motion = placement.compose(&standard);
        let corners: Vec<Complex64> = self
            .corners
            .iter()
            .zip(&ideal)
            .map(|(&z, &is_ideal)| {
                if is_ideal {
                    motion.apply_ideal(z)
                } else {
                    motion.apply(z)
                }
            })
            .collect();
        let walls: Vec<DVec3> = self.walls.iter().map(|&nu| motion.apply_wall(nu)).collect();
        let vertices = signature
            .corners()
            .iter()
            .zip(&corners)
            .map(|(order, &position)| Vertex {
                position,
                order: *order,
                angle: order.corner_angle(),
                ideal: order.is_infinite(),
            })
            .collect::<Vec<_>>();
        let edges = edges(space, &vertices, &walls);
        let area = polygon_area(space, signature, &vertices);
        Layout {
            symbol: signature.clone().into(),
            geometry: space.geometry(),
            vertices,
            edges,
            parameter_ranges: vec![(0.0, f64::INFINITY); self.parameters.len()],
            parameters: self.parameters,
            parameter_meaning: self.meaning,
            area,
            centre: options.at,
            heading: options.angle,
        }
    }
}

fn edges(space: Space, vertices: &[Vertex], walls: &[DVec3]) -> Vec<Edge> {
    let n = vertices.len();
    if n == 0 {
        return vec![Edge {
            from: None,
            to: None,
            length: 2.0 * PI,
            wall: walls[0],
            geodesic: space.model_geodesic(walls[0]),
            kind: EdgeKind::Mirror,
            neighbour: reflection(space, walls[0]),
        }];
    }
    (0..n)
        .map(|i| {
            let (a, b) = (vertices[i], vertices[(i + 1) % n]);
            let length = if a.ideal || b.ideal {
                f64::INFINITY
            } else {
                space.distance(a.position, b.position)
            };
            // The lune's walls join antipodal corners: half a great circle, whichever way.
            let length = if n == 2 { PI } else { length };
            Edge {
                from: Some(i),
                to: Some((i + 1) % n),
                length,
                wall: walls[i],
                geodesic: space.model_geodesic(walls[i]),
                kind: EdgeKind::Mirror,
                neighbour: reflection(space, walls[i]),
            }
        })
        .collect()
}

/// Gauss–Bonnet for curved polygons; the shoelace formula (λ = 2) for flat ones.
fn polygon_area(space: Space, signature: &Signature, vertices: &[Vertex]) -> f64 {
    match space.geometry() {
        Geometry::Euclidean => {
            let n = vertices.len();
            let twice: f64 = (0..n)
                .map(|i| {
                    let (a, b) = (vertices[i].position, vertices[(i + 1) % n].position);
                    a.re * b.im - a.im * b.re
                })
                .sum();
            2.0 * twice.abs()
        }
        _ => signature.euler_characteristic().area(),
    }
}
