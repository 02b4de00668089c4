//! The disc test of a node's eight children in f64 lanes (ARCHITECTURE.md §8), for the rays and
//! meshes that the box lanes (`super::chart_lanes`) do not serve: a mesh too wide for a chart, a
//! vertical ray (a point of the chart), a nearly level ray whose box lanes would leave f32's
//! range.
//!
//! Each lane is [`RayFrame::entry`] for one child's disc × height interval, with the formulas of
//! [`RayFrame::disc`] (`crate::ray_frame`) written without branches: selects, and `fastmath`'s
//! logarithm and arc tangent, which have no branches and a stated error that the bounds are
//! widened by. So the compiler runs the eight lanes side by side in SIMD registers, where a
//! binary tree would wait for one bound test after another. A vertical ray takes the scalar
//! test, lane by lane. The lanes are methods of [`RayFrame`], kept here beside the traversal's
//! use of them ([`DiscLanes`]) and the node layout they read (`super::node`).

use std::f64::consts::TAU;

use glam::DVec3;

use super::Bvh;
use super::node::{Discs, Node, WIDTH};
use super::traverse::Lanes;
use crate::fastmath::atan2_fast;
use crate::ray_frame::{RayFrame, ceil_select, hyperbolic_span, widened};

/// The children's discs, in f64 (a mesh without a chart, a vertical ray).
pub(super) struct DiscLanes<'a> {
    pub(super) frame: &'a RayFrame,
    pub(super) s_lo: f64,
}

impl Lanes for DiscLanes<'_> {
    type E = f64;

    #[inline(always)]
    fn bound(&self, s: f64) -> f64 {
        s
    }

    #[inline(always)]
    fn entries(&self, bvh: &Bvh, node: &Node, at: Option<usize>, hi: f64) -> [f64; WIDTH] {
        let discs = at.map_or(&bvh.root_discs, |at| &bvh.discs[at]);
        self.frame.entries(node, discs, self.s_lo, hi)
    }
}

impl RayFrame {
    /// Where the ray enters each of a node's child bounds within [s_lo, s_hi] (NaN where it
    /// does not, so that every comparison with a miss fails, even when s_hi = +∞):
    /// [`RayFrame::entry`] for all at once. Away from vertical rays the lanes are straight-line
    /// arithmetic with selects for branches (the fast functions' reductions too), so that they
    /// run side by side rather than one after another.
    #[inline(always)]
    fn entries(&self, node: &Node, discs: &Discs, s_lo: f64, s_hi: f64) -> [f64; WIDTH] {
        if self.vertical {
            return std::array::from_fn(|i| {
                let b = discs.bound(node, i);
                self.entry(b.centre, b.reach, b.h_lo, b.h_hi, s_lo, s_hi)
                    .unwrap_or(f64::NAN)
            });
        }
        let mut out = [f64::NAN; WIDTH];
        if self.kappa > 0.0 {
            for (i, e) in out.iter_mut().enumerate() {
                *e = self.lane::<1>(node, discs, i, s_lo, s_hi);
            }
        } else if self.kappa == 0.0 {
            for (i, e) in out.iter_mut().enumerate() {
                *e = self.lane::<0>(node, discs, i, s_lo, s_hi);
            }
        } else {
            for (i, e) in out.iter_mut().enumerate() {
                *e = self.lane::<-1>(node, discs, i, s_lo, s_hi);
            }
        }
        out
    }

