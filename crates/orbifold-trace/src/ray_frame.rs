//! The per-ray frame and the disc test (ARCHITECTURE.md §8): what every bound and triangle
//! test reads of a ray, computed once a ray ([`RayFrame`]), and where the ray's horizontal
//! geodesic is inside a geodesic disc ([`RayFrame::disc`], [`Disc`]). The BVH's nodes, the
//! instances' world bounds and the triangles all bound what they hold by such discs
//! ([`disc_around`]); the BVH also tests eight of them at once with the same formulas (its disc
//! lanes, `crate::accel`).
//!
//! **The frame.** A ray starts at p (ambient) at height h with unit horizontal direction u and
//! elevation α, and is at height h + s sin α and horizontal distance σ = s cos α at arc length
//! s. The frame turns u and α round so that cos α ≥ 0 (the same geodesic), and keeps v = J u,
//! the products ⟨p, u⟩_κ and ⟨p, v⟩_κ, 1/cos α and 1/sin α (so that the tests multiply rather
//! than divide), and the normal p × u of the plane through the origin that cuts the horizontal
//! geodesic out of the model surface, for the triangles' side test
//! ([`RayFrame::misses_hull`]).
//!
//! **Discs.** A disc with centre c and intrinsic radius r is kept as c and V(r), with
//! V(d) = ½|x − c|²_κ (1 − cos d, d²/2, cosh d − 1) for a point x at distance d from c. It is
//! convex (on the sphere when r < π/2; larger bounds are replaced by the whole sphere), so a
//! disc that contains a node's or a triangle's vertices contains its triangles. Let v = J u be
//! the unit tangent at the ray's origin p perpendicular to its horizontal direction u. The
//! distance d⊥ from c to the ray's horizontal geodesic has S(d⊥) = ⟨c − p, v⟩ =: γ, and the
//! point at horizontal distance σ is inside the disc iff V(σ − σ_c) ≤ (V(r) − V(d⊥))/C(d⊥)
//! (spherical, Euclidean and hyperbolic Pythagoras), where V(d⊥) = γ²/(1 + C(d⊥)) and
//! C(d⊥) = √(1 − κγ²) are computed without cancellation. The first comparison, V(d⊥) ≤ V(r),
//! needs no transcendental function; then the half-width w and the foot σ_c give a σ-interval,
//! which is intersected with the height slab's interval and the ray's current [s_min, s_best]
//! ([`RayFrame::entry`]). On H² the disc test is cheaper still: sinh²w comes straight from
//! cosh w = cosh r / cosh d⊥, w is bounded from above by a short series rather than taken
//! exactly, and σ_c is half the logarithm of (cosh d(p, c) + |⟨c, u⟩|)²/cosh²d⊥ — one division,
//! one square root and one logarithm a bound (see [`hyperbolic_span`]).

use std::f64::consts::{FRAC_PI_2, TAU};

use glam::DVec3;
use orbifold::space::Space;

use crate::fastmath::{ATAN_FAST_ERROR, LN_FAST_ERROR, ln_fast};
use crate::geodesic::Ray;

/// Per-ray quantities for the bound and triangle tests, computed once a ray (see the module
/// documentation).
#[derive(Clone, Copy, Debug)]
pub(crate) struct RayFrame {
    /// The curvature κ.
    pub(crate) kappa: f64,
    /// The ray's start (ambient), its unit horizontal direction (so that cos α ≥ 0), and
    /// v = J u, the unit tangent at p perpendicular to u.
    pub(crate) p: DVec3,
    pub(crate) u: DVec3,
    pub(crate) v: DVec3,
    /// ⟨p, u⟩_κ and ⟨p, v⟩_κ.
    pub(crate) pu: f64,
    pub(crate) pv: f64,
    /// The start's height.
    pub(crate) h: f64,
    /// cos α ≥ 0 and 1/cos α, sin α and 1/sin α.
    pub(crate) ca: f64,
    pub(crate) inv_ca: f64,
    sa: f64,
    pub(crate) inv_sa: f64,
    /// Whether the ray is level (sin α = 0), and whether it is vertical (cos α = 0).
    pub(crate) level: bool,
    pub(crate) vertical: bool,
    /// p × u (Euclidean cross product): the normal of the plane through the origin that cuts
    /// the ray's horizontal geodesic out of the model surface (the gnomonic picture, where
    /// geodesics are straight), and its Euclidean length.
    plane: DVec3,
    plane_length: f64,
}

