//! Straight rays (`orbifold render --straight-rays`): the room as its model picture, lit and
//! seen as if space were flat — what an ordinary renderer shows when it is given the model
//! coordinates of a non-Euclidean room (the seed's Fig. 8.1a and Fig. 8.4, left).
//!
//! Every point keeps its model position and height; the flat plane's ambient coordinates are
//! (2x, 2y, 1) for the model point x + iy, so that lengths agree with the curved plane's at the
//! model's origin, where its conformal factor is 2. Walls become the model curves of the curved
//! walls (circles, or lines through the origin) and mirrors reflect across their tangent lines,
//! which is no isometry: mirror images bend and light through mirrors cannot be found from
//! images, so light sampling only reaches lights directly (paths that meet a light after
//! mirrors still count it). A portal sends a ray on from the partner wall by the model map of
//! its pairing, to first order at the crossing (`AnalyticRoom::passage`): in E² the pairing
//! itself. Objects and area lights are their curved meshes' model pictures.
//! In a Euclidean room the picture is the room itself, and the two renders agree.

use std::sync::Arc;

use glam::DVec3;
use num_complex::Complex64;
use orbifold::Geometry;
use orbifold::embed::Placement;
use orbifold::space::Space;

use crate::lights::{Emitter, Light, TangentFrame, mesh_emitter};
use orbifold_trace::accel::Bvh;
use orbifold_trace::accel::{Instance, Instances};
use orbifold_trace::tracer::Tracer;

/// The flat plane of straight rays.
pub fn flat_space() -> Space {
    Space::new(Geometry::Euclidean)
}

/// The flat ambient point with the same model position as the curved ambient point `p`.
fn flatten_point(curved: Space, p: DVec3) -> DVec3 {
    flat_space().to_ambient(curved.to_model(p))
}

/// An object's model picture, as a flat instance.
fn flatten_instance(curved: Space, instance: &Instance) -> Instance {
    let (points, heights, triangles) = instance.bvh.mesh();
    let points: Vec<DVec3> = points
        .iter()
        .map(|p| flatten_point(curved, instance.to_world * *p))
        .collect();
    let heights: Vec<f64> = heights.iter().map(|h| h + instance.height).collect();
    let flat = flat_space();
    let mut bvh = Bvh::build(flat, &points, &heights, triangles);
    if let Some(crease) = instance.bvh.crease() {
        bvh = bvh.with_smooth_normals(flat, crease);
    }
    let origin = Placement {
        at: Complex64::new(0.0, 0.0),
        height: 0.0,
        yaw: 0.0,
    };
    Instance::from_placement(flat, Arc::new(bvh), &origin)
}

/// The tracer's room and objects as their model pictures in the flat plane.
///
/// ```
/// use orbifold::{Layout, LayoutOptions};
/// use orbifold_render::straight_rays::flatten_tracer;
/// use orbifold_trace::tracer::Tracer;
/// let layout = Layout::new(&"*2223".parse()?, &LayoutOptions::default())?;
/// let tracer = Tracer::mirror_room(layout, 1.0)?;
/// let flat = flatten_tracer(&tracer);
/// assert_eq!(flat.space().kappa(), 0.0);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn flatten_tracer(tracer: &Tracer) -> Tracer {
    let curved = tracer.space();
    Tracer {
        layout: tracer.layout.clone(),
        room: tracer.room.flattened(),
        objects: Instances::new(
            tracer
                .objects
                .instances()
                .iter()
                .map(|i| flatten_instance(curved, i))
                .collect(),
        ),
        object_names: tracer.object_names.clone(),
    }
}

/// A direction given in local coordinates of `from` at the curved point `p`, in local
/// coordinates of the flat frame `to` at the same model point (the model is conformal: the
/// direction keeps its model bearing and its elevation).
fn flatten_direction(
    curved: Space,
    p: DVec3,
    from: &TangentFrame,
    to: &TangentFrame,
    v: DVec3,
) -> DVec3 {
    let flat = flat_space();
    let z = curved.to_model(p);
    let (horizontal, up) = from.to_ambient(v);
    let model = |space: Space| {
        [
            space.model_tangent(z, Complex64::new(1.0, 0.0)),
            space.model_tangent(z, Complex64::new(0.0, 1.0)),
        ]
    };
    let [cx, cy] = model(curved);
    let (mx, my) = (
        curved.point_dot(horizontal, cx),
        curved.point_dot(horizontal, cy),
    );
    let [fx, fy] = model(flat);
    to.to_local(flat, fx * mx + fy * my, up)
}

/// A light as its model picture in the flat plane, with the same power.
pub fn flatten_light(curved: Space, light: &Light) -> Result<Light, String> {
    let flat = flat_space();
    let position = flatten_point(curved, light.position);
    let frame = TangentFrame::at(flat, position);
    let emitter = match &light.emitter {
        Emitter::Point { intensity } => Emitter::Point {
            intensity: *intensity,
        },
        Emitter::Spot {
            intensity,
            axis,
            cos_cone,
        } => Emitter::Spot {
            intensity: *intensity,
            axis: flatten_direction(curved, light.position, &light.frame, &frame, *axis)
                .normalize(),
            cos_cone: *cos_cone,
        },
        Emitter::Area {
            instance,
            two_sided,
            ..
        } => mesh_emitter(
            flat,
            flatten_instance(curved, instance),
            light.power,
            *two_sided,
        )?,
    };
    Ok(Light {
        position,
        height: light.height,
        frame,
        power: light.power,
        emitter,
    })
}
