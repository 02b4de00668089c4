//! Intrinsically flat triangles of S²×ℝ, E²×ℝ and H²×ℝ and their intersection with geodesic rays,
//! written once for every curvature (ARCHITECTURE.md §7, §8).
//!
//! A triangle with ambient vertices p₀, p₁, p₂ and heights h₀, h₁, h₂ is the set of points
//! (normalise_κ(Σ wᵢ pᵢ), Σ wᵢ hᵢ) for barycentric w ≥ 0, Σ w = 1; for κ = 0 it is an ordinary
//! flat triangle. With M = [p₀ p₁ p₂] and eᵢ the rows of M⁻¹, a horizontal point x lies over the
//! triangle iff every qᵢ = eᵢ·x ≥ 0, and then w = q / Σ q.
//!
//! **Intersection.** With n_i = p_j × p_k (i, j, k cyclic; det M times the rows of M⁻¹), the
//! function G(s) = Σ (h(s) − hᵢ)(nᵢ·x(σ)) = h(s)·Q(σ) − H(σ), σ = s cos α, vanishes exactly where
//! the ray meets the triangle's surface continued beyond its edges (for a vertical triangle, its
//! vertical plane). It is a combination of C, S, s·C and s·S, and is solved in s (not σ, so that
//! near-vertical rays are fine) by a bracketed, safeguarded Newton iteration with an analytic
//! derivative, on the arc lengths where the ray is inside the triangle's height interval and
//! over its footprint, cut into pieces of horizontal length ≤ 1/4. On E² and H² the span over the
//! footprint is exact (each edge form is a + b·T along the ray, T = S(σ)/C(σ), so three linear
//! inequalities in T and one artanh each end; widened by 10⁻⁹ beyond the edges); on S² and for
//! vertical triangles and rays it is the span inside the bounding disc (a closed form, as for the
//! BVH). The exact span spares Newton searches: the disc's span often holds a root of G on the
//! triangle's surface continued beyond its edges.
//! First, a ray whose horizontal geodesic passes beside the footprint is rejected by three dot
//! products: the geodesic is the model surface cut by the plane through the origin spanned by
//! the ray's p and u, and the footprint lies in the cone of its vertices, so vertices all on one
//! side of that plane (by a margin far above the edge slack below) cannot be met. A piece
//! without a sign change of G is still searched when |G| falls at its start and rises at its end
//! (a ray that crosses the curved surface twice).
//!
//! At a root the point is tested for being on the triangle by its barycentric coordinates, from
//! the 4×4 system Σ wᵢ(pᵢ, hᵢ − h) = λ(x, 0) (see `inside`), which works for steep and exactly
//! vertical triangles too (where footprint barycentrics are 0/0). Each wᵢ depends on its edge only
//! through a cross product of the edge's two lifted vertices, which the neighbouring triangle
//! computes exactly negated, and wᵢ ≥ −ε is accepted with ε = `FOOTPRINT_EPSILON` relative to the
//! edge's scale: rays through a shared edge or vertex hit at least one of the triangles
//! (watertightness). When a root is not on the triangle the search goes on after it.
//!
//! A ray that touches the surface without crossing it, or (rarely) crosses it three times within
//! one piece, may be reported as a miss or at its later crossing.

use std::f64::consts::{PI, TAU};

use glam::DVec3;
use orbifold::space::Space;

use crate::fastmath::{LN_FAST_ERROR, atan2_fast, ln_fast};
use crate::geodesic::Ray;
use crate::ray_frame::{Disc, RayFrame, disc_around};

/// Barycentric slack at a hit, relative to the edge's scale: neighbouring triangles overlap by
/// this much, so that no ray slips between them.
pub const FOOTPRINT_EPSILON: f64 = 1e-12;
/// Relative widening of the height interval a triangle spans (so that level triangles have a
/// height slab of nonzero thickness to bracket in).
const HEIGHT_EPSILON: f64 = 1e-12;
/// Newton stops when a step is below this times 1 + |s|.
const NEWTON_TOLERANCE: f64 = 1e-13;
/// Newton gives up refining after this many iterations (the bracket still holds the root).
const NEWTON_ITERATIONS: usize = 48;
/// The longest horizontal distance over which G is searched for roots in one piece.
const PIECE: f64 = 0.25;
/// On the sphere, the most turns a ray is followed over one triangle: rays that wind round the
/// sphere more often than this before reaching a triangle are not followed to it. (A level ray is
/// followed over one turn, which is exact.)
const MAX_TURNS: usize = 1024;

