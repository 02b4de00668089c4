//! The rays of the seed's Table 8.2 (section 8.3.4): 146 locations spread evenly around an
//! object, each shooting 614 rays spread evenly over a cone aimed at the object — 89,644 rays.
//! Shared by the `trace` benchmark and the `hierarchy_table` example.
#![allow(dead_code)] // Each includer uses part of it.

use std::path::{Path, PathBuf};

use glam::DVec3;
use num_complex::Complex64;
use orbifold::space::Space;
use orbifold_scene::geometry::{Fit, embed_object};
use orbifold_scene::mesh::TriangleMesh;
use orbifold_scene::mesh::import::load_mesh;
use orbifold_trace::geodesic::Ray;

/// Locations around the object.
pub const LOCATIONS: usize = 146;
/// Rays per location.
pub const RAYS_PER_LOCATION: usize = 614;
/// The object's largest extent, in intrinsic units.
pub const OBJECT_SIZE: f64 = 1.0;
/// Horizontal distance of the locations from the object's centre.
pub const DISTANCE: f64 = 1.5;
/// Half-angle of each location's cone of rays (it covers the object).
pub const CONE: f64 = 0.45;

/// The benchmark models of `../shared/models/` (relative to the workspace root).
pub const MODELS: [&str; 5] = [
    "teapot.obj",
    "dragon.ply",
    "bunny.obj",
    "lucy.obj",
    "buddha.obj",
];

/// The models folder beside the workspace, if it is there.
pub fn models_dir() -> Option<PathBuf> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../../shared/models");
    dir.is_dir().then_some(dir)
}

/// A model read from the models folder.
pub fn load(name: &str) -> Option<TriangleMesh> {
    load_mesh(&models_dir()?.join(name)).ok()
}

/// An object embedded at the origin of `space`, `OBJECT_SIZE` across: points and heights.
pub fn embedded(space: Space, mesh: &TriangleMesh) -> (Vec<DVec3>, Vec<f64>) {
    let e = embed_object(space, mesh, Fit::Size(OBJECT_SIZE)).expect("a mesh with an extent");
    (e.points, e.heights)
}

/// The golden-angle spiral: point `k` of `n`, as a fraction in (0, 1) and a turn.
fn spiral(k: usize, n: usize) -> (f64, f64) {
    let golden = std::f64::consts::PI * (3.0 - 5f64.sqrt());
    ((k as f64 + 0.5) / n as f64, k as f64 * golden)
}

/// The 89,644 rays around an object of height `top` standing at the origin.
pub fn rays(space: Space, top: f64) -> Vec<Ray> {
    let mut rays = Vec::with_capacity(LOCATIONS * RAYS_PER_LOCATION);
    let origin = Complex64::new(0.0, 0.0);
    for l in 0..LOCATIONS {
        let (t, bearing) = spiral(l, LOCATIONS);
        // At intrinsic distance DISTANCE (model radius tan_κ(d/2)), heights from 0 to the top.
        let z = Complex64::from_polar(space.tan(0.5 * DISTANCE), bearing);
        let height = t * top;
        let towards = space.direction(z, origin);
        let pitch_to_centre = (0.5 * top - height).atan2(DISTANCE);
        for k in 0..RAYS_PER_LOCATION {
            // Evenly over the cone: area-uniform radius, golden-angle turn.
            let (u, turn) = spiral(k, RAYS_PER_LOCATION);
            let off = CONE * u.sqrt();
            let yaw = towards.arg() + off * turn.cos();
            let pitch = pitch_to_centre + off * turn.sin();
            rays.push(Ray::from_model(space, z, height, yaw, pitch));
        }
    }
    rays
}
