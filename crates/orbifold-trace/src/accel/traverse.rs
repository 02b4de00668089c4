//! The traversals of the BVH (ARCHITECTURE.md §8): the nearest hit ([`Bvh::intersect`]) and
//! whether anything is hit ([`Bvh::occluded`]), generic over how a node's children are tested
//! ([`Lanes`]: their chart boxes in f32, `super::chart_lanes`, or their discs in f64,
//! `super::disc_lanes`).
//!
//! Before its frame is built, a ray is tested against the root's height interval and disc
//! ([`Bvh::heights_met`], [`Bvh::root_missed`]), which turn away most of the rays that pass the
//! object by. Then the root's bound, by the lanes' own test, is the first test of every ray. A
//! node's eight bounds are tested at once; the children met (a mask of one vector comparison)
//! go on the stack farthest first, their nodes or triangles prefetched; nearest hits prune the
//! rest ([`ClosestHit`]), any hit ends the search ([`AnyHit`]). Both searches run through a copy
//! compiled for AVX2 and FMA where the processor has them (`crate::with_avx2`, called by the
//! public methods): the `_portable` methods and all they call are `#[inline(always)]`, so that
//! the copy compiles them anew with the wider registers.

use arrayvec::ArrayVec;
use glam::DVec3;
use orbifold::space::Space;

use super::Bvh;
use super::chart::ChartRay;
use super::chart_lanes::{BoxLanes, ChartLanes};
use super::disc_lanes::DiscLanes;
use super::node::{Node, WIDTH};
use crate::geodesic::Ray;
use crate::ray_frame::{RayFrame, height_slab};
use crate::triangle::{PreparedTriangle, TriangleHit};

/// Traversal stack size: each level leaves at most seven children waiting, and the depth is at
/// most `SAH_DEPTH` (`super::build`) + log₂ of the triangle count (≤ 96).
pub(super) const STACK: usize = 7 * 96;

/// A child waiting on the traversal stack: a node, or a leaf's triangles, and where the ray
/// enters its bound.
#[derive(Clone, Copy, Debug)]
struct StackEntry<E> {
    index: u32,
    count: u32,
    entry: E,
}

/// How a traversal tests a node's children: its entries' unit (`E`: σ' in f32 for
/// [`ChartLanes`], arc length s in f64 for the discs) and the test itself.
pub(super) trait Lanes {
    type E: Copy + PartialOrd;
    /// The entry unit's value at arc length `s`, rounded up.
    fn bound(&self, s: f64) -> Self::E;
    /// Where the ray enters each child of the node at `at` (NaN where it does not) before `hi`.
    fn entries(&self, bvh: &Bvh, node: &Node, at: Option<usize>, hi: Self::E) -> [Self::E; WIDTH];
}

/// The ray's part a search looks at: its space, frame and arc lengths [s_min, s_max].
#[derive(Clone, Copy)]
struct Segment<'a> {
    space: Space,
    frame: &'a RayFrame,
    s_min: f64,
    s_max: f64,
}

/// A search of the tree ([`ClosestHit`] or [`AnyHit`]), generic over the lanes that test its
/// nodes.
trait Search {
    type Found;
    /// What a ray that misses the root finds.
    const MISSED: Self::Found;
    fn run<L: Lanes>(self, bvh: &Bvh, at: &Segment, lanes: &L) -> Self::Found;
}

/// The nearest hit ([`Bvh::intersect`]).
struct ClosestHit;

impl Search for ClosestHit {
    type Found = Option<TriangleHit>;
    const MISSED: Option<TriangleHit> = None;

    #[inline(always)]
    fn run<L: Lanes>(self, bvh: &Bvh, at: &Segment, lanes: &L) -> Option<TriangleHit> {
        bvh.closest_hit(at, lanes)
    }
}

/// Whether anything is hit ([`Bvh::occluded`]).
struct AnyHit;

impl Search for AnyHit {
    type Found = bool;
    const MISSED: bool = false;

    #[inline(always)]
    fn run<L: Lanes>(self, bvh: &Bvh, at: &Segment, lanes: &L) -> bool {
        bvh.any_hit(at, lanes)
    }
}

/// Whether a lane's entry is at most `bound` (never for a NaN: a lane that was not met).
#[inline(always)]
fn is_met<E: PartialOrd>(entry: E, bound: E) -> bool {
    entry <= bound
}

