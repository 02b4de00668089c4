//! The nodes of the BVH (ARCHITECTURE.md §8): eight children a node, their bounds side by side.
//!
//! The tree is a flat array of 256-byte nodes ([`Node`], four cache lines) that hold their eight
//! children's boxes in the mesh's gnomonic chart (`super::chart`) and their height intervals side
//! by side in f32 — a structure of arrays, so that one pass of straight-line arithmetic tests all
//! eight — and beside it the array of their **geodesic discs** ([`Discs`], in f64), kept apart
//! from the nodes so that the traversal reads four cache lines a node rather than eight. The
//! discs are tested instead of the boxes by vertical rays (a point of the chart), and for a mesh
//! too wide for a chart (a vertex more than about 84° from the centre on S², where the gnomonic
//! picture ends at the hemisphere's edge, or 3.8 on H², where the bound on artanh grows without
//! limit). A child's bound in full precision, as the build finds it and as the instances move
//! it, is a [`Bound`].

use glam::DVec3;

use super::chart_lanes::{f32_above, f32_below};

/// Children per node.
pub(super) const WIDTH: usize = 8;

/// A node: up to eight children's bounds side by side (a structure of arrays, so that one pass
/// of straight-line arithmetic tests all eight), and for each child either the index of its node
/// or its leaf's triangle range. The bounds are boxes in the mesh's chart × height intervals
/// (what the traversal tests, four cache lines); their discs, for meshes without a chart and for
/// vertical rays, are kept apart ([`Discs`]). An empty slot has an empty box and reach −∞,
/// which every ray misses.
#[derive(Clone, Copy, Debug, PartialEq)]
#[repr(C, align(64))]
pub(super) struct Node {
    /// The children's boxes in the mesh's gnomonic chart ([`Chart`](super::chart::Chart)), rounded
    /// outwards to f32.
    pub(super) gx_lo: [f32; WIDTH],
    pub(super) gx_hi: [f32; WIDTH],
    pub(super) gy_lo: [f32; WIDTH],
    pub(super) gy_hi: [f32; WIDTH],
    /// Height intervals, rounded outwards to f32.
    pub(super) h_lo: [f32; WIDTH],
    pub(super) h_hi: [f32; WIDTH],
    /// The child's node (inner child) or first triangle (leaf child).
    pub(super) index: [u32; WIDTH],
    /// The leaf child's number of triangles; 0 for an inner child.
    pub(super) count: [u32; WIDTH],
}

/// A node's children's bounding discs (same slots as its [`Node`]).
#[derive(Clone, Copy, Debug, PartialEq)]
#[repr(C, align(64))]
pub(super) struct Discs {
    /// Ambient centres of the discs.
    pub(super) x: [f64; WIDTH],
    pub(super) y: [f64; WIDTH],
    pub(super) z: [f64; WIDTH],
    /// V(r) = ½|x − c|²_κ at the (slightly enlarged) radii; +∞ for the whole plane.
    pub(super) reach: [f64; WIDTH],
}

impl Node {
    pub(super) const EMPTY: Node = Node {
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
    pub(super) fn set(&mut self, slot: usize, bound: &Bound, index: u32, count: u32) {
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
    pub(super) const EMPTY: Discs = Discs {
        x: [0.0; WIDTH],
        y: [0.0; WIDTH],
        z: [1.0; WIDTH],
        reach: [f64::NEG_INFINITY; WIDTH],
    };

    /// Puts a child's disc in `slot`.
    pub(super) fn set(&mut self, slot: usize, bound: &Bound) {
        self.x[slot] = bound.centre.x;
        self.y[slot] = bound.centre.y;
        self.z[slot] = bound.centre.z;
        self.reach[slot] = bound.reach;
    }

    /// The bound in `slot` of `node`.
    pub(super) fn bound(&self, node: &Node, slot: usize) -> Bound {
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

/// A bound in full precision: a geodesic disc × a height interval, and the box in the mesh's
/// chart.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct Bound {
    /// The disc's ambient centre, and V(r) at its radius ([`crate::ray_frame::disc_around`]).
    pub(super) centre: DVec3,
    pub(super) reach: f64,
    /// The height interval.
    pub(super) h_lo: f64,
    pub(super) h_hi: f64,
    /// The box of the vertices in the mesh's gnomonic chart (empty where there is none).
    pub(super) chart_lo: [f64; 2],
    pub(super) chart_hi: [f64; 2],
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn nodes_are_four_cache_lines() {
        assert_eq!(std::mem::size_of::<Node>(), 256);
        assert_eq!(std::mem::size_of::<Discs>(), 256);
    }
}
