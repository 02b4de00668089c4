//! The mesh's gnomonic chart (ARCHITECTURE.md §8): where the BVH's boxes are taken, and where a
//! ray's horizontal geodesic is a straight line.
//!
//! The chart ([`Chart`]) about the mesh's centre c sends a point x to
//! (⟨x − c, e₁⟩, ⟨x − c, e₂⟩)/C(d(x, c)): the Beltrami–Klein model on H², the gnomonic
//! projection of the hemisphere about c on S², the plane itself on E². In all three it takes
//! geodesics to straight lines, so a triangle's footprint is the straight triangle of its
//! vertices' chart points, a node's box is the box of its vertices' chart points (exact, padded
//! by 10⁻⁹ and rounded outwards to f32), and a ray's horizontal geodesic crosses a box on one
//! interval of a straight line. The boxes live in the mesh's own frame, so a mesh's BVH never
//! changes when the mesh is moved (see `super::instance`).
//!
//! **Ray–box test.** A ray is taken once per traversal from the foot of the perpendicular from
//! c to its geodesic ([`ChartRay`]): there its chart point is affine in T = S(σ')/C(σ') (tan σ',
//! σ', tanh σ' of the horizontal distance σ' from the foot), so each of a box's two slabs is
//! an interval of T found by one multiply-add per side — no square root, division or
//! logarithm. A point of the geodesic within the mesh's radius R of c is within R of the foot,
//! so T is clamped to |T| ≤ T(R); there T⁻¹ is bounded from below at the interval's start and
//! from above at its end by odd polynomials (artanh T between T + T³/3 and that plus
//! T⁵/(5(1 − T(R)²)); arctan T between T − T³/3 and that plus T⁵/5; σ' = T on E²), which widen
//! the interval by at most K·T(R)⁵ (about 5·10⁻⁴ where T(R) = 0.3). The σ-interval is then cut
//! by the height slab and the ray's current [s_min, s_best]; on S² its first repetition
//! (period 2π) after s_min is taken. The test runs in f32 lanes, eight children at once
//! (`super::chart_lanes`).
//!
//! A mesh too wide for a chart — a vertex more than about 84° from the centre on S², where the
//! gnomonic picture ends at the hemisphere's edge, or 3.8 on H², where the bound on artanh grows
//! without limit — has none, and its nodes are tested by their discs (`super::disc_lanes`).

use glam::DVec3;
use orbifold::space::Space;

use crate::fastmath::{ATAN_FAST_ERROR, LN_FAST_ERROR, atan2_fast, ln_fast};
use crate::ray_frame::RayFrame;

/// The mesh's gnomonic chart: centre c, an orthonormal tangent frame (e₁, e₂) there along the
/// principal axes of the vertices' chart points (so that the boxes of an object turned askew
/// are as tight as those of one lying along the frame), and
/// g(x) = (⟨x − c, e₁⟩, ⟨x − c, e₂⟩)/C(d(x, c)), with C(d) = 1 − κ·½|x − c|²_κ (cos, 1, cosh).
/// It takes geodesics to straight lines in all three geometries (the Beltrami–Klein model on
/// H², the gnomonic projection of the open hemisphere about c on S², the identity on E²), so a
/// node's footprint box in it is met by a ray's horizontal geodesic on an interval of a
/// straight line, which a slab test finds with no square root, division or logarithm.
///
/// A ray is taken from the foot of the perpendicular from c to its geodesic
/// ([`ChartRay`]): there the chart point is affine in T = S(σ')/C(σ') (tan, identity, tanh of
/// the horizontal distance σ' from the foot), and T⁻¹ is bounded from both sides by short
/// odd polynomials on |T| ≤ T(R), R the radius about c that holds every vertex (a point of
/// the geodesic within R of c is within R of the foot).
#[derive(Clone, Copy, Debug)]
pub(super) struct Chart {
    kappa: f64,
    centre: DVec3,
    frame: [DVec3; 2],
    /// T(R), widened.
    t_max: f64,
    /// The coefficient K of the bound T + T³/3 + K·T⁵ (H²: 1/(5(1 − T(R)²)); S²: 1/5 for
    /// T − T³/3 + T⁵/5; E²: 0, where σ' = T).
    quintic: f64,
}