/// An intrinsically flat triangle: ambient vertices and heights.
///
/// ```
/// use orbifold::{Geometry, space::Space};
/// use orbifold_trace::geodesic::Ray;
/// use orbifold_trace::triangle::Triangle;
/// use glam::DVec3;
/// let h2 = Space::new(Geometry::Hyperbolic);
/// let tri = Triangle::new(
///     [h2.exp(DVec3::Z, DVec3::new(1.0, -1.0, 0.0)), h2.exp(DVec3::Z, DVec3::new(1.0, 1.0, 0.0)),
///      h2.exp(DVec3::Z, DVec3::new(1.0, 0.0, 0.0))],
///     [0.0, 0.0, 2.0],
/// );
/// // A ray from the origin at height 0.5 heading along +x meets it.
/// let ray = Ray::new(h2, DVec3::Z, DVec3::X, 0.5, 0.0);
/// let hit = tri.intersect(h2, &ray, 0.0, 10.0).unwrap();
/// let (x, h) = tri.point(h2, hit.barycentric);
/// let (y, k) = ray.point_at(h2, hit.s);
/// assert!((x - y).length() < 1e-12 && (h - k).abs() < 1e-12);
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Triangle {
    /// Ambient coordinates of the vertices' horizontal positions.
    pub points: [DVec3; 3],
    /// Heights of the vertices.
    pub heights: [f64; 3],
}

/// Where a ray crosses a single triangle: arc length along the ray and barycentric coordinates.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Crossing {
    /// Arc length along the ray.
    pub s: f64,
    /// Barycentric coordinates w of the hit (Σ w = 1; each ≥ −ε with ε ~ `FOOTPRINT_EPSILON`).
    pub barycentric: [f64; 3],
}

/// A ray's hit on a triangle of a mesh (a [`crate::accel::Bvh`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TriangleHit {
    /// Arc length along the ray.
    pub s: f64,
    /// Index of the triangle in the mesh's triangle list.
    pub triangle: u32,
    /// Barycentric coordinates w of the hit (Σ w = 1).
    pub barycentric: [f64; 3],
}

impl Triangle {
    /// The triangle with these ambient vertices and heights.
    pub fn new(points: [DVec3; 3], heights: [f64; 3]) -> Triangle {
        Triangle { points, heights }
    }

    /// The point (ambient horizontal position, height) with barycentric coordinates `w`:
    /// (normalise_κ(Σ wᵢ pᵢ), Σ wᵢ hᵢ).
    pub fn point(&self, space: Space, w: [f64; 3]) -> (DVec3, f64) {
        let p = self.points[0] * w[0] + self.points[1] * w[1] + self.points[2] * w[2];
        let h = self.heights[0] * w[0] + self.heights[1] * w[1] + self.heights[2] * w[2];
        (space.normalize_point(p), h)
    }

    /// The first crossing of the ray with the triangle at arc length in `[s_min, s_max]`
    /// (`s_min` finite), or `None`. See the module documentation.
    pub fn intersect(&self, space: Space, ray: &Ray, s_min: f64, s_max: f64) -> Option<Crossing> {
        PreparedTriangle::new(space, self.points, self.heights)?.intersect(space, ray, s_min, s_max)
    }

    /// The unit surface normal at the point with barycentric coordinates `w`, in the tangent space
    /// of the product at that point: (horizontal ambient tangent vector, vertical component), unit
    /// in the product metric ⟨·,·⟩_κ + dh². It is the right-handed normal of the vertex order: seen
    /// from the side it points to, p₀ → p₁ → p₂ runs counter-clockwise (as for a flat triangle
    /// in ℝ³ with "up" as the third axis and the model's orientation on the first two). `None` for
    /// a degenerate triangle.
    ///
    /// ```
    /// use orbifold::{Geometry, space::Space};
    /// use orbifold_trace::triangle::Triangle;
    /// use glam::DVec3;
    /// let s2 = Space::new(Geometry::Spherical);
    /// let p = |x: f64, y: f64| s2.exp(DVec3::Z, DVec3::new(x, y, 0.0));
    /// // A level triangle, counter-clockwise seen from above: the normal points up.
    /// let tri = Triangle::new([p(0.0, 0.0), p(0.1, 0.0), p(0.0, 0.1)], [1.0; 3]);
    /// let (n, up) = tri.normal(s2, [0.2, 0.3, 0.5]).unwrap();
    /// assert!(n.length() < 1e-12 && (up - 1.0).abs() < 1e-12);
    /// ```
    pub fn normal(&self, space: Space, w: [f64; 3]) -> Option<(DVec3, f64)> {
        let big_p = self.points[0] * w[0] + self.points[1] * w[1] + self.points[2] * w[2];
        let k = space.kappa();
        // ρ with x = P/ρ on the surface; dN[v] = (v − x·(κ⟨x, v⟩ or v₃))/ρ, the tangent part of v.
        let rho = if k == 0.0 {
            big_p.z
        } else {
            (k * space.point_dot(big_p, big_p)).sqrt()
        };
        if rho.is_nan() || rho <= 0.0 {
            return None;
        }
        let x = big_p / rho;
        let tangent = |v: DVec3| {
            let along = if k == 0.0 {
                v.z
            } else {
                k * space.point_dot(x, v)
            };
            (v - x * along) / rho
        };
        let a = tangent(self.points[1] - self.points[0]);
        let alpha = self.heights[1] - self.heights[0];
        let b = tangent(self.points[2] - self.points[0]);
        let beta = self.heights[2] - self.heights[0];
        // In an orthonormal frame (e, J e, up) the cross product of (a, α) and (b, β) is
        // (J(α b − β a), ⟨J a, b⟩).
        let horizontal = space.quarter_turn(x, b * alpha - a * beta);
        let vertical = space.point_dot(space.quarter_turn(x, a), b);
        let norm = (space.point_dot(horizontal, horizontal) + vertical * vertical).sqrt();
        (norm > 0.0 && norm.is_finite()).then(|| (horizontal / norm, vertical / norm))
    }
}