impl RayFrame {
    /// The frame of a ray (made to have cos α ≥ 0).
    pub(crate) fn new(space: Space, ray: &Ray) -> RayFrame {
        let (u, ca) = if ray.cos_elevation < 0.0 {
            (-ray.direction, -ray.cos_elevation)
        } else {
            (ray.direction, ray.cos_elevation)
        };
        let p = ray.origin;
        let v = space.quarter_turn(p, u);
        let plane = p.cross(u);
        RayFrame {
            kappa: space.kappa(),
            p,
            u,
            v,
            pu: space.point_dot(p, u),
            pv: space.point_dot(p, v),
            h: ray.height,
            ca,
            inv_ca: 1.0 / ca,
            sa: ray.sin_elevation,
            inv_sa: 1.0 / ray.sin_elevation,
            level: ray.sin_elevation == 0.0,
            vertical: ca == 0.0,
            plane,
            plane_length: plane.length(),
        }
    }

    /// Whether the ray's horizontal geodesic certainly misses the geodesic convex hull of three
    /// points, each at least `margin` × its distance scale from the geodesic's plane through
    /// the origin: they are all strictly on one side of it, and so is every nonnegative
    /// combination of them. `scale` is the largest Euclidean length of the points. Never true for
    /// a vertical ray (whose horizontal geodesic is a point).
    #[inline(always)]
    pub(crate) fn misses_hull(&self, points: &[DVec3; 3], scale: f64) -> bool {
        /// Far above the slack that the triangle test allows on an edge (1e-12, relative), so
        /// that no hit that test would accept is rejected here.
        const MARGIN: f64 = 1e-9;
        let tolerance = MARGIN * self.plane_length * scale;
        let side = points.map(|q| self.plane.dot(q));
        !self.vertical
            && (side.iter().all(|&d| d > tolerance) || side.iter().all(|&d| d < -tolerance))
    }

    /// ⟨a, b⟩_κ = a_x b_x + a_y b_y + κ a_z b_z.
    #[inline(always)]
    pub(crate) fn dot(&self, a: DVec3, b: DVec3) -> f64 {
        a.x * b.x + a.y * b.y + self.kappa * a.z * b.z
    }

    /// The curvature κ.
    #[inline(always)]
    pub(crate) fn kappa(&self) -> f64 {
        self.kappa
    }

    /// The ray's start (ambient).
    #[inline(always)]
    pub(crate) fn origin(&self) -> DVec3 {
        self.p
    }

    /// The ray's unit horizontal direction (made so that cos α ≥ 0).
    #[inline(always)]
    pub(crate) fn direction(&self) -> DVec3 {
        self.u
    }

    /// The start's height.
    #[inline(always)]
    pub(crate) fn height(&self) -> f64 {
        self.h
    }

    /// cos α ≥ 0.
    #[inline(always)]
    pub(crate) fn ca(&self) -> f64 {
        self.ca
    }

    /// 1/cos α.
    #[inline(always)]
    pub(crate) fn inv_ca(&self) -> f64 {
        self.inv_ca
    }

    /// sin α.
    #[inline(always)]
    pub(crate) fn sa(&self) -> f64 {
        self.sa
    }

    /// Whether the ray is level (sin α = 0).
    #[inline(always)]
    pub(crate) fn level(&self) -> bool {
        self.level
    }

    /// Whether the ray is vertical (cos α = 0).
    #[inline(always)]
    pub(crate) fn vertical(&self) -> bool {
        self.vertical
    }

    /// The point (ambient, height) at arc length `s`.
    #[inline]
    pub(crate) fn point_at(&self, space: Space, s: f64) -> (DVec3, f64) {
        let (c, sn) = space.cos_sin(s * self.ca);
        (self.p * c + self.u * sn, self.h + s * self.sa)
    }

    /// [s_lo, s_hi] clipped to the arc lengths where the height is in [h_lo, h_hi].
    #[inline(always)]
    pub(crate) fn slab(&self, h_lo: f64, h_hi: f64, s_lo: f64, s_hi: f64) -> Option<(f64, f64)> {
        height_slab(
            (self.h, self.inv_sa, self.level),
            (h_lo, h_hi),
            (s_lo, s_hi),
        )
    }

