//! A bounding volume hierarchy for curved rays (DESIGN.md §8).
//!
//! **Bounds.** Each node's children are bounded by **boxes in the mesh's gnomonic chart ×
//! height intervals**. The chart (`Chart`) about the mesh's centre c sends a point x to
//! (⟨x − c, e₁⟩, ⟨x − c, e₂⟩)/C(d(x, c)): the Beltrami–Klein model on H², the gnomonic
//! projection of the hemisphere about c on S², the plane itself on E². In all three it takes
//! geodesics to straight lines, so a triangle's footprint is the straight triangle of its
//! vertices' chart points, a node's box is the box of its vertices' chart points (exact, padded
//! by 10⁻⁹ and rounded outwards to f32), and a ray's horizontal geodesic crosses a box on one
//! interval of a straight line. The boxes live in the mesh's own frame, so a mesh's BVH never
//! changes when the mesh is moved (see [`crate::instance`]).
//!
//! **Ray–box test.** A ray is taken once per traversal from the foot of the perpendicular from
//! c to its geodesic (`ChartRay`): there its chart point is affine in T = S(σ')/C(σ') (tan σ',
//! σ', tanh σ' of the horizontal distance σ' from the foot), so each of a box's two slabs is
//! an interval of T found by one multiply-add per side — no square root, division or
//! logarithm. A point of the geodesic within the mesh's radius R of c is within R of the foot,
//! so T is clamped to |T| ≤ T(R); there T⁻¹ is bounded from below at the interval's start and
//! from above at its end by odd polynomials (artanh T between T + T³/3 and that plus
//! T⁵/(5(1 − T(R)²)); arctan T between T − T³/3 and that plus T⁵/5; σ' = T on E²), which widen
//! the interval by at most K·T(R)⁵ (5·10⁻⁴ for the dragon of `*444`, whose R is about ⅓). The
//! σ-interval is then cut by the height slab and the ray's current [s_min, s_best] as before;
//! on S² its first repetition (period 2π) after s_min is taken. The test runs in **f32 lanes,
//! eight children a node** (`ChartLanes`): every quantity is taken in the arc length from the
//! foot, σ' (so that no lane carries the foot's own magnitude), rounded to f32 once a ray, and
//! padded by a bound on the rounding of every product and sum — from the largest chart
//! coordinate and height of any box (the root's) — so that a lane is never later than the
//! exact entry and never misses a box the exact test meets. A nearly level ray, whose heights'
//! σ' would leave f32's range, is tested by its discs.
//!
//! **Discs, where there is no chart.** Every node also keeps its children's **geodesic discs**
//! (`Discs`, apart from the nodes so that the traversal reads four cache lines a node, not
//! three). They are tested instead of the boxes by vertical rays (a point of the chart), and
//! for a mesh too wide for a chart (a vertex more than about 84° from the centre on S², where
//! the gnomonic picture ends at the hemisphere's edge, or 3.8 on H², where the bound on artanh
//! grows without limit). A disc with centre c and intrinsic radius r is convex (on the sphere
//! when r < π/2; larger bounds are replaced by the whole sphere), so a disc that contains a
//! node's vertices contains its triangles. Let v = J u be the unit tangent at the ray's origin p
//! perpendicular to its horizontal direction u. The distance d⊥ from c to the ray's horizontal
//! geodesic has S(d⊥) = ⟨c − p, v⟩ =: γ, and with V(d) = ½|x − c|²_κ (1 − cos d, d²/2, cosh d − 1)
//! the point at horizontal distance σ is inside the disc iff V(σ − σ_c) ≤ (V(r) − V(d⊥))/C(d⊥)
//! (spherical, Euclidean and hyperbolic Pythagoras), where V(d⊥) = γ²/(1 + C(d⊥)) and
//! C(d⊥) = √(1 − κγ²) are computed without cancellation. The first comparison, V(d⊥) ≤ V(r),
//! needs no transcendental function; then the half-width w and the foot σ_c give a σ-interval,
//! which is intersected with the height slab's interval and the ray's current [s_min, s_best].
//! On H² the disc test is cheaper still: sinh²w comes straight from cosh w = cosh r / cosh d⊥,
//! w is bounded from above by a short series rather than taken exactly, and σ_c is half the
//! logarithm of (cosh d(p, c) + |⟨c, u⟩|)²/cosh²d⊥ — one division, one square root and one
//! logarithm a bound (see `hyperbolic_span`). The root's disc is the first test of every ray.
//!
//! **Build.** Top-down binned SAH over the triangles' vertices in the chart (where there is
//! none, in tangent coordinates at the mesh's centre by `Space::log`) and height, each side
//! costed by the area of its box — the shape its bound will have (with discs, by the vertical
//! cylinder around the box, whose area a long thin side's wide disc has) — leaves of at most
//! four triangles, subtrees built in parallel
//! with rayon above a size. The binary tree is then collapsed into an 8-wide one (each node takes
//! its two children, then the largest inner child's two in its place, until it has eight): a
//! flat array of 256-byte nodes that hold their eight children's boxes and heights side by side
//! in f32, and beside it the array of their discs.
//!
//! **Traversal.** A node's eight bounds are tested at once: away from vertical rays the test is
//! straight-line arithmetic (selects for its branches; for discs, `fastmath`'s logarithm and arc
//! tangent, which have no branches and a stated error that the bounds are widened by), so the
//! compiler runs the lanes in SIMD registers (the eight f32 box lanes in one AVX2 register) —
//! where a binary tree waits for one bound test after another. On the dragon of `*444` a
//! traversal visits 5.0 nodes where the 4-wide tree visited 7.3. The children met (a mask of
//! one vector comparison) go on the stack farthest first, their nodes or triangles prefetched;
//! nearest hits prune the rest (`intersect`), any hit ends the search (`occluded`).

