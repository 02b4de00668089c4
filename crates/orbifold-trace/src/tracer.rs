//! Following rays through a mirror room: the analytic room, its mirrors and its objects.
//!
//! A ray runs until it meets a surface that is not a mirror or a portal, escapes (a horizontal
//! ray running out through an ideal corner), or has passed `max_bounces` mirrors and portals
//! (rays that approach an ideal corner bounce forever; they end here and go dark, as in the
//! seed's Fig. 8.12). Each mirror multiplies the ray's throughput by its reflectance, each
//! portal by its transmittance; a portal sends the ray on from its partner wall
//! ([`crate::room::Passage`]).

use std::path::Path;
use std::sync::Arc;

use glam::DVec3;
use orbifold::Layout;
use orbifold::space::Space;
use orbifold_scene::{Color, Scene};

use crate::accel::Bvh;
use crate::accel::{Instance, Instances};
use crate::geodesic::Ray;
use crate::room::{AnalyticRoom, RoomSurface};

/// What a ray met.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SurfaceId {
    /// The floor.
    Floor,
    /// The ceiling.
    Ceiling,
    /// Wall `i` (the edge index of `orbifold layout`).
    Wall(usize),
    /// Object `i` of the scene.
    Object(usize),
}

impl SurfaceId {
    /// The integer written in the surface-id AOV: 0 floor, 1 ceiling, 2 + i for wall i,
    /// 1000 + i for object i (and −1, written by the AOV pass, for no surface).
    pub fn code(self) -> i32 {
        match self {
            SurfaceId::Floor => 0,
            SurfaceId::Ceiling => 1,
            SurfaceId::Wall(i) => 2 + i as i32,
            SurfaceId::Object(i) => 1000 + i as i32,
        }
    }
}

impl From<RoomSurface> for SurfaceId {
    fn from(s: RoomSurface) -> Self {
        match s {
            RoomSurface::Floor => SurfaceId::Floor,
            RoomSurface::Ceiling => SurfaceId::Ceiling,
            RoomSurface::Wall(i) => SurfaceId::Wall(i),
        }
    }
}

/// The nearest surface along a ray.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Hit {
    /// Arc length from the ray's origin.
    pub s: f64,
    /// What was hit.
    pub surface: SurfaceId,
    /// Ambient horizontal position.
    pub point: DVec3,
    /// The ray's unit horizontal tangent there (before any reflection; [`Ray::continued`]).
    pub tangent: DVec3,
    /// Height.
    pub height: f64,
    /// For an object, the triangle and barycentric coordinates.
    pub triangle: Option<(u32, [f64; 3])>,
}

/// One hit of a traced path.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PathHit {
    /// The hit.
    pub hit: Hit,
    /// For a mirror, its index on the wall.
    pub mirror: Option<usize>,
    /// For a portal, the partner wall the ray went on from.
    pub portal: Option<usize>,
    /// Arc length from the path's start.
    pub s: f64,
    /// The product of the reflectances of the mirrors and the transmittances of the portals
    /// passed so far, this one included.
    pub throughput: Color,
}

/// How a path ended.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PathEnd {
    /// At a surface that is not a mirror (the last hit).
    Surface,
    /// After the largest number of mirrors and portals allowed.
    BounceLimit,
    /// It left the room through an ideal corner without meeting anything.
    Escaped,
}

/// A ray followed through the mirrors.
#[derive(Clone, Debug, PartialEq)]
pub struct TracedPath {
    /// Every hit in order; mirrors and portals first, then the surface where it ended (if any).
    pub hits: Vec<PathHit>,
    /// How it ended.
    pub end: PathEnd,
    /// The ray after its last mirror or portal (what goes on from the last hit).
    pub last_ray: Ray,
}

/// A mirror room with its objects, ready to trace.
///
/// ```
/// use orbifold::{Layout, LayoutOptions};
/// use orbifold_trace::geodesic::Ray;
/// use orbifold_trace::tracer::{PathEnd, Tracer};
/// use num_complex::Complex64;
/// let layout = Layout::new(&"*2222".parse()?, &LayoutOptions::default())?;
/// let tracer = Tracer::mirror_room(layout, 1.0)?;
/// // A horizontal ray in a room of full mirrors bounces until the limit.
/// let ray = Ray::from_model(tracer.space(), Complex64::new(0.0, 0.0), 0.5, 0.3, 0.0);
/// let path = tracer.follow(&ray, 10);
/// assert_eq!(path.end, PathEnd::BounceLimit);
/// assert_eq!(path.hits.len(), 10);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
#[derive(Clone, Debug)]
pub struct Tracer {
    /// The polygon.
    pub layout: Layout,
    /// The analytic room.
    pub room: AnalyticRoom,
    /// The objects, as instances.
    pub objects: Instances,
    /// The objects' names (`objects` order), for reports.
    pub object_names: Vec<String>,
}