    /// Where the ray's horizontal geodesic is inside the disc with this centre and V(r)
    /// (conservatively: widened by a relative 1e-9).
    #[inline]
    pub(crate) fn disc(&self, centre: DVec3, reach: f64) -> Disc {
        if reach == f64::INFINITY {
            return Disc::Everywhere;
        }
        if self.vertical {
            let d = self.p - centre;
            return if 0.5 * self.dot(d, d) <= reach {
                Disc::Everywhere
            } else {
                Disc::Missed
            };
        }
        let k = self.kappa;
        let gamma = self.dot(centre, self.v) - self.pv;
        let g2 = gamma * gamma;
        if k < 0.0 {
            let cu = self.dot(centre, self.u) - self.pu;
            let (near, w, centre_sigma) = hyperbolic_span(g2, reach, cu, -self.dot(centre, self.p));
            if !near {
                return Disc::Missed;
            }
            let w = widened(w, centre_sigma);
            return Disc::Span(centre_sigma - w, centre_sigma + w);
        }
        let (m, v_perp) = if k == 0.0 {
            (1.0, 0.5 * g2)
        } else {
            let m = (1.0 - k * g2).max(0.0).sqrt();
            (m, g2 / (1.0 + m))
        };
        if v_perp > reach {
            return Disc::Missed;
        }
        // V(w) = (V(r) − V(d⊥))/C(d⊥); w = 2·S⁻¹(√(V(w)/2)).
        let x = (0.5 * (reach - v_perp) / m).sqrt();
        let cu = self.dot(centre, self.u) - self.pu;
        let (w, centre_sigma) = if k > 0.0 {
            if x.is_nan() || x >= 1.0 {
                return Disc::Everywhere; // the whole great circle is inside
            }
            (2.0 * x.asin(), cu.atan2(self.dot(centre, self.p)))
        } else {
            (2.0 * x, cu)
        };
        let w = widened(w, centre_sigma);
        Disc::Span(centre_sigma - w, centre_sigma + w)
    }

    /// The arc length at which the ray enters the bound within [s_lo, s_hi] (at least s_lo), or
    /// `None` when it does not meet the bound there. Conservative: never `None` for a ray that
    /// meets a triangle inside the bound.
    #[inline]
    pub(crate) fn entry(
        &self,
        centre: DVec3,
        reach: f64,
        h_lo: f64,
        h_hi: f64,
        s_lo: f64,
        s_hi: f64,
    ) -> Option<f64> {
        let (lo, hi) = self.slab(h_lo, h_hi, s_lo, s_hi)?;
        let (start, end) = match self.disc(centre, reach) {
            Disc::Missed => return None,
            Disc::Everywhere => return Some(lo),
            Disc::Span(a, b) => (a, b),
        };
        let (sigma_lo, sigma_hi) = (lo * self.ca, hi * self.ca);
        let (start, end) = if self.kappa > 0.0 && !(end >= sigma_lo && end - TAU < sigma_lo) {
            // The first repetition (period 2π) that ends after σ_lo (usually the one found).
            let turns = ceil_select((sigma_lo - end) / TAU);
            (start + turns * TAU, end + turns * TAU)
        } else {
            (start, end)
        };
        if start > sigma_hi || end < sigma_lo {
            return None;
        }
        Some(if start > sigma_lo {
            (start * self.inv_ca).min(hi)
        } else {
            lo
        })
    }
}

/// Where a ray's horizontal geodesic is inside a disc, in horizontal distance σ.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum Disc {
    /// Nowhere.
    Missed,
    /// Everywhere (a vertical ray over the disc, or a disc that contains the geodesic).
    Everywhere,
    /// On [a, b] (on the sphere: and its repetitions with period 2π).
    Span(f64, f64),
}

/// The bounding disc of some points: centre (the normalised mean) and V(r) for a radius r a
/// little larger than the farthest point's distance; V = +∞ (the whole plane) on the sphere
/// when r would reach π/2, where discs stop being convex. `None` for no points or non-finite ones.
pub(crate) fn disc_around<'a>(
    space: Space,
    points: impl IntoIterator<Item = &'a DVec3> + Clone,
) -> Option<(DVec3, f64)> {
    let (sum, n) = points
        .clone()
        .into_iter()
        .fold((DVec3::ZERO, 0usize), |(s, n), p| (s + *p, n + 1));
    if n == 0 || !sum.is_finite() {
        return None;
    }
    let k = space.kappa();
    if k > 0.0 && sum.length() <= 1e-9 * n as f64 {
        return Some((DVec3::Z, f64::INFINITY));
    }
    let centre = space.normalize_point(sum);
    if !centre.is_finite() {
        return Some((DVec3::Z, f64::INFINITY));
    }
    // The distance grows with the chord, so one inverse function for the farthest chord.
    let chord2 = points
        .into_iter()
        .map(|p| {
            let d = *p - centre;
            space.point_dot(d, d)
        })
        .fold(0.0, f64::max);
    let r = 2.0 * space.asin(0.5 * chord2.sqrt());
    if k > 0.0 && r >= FRAC_PI_2 - 1e-6 || !r.is_finite() {
        return Some((DVec3::Z, f64::INFINITY));
    }
    let r = r * (1.0 + 1e-6) + 1e-9;
    let half = space.sin(0.5 * r);
    Some((centre, 2.0 * half * half))
}

