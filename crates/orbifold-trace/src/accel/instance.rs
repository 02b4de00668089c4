//! Objects as instances (ARCHITECTURE.md §7, §8): a mesh's BVH, built once at the origin, placed
//! by an isometry of the plane and a height offset. A ray is moved into the object's frame
//! (isometries are linear in ambient coordinates and keep arc length), so moving an instance
//! rebuilds nothing.

use std::sync::Arc;

use glam::{DMat3, DVec3};
use orbifold::embed::Placement;
use orbifold::isometry::Isometry;
use orbifold::space::Space;

use super::Bvh;
use super::node::Bound;
use crate::geodesic::Ray;
use crate::ray_frame::RayFrame;
use crate::triangle::TriangleHit;

/// A placed copy of a mesh: its BVH (shared), the isometry that takes object coordinates to world
/// coordinates and its inverse (3×3 ambient matrices), and the height added to object heights.
///
/// ```
/// use std::sync::Arc;
/// use orbifold::{Geometry, space::Space, embed::Placement};
/// use orbifold_trace::{accel::{Bvh, Instance}, geodesic::Ray};
/// use glam::DVec3;
/// use num_complex::Complex64;
/// let h2 = Space::new(Geometry::Hyperbolic);
/// let p = |x: f64, y: f64| h2.exp(DVec3::Z, DVec3::new(x, y, 0.0));
/// // A small upright square facing −x, at the origin of its own frame.
/// let bvh = Arc::new(Bvh::build(
///     h2,
///     &[p(0.0, -0.1), p(0.0, 0.1), p(0.0, 0.1), p(0.0, -0.1)],
///     &[0.0, 0.0, 0.2, 0.2],
///     &[[0, 1, 2], [0, 2, 3]],
/// ));
/// // Placed at model point 0.3 (intrinsic distance 2 artanh 0.3 from the centre), raised by 1.
/// let placement = Placement { at: Complex64::new(0.3, 0.0), height: 1.0, yaw: 0.0 };
/// let object = Instance::from_placement(h2, bvh, &placement);
/// let ray = Ray::new(h2, DVec3::Z, DVec3::X, 1.1, 0.0);
/// let hit = object.intersect(h2, &ray, 0.0, 10.0).unwrap();
/// assert!((hit.s - 2.0 * 0.3f64.atanh()).abs() < 1e-12);
/// ```
#[derive(Clone, Debug)]
pub struct Instance {
    /// The mesh, in object coordinates.
    pub bvh: Arc<Bvh>,
    /// Object → world ambient isometry.
    pub to_world: DMat3,
    /// World → object ambient isometry (the inverse of `to_world`).
    pub to_object: DMat3,
    /// Added to object heights to give world heights.
    pub height: f64,
}

impl Instance {
    /// The mesh moved by an isometry and raised by `height`.
    pub fn new(bvh: Arc<Bvh>, isometry: &Isometry, height: f64) -> Instance {
        Instance {
            bvh,
            to_world: isometry.matrix(),
            to_object: isometry.inverse().matrix(),
            height,
        }
    }

    /// The mesh placed as an embedded object is placed (`orbifold::embed::place`).
    pub fn from_placement(space: Space, bvh: Arc<Bvh>, placement: &Placement) -> Instance {
        Instance::new(bvh, &placement.isometry(space), placement.height)
    }

    /// The ray in the object's frame.
    #[inline]
    pub fn to_object_ray(&self, ray: &Ray) -> Ray {
        ray.transformed(&self.to_object, -self.height)
    }

    /// The nearest hit at arc length in `[s_min, s_max]` (arc length is the same in both frames).
    pub fn intersect(
        &self,
        space: Space,
        ray: &Ray,
        s_min: f64,
        s_max: f64,
    ) -> Option<TriangleHit> {
        self.bvh
            .intersect(space, &self.to_object_ray(ray), s_min, s_max)
    }

    /// Whether the ray meets the object at arc length in `[s_min, s_max]`.
    pub fn occluded(&self, space: Space, ray: &Ray, s_min: f64, s_max: f64) -> bool {
        self.bvh
            .occluded(space, &self.to_object_ray(ray), s_min, s_max)
    }

    /// The world point (ambient horizontal position, height) of a hit.
    pub fn point(&self, space: Space, hit: &TriangleHit) -> (DVec3, f64) {
        let (x, h) = self.bvh.point(space, hit);
        (self.to_world * x, h + self.height)
    }

    /// The unit surface normal at a hit, in the world tangent space at the hit (see
    /// [`crate::triangle::Triangle::normal`]).
    pub fn normal(&self, space: Space, hit: &TriangleHit) -> Option<(DVec3, f64)> {
        let (n, up) = self.bvh.normal(space, hit)?;
        Some((self.to_world * n, up))
    }

    /// The shading normal at a hit (smooth where the mesh is shaded smooth), in the world
    /// tangent space at the hit (see [`crate::accel::Bvh::shading_normal`]).
    pub fn shading_normal(&self, space: Space, hit: &TriangleHit) -> Option<(DVec3, f64)> {
        let (n, up) = self.bvh.shading_normal(space, hit)?;
        Some((self.to_world * n, up))
    }

    /// The world bound of the whole object.
    fn world_bound(&self) -> Option<Bound> {
        self.bvh.bound().map(|b| Bound {
            centre: self.to_world * b.centre,
            reach: b.reach,
            h_lo: b.h_lo + self.height,
            h_hi: b.h_hi + self.height,
            // In the object's own chart: a world bound is tested as a disc only.
            chart_lo: b.chart_lo,
            chart_hi: b.chart_hi,
        })
    }
}