/// A triangle prepared for many ray tests: vertices, heights, edge forms and a bounding disc.
///
/// ```
/// use orbifold::{Geometry, space::Space};
/// use orbifold_trace::geodesic::Ray;
/// use orbifold_trace::triangle::PreparedTriangle;
/// use glam::DVec3;
/// let e2 = Space::new(Geometry::Euclidean);
/// // A vertical triangle: two vertices share their horizontal position.
/// let pts = [DVec3::new(1.0, -1.0, 1.0), DVec3::new(1.0, 1.0, 1.0), DVec3::new(1.0, -1.0, 1.0)];
/// let tri = PreparedTriangle::new(e2, pts, [0.0, 0.0, 2.0]).unwrap();
/// let ray = Ray::new(e2, DVec3::Z, DVec3::X, 0.5, 0.0);
/// assert!((tri.intersect(e2, &ray, 0.0, 10.0).unwrap().s - 1.0).abs() < 1e-15);
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PreparedTriangle {
    points: [DVec3; 3],
    heights: [f64; 3],
    /// pⱼ × pₖ for (i, j, k) cyclic: det M times the rows of M⁻¹.
    edges: [DVec3; 3],
    /// Bounding disc of the vertices: centre and V(r) (see [`crate::ray_frame`]).
    centre: DVec3,
    reach: f64,
    /// The largest Euclidean length of the ambient vertices (the scale of the side test).
    scale: f64,
    /// For E² and H², how far each edge form may go below 0 at a point within `FOOTPRINT_SLACK`
    /// of the footprint (the slack times the form's norm as a line of the plane); `None` on S²,
    /// and where the footprint's orientation is not certain (a vertical or nearly vertical
    /// triangle), which keep to the bounding disc.
    footprint_slack: Option<[f64; 3]>,
}

/// How far beyond its edges a triangle's footprint is searched for hits, as the bounding discs
/// are widened ([`disc_around`]): far above the slack that [`PreparedTriangle`]'s
/// inside test allows.
const FOOTPRINT_SLACK: f64 = 1e-9;

impl PreparedTriangle {
    /// Prepares a triangle; `None` when it is degenerate (its vertices, lifted to ℝ⁴ as
    /// (pᵢ, hᵢ), are affinely dependent: a segment or a point) or not finite.
    pub fn new(space: Space, points: [DVec3; 3], heights: [f64; 3]) -> Option<PreparedTriangle> {
        let [p0, p1, p2] = points;
        if !points.iter().all(|p| p.is_finite()) || !heights.iter().all(|h| h.is_finite()) {
            return None;
        }
        let edges = [p1.cross(p2), p2.cross(p0), p0.cross(p1)];
        // Degenerate iff the product-space edge vectors are parallel (zero area).
        let d1 = (p1 - p0, heights[1] - heights[0]);
        let d2 = (p2 - p0, heights[2] - heights[0]);
        let gram = |a: (DVec3, f64), b: (DVec3, f64)| a.0.dot(b.0) + a.1 * b.1;
        let (g11, g22, g12) = (gram(d1, d1), gram(d2, d2), gram(d1, d2));
        let area2 = g11 * g22 - g12 * g12;
        if area2.is_nan() || area2 <= 1e-24 * g11 * g22 {
            return None;
        }
        let (centre, reach) = disc_around(space, &points)?;
        let scale = points.iter().map(|p| p.length()).fold(0.0, f64::max);
        // det M = p₀·(p₁ × p₂), far from its rounding error, orients the footprint; its edge
        // forms are turned so that the footprint is where all three are ≥ 0.
        let det = p0.dot(edges[0]);
        let k = space.kappa();
        let oriented = k <= 0.0 && det.abs() > 1e-9 * p0.length() * p1.length() * p2.length();
        let edges = if oriented && det < 0.0 {
            edges.map(|e| -e)
        } else {
            edges
        };
        // A form n as a line of the plane: n·x = sinh(distance)·√(n_x² + n_y² + κ n_z²) on H²
        // (and the distance itself on E²), and sinh d ≥ d.
        let footprint_slack = oriented.then(|| {
            edges.map(|n| FOOTPRINT_SLACK * (n.x * n.x + n.y * n.y + k * n.z * n.z).max(0.0).sqrt())
        });
        Some(PreparedTriangle {
            points,
            heights,
            edges,
            centre,
            reach,
            scale,
            footprint_slack,
        })
    }

