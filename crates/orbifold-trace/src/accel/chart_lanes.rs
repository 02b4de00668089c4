//! The box test of a node's eight children in f32 lanes ([`ChartLanes`], ARCHITECTURE.md §8).
//!
//! Every quantity of the chart's ray–box test (`super::chart`) is taken in the arc length from
//! the foot, σ' (so that no lane carries the foot's own magnitude), rounded to f32 once a ray,
//! and padded by a bound on the rounding of every product and sum — from the largest chart
//! coordinate and height of any box (the root's) — so that a lane is never later than the exact
//! entry and never misses a box the exact test meets. A nearly level ray, whose heights' σ'
//! would leave f32's range, is tested by its discs (`super::disc_lanes`).
//!
//! A lane is straight-line arithmetic, with selects for its branches ([`min32`], [`max32`],
//! [`ceil_select32`]: one instruction or a few a lane, where the library's functions take care
//! of NaN or are calls), so that the compiler runs the eight lanes of a node side by side in
//! SIMD registers (all eight in one AVX2 register) where a binary tree would wait for one bound
//! test after another. The outward roundings to f32 ([`f32_below`], [`f32_above`]) also make the
//! nodes' boxes.

use std::f64::consts::TAU;

use super::Bvh;
use super::chart::{ChartRay, FOOT_ERROR};
use super::node::{Node, WIDTH};
use super::traverse::Lanes;
use crate::ray_frame::RayFrame;

/// f32's unit roundoff, 2⁻²⁴.
const F32_EPSILON: f64 = 1.0 / 16_777_216.0;

/// ⌈t⌉ in f32 by adding and taking away 1.5·2²³ and a select
/// ([`ceil_select`](crate::ray_frame::ceil_select) in single precision).
#[inline(always)]
fn ceil_select32(t: f32) -> f32 {
    const ROUND: f32 = 12_582_912.0; // 1.5·2²³
    if t.abs() >= 8_388_608.0 {
        return t; // already an integer (2²³ and beyond)
    }
    let nearest = (t + ROUND) - ROUND;
    nearest + if nearest < t { 1.0 } else { 0.0 }
}

/// The smaller of two f32 by one comparison (a NaN gives `b`): one instruction a lane, where
/// `f32::min`'s care for NaN takes three. The lanes' NaNs are only in empty slots, which are
/// turned away by their own test.
#[inline(always)]
fn min32(a: f32, b: f32) -> f32 {
    if a < b { a } else { b }
}

/// The larger of two f32 by one comparison (a NaN gives `b`; see [`min32`]).
#[inline(always)]
fn max32(a: f32, b: f32) -> f32 {
    if a > b { a } else { b }
}

/// Rounds down to an f32 that is ≤ x.
pub(super) fn f32_below(x: f64) -> f32 {
    let y = x as f32;
    if f64::from(y) > x { y.next_down() } else { y }
}

/// Rounds up to an f32 that is ≥ x.
pub(super) fn f32_above(x: f64) -> f32 {
    let y = x as f32;
    if f64::from(y) < x { y.next_up() } else { y }
}

/// A [`ChartRay`] made ready for eight lanes of single precision: every quantity of the box
/// test in the horizontal arc length from the foot, σ' = σ − σ_foot (so that no lane adds the
/// foot's own magnitude), rounded to f32, with pads that cover every rounding of the lanes'
/// arithmetic (each product and sum at most a few units in the last place of the largest
/// value it can take: the chart's and the heights' extents, which the root's box bounds).
/// A lane's result is an entry σ' that is never after the true one, and never a miss where
/// the exact test in f64 meets.
#[derive(Clone, Copy, Debug)]
pub(super) struct ChartLanes {
    /// σ of the foot, and cos α: σ' = s·cos α − foot.
    foot: f64,
    ca: f64,
    /// Where the ray starts (σ' of s_min, rounded down).
    lo: f32,
    /// The T of a box side v is v·scale − shift, within ±pad (pad = +∞ for an axis along
    /// which the line barely moves, whose scale and shift are 0).
    scale: [f32; 2],
    shift: [f32; 2],
    pad: [f32; 2],
    t_max: f32,
    cubic: f32,
    quintic: f32,
    /// Widening of the σ'-interval from T⁻¹'s bounds (the foot's error, rounding).
    slack: f32,
    /// Heights: σ'(h) = h·rise − offset within ±height_pad, for a ray that is not level.
    rise: f32,
    offset: f32,
    height_pad: f32,
    /// A level ray's height, rounded down and up.
    level: bool,
    h_below: f32,
    h_above: f32,
}