    /// One lane of [`RayFrame::entries`] for a ray that is not vertical, in the geometry whose
    /// curvature has the sign `K`: the same formulas as [`RayFrame::disc`] and
    /// [`RayFrame::entry`], without branches.
    #[inline(always)]
    fn lane<const K: i32>(
        &self,
        node: &Node,
        discs: &Discs,
        i: usize,
        s_lo: f64,
        s_hi: f64,
    ) -> f64 {
        let (lo, hi) = self.lane_slab(node, i, s_lo, s_hi);
        let c = DVec3::new(discs.x[i], discs.y[i], discs.z[i]);
        let reach = discs.reach[i];
        let gamma = self.dot(c, self.v) - self.pv;
        let g2 = gamma * gamma;
        let cu = self.dot(c, self.u) - self.pu;
        let (near, q, w, centre_sigma) = match K {
            // On H² the closed form shared with `RayFrame::disc` (one division, one square root
            // and one logarithm).
            -1 => {
                let (near, w, centre_sigma) = hyperbolic_span(g2, reach, cu, -self.dot(c, self.p));
                (near, 0.0, w, centre_sigma)
            }
            // As in `RayFrame::disc`, with x² = q computed on one division and never rooted:
            // V(d⊥) = γ²/(1 + C) ≤ V(r) is γ² ≤ V(r)·(1 + C), and q = (V(r)(1 + C) − γ²)/(2C(1 + C)).
            // On S², cos w = 1 − 2q and sin w = 2√(q(1 − q)).
            1 => {
                let m = (1.0 - g2).max(0.0).sqrt();
                let one_m = 1.0 + m;
                let near = g2 <= reach * one_m;
                let q = 0.5 * (reach * one_m - g2) / (m * one_m);
                let qs = if q < 1.0 { q } else { 0.0 };
                (
                    near,
                    q,
                    atan2_fast(2.0 * (qs * (1.0 - qs)).sqrt(), 1.0 - 2.0 * qs),
                    atan2_fast(cu, self.dot(c, self.p)),
                )
            }
            _ => {
                let q = 0.5 * (reach - 0.5 * g2);
                (0.5 * g2 <= reach, q, 2.0 * q.sqrt(), cu)
            }
        };
        // On S² a disc that holds the whole great circle (q ≥ 1, or NaN when C = 0), and in
        // every geometry the whole plane (reach = +∞), is entered wherever the slab is.
        let everywhere = reach == f64::INFINITY || (K > 0 && (q.is_nan() || q >= 1.0));
        let w = widened(w, centre_sigma);
        let span = (centre_sigma - w, centre_sigma + w);
        self.lane_entry::<K>((lo, hi), span, near, everywhere)
    }

    /// A lane's [s_lo, s_hi] cut to where the ray is within child `i`'s heights (empty when
    /// lo > hi).
    #[inline(always)]
    fn lane_slab(&self, node: &Node, i: usize, s_lo: f64, s_hi: f64) -> (f64, f64) {
        let (h_lo, h_hi) = (f64::from(node.h_lo[i]), f64::from(node.h_hi[i]));
        if self.level {
            let inside = self.h >= h_lo && self.h <= h_hi;
            (s_lo, if inside { s_hi } else { f64::NEG_INFINITY })
        } else {
            let t1 = (h_lo - self.h) * self.inv_sa;
            let t2 = (h_hi - self.h) * self.inv_sa;
            (s_lo.max(t1.min(t2)), s_hi.min(t1.max(t2)))
        }
    }

    /// Where a lane's ray enters its bound (NaN where it does not), from the arc lengths
    /// [lo, hi] within its heights and the σ-interval `[start, end]` over its footprint (on S²,
    /// `K` > 0, the first repetition, period 2π, that ends at or after σ_lo), met only where
    /// the lane's own test `passed`; `everywhere` for a bound that holds the whole geodesic.
    #[inline(always)]
    fn lane_entry<const K: i32>(
        &self,
        (lo, hi): (f64, f64),
        (mut start, mut end): (f64, f64),
        passed: bool,
        everywhere: bool,
    ) -> f64 {
        let (sigma_lo, sigma_hi) = (lo * self.ca, hi * self.ca);
        if K > 0 {
            let turns = ceil_select((sigma_lo - end) / TAU);
            start += turns * TAU;
            end += turns * TAU;
            let behind = end < sigma_lo;
            start += if behind { TAU } else { 0.0 };
            end += if behind { TAU } else { 0.0 };
        }
        let met = lo <= hi && passed && (everywhere || (start <= sigma_hi && end >= sigma_lo));
        let entry = if everywhere || start <= sigma_lo {
            lo
        } else {
            (start * self.inv_ca).min(hi)
        };
        if met { entry } else { f64::NAN }
    }
}

#[cfg(test)]
mod tests {
    use orbifold::Geometry;
    use orbifold::space::Space;

    use super::*;
    use crate::accel::node::Bound;
    use crate::geodesic::Ray;
    use crate::test_util::uniforms;