/// The lanes whose entry is at most `bound`, as bits (one vector comparison and a move of its
/// mask, where a loop of branches would test the lanes one by one).
#[inline(always)]
fn met_mask<E: Copy + PartialOrd>(entries: &[E; WIDTH], bound: E) -> u32 {
    let mut mask = 0;
    for (slot, &e) in entries.iter().enumerate() {
        mask |= u32::from(is_met(e, bound)) << slot;
    }
    mask
}

impl Bvh {
    /// [`Bvh::intersect`], compiled anew into each of its copies.
    #[inline(always)]
    pub(super) fn intersect_portable(
        &self,
        space: Space,
        ray: &Ray,
        s_min: f64,
        s_max: f64,
    ) -> Option<TriangleHit> {
        self.search(space, ray, (s_min, s_max), ClosestHit)
    }

    /// Runs `search` with the lanes that suit the ray (its chart's f32 boxes, or the discs),
    /// after the two tests that turn most rays away before their frame is built.
    #[inline(always)]
    fn search<S: Search>(
        &self,
        space: Space,
        ray: &Ray,
        (s_min, s_max): (f64, f64),
        search: S,
    ) -> S::Found {
        debug_assert_eq!(
            space.kappa(),
            self.kappa,
            "the BVH was built for another geometry"
        );
        if !self.heights_met(ray, s_min, s_max) || self.root_missed(ray) {
            return S::MISSED;
        }
        let frame = RayFrame::new(space, ray);
        let at = Segment {
            space,
            frame: &frame,
            s_min,
            s_max,
        };
        match self.chart_lanes(&frame, s_min) {
            Some(lanes) if self.kappa > 0.0 => search.run(self, &at, &BoxLanes::<1>(lanes)),
            Some(lanes) => search.run(self, &at, &BoxLanes::<0>(lanes)),
            None => {
                let lanes = DiscLanes {
                    frame: &frame,
                    s_lo: s_min,
                };
                search.run(self, &at, &lanes)
            }
        }
    }

    /// The ray's [`ChartLanes`], where the mesh has a chart and the ray is seen in it.
    #[inline(always)]
    fn chart_lanes(&self, frame: &RayFrame, s_min: f64) -> Option<ChartLanes> {
        let chart = self.chart.as_ref()?;
        let ray = ChartRay::new(chart, frame)?;
        ChartLanes::new(&ray, frame, self.lane_extent[0], self.lane_extent[1], s_min)
    }

    /// The nearest hit, the children tested by `lanes`.
    #[inline(always)]
    fn closest_hit<L: Lanes>(&self, at: &Segment, lanes: &L) -> Option<TriangleHit> {
        let Segment {
            space,
            frame,
            s_min,
            s_max,
        } = *at;
        let mut best_s = s_max;
        let mut bound = lanes.bound(s_max);
        let entry = lanes.entries(self, &self.root_node, None, bound)[0];
        if !is_met(entry, bound) {
            return None; // missed
        }
        let mut best = None;
        // Not an array: zeroing the whole stack for every ray would cost more than a short
        // traversal.
        let mut stack = ArrayVec::<StackEntry<L::E>, STACK>::new();
        stack.push(StackEntry {
            index: 0,
            count: 0,
            entry,
        });
        while let Some(pending) = stack.pop() {
            if pending.entry > bound {
                continue;
            }
            if pending.count > 0 {
                let start = pending.index as usize;
                for t in start..start + pending.count as usize {
                    if let Some(c) = self.prepared[t].intersect_in(space, frame, s_min, best_s)
                        && c.s <= best_s
                    {
                        best_s = c.s;
                        bound = lanes.bound(best_s);
                        best = Some(TriangleHit {
                            s: c.s,
                            triangle: self.order[t],
                            barycentric: c.barycentric,
                        });
                    }
                }
                continue;
            }
            let at = pending.index as usize;
            let node = &self.nodes[at];
            let entries = lanes.entries(self, node, Some(at), bound);
            // The children met, farthest first, so that the nearest is taken next.
            let mut met = [(entry, 0usize); WIDTH];
            let mut n = 0;
            let mut mask = met_mask(&entries, bound);
            while mask != 0 {
                let slot = mask.trailing_zeros() as usize;
                mask &= mask - 1;
                let e = entries[slot];
                {
                    let mut j = n;
                    while j > 0 && met[j - 1].0 < e {
                        met[j] = met[j - 1];
                        j -= 1;
                    }
                    met[j] = (e, slot);
                    n += 1;
                    self.prefetch_child(node, slot);
                }
            }
            for &(entry, slot) in &met[..n] {
                stack.push(StackEntry {
                    index: node.index[slot],
                    count: node.count[slot],
                    entry,
                });
            }
        }
        best
    }

