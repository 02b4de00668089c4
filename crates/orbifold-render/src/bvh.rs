//! A bounding volume hierarchy for curved rays (DESIGN.md §8).
//!
//! Bounds are **geodesic discs × height intervals**: a centre c (ambient), an intrinsic radius r and
//! [h_min, h_max]. They are invariant under isometries, so a mesh's BVH never changes when the mesh
//! is moved (see [`crate::instance`]). A triangle's footprint lies in the geodesic convex hull of
//! its vertices, and a geodesic disc is convex (on the sphere when r < π/2; larger bounds are
//! replaced by the whole sphere), so a disc that contains a node's vertices contains its triangles.
//!
//! **Ray–bound test (closed form).** Let v = J u be the unit tangent at the ray's origin p
//! perpendicular to its horizontal direction u. The distance d⊥ from c to the ray's horizontal
//! geodesic has S(d⊥) = ⟨c − p, v⟩ =: γ, and with V(d) = ½|x − c|²_κ (1 − cos d, d²/2, cosh d − 1)
//! the point at horizontal distance σ is inside the disc iff V(σ − σ_c) ≤ (V(r) − V(d⊥))/C(d⊥)
//! (spherical, Euclidean and hyperbolic Pythagoras), where V(d⊥) = γ²/(1 + C(d⊥)) and
//! C(d⊥) = √(1 − κγ²) are computed without cancellation. The first comparison, V(d⊥) ≤ V(r),
//! needs no transcendental function; then the half-width w and the foot σ_c give a σ-interval,
//! which is intersected with the height slab's interval and the ray's current [s_min, s_best].
//!
//! **Build.** Top-down binned SAH over the triangles' vertices in tangent coordinates at the mesh's
//! centre (`Space::log`) and height, leaves of at most four triangles, subtrees built in parallel
//! with rayon above a size; the nodes are a flat array (48 bytes each) with siblings adjacent.

use std::f64::consts::{FRAC_PI_2, TAU};

use glam::DVec3;
use orbifold::space::Space;

use crate::fastmath::{LN_FAST_ERROR, asinh_fast};
use crate::geodesic::Ray;
/// A hit on a mesh's triangle (defined in [`crate::triangle`]).
pub use crate::triangle::TriangleHit;
use crate::triangle::{PreparedTriangle, Triangle};

/// Most triangles in a leaf.
const LEAF_SIZE: usize = 4;
/// SAH bins per axis.
const BINS: usize = 16;
/// Subtrees with more triangles than this are built on another thread.
const PARALLEL_THRESHOLD: usize = 2048;
/// Below this depth SAH decides the split; deeper, the median (so the depth stays bounded).
const SAH_DEPTH: usize = 48;
/// Traversal stack size (the depth is at most `SAH_DEPTH` + log₂ of the triangle count).
const STACK: usize = 128;

/// A node: a geodesic disc × height interval, and either two adjacent children or a leaf range.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Node {
    /// Ambient centre of the disc.
    centre: DVec3,
    /// V(r) = ½|x − c|²_κ at the (slightly enlarged) radius; +∞ for the whole plane.
    reach: f64,
    /// Height interval, rounded outwards to f32.
    heights: [f32; 2],
    /// First child (interior) or first triangle (leaf).
    index: u32,
    /// Number of triangles (0 for an interior node).
    count: u32,
}

/// A bounding disc × height interval in full precision.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Bound {
    pub(crate) centre: DVec3,
    pub(crate) reach: f64,
    pub(crate) h_lo: f64,
    pub(crate) h_hi: f64,
}