impl ChartLanes {
    /// `None` where a constant would leave f32's range (a nearly level ray climbs so slowly
    /// that its heights' σ' overflow): the discs are tested instead. `extent` bounds the
    /// absolute chart coordinates of every box, `heights` the absolute heights.
    #[inline(always)]
    pub(super) fn new(
        ray: &ChartRay,
        frame: &RayFrame,
        extent: f64,
        heights: f64,
        s_lo: f64,
    ) -> Option<ChartLanes> {
        const LIMIT: f64 = 1e30;
        let (foot, ca) = (ray.foot, frame.ca);
        let mut lanes = ChartLanes {
            foot,
            ca,
            lo: 0.0,
            scale: [0.0; 2],
            shift: [0.0; 2],
            pad: [f32::INFINITY; 2],
            t_max: f32_above(ray.t_max),
            cubic: ray.cubic as f32,
            quintic: f32_above(ray.quintic),
            slack: 0.0,
            rise: 0.0,
            offset: 0.0,
            height_pad: 0.0,
            level: frame.level,
            h_below: f32_below(frame.h),
            h_above: f32_above(frame.h),
        };
        lanes.lo = lanes.sigma_below(s_lo);
        for i in 0..2 {
            let (scale, shift) = (ray.scale[i], ray.shift[i]);
            let reach = extent * scale.abs() + shift.abs();
            if ray.free[i] || !reach.is_finite() || reach >= LIMIT {
                continue; // free: T = 0 ± ∞
            }
            // Products and sums of values up to `reach`, each rounded once (and the constants
            // themselves), and the subtraction of the pad: 8 units of roundoff.
            let pad = ray.pad[i] + 8.0 * F32_EPSILON * reach;
            lanes.scale[i] = scale as f32;
            lanes.shift[i] = shift as f32;
            lanes.pad[i] = f32_above(pad);
        }
        // |T⁻¹'s bounds| ≤ their value at T(R).
        let t = ray.t_max;
        let bound = t * (1.0 + ray.cubic.abs() * t * t) + ray.quintic * t.powi(4) * t;
        let slack = 1e-12 * (1.0 + foot.abs() + bound) + FOOT_ERROR + 16.0 * F32_EPSILON * bound;
        lanes.slack = f32_above(slack);
        if !frame.level {
            let rise = ca * frame.inv_sa;
            let offset = frame.h * rise + foot;
            let reach = heights * rise.abs() + offset.abs();
            if !reach.is_finite() || reach >= LIMIT {
                return None;
            }
            lanes.rise = rise as f32;
            lanes.offset = offset as f32;
            lanes.height_pad = f32_above(8.0 * F32_EPSILON * reach + 1e-12 * reach);
        }
        (lanes.lo.is_finite() && lanes.slack.is_finite()).then_some(lanes)
    }

    /// σ' at arc length s, rounded down (never after the true one).
    #[inline(always)]
    fn sigma_below(&self, s: f64) -> f32 {
        let sigma = s * self.ca - self.foot;
        f32_below(sigma - 1e-12 * (1.0 + sigma.abs() + self.foot.abs()))
    }

    /// σ' at arc length s, rounded up.
    #[inline(always)]
    fn sigma_above(&self, s: f64) -> f32 {
        let sigma = s * self.ca - self.foot;
        f32_above(sigma + 1e-12 * (1.0 + sigma.abs() + self.foot.abs()))
    }

    /// Where the ray enters each of a node's children's boxes × heights, as σ', before `hi`
    /// (NaN where it does not); `K` > 0 on S², where the first repetition is taken.
    #[inline(always)]
    fn entries<const K: i32>(&self, node: &Node, hi: f32) -> [f32; WIDTH] {
        let mut out = [f32::NAN; WIDTH];
        for (i, e) in out.iter_mut().enumerate() {
            *e = self.lane::<K>(node, i, hi);
        }
        out
    }

