//! A fundamental polygon with side pairings for every good two-dimensional orbifold
//! (ARCHITECTURE.md §11; docs/orbifolds.md).
//!
//! Every orbifold group acts on S², E² or H² with a fundamental polygon P whose edges are mirrors
//! or are paired by isometries; Poincaré's polygon theorem (Maskit, "On Poincaré's theorem for
//! fundamental polygons", Adv. Math. 7, 1971) says that the pairings generate a discrete group
//! with P as its fundamental domain when the angles around every vertex cycle add up to 2π/k (a
//! cone point of order k), π/k (a mirror corner of order k) or 2π (an ordinary point). The
//! notation and the families are Conway's (Conway, Burgiel, Goodman-Strauss, *The Symmetries of
//! Things*, 2008).
//!
//! | symbols | construction |
//! |---|---|
//! | `*k₁…k_N` | today's kaleidoscopic [`Layout`], every edge a mirror |
//! | `pqr` (three cones) | two copies of the triangle of `*pqr`, edges paired by the rotations about p and q |
//! | `k*m`, `k*` (k ≥ 3) | the isosceles triangle with apex 2π/k, its legs paired by the rotation, its base a mirror |
//! | `2*mn`, `2*m`, `2*` | the triangle π/m, β, γ (β + γ = π/n) of mirrors, its third side folded by a half-turn |
//! | `2*k₁…kₙ` (n ≥ 3, or `2*m∞`) | the polygon of mirrors of `*k₁…kₙ22`, its side between the two right angles folded by a half-turn |
//! | `NN`, `N×`, `×` | a lune, its sides paired by a rotation (NN) or a rotatory reflection (N×) |
//! | `o` | a parallelogram, opposite sides paired by the lattice's translations |
//! | `2222` | half a lattice parallelogram, two sides folded by half-turns, two paired by a translation |
//! | everything else | the *star* ([`star`]): sectors around a centre, one per feature; in H² deformed to every free parameter ([`deform`]) |
//!
//! ```
//! use orbifold::pairing::{CycleKind, FundamentalPolygon};
//! let p = FundamentalPolygon::new(&"632".parse().unwrap(), &Default::default()).unwrap();
//! assert_eq!(p.edges.len(), 4);
//! let kinds: Vec<_> = p.cycles.iter().map(|c| c.kind).collect();
//! assert!(kinds.iter().all(|&k| k == CycleKind::Cone));
//! ```

pub mod cover;
pub(crate) mod cycles;
pub mod deform;
pub(crate) mod geometry;
pub mod star;
pub(crate) mod textbook;

#[cfg(test)]
mod tests;

use glam::{DMat3, DVec3};
use num_complex::Complex64;

use crate::conway::OrbifoldSymbol;
use crate::cover::reflection;
use crate::euler::Geometry;
use crate::isometry::Isometry;
use crate::layout::{Layout, LayoutError, LayoutOptions, Shape};
use crate::order::Order;
use crate::space::Space;

/// What an edge of the polygon is.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum EdgeKind {
    /// A mirror: the tile across it is the polygon's reflection in it.
    Mirror,
    /// Glued to edge `partner` (possibly itself… never in these constructions) by an isometry.
    Paired {
        /// The partner edge's index.
        partner: usize,
    },
}

/// A side of the polygon: edge i joins vertex i to vertex i + 1.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Edge {
    /// The vertex it starts at (`None` for the single wall of `*`).
    pub from: Option<usize>,
    /// The vertex it ends at.
    pub to: Option<usize>,
    /// The wall as a linear form on ambient coordinates, positive inside the polygon.
    pub wall: DVec3,
    /// Mirror or paired.
    pub kind: EdgeKind,
    /// The group element g with g(P) the tile across this edge (ARCHITECTURE.md §11): the
    /// reflection in the edge for a mirror; for an edge paired with j, the isometry that takes
    /// edge j onto this edge, so that `neighbour(j) = neighbour(i)⁻¹`.
    pub neighbour: DMat3,
}

impl Edge {
    /// Whether [`Edge::neighbour`] reverses orientation (a mirror, or a glide reflection).
    pub fn reverses_orientation(&self) -> bool {
        self.neighbour.determinant() < 0.0
    }
}