    /// The triangle it was prepared from (its vertices and heights, as given).
    pub fn triangle(&self) -> Triangle {
        Triangle::new(self.points, self.heights)
    }

    /// The first crossing of the ray with the triangle at arc length in `[s_min, s_max]`
    /// (`s_min` finite), or `None`. See the module documentation.
    pub fn intersect(&self, space: Space, ray: &Ray, s_min: f64, s_max: f64) -> Option<Crossing> {
        self.intersect_in(space, &RayFrame::new(space, ray), s_min, s_max)
    }

    /// [`PreparedTriangle::intersect`] with the ray's frame computed once by the caller.
    pub(crate) fn intersect_in(
        &self,
        space: Space,
        frame: &RayFrame,
        s_min: f64,
        s_max: f64,
    ) -> Option<Crossing> {
        let h_lo = self.heights[0].min(self.heights[1]).min(self.heights[2]);
        let h_hi = self.heights[0].max(self.heights[1]).max(self.heights[2]);
        let pad = HEIGHT_EPSILON * (1.0 + h_lo.abs().max(h_hi.abs()));
        let (lo, hi) = frame.slab(h_lo - pad, h_hi + pad, s_min, s_max)?;
        if !lo.is_finite() || frame.misses_hull(&self.points, self.scale) {
            return None;
        }
        let try_piece = |(x, y): Interval| -> Option<Crossing> {
            let (x, y) = (x.max(lo), y.min(hi));
            if x.is_nan() || x > y || !y.is_finite() {
                return None;
            }
            let inflection = self.inflection(space, frame);
            // G is examined on pieces of horizontal length at most `PIECE`, each cut where G''
            // changes sign near the surface, so that G has at most one extremum on each part
            // in practice (see `solve`).
            let pieces = (((y - x) * frame.ca() / PIECE).ceil() as usize).clamp(1, 256);
            let width = (y - x) / pieces as f64;
            for j in 0..pieces {
                let end = if j + 1 == pieces {
                    y
                } else {
                    x + width * (j + 1) as f64
                };
                let start = x + width * j as f64;
                let found = match inflection(start, end) {
                    Some(cut) => self
                        .search(space, frame, (start, cut))
                        .or_else(|| self.search(space, frame, (cut, end))),
                    None => self.search(space, frame, (start, end)),
                };
                if found.is_some() {
                    return found;
                }
            }
            None
        };
        if let Some(slack) = &self.footprint_slack
            && !frame.vertical()
        {
            let (a, b) = self.footprint_span(frame, slack)?;
            return try_piece((a * frame.inv_ca(), b * frame.inv_ca()));
        }
        match frame.disc(self.centre, self.reach) {
            Disc::Missed => None,
            Disc::Everywhere => {
                if frame.vertical() || space.kappa() <= 0.0 {
                    try_piece((lo, hi))
                } else {
                    // The whole great circle: one turn at a time.
                    let turn = TAU * frame.inv_ca();
                    let mut start = lo;
                    for _ in 0..MAX_TURNS {
                        if start > hi {
                            break;
                        }
                        if let Some(c) = try_piece((start, start + turn)) {
                            return Some(c);
                        }
                        if frame.level() {
                            break; // a level ray repeats itself
                        }
                        start += turn;
                    }
                    None
                }
            }
            Disc::Span(a, b) => {
                if space.kappa() <= 0.0 {
                    return try_piece((a * frame.inv_ca(), b * frame.inv_ca()));
                }
                // Periodic in σ with period 2π: the repetitions that meet [lo, hi].
                let (sigma_lo, sigma_hi) = (lo * frame.ca(), hi * frame.ca());
                let mut k = ((sigma_lo - b) / TAU).ceil();
                for _ in 0..MAX_TURNS {
                    let (x, y) = (a + k * TAU, b + k * TAU);
                    if x > sigma_hi {
                        break;
                    }
                    if let Some(c) = try_piece((x * frame.inv_ca(), y * frame.inv_ca())) {
                        return Some(c);
                    }
                    if frame.level() {
                        break;
                    }
                    k += 1.0;
                }
                None
            }
        }
    }