    /// [`Bvh::occluded`], compiled anew into each of its copies.
    #[inline(always)]
    pub(super) fn occluded_portable(
        &self,
        space: Space,
        ray: &Ray,
        s_min: f64,
        s_max: f64,
    ) -> bool {
        self.search(space, ray, (s_min, s_max), AnyHit)
    }

    /// Whether any triangle is hit, the children tested by `lanes`.
    #[inline(always)]
    fn any_hit<L: Lanes>(&self, at: &Segment, lanes: &L) -> bool {
        let Segment {
            space,
            frame,
            s_min,
            s_max,
        } = *at;
        let bound = lanes.bound(s_max);
        if !is_met(lanes.entries(self, &self.root_node, None, bound)[0], bound) {
            return false; // missed
        }
        let mut stack = ArrayVec::<(u32, u32), STACK>::new();
        stack.push((0, 0));
        while let Some((index, count)) = stack.pop() {
            if count > 0 {
                let start = index as usize;
                if self.prepared[start..start + count as usize]
                    .iter()
                    .any(|t| t.intersect_in(space, frame, s_min, s_max).is_some())
                {
                    return true;
                }
                continue;
            }
            let at = index as usize;
            let node = &self.nodes[at];
            let entries = lanes.entries(self, node, Some(at), bound);
            let mut mask = met_mask(&entries, bound);
            while mask != 0 {
                let slot = mask.trailing_zeros() as usize;
                mask &= mask - 1;
                self.prefetch_child(node, slot);
                stack.push((node.index[slot], node.count[slot]));
            }
        }
        false
    }

    /// Starts bringing a child that was met into the cache (its node, or its leaf's
    /// triangles): the nearest is read right after, and the nodes and triangles of a mesh of
    /// tens of thousands of triangles do not fit the core's own caches, so that the traversal
    /// would otherwise wait for the first read of each node and of each triangle.
    #[inline(always)]
    fn prefetch_child(&self, node: &Node, slot: usize) {
        const NODE_LINES: usize = size_of::<Node>() / 64;
        const TRIANGLE_BYTES: usize = size_of::<PreparedTriangle>();
        let (index, count) = (node.index[slot] as usize, node.count[slot] as usize);
        if count == 0 {
            if let Some(child) = self.nodes.get(index) {
                crate::cpu::prefetch(child, NODE_LINES);
            }
        } else if let Some(first) = self.prepared.get(index) {
            crate::cpu::prefetch(first, (count * TRIANGLE_BYTES).div_ceil(64));
        }
    }

    /// Whether the ray is within the mesh's heights somewhere in `[s_min, s_max]`: the root
    /// bound's height test, done before the ray's frame is built (which costs more than the
    /// test): most rays between two mirrors of a room pass above or below the object.
    #[inline(always)]
    fn heights_met(&self, ray: &Ray, s_min: f64, s_max: f64) -> bool {
        let Some(root) = self.root.as_ref() else {
            return false;
        };
        // As `RayFrame::new` computes them, so that this never rejects what `entry` accepts.
        let climb = (
            ray.height,
            1.0 / ray.sin_elevation,
            ray.sin_elevation == 0.0,
        );
        height_slab(climb, (root.h_lo, root.h_hi), (s_min, s_max)).is_some()
    }

    /// Whether the ray's whole horizontal geodesic misses the root's disc, by two dot
    /// products and no division or square root: the distance d⊥ from the disc's centre c to
    /// the geodesic has C(d⊥)² = α² + κβ² with α = C(d(p, c)) = 1 − κ·½|p − c|²_κ and
    /// β = κ⟨u, c⟩ (the chart's α and β, [`ChartRay`]), and on E² d⊥² = |p − c|² − ⟨p − c, u⟩².
    /// Many of the rays that pass [`Bvh::heights_met`] miss the object's disc: they are turned
    /// away before their frame is built. Also right for a vertical ray, whose geodesic through p
    /// meets the disc wherever p is in it.
    #[inline(always)]
    fn root_missed(&self, ray: &Ray) -> bool {
        let Some(root) = self.root.as_ref() else {
            return true;
        };
        let k = self.kappa;
        if root.reach == f64::INFINITY {
            return false;
        }
        let dot = |a: DVec3, b: DVec3| a.x * b.x + a.y * b.y + k * a.z * b.z;
        let d = ray.origin - root.centre;
        let dd = dot(d, d);
        if k == 0.0 {
            let along = dot(d, ray.direction);
            let perp2 = dd - along * along;
            return perp2 > 2.0 * root.reach + 1e-9 * (dd + 2.0 * root.reach) + 1e-12;
        }
        let alpha = 1.0 - 0.5 * k * dd;
        let beta = k * dot(ray.direction, root.centre);
        let c2 = alpha * alpha + k * beta * beta;
        let limit = (1.0 - k * root.reach) * (1.0 - k * root.reach);
        let margin = 1e-9 * (alpha * alpha + beta * beta + limit) + 1e-12;
        if k < 0.0 {
            c2 > limit + margin
        } else {
            c2 < limit - margin
        }
    }
}