impl Chart {
    /// The chart about `centre` for a mesh with these vertices; `None` when a vertex is too far
    /// from the centre for the chart (on S², more than about 84° away; on H², 3.8).
    pub(super) fn new(
        space: Space,
        centre: DVec3,
        vertices: impl IntoIterator<Item = DVec3>,
    ) -> Option<Chart> {
        let kappa = space.kappa();
        let mut chart = Chart {
            kappa,
            centre,
            frame: space.tangent_frame(centre),
            t_max: 0.0,
            quintic: 0.0,
        };
        let mut t_max = 0.0f64;
        // The chart points' second moments, for the principal axes.
        let (mut n, mut sum, mut moments) = (0.0, [0.0; 2], [0.0; 3]);
        for v in vertices {
            let [x, y] = chart.coords(v)?;
            t_max = t_max.max(x.hypot(y));
            n += 1.0;
            sum = [sum[0] + x, sum[1] + y];
            moments = [moments[0] + x * x, moments[1] + x * y, moments[2] + y * y];
        }
        // Turn the frame onto the principal axes of the vertices' chart points: every node's
        // box is taken along the frame's axes, and a long mesh lying askew would have boxes
        // wider than its nodes (the root's most of all).
        if n > 0.0 {
            let (mx, my) = (sum[0] / n, sum[1] / n);
            let sxx = moments[0] / n - mx * mx;
            let sxy = moments[1] / n - mx * my;
            let syy = moments[2] / n - my * my;
            let angle = 0.5 * (2.0 * sxy).atan2(sxx - syy);
            if angle.is_finite() {
                let (sin, cos) = angle.sin_cos();
                let [e1, e2] = chart.frame;
                chart.frame = [e1 * cos + e2 * sin, e2 * cos - e1 * sin];
            }
        }
        let t_max = t_max * (1.0 + 1e-9) + 1e-12;
        if !t_max.is_finite() || (kappa > 0.0 && t_max > 10.0) || (kappa < 0.0 && t_max > 0.999) {
            return None;
        }
        chart.t_max = t_max;
        chart.quintic = if kappa < 0.0 {
            1.0 / (5.0 * (1.0 - t_max * t_max))
        } else if kappa > 0.0 {
            0.2
        } else {
            0.0
        };
        Some(chart)
    }

    #[inline(always)]
    fn dot(&self, a: DVec3, b: DVec3) -> f64 {
        a.x * b.x + a.y * b.y + self.kappa * a.z * b.z
    }

    /// The chart point of x; `None` on the far hemisphere of S² (and its edge).
    pub(super) fn coords(&self, x: DVec3) -> Option<[f64; 2]> {
        let d = x - self.centre;
        let denom = 1.0 - 0.5 * self.kappa * self.dot(d, d);
        let g = [
            self.dot(d, self.frame[0]) / denom,
            self.dot(d, self.frame[1]) / denom,
        ];
        (denom > 0.0 && g[0].is_finite() && g[1].is_finite()).then_some(g)
    }
}

/// How far a [`ChartRay`]'s foot may be off: `ln_fast`'s error on H² (halved, and the rounding
/// of its argument), `atan2_fast`'s on S².
pub(super) const FOOT_ERROR: f64 = 2.0
    * if LN_FAST_ERROR > ATAN_FAST_ERROR {
        LN_FAST_ERROR
    } else {
        ATAN_FAST_ERROR
    };

