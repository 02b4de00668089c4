//! Smooth shading normals of triangle meshes in S²×ℝ, E²×ℝ and H²×ℝ, written once for every
//! curvature.
//!
//! A scanned mesh such as the Stanford dragon is a fine polyhedron: shaded with its faces'
//! own normals it looks faceted, and a denoiser guided by normals cannot average across its
//! facets. As in every renderer, each corner of a face gets a *vertex normal*: the mean of the
//! normals of the faces round the vertex that bend from this face by less than a crease angle,
//! each weighted by its corner angle there (Thürmer and Wüthrich's angle weights, which do not
//! depend on how a face is cut into triangles). Faces that bend more stay sharp.
//!
//! In a curved plane the faces' normals at a vertex all live in the one tangent space there, so
//! the mean needs nothing new. Across a face the corners' normals live at three different points:
//! each is carried by parallel transport ([`Space::transport`]) along the geodesic to the point
//! being shaded, and the three are averaged with the point's barycentric weights. The result
//! depends on an edge's two corners only, so two faces that share a smooth edge agree along it;
//! in E²×ℝ transport is the identity and this is the usual linear interpolation of normals.
//! Vertical components need no transport (the product's vertical direction is parallel).
//!
//! Only the shading uses these normals: which side of a surface a direction is on is still
//! decided by the face's own (geometric) normal.

use glam::DVec3;
use orbifold::space::Space;

use crate::triangle::Triangle;

/// A tangent vector of the product space at a point: horizontal ambient part and vertical part.
type Tangent = (DVec3, f64);

/// The default crease angle (degrees) between faces that are shaded as one smooth surface.
pub const DEFAULT_CREASE_DEGREES: f64 = 60.0;

/// The vertex normals of a mesh, corner by corner (a vertex on a crease has one normal on each
/// side of it).
///
/// ```
/// use orbifold::{Geometry, space::Space};
/// use orbifold_trace::shading_normal::VertexNormals;
/// use glam::DVec3;
/// let e2 = Space::new(Geometry::Euclidean);
/// let p = |x: f64, y: f64| e2.exp(DVec3::Z, DVec3::new(x, y, 0.0));
/// // Two faces of a roof folded by 40° along the edge 0–1: smooth at a crease angle of 60°.
/// let t = 20f64.to_radians().tan();
/// let points = [p(0.0, 0.0), p(1.0, 0.0), p(0.0, 1.0), p(0.0, -1.0)];
/// let heights = [0.0, 0.0, -t, -t];
/// let tris = [[0, 1, 2], [1, 0, 3]];
/// let smooth = VertexNormals::new(e2, &points, &heights, &tris, 60f64.to_radians());
/// // On the shared edge both faces shade with the vertical normal.
/// let (n, up) = smooth.at(e2, 0, [points[0], points[1], points[2]], [0.5, 0.5, 0.0]).unwrap();
/// assert!(n.length() < 1e-12 && (up - 1.0).abs() < 1e-12);
/// ```
#[derive(Clone, Debug, Default)]
pub struct VertexNormals {
    /// For each triangle, its corners' normals; `None` where all three are the face's own normal
    /// (the face is shaded flat, exactly).
    corners: Vec<Option<[Tangent; 3]>>,
    /// The crease angle they were made with (radians).
    crease: f64,
}

/// The face normal and corner angle of one corner of one triangle.
#[derive(Clone, Copy)]
struct Corner {
    triangle: u32,
    normal: Tangent,
    angle: f64,
}

impl VertexNormals {
    /// Vertex normals for the mesh (ambient points, heights, triangles): faces round a vertex
    /// whose normals differ by less than `crease` (radians) are shaded as one surface. Faces
    /// are assumed consistently oriented; a neighbour that is not counts as a crease.
    pub fn new(
        space: Space,
        points: &[DVec3],
        heights: &[f64],
        triangles: &[[u32; 3]],
        crease: f64,
    ) -> VertexNormals {
        let cos_crease = crease.cos();
        let corners_of = corners_by_vertex(space, points, heights, triangles);
        let corners = triangles
            .iter()
            .enumerate()
            .map(|(t, triangle)| {
                let face = triangle_of(points, heights, triangle);
                let mut smooth = false;
                let mut normals = [(DVec3::ZERO, 0.0); 3];
                for (i, normal) in normals.iter_mut().enumerate() {
                    let own = face.normal(space, unit(i))?;
                    let mut sum = (DVec3::ZERO, 0.0);
                    for c in &corners_of[triangle[i] as usize] {
                        if c.triangle as usize != t
                            && product_dot(space, c.normal, own) >= cos_crease
                        {
                            sum = (sum.0 + c.normal.0 * c.angle, sum.1 + c.normal.1 * c.angle);
                            smooth = true;
                        }
                    }
                    let angle = corner_angle(space, &face, i);
                    sum = (sum.0 + own.0 * angle, sum.1 + own.1 * angle);
                    *normal = normalized(space, sum).unwrap_or(own);
                }
                smooth.then_some(normals)
            })
            .collect();
        VertexNormals { corners, crease }
    }