    /// Where (in σ) the horizontal geodesic of a ray that is not vertical is over the footprint
    /// widened by `FOOTPRINT_SLACK`, on E² and H²: with x(σ) = C p + S u and C > 0, each edge
    /// form is a + b T with T = S/C (σ on E², tanh σ on H²), so the span is an interval of T cut
    /// by three linear inequalities. Tighter than the bounding disc, so that fewer pieces of the
    /// ray are searched for roots of G that are not on the triangle.
    #[inline]
    fn footprint_span(&self, frame: &RayFrame, slack: &[f64; 3]) -> Option<(f64, f64)> {
        let (p, u) = (frame.origin(), frame.direction());
        let hyperbolic = frame.kappa() < 0.0;
        let (mut lo, mut hi) = if hyperbolic {
            (-1.0, 1.0)
        } else {
            (f64::NEG_INFINITY, f64::INFINITY)
        };
        for (n, slack) in self.edges.iter().zip(slack) {
            // a + b T ≥ −slack (C ≥ 1 on H², so this holds wherever (a + b T)·C ≥ −slack).
            let (a, b) = (n.dot(p) + slack, n.dot(u));
            let bound = -a / b;
            if b > 0.0 {
                lo = lo.max(bound);
            } else if b < 0.0 {
                hi = hi.min(bound);
            } else if a < 0.0 {
                return None;
            }
        }
        if lo > hi {
            return None;
        }
        if !hyperbolic {
            return Some((lo, hi));
        }
        let artanh = |t: f64| {
            if t <= -1.0 {
                f64::NEG_INFINITY
            } else if t >= 1.0 {
                f64::INFINITY
            } else {
                0.5 * ln_fast((1.0 + t) / (1.0 - t))
            }
        };
        // ln_fast's absolute error, and the rounding of (1 + T)/(1 − T).
        let pad = 2.0 * LN_FAST_ERROR;
        let (a, b) = (artanh(lo), artanh(hi));
        Some((a - pad - 1e-12 * a.abs(), b + pad + 1e-12 * b.abs()))
    }

    /// The first crossing in `piece`: roots of G one after another (the first may be a
    /// crossing of the triangle's surface continued beyond its edges; then look on after it).
    #[inline]
    fn search(
        &self,
        space: Space,
        frame: &RayFrame,
        (mut start, end): Interval,
    ) -> Option<Crossing> {
        for _ in 0..3 {
            let s = self.solve(space, frame, (start, end))?;
            if let Some(c) = self.inside(space, frame, s) {
                return Some(c);
            }
            start = s + 1e-9 * (1.0 + s.abs());
            if start >= end {
                break;
            }
        }
        None
    }

    /// Where in (a, b) a search should cut its piece: at the arc length where Q' = 0, if it is
    /// inside. Since G'' = 2 sin α cos α Q' − κ cos²α G (the functions C and S of σ satisfy
    /// f'' = −κ f), near the surface, where G is small, G'' changes sign only there; a ray that
    /// grazes the surface can cross it twice in one piece, with the same sign of G at both ends
    /// and an extremum on either side of the cut (seen in H² with crossings 0.25 apart and a
    /// cosine of 10⁻³ between the ray and the normal), which `solve` finds only on the two
    /// halves. Q' = −κ S qp + C qu vanishes at most once on H² (tanh σ = −qu/qp), every π on
    /// S² (tan σ = qu/qp) and nowhere on E².
    #[inline]
    fn inflection(&self, space: Space, frame: &RayFrame) -> impl Fn(f64, f64) -> Option<f64> {
        let (p, u, ca) = (frame.origin(), frame.direction(), frame.ca());
        let k = space.kappa();
        let qp: f64 = self.edges.iter().map(|e| e.dot(p)).sum();
        let qu: f64 = self.edges.iter().map(|e| e.dot(u)).sum();
        // σ of an inflection (on S², the first of a series with period π), if any.
        let sigma = if ca == 0.0 || frame.level() || k == 0.0 {
            None
        } else if k < 0.0 {
            // (Where the cut falls only needs to be near the inflection: fast functions.)
            let t = -qu / qp;
            (t.abs() < 1.0).then(|| 0.5 * ln_fast((1.0 + t) / (1.0 - t)))
        } else {
            Some(atan2_fast(qu, qp))
        };
        let inv_ca = frame.inv_ca();
        move |a: f64, b: f64| {
            let sigma = sigma?;
            let sigma = if k > 0.0 {
                // The first of σ + nπ after a.
                sigma + PI * ((a * ca - sigma) / PI).ceil()
            } else {
                sigma
            };
            let cut = sigma * inv_ca;
            (cut > a && cut < b).then_some(cut)
        }
    }

