//! Light transport in mirror rooms of S²×R, E²×R and H²×R: a unidirectional path tracer with
//! next-event estimation through mirror images, multiple importance sampling and Russian
//! roulette (ARCHITECTURE.md §8; docs/rendering.md).
//!
//! A camera path runs along exact geodesics. Mirrors are followed deterministically (their
//! reflectance multiplies the path's throughput); at every other surface the path gathers direct
//! light and then scatters by its BSDF. Direct light is sampled through the mirror images of the
//! lights: a (light, image, way round) choice, a point on that light, and the geodesic from the
//! surface to the light's image, followed through the real room; it counts only if it arrives at
//! the light through mirrors alone.
//!
//! [`Integrator`] holds the scene ready to render and is built here ([`Integrator::from_scene`]);
//! the rest is split by concept, as in pbrt:
//!
//! - `settings.rs`: [`Settings`], what the light transport does;
//! - `path.rs`: the path loop ([`Integrator::sample_pixel_cached`]) and what a path returns
//!   ([`PathSample`], [`FirstHit`]);
//! - `mirror_segment.rs`: following a ray through the mirrors to the next thing that is not
//!   one (a *mirror segment*), with Russian roulette, for path rays and shadow rays alike;
//! - `ray_footprint.rs`: the pixel and bounce footprints that rays carry, which count small
//!   light images by coverage and filter textures;
//! - `surface.rs`: normals and BSDF where a ray meets a surface, and the shading-normal guards;
//! - `light_sampler.rs`: the choice of light, image and way round, and its probability;
//! - `direct_light.rs`: the light sample (resampled among candidates) and its MIS weight;
//! - `radiance_cache_use.rs`: reading and feeding the radiance cache.
//!
//! Textures and materials, which turn a scene's surface descriptions into BSDFs at a point, are
//! in [`crate::textures`] and [`crate::materials`].

mod direct_light;
mod light_sampler;
mod mirror_segment;
mod path;
mod radiance_cache_use;
mod ray_footprint;
mod settings;
mod surface;

use glam::DVec3;
use num_complex::Complex64;
use orbifold::space::Space;
use orbifold_scene::Scene;
use orbifold_trace::footprint::Sphere;
use orbifold_trace::tracer::Tracer;

use self::light_sampler::{Entry, NearImages};
use crate::lights::{ImageSet, Light, Rgb, TangentFrame};
use crate::materials::SurfaceMaterial;
use crate::sampler::Distribution1d;
use crate::straight_rays::{flatten_light, flatten_tracer};

pub use self::direct_light::{
    DEFAULT_LIGHT_CANDIDATES, FEW_CANDIDATES, FEW_ENTRIES, MAX_LIGHT_CANDIDATES,
};
pub use self::mirror_segment::MAX_MIRROR_BOUNCES;
pub use self::path::{FirstHit, PathSample};
pub use self::settings::Settings;

/// How far a new ray starts from the surface it leaves (intrinsic units).
const RAY_EPSILON: f64 = 1e-7;

/// A mirror room ready to render: geometry, materials, lights and their images.
#[derive(Clone, Debug)]
pub struct Integrator {
    /// Room and objects.
    pub tracer: Tracer,
    /// The lights.
    pub lights: Vec<Light>,
    /// The room's mirror images.
    pub images: ImageSet,
    /// Light transport settings.
    pub settings: Settings,
    entries: Vec<Entry>,
    distribution: Option<Distribution1d>,
    /// Indices into `entries` weighted per surface point (at most `NEAR_MAX`).
    near: Vec<usize>,
    /// What the per-point weights need of the `near` entries, side by side.
    near_images: NearImages,
    floor: SurfaceMaterial,
    ceiling: SurfaceMaterial,
    walls: Vec<SurfaceMaterial>,
    objects: Vec<SurfaceMaterial>,
    centre: DVec3,
    centre_frame: TangentFrame,
    /// The sphere lights (index, as the footprint sees them, radiance).
    spheres: Vec<(usize, Sphere, Rgb)>,
}

/// Channel by channel product.
fn mul(a: Rgb, b: Rgb) -> Rgb {
    [a[0] * b[0], a[1] * b[1], a[2] * b[2]]
}

/// Every channel times `s`.
fn scale(a: Rgb, s: f64) -> Rgb {
    a.map(|v| v * s)
}

/// Adds `b` to `a`, channel by channel.
fn add(a: &mut Rgb, b: Rgb) {
    for (x, y) in a.iter_mut().zip(b) {
        *x += y;
    }
}

impl Integrator {
    /// The scene's room, objects, materials and lights; `base` resolves file names.
    pub fn from_scene(
        scene: &Scene,
        base: Option<&std::path::Path>,
        settings: Settings,
    ) -> Result<Integrator, String> {
        let mut tracer = Tracer::from_scene(scene, base)?;
        let mut lights = Light::from_scene(tracer.space(), scene)?;
        if settings.straight_rays {
            let curved = tracer.space();
            lights = lights
                .iter()
                .map(|l| flatten_light(curved, l))
                .collect::<Result<_, _>>()?;
            tracer = flatten_tracer(&tracer);
        }
        let space = tracer.space();
        let centre = space.to_ambient(tracer.layout.centre);
        let images = ImageSet::new(&tracer.room, centre);
        let wall_material = |i: usize| {
            scene
                .walls
                .iter()
                .find(|w| w.index == i)
                .and_then(|w| w.material.clone())
                .unwrap_or_else(|| scene.room.wall_material.clone())
        };
        let walls = (0..tracer.room.walls.len())
            .map(|i| SurfaceMaterial::new(&wall_material(i), base))
            .collect::<Result<_, _>>()?;
        let objects = scene
            .objects
            .iter()
            .map(|o| SurfaceMaterial::new(&o.material, base))
            .collect::<Result<_, _>>()?;
        let mut integrator = Integrator {
            floor: SurfaceMaterial::new(&scene.room.floor, base)?,
            ceiling: SurfaceMaterial::new(&scene.room.ceiling, base)?,
            walls,
            objects,
            centre,
            centre_frame: TangentFrame::at(space, centre),
            tracer,
            lights,
            images,
            settings,
            entries: Vec::new(),
            distribution: None,
            near: Vec::new(),
            near_images: NearImages::default(),
            spheres: Vec::new(),
        };
        if settings.pixel_footprint && !settings.straight_rays {
            integrator.spheres = integrator.footprint_spheres();
        }
        integrator.build_light_distribution(scene.room.height);
        Ok(integrator)
    }

    /// The plane.
    pub fn space(&self) -> Space {
        self.tracer.space()
    }

    /// The model point of the room's centre (for cameras and tests).
    pub fn centre(&self) -> Complex64 {
        self.tracer.layout.centre
    }
}