/// A BVH over a triangle mesh whose bounds are geodesic discs × height intervals.
///
/// ```
/// use orbifold::{Geometry, space::Space};
/// use orbifold_render::bvh::Bvh;
/// use orbifold_render::geodesic::Ray;
/// use glam::DVec3;
/// let s2 = Space::new(Geometry::Spherical);
/// let p = |x: f64, y: f64| s2.exp(DVec3::Z, DVec3::new(x, y, 0.0));
/// // A wall-like square at x = 0.5 from height 0 to 1, as two triangles.
/// let points = [p(0.5, -0.2), p(0.5, 0.2), p(0.5, 0.2), p(0.5, -0.2)];
/// let heights = [0.0, 0.0, 1.0, 1.0];
/// let bvh = Bvh::build(s2, &points, &heights, &[[0, 1, 2], [0, 2, 3]]);
/// let ray = Ray::new(s2, DVec3::Z, DVec3::X, 0.5, 0.0);
/// let hit = bvh.intersect(s2, &ray, 0.0, 10.0).unwrap();
/// // The wall's geodesic bows away from the origin: it is crossed a little after 0.5.
/// assert!(hit.s > 0.5 && hit.s < 0.51);
/// let (x, h) = bvh.point(s2, &hit);
/// let (y, k) = ray.point_at(s2, hit.s);
/// assert!((x - y).length() < 1e-12 && (h - k).abs() < 1e-12);
/// assert!(bvh.occluded(s2, &ray, 0.0, 10.0) && !bvh.occluded(s2, &ray, 0.0, 0.5));
/// ```
#[derive(Clone, Debug)]
pub struct Bvh {
    kappa: f64,
    nodes: Vec<Node>,
    /// Triangles in leaf order, prepared for ray tests.
    prepared: Vec<PreparedTriangle>,
    /// For each prepared triangle, its index in the input.
    order: Vec<u32>,
    points: Vec<DVec3>,
    heights: Vec<f64>,
    triangles: Vec<[u32; 3]>,
    depth: usize,
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

/// Per-ray quantities for the ray–bound test, computed once per traversal.
#[derive(Clone, Copy, Debug)]
pub(crate) struct RayFrame {
    kappa: f64,
    p: DVec3,
    u: DVec3,
    v: DVec3,
    pu: f64,
    pv: f64,
    h: f64,
    ca: f64,
    inv_ca: f64,
    sa: f64,
    inv_sa: f64,
    level: bool,
    vertical: bool,
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
        }
    }

    #[inline(always)]
    fn dot(&self, a: DVec3, b: DVec3) -> f64 {
        a.x * b.x + a.y * b.y + self.kappa * a.z * b.z
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
        let (mut lo, mut hi) = (s_lo, s_hi);
        if self.level {
            if self.h < h_lo || self.h > h_hi {
                return None;
            }
        } else {
            let t1 = (h_lo - self.h) * self.inv_sa;
            let t2 = (h_hi - self.h) * self.inv_sa;
            lo = lo.max(t1.min(t2));
            hi = hi.min(t1.max(t2));
        }
        (lo <= hi).then_some((lo, hi))
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
        } else if k == 0.0 {
            (2.0 * x, cu)
        } else {
            (2.0 * asinh_fast(x), asinh_fast(cu / m))
        };
        // Rounding, and on H² the two fast logarithms' errors.
        let w = w * (1.0 + 1e-9) + 1e-12 * (1.0 + centre_sigma.abs()) + 3.0 * LN_FAST_ERROR;
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
            let turns = ((sigma_lo - end) / TAU).ceil();
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

    /// [`RayFrame::entry`] for a stored node.
    #[inline(always)]
    fn node_entry(&self, node: &Node, s_lo: f64, s_hi: f64) -> Option<f64> {
        self.entry(
            node.centre,
            node.reach,
            f64::from(node.heights[0]),
            f64::from(node.heights[1]),
            s_lo,
            s_hi,
        )
    }
}

/// A triangle's place in SAH space (tangent coordinates at the mesh centre, and height).
#[derive(Clone, Copy, Debug)]
struct Key {
    centroid: DVec3,
    lo: DVec3,
    hi: DVec3,
}

/// A node of the tree before flattening.
enum Temp {
    Leaf(Bound, u32, u32),
    Inner(Bound, Box<[Temp; 2]>),
}

struct Builder<'a> {
    space: Space,
    points: &'a [DVec3],
    heights: &'a [f64],
    triangles: &'a [[u32; 3]],
    keys: Vec<Key>,
}

/// Axis-aligned box in SAH space.
#[derive(Clone, Copy)]
struct Aabb {
    lo: DVec3,
    hi: DVec3,
}