impl Tracer {
    /// The room of `layout`, `height` high, every wall a full mirror of reflectance 1 and no
    /// objects.
    pub fn mirror_room(layout: Layout, height: f64) -> Result<Tracer, String> {
        let room = AnalyticRoom::all_mirrors(&layout, height, [1.0; 3])?;
        Ok(Tracer {
            layout,
            room,
            objects: Instances::default(),
            object_names: Vec::new(),
        })
    }

    /// The room, mirrors and objects of a scene; `base` resolves mesh file names.
    pub fn from_scene(scene: &Scene, base: Option<&Path>) -> Result<Tracer, String> {
        let layout = scene.layout()?;
        let room = AnalyticRoom::from_scene(scene, &layout)?;
        let space = layout.space();
        let mut instances = Vec::with_capacity(scene.objects.len());
        let mut object_names = Vec::with_capacity(scene.objects.len());
        for (i, object) in scene.objects.iter().enumerate() {
            let (embedded, triangles, placement) = scene.embedded_object(&layout, i, base)?;
            let mut bvh = Bvh::build(space, &embedded.points, &embedded.heights, &triangles);
            if object.crease > 0.0 {
                bvh = bvh.with_smooth_normals(space, object.crease.to_radians());
            }
            instances.push(Instance::from_placement(space, Arc::new(bvh), &placement));
            object_names.push(object.name.clone().unwrap_or_else(|| i.to_string()));
        }
        Ok(Tracer {
            layout,
            room,
            objects: Instances::new(instances),
            object_names,
        })
    }

    /// The plane.
    pub fn space(&self) -> Space {
        self.room.space
    }

    /// The nearest surface along a ray from inside the room: an object, or the face of the room
    /// where the ray leaves it.
    pub fn nearest(&self, ray: &Ray) -> Option<Hit> {
        let space = self.space();
        let exit = self.room.exit(ray);
        let limit = exit.map_or(f64::INFINITY, |e| e.s);
        if let Some((i, t)) = self.objects.intersect(space, ray, 0.0, limit) {
            let (point, tangent, height) = ray.point_and_tangent_at(space, t.s);
            return Some(Hit {
                s: t.s,
                surface: SurfaceId::Object(i),
                point,
                tangent,
                height,
                triangle: Some((t.triangle, t.barycentric)),
            });
        }
        exit.map(|e| Hit {
            s: e.s,
            surface: e.surface.into(),
            point: e.point,
            tangent: e.tangent,
            height: e.height,
            triangle: None,
        })
    }

    /// Follows a ray through at most `max_bounces` mirrors and portals.
    pub fn follow(&self, ray: &Ray, max_bounces: usize) -> TracedPath {
        let space = self.space();
        let mut ray = *ray;
        let mut hits = Vec::new();
        let mut travelled = 0.0;
        let mut throughput = [1.0; 3];
        loop {
            let Some(hit) = self.nearest(&ray) else {
                return TracedPath {
                    hits,
                    end: PathEnd::Escaped,
                    last_ray: ray,
                };
            };
            travelled += hit.s;
            let passage = match hit.surface {
                SurfaceId::Wall(w) => self.room.passage(w, hit.point, hit.height),
                _ => None,
            };
            let Some(passage) = passage else {
                hits.push(PathHit {
                    hit,
                    mirror: None,
                    portal: None,
                    s: travelled,
                    throughput,
                });
                return TracedPath {
                    hits,
                    end: PathEnd::Surface,
                    last_ray: ray,
                };
            };
            if hits.len() >= max_bounces {
                return TracedPath {
                    hits,
                    end: PathEnd::BounceLimit,
                    last_ray: ray,
                };
            }
            for (t, r) in throughput.iter_mut().zip(passage.throughput) {
                *t *= r;
            }
            hits.push(PathHit {
                hit,
                mirror: passage.mirror,
                portal: passage.portal_to,
                s: travelled,
                throughput,
            });
            ray = ray
                .continued(space, hit.s, hit.point, hit.tangent)
                .passed(space, &passage);
        }
    }

    /// The name of a surface in reports: `floor`, `ceiling`, `wall 2`, `object NAME`.
    pub fn surface_name(&self, surface: SurfaceId) -> String {
        match surface {
            SurfaceId::Floor => "floor".into(),
            SurfaceId::Ceiling => "ceiling".into(),
            SurfaceId::Wall(i) => format!("wall {i}"),
            SurfaceId::Object(i) => match self.object_names.get(i) {
                Some(name) => format!("object {name}"),
                None => format!("object {i}"),
            },
        }
    }
}