    /// The root of G(s) = (h(s) − h_ref)·Q(σ) − H(σ) on `piece`, if G changes sign there.
    #[inline]
    fn solve(&self, space: Space, frame: &RayFrame, piece: Interval) -> Option<f64> {
        let (p, u, ca, sa) = (frame.origin(), frame.direction(), frame.ca(), frame.sa());
        let k = space.kappa();
        let h_ref = self.heights[0];
        let a = self.edges.map(|e| e.dot(p));
        let b = self.edges.map(|e| e.dot(u));
        let (qp, qu) = (a[0] + a[1] + a[2], b[0] + b[1] + b[2]);
        let (dh1, dh2) = (self.heights[1] - h_ref, self.heights[2] - h_ref);
        let hp = a[1] * dh1 + a[2] * dh2;
        let hu = b[1] * dh1 + b[2] * dh2;
        let h0 = frame.height() - h_ref;
        let eval = |s: f64| -> (f64, f64) {
            let sigma = s * ca;
            let (c, sn) = space.cos_sin(sigma);
            let height = h0 + s * sa;
            let q = c * qp + sn * qu;
            let dq = -k * sn * qp + c * qu;
            let big_h = c * hp + sn * hu;
            let dbig_h = -k * sn * hp + c * hu;
            (height * q - big_h, sa * q + ca * (height * dq - dbig_h))
        };
        let (mut lo, mut hi) = piece;
        let (g_lo, d_lo) = eval(lo);
        if g_lo == 0.0 {
            return Some(lo);
        }
        let (mut g_hi, d_hi) = eval(hi);
        if g_hi == 0.0 {
            return Some(hi);
        }
        if !(g_lo.is_finite() && g_hi.is_finite()) {
            return None;
        }
        if (g_lo > 0.0) == (g_hi > 0.0) {
            // No sign change, but G may dip through zero and back (a ray crossing the curved
            // surface twice): if |G| decreases at lo and increases at hi, look for a point in
            // between with the other sign by bisection on G'.
            if !(d_lo * g_lo < 0.0 && d_hi * g_hi > 0.0) {
                return None;
            }
            let (mut a, mut b) = (lo, hi);
            let mut found = false;
            for _ in 0..60 {
                let m = 0.5 * (a + b);
                let (g, d) = eval(m);
                if (g > 0.0) != (g_lo > 0.0) || g == 0.0 {
                    hi = m;
                    g_hi = g;
                    found = true;
                    break;
                }
                if (d * g_lo < 0.0) == (d_lo * g_lo < 0.0) {
                    a = m;
                } else {
                    b = m;
                }
                if b - a <= NEWTON_TOLERANCE * (1.0 + a.abs()) {
                    break;
                }
            }
            if !found {
                return None;
            }
            if g_hi == 0.0 {
                return Some(hi);
            }
        }
        let lo_positive = g_lo > 0.0;
        // Start from the secant (regula falsi) point: the root itself when G is linear.
        let mut s = lo - g_lo * (hi - lo) / (g_hi - g_lo);
        if !(s >= lo && s <= hi) {
            s = 0.5 * (lo + hi);
        }
        for _ in 0..NEWTON_ITERATIONS {
            let (g, dg) = eval(s);
            if g == 0.0 {
                return Some(s);
            }
            if (g > 0.0) == lo_positive {
                lo = s;
            } else {
                hi = s;
            }
            let mut next = s - g / dg;
            if !(next > lo && next < hi) {
                next = 0.5 * (lo + hi);
            }
            let step = (next - s).abs();
            s = next;
            if step <= NEWTON_TOLERANCE * (1.0 + s.abs()) || hi - lo <= f64::EPSILON * s.abs() {
                break;
            }
        }
        Some(s)
    }