    /// One lane of [`ChartLanes::entries`]: the height slab, the box's T-interval (two slabs,
    /// clamped to |T| ≤ T(R)) taken to σ' by the bounds on T⁻¹, met where they overlap.
    #[inline(always)]
    fn lane<const K: i32>(&self, node: &Node, i: usize, s_hi: f32) -> f32 {
        let (lo, hi) = if self.level {
            let inside = self.h_above >= node.h_lo[i] && self.h_below <= node.h_hi[i];
            (self.lo, if inside { s_hi } else { f32::NEG_INFINITY })
        } else {
            let t1 = node.h_lo[i] * self.rise - self.offset;
            let t2 = node.h_hi[i] * self.rise - self.offset;
            (
                max32(self.lo, min32(t1, t2) - self.height_pad),
                min32(s_hi, max32(t1, t2) + self.height_pad),
            )
        };
        let axis = |a: usize, v_lo: f32, v_hi: f32| {
            let t1 = v_lo * self.scale[a] - self.shift[a];
            let t2 = v_hi * self.scale[a] - self.shift[a];
            (min32(t1, t2) - self.pad[a], max32(t1, t2) + self.pad[a])
        };
        let (x_in, x_out) = axis(0, node.gx_lo[i], node.gx_hi[i]);
        let (y_in, y_out) = axis(1, node.gy_lo[i], node.gy_hi[i]);
        let t_in = max32(max32(x_in, y_in), -self.t_max);
        let t_out = min32(min32(x_out, y_out), self.t_max);
        let odd = |t: f32| t * (1.0 + self.cubic * (t * t));
        let fifth = |t: f32| {
            let t2 = t * t;
            self.quintic * (t2 * t2) * t
        };
        let mut start = odd(t_in) + min32(fifth(t_in), 0.0) - self.slack;
        let mut end = odd(t_out) + max32(fifth(t_out), 0.0) + self.slack;
        if K > 0 {
            // The first repetition (period 2π) that ends at or after lo, widened by the
            // rounding of the turns; far beyond any ray's length, the whole turn.
            const TAU32: f32 = TAU as f32;
            const INV_TAU32: f32 = (1.0 / TAU) as f32;
            let wrap = 32.0 * F32_EPSILON as f32 * (lo.abs() + end.abs() + 8.0);
            let turns = ceil_select32((lo - end - wrap) * INV_TAU32);
            start += turns * TAU32;
            end += turns * TAU32;
            let behind = end + wrap < lo;
            start += if behind { TAU32 } else { 0.0 };
            end += if behind { TAU32 } else { 0.0 };
            let far = lo.abs() > 1e5;
            start = if far { f32::NEG_INFINITY } else { start - wrap };
            end = if far { f32::INFINITY } else { end + wrap };
        }
        let occupied = node.gx_lo[i] <= node.gx_hi[i];
        let met = lo <= hi && occupied && t_in <= t_out && start <= hi && end >= lo;
        let entry = if start <= lo { lo } else { min32(start, hi) };
        if met { entry } else { f32::NAN }
    }
}

/// The children's chart boxes in f32 lanes, on S² (`K` > 0) or not.
pub(super) struct BoxLanes<const K: i32>(pub(super) ChartLanes);

impl<const K: i32> Lanes for BoxLanes<K> {
    type E = f32;

    #[inline(always)]
    fn bound(&self, s: f64) -> f32 {
        self.0.sigma_above(s)
    }

    #[inline(always)]
    fn entries(&self, _: &Bvh, node: &Node, _: Option<usize>, hi: f32) -> [f32; WIDTH] {
        self.0.entries::<K>(node, hi)
    }
}

#[cfg(test)]
mod tests {
    use std::f64::consts::FRAC_PI_2;

    use glam::DVec3;
    use orbifold::Geometry;
    use orbifold::space::Space;

    use super::*;
    use crate::accel::chart::Chart;
    use crate::accel::node::{Bound, Discs};
    use crate::geodesic::Ray;
    use crate::test_util::uniforms;