/// A corner of the polygon.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Vertex {
    /// Model coordinates (on the unit circle for an ideal vertex).
    pub position: Complex64,
    /// Ambient coordinates (the null direction (x, y, 1) for an ideal vertex).
    pub ambient: DVec3,
    /// The interior angle in radians (0 for an ideal vertex).
    pub angle: f64,
    /// Whether the vertex is at infinity.
    pub ideal: bool,
}

/// What kind of point of the orbifold a vertex cycle is.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum CycleKind {
    /// A cone point of order k ≥ 2: angles add up to 2π/k.
    Cone,
    /// A point on a mirror boundary: angles add up to π/k (k = 1 is a plain mirror point).
    Corner,
    /// An ordinary point: angles add up to 2π.
    Regular,
    /// A point at infinity (a cusp, or an ideal corner): angles add up to 0.
    Ideal,
}

impl CycleKind {
    /// `cone`, `corner`, `regular` or `ideal`.
    pub fn name(self) -> &'static str {
        match self {
            CycleKind::Cone => "cone",
            CycleKind::Corner => "corner",
            CycleKind::Regular => "regular",
            CycleKind::Ideal => "ideal",
        }
    }
}

/// A class of vertices glued into one point of the orbifold.
#[derive(Clone, Debug, PartialEq)]
pub struct Cycle {
    /// The vertices, in the order the pairings visit them.
    pub vertices: Vec<usize>,
    /// Cone point, mirror corner, ordinary point or point at infinity.
    pub kind: CycleKind,
    /// The order k of the point (1 for ordinary points and plain mirror points, ∞ at infinity).
    pub order: Order,
    /// The sum of the interior angles of the cycle's vertices.
    pub angle_sum: f64,
    /// Whether the walk around the point closes up (false when it runs from mirror to mirror).
    pub closed: bool,
}

impl Cycle {
    /// The angle sum Poincaré's theorem asks for: 2π/k closed, π/k on a mirror, 0 at infinity.
    pub fn expected_angle_sum(&self) -> f64 {
        let k = self.order.to_f64();
        match (self.kind, self.closed) {
            (CycleKind::Ideal, _) => 0.0,
            (_, true) => std::f64::consts::TAU / k,
            (_, false) => std::f64::consts::PI / k,
        }
    }
}

/// Which construction built the polygon (docs/orbifolds.md).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Construction {
    /// `*k₁…k_N`: the kaleidoscopic [`Layout`].
    Kaleidoscopic,
    /// Three cones `pqr`: the triangle of `*pqr` and its mirror image.
    DoubledTriangle,
    /// `k*m`, `k*`: an isosceles triangle, legs paired by the rotation about its apex.
    ConeAndMirror,
    /// `2*mn`, `2*m`, `2*`: a triangle of mirrors with its third side folded by a half-turn.
    FoldedTriangle,
    /// `2*k₁…kₙ` (n ≥ 3, or `2*m∞`): the polygon of `*k₁…kₙ22`, its side between the right
    /// angles folded by a half-turn.
    FoldedPolygon,
    /// `NN`, `N×`, `×`: a lune with its sides paired.
    Lune,
    /// `o` (p1): a parallelogram, opposite sides paired by translations.
    Parallelogram,
    /// `2222` (p2): half a lattice parallelogram, two sides folded by half-turns.
    FoldedParallelogram,
    /// The general star around a centre ([`star`]).
    Star,
    /// A room layout given back ([`FundamentalPolygon::from_layout`]), whose construction is
    /// not recorded.
    Given,
}

impl Construction {
    /// A short name for reports.
    pub fn name(self) -> &'static str {
        match self {
            Construction::Kaleidoscopic => "kaleidoscopic",
            Construction::DoubledTriangle => "doubled triangle",
            Construction::ConeAndMirror => "cone and mirror",
            Construction::FoldedTriangle => "folded triangle",
            Construction::FoldedPolygon => "folded polygon",
            Construction::Lune => "lune",
            Construction::Parallelogram => "parallelogram",
            Construction::FoldedParallelogram => "folded parallelogram",
            Construction::Star => "star",
            Construction::Given => "given polygon",
        }
    }
}