/// A ray seen in a [`Chart`], from the foot of the perpendicular from its centre: the chart
/// point at T = S(σ')/C(σ') is (a + b·T)/C(d⊥) on each axis, so the T at which axis i reads v
/// is v·`scale[i]` − `shift[i]`.
#[derive(Clone, Copy, Debug)]
pub(super) struct ChartRay {
    /// σ of the foot (from the ray's origin).
    pub(super) foot: f64,
    pub(super) scale: [f64; 2],
    pub(super) shift: [f64; 2],
    /// How far T may be off on each axis (rounding, grown with the distance to the foot).
    pub(super) pad: [f64; 2],
    /// Axes along which the line barely moves: not used to cull.
    pub(super) free: [bool; 2],
    /// T(R), and the bounds T + cubic·T³ (+ quintic·T⁵) on T⁻¹, from the [`Chart`].
    pub(super) t_max: f64,
    pub(super) cubic: f64,
    pub(super) quintic: f64,
}

impl ChartRay {
    /// `None` for a vertical ray (a point of the chart) or a great circle that misses the
    /// chart's hemisphere.
    #[inline(always)]
    pub(super) fn new(chart: &Chart, frame: &RayFrame) -> Option<ChartRay> {
        if frame.vertical {
            return None;
        }
        let k = chart.kappa;
        let (p, u, c) = (frame.p, frame.u, chart.centre);
        let d = p - c;
        let alpha = 1.0 - 0.5 * k * chart.dot(d, d);
        let beta = k * chart.dot(u, c);
        let a0 = (alpha * alpha + k * beta * beta).sqrt();
        if !(a0 > 0.0 && a0.is_finite()) {
            return None;
        }
        // The foot, from the fast functions: their errors widen the lanes' intervals.
        let (cf, sf, foot) = if k == 0.0 {
            // x(σ) = p + σu: the foot is at ⟨c − p, u⟩.
            let foot = chart.dot(c - p, u);
            (1.0, foot, foot)
        } else if k < 0.0 {
            // artanh(−β/α) = ½ ln((α − β)/(α + β)), with α > |β| but for rounding (where it
            // fails, far from the chart, the discs are tested instead).
            let ratio = (alpha - beta) / (alpha + beta);
            if !(ratio > f64::MIN_POSITIVE && ratio < f64::MAX) {
                return None;
            }
            let foot = 0.5 * ln_fast(ratio);
            (alpha / a0, -beta / a0, foot)
        } else {
            (alpha / a0, beta / a0, atan2_fast(beta, alpha))
        };
        let p0 = p * cf + u * sf;
        let u0 = u * cf - p * (k * sf);
        let error = 1e-15 * (cf.abs() * p.length() + sf.abs() * u.length() + c.length() + 1.0);
        let mut ray = ChartRay {
            foot,
            scale: [0.0; 2],
            shift: [0.0; 2],
            pad: [0.0; 2],
            free: [true; 2],
            t_max: chart.t_max,
            cubic: -k / 3.0,
            quintic: chart.quintic,
        };
        for i in 0..2 {
            let a = chart.dot(p0 - c, chart.frame[i]);
            let b = chart.dot(u0, chart.frame[i]);
            if b.abs() > 1e-9 {
                ray.free[i] = false;
                ray.scale[i] = a0 / b;
                ray.shift[i] = a / b;
                ray.pad[i] = error * (1.0 + chart.t_max + a.abs() + a0) / b.abs();
            }
        }
        foot.is_finite().then_some(ray)
    }
}

#[cfg(test)]
mod tests {
    use orbifold::Geometry;

    use super::*;
    use crate::accel::Bvh;
    use crate::geodesic::Ray;
    use crate::test_util::uniforms;