    /// The shading normal of triangle `index` of the mesh, whose vertices are `vertices`, at
    /// barycentric coordinates `w`: unit in the product metric, in the tangent space at that
    /// point. `None` where the face is shaded flat (use its own normal).
    pub fn at(
        &self,
        space: Space,
        index: u32,
        vertices: [DVec3; 3],
        w: [f64; 3],
    ) -> Option<Tangent> {
        let corners = self.corners.get(index as usize)?.as_ref()?;
        let x = space.normalize_point(vertices[0] * w[0] + vertices[1] * w[1] + vertices[2] * w[2]);
        let mut sum = (DVec3::ZERO, 0.0);
        for i in 0..3 {
            let (h, v) = corners[i];
            sum.0 += space.transport(vertices[i], x, h) * w[i];
            sum.1 += v * w[i];
        }
        normalized(space, sum)
    }

    /// The crease angle (radians) they were made with.
    pub fn crease(&self) -> f64 {
        self.crease
    }

    /// How many faces are shaded smooth (the rest are flat).
    pub fn smooth_faces(&self) -> usize {
        self.corners.iter().filter(|c| c.is_some()).count()
    }
}

/// Every vertex's corners: the face normal of each triangle at that vertex and its corner angle.
fn corners_by_vertex(
    space: Space,
    points: &[DVec3],
    heights: &[f64],
    triangles: &[[u32; 3]],
) -> Vec<Vec<Corner>> {
    let mut corners: Vec<Vec<Corner>> = vec![Vec::new(); points.len()];
    for (t, triangle) in triangles.iter().enumerate() {
        let face = triangle_of(points, heights, triangle);
        for i in 0..3 {
            let Some(normal) = face.normal(space, unit(i)) else {
                continue;
            };
            let angle = corner_angle(space, &face, i);
            if angle > 0.0 {
                corners[triangle[i] as usize].push(Corner {
                    triangle: t as u32,
                    normal,
                    angle,
                });
            }
        }
    }
    corners
}

/// The angle of a triangle at corner `i`: between the two edges leaving it, in the product
/// metric (the edges' tangents at the vertex, from the central projection that draws them).
fn corner_angle(space: Space, face: &Triangle, i: usize) -> f64 {
    let x = face.points[i];
    // The differential at a unit point x of p ↦ normalise(p): v minus its part along x.
    let tangent = |v: DVec3| {
        let along = if space.kappa() == 0.0 {
            v.z
        } else {
            space.kappa() * space.point_dot(x, v)
        };
        v - x * along
    };
    let edge = |j: usize| {
        let j = (i + j) % 3;
        (
            tangent(face.points[j] - x),
            face.heights[j] - face.heights[i],
        )
    };
    let (e, f) = (edge(1), edge(2));
    let norms = product_dot(space, e, e).sqrt() * product_dot(space, f, f).sqrt();
    if !(norms > 0.0 && norms.is_finite()) {
        return 0.0;
    }
    (product_dot(space, e, f) / norms).clamp(-1.0, 1.0).acos()
}

fn triangle_of(points: &[DVec3], heights: &[f64], triangle: &[u32; 3]) -> Triangle {
    let [a, b, c] = triangle.map(|i| i as usize);
    Triangle::new(
        [points[a], points[b], points[c]],
        [heights[a], heights[b], heights[c]],
    )
}

/// The barycentric coordinates of corner `i`.
fn unit(i: usize) -> [f64; 3] {
    let mut w = [0.0; 3];
    w[i] = 1.0;
    w
}

/// The product metric ⟨·,·⟩_κ + dh² on tangent vectors.
fn product_dot(space: Space, a: Tangent, b: Tangent) -> f64 {
    space.point_dot(a.0, b.0) + a.1 * b.1
}

fn normalized(space: Space, v: Tangent) -> Option<Tangent> {
    let norm = product_dot(space, v, v).sqrt();
    (norm > 1e-300 && norm.is_finite()).then(|| (v.0 / norm, v.1 / norm))
}