/// A fundamental polygon of an orbifold group with its side pairings, vertex cycles and free
/// shape parameters.
///
/// ```
/// use orbifold::pairing::{EdgeKind, FundamentalPolygon};
/// let p = FundamentalPolygon::new(&"22×".parse().unwrap(), &Default::default()).unwrap();
/// // Every paired edge's neighbour is the inverse of its partner's.
/// for (i, e) in p.edges.iter().enumerate() {
///     if let EdgeKind::Paired { partner } = e.kind {
///         let product = e.neighbour * p.edges[partner].neighbour;
///         assert!(product.abs_diff_eq(glam::DMat3::IDENTITY, 1e-9), "edge {i}");
///     }
/// }
/// assert_eq!(p.parameters.len(), 1);
/// ```
#[derive(Clone, Debug, PartialEq)]
pub struct FundamentalPolygon {
    /// The symbol, as given.
    pub symbol: OrbifoldSymbol,
    /// Spherical, Euclidean or hyperbolic.
    pub geometry: Geometry,
    /// The corners, counter-clockwise.
    pub vertices: Vec<Vertex>,
    /// The sides; edge i joins vertex i to vertex i + 1.
    pub edges: Vec<Edge>,
    /// The vertex cycles.
    pub cycles: Vec<Cycle>,
    /// The values of the free parameters this construction supports.
    pub parameters: Vec<f64>,
    /// What each parameter means, with its valid range and default.
    pub parameter_meanings: Vec<String>,
    /// Each parameter's open range of valid values, as the meaning states it.
    pub parameter_ranges: Vec<(f64, f64)>,
    /// How many of the symbol's [`OrbifoldSymbol::free_parameters`] this construction does not
    /// offer (docs/orbifolds.md says which and why).
    pub missing_parameters: usize,
    /// The construction used.
    pub construction: Construction,
    /// The intrinsic area: 2π|χ| on the sphere and in the hyperbolic plane.
    pub area: f64,
    /// An interior point (the star's centre, or the centre of the largest inscribed disk; for
    /// kaleidoscopic polygons the layout's centre), in model coordinates.
    pub centre: Complex64,
    /// The kaleidoscopic layout, for `*k₁…k_N`.
    pub layout: Option<Layout>,
}

/// A polygon before it is measured: points, walls and how the edges are glued.
#[derive(Clone)]
pub(crate) struct Draft {
    /// Ambient points (null directions for ideal ones), counter-clockwise.
    pub(crate) points: Vec<DVec3>,
    pub(crate) ideal: Vec<bool>,
    /// The declared order of each vertex's cycle (1 for ordinary and plain mirror points).
    pub(crate) orders: Vec<Order>,
    /// Walls given by the construction (needed where two consecutive points are antipodal);
    /// `None` to take the wall through the edge's end points.
    pub(crate) walls: Option<Vec<DVec3>>,
    /// Edge i: mirror, or paired with (partner, orientation-reversing).
    pub(crate) glue: Vec<Glue>,
    /// Pairings given by the construction (as products of reflections, exact where both ends of
    /// an edge are ideal); `None` to build each from a finite end point of its edge.
    pub(crate) neighbours: Option<Vec<DMat3>>,
    /// An interior point.
    pub(crate) centre: DVec3,
    pub(crate) parameters: Vec<f64>,
    /// Each parameter's open range of valid values.
    pub(crate) ranges: Vec<(f64, f64)>,
    pub(crate) meanings: Vec<String>,
    pub(crate) construction: Construction,
}

/// The textbooks' labels of side pairings: letters a, b, c, … for the pairs of paired edges, in
/// the order of their lower edge, given each edge's partner (`None` for a mirror, which gets no
/// letter).
///
/// ```
/// use orbifold::pairing::pair_letters;
/// assert_eq!(pair_letters(&[Some(3), None, Some(2), Some(0)]), [Some('a'), None, Some('b'), Some('a')]);
/// ```
pub fn pair_letters(partners: &[Option<usize>]) -> Vec<Option<char>> {
    let mut letters = vec![None; partners.len()];
    let mut next = 0u8;
    for (i, partner) in partners.iter().enumerate() {
        if let Some(j) = *partner
            && letters[i].is_none()
        {
            let letter = (b'a' + next % 26) as char;
            next += 1;
            letters[i] = Some(letter);
            letters[j] = Some(letter);
        }
    }
    letters
}