    /// The crossing at arc length `s` (a root of G) if its point is on the triangle.
    ///
    /// With Pᵢ = (pᵢ, hᵢ − h) and X = (x, 0) in ℝ⁴, the point is on the triangle iff
    /// Σ wᵢ Pᵢ = λX with w ≥ 0; at a root of G the 4×4 system [P₀ P₁ P₂ −X] is singular and w is
    /// proportional to wᵢ ∝ det[Pⱼ, Pₖ, X] over any three of its four rows. Dropping the height row
    /// gives the footprint's barycentrics (bad for steep triangles); we drop the row that makes
    /// Σ wᵢ largest. Each wᵢ depends on its opposite edge only through Pⱼ × Pₖ, which the
    /// neighbour across that edge computes exactly negated; accepting wᵢ ≥ −ε (ε relative to that
    /// edge's scale) makes the test watertight.
    #[inline]
    fn inside(&self, space: Space, frame: &RayFrame, s: f64) -> Option<Crossing> {
        let (x, h) = frame.point_at(space, s);
        let lifted = |p: DVec3, height: f64| [p.x, p.y, p.z, height - h];
        let big_p = [0, 1, 2].map(|i| lifted(self.points[i], self.heights[i]));
        let big_x = [x.x, x.y, x.z, 0.0];
        let drop = |v: &[f64; 4], r: usize| -> DVec3 {
            match r {
                0 => DVec3::new(v[1], v[2], v[3]),
                1 => DVec3::new(v[0], v[2], v[3]),
                2 => DVec3::new(v[0], v[1], v[3]),
                _ => DVec3::new(v[0], v[1], v[2]),
            }
        };
        let mut best: Option<([f64; 3], [f64; 3], f64)> = None;
        for r in 0..4 {
            let [a, b, c] = big_p.map(|v| drop(&v, r));
            let xr = drop(&big_x, r);
            let crosses = [b.cross(c), c.cross(a), a.cross(b)];
            let w = crosses.map(|n| n.dot(xr));
            let scale = crosses.map(|n| n.length() * xr.length());
            let total = w[0] + w[1] + w[2];
            if best.is_none_or(|(_, _, t)| total.abs() > t.abs()) {
                best = Some((w, scale, total));
            }
        }
        let (w, scale, total) = best?;
        if !(total != 0.0 && total.is_finite()) {
            return None;
        }
        let sign = total.signum();
        if (0..3).any(|i| w[i] * sign < -FOOTPRINT_EPSILON * scale[i]) {
            return None;
        }
        // On the sphere, x and −x have the same ray through the origin: require λ > 0, i.e. the
        // point to be on the same side as the triangle.
        let cone = self.points[0] * w[0] + self.points[1] * w[1] + self.points[2] * w[2];
        if space.kappa() > 0.0 && x.dot(cone) * total <= 0.0 {
            return None;
        }
        Some(Crossing {
            s,
            barycentric: w.map(|w| w / total),
        })
    }
}

/// A closed interval.
type Interval = (f64, f64);

#[cfg(test)]
mod tests {
    use super::*;
    use orbifold::Geometry;
    use proptest::prelude::*;