#[cfg(test)]
mod tests {
    use super::*;
    use orbifold::Geometry;
    use proptest::prelude::*;

    const GEOMETRIES: [Geometry; 3] = [
        Geometry::Spherical,
        Geometry::Euclidean,
        Geometry::Hyperbolic,
    ];

    /// A latitude–longitude sphere of product-metric radius `r` round the point `centre` at
    /// height `h`: points, heights, triangles (outward normals) and the exact unit normal of the
    /// geodesic sphere at a point.
    struct Ball {
        points: Vec<DVec3>,
        heights: Vec<f64>,
        triangles: Vec<[u32; 3]>,
        centre: DVec3,
        h: f64,
    }

    fn ball(space: Space, centre: DVec3, h: f64, r: f64, around: u32, rows: u32) -> Ball {
        let frame = [
            space.transport(DVec3::Z, centre, DVec3::X),
            space.transport(DVec3::Z, centre, DVec3::Y),
        ];
        let mut points = vec![centre];
        let mut heights = vec![h + r];
        for row in 1..rows {
            let polar = std::f64::consts::PI * f64::from(row) / f64::from(rows);
            for k in 0..around {
                let azimuth = std::f64::consts::TAU * f64::from(k) / f64::from(around);
                let v = (frame[0] * azimuth.cos() + frame[1] * azimuth.sin()) * (r * polar.sin());
                points.push(space.exp(centre, v));
                heights.push(h + r * polar.cos());
            }
        }
        points.push(centre);
        heights.push(h - r);
        let ring = |row: u32, k: u32| 1 + (row - 1) * around + k % around;
        let bottom = points.len() as u32 - 1;
        let mut triangles = Vec::new();
        for k in 0..around {
            triangles.push([0, ring(1, k), ring(1, k + 1)]);
            for row in 1..rows - 1 {
                let (a, b) = (ring(row, k), ring(row, k + 1));
                let (c, d) = (ring(row + 1, k), ring(row + 1, k + 1));
                triangles.push([a, c, d]);
                triangles.push([a, d, b]);
            }
            triangles.push([ring(rows - 1, k), bottom, ring(rows - 1, k + 1)]);
        }
        Ball {
            points,
            heights,
            triangles,
            centre,
            h,
        }
    }

    impl Ball {
        /// The exact outward unit normal of the geodesic sphere at (x, h): minus the product
        /// log towards the centre, normalised.
        fn true_normal(&self, space: Space, x: DVec3, h: f64) -> Tangent {
            let v = (-space.log(x, self.centre), h - self.h);
            normalized(space, v).unwrap()
        }

        fn vertices(&self, t: usize) -> [DVec3; 3] {
            self.triangles[t].map(|i| self.points[i as usize])
        }

        fn face(&self, t: usize) -> Triangle {
            triangle_of(&self.points, &self.heights, &self.triangles[t])
        }
    }

    fn angle(space: Space, a: Tangent, b: Tangent) -> f64 {
        product_dot(space, a, b).clamp(-1.0, 1.0).acos()
    }

