//! Building the BVH (ARCHITECTURE.md §8): top-down binned SAH over the triangles' vertices in the
//! chart (where there is none, in tangent coordinates at the mesh's centre by `Space::log`) and
//! height, each side costed by the area of its box — the shape its bound will have (with discs,
//! by the vertical cylinder around the box, whose area a long thin side's wide disc has) —
//! leaves of at most four triangles, subtrees built in parallel with rayon above a size. The
//! binary tree is then collapsed into an 8-wide one (each node takes its two children, then the
//! largest inner child's two in its place, until it has eight) and flattened into the array of
//! nodes and, beside it, the array of their discs (`super::node`).

use glam::DVec3;
use orbifold::space::Space;

use super::Bvh;
use super::chart::Chart;
use super::node::{Bound, Discs, Node, WIDTH};
use super::traverse::STACK;
use crate::ray_frame::disc_around;
use crate::triangle::PreparedTriangle;

/// Most triangles in a leaf.
const LEAF_SIZE: usize = 4;
/// SAH bins per axis.
const BINS: usize = 16;
/// Subtrees with more triangles than this are built on another thread.
const PARALLEL_THRESHOLD: usize = 2048;
/// Below this depth SAH decides the split; deeper, the median (so the depth stays bounded).
const SAH_DEPTH: usize = 48;

/// A triangle's place in SAH space (its vertices' chart coordinates, or where there is no chart
/// their tangent coordinates at the mesh centre, and heights): centroid and bounding box.
#[derive(Clone, Copy, Debug)]
struct PrimitiveInfo {
    centroid: DVec3,
    lo: DVec3,
    hi: DVec3,
}

/// A node of the binary tree the build makes, before it is collapsed into 8-wide nodes.
enum BuildNode {
    /// A leaf: its bound, and its `count` triangles from `first` on, in leaf order.
    Leaf {
        bound: Bound,
        first: u32,
        count: u32,
    },
    /// An inner node: its bound, its two children, and the number of triangles below it.
    Inner {
        bound: Bound,
        children: Box<[BuildNode; 2]>,
        count: usize,
    },
}

impl BuildNode {
    fn bound(&self) -> &Bound {
        match self {
            BuildNode::Leaf { bound, .. } | BuildNode::Inner { bound, .. } => bound,
        }
    }

    /// The children a node of the flattened tree gets for this one: its two, then the largest
    /// inner child replaced by its two until there are eight (or only leaves).
    fn children(self) -> Vec<BuildNode> {
        let BuildNode::Inner { children: pair, .. } = self else {
            return vec![self];
        };
        let mut children: Vec<BuildNode> = Vec::from(*pair);
        while children.len() < WIDTH {
            let largest = children
                .iter()
                .enumerate()
                .filter_map(|(i, c)| match c {
                    BuildNode::Inner { count, .. } => Some((i, *count)),
                    BuildNode::Leaf { .. } => None,
                })
                .max_by_key(|&(_, n)| n);
            let Some((i, _)) = largest else { break };
            let BuildNode::Inner { children: pair, .. } = children.swap_remove(i) else {
                unreachable!("an inner child was chosen")
            };
            children.extend(*pair);
        }
        children
    }
}

/// What the recursive split reads (on rayon's threads too): the mesh, the triangles' places in
/// SAH space, and the chart the bounds' boxes are taken in.
struct Builder<'a> {
    space: Space,
    points: &'a [DVec3],
    heights: &'a [f64],
    triangles: &'a [[u32; 3]],
    primitives: Vec<PrimitiveInfo>,
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
            let c = self.primitives[t as usize].centroid;
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
                    let primitive = &self.primitives[t as usize];
                    let b = (((primitive.centroid[axis] - centroids.lo[axis]) * scale) as usize)
                        .min(BINS - 1);
                    boxes[b].grow(primitive.lo, primitive.hi);
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
                let primitives = &self.primitives;
                let left = |t: &u32| {
                    (((primitives[*t as usize].centroid[axis] - lo) * scale) as usize).min(BINS - 1)
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
        let primitives = &self.primitives;
        tris.select_nth_unstable_by(mid, |a, b| {
            primitives[*a as usize].centroid[axis]
                .total_cmp(&primitives[*b as usize].centroid[axis])
        });
        mid
    }

    fn build(&self, tris: &mut [u32], offset: usize, depth: usize) -> BuildNode {
        let bound = self.bound(tris);
        if tris.len() <= LEAF_SIZE {
            return BuildNode::Leaf {
                bound,
                first: offset as u32,
                count: tris.len() as u32,
            };
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
        BuildNode::Inner {
            bound,
            children: Box::new([a, b]),
            count: size,
        }
    }
}

/// Writes a node for `children` at `at` (and its discs) and its descendants after the current
/// end; returns the subtree's depth.
fn flatten(
    children: Vec<BuildNode>,
    at: usize,
    nodes: &mut Vec<Node>,
    discs: &mut Vec<Discs>,
) -> usize {
    let mut node = Node::EMPTY;
    let mut disc = Discs::EMPTY;
    let mut inner = Vec::new();
    for (slot, child) in children.into_iter().enumerate() {
        disc.set(slot, child.bound());
        match child {
            BuildNode::Leaf {
                bound,
                first,
                count,
            } => node.set(slot, &bound, first, count),
            BuildNode::Inner { bound, .. } => {
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

/// The BVH of a mesh: [`Bvh::build`], which says what it takes.
pub(super) fn build(
    space: Space,
    points: &[DVec3],
    heights: &[f64],
    triangles: &[[u32; 3]],
) -> Bvh {
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

    // Where the triangles are in SAH space: chart coordinates (where there is no chart,
    // tangent coordinates at the mesh centre), and height.
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
    let sah_point = |i: u32| {
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
    let sah_points: Vec<DVec3> = (0..points.len() as u32).map(sah_point).collect();
    let primitives = triangles
        .iter()
        .map(|t| {
            let [a, b, c] = t.map(|i| sah_points[i as usize]);
            PrimitiveInfo {
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
        primitives,
        chart,
    };
    let root = builder.build(&mut tris, 0, 0);
    bvh.root = Some(*root.bound());
    bvh.chart = chart;
    bvh.root_node.set(0, root.bound(), 0, 0);
    bvh.root_discs.set(0, root.bound());
    let r = &bvh.root_node;
    let largest = |values: [f32; 4]| values.iter().fold(0.0f64, |m, v| m.max(f64::from(v.abs())));
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