    /// A random node of eight bounds around the origin of `space` (some slots left empty).
    fn random_node(space: Space, rnd: &mut impl FnMut() -> f64) -> (Node, Discs) {
        let mut node = Node::EMPTY;
        let mut discs = Discs::EMPTY;
        for slot in 0..WIDTH {
            if rnd() < 0.15 {
                continue; // an empty slot
            }
            let c = space.exp(DVec3::Z, DVec3::new(rnd() - 0.5, rnd() - 0.5, 0.0) * 2.0);
            let reach = if rnd() < 0.05 {
                f64::INFINITY
            } else {
                let half = space.sin(0.25 * rnd());
                2.0 * half * half
            };
            let (h_lo, h_hi) = (rnd() * 0.5, 0.5 + rnd() * 0.5);
            let bound = Bound {
                centre: c,
                reach,
                h_lo,
                h_hi,
                chart_lo: [f64::INFINITY; 2],
                chart_hi: [f64::NEG_INFINITY; 2],
            };
            node.set(slot, &bound, slot as u32, 0);
            discs.set(slot, &bound);
        }
        (node, discs)
    }

    #[test]
    fn the_disc_lanes_agree_with_the_scalar_test_and_with_sampling() {
        // Every lane of `entries` is conservative (never after a sample point inside its bound,
        // never a miss when one is inside) and, but for the fast functions' errors, equal to
        // `entry`; empty slots are missed. Rays of every kind: level, vertical, steep, long
        // (several turns round the sphere), with s_max = +∞.
        for g in [
            Geometry::Spherical,
            Geometry::Euclidean,
            Geometry::Hyperbolic,
        ] {
            let space = Space::new(g);
            let mut rnd = uniforms(987654321u64);
            let (mut met, mut missed) = (0, 0);
            // Fewer cases unoptimised (CI runs the tests in debug builds).
            let (cases, samples) = if cfg!(debug_assertions) {
                (800, 1000)
            } else {
                (3000, 3000)
            };
            for case in 0..cases {
                let (node, discs) = random_node(space, &mut rnd);
                let origin = space.exp(DVec3::Z, DVec3::new(rnd() - 0.5, rnd() - 0.5, 0.0));
                let dir = DVec3::new(rnd() - 0.5, rnd() - 0.5, 0.0);
                let elevation = match case % 5 {
                    0 => 0.0,
                    1 => std::f64::consts::FRAC_PI_2,
                    _ => 1.4 * (rnd() - 0.5),
                };
                let ray = Ray::new(space, origin, dir, rnd(), elevation);
                let frame = RayFrame::new(space, &ray);
                let s_min = if case % 7 == 0 { 2.5 } else { 0.0 };
                let s_max = match case % 3 {
                    0 => f64::INFINITY,
                    1 => 9.0,
                    _ => 4.0,
                };
                let entries = frame.entries(&node, &discs, s_min, s_max);
                for (slot, &lane) in entries.iter().enumerate() {
                    let b = discs.bound(&node, slot);
                    if b.reach == f64::NEG_INFINITY {
                        assert!(lane.is_nan(), "{g:?}: an empty slot was met");
                        continue;
                    }
                    let scalar = frame.entry(b.centre, b.reach, b.h_lo, b.h_hi, s_min, s_max);
                    match scalar {
                        Some(e) => {
                            assert!(
                                (lane - e).abs() <= 1e-8 * (1.0 + e.abs()),
                                "{g:?}: lane {lane} vs scalar {e}"
                            );
                            met += 1;
                        }
                        None => {
                            missed += 1;
                        }
                    }
                    // Sampling along the ray up to 9 (or s_max).
                    let end = s_max.min(9.0);
                    let r = 2.0 * space.asin((0.5 * b.reach).sqrt());
                    for i in 0..=samples {
                        let s = s_min + (end - s_min) * f64::from(i) / f64::from(samples);
                        let (x, h) = ray.point_at(space, s);
                        let inside = if b.reach == f64::INFINITY {
                            true
                        } else {
                            space.ambient_distance(x, b.centre) <= r
                        };
                        if inside && h >= b.h_lo && h <= b.h_hi {
                            assert!(
                                lane <= s + 1e-9,
                                "{g:?}: lane {lane} after inside sample {s} (scalar {scalar:?})"
                            );
                            break;
                        }
                    }
                }
            }
            assert!(
                met > cases / 6 && missed > cases / 6,
                "{g:?}: {met} met, {missed} missed"
            );
        }
    }
}