/// A bound's half-width w in σ around its centre σ_c, widened for rounding and for the fast
/// functions' errors (two logarithms on H², two arc tangents on S²).
#[inline(always)]
pub(crate) fn widened(w: f64, centre_sigma: f64) -> f64 {
    const FAST_ERROR: f64 = if LN_FAST_ERROR > ATAN_FAST_ERROR {
        LN_FAST_ERROR
    } else {
        ATAN_FAST_ERROR
    };
    w * (1.0 + 1e-9) + 1e-12 * (1.0 + centre_sigma.abs()) + 3.0 * FAST_ERROR
}

/// ⌈t⌉ by adding and taking away 1.5·2⁵² (which rounds to an integer) and a select: `f64::ceil`
/// is a library call on baseline x86-64, which would keep the lanes of a node test from
/// running side by side.
#[inline(always)]
pub(crate) fn ceil_select(t: f64) -> f64 {
    const ROUND: f64 = 6_755_399_441_055_744.0; // 1.5·2⁵²
    if t.abs() >= 4_503_599_627_370_496.0 {
        return t; // already an integer (2⁵² and beyond)
    }
    let nearest = (t + ROUND) - ROUND;
    nearest + if nearest < t { 1.0 } else { 0.0 }
}

/// An upper bound on arsinh x for x ≥ 0, with no logarithm: its Taylor series to x⁵ (the
/// series alternates with shrinking terms for x ≤ 1, so stopping after a positive term bounds
/// it from above; 2·10⁻⁵ over at x = ½, 10⁻⁹ at x = 0.1), and x itself beyond 1 (arsinh x ≤ x).
#[inline(always)]
fn asinh_above(x: f64) -> f64 {
    let x2 = x * x;
    let series = x * (1.0 - (x2 * (1.0 / 6.0)) * (1.0 - 0.45 * x2));
    if x <= 1.0 { series } else { x }
}

/// The H² disc test in closed form with one division, one square root and one logarithm
/// (`RayFrame::disc` and the lanes' test share it, to the bit). With g = γ = sinh d⊥,
/// `along` = ⟨c, u⟩ and `cosh_pc` = cosh d(p, c):
///
/// - Pythagoras, cosh w = cosh r / cosh d⊥, gives sinh²w = (V(2 + V) − g²)/(1 + g²) for
///   V = V(r) = cosh r − 1, which is ≥ 0 exactly when the geodesic meets the disc, and the
///   half-width is w = arsinh(sinh w) ≤ [`asinh_above`] (a bound a hair wider, never narrower);
/// - the foot σ_c has tanh σ_c = ⟨c, u⟩/cosh d(p, c), so e^{2|σ_c|} = (cosh d(p, c) + |⟨c, u⟩|)²
///   / cosh²d⊥ (the denominator is 1 + g², the same division), one logarithm.
///
/// Returns whether the geodesic meets the disc, w (unwidened) and σ_c.
#[inline(always)]
pub(crate) fn hyperbolic_span(g2: f64, reach: f64, along: f64, cosh_pc: f64) -> (bool, f64, f64) {
    let inv = 1.0 / (1.0 + g2);
    let sinh2 = (reach * (2.0 + reach) - g2) * inv;
    // reach = −∞ (an empty slot) would square to +∞.
    let near = reach >= 0.0 && sinh2 >= 0.0;
    let w = asinh_above(sinh2.max(0.0).sqrt());
    let a = along.abs();
    let e2 = (cosh_pc + a) * (cosh_pc + a) * inv;
    // e2 ≥ 1 but for rounding; the logarithm's floor keeps σ_c ≥ 0 before its sign.
    let centre_sigma = (0.5 * ln_fast(e2.max(1.0))).copysign(along);
    (near, w, centre_sigma)
}