#[cfg(test)]
mod tests {
    use orbifold::Geometry;

    use super::*;
    use crate::test_util::uniforms;
    use crate::triangle::Triangle;

    /// The AVX2 copies of the traversals (what `intersect` and `occluded` run on a processor
    /// with AVX2) return exactly what the portable ones do (the same operations, wider
    /// registers): a random soup of triangles, random rays, every geometry.
    #[test]
    #[cfg(target_arch = "x86_64")]
    fn the_avx2_traversals_are_the_portable_ones_bit_for_bit() {
        if !crate::cpu::has_avx2_fma() {
            eprintln!("skipped: no AVX2 and FMA here");
            return;
        }
        for g in [
            Geometry::Spherical,
            Geometry::Euclidean,
            Geometry::Hyperbolic,
        ] {
            let space = Space::new(g);
            let mut u = uniforms(7);
            let point = |u: &mut dyn FnMut() -> f64| {
                let v = DVec3::new(u() - 0.5, u() - 0.5, 0.0) * 1.6;
                (space.exp(DVec3::Z, v), u())
            };
            let (points, heights): (Vec<DVec3>, Vec<f64>) = (0..600).map(|_| point(&mut u)).unzip();
            let triangles: Vec<[u32; 3]> =
                (0..200).map(|t| [3 * t, 3 * t + 1, 3 * t + 2]).collect();
            let bvh = Bvh::build(space, &points, &heights, &triangles);
            let mut hits = 0;
            for _ in 0..2000 {
                let (origin, h) = point(&mut u);
                let angle = std::f64::consts::TAU * u();
                let direction = DVec3::new(angle.cos(), angle.sin(), 0.0);
                let direction = space.transport(DVec3::Z, origin, direction);
                let ray = Ray::new(space, origin, direction, h, 1.4 * (u() - 0.5));
                let s_max = 4.0 * u();
                let portable = bvh.intersect_portable(space, &ray, 0.0, s_max);
                let avx2 = bvh.intersect(space, &ray, 0.0, s_max);
                assert_eq!(
                    portable.map(|h| (h.s.to_bits(), h.triangle)),
                    avx2.map(|h| (h.s.to_bits(), h.triangle))
                );
                hits += usize::from(avx2.is_some());
                let portable = bvh.occluded_portable(space, &ray, 0.0, s_max);
                let avx2 = bvh.occluded(space, &ray, 0.0, s_max);
                assert_eq!(portable, avx2);
            }
            assert!(hits > 100, "{g:?}: only {hits} hits");
        }
    }