/// Whether the textbooks' arrow on paired edge `i` (partner `partner`) runs from its first
/// corner to its second, so that the pairing takes the partner's arrow onto this one's: the
/// lower edge of a pair runs forwards; an orientation-preserving pairing takes the partner's
/// first corner to this edge's second, so the other runs backwards; a glide (`reverses`) keeps
/// the direction, so both run forwards.
pub fn arrow_runs_forward(i: usize, partner: usize, reverses: bool) -> bool {
    reverses || i < partner
}

/// How a draft's edge is glued.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum Glue {
    Mirror,
    Paired { partner: usize, reverses: bool },
}

impl FundamentalPolygon {
    /// The fundamental polygon of `symbol`, with the shape parameters and placement of `options`
    /// ([`Shape::Incircle`] is only for kaleidoscopic symbols).
    pub fn new(
        symbol: &OrbifoldSymbol,
        options: &LayoutOptions,
    ) -> Result<FundamentalPolygon, LayoutError> {
        if let Some(signature) = symbol.as_kaleidoscopic() {
            let layout = Layout::new(&signature, options)?;
            return Ok(FundamentalPolygon::from_layout(symbol.clone(), layout));
        }
        if let Some(reason) = symbol.reason() {
            return Err(LayoutError::NotBuildable(reason));
        }
        let at = options.at;
        if !(at.re.is_finite() && at.im.is_finite() && options.angle.is_finite()) {
            return Err(LayoutError::Placement(
                "the position and angle must be finite numbers".into(),
            ));
        }
        let space = Space::new(symbol.geometry());
        if space.kappa() < 0.0 && at.norm() >= 1.0 {
            return Err(LayoutError::Placement(format!(
                "({}, {}) is not inside the Poincaré disk; the centre must satisfy x² + y² < 1",
                at.re, at.im
            )));
        }
        let parameters = match &options.shape {
            Shape::Default => None,
            Shape::Parameters(values) => Some(values.as_slice()),
            Shape::Incircle => {
                return Err(LayoutError::Unsupported(format!(
                    "{symbol} is not kaleidoscopic; --shape incircle is only for polygons of mirrors"
                )));
            }
        };
        let draft = match textbook::draft(symbol, space, parameters)? {
            Some(draft) => draft,
            // In H² every free parameter: the star deformed (deform.rs), the star the default.
            None if space.kappa() < 0.0 => {
                deform::deformed(symbol, space, star::draft(symbol, space, None)?, parameters)?
            }
            None => star::draft(symbol, space, parameters)?,
        };
        let motion =
            Isometry::translation(space, at).compose(&Isometry::rotation(space, options.angle));
        finish(symbol, space, draft, motion.matrix())
    }

    /// Wraps a layout: a kaleidoscopic one (any, non-orbifold rooms too: every edge a mirror,
    /// every corner its own cycle), or the room layout of a polygon with side pairings
    /// ([`FundamentalPolygon::room_layout`], whose cycles are walked again).
    ///
    /// ```
    /// use orbifold::{Layout, pairing::FundamentalPolygon};
    /// let layout = Layout::new(&"*2333".parse().unwrap(), &Default::default()).unwrap();
    /// let p = FundamentalPolygon::from_layout(layout.symbol.clone(), layout);
    /// assert_eq!(p.cycles.len(), 4);
    /// ```
    pub fn from_layout(symbol: OrbifoldSymbol, layout: Layout) -> FundamentalPolygon {
        let space = layout.space();
        let vertices: Vec<Vertex> = layout
            .vertices
            .iter()
            .map(|v| Vertex {
                position: v.position,
                ambient: if v.ideal {
                    DVec3::new(v.position.re, v.position.im, 1.0)
                } else {
                    space.to_ambient(v.position)
                },
                angle: v.angle,
                ideal: v.ideal,
            })
            .collect();
        let edges: Vec<Edge> = layout
            .edges
            .iter()
            .map(|e| Edge {
                from: e.from,
                to: e.to,
                wall: e.wall,
                kind: e.kind,
                neighbour: e.neighbour,
            })
            .collect();
        let cycles = if layout.is_kaleidoscopic() {
            layout
                .vertices
                .iter()
                .enumerate()
                .map(|(i, v)| Cycle {
                    vertices: vec![i],
                    kind: if v.ideal {
                        CycleKind::Ideal
                    } else {
                        CycleKind::Corner
                    },
                    order: v.order,
                    angle_sum: v.angle,
                    closed: false,
                })
                .collect()
        } else {
            // A room layout of a polygon with side pairings: its corners carry their cycles'
            // orders, from which the cycles are walked again.
            let orders: Vec<Order> = layout.vertices.iter().map(|v| v.order).collect();
            cycles::cycles(&vertices, &edges, &orders)
        };
        let meanings = (0..layout.parameters.len())
            .map(|_| layout.parameter_meaning.describe(layout.vertices.len()))
            .collect();
        FundamentalPolygon {
            geometry: layout.geometry,
            missing_parameters: symbol
                .free_parameters()
                .saturating_sub(layout.parameters.len()),
            symbol,
            vertices,
            edges,
            cycles,
            parameters: layout.parameters.clone(),
            parameter_meanings: meanings,
            parameter_ranges: layout.parameter_ranges.clone(),
            construction: if layout.is_kaleidoscopic() {
                Construction::Kaleidoscopic
            } else {
                Construction::Given
            },
            area: layout.area,
            centre: layout.centre,
            layout: Some(layout),
        }
    }