    proptest! {
        /// On a finely cut ball in each geometry the smooth normals are close to the exact
        /// normals of the geodesic sphere, much closer than the faces' own normals, and two
        /// faces that share an edge agree along it (up to rounding).
        #[test]
        fn smooth_normals_follow_a_ball_and_agree_across_edges(
            g in 0usize..3,
            at in (-0.6f64..0.6, -0.6f64..0.6),
            picks in prop::collection::vec((0usize..10_000, 0.0f64..1.0, 0.0f64..1.0), 20),
        ) {
            let space = Space::new(GEOMETRIES[g]);
            let centre = space.to_ambient(num_complex::Complex64::new(at.0, at.1));
            let ball = ball(space, centre, 0.5, 0.25, 32, 16);
            let smooth = VertexNormals::new(
                space, &ball.points, &ball.heights, &ball.triangles, 60f64.to_radians(),
            );
            prop_assert_eq!(smooth.smooth_faces(), ball.triangles.len());
            let (mut smooth_error, mut flat_error) = (0.0, 0.0);
            for &(t, a, b) in &picks {
                let t = t % ball.triangles.len();
                let (a, b) = if a + b > 1.0 { (1.0 - a, 1.0 - b) } else { (a, b) };
                let w = [1.0 - a - b, a, b];
                let face = ball.face(t);
                let (x, h) = face.point(space, w);
                let exact = ball.true_normal(space, x, h);
                let shaded = smooth.at(space, t as u32, ball.vertices(t), w).unwrap();
                let own = face.normal(space, w).unwrap();
                // A tangent vector at the shaded point (what transport is for).
                if space.kappa() != 0.0 {
                    prop_assert!(space.point_dot(x, shaded.0).abs() < 1e-12);
                }
                smooth_error += angle(space, shaded, exact);
                flat_error += angle(space, own, exact);
                prop_assert!(angle(space, shaded, exact) < 0.03, "{}", angle(space, shaded, exact));
            }
            prop_assert!(smooth_error < 0.3 * flat_error, "{smooth_error} vs {flat_error}");
            // Every edge: the midpoint and a point a third of the way, from both faces.
            let mut edges = std::collections::HashMap::new();
            for (t, tri) in ball.triangles.iter().enumerate() {
                for i in 0..3 {
                    let (u, v) = (tri[i], tri[(i + 1) % 3]);
                    edges.entry((u.min(v), u.max(v))).or_insert_with(Vec::new).push(t);
                }
            }
            for ((u, v), faces) in edges {
                prop_assert_eq!(faces.len(), 2);
                for f in [0.5, 1.0 / 3.0] {
                    let normal = |t: usize| {
                        let tri = ball.triangles[t];
                        let w: [f64; 3] = std::array::from_fn(|i| match tri[i] {
                            i if i == u => f,
                            i if i == v => 1.0 - f,
                            _ => 0.0,
                        });
                        smooth.at(space, t as u32, ball.vertices(t), w).unwrap()
                    };
                    let (a, b) = (normal(faces[0]), normal(faces[1]));
                    // (Not the angle: acos loses half the digits near 1.)
                    let d = (a.0 - b.0, a.1 - b.1);
                    let gap = product_dot(space, d, d).max(0.0).sqrt();
                    prop_assert!(gap < 1e-10, "edge {u}-{v}: {gap}");
                }
            }
        }
    }

    /// A cube's faces meet at 90°: below that crease they stay flat, above it they are smooth,
    /// and a vertex normal is the corner-angle-weighted mean of its faces' normals.
    #[test]
    fn a_cube_stays_sharp_below_its_crease_and_rounds_above_it() {
        let e2 = Space::new(Geometry::Euclidean);
        let corner = |i: u32| {
            let (x, y) = (f64::from(i & 1) - 0.5, f64::from((i >> 1) & 1) - 0.5);
            (e2.exp(DVec3::Z, DVec3::new(x, y, 0.0)), f64::from(i >> 2))
        };
        let (points, heights): (Vec<DVec3>, Vec<f64>) = (0..8).map(corner).unzip();
        // Quads of corner bits, counter-clockwise seen from outside.
        let quads = [
            [0, 2, 3, 1],
            [4, 5, 7, 6],
            [0, 1, 5, 4],
            [2, 6, 7, 3],
            [0, 4, 6, 2],
            [1, 3, 7, 5],
        ];
        let triangles: Vec<[u32; 3]> = quads
            .iter()
            .flat_map(|q| [[q[0], q[1], q[2]], [q[0], q[2], q[3]]])
            .collect();
        let sharp = VertexNormals::new(e2, &points, &heights, &triangles, 60f64.to_radians());
        // Each face's two triangles are coplanar and do smooth into one another, exactly flat.
        for (t, triangle) in triangles.iter().enumerate() {
            let vertices = triangle.map(|i| points[i as usize]);
            let face = triangle_of(&points, &heights, triangle);
            let own = face.normal(e2, [0.2, 0.3, 0.5]).unwrap();
            let shaded = sharp.at(e2, t as u32, vertices, [0.2, 0.3, 0.5]);
            let gap = |n: Tangent| (n.0 - own.0).length() + (n.1 - own.1).abs();
            assert!(shaded.is_none_or(|n| gap(n) < 1e-12), "{t}");
        }
        let round = VertexNormals::new(e2, &points, &heights, &triangles, 100f64.to_radians());
        assert_eq!(round.smooth_faces(), 12);
        // At corner 0 the three faces meet, each with angle 90° there (the split diagonal
        // halves one corner of two of them, but the halves add up): the normal points out
        // along the cube's diagonal.
        let t = triangles.iter().position(|t| t[0] == 0).unwrap();
        let vertices = triangles[t].map(|i| points[i as usize]);
        let (n, up) = round.at(e2, t as u32, vertices, [1.0, 0.0, 0.0]).unwrap();
        let diagonal = DVec3::new(-1.0, -1.0, -1.0).normalize();
        assert!((n.x - diagonal.x).abs() < 1e-12 && (n.y - diagonal.y).abs() < 1e-12);
        assert!((up - diagonal.z).abs() < 1e-12);
    }
}