impl Aabb {
    const EMPTY: Aabb = Aabb {
        lo: DVec3::INFINITY,
        hi: DVec3::NEG_INFINITY,
    };

    fn grow(&mut self, lo: DVec3, hi: DVec3) {
        self.lo = self.lo.min(lo);
        self.hi = self.hi.max(hi);
    }

    fn area(&self) -> f64 {
        let d = (self.hi - self.lo).max(DVec3::ZERO);
        2.0 * (d.x * d.y + d.y * d.z + d.z * d.x)
    }
}

/// Rounds down to an f32 that is ≤ x.
fn f32_below(x: f64) -> f32 {
    let y = x as f32;
    if f64::from(y) > x { y.next_down() } else { y }
}

/// Rounds up to an f32 that is ≥ x.
fn f32_above(x: f64) -> f32 {
    let y = x as f32;
    if f64::from(y) < x { y.next_up() } else { y }
}

impl Builder<'_> {
    /// The bounding disc × height interval of some triangles' vertices.
    fn bound(&self, tris: &[u32]) -> Bound {
        let (mut h_lo, mut h_hi) = (f64::INFINITY, f64::NEG_INFINITY);
        for &t in tris {
            for &i in &self.triangles[t as usize] {
                let h = self.heights[i as usize];
                h_lo = h_lo.min(h);
                h_hi = h_hi.max(h);
            }
        }
        let vertices = tris
            .iter()
            .flat_map(|&t| self.triangles[t as usize])
            .map(|i| &self.points[i as usize]);
        let (centre, reach) =
            disc_around(self.space, vertices).unwrap_or((DVec3::Z, f64::INFINITY));
        Bound {
            centre,
            reach,
            h_lo,
            h_hi,
        }
    }

    /// Splits `tris` in two (returns the size of the first part), by binned SAH or the median.
    fn split(&self, tris: &mut [u32], sah: bool) -> usize {
        let mut centroids = Aabb::EMPTY;
        for &t in tris.iter() {
            let c = self.keys[t as usize].centroid;
            centroids.grow(c, c);
        }
        let extent = centroids.hi - centroids.lo;
        if sah {
            let mut best: Option<(f64, usize, usize)> = None; // (cost, axis, last bin on the left)
            for axis in 0..3 {
                if extent[axis].is_nan() || extent[axis] <= 0.0 {
                    continue;
                }
                let scale = BINS as f64 / extent[axis];
                let mut boxes = [Aabb::EMPTY; BINS];
                let mut counts = [0usize; BINS];
                for &t in tris.iter() {
                    let key = &self.keys[t as usize];
                    let b = (((key.centroid[axis] - centroids.lo[axis]) * scale) as usize)
                        .min(BINS - 1);
                    boxes[b].grow(key.lo, key.hi);
                    counts[b] += 1;
                }
                let mut right_area = [0.0; BINS];
                let mut right_count = [0usize; BINS];
                let (mut acc, mut n) = (Aabb::EMPTY, 0);
                for b in (1..BINS).rev() {
                    acc.grow(boxes[b].lo, boxes[b].hi);
                    n += counts[b];
                    right_area[b] = acc.area();
                    right_count[b] = n;
                }
                let (mut acc, mut n) = (Aabb::EMPTY, 0);
                for b in 0..BINS - 1 {
                    acc.grow(boxes[b].lo, boxes[b].hi);
                    n += counts[b];
                    if n == 0 || right_count[b + 1] == 0 {
                        continue;
                    }
                    let cost =
                        acc.area() * n as f64 + right_area[b + 1] * right_count[b + 1] as f64;
                    if best.is_none_or(|(c, _, _)| cost < c) {
                        best = Some((cost, axis, b));
                    }
                }
            }
            if let Some((_, axis, bin)) = best {
                let scale = BINS as f64 / extent[axis];
                let lo = centroids.lo[axis];
                let keys = &self.keys;
                let left = |t: &u32| {
                    (((keys[*t as usize].centroid[axis] - lo) * scale) as usize).min(BINS - 1)
                        <= bin
                };
                let mut mid = 0;
                for i in 0..tris.len() {
                    if left(&tris[i]) {
                        tris.swap(i, mid);
                        mid += 1;
                    }
                }
                if mid > 0 && mid < tris.len() {
                    return mid;
                }
            }
        }
        let axis = extent.max_position();
        let mid = tris.len() / 2;
        let keys = &self.keys;
        tris.select_nth_unstable_by(mid, |a, b| {
            keys[*a as usize].centroid[axis].total_cmp(&keys[*b as usize].centroid[axis])
        });
        mid
    }

    fn build(&self, tris: &mut [u32], offset: usize, depth: usize) -> Temp {
        let bound = self.bound(tris);
        if tris.len() <= LEAF_SIZE {
            return Temp::Leaf(bound, offset as u32, tris.len() as u32);
        }
        let mid = self.split(tris, depth < SAH_DEPTH);
        let size = tris.len();
        let (left, right) = tris.split_at_mut(mid);
        let (a, b) = if size > PARALLEL_THRESHOLD {
            rayon::join(
                || self.build(left, offset, depth + 1),
                || self.build(right, offset + mid, depth + 1),
            )
        } else {
            (
                self.build(left, offset, depth + 1),
                self.build(right, offset + mid, depth + 1),
            )
        };
        Temp::Inner(bound, Box::new([a, b]))
    }
}