use std::f64::consts::{FRAC_PI_2, TAU};

use arrayvec::ArrayVec;
use glam::DVec3;
use orbifold::space::Space;

use crate::fastmath::{ATAN_FAST_ERROR, LN_FAST_ERROR, atan2_fast, ln_fast};
use crate::geodesic::Ray;
use crate::shading_normal::VertexNormals;
/// A hit on a mesh's triangle (defined in [`crate::triangle`]).
pub use crate::triangle::TriangleHit;
use crate::triangle::{PreparedTriangle, Triangle};
use crate::with_avx2;

/// Most triangles in a leaf.
const LEAF_SIZE: usize = 4;
/// SAH bins per axis.
const BINS: usize = 16;
/// Subtrees with more triangles than this are built on another thread.
const PARALLEL_THRESHOLD: usize = 2048;
/// Below this depth SAH decides the split; deeper, the median (so the depth stays bounded).
const SAH_DEPTH: usize = 48;
/// Traversal stack size: each level leaves at most seven children waiting, and the depth is at
/// most `SAH_DEPTH` + log₂ of the triangle count (≤ 96).
const STACK: usize = 7 * 96;

/// Children per node.
const WIDTH: usize = 8;

/// A node: up to eight children's bounds side by side (a structure of arrays, so that one pass
/// of straight-line arithmetic tests all eight), and for each child either the index of its node
/// or its leaf's triangle range. The bounds are boxes in the mesh's chart × height intervals
/// (what the traversal tests, four cache lines); their discs, for meshes without a chart and for
/// vertical rays, are kept apart ([`Discs`]). An empty slot has an empty box and reach −∞,
/// which every ray misses.
#[derive(Clone, Copy, Debug, PartialEq)]
#[repr(C, align(64))]
struct Node {
    /// The children's boxes in the mesh's gnomonic chart ([`Chart`]), rounded outwards to f32.
    gx_lo: [f32; WIDTH],
    gx_hi: [f32; WIDTH],
    gy_lo: [f32; WIDTH],
    gy_hi: [f32; WIDTH],
    /// Height intervals, rounded outwards to f32.
    h_lo: [f32; WIDTH],
    h_hi: [f32; WIDTH],
    /// The child's node (inner child) or first triangle (leaf child).
    index: [u32; WIDTH],
    /// The leaf child's number of triangles; 0 for an inner child.
    count: [u32; WIDTH],
}