    /// The curvature κ of the model.
    pub fn space(&self) -> Space {
        Space::new(self.geometry)
    }

    /// The polygon as a room's [`Layout`]: its corners (each with its cycle's order), walls with
    /// their lengths, mirrors and pairings, area and centre; `heading` is the placement angle the
    /// polygon was built with. A kaleidoscopic polygon gives back its own layout.
    ///
    /// ```
    /// use orbifold::pairing::{EdgeKind, FundamentalPolygon};
    /// let p = FundamentalPolygon::new(&"4*2".parse()?, &Default::default())?;
    /// let layout = p.room_layout(0.0);
    /// assert_eq!(layout.edges.len(), p.edges.len());
    /// assert!((layout.area - p.area).abs() < 1e-12);
    /// assert!(layout.edges.iter().any(|e| e.kind == EdgeKind::Mirror));
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn room_layout(&self, heading: f64) -> Layout {
        if let Some(layout) = &self.layout {
            return layout.clone();
        }
        let space = self.space();
        let n = self.vertices.len();
        let cycle_order = |i: usize| {
            self.cycles
                .iter()
                .find(|c| c.vertices.contains(&i))
                .map_or(Order::integer(1), |c| c.order)
        };
        let vertices: Vec<crate::layout::Vertex> = self
            .vertices
            .iter()
            .enumerate()
            .map(|(i, v)| crate::layout::Vertex {
                position: v.position,
                order: cycle_order(i),
                angle: v.angle,
                ideal: v.ideal,
            })
            .collect();
        let edges = self
            .edges
            .iter()
            .enumerate()
            .map(|(i, e)| {
                let (a, b) = (&self.vertices[i], &self.vertices[(i + 1) % n]);
                let length = if a.ideal || b.ideal {
                    f64::INFINITY
                } else if space.kappa() > 0.0 && n == 2 {
                    // A lune's sides join antipodal corners: half a great circle.
                    std::f64::consts::PI
                } else {
                    space.ambient_distance(a.ambient, b.ambient)
                };
                crate::layout::Edge {
                    from: e.from,
                    to: e.to,
                    length,
                    wall: e.wall,
                    geodesic: space.model_geodesic(e.wall),
                    kind: e.kind,
                    neighbour: e.neighbour,
                }
            })
            .collect();
        Layout {
            symbol: self.symbol.clone(),
            geometry: self.geometry,
            vertices,
            edges,
            parameters: self.parameters.clone(),
            parameter_ranges: self.parameter_ranges.clone(),
            parameter_meaning: crate::layout::ParameterMeaning::SidePairing,
            area: self.area,
            centre: self.centre,
            heading,
        }
    }

    /// The generator `neighbour(i)` as an [`Isometry`].
    pub fn neighbour(&self, i: usize) -> Isometry {
        Isometry::from_matrix(self.space(), self.edges[i].neighbour)
    }

    /// The centre's ambient coordinates.
    pub fn centre_ambient(&self) -> DVec3 {
        self.space().to_ambient(self.centre)
    }

    /// The intrinsic distance from the centre to the nearest edge (its inradius about the centre).
    pub fn clearance(&self) -> f64 {
        let space = self.space();
        let o = self.centre_ambient();
        self.edges
            .iter()
            .map(|e| space.asin(e.wall.dot(o)))
            .fold(f64::INFINITY, f64::min)
    }