    /// A triangle of intrinsic size 10⁻³–1 near the origin, level, sloping or nearly vertical.
    fn triangle(space: Space, r: &mut impl FnMut() -> f64) -> Option<PreparedTriangle> {
        let size = 10f64.powf(-3.0 * r());
        let centre = DVec3::new(r() - 0.5, r() - 0.5, 0.0);
        let slope = [0.0, 1.0, 1e3][(3.0 * r()) as usize % 3];
        let mut offsets = [0, 1, 2].map(|_| DVec3::new(r() - 0.5, r() - 0.5, 0.0) * size);
        if slope > 1.0 {
            offsets[2] = offsets[1] + DVec3::new(1e-9 * size, 0.0, 0.0); // almost over vertex 1
        }
        let points = offsets.map(|v| space.exp(DVec3::Z, centre + v));
        let heights = [0, 1, 2].map(|i| 0.5 + slope * size * (r() - 0.5) + 0.1 * i as f64 * size);
        PreparedTriangle::new(space, points, heights)
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(64))]
        /// The search over the footprint's span finds what the search over the bounding disc
        /// finds, for rays aimed at the triangle's edges and just beside them: the same hit (to
        /// 10⁻¹⁰), but for rays that graze the surface, and only a hit within 10⁻¹⁰ of an edge
        /// found by one alone
        /// (there the root searches of the two intervals may stop a rounding apart, on either
        /// side of what the inside test accepts, `FOOTPRINT_EPSILON` relative to the edge
        /// forms' scale: about 10⁻¹²/size in barycentric coordinates; a hit at −1.7·10⁻¹⁰ on a
        /// triangle of size 0.06 was found by one only).
        #[test]
        fn the_footprint_span_finds_what_the_bounding_disc_finds(
            seed in any::<u64>(),
            hyperbolic in any::<bool>(),
        ) {
            let space = Space::new(if hyperbolic { Geometry::Hyperbolic } else { Geometry::Euclidean });
            let mut rng = rand_pcg::Pcg64Mcg::new(u128::from(seed) << 1 | 1);
            // 53 random bits as a number in [0, 1).
            let mut r = move || (rand::Rng::next_u64(&mut rng) >> 11) as f64 / (1u64 << 53) as f64;
            let mut checked = 0;
            for _ in 0..200 {
                let Some(tri) = triangle(space, &mut r) else { continue };
                let mut by_disc = tri;
                by_disc.footprint_slack = None;
                // A target on an edge (w = 0), just inside or outside it, or anywhere.
                let mut w = [r(), r(), r()];
                let edge = (3.0 * r()) as usize % 3;
                w[edge] = [0.0, 1e-12, -1e-12, 1e-6, -1e-6, r() - 0.2][(6.0 * r()) as usize % 6];
                let total: f64 = w.iter().sum();
                let w = w.map(|x| x / total);
                let triangle = Triangle::new(tri.points, tri.heights);
                let (target, target_h) = triangle.point(space, w);
                let origin = space.exp(DVec3::Z, DVec3::new(r() - 0.5, r() - 0.5, 0.0) * 2.0);
                let log = space.log(origin, target);
                let d = space.point_dot(log, log).sqrt();
                if d < 1e-6 {
                    continue;
                }
                let h = 2.0 * r() - 0.5;
                let ray = Ray::new(space, origin, log, h, (target_h - h).atan2(d));
                let (a, b) = (tri.intersect(space, &ray, 0.0, 10.0), by_disc.intersect(space, &ray, 0.0, 10.0));
                // Within 10⁻¹⁰ of an edge, in barycentric coordinates times the triangle's size
                // (about the distance; the inside test accepts 10⁻¹² relative to the edge
                // forms, a barycentric 4.5·10⁻⁹ outside on the smallest triangles here).
                let size = (0..3)
                    .map(|i| (tri.points[i] - tri.points[(i + 1) % 3]).length())
                    .fold(0.0, f64::max);
                let near_edge = |c: &Crossing| c.barycentric.iter().any(|&x| x.abs() * size < 1e-10);
                // A crossing of the ray and the triangle.
                let genuine = |c: &Crossing| {
                    let (x, h) = ray.point_at(space, c.s);
                    let (y, k) = triangle.point(space, c.barycentric);
                    (x - y).length() < 1e-9 && (h - k).abs() < 1e-9
                };
                // The cosine between the ray and the surface's normal there is below 10⁻⁵. Such
                // a ray can cross the (curved) surface twice within one piece of a search: G has
                // the same sign at both ends and two extrema, and the search misses the pair
                // (seen at G ~ 10⁻⁷, crossings 0.25 apart), or its Newton steps end on the
                // second. Either search may then find a crossing the other does not.
                let grazing = |c: &Crossing| {
                    let Some((n, n_up)) = triangle.normal(space, c.barycentric) else {
                        return true;
                    };
                    let t = ray.tangent_at(space, c.s * ray.cos_elevation);
                    let cos = space.point_dot(n, t) * ray.cos_elevation + n_up * ray.sin_elevation;
                    cos.abs() < 1e-5
                };
                match (a, b) {
                    // Newton's method stops within 10⁻¹³ of a crossing, from a start in another
                    // interval, and a grazing ray's crossing is ill-conditioned (2.3·10⁻¹²
                    // apart seen).
                    // Else the ray crosses the triangle twice, and the earlier crossing, which
                    // one search missed, is at an edge or grazing.
                    (Some(a), Some(b)) => {
                        let first = if a.s < b.s { &a } else { &b };
                        prop_assert!(
                            (a.s - b.s).abs() <= 1e-10 * (1.0 + b.s)
                                || (genuine(&a) && genuine(&b) && (near_edge(first) || grazing(first))),
                            "{a:?} {b:?}"
                        );
                    }
                    (None, None) => {}
                    (None, Some(c)) => prop_assert!(near_edge(&c) || grazing(&c), "{c:?} by the disc's search only"),
                    (Some(c), None) => prop_assert!(genuine(&c) && (near_edge(&c) || grazing(&c)), "{c:?} by the span's search only"),
                }
                checked += 1;
            }
            prop_assert!(checked > 100);
        }
    }
}