fn to_node(bound: &Bound, index: u32, count: u32) -> Node {
    Node {
        centre: bound.centre,
        reach: bound.reach,
        heights: [f32_below(bound.h_lo), f32_above(bound.h_hi)],
        index,
        count,
    }
}

/// Writes `temp` at `at` and its descendants after the current end; returns the subtree's depth.
fn flatten(temp: Temp, at: usize, nodes: &mut Vec<Node>) -> usize {
    match temp {
        Temp::Leaf(bound, start, count) => {
            nodes[at] = to_node(&bound, start, count);
            1
        }
        Temp::Inner(bound, children) => {
            let first = nodes.len();
            nodes[at] = to_node(&bound, first as u32, 0);
            let placeholder = nodes[at];
            nodes.extend([placeholder; 2]);
            let [a, b] = *children;
            let da = flatten(a, first, nodes);
            let db = flatten(b, first + 1, nodes);
            1 + da.max(db)
        }
    }
}

impl Bvh {
    /// Builds the BVH of a mesh: ambient vertex positions, vertex heights and triangles (indices
    /// into both). Degenerate triangles (zero determinant) are left out: they are never hit.
    ///
    /// # Panics
    ///
    /// When `points` and `heights` differ in length or a triangle indexes past them.
    pub fn build(space: Space, points: &[DVec3], heights: &[f64], triangles: &[[u32; 3]]) -> Bvh {
        assert_eq!(points.len(), heights.len(), "one height per point");
        assert!(
            triangles
                .iter()
                .flatten()
                .all(|&i| (i as usize) < points.len()),
            "triangle index out of range"
        );
        let mut tris: Vec<u32> = (0..triangles.len() as u32)
            .filter(|&t| {
                let [a, b, c] = triangles[t as usize].map(|i| i as usize);
                PreparedTriangle::new(
                    space,
                    [points[a], points[b], points[c]],
                    [heights[a], heights[b], heights[c]],
                )
                .is_some()
            })
            .collect();
        let mut bvh = Bvh {
            kappa: space.kappa(),
            nodes: Vec::new(),
            prepared: Vec::new(),
            order: Vec::new(),
            points: points.to_vec(),
            heights: heights.to_vec(),
            triangles: triangles.to_vec(),
            depth: 0,
        };
        if tris.is_empty() {
            return bvh;
        }

        // SAH keys: tangent coordinates at the mesh centre, and height.
        let sum: DVec3 = tris
            .iter()
            .flat_map(|&t| triangles[t as usize])
            .map(|i| points[i as usize])
            .sum();
        let mut centre = space.normalize_point(sum);
        if !centre.is_finite() {
            centre = points[triangles[tris[0] as usize][0] as usize];
        }
        let k = space.kappa();
        let tangent = |v: DVec3| {
            if k == 0.0 {
                DVec3::new(v.x, v.y, 0.0)
            } else {
                v - centre * (k * space.point_dot(centre, v))
            }
        };
        let mut e1 = tangent(DVec3::X);
        if space.point_dot(e1, e1) < 0.25 {
            e1 = tangent(DVec3::Y);
        }
        let e1 = e1 / space.point_dot(e1, e1).sqrt();
        let e2 = space.quarter_turn(centre, e1);
        let vertex_key = |i: u32| {
            let l = space.log(centre, points[i as usize]);
            DVec3::new(
                space.point_dot(l, e1),
                space.point_dot(l, e2),
                heights[i as usize],
            )
        };
        let vertex_keys: Vec<DVec3> = (0..points.len() as u32).map(vertex_key).collect();
        let keys = triangles
            .iter()
            .map(|t| {
                let [a, b, c] = t.map(|i| vertex_keys[i as usize]);
                Key {
                    centroid: (a + b + c) / 3.0,
                    lo: a.min(b).min(c),
                    hi: a.max(b).max(c),
                }
            })
            .collect();
        let builder = Builder {
            space,
            points,
            heights,
            triangles,
            keys,
        };
        let root = builder.build(&mut tris, 0, 0);
        let mut nodes = Vec::with_capacity(2 * tris.len() / LEAF_SIZE + 1);
        nodes.push(to_node(
            &Bound {
                centre: DVec3::Z,
                reach: 0.0,
                h_lo: 0.0,
                h_hi: 0.0,
            },
            0,
            0,
        ));
        bvh.depth = flatten(root, 0, &mut nodes);
        bvh.nodes = nodes;
        bvh.prepared = tris
            .iter()
            .map(|&t| {
                let [a, b, c] = triangles[t as usize].map(|i| i as usize);
                PreparedTriangle::new(
                    space,
                    [points[a], points[b], points[c]],
                    [heights[a], heights[b], heights[c]],
                )
                .expect("kept triangles are not degenerate")
            })
            .collect();
        bvh.order = tris;
        bvh
    }