/// The objects of a scene. Each ray is first tested against every object's whole bound (a geodesic
/// disc × height interval in world coordinates, kept up to date here), and objects are visited
/// nearest bound first.
///
/// ```
/// use std::sync::Arc;
/// use orbifold::{Geometry, space::Space, isometry::Isometry};
/// use orbifold_trace::{accel::{Bvh, Instance, Instances}, geodesic::Ray};
/// use glam::DVec3;
/// use num_complex::Complex64;
/// let e2 = Space::new(Geometry::Euclidean);
/// let p = |x: f64, y: f64| e2.exp(DVec3::Z, DVec3::new(x, y, 0.0));
/// let bvh = Arc::new(Bvh::build(
///     e2,
///     &[p(0.0, -0.1), p(0.0, 0.1), p(0.0, 0.1), p(0.0, -0.1)],
///     &[0.0, 0.0, 0.2, 0.2],
///     &[[0, 1, 2], [0, 2, 3]],
/// ));
/// let at = |x: f64| Instance::new(bvh.clone(), &Isometry::translation(e2, Complex64::new(x, 0.0)), 0.0);
/// let objects = Instances::new(vec![at(0.5), at(0.25)]);
/// let ray = Ray::new(e2, DVec3::Z, DVec3::X, 0.1, 0.0);
/// // Model x = 0.25 is intrinsic distance 0.5 (λ = 2): the second object is hit first.
/// let (index, hit) = objects.intersect(e2, &ray, 0.0, 10.0).unwrap();
/// assert_eq!(index, 1);
/// assert!((hit.s - 0.5).abs() < 1e-12);
/// ```
#[derive(Clone, Debug, Default)]
pub struct Instances {
    instances: Vec<Instance>,
    bounds: Vec<Option<Bound>>,
}

impl Instances {
    /// The given objects.
    pub fn new(instances: Vec<Instance>) -> Instances {
        let bounds = instances.iter().map(Instance::world_bound).collect();
        Instances { instances, bounds }
    }

    /// The objects.
    pub fn instances(&self) -> &[Instance] {
        &self.instances
    }

    /// The number of objects.
    pub fn len(&self) -> usize {
        self.instances.len()
    }

    /// Whether there are no objects.
    pub fn is_empty(&self) -> bool {
        self.instances.is_empty()
    }

    /// Adds an object; returns its index.
    pub fn push(&mut self, instance: Instance) -> usize {
        self.bounds.push(instance.world_bound());
        self.instances.push(instance);
        self.instances.len() - 1
    }

    /// Moves object `index` to a new isometry and height (nothing is rebuilt).
    ///
    /// # Panics
    ///
    /// When `index` is out of range.
    pub fn set_transform(&mut self, index: usize, isometry: &Isometry, height: f64) {
        let instance = &mut self.instances[index];
        instance.to_world = isometry.matrix();
        instance.to_object = isometry.inverse().matrix();
        instance.height = height;
        self.bounds[index] = instance.world_bound();
    }

    /// The nearest hit at arc length in `[s_min, s_max]` (`s_min` finite): the object's index and
    /// the hit in its mesh.
    pub fn intersect(
        &self,
        space: Space,
        ray: &Ray,
        s_min: f64,
        s_max: f64,
    ) -> Option<(usize, TriangleHit)> {
        // One object (the usual scene): no list of candidates to allocate and sort — this runs
        // for every stretch of every path between two mirrors — and no world bound test, which
        // would repeat the BVH's test of its root bound.
        if let [instance] = self.instances.as_slice() {
            return instance
                .intersect(space, ray, s_min, s_max)
                .map(|hit| (0, hit));
        }
        let frame = RayFrame::new(space, ray);
        let mut candidates: Vec<(f64, usize)> = self
            .bounds
            .iter()
            .enumerate()
            .filter_map(|(i, b)| {
                let b = b.as_ref()?;
                let entry = frame.entry(b.centre, b.reach, b.h_lo, b.h_hi, s_min, s_max)?;
                Some((entry, i))
            })
            .collect();
        candidates.sort_by(|a, b| a.0.total_cmp(&b.0));
        let mut best: Option<(usize, TriangleHit)> = None;
        let mut best_s = s_max;
        for (entry, i) in candidates {
            if entry > best_s {
                break;
            }
            if let Some(hit) = self.instances[i].intersect(space, ray, s_min, best_s)
                && hit.s <= best_s
            {
                best_s = hit.s;
                best = Some((i, hit));
            }
        }
        best
    }

    /// Whether the ray meets any object at arc length in `[s_min, s_max]` (for shadow rays).
    pub fn occluded(&self, space: Space, ray: &Ray, s_min: f64, s_max: f64) -> bool {
        if let [instance] = self.instances.as_slice() {
            return instance.occluded(space, ray, s_min, s_max);
        }
        let frame = RayFrame::new(space, ray);
        self.instances.iter().zip(&self.bounds).any(|(o, b)| {
            b.as_ref().is_some_and(|b| {
                frame
                    .entry(b.centre, b.reach, b.h_lo, b.h_hi, s_min, s_max)
                    .is_some()
            }) && o.occluded(space, ray, s_min, s_max)
        })
    }
}
