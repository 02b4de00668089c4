//! The polygon's boundary as a loop of ambient points, with its ideal corners cut off.

use glam::DVec3;

use crate::layout::Layout;
use crate::space::Space;

/// One side of the loop: from corner `i` to corner `i + 1` of [`Boundary::corners`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Side {
    /// The wall (edge index of the layout) it lies on, or `None` for the chord that cuts off a
    /// cusp.
    pub wall: Option<usize>,
    /// Its intrinsic length.
    pub length: f64,
}

/// The finite polygon that is meshed: the layout's corners, each ideal corner replaced by the two
/// points where a geodesic chord at distance [`Boundary::cusp_distance`] from the centre cuts its
/// walls. For `*` (a hemisphere with no corners) four points on its wall stand in for corners.
#[derive(Clone, Debug, PartialEq)]
pub struct Boundary {
    /// The plane.
    pub space: Space,
    /// Corners of the loop in ambient coordinates, counter-clockwise.
    pub corners: Vec<DVec3>,
    /// `sides[i]` joins `corners[i]` to `corners[i + 1]`.
    pub sides: Vec<Side>,
    /// The polygon's centre in ambient coordinates.
    pub centre: DVec3,
    /// For a polygon with ideal corners, the intrinsic distance from the centre at which each
    /// cusp is cut off.
    pub cusp_distance: Option<f64>,
}

/// How far beyond the farthest finite feature the cusps are cut by default.
pub const DEFAULT_CUSP_MARGIN: f64 = 3.0;

impl Boundary {
    /// The loop of `layout`. `cusp_distance` (from the centre) is raised where needed so that
    /// every cut lies beyond the finite corners and the walls' nearest points; `None` puts the
    /// cut [`DEFAULT_CUSP_MARGIN`] beyond them.
    pub fn new(layout: &Layout, cusp_distance: Option<f64>) -> Boundary {
        let space = layout.space();
        let centre = space.to_ambient(layout.centre);
        if layout.vertices.is_empty() {
            return Self::hemisphere(layout, centre);
        }
        let has_cusp = layout.vertices.iter().any(|v| v.ideal);
        let cusp = has_cusp.then(|| Self::cusp_radius(layout, centre, cusp_distance));
        let n = layout.vertices.len();
        let mut corners = Vec::with_capacity(n + 2);
        let mut walls = Vec::with_capacity(n + 2);
        for (i, vertex) in layout.vertices.iter().enumerate() {
            let before = (i + n - 1) % n;
            if vertex.ideal {
                let r = cusp.expect("an ideal corner has a cusp radius");
                let ideal = DVec3::new(vertex.position.re, vertex.position.im, 1.0);
                corners.push(point_towards_ideal(
                    space,
                    layout.edges[before].wall,
                    centre,
                    ideal,
                    r,
                ));
                walls.push(None);
                corners.push(point_towards_ideal(
                    space,
                    layout.edges[i].wall,
                    centre,
                    ideal,
                    r,
                ));
            } else {
                corners.push(space.to_ambient(vertex.position));
            }
            walls.push(Some(i));
        }
        split_half_circles(layout, centre, &mut corners, &mut walls);
        let sides = (0..corners.len())
            .map(|i| Side {
                wall: walls[i],
                length: space.ambient_distance(corners[i], corners[(i + 1) % corners.len()]),
            })
            .collect();
        Boundary {
            space,
            corners,
            sides,
            centre,
            cusp_distance: cusp,
        }
    }

    /// `*`: four points a quarter turn apart on the great circle that bounds the hemisphere.
    fn hemisphere(layout: &Layout, centre: DVec3) -> Boundary {
        let space = layout.space();
        let nu = layout.edges[0].wall;
        // Two orthonormal vectors spanning the wall's plane ν·p = 0 (ν is the centre's direction).
        let a = nu.any_orthonormal_vector();
        let b = nu.normalize().cross(a);
        let corners: Vec<DVec3> = [a, b, -a, -b].into();
        Boundary {
            space,
            sides: vec![
                Side {
                    wall: Some(0),
                    length: std::f64::consts::FRAC_PI_2,
                };
                4
            ],
            corners,
            centre,
            cusp_distance: None,
        }
    }