    /// The nearest hit at arc length in `[s_min, s_max]` (`s_min` finite), or `None`.
    pub fn intersect(
        &self,
        space: Space,
        ray: &Ray,
        s_min: f64,
        s_max: f64,
    ) -> Option<TriangleHit> {
        debug_assert_eq!(
            space.kappa(),
            self.kappa,
            "the BVH was built for another geometry"
        );
        let frame = RayFrame::new(space, ray);
        let mut best_s = s_max;
        let mut best = None;
        let root = self.nodes.first()?;
        let entry = frame.node_entry(root, s_min, best_s)?;
        let mut stack = [(0u32, 0.0f64); STACK];
        stack[0] = (0, entry);
        let mut top = 1;
        while top > 0 {
            top -= 1;
            let (index, entry) = stack[top];
            if entry > best_s {
                continue;
            }
            let node = &self.nodes[index as usize];
            if node.count > 0 {
                let start = node.index as usize;
                for t in start..start + node.count as usize {
                    if let Some(c) = self.prepared[t].intersect_in(space, &frame, s_min, best_s)
                        && c.s <= best_s
                    {
                        best_s = c.s;
                        best = Some(TriangleHit {
                            s: c.s,
                            triangle: self.order[t],
                            barycentric: c.barycentric,
                        });
                    }
                }
                continue;
            }
            let first = node.index as usize;
            let a = frame.node_entry(&self.nodes[first], s_min, best_s);
            let b = frame.node_entry(&self.nodes[first + 1], s_min, best_s);
            match (a, b) {
                (Some(a), Some(b)) => {
                    let (near, far) = if a <= b {
                        ((first, a), (first + 1, b))
                    } else {
                        ((first + 1, b), (first, a))
                    };
                    stack[top] = (far.0 as u32, far.1);
                    stack[top + 1] = (near.0 as u32, near.1);
                    top += 2;
                }
                (Some(a), None) => {
                    stack[top] = (first as u32, a);
                    top += 1;
                }
                (None, Some(b)) => {
                    stack[top] = (first as u32 + 1, b);
                    top += 1;
                }
                (None, None) => {}
            }
        }
        best
    }