/// A node's children's bounding discs (same slots as its [`Node`]).
#[derive(Clone, Copy, Debug, PartialEq)]
#[repr(C, align(64))]
struct Discs {
    /// Ambient centres of the discs.
    x: [f64; WIDTH],
    y: [f64; WIDTH],
    z: [f64; WIDTH],
    /// V(r) = ½|x − c|²_κ at the (slightly enlarged) radii; +∞ for the whole plane.
    reach: [f64; WIDTH],
}

impl Node {
    const EMPTY: Node = Node {
        gx_lo: [f32::INFINITY; WIDTH],
        gx_hi: [f32::NEG_INFINITY; WIDTH],
        gy_lo: [f32::INFINITY; WIDTH],
        gy_hi: [f32::NEG_INFINITY; WIDTH],
        h_lo: [f32::INFINITY; WIDTH],
        h_hi: [f32::NEG_INFINITY; WIDTH],
        index: [0; WIDTH],
        count: [0; WIDTH],
    };

    /// Puts a child's bound in `slot`.
    fn set(&mut self, slot: usize, bound: &Bound, index: u32, count: u32) {
        self.h_lo[slot] = f32_below(bound.h_lo);
        self.h_hi[slot] = f32_above(bound.h_hi);
        self.index[slot] = index;
        self.count[slot] = count;
        self.gx_lo[slot] = f32_below(bound.chart_lo[0]);
        self.gx_hi[slot] = f32_above(bound.chart_hi[0]);
        self.gy_lo[slot] = f32_below(bound.chart_lo[1]);
        self.gy_hi[slot] = f32_above(bound.chart_hi[1]);
    }
}

impl Discs {
    const EMPTY: Discs = Discs {
        x: [0.0; WIDTH],
        y: [0.0; WIDTH],
        z: [1.0; WIDTH],
        reach: [f64::NEG_INFINITY; WIDTH],
    };

    /// Puts a child's disc in `slot`.
    fn set(&mut self, slot: usize, bound: &Bound) {
        self.x[slot] = bound.centre.x;
        self.y[slot] = bound.centre.y;
        self.z[slot] = bound.centre.z;
        self.reach[slot] = bound.reach;
    }

    /// The bound in `slot` of `node`.
    fn bound(&self, node: &Node, slot: usize) -> Bound {
        Bound {
            centre: DVec3::new(self.x[slot], self.y[slot], self.z[slot]),
            reach: self.reach[slot],
            h_lo: f64::from(node.h_lo[slot]),
            h_hi: f64::from(node.h_hi[slot]),
            chart_lo: [f64::from(node.gx_lo[slot]), f64::from(node.gy_lo[slot])],
            chart_hi: [f64::from(node.gx_hi[slot]), f64::from(node.gy_hi[slot])],
        }
    }
}

/// A child waiting on the traversal stack: a node, or a leaf's triangles, and where the ray
/// enters its bound.
#[derive(Clone, Copy, Debug)]
struct Pending<E> {
    index: u32,
    count: u32,
    entry: E,
}

/// A bounding disc × height interval in full precision.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Bound {
    pub(crate) centre: DVec3,
    pub(crate) reach: f64,
    pub(crate) h_lo: f64,
    pub(crate) h_hi: f64,
    /// The box of the vertices in the mesh's gnomonic chart (empty where there is none).
    pub(crate) chart_lo: [f64; 2],
    pub(crate) chart_hi: [f64; 2],
}

