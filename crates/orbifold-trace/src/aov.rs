//! Arbitrary output variables: per-pixel geometry of what a camera sees through the mirrors —
//! geodesic depth, hit position, normal, surface id and mirror-bounce count — for the renderer,
//! the preview's tests and users, written as the channels of one EXR layer.
//!
//! Channels (all `f32`): `Z` the total arc length from the eye to the surface where the ray
//! ended (+∞ where it ended at no surface); `P.X`, `P.Y` its model position and `P.Z` its height;
//! `N.X`, `N.Y`, `N.Z` its unit normal in the local frame at the hit (model +x, model +y, up),
//! facing into the room (objects: facing the ray); `id` the surface code of
//! [`SurfaceId::code`] (−1 for none); `bounces` the number of mirror reflections.

use std::io::Cursor;

use glam::DVec3;
use num_complex::Complex64;
use rayon::prelude::*;

use crate::camera::Camera;
use crate::tracer::{PathEnd, SurfaceId, Tracer};
use crate::triangle::TriangleHit;

/// The AOVs of one image, row-major from the top-left pixel.
#[derive(Clone, Debug, PartialEq)]
pub struct Aovs {
    /// Image width in pixels.
    pub width: u32,
    /// Image height in pixels.
    pub height: u32,
    /// Geodesic depth (arc length), +∞ for no surface.
    pub depth: Vec<f32>,
    /// Model x, y and height of the final hit (0 for no surface).
    pub position: Vec<[f32; 3]>,
    /// Unit normal in the local frame (0 for no surface).
    pub normal: Vec<[f32; 3]>,
    /// Surface code, −1 for none.
    pub surface: Vec<i32>,
    /// Mirror reflections before the final hit.
    pub bounces: Vec<u32>,
}

/// One pixel's AOVs.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PixelAov {
    /// Geodesic depth.
    pub depth: f64,
    /// Model position and height.
    pub position: [f64; 3],
    /// Unit normal in the local frame.
    pub normal: [f64; 3],
    /// Surface code.
    pub surface: i32,
    /// Mirror reflections.
    pub bounces: u32,
}

/// Traces the centre of every pixel (in parallel) and gathers its AOVs.
///
/// ```
/// use orbifold::{Layout, LayoutOptions};
/// use orbifold_trace::{aov, camera::Camera, tracer::Tracer};
/// use orbifold_scene::Camera as Settings;
/// let layout = Layout::new(&"*333".parse()?, &LayoutOptions::default())?;
/// let tracer = Tracer::mirror_room(layout, 1.0)?;
/// let camera = Camera::new(tracer.space(), &Settings { at: [0.0, 0.0], pitch: 0.0, ..Settings::default() });
/// let aovs = aov::render(&tracer, &camera, 9, 7, 20);
/// // The middle pixel looks level: with full mirrors all round it bounces until the limit.
/// assert_eq!((aovs.surface[3 * 9 + 4], aovs.bounces[3 * 9 + 4]), (-1, 20));
/// // The top row sees the ceiling (code 1), perhaps through mirrors.
/// assert_eq!(aovs.surface[4], 1);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn render(tracer: &Tracer, camera: &Camera, width: u32, height: u32, bounces: usize) -> Aovs {
    let pixels: Vec<PixelAov> = (0..width * height)
        .into_par_iter()
        .map(|k| {
            let ray = camera.ray(k % width, k / width, width, height, (0.5, 0.5));
            pixel(tracer, &ray, bounces)
        })
        .collect();
    Aovs {
        width,
        height,
        depth: pixels.iter().map(|p| p.depth as f32).collect(),
        position: pixels
            .iter()
            .map(|p| p.position.map(|v| v as f32))
            .collect(),
        normal: pixels.iter().map(|p| p.normal.map(|v| v as f32)).collect(),
        surface: pixels.iter().map(|p| p.surface).collect(),
        bounces: pixels.iter().map(|p| p.bounces).collect(),
    }
}