/// [s_lo, s_hi] clipped to the arc lengths where a ray that starts at `height` and climbs
/// 1/`inv_sa` per unit of arc length (or is `level`) is in [h_lo, h_hi]: `RayFrame::slab`, and
/// the test that rejects a ray before its frame is built (`Bvh::heights_met`), with the same
/// arithmetic so that the two agree to the bit.
#[inline(always)]
pub(crate) fn height_slab(
    (height, inv_sa, level): (f64, f64, bool),
    (h_lo, h_hi): (f64, f64),
    (s_lo, s_hi): (f64, f64),
) -> Option<(f64, f64)> {
    let (mut lo, mut hi) = (s_lo, s_hi);
    if level {
        if height < h_lo || height > h_hi {
            return None;
        }
    } else {
        let t1 = (h_lo - height) * inv_sa;
        let t2 = (h_hi - height) * inv_sa;
        lo = lo.max(t1.min(t2));
        hi = hi.min(t1.max(t2));
    }
    (lo <= hi).then_some((lo, hi))
}

#[cfg(test)]
mod tests {
    use orbifold::Geometry;

    use super::*;
    use crate::test_util::uniforms;

    #[test]
    fn ceil_select_is_ceil() {
        for t in [
            0.0,
            -0.0,
            0.5,
            -0.5,
            1.0,
            -1.0,
            1.5,
            2.5,
            -2.5,
            1e-300,
            -1e-300,
            3.999_999_999,
            4_503_599_627_370_495.5,
            1e20,
            -1e20,
            0.999_999_999_999_999_9,
        ] {
            assert_eq!(ceil_select(t), t.ceil(), "{t}");
        }
    }

    /// On H² the disc test's span is the exact one (found by searching along the geodesic for
    /// its nearest point to the centre and bisecting for where it leaves the disc), never
    /// narrower, wider only by the bound on arsinh: 0.1 % of the half-width for radii up to ½.
    #[test]
    fn the_hyperbolic_disc_span_is_the_exact_one_or_a_hair_wider() {
        let space = Space::new(Geometry::Hyperbolic);
        let mut rnd = uniforms(20261127);
        let (mut met, mut missed) = (0, 0);
        for _ in 0..4000 {
            let c = space.exp(DVec3::Z, DVec3::new(rnd() - 0.5, rnd() - 0.5, 0.0) * 1.5);
            let r = 1e-3 * 1500f64.powf(rnd());
            let reach = space.cos(r).mul_add(-1.0, 1.0).abs(); // cosh r − 1 on H²
            // Origins up to 3 from the centre (cosh d(p, c) up to 10).
            let origin = space.exp(DVec3::Z, DVec3::new(rnd() - 0.5, rnd() - 0.5, 0.0) * 3.0);
            let dir = DVec3::new(rnd() - 0.5, rnd() - 0.5, 0.0);
            let ray = Ray::new(space, origin, dir, 0.0, 0.0);
            let frame = RayFrame::new(space, &ray);
            let distance = |sigma: f64| space.ambient_distance(ray.point_at(space, sigma).0, c);
            // The distance to c along a geodesic of H² is convex: ternary search for its least.
            let (mut a, mut b) = (-20.0, 20.0);
            for _ in 0..200 {
                let (x, y) = (a + (b - a) / 3.0, b - (b - a) / 3.0);
                if distance(x) < distance(y) {
                    b = y
                } else {
                    a = x
                }
            }
            let foot = 0.5 * (a + b);
            let perpendicular = distance(foot);
            let span = frame.disc(c, reach);
            if perpendicular > r * (1.0 + 1e-9) + 1e-12 {
                assert_eq!(span, Disc::Missed, "d⊥ {perpendicular} > r {r}");
                missed += 1;
                continue;
            }
            if perpendicular > r * (1.0 - 1e-6) {
                continue; // grazing: either answer is right within rounding
            }
            let Disc::Span(lo, hi) = span else {
                panic!("d⊥ {perpendicular} < r {r}, but {span:?}")
            };
            let boundary = |mut inside: f64, mut outside: f64| {
                for _ in 0..200 {
                    let mid = 0.5 * (inside + outside);
                    if distance(mid) <= r {
                        inside = mid
                    } else {
                        outside = mid
                    }
                }
                inside
            };
            let (enter, leave) = (boundary(foot, foot - 30.0), boundary(foot, foot + 30.0));
            let w = 0.5 * (leave - enter);
            assert!(
                lo <= enter + 1e-9 && hi >= leave - 1e-9,
                "[{lo}, {hi}] within [{enter}, {leave}]"
            );
            let slack = if w <= 0.5 { 1e-3 * w } else { w.sinh() - w };
            assert!(
                enter - lo <= slack + 1e-8 && hi - leave <= slack + 1e-8,
                "[{lo}, {hi}] too wide around [{enter}, {leave}] (r {r})"
            );
            met += 1;
        }
        assert!(met > 300 && missed > 300, "{met} met, {missed} missed");
    }