/// A BVH over a triangle mesh whose bounds are geodesic discs × height intervals.
///
/// ```
/// use orbifold::{Geometry, space::Space};
/// use orbifold_trace::accel::Bvh;
/// use orbifold_trace::geodesic::Ray;
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
    /// The bound of the whole mesh (`None` when it has no triangle).
    root: Option<Bound>,
    /// The root's bound as a node's slot 0 (the other slots empty), so that a ray enters it
    /// by the lanes' test: the fast functions rather than the library's.
    root_node: Node,
    root_discs: Discs,
    /// Node 0 holds the root's children.
    nodes: Vec<Node>,
    /// The nodes' discs, in the same order.
    discs: Vec<Discs>,
    /// Triangles in leaf order, prepared for ray tests.
    prepared: Vec<PreparedTriangle>,
    /// For each prepared triangle, its index in the input.
    order: Vec<u32>,
    /// For each input triangle, its index in `prepared` (`u32::MAX` for a degenerate one, which
    /// is not prepared).
    slot_of: Vec<u32>,
    points: Vec<DVec3>,
    heights: Vec<f64>,
    triangles: Vec<[u32; 3]>,
    depth: usize,
    /// Smooth shading normals (none: every face is shaded flat).
    shading: Option<VertexNormals>,
    /// The chart the nodes' boxes are in (`None`: the nodes are tested by their discs).
    chart: Option<Chart>,
    /// The largest absolute chart coordinate and height of any node's box (the root's), which
    /// bound the rounding of the f32 lanes ([`ChartLanes`]).
    lane_extent: [f64; 2],
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
fn widened(w: f64, centre_sigma: f64) -> f64 {
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
fn ceil_select(t: f64) -> f64 {
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
fn hyperbolic_span(g2: f64, reach: f64, along: f64, cosh_pc: f64) -> (bool, f64, f64) {
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
/// the test that rejects a ray before its frame is built ([`Bvh::heights_met`]), with the same
/// arithmetic so that the two agree to the bit.
#[inline(always)]
fn height_slab(
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
pub(crate) struct Chart {
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
    fn new(
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
    fn coords(&self, x: DVec3) -> Option<[f64; 2]> {
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
const FOOT_ERROR: f64 = 2.0
    * if LN_FAST_ERROR > ATAN_FAST_ERROR {
        LN_FAST_ERROR
    } else {
        ATAN_FAST_ERROR
    };

/// A ray seen in a [`Chart`], from the foot of the perpendicular from its centre: the chart
/// point at T = S(σ')/C(σ') is (a + b·T)/C(d⊥) on each axis, so the T at which axis i reads v
/// is v·`scale[i]` − `shift[i]`.
#[derive(Clone, Copy, Debug)]
struct ChartRay {
    /// σ of the foot (from the ray's origin).
    foot: f64,
    scale: [f64; 2],
    shift: [f64; 2],
    /// How far T may be off on each axis (rounding, grown with the distance to the foot).
    pad: [f64; 2],
    /// Axes along which the line barely moves: not used to cull.
    free: [bool; 2],
    t_max: f64,
    cubic: f64,
    quintic: f64,
}

impl ChartRay {
    /// `None` for a vertical ray (a point of the chart) or a great circle that misses the
    /// chart's hemisphere.
    #[inline(always)]
    fn new(chart: &Chart, frame: &RayFrame) -> Option<ChartRay> {
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

/// f32's unit roundoff, 2⁻²⁴.
const F32_EPSILON: f64 = 1.0 / 16_777_216.0;

/// ⌈t⌉ in f32 by adding and taking away 1.5·2²³ and a select ([`ceil_select`] in single
/// precision).
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

/// A [`ChartRay`] made ready for eight lanes of single precision: every quantity of the box
/// test in the horizontal arc length from the foot, σ' = σ − σ_foot (so that no lane adds the
/// foot's own magnitude), rounded to f32, with pads that cover every rounding of the lanes'
/// arithmetic (each product and sum at most a few units in the last place of the largest
/// value it can take: the chart's and the heights' extents, which the root's box bounds).
/// A lane's result is an entry σ' that is never after the true one, and never a miss where
/// the f64 test ([`RayFrame::chart_entries`] before it was single) meets.
#[derive(Clone, Copy, Debug)]
struct ChartLanes {
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
    fn new(
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

    #[inline(always)]
    fn dot(&self, a: DVec3, b: DVec3) -> f64 {
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

    /// Where the ray enters each of a node's child bounds within [s_lo, s_hi] (NaN where it
    /// does not, so that every comparison with a miss fails, even when s_hi = +∞): [`RayFrame::entry`] for all at once. Away from vertical rays the
    /// lanes are straight-line arithmetic with selects for branches (the fast functions'
    /// reductions too), so that they run side by side rather than one after another.
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

/// How a traversal tests a node's children: its entries' unit (`E`: σ' in f32 for
/// [`ChartLanes`], arc length s in f64 for the discs) and the test itself.
trait Lanes {
    type E: Copy + PartialOrd;
    /// The entry unit's value at arc length `s`, rounded up.
    fn bound(&self, s: f64) -> Self::E;
    /// Where the ray enters each child of the node at `at` (NaN where it does not) before `hi`.
    fn entries(&self, bvh: &Bvh, node: &Node, at: Option<usize>, hi: Self::E) -> [Self::E; WIDTH];
}

/// The children's discs, in f64 (a mesh without a chart, a vertical ray).
struct DiscLanes<'a> {
    frame: &'a RayFrame,
    s_lo: f64,
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

/// The children's chart boxes in f32 lanes, on S² (`K` > 0) or not.
struct BoxLanes<const K: i32>(ChartLanes);

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

/// The ray's part a search looks at: its space, frame and arc lengths [s_min, s_max].
#[derive(Clone, Copy)]
struct Segment<'a> {
    space: Space,
    frame: &'a RayFrame,
    s_min: f64,
    s_max: f64,
}

/// A search of the tree ([`Nearest`] or [`Any`]), generic over the lanes that test its nodes.
trait Search {
    type Found;
    /// What a ray that misses the root finds.
    const MISSED: Self::Found;
    fn run<L: Lanes>(self, bvh: &Bvh, at: &Segment, lanes: &L) -> Self::Found;
}

/// The nearest hit ([`Bvh::intersect`]).
struct Nearest;

impl Search for Nearest {
    type Found = Option<TriangleHit>;
    const MISSED: Option<TriangleHit> = None;

    #[inline(always)]
    fn run<L: Lanes>(self, bvh: &Bvh, at: &Segment, lanes: &L) -> Option<TriangleHit> {
        bvh.nearest(at, lanes)
    }
}

/// Whether anything is hit ([`Bvh::occluded`]).
struct Any;

impl Search for Any {
    type Found = bool;
    const MISSED: bool = false;

    #[inline(always)]
    fn run<L: Lanes>(self, bvh: &Bvh, at: &Segment, lanes: &L) -> bool {
        bvh.any(at, lanes)
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

/// A triangle's place in SAH space (tangent coordinates at the mesh centre, and height).
#[derive(Clone, Copy, Debug)]
struct Key {
    centroid: DVec3,
    lo: DVec3,
    hi: DVec3,
}

/// A node of the tree before flattening.
enum Temp {
    /// Bound, first triangle, number of triangles.
    Leaf(Bound, u32, u32),
    /// Bound, children, number of triangles below.
    Inner(Bound, Box<[Temp; 2]>, usize),
}

impl Temp {
    fn bound(&self) -> &Bound {
        match self {
            Temp::Leaf(b, ..) | Temp::Inner(b, ..) => b,
        }
    }

    /// The children a node of the flattened tree gets for this one: its two, then the largest
    /// inner child replaced by its two until there are eight (or only leaves).
    fn children(self) -> Vec<Temp> {
        let Temp::Inner(_, pair, _) = self else {
            return vec![self];
        };
        let mut children: Vec<Temp> = Vec::from(*pair);
        while children.len() < WIDTH {
            let largest = children
                .iter()
                .enumerate()
                .filter_map(|(i, c)| match c {
                    Temp::Inner(_, _, n) => Some((i, *n)),
                    Temp::Leaf(..) => None,
                })
                .max_by_key(|&(_, n)| n);
            let Some((i, _)) = largest else { break };
            let Temp::Inner(_, pair, _) = children.swap_remove(i) else {
                unreachable!("an inner child was chosen")
            };
            children.extend(*pair);
        }
        children
    }
}

struct Builder<'a> {
    space: Space,
    points: &'a [DVec3],
    heights: &'a [f64],
    triangles: &'a [[u32; 3]],
    keys: Vec<Key>,
    chart: Option<Chart>,
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

    /// The surface area of the vertical cylinder around the box (the horizontal diagonal for
    /// its diameter, z its height): what the node's bound will be, a disc × a height interval.
    fn cylinder_area(&self) -> f64 {
        let d = (self.hi - self.lo).max(DVec3::ZERO);
        let r = 0.5 * d.x.hypot(d.y);
        2.0 * std::f64::consts::PI * r * (r + d.z)
    }

    /// The box's own surface area.
    fn area(&self) -> f64 {
        let d = (self.hi - self.lo).max(DVec3::ZERO);
        2.0 * (d.x * d.y + d.z * (d.x + d.y))
    }

    /// What a side's bound costs: its box's area where the nodes are boxes in the chart,
    /// the cylinder's where they are discs.
    fn cost(&self, boxes: bool) -> f64 {
        if boxes {
            self.area()
        } else {
            self.cylinder_area()
        }
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
            disc_around(self.space, vertices.clone()).unwrap_or((DVec3::Z, f64::INFINITY));
        // The box in the chart, padded far beyond the rounding of the chart points.
        let (mut chart_lo, mut chart_hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
        if let Some(chart) = &self.chart {
            for v in vertices {
                let g = chart.coords(*v).unwrap_or([f64::NAN; 2]);
                for i in 0..2 {
                    chart_lo[i] = chart_lo[i].min(g[i] - 1e-9 * (1.0 + g[i].abs()));
                    chart_hi[i] = chart_hi[i].max(g[i] + 1e-9 * (1.0 + g[i].abs()));
                }
            }
        }
        Bound {
            centre,
            reach,
            h_lo,
            h_hi,
            chart_lo,
            chart_hi,
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
                    right_area[b] = acc.cost(self.chart.is_some());
                    right_count[b] = n;
                }
                let (mut acc, mut n) = (Aabb::EMPTY, 0);
                for b in 0..BINS - 1 {
                    acc.grow(boxes[b].lo, boxes[b].hi);
                    n += counts[b];
                    if n == 0 || right_count[b + 1] == 0 {
                        continue;
                    }
                    let cost = acc.cost(self.chart.is_some()) * n as f64
                        + right_area[b + 1] * right_count[b + 1] as f64;
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
        Temp::Inner(bound, Box::new([a, b]), size)
    }
}

/// Writes a node for `children` at `at` (and its discs) and its descendants after the current
/// end; returns the subtree's depth.
fn flatten(children: Vec<Temp>, at: usize, nodes: &mut Vec<Node>, discs: &mut Vec<Discs>) -> usize {
    let mut node = Node::EMPTY;
    let mut disc = Discs::EMPTY;
    let mut inner = Vec::new();
    for (slot, child) in children.into_iter().enumerate() {
        disc.set(slot, child.bound());
        match child {
            Temp::Leaf(bound, start, count) => node.set(slot, &bound, start, count),
            Temp::Inner(bound, ..) => {
                node.set(slot, &bound, 0, 0);
                inner.push((slot, child));
            }
        }
    }
    nodes[at] = node;
    discs[at] = disc;
    let mut depth = 0;
    for (slot, child) in inner {
        let index = nodes.len();
        nodes.push(Node::EMPTY);
        discs.push(Discs::EMPTY);
        nodes[at].index[slot] = index as u32;
        depth = depth.max(flatten(child.children(), index, nodes, discs));
    }
    1 + depth
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
            root: None,
            root_node: Node::EMPTY,
            root_discs: Discs::EMPTY,
            nodes: Vec::new(),
            discs: Vec::new(),
            prepared: Vec::new(),
            order: Vec::new(),
            slot_of: Vec::new(),
            points: points.to_vec(),
            heights: heights.to_vec(),
            triangles: triangles.to_vec(),
            depth: 0,
            shading: None,
            chart: None,
            lane_extent: [0.0; 2],
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
        let chart = Chart::new(
            space,
            centre,
            tris.iter()
                .flat_map(|&t| triangles[t as usize])
                .map(|i| points[i as usize]),
        );
        let [e1, e2] = space.tangent_frame(centre);
        let vertex_key = |i: u32| {
            let x = points[i as usize];
            if let Some([gx, gy]) = chart.and_then(|c| c.coords(x)) {
                return DVec3::new(gx, gy, heights[i as usize]);
            }
            let l = space.log(centre, x);
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
            chart,
        };
        let root = builder.build(&mut tris, 0, 0);
        bvh.root = Some(*root.bound());
        bvh.chart = chart;
        bvh.root_node.set(0, root.bound(), 0, 0);
        bvh.root_discs.set(0, root.bound());
        let r = &bvh.root_node;
        let largest =
            |values: [f32; 4]| values.iter().fold(0.0f64, |m, v| m.max(f64::from(v.abs())));
        bvh.lane_extent = [
            largest([r.gx_lo[0], r.gx_hi[0], r.gy_lo[0], r.gy_hi[0]]),
            largest([r.h_lo[0], r.h_hi[0], 0.0, 0.0]),
        ];
        let mut nodes = Vec::with_capacity(tris.len() / LEAF_SIZE + 1);
        let mut discs = Vec::with_capacity(tris.len() / LEAF_SIZE + 1);
        nodes.push(Node::EMPTY);
        discs.push(Discs::EMPTY);
        bvh.depth = flatten(root.children(), 0, &mut nodes, &mut discs);
        assert!(
            (WIDTH - 1) * bvh.depth < STACK,
            "the BVH is too deep for its traversal stack"
        );
        bvh.nodes = nodes;
        bvh.discs = discs;
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
        bvh.slot_of = vec![u32::MAX; triangles.len()];
        for (slot, &t) in tris.iter().enumerate() {
            bvh.slot_of[t as usize] = slot as u32;
        }
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
        with_avx2!(
            Bvh,
            self.intersect_portable(space: Space, ray: &Ray, s_min: f64, s_max: f64) -> Option<TriangleHit>
        )
    }

    #[inline(always)]
    fn intersect_portable(
        &self,
        space: Space,
        ray: &Ray,
        s_min: f64,
        s_max: f64,
    ) -> Option<TriangleHit> {
        self.search(space, ray, (s_min, s_max), Nearest)
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
    fn nearest<L: Lanes>(&self, at: &Segment, lanes: &L) -> Option<TriangleHit> {
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
        // Not an array: zeroing 4 KiB for every ray would cost more than a short traversal.
        let mut stack = ArrayVec::<Pending<L::E>, STACK>::new();
        stack.push(Pending {
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
                stack.push(Pending {
                    index: node.index[slot],
                    count: node.count[slot],
                    entry,
                });
            }
        }
        best
    }

    /// Whether the ray meets any triangle at arc length in `[s_min, s_max]` (for shadow rays).
    pub fn occluded(&self, space: Space, ray: &Ray, s_min: f64, s_max: f64) -> bool {
        with_avx2!(
            Bvh,
            self.occluded_portable(space: Space, ray: &Ray, s_min: f64, s_max: f64) -> bool
        )
    }

    #[inline(always)]
    fn occluded_portable(&self, space: Space, ray: &Ray, s_min: f64, s_max: f64) -> bool {
        self.search(space, ray, (s_min, s_max), Any)
    }

    /// Whether any triangle is hit, the children tested by `lanes`.
    #[inline(always)]
    fn any<L: Lanes>(&self, at: &Segment, lanes: &L) -> bool {
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
    /// triangles): the nearest is read right after, and a
    /// 50k-triangle mesh's nodes and triangles do not fit the core's own caches (on `*444` a
    /// fifth of the nearest-hit traversal's time was spent waiting for the first read of a node,
    /// and a third of the triangle test's for its triangle).
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
    /// test). Most rays between two mirrors of a Table 8.1 room pass above or below the object
    /// (72 % of those in `*444`).
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
    /// Of the rays that pass [`Bvh::heights_met`] in `*444`, two in three miss the dragon's disc:
    /// they are turned away before their frame is built. Also right for a vertical ray, whose
    /// geodesic through p meets the disc wherever p is in it.
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

    /// The triangle with this index in the input list.
    pub fn triangle(&self, index: u32) -> Triangle {
        // The prepared copy holds the same vertices in one place, and it is in the cache just
        // after a hit on it; the input's are three reads of scattered vertices away.
        let prepared = self.slot_of.get(index as usize);
        if let Some(prepared) = prepared.and_then(|&slot| self.prepared.get(slot as usize)) {
            return prepared.triangle();
        }
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

    /// Shades the mesh smooth: faces whose normals differ by less than `crease` (radians) at a
    /// shared vertex are shaded as one surface ([`crate::shading_normal`]).
    pub fn with_smooth_normals(mut self, space: Space, crease: f64) -> Bvh {
        self.shading = Some(VertexNormals::new(
            space,
            &self.points,
            &self.heights,
            &self.triangles,
            crease,
        ));
        self
    }

    /// The crease angle (radians) of its smooth shading, if it is shaded smooth.
    pub fn crease(&self) -> Option<f64> {
        self.shading.as_ref().map(VertexNormals::crease)
    }

    /// The shading normal at a hit: the smooth normal where the mesh is shaded smooth, else the
    /// face's own [`Bvh::normal`].
    pub fn shading_normal(&self, space: Space, hit: &TriangleHit) -> Option<(DVec3, f64)> {
        let smooth = self.shading.as_ref().and_then(|shading| {
            let vertices = self.triangle(hit.triangle).points;
            shading.at(space, hit.triangle, vertices, hit.barycentric)
        });
        smooth.or_else(|| self.normal(space, hit))
    }

    /// The bound of the whole mesh (`None` when it has no triangle).
    pub(crate) fn bound(&self) -> Option<Bound> {
        self.root
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
    /// use orbifold_trace::accel::Bvh;
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
    fn nodes_are_four_cache_lines() {
        assert_eq!(std::mem::size_of::<Node>(), 256);
        assert_eq!(std::mem::size_of::<Discs>(), 256);
    }

    /// `triangle` reads the prepared copy: the same vertices, in the input's order, for every
    /// input triangle (a degenerate one, which has no prepared copy, included).
    #[test]
    fn triangles_are_the_input_ones() {
        let space = Space::new(Geometry::Hyperbolic);
        let mut u = uniforms(3);
        let points: Vec<DVec3> = (0..90)
            .map(|_| space.exp(DVec3::Z, DVec3::new(u() - 0.5, u() - 0.5, 0.0)))
            .collect();
        let heights: Vec<f64> = (0..90).map(|_| u()).collect();
        let mut triangles: Vec<[u32; 3]> = (0..30).map(|t| [3 * t, 3 * t + 1, 3 * t + 2]).collect();
        triangles[17] = [4, 4, 5]; // a segment: not prepared
        let bvh = Bvh::build(space, &points, &heights, &triangles);
        assert_eq!(bvh.prepared.len(), 29);
        for (index, t) in triangles.iter().enumerate() {
            let triangle = bvh.triangle(index as u32);
            assert_eq!(triangle.points, t.map(|i| points[i as usize]), "{index}");
            assert_eq!(triangle.heights, t.map(|i| heights[i as usize]), "{index}");
        }
    }

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

    #[test]
    fn f32_rounding_is_outward() {
        for x in [0.1, -0.1, 1e-30, 3.0, 1.0 / 3.0, -7.123456789] {
            assert!(f64::from(f32_below(x)) <= x && f64::from(f32_above(x)) >= x);
        }
    }

    /// Uniforms in [0, 1) from a linear congruential generator (deterministic, no crate).
    fn uniforms(mut seed: u64) -> impl FnMut() -> f64 {
        move || {
            seed = seed
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (seed >> 11) as f64 / (1u64 << 53) as f64
        }
    }

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
    fn four_lane_test_agrees_with_the_scalar_one_and_with_sampling() {
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
                let t = chart.t_max;
                let pads = f64::from(lanes.slack + lanes.height_pad) + 1e-6;
                let slack =
                    (chart.quintic * t.powi(5) + pads + 1e-9) * frame.inv_ca() + step + 1e-9;
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
            // Both outcomes are exercised (about 100 lanes met of 2000 in a debug build's 600
            // cases: the boxes are of small random clusters).
            assert!(
                met > cases / 10 && missed > cases / 10,
                "{g:?}: {met} met, {missed} missed"
            );
        }
    }

    /// A mesh too wide for a chart (beyond 84° from its centre on S², 3.8 on H²) has none and
    /// is traversed by its discs, with the same hits as testing every triangle.
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