    #[test]
    fn ceil_select32_is_ceil() {
        for t in [
            0.0f32,
            -0.0,
            0.5,
            -0.5,
            1.0,
            -1.0,
            1.000_001,
            2.5,
            -2.5,
            1e6,
            -1e6 - 0.5,
            1e7,
        ] {
            assert_eq!(ceil_select32(t), t.ceil(), "{t}");
        }
        let mut rnd = uniforms(2026);
        for _ in 0..10_000 {
            let t = ((rnd() - 0.5) * 2e5) as f32;
            assert_eq!(ceil_select32(t), t.ceil(), "{t}");
        }
    }

    #[test]
    fn f32_rounding_is_outward() {
        for x in [0.1, -0.1, 1e-30, 3.0, 1.0 / 3.0, -7.123456789] {
            assert!(f64::from(f32_below(x)) <= x && f64::from(f32_above(x)) >= x);
        }
    }

    /// Every f32 lane of [`ChartLanes::entries`] is conservative: never a miss, and never an
    /// entry after a point of the ray that is inside the child's chart box and height interval
    /// and within the chart's radius; and it is not much before the first such point (only by
    /// the bound on T⁻¹, the lanes' pads and the sampling step). Rays of every kind: level,
    /// steep, nearly vertical, from far away, long (several turns round the sphere), with
    /// s_max = +∞.
    #[test]
    fn the_chart_box_test_is_conservative_and_tight() {
        for g in [
            Geometry::Spherical,
            Geometry::Euclidean,
            Geometry::Hyperbolic,
        ] {
            let space = Space::new(g);
            let mut rnd = uniforms(31415);
            let (cases, samples) = if cfg!(debug_assertions) {
                (600, 1500)
            } else {
                (3000, 3000)
            };
            let (mut met, mut missed) = (0, 0);
            for case in 0..cases {
                // A cluster of vertices about a centre, and boxes round some of them.
                let centre = space.exp(DVec3::Z, DVec3::new(rnd() - 0.5, rnd() - 0.5, 0.0));
                let spread = 0.1 + 0.5 * rnd();
                let vertices: Vec<DVec3> = (0..12)
                    .map(|_| {
                        let t = DVec3::new(rnd() - 0.5, rnd() - 0.5, 0.0) * spread;
                        space.exp(
                            centre,
                            space.tangent_frame(centre)[0] * t.x
                                + space.tangent_frame(centre)[1] * t.y,
                        )
                    })
                    .collect();
                let chart = Chart::new(space, centre, vertices.iter().copied()).unwrap();
                let mut node = Node::EMPTY;
                for slot in 0..WIDTH {
                    if rnd() < 0.15 {
                        continue;
                    }
                    let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
                    for v in vertices.iter().filter(|_| rnd() < 0.4) {
                        let c = chart.coords(*v).unwrap();
                        for i in 0..2 {
                            lo[i] = lo[i].min(c[i]);
                            hi[i] = hi[i].max(c[i]);
                        }
                    }
                    let (h_lo, h_hi) = (rnd() * 0.5, 0.5 + rnd() * 0.5);
                    let bound = Bound {
                        centre,
                        reach: 0.0,
                        h_lo,
                        h_hi,
                        chart_lo: lo,
                        chart_hi: hi,
                    };
                    node.set(slot, &bound, slot as u32, 0);
                }
                let far = if case % 11 == 0 { 3.0 } else { 1.0 };
                let origin = space.exp(DVec3::Z, DVec3::new(rnd() - 0.5, rnd() - 0.5, 0.0) * far);
                let dir = DVec3::new(rnd() - 0.5, rnd() - 0.5, 0.0);
                let elevation = match case % 5 {
                    0 => 0.0,
                    // Nearly vertical (cos α down to 10⁻³): σ' barely moves along the ray.
                    1 if case % 3 == 0 => (1.0 - 1e-3 * rnd()).copysign(rnd() - 0.5) * FRAC_PI_2,
                    _ => 1.4 * (rnd() - 0.5),
                };
                let ray = Ray::new(space, origin, dir, rnd(), elevation);
                let frame = RayFrame::new(space, &ray);
                let Some(chart_ray) = ChartRay::new(&chart, &frame) else {
                    continue; // a great circle that misses the chart's hemisphere
                };
                let s_min = if case % 7 == 0 { 2.5 } else { 0.0 };
                let s_max = match case % 3 {
                    0 => f64::INFINITY,
                    1 => 9.0,
                    _ => 4.0,
                };
                // The boxes' extent, and the heights' (all within [0, 1]).
                let extent = (0..WIDTH)
                    .filter(|&i| node.gx_lo[i] <= node.gx_hi[i])
                    .flat_map(|i| [node.gx_lo[i], node.gx_hi[i], node.gy_lo[i], node.gy_hi[i]])
                    .fold(0.0f64, |m, v| m.max(f64::from(v.abs())));
                let Some(lanes) = ChartLanes::new(&chart_ray, &frame, extent, 1.0, s_min) else {
                    continue; // so nearly level that its heights leave f32's range
                };
                let hi = lanes.sigma_above(s_max);
                let sigmas = if g == Geometry::Spherical {
                    lanes.entries::<1>(&node, hi)
                } else {
                    lanes.entries::<0>(&node, hi)
                };
                // The lanes' σ' taken back to arc lengths.
                let entries = sigmas.map(|e| (f64::from(e) + lanes.foot) * frame.inv_ca());
                let end = s_max.min(9.0);
                let step = (end - s_min) / f64::from(samples);
                // How far before the true entry a lane may be: the bound on T⁻¹ at T(R), and
                // the pads of the f32 lanes.
                let t = chart_ray.t_max;
                let pads = f64::from(lanes.slack + lanes.height_pad) + 1e-6;
                let slack =
                    (chart_ray.quintic * t.powi(5) + pads + 1e-9) * frame.inv_ca() + step + 1e-9;
                for (slot, &lane) in entries.iter().enumerate() {
                    if node.gx_lo[slot] > node.gx_hi[slot] {
                        assert!(lane.is_nan(), "{g:?}: an empty slot was met");
                        continue;
                    }
                    if lane.is_nan() {
                        missed += 1;
                    } else {
                        met += 1;
                    }
                    let b = Discs::EMPTY.bound(&node, slot);
                    let mut first_in_box = None;
                    for i in 0..=samples {
                        let s = s_min + step * f64::from(i);
                        let (x, h) = ray.point_at(space, s);
                        let Some(c) = chart.coords(x) else { continue };
                        let in_box = c[0] >= b.chart_lo[0]
                            && c[0] <= b.chart_hi[0]
                            && c[1] >= b.chart_lo[1]
                            && c[1] <= b.chart_hi[1]
                            && h >= b.h_lo
                            && h <= b.h_hi;
                        if in_box && first_in_box.is_none() {
                            first_in_box = Some(s);
                        }
                        // Within the chart's radius, where the mesh is.
                        if in_box && c[0].hypot(c[1]) <= t {
                            assert!(
                                lane <= s + 1e-9,
                                "{g:?} case {case}: lane {lane} after inside sample {s}"
                            );
                            break;
                        }
                    }
                    // A ray that only grazes a corner of the box may cross it between two
                    // samples: look again, finely, just after the lane's entry.
                    let grazed = |from: f64| {
                        (0..=20_000).any(|i| {
                            let s = from + 1e-5 * f64::from(i);
                            let (x, h) = ray.point_at(space, s);
                            chart.coords(x).is_some_and(|c| {
                                c[0] >= b.chart_lo[0]
                                    && c[0] <= b.chart_hi[0]
                                    && c[1] >= b.chart_lo[1]
                                    && c[1] <= b.chart_hi[1]
                                    && h >= b.h_lo
                                    && h <= b.h_hi
                            })
                        })
                    };
                    if let Some(s) = first_in_box {
                        assert!(
                            lane.is_nan()
                                || lane >= s - slack
                                || lane <= s_min + 1e-12
                                || grazed(lane - slack),
                            "{g:?} case {case}: lane {lane} long before the box, at {s}"
                        );
                    }
                }
            }
            // Both outcomes are exercised (few lanes are met: the boxes are of small random
            // clusters).
            assert!(
                met > cases / 10 && missed > cases / 10,
                "{g:?}: {met} met, {missed} missed"
            );
        }
    }
}
