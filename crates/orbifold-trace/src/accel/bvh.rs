//! A bounding volume hierarchy for curved rays (ARCHITECTURE.md §8): the [`Bvh`] type, what it
//! holds and its public methods.
//!
//! Each node's eight children are bounded by **boxes in the mesh's gnomonic chart × height
//! intervals** (`super::chart`), where a ray's horizontal geodesic is a straight line, and
//! tested at once in f32 lanes (`super::chart_lanes`); every node also keeps its children's
//! **geodesic discs** (`super::node`), tested instead where there is no chart and for vertical
//! rays (`super::disc_lanes`). The tree is built top-down by binned SAH and collapsed into
//! 8-wide nodes (`super::build`); a traversal tests a node's children at once and goes on to
//! those met, nearest first (`super::traverse`). The hierarchy is built in the mesh's own frame,
//! so that instances placed by isometries share it ([`super::Instance`]).

use glam::DVec3;
use orbifold::space::Space;

use super::build;
use super::chart::Chart;
use super::node::{Bound, Discs, Node};
use crate::geodesic::Ray;
use crate::shading_normal::VertexNormals;
use crate::triangle::{PreparedTriangle, Triangle, TriangleHit};
use crate::with_avx2;

/// A BVH over a triangle mesh for curved rays: 8-wide nodes whose children are bounded by boxes
/// in the mesh's gnomonic chart × height intervals, and by geodesic discs where there is no
/// chart.
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
    pub(super) kappa: f64,
    /// The bound of the whole mesh (`None` when it has no triangle).
    pub(super) root: Option<Bound>,
    /// The root's bound as a node's slot 0 (the other slots empty), so that a ray enters it
    /// by the lanes' test: the fast functions rather than the library's.
    pub(super) root_node: Node,
    pub(super) root_discs: Discs,
    /// Node 0 holds the root's children.
    pub(super) nodes: Vec<Node>,
    /// The nodes' discs, in the same order.
    pub(super) discs: Vec<Discs>,
    /// Triangles in leaf order, prepared for ray tests.
    pub(super) prepared: Vec<PreparedTriangle>,
    /// For each prepared triangle, its index in the input.
    pub(super) order: Vec<u32>,
    /// For each input triangle, its index in `prepared` (`u32::MAX` for a degenerate one, which
    /// is not prepared).
    pub(super) slot_of: Vec<u32>,
    pub(super) points: Vec<DVec3>,
    pub(super) heights: Vec<f64>,
    pub(super) triangles: Vec<[u32; 3]>,
    pub(super) depth: usize,
    /// Smooth shading normals (none: every face is shaded flat).
    pub(super) shading: Option<VertexNormals>,
    /// The chart the nodes' boxes are in (`None`: the nodes are tested by their discs).
    pub(super) chart: Option<Chart>,
    /// The largest absolute chart coordinate and height of any node's box (the root's), which
    /// bound the rounding of the f32 lanes (`super::chart_lanes`).
    pub(super) lane_extent: [f64; 2],
}

impl Bvh {
    /// Builds the BVH of a mesh: ambient vertex positions, vertex heights and triangles (indices
    /// into both). Degenerate triangles (zero determinant) are left out: they are never hit.
    ///
    /// # Panics
    ///
    /// When `points` and `heights` differ in length or a triangle indexes past them.
    pub fn build(space: Space, points: &[DVec3], heights: &[f64], triangles: &[[u32; 3]]) -> Bvh {
        build::build(space, points, heights, triangles)
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

    /// Whether the ray meets any triangle at arc length in `[s_min, s_max]` (for shadow rays).
    pub fn occluded(&self, space: Space, ray: &Ray, s_min: f64, s_max: f64) -> bool {
        with_avx2!(
            Bvh,
            self.occluded_portable(space: Space, ray: &Ray, s_min: f64, s_max: f64) -> bool
        )
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
    pub(super) fn bound(&self) -> Option<Bound> {
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
    use orbifold::Geometry;

    use super::*;
    use crate::test_util::uniforms;

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
}