    /// Whether the model point `z` lies in the closed polygon (within `slack` of its walls).
    pub fn contains(&self, z: Complex64, slack: f64) -> bool {
        let p = self.space().to_ambient(z);
        self.contains_ambient(p, slack)
    }

    /// Whether the ambient point `p` lies in the closed polygon, with slack in ν·p.
    pub fn contains_ambient(&self, p: DVec3, slack: f64) -> bool {
        self.edges.iter().all(|e| e.wall.dot(p) >= -slack)
    }
}

/// Measures a draft: walls, angles, pairings, cycles and area; checks that it is convex, then
/// moves it by `motion`.
fn finish(
    symbol: &OrbifoldSymbol,
    space: Space,
    draft: Draft,
    motion: DMat3,
) -> Result<FundamentalPolygon, LayoutError> {
    let Draft {
        points,
        ideal,
        orders,
        walls,
        glue,
        neighbours: given,
        centre,
        parameters,
        ranges,
        meanings,
        construction,
    } = draft;
    let n = points.len();
    // Standard position first: the centre at the origin, where bearings check convexity.
    let centring = Isometry::translation(space, model_of(space, centre, false))
        .inverse()
        .matrix();
    let points: Vec<DVec3> = points.iter().map(|&p| centring * p).collect();
    let walls: Vec<DVec3> = match walls {
        Some(w) => w
            .iter()
            .map(|&nu| Isometry::from_matrix(space, centring).apply_wall(nu))
            .collect(),
        None => (0..n)
            .map(|i| geometry::wall_through(space, points[i], points[(i + 1) % n], DVec3::Z))
            .collect(),
    };
    let angles: Vec<f64> = (0..n)
        .map(|i| {
            if ideal[i] {
                0.0
            } else {
                geometry::interior_angle(space, points[i], walls[(i + n - 1) % n], walls[i])
            }
        })
        .collect();
    check_convex(space, &points, &walls, &angles)?;
    let neighbours: Vec<DMat3> = match given {
        Some(given) => {
            let back = Isometry::from_matrix(space, centring).inverse().matrix();
            given.iter().map(|&g| centring * g * back).collect()
        }
        None => (0..n)
            .map(|i| neighbour(space, &points, &ideal, &walls, &glue, i))
            .collect(),
    };
    let area = polygon_area(space, &points, &ideal, &angles);
    let m = Isometry::from_matrix(space, motion);
    let m_inv = m.inverse().matrix();
    let vertices: Vec<Vertex> = (0..n)
        .map(|i| {
            let ambient = motion * points[i];
            Vertex {
                position: model_of(space, ambient, ideal[i]),
                ambient: if ideal[i] {
                    ambient / ambient.z
                } else {
                    ambient
                },
                angle: angles[i],
                ideal: ideal[i],
            }
        })
        .collect();
    let edges: Vec<Edge> = (0..n)
        .map(|i| Edge {
            from: Some(i),
            to: Some((i + 1) % n),
            wall: m.apply_wall(walls[i]),
            kind: match glue[i] {
                Glue::Mirror => EdgeKind::Mirror,
                Glue::Paired { partner, .. } => EdgeKind::Paired { partner },
            },
            neighbour: motion * neighbours[i] * m_inv,
        })
        .collect();
    let cycles = cycles::cycles(&vertices, &edges, &orders);
    let supported = parameters.len();
    Ok(FundamentalPolygon {
        symbol: symbol.clone(),
        geometry: space.geometry(),
        vertices,
        edges,
        cycles,
        parameters,
        parameter_meanings: meanings,
        parameter_ranges: ranges,
        missing_parameters: symbol.free_parameters().saturating_sub(supported),
        construction,
        area,
        centre: model_of(space, motion * DVec3::Z, false),
        layout: None,
    })
}

/// Model coordinates of an ambient point or an ideal point's null direction.
fn model_of(space: Space, p: DVec3, ideal: bool) -> Complex64 {
    if ideal {
        space.ideal_to_model(p)
    } else {
        space.to_model(p)
    }
}