    #[test]
    fn bound_test_agrees_with_sampling() {
        // The entry test never rejects a ray segment that has a sample point inside the bound.
        for g in [
            Geometry::Spherical,
            Geometry::Euclidean,
            Geometry::Hyperbolic,
        ] {
            let space = Space::new(g);
            let mut rnd = uniforms(12345u64);
            for _ in 0..2000 {
                let c = space.exp(DVec3::Z, DVec3::new(rnd() - 0.5, rnd() - 0.5, 0.0) * 2.0);
                let r = 0.5 * rnd();
                let half = space.sin(0.5 * r);
                let reach = 2.0 * half * half;
                let origin = space.exp(DVec3::Z, DVec3::new(rnd() - 0.5, rnd() - 0.5, 0.0));
                let dir = DVec3::new(rnd() - 0.5, rnd() - 0.5, rnd() - 0.5);
                let ray = Ray::new(space, origin, dir, rnd(), 1.4 * (rnd() - 0.5));
                let frame = RayFrame::new(space, &ray);
                let (h_lo, h_hi) = (rnd() * 0.5, 0.5 + rnd() * 0.5);
                let s_max = 4.0;
                let entry = frame.entry(c, reach, h_lo, h_hi, 0.0, s_max);
                let mut first = None;
                for i in 0..=4000 {
                    let s = s_max * i as f64 / 4000.0;
                    let (x, h) = ray.point_at(space, s);
                    if space.ambient_distance(x, c) <= r && h >= h_lo && h <= h_hi {
                        first = Some(s);
                        break;
                    }
                }
                if let Some(s) = first {
                    let e = entry.unwrap_or_else(|| panic!("{g:?}: missed a sample inside"));
                    assert!(e <= s + 1e-9, "{g:?}: entry {e} after inside sample {s}");
                }
            }
        }
    }

    /// The side test never rejects a triangle whose footprint holds a point of the ray's
    /// horizontal geodesic (small triangles too, where the margin matters), and always rejects
    /// one that lies wholly beside it.
    #[test]
    fn the_side_test_keeps_triangles_on_the_geodesic_and_rejects_those_beside_it() {
        for g in [
            Geometry::Spherical,
            Geometry::Euclidean,
            Geometry::Hyperbolic,
        ] {
            let space = Space::new(g);
            let mut rnd = uniforms(99);
            for _ in 0..20_000 {
                let origin = space.exp(DVec3::Z, DVec3::new(rnd() - 0.5, rnd() - 0.5, 0.0) * 3.0);
                let dir = DVec3::new(rnd() - 0.5, rnd() - 0.5, 0.0);
                let ray = Ray::new(space, origin, dir, rnd(), 1.4 * (rnd() - 0.5));
                let frame = RayFrame::new(space, &ray);
                // A point of the horizontal geodesic, ahead or behind, and the geodesic's unit
                // tangent and normal there.
                let sigma = 4.0 * (rnd() - 0.5);
                let (c, s) = space.cos_sin(sigma);
                let (p, u) = (frame.origin(), frame.direction());
                let x = p * c + u * s;
                let along = u * c - p * (space.kappa() * s);
                let across = space.quarter_turn(x, along);
                let r = 10f64.powf(-6.0 * rnd()) * 0.3;
                let start = std::f64::consts::TAU * rnd();
                let mut triangle_around = |centre: DVec3| -> [DVec3; 3] {
                    std::array::from_fn(|i| {
                        let angle = start + std::f64::consts::TAU * (i as f64 + 0.3 * rnd()) / 3.0;
                        let t = along * angle.cos() + across * angle.sin();
                        space.exp(centre, t * r)
                    })
                };
                let scale = |t: &[DVec3; 3]| t.iter().map(|q| q.length()).fold(0.0, f64::max);
                let on = triangle_around(x);
                assert!(
                    !frame.misses_hull(&on, scale(&on)),
                    "{g:?}: {on:?} was rejected"
                );
                let beside = triangle_around(space.exp(x, across * (2.5 * r)));
                assert!(
                    frame.misses_hull(&beside, scale(&beside)),
                    "{g:?}: {beside:?} was kept"
                );
            }
        }
    }
}