    /// The distance from the centre at which cusps are cut.
    fn cusp_radius(layout: &Layout, centre: DVec3, wanted: Option<f64>) -> f64 {
        let space = layout.space();
        let finite = layout
            .vertices
            .iter()
            .filter(|v| !v.ideal)
            .map(|v| space.ambient_distance(centre, space.to_ambient(v.position)));
        let feet = layout.edges.iter().map(|e| space.asin(e.wall.dot(centre)));
        let floor = finite.chain(feet).fold(0.0, f64::max) + 1e-3;
        wanted.unwrap_or(floor + DEFAULT_CUSP_MARGIN).max(floor)
    }

    /// The number of corners of the loop.
    pub fn len(&self) -> usize {
        self.corners.len()
    }

    /// Whether the loop is empty (never, for a layout).
    pub fn is_empty(&self) -> bool {
        self.corners.is_empty()
    }

    /// The sides that lie on a wall of the layout, in order along it (one side, but two for each
    /// wall of a lune and four for the wall of `*`); empty if `wall` is not on the loop.
    pub fn wall_sides(&self, wall: usize) -> Vec<usize> {
        let on_wall: Vec<usize> = (0..self.len())
            .filter(|&i| self.sides[i].wall == Some(wall))
            .collect();
        // Start where the previous side is not on this wall (a wall's sides are consecutive,
        // possibly across the end of the loop).
        let start = on_wall
            .iter()
            .position(|&i| self.sides[(i + self.len() - 1) % self.len()].wall != Some(wall))
            .unwrap_or(0);
        on_wall[start..]
            .iter()
            .chain(&on_wall[..start])
            .copied()
            .collect()
    }

    /// The point at fraction `t` of side `i`.
    pub fn point_on_side(&self, i: usize, t: f64) -> DVec3 {
        let (p, q) = (self.corners[i], self.corners[(i + 1) % self.len()]);
        self.space.interpolate(p, q, t)
    }
}

/// The walls of a lune `*kk` join antipodal corners, where the geodesic is not determined by its
/// ends: such a side gets its midpoint, the foot of the perpendicular from the centre.
fn split_half_circles(
    layout: &Layout,
    centre: DVec3,
    corners: &mut Vec<DVec3>,
    walls: &mut Vec<Option<usize>>,
) {
    let space = layout.space();
    let mut i = 0;
    while i < corners.len() {
        let next = corners[(i + 1) % corners.len()];
        if let Some(wall) = walls[i]
            && space.kappa() > 0.0
            && space.ambient_distance(corners[i], next) > 3.0
        {
            corners.insert(i + 1, foot(space, layout.edges[wall].wall, centre));
            walls.insert(i + 1, Some(wall));
        }
        i += 1;
    }
}

/// The foot of the perpendicular from `p` to the wall `nu`. Every perpendicular of a wall passes
/// through its pole G ν, so the foot is the point of the wall on the line through `p` and the
/// pole (⟨ν, Gν⟩ = 1 for a normalised wall).
fn foot(space: Space, nu: DVec3, p: DVec3) -> DVec3 {
    let pole = DVec3::new(nu.x, nu.y, space.kappa() * nu.z);
    space.normalize_point(p - pole * nu.dot(p))
}

/// The point of the wall `nu` (hyperbolic) at distance `r` from `centre` on the side of the ideal
/// point `ideal` (a null vector): from the foot f of the perpendicular from the centre, along the
/// unit tangent u = ideal/(−⟨f, ideal⟩) − f by t with cosh r = cosh d₀ · cosh t.
fn point_towards_ideal(space: Space, nu: DVec3, centre: DVec3, ideal: DVec3, r: f64) -> DVec3 {
    let foot = foot(space, nu, centre);
    let d0 = space.asin(nu.dot(centre));
    let u = ideal / -space.point_dot(foot, ideal) - foot;
    let t = (space.cos(r) / space.cos(d0)).max(1.0).acosh();
    foot * space.cos(t) + u * space.sin(t)
}