    /// Whether the ray meets any triangle at arc length in `[s_min, s_max]` (for shadow rays).
    pub fn occluded(&self, space: Space, ray: &Ray, s_min: f64, s_max: f64) -> bool {
        debug_assert_eq!(
            space.kappa(),
            self.kappa,
            "the BVH was built for another geometry"
        );
        let frame = RayFrame::new(space, ray);
        if self.nodes.is_empty() {
            return false;
        }
        let mut stack = [0u32; STACK];
        let mut top = 1;
        while top > 0 {
            top -= 1;
            let node = &self.nodes[stack[top] as usize];
            if frame.node_entry(node, s_min, s_max).is_none() {
                continue;
            }
            if node.count > 0 {
                let start = node.index as usize;
                if self.prepared[start..start + node.count as usize]
                    .iter()
                    .any(|t| t.intersect_in(space, &frame, s_min, s_max).is_some())
                {
                    return true;
                }
                continue;
            }
            stack[top] = node.index + 1;
            stack[top + 1] = node.index;
            top += 2;
        }
        false
    }

    /// The triangle with this index in the input list.
    pub fn triangle(&self, index: u32) -> Triangle {
        let [a, b, c] = self.triangles[index as usize].map(|i| i as usize);
        Triangle::new(
            [self.points[a], self.points[b], self.points[c]],
            [self.heights[a], self.heights[b], self.heights[c]],
        )
    }

    /// The point of a hit (ambient horizontal position, height) on its triangle.
    pub fn point(&self, space: Space, hit: &TriangleHit) -> (DVec3, f64) {
        self.triangle(hit.triangle).point(space, hit.barycentric)
    }

    /// The unit surface normal at a hit, see [`Triangle::normal`].
    pub fn normal(&self, space: Space, hit: &TriangleHit) -> Option<(DVec3, f64)> {
        self.triangle(hit.triangle).normal(space, hit.barycentric)
    }

    /// The bound of the whole mesh (`None` when it has no triangle).
    pub(crate) fn bound(&self) -> Option<Bound> {
        self.nodes.first().map(|n| Bound {
            centre: n.centre,
            reach: n.reach,
            h_lo: f64::from(n.heights[0]),
            h_hi: f64::from(n.heights[1]),
        })
    }

    /// The depth of the tree (1 for a single leaf, 0 when empty).
    pub fn depth(&self) -> usize {
        self.depth
    }

    /// The number of nodes.
    pub fn node_count(&self) -> usize {
        self.nodes.len()
    }

    /// The number of triangles the BVH was built from (degenerate ones included, though they are
    /// never hit).
    pub fn triangle_count(&self) -> usize {
        self.triangles.len()
    }

    /// The mesh it was built from: ambient points, heights and triangles.
    ///
    /// ```
    /// use glam::DVec3;
    /// use orbifold::{Geometry, space::Space};
    /// use orbifold_render::bvh::Bvh;
    /// let flat = Space::new(Geometry::Euclidean);
    /// let points = [DVec3::new(0.0, 0.0, 1.0), DVec3::new(1.0, 0.0, 1.0), DVec3::new(0.0, 1.0, 1.0)];
    /// let bvh = Bvh::build(flat, &points, &[0.0; 3], &[[0, 1, 2]]);
    /// let (p, h, t) = bvh.mesh();
    /// assert_eq!((p.len(), h.len(), t), (3, 3, &[[0, 1, 2]][..]));
    /// ```
    pub fn mesh(&self) -> (&[DVec3], &[f64], &[[u32; 3]]) {
        (&self.points, &self.heights, &self.triangles)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use orbifold::Geometry;

    #[test]
    fn nodes_are_48_bytes() {
        assert_eq!(std::mem::size_of::<Node>(), 48);
    }

    #[test]
    fn f32_rounding_is_outward() {
        for x in [0.1, -0.1, 1e-30, 3.0, 1.0 / 3.0, -7.123456789] {
            assert!(f64::from(f32_below(x)) <= x && f64::from(f32_above(x)) >= x);
        }
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
            let mut seed = 12345u64;
            let mut rnd = || {
                seed = seed
                    .wrapping_mul(6364136223846793005)
                    .wrapping_add(1442695040888963407);
                (seed >> 11) as f64 / (1u64 << 53) as f64
            };
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
}