    /// The chart takes geodesics to straight lines: three points of one geodesic have chart
    /// points on one line, in all three geometries.
    #[test]
    fn the_chart_takes_geodesics_to_straight_lines() {
        for g in [
            Geometry::Spherical,
            Geometry::Euclidean,
            Geometry::Hyperbolic,
        ] {
            let space = Space::new(g);
            let mut rnd = uniforms(2024);
            for _ in 0..2000 {
                let centre = space.exp(DVec3::Z, DVec3::new(rnd() - 0.5, rnd() - 0.5, 0.0));
                let chart = Chart::new(space, centre, [centre]).unwrap();
                let origin = space.exp(centre, space.tangent_frame(centre)[0] * (rnd() - 0.5));
                let ray = Ray::new(
                    space,
                    origin,
                    DVec3::new(rnd() - 0.5, rnd() - 0.5, 0.0),
                    0.0,
                    0.0,
                );
                let at = |s: f64| chart.coords(ray.point_at(space, s).0).unwrap();
                let [a, b, c] = [at(-0.6 * rnd()), at(0.0), at(0.6 * rnd())];
                let cross = (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
                assert!(
                    cross.abs() < 1e-12,
                    "{g:?}: chart points off a line by {cross}"
                );
            }
        }
    }

    /// The chart's axes follow the mesh: a long thin strip of triangles lying at 30° to the
    /// tangent frame gets a root box about as large as the strip itself (a box along the
    /// frame's own axes would be about 0.5 × 1 × 0.5 × 1 = 0.25 square units).
    #[test]
    fn the_chart_axes_follow_a_long_mesh() {
        for g in [
            Geometry::Spherical,
            Geometry::Euclidean,
            Geometry::Hyperbolic,
        ] {
            let space = Space::new(g);
            let [e1, e2] = space.tangent_frame(DVec3::Z);
            let (along, across) = (e1 * 0.866 + e2 * 0.5, e2 * 0.866 - e1 * 0.5);
            let (mut points, mut heights, mut triangles) = (Vec::new(), Vec::new(), Vec::new());
            for i in 0..40u32 {
                let t = f64::from(i) / 39.0 - 0.5;
                for (a, b) in [(t, -0.01), (t + 0.01, 0.01), (t, 0.01)] {
                    points.push(space.exp(DVec3::Z, along * a + across * b));
                    heights.push(0.5);
                }
                triangles.push([3 * i, 3 * i + 1, 3 * i + 2]);
            }
            let bvh = Bvh::build(space, &points, &heights, &triangles);
            let root = bvh.root.unwrap();
            let area =
                (root.chart_hi[0] - root.chart_lo[0]) * (root.chart_hi[1] - root.chart_lo[1]);
            assert!(
                area < 0.03,
                "{g:?}: root box {:?} – {:?}",
                root.chart_lo,
                root.chart_hi
            );
        }
    }

    /// The odd polynomials bound T⁻¹ from both sides on |T| ≤ T(R): artanh on H², arctan on
    /// S², the identity on E².
    #[test]
    fn the_bounds_on_the_inverse_hold() {
        for (kappa, r) in [(-1.0, 0.3), (-1.0, 2.0), (1.0, 0.3), (1.0, 1.4), (0.0, 5.0)] {
            let space = Space::new(if kappa < 0.0 {
                Geometry::Hyperbolic
            } else if kappa > 0.0 {
                Geometry::Spherical
            } else {
                Geometry::Euclidean
            });
            let far = space.exp(DVec3::Z, DVec3::new(r, 0.0, 0.0));
            let chart = Chart::new(space, DVec3::Z, [DVec3::Z, far]).unwrap();
            let cubic = -kappa / 3.0;
            for i in -1000..=1000 {
                let t = chart.t_max * f64::from(i) / 1000.0;
                let exact = if kappa < 0.0 {
                    t.atanh()
                } else if kappa > 0.0 {
                    t.atan()
                } else {
                    t
                };
                let odd = t * (1.0 + cubic * t * t);
                let fifth = chart.quintic * t.powi(5);
                let (below, above) = (odd + fifth.min(0.0), odd + fifth.max(0.0));
                assert!(
                    below <= exact + 1e-15 && exact <= above + 1e-15,
                    "κ = {kappa}, T = {t}: {below} ≤ {exact} ≤ {above} fails"
                );
            }
        }
    }
}