/// The AOVs of one ray.
pub fn pixel(tracer: &Tracer, ray: &crate::geodesic::Ray, bounces: usize) -> PixelAov {
    let path = tracer.follow(ray, bounces);
    let mirrors = path.hits.iter().filter(|h| h.mirror.is_some()).count() as u32;
    let last = path.hits.last().filter(|_| path.end == PathEnd::Surface);
    let Some(last) = last else {
        return PixelAov {
            depth: f64::INFINITY,
            position: [0.0; 3],
            normal: [0.0; 3],
            surface: -1,
            bounces: mirrors,
        };
    };
    let space = tracer.space();
    let hit = last.hit;
    let z = space.to_model(hit.point);
    let frame = [
        space.model_tangent(z, Complex64::new(1.0, 0.0)),
        space.model_tangent(z, Complex64::new(0.0, 1.0)),
    ];
    let local = |horizontal: DVec3, vertical: f64| {
        [
            space.point_dot(horizontal, frame[0]),
            space.point_dot(horizontal, frame[1]),
            vertical,
        ]
    };
    let normal = match hit.surface {
        SurfaceId::Floor => [0.0, 0.0, 1.0],
        SurfaceId::Ceiling => [0.0, 0.0, -1.0],
        SurfaceId::Wall(i) => {
            let nu = tracer.room.wall_form_at(i, hit.point);
            local(DVec3::new(nu.x, nu.y, space.kappa() * nu.z), 0.0)
        }
        SurfaceId::Object(i) => {
            let (triangle, barycentric) = hit.triangle.unwrap_or((0, [1.0 / 3.0; 3]));
            let at = TriangleHit {
                s: hit.s,
                triangle,
                barycentric,
            };
            match tracer.objects.instances()[i].normal(space, &at) {
                Some((horizontal, vertical)) => {
                    // Face the ray: the normal's side is the mesh's winding, which imported
                    // meshes do not always keep.
                    let ray = &path.last_ray;
                    let along = ray.tangent_at(space, hit.s * ray.cos_elevation);
                    let facing = space.point_dot(horizontal, along) * ray.cos_elevation
                        + vertical * ray.sin_elevation;
                    let sign = if facing > 0.0 { -1.0 } else { 1.0 };
                    local(horizontal * sign, vertical * sign)
                }
                None => [0.0; 3],
            }
        }
    };
    PixelAov {
        depth: last.s,
        position: [z.re, z.im, hit.height],
        normal,
        surface: hit.surface.code(),
        bounces: mirrors,
    }
}

impl Aovs {
    /// The AOVs as an EXR file's bytes: one layer named `aov` with the channels listed in the
    /// module documentation, lossless (ZIP) compressed.
    pub fn to_exr(&self) -> Result<Vec<u8>, String> {
        use exr::prelude::*;
        let size = (self.width as usize, self.height as usize);
        let channel =
            |name: &str, values: Vec<f32>| AnyChannel::new(name, FlatSamples::F32(values));
        let component = |v: &[[f32; 3]], k: usize| v.iter().map(|p| p[k]).collect::<Vec<f32>>();
        let channels = vec![
            channel("Z", self.depth.clone()),
            channel("P.X", component(&self.position, 0)),
            channel("P.Y", component(&self.position, 1)),
            channel("P.Z", component(&self.position, 2)),
            channel("N.X", component(&self.normal, 0)),
            channel("N.Y", component(&self.normal, 1)),
            channel("N.Z", component(&self.normal, 2)),
            channel("id", self.surface.iter().map(|&v| v as f32).collect()),
            channel("bounces", self.bounces.iter().map(|&v| v as f32).collect()),
        ];
        let layer = Layer::new(
            size,
            LayerAttributes::named("aov"),
            Encoding::SMALL_LOSSLESS,
            AnyChannels::sort(SmallVec::from_vec(channels)),
        );
        let mut bytes = Cursor::new(Vec::new());
        Image::from_layer(layer)
            .write()
            .to_buffered(&mut bytes)
            .map_err(|e| format!("cannot encode the EXR: {e}"))?;
        Ok(bytes.into_inner())
    }
}