/// The pairing that takes edge `partner` onto edge `i`, built from a finite end point and the
/// edge's direction there, so that ideal vertices need no special case.
fn neighbour(
    space: Space,
    points: &[DVec3],
    ideal: &[bool],
    walls: &[DVec3],
    glue: &[Glue],
    i: usize,
) -> DMat3 {
    let n = points.len();
    let Glue::Paired {
        partner: j,
        reverses,
    } = glue[i]
    else {
        return reflection(space, walls[i]);
    };
    let (s, t) = (i, (i + 1) % n);
    let (s2, t2) = (j, (j + 1) % n);
    // Forward (start → end) and backward (end → start) unit tangents along an edge.
    let forward = |edge: usize, v: usize| geometry::along(space, walls[edge], points[v]);
    let backward = |edge: usize, v: usize| -geometry::along(space, walls[edge], points[v]);
    // Preserving: j's start ↦ i's end, j's end ↦ i's start. Reversing: start ↦ start, end ↦ end.
    let (from, to) = match (reverses, ideal[s2]) {
        (false, false) => ((points[s2], forward(j, s2)), (points[t], backward(i, t))),
        (false, true) => ((points[t2], backward(j, t2)), (points[s], forward(i, s))),
        (true, false) => ((points[s2], forward(j, s2)), (points[s], forward(i, s))),
        (true, true) => ((points[t2], backward(j, t2)), (points[t], backward(i, t))),
    };
    geometry::frame_map(space, from, to, reverses)
}

/// Every finite corner at most π, and the corners' bearings from the centre (the origin) turn
/// once around it, each step less than π: the polygon is convex, simple and contains the centre.
fn check_convex(
    space: Space,
    points: &[DVec3],
    walls: &[DVec3],
    angles: &[f64],
) -> Result<(), LayoutError> {
    let n = points.len();
    let bad = |what: String| Err(LayoutError::Unrealisable(what));
    if let Some(i) = angles
        .iter()
        .position(|&a| !(a.is_finite() && a <= std::f64::consts::PI + 1e-9))
    {
        return bad(format!(
            "the construction gave a corner of {} rad at vertex {i}, which is not convex",
            angles[i]
        ));
    }
    if let Some(i) = walls
        .iter()
        .position(|w| w.dot(DVec3::Z).is_nan() || w.dot(DVec3::Z) <= 0.0)
    {
        return bad(format!("the centre is not inside edge {i}"));
    }
    let bearing = |p: DVec3| p.y.atan2(p.x);
    let total: f64 = (0..n)
        .map(|i| {
            (bearing(points[(i + 1) % n]) - bearing(points[i])).rem_euclid(std::f64::consts::TAU)
        })
        .sum();
    if (total - std::f64::consts::TAU).abs() > 1e-6 || points.iter().any(|p| !p.is_finite()) {
        return bad("the construction's corners do not go once around its centre".into());
    }
    let _ = space;
    Ok(())
}

/// The area as a fan of triangles from the centre (the origin); a triangle with an ideal corner
/// n takes the limit of Van Oosterom–Strackee's formula, 2·atan2(|det(p, q, n)|, κ⟨q, n⟩ + κ⟨n, p⟩).
/// On the sphere, where a lune's corners are antipodal, Gauss–Bonnet from the measured angles.
fn polygon_area(space: Space, points: &[DVec3], ideal: &[bool], angles: &[f64]) -> f64 {
    let n = points.len();
    if space.kappa() > 0.0 {
        return angles.iter().sum::<f64>() - (n as f64 - 2.0) * std::f64::consts::PI;
    }
    let o = DVec3::Z;
    (0..n)
        .map(|i| {
            let j = (i + 1) % n;
            let (p, q) = (points[i], points[j]);
            match (ideal[i], ideal[j]) {
                (false, false) => space.triangle_area(o, p, q),
                (true, false) => ideal_triangle_area(space, q, o, p),
                (false, true) => ideal_triangle_area(space, o, p, q),
                // Both ideal: the angles there are 0, so the area is π minus the angle at O.
                (true, true) => {
                    std::f64::consts::PI
                        - (q.y.atan2(q.x) - p.y.atan2(p.x)).rem_euclid(std::f64::consts::TAU)
                }
            }
        })
        .sum()
}

/// The area of the triangle with finite corners `p`, `q` and ideal corner `n`.
fn ideal_triangle_area(space: Space, p: DVec3, q: DVec3, n: DVec3) -> f64 {
    let k = space.kappa();
    let det = DMat3::from_cols(p, q, n).determinant().abs();
    2.0 * det.atan2(k * space.point_dot(q, n) + k * space.point_dot(n, p))
}