    /// A mesh too wide for a chart (beyond 84° from its centre on S², 3.8 on H²) has none and
    /// is traversed by its discs, with the same hits as testing every triangle.
    #[test]
    fn a_mesh_too_wide_for_a_chart_is_traversed_by_its_discs() {
        for (g, radius) in [(Geometry::Spherical, 1.55), (Geometry::Hyperbolic, 4.2)] {
            let space = Space::new(g);
            let mut rnd = uniforms(777);
            let (mut points, mut heights, mut triangles) = (Vec::new(), Vec::new(), Vec::new());
            for t in 0..400u32 {
                let angle = std::f64::consts::TAU * rnd();
                let r = radius * rnd().sqrt();
                let centre = DVec3::new(r * angle.cos(), r * angle.sin(), 0.0);
                for _ in 0..3 {
                    let v = centre + DVec3::new(rnd() - 0.5, rnd() - 0.5, 0.0) * 0.2;
                    points.push(space.exp(DVec3::Z, v));
                    heights.push(rnd());
                }
                triangles.push([3 * t, 3 * t + 1, 3 * t + 2]);
            }
            let bvh = Bvh::build(space, &points, &heights, &triangles);
            assert!(
                bvh.chart.is_none(),
                "{g:?}: a chart for a mesh {radius} wide"
            );
            let mut hits = 0;
            for _ in 0..400 {
                let origin =
                    space.exp(DVec3::Z, DVec3::new(rnd() - 0.5, rnd() - 0.5, 0.0) * radius);
                let dir = DVec3::new(rnd() - 0.5, rnd() - 0.5, 0.0);
                let ray = Ray::new(space, origin, dir, rnd(), 0.6 * (rnd() - 0.5));
                let expected = triangles
                    .iter()
                    .enumerate()
                    .filter_map(|(t, tri)| {
                        let tri = Triangle::new(
                            tri.map(|i| points[i as usize]),
                            tri.map(|i| heights[i as usize]),
                        );
                        Some((t as u32, tri.intersect(space, &ray, 0.0, 6.0)?.s))
                    })
                    .min_by(|a, b| a.1.total_cmp(&b.1));
                let got = bvh
                    .intersect(space, &ray, 0.0, 6.0)
                    .map(|h| (h.triangle, h.s));
                match (got, expected) {
                    (Some((t, s)), Some((u, e))) => {
                        assert!(t == u && (s - e).abs() < 1e-12, "{g:?}: {ray:?}");
                    }
                    (got, expected) => assert_eq!(got, expected, "{g:?}: {ray:?}"),
                }
                assert_eq!(bvh.occluded(space, &ray, 0.0, 6.0), expected.is_some());
                hits += usize::from(expected.is_some());
            }
            assert!(hits > 40, "{g:?}: only {hits} hits");
        }
    }

    /// The quick root test turns a ray away only when its whole horizontal geodesic misses the
    /// mesh's disc (no point of it, sampled both ways from the origin, is inside), and it turns
    /// away most of those that do miss by more than a sampling step.
    #[test]
    fn the_quick_root_test_turns_away_only_rays_that_miss_the_disc() {
        for g in [
            Geometry::Spherical,
            Geometry::Euclidean,
            Geometry::Hyperbolic,
        ] {
            let space = Space::new(g);
            let mut rnd = uniforms(4242);
            let (mut missed, mut turned_away) = (0, 0);
            for case in 0..400 {
                let centre = space.exp(DVec3::Z, DVec3::new(rnd() - 0.5, rnd() - 0.5, 0.0));
                let points: Vec<DVec3> = (0..6)
                    .map(|_| {
                        space.exp(
                            centre,
                            space.tangent_frame(centre)[0] * (0.4 * rnd() - 0.2)
                                + space.tangent_frame(centre)[1] * (0.4 * rnd() - 0.2),
                        )
                    })
                    .collect();
                let heights = [0.0; 6];
                let bvh = Bvh::build(space, &points, &heights, &[[0, 1, 2], [3, 4, 5]]);
                let root = bvh.root.unwrap();
                let r = 2.0 * space.asin((0.5 * root.reach).sqrt());
                let far = if case % 5 == 0 { 4.0 } else { 1.5 };
                let origin = space.exp(DVec3::Z, DVec3::new(rnd() - 0.5, rnd() - 0.5, 0.0) * far);
                let elevation = if case % 7 == 0 {
                    std::f64::consts::FRAC_PI_2
                } else {
                    0.3
                };
                let ray = Ray::new(
                    space,
                    origin,
                    DVec3::new(rnd() - 0.5, rnd() - 0.5, 0.0),
                    0.0,
                    elevation,
                );
                let horizontal = Ray::new(space, ray.origin, ray.direction, 0.0, 0.0);
                let reach = if g == Geometry::Spherical {
                    std::f64::consts::PI
                } else {
                    12.0
                };
                let nearest = (-2000..=2000)
                    .map(|i| {
                        let (x, _) = horizontal.point_at(space, reach * f64::from(i) / 2000.0);
                        space.ambient_distance(x, root.centre)
                    })
                    .fold(f64::INFINITY, f64::min);
                let turned = bvh.root_missed(&ray);
                if elevation == std::f64::consts::FRAC_PI_2 {
                    let d = space.ambient_distance(ray.origin, root.centre);
                    assert!(
                        !(turned && d <= r),
                        "{g:?}: a vertical ray over the disc turned away"
                    );
                    continue;
                }
                assert!(
                    !(turned && nearest <= r),
                    "{g:?}: turned away at {nearest} from a disc of {r}"
                );
                if nearest > r + 0.01 {
                    missed += 1;
                    turned_away += usize::from(turned);
                }
            }
            assert!(
                missed > 50 && turned_away == missed,
                "{g:?}: {turned_away} of {missed} misses turned away"
            );
        }
    }
}
