//! Light transport in mirror rooms of S²×R, E²×R and H²×R: a unidirectional path tracer with
//! next-event estimation through mirror images, multiple importance sampling and Russian
//! roulette (DESIGN.md §8; docs/rendering.md).
//!
//! A camera path runs along exact geodesics. Mirrors are followed deterministically (their
//! reflectance multiplies the path's throughput); at every other surface the path gathers direct
//! light and then scatters by its BSDF. Direct light is sampled by picking one (light, image,
//! way round) from a distribution fixed per scene (∝ the light's power × the image's
//! reflectance bound / J at its distance from the room's centre), a point on that light, and the
//! geodesic from the surface to the light's image; the geodesic is followed through the real
//! room, and counts only if it arrives at the light through mirrors alone. A path that hits an
//! area light after a non-specular bounce is weighted against that light sample by the power
//! heuristic; the image it came through is found from the walls it met.

use arrayvec::ArrayVec;
use glam::{DMat3, DVec3};
use num_complex::Complex64;
use orbifold::space::Space;
use orbifold_scene::geometry::representative;
use orbifold_scene::{Coordinates, Material, MetalName, Scene};

use crate::lights::{
    AimedLight, Connection, Emitter, ImageSet, Light, LightPoint, Rgb, TangentFrame, aim_at,
    connect, reflection_matrix, spread, travel_direction, turned,
};
use crate::materials::bsdf::{Bsdf, marble};
use crate::radiance_cache::{self, Deposit, RadianceCache, facing};
use crate::sampler::{Distribution1d, Frame, Sampler, power_heuristic};
use crate::straight_rays::{flatten_light, flatten_tracer};
use crate::textures::ImageTexture;
use orbifold_trace::fastmath::{asin_fast, ln_fast};
use orbifold_trace::footprint::{Footprint, Glimpse, Sphere, sphere_coverage};
use orbifold_trace::geodesic::Ray;
use orbifold_trace::room::RoomSurface;
use orbifold_trace::tracer::{SurfaceId, Tracer};
use orbifold_trace::triangle::TriangleHit;

/// How far a new ray starts from the surface it leaves (intrinsic units).
const RAY_EPSILON: f64 = 1e-7;
/// The most mirror reflections on one straight stretch of a path (rays that run into an ideal
/// corner bounce ever faster; they end here, dark).
pub const MAX_MIRROR_BOUNCES: usize = 256;

/// Below this luminance of a path's throughput, mirror chains play Russian roulette.
const ROULETTE_LEVEL: f64 = 0.1;
/// The level for a camera ray that carries its pixel's footprint, much lower: every stretch of
/// it gathers the light images near it ([`orbifold_trace::footprint`]), so that a march cut short
/// early loses a long tail of them, and the paths that survive carry that tail weighted up
/// (at `ROULETTE_LEVEL` this was nearly all the variance of the band of far light images at
/// the horizon of a hyperbolic room; docs/benchmarks.md).
const FOOTPRINT_ROULETTE_LEVEL: f64 = 0.01;

/// Settings of the light transport.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Settings {
    /// The most non-mirror bounces of a path.
    pub max_depth: u32,
    /// Next-event estimation (light sampling through mirror images) with MIS; without it, light
    /// is found only by paths that hit it (brute force, the reference for tests).
    pub nee: bool,
    /// Radiance that every opaque surface other than a mirror or a light emits, uniformly in every
    /// direction (0 by default). A closed room whose surfaces all glow and reflect with albedo
    /// ρ reaches the radiance glow / (1 − ρ) everywhere (the furnace test); a small glow also
    /// shows the room's shape without any lights.
    pub glow: Rgb,
    /// Light as if space were flat: the room's model picture rendered with straight rays (see
    /// [`crate::straight_rays`]; the seed's Fig. 8.1a), for teaching and comparison.
    pub straight_rays: bool,
    /// Carry each camera ray's pixel footprint ([`orbifold_trace::footprint`]; on by default): the
    /// light's mirror images up to a few pixels wide count by the share of the pixel they
    /// cover, not by ray hits, and checkerboards are averaged over the footprint. It needs the room's
    /// mirrors to be isometries, so straight rays never carry it.
    pub pixel_footprint: bool,
    /// With the pixel footprint and light sampling, rays that leave a diffuse bounce carry a
    /// footprint too (`BOUNCE_GLIMPSE`; on by default), with which the far mirror images of
    /// sphere lights that light sampling cannot draw (beyond the image set's cutoff: thousands
    /// in a hyperbolic room) count by the share of it they cover instead of by rare hits of
    /// enormous radiance. Off, those images are found by ray hits alone.
    pub bounce_footprint: bool,
    /// Read the light that far mirror images of diffuse surfaces reflect, and the light that
    /// diffuse surfaces reached by a diffuse bounce reflect, from a cache filled by the render's
    /// own paths ([`crate::radiance_cache`]; on by default, used by [`crate::render`]). It needs
    /// light sampling and the pixel footprint.
    pub radiance_cache: bool,
    /// Candidates drawn for each light sample, of which one is kept by resampling and tested
    /// for visibility (1 for the plain light sample; at most [`MAX_LIGHT_CANDIDATES`]). More
    /// candidates cost something each and lower the noise of direct light wherever the
    /// per-image choice misjudges a point's light. `None` (the default): [`FEW_CANDIDATES`]
    /// where light sampling draws at most [`FEW_ENTRIES`] (light, image, way) choices (the
    /// spherical rooms), else [`DEFAULT_LIGHT_CANDIDATES`].
    pub light_candidates: Option<u32>,
}

impl Default for Settings {
    fn default() -> Self {
        Settings {
            max_depth: 8,
            nee: true,
            glow: [0.0; 3],
            straight_rays: false,
            pixel_footprint: true,
            bounce_footprint: true,
            radiance_cache: true,
            light_candidates: None,
        }
    }
}

impl Settings {
    /// The settings a scene's `[render]` table asks for: its most bounces and whether light
    /// runs in straight lines; the rest as by default.
    ///
    /// ```
    /// use orbifold_render::integrator::Settings;
    /// use orbifold_scene::Scene;
    ///
    /// let mut scene = Scene::default();
    /// scene.render.max_depth = 3;
    /// scene.render.straight_rays = true;
    /// let settings = Settings::of_scene(&scene);
    /// assert_eq!((settings.max_depth, settings.straight_rays), (3, true));
    /// assert!(settings.nee);
    /// ```
    pub fn of_scene(scene: &Scene) -> Settings {
        Settings {
            max_depth: scene.render.max_depth,
            straight_rays: scene.render.straight_rays,
            ..Settings::default()
        }
    }
}

/// A texture: what a diffuse surface's albedo is at a point.
#[derive(Clone, Debug)]
enum Texture {
    Solid(Rgb),
    Checker {
        colors: [Rgb; 2],
        size: f64,
        intrinsic: bool,
    },
    Image {
        image: ImageTexture,
        scale: f64,
        intrinsic: bool,
    },
}

impl Texture {
    fn new(material: &Material, base: Option<&std::path::Path>) -> Result<Texture, String> {
        Ok(match material {
            Material::Color { color } => Texture::Solid(*color),
            Material::Checker {
                colors,
                size,
                coordinates,
            } => Texture::Checker {
                colors: *colors,
                size: *size,
                intrinsic: *coordinates == Coordinates::Intrinsic,
            },
            Material::Texture {
                path,
                scale,
                coordinates,
            } => {
                let file = base.map_or_else(|| path.into(), |b| b.join(path));
                let image = image::open(&file)
                    .map_err(|e| format!("cannot read texture {}: {e}", file.display()))?
                    .to_rgb8();
                let (width, height) = (image.width() as usize, image.height() as usize);
                let pixels = image
                    .pixels()
                    .map(|p| p.0.map(orbifold_scene::color::linear_from_srgb8))
                    .collect::<Vec<_>>();
                if width == 0 || height == 0 {
                    return Err(format!("texture {} has no pixels", file.display()));
                }
                Texture::Image {
                    image: ImageTexture::new(pixels, width, height),
                    scale: *scale,
                    intrinsic: *coordinates == Coordinates::Intrinsic,
                }
            }
            // Not a pattern (`Look` handles these): the colour that stands for it.
            other => Texture::Solid(representative(other)),
        })
    }

    /// The albedo where `lookup` says. Seen by a camera ray, checkerboards and images are
    /// averaged over the pixel's footprint (box filters: in closed form, and by a summed-area
    /// table); marble is point-sampled.
    fn albedo(&self, lookup: &Lookup) -> Rgb {
        match self {
            Texture::Solid(c) => *c,
            Texture::Checker {
                colors,
                size,
                intrinsic: use_intrinsic,
            } => {
                let Some([centre, a, b]) = lookup.footprint else {
                    let p = (lookup.coords)(*use_intrinsic, DVec3::ZERO);
                    let parity: i64 = p.iter().map(|v| (v / size).floor() as i64).sum();
                    return colors[parity.rem_euclid(2) as usize];
                };
                let (p, pa, pb) = (
                    (lookup.coords)(*use_intrinsic, centre),
                    (lookup.coords)(*use_intrinsic, centre + a),
                    (lookup.coords)(*use_intrinsic, centre + b),
                );
                let mut sign = 1.0;
                for i in 0..3 {
                    // The box, axis by axis in texture coordinates, whose second moments are
                    // the footprint's (the parallelogram ±a ± b around the pixel's centre): a
                    // box around the whole parallelogram blurred footprints seen at an angle
                    // to the checks over twice their area.
                    let half = ((pa[i] - p[i]).powi(2) + (pb[i] - p[i]).powi(2)).sqrt();
                    sign *= box_filtered_square_wave(p[i] / size, 2.0 * half / size);
                }
                let (c0, c1) = (colors[0], colors[1]);
                std::array::from_fn(|k| 0.5 * (c0[k] + c1[k]) + 0.5 * (c0[k] - c1[k]) * sign)
            }
            Texture::Image {
                image,
                scale,
                intrinsic: use_intrinsic,
            } => {
                let Some([centre, a, b]) = lookup.footprint else {
                    let p = (lookup.coords)(*use_intrinsic, DVec3::ZERO);
                    return image.texel(p[0] / scale, p[1] / scale);
                };
                let (p, pa, pb) = (
                    (lookup.coords)(*use_intrinsic, centre),
                    (lookup.coords)(*use_intrinsic, centre + a),
                    (lookup.coords)(*use_intrinsic, centre + b),
                );
                let (u, v) = (p[0] / scale, p[1] / scale);
                let half =
                    |i: usize| ((pa[i] - p[i]).powi(2) + (pb[i] - p[i]).powi(2)).sqrt() / scale;
                image.box_mean(u, v, half(0), half(1))
            }
        }
    }
}

/// The mean of the square wave (−1)^⌊t⌋ over [x − w/2, x + w/2] (its value at x when w = 0, or
/// when the box is not finite: 0 then, the wave's mean): differences of its integral, the
/// triangle wave.
fn box_filtered_square_wave(x: f64, w: f64) -> f64 {
    let integral = |t: f64| {
        let m = t.rem_euclid(2.0);
        if m < 1.0 { m } else { 2.0 - m }
    };
    if !(x.is_finite() && w.is_finite()) {
        return 0.0;
    }
    if w < 1e-9 {
        return if x.floor().rem_euclid(2.0) == 0.0 {
            1.0
        } else {
            -1.0
        };
    }
    ((integral(x + 0.5 * w) - integral(x - 0.5 * w)) / w).clamp(-1.0, 1.0)
}

/// Where a texture is looked up.
struct Lookup<'a> {
    /// The texture coordinates (intrinsic or model, as asked) of the point moved by a tangent
    /// vector (local frame; zero for the point itself).
    coords: &'a dyn Fn(bool, DVec3) -> [f64; 3],
    /// For a camera ray's first surface: its pixel's footprint there, as the tangent vector
    /// from the point to where the pixel's centre is seen and two half-axes (local frame), all
    /// in the surface.
    footprint: Option<[DVec3; 3]>,
}

/// A camera ray's pixel footprint where it meets its first surface.
#[derive(Clone, Copy, Debug)]
struct Spread {
    /// Widths across the ray and up (perpendicular to it in its vertical plane).
    widths: (f64, f64),
    /// How far the pixel's centre is seen from the ray, across (to the left) and up: the
    /// footprint's turns to it ([`Footprint::centre`]), grown as the widths have.
    centre: (f64, f64),
    /// The ray's direction of travel (local frame).
    travel: DVec3,
    /// The widest cells of the radiance cache that the surface may read ([`Spread::cache_width`]).
    cache_width: f64,
}

impl Spread {
    /// The footprint of `pixel` carried `s` along a ray of elevation cosine `cos_elevation` and
    /// direction `travel` there.
    fn new(space: Space, pixel: &Footprint, s: f64, cos_elevation: f64, travel: DVec3) -> Spread {
        let widths = pixel.widths(space, s, cos_elevation);
        let grown = |turn: f64, width: f64, angle: f64| {
            let d = turn * width / angle;
            if d.is_finite() { d } else { 0.0 }
        };
        Spread {
            widths,
            centre: (
                grown(pixel.centre[0], widths.0, pixel.across),
                grown(pixel.centre[1], widths.1, pixel.up),
            ),
            travel,
            cache_width: Spread::cache_width(pixel, widths),
        }
    }

    /// How wide the radiance cache's cells read at the surface may be: the footprint's narrower
    /// width, times the square root of how much wider than in flat space curvature has made it
    /// across the ray (S_κ(σ)/(s cos α), the ratio of the two widths for a square pixel). In H²
    /// that ratio grows like e^σ/σ, and the narrower width alone kept the first rings of far
    /// images off the cache; the root blurs their lighting by at most that many pixel heights
    /// up and down and by less than a pixel across. In E² and S² it is the narrower width.
    fn cache_width(pixel: &Footprint, (across, up): (f64, f64)) -> f64 {
        let narrow = across.min(up);
        let stretch = (across * pixel.up) / (up * pixel.across);
        if stretch > 1.0 {
            narrow * stretch.sqrt()
        } else {
            narrow
        }
    }

    /// The tangent vector to where the pixel's centre is seen and the footprint's half-axes,
    /// projected along the ray onto the plane with normal `n`, each at most `MAX_FOOTPRINT`
    /// long (beyond, every pattern is averaged out anyway). Centred on the pixel, the box is
    /// the same for every sample of it, up to the change of the projection across the pixel:
    /// each sample gets the pixel's own filtered value, the one its ray hits average to.
    fn axes(&self, n: DVec3) -> [DVec3; 3] {
        const MAX_FOOTPRINT: f64 = 10.0;
        let d = self.travel;
        let across = d.cross(DVec3::Z).try_normalize().unwrap_or(DVec3::X);
        let up = across.cross(d);
        let facing = n.dot(d);
        let project = |v: DVec3| {
            let p = if facing.abs() > 1e-6 {
                v - d * (n.dot(v) / facing)
            } else {
                v
            };
            // What rounding leaves along the normal, taken off: on the floor it would move
            // the point a hair below height 0, onto the other side of a 3D checker's layer.
            let p = p - n * n.dot(p);
            p.clamp_length_max(MAX_FOOTPRINT)
        };
        [
            project(up * self.centre.1 - across * self.centre.0),
            project(across * (0.5 * self.widths.0)),
            project(up * (0.5 * self.widths.1)),
        ]
    }
}

/// A surface's material, ready to give the BSDF at a point.
#[derive(Clone, Debug)]
enum Look {
    /// Lambertian with a texture.
    Diffuse(Texture),
    /// Anything whose BSDF is the same everywhere (glass, metal).
    Uniform(Bsdf),
    /// Rough plastic over a textured base.
    Plastic(Texture, f64),
    /// Procedural marble (diffuse): ground, vein, scale, intrinsic coordinates.
    Marble(Rgb, Rgb, f64, bool),
}

impl Look {
    fn new(material: &Material, base: Option<&std::path::Path>) -> Result<Look, String> {
        Ok(match material {
            Material::Glass { tint, ior } => Look::Uniform(Bsdf::Dielectric {
                eta: *ior,
                tint: *tint,
            }),
            Material::Metal { metal, roughness } => Look::Uniform(match metal {
                MetalName::Silver => Bsdf::silver(*roughness),
                MetalName::Gold => Bsdf::gold(*roughness),
                MetalName::Copper => Bsdf::copper(*roughness),
                MetalName::Aluminium => Bsdf::aluminium(*roughness),
            }),
            Material::Plastic { color, roughness } => {
                Look::Plastic(Texture::Solid(*color), *roughness)
            }
            Material::Marble {
                base: ground,
                vein,
                scale,
                coordinates,
            } => Look::Marble(
                *ground,
                *vein,
                *scale,
                *coordinates == Coordinates::Intrinsic,
            ),
            _ => Look::Diffuse(Texture::new(material, base)?),
        })
    }

    /// The BSDF where `lookup` says.
    fn bsdf(&self, lookup: &Lookup) -> Bsdf {
        match self {
            Look::Diffuse(texture) => Bsdf::diffuse(texture.albedo(lookup)),
            Look::Uniform(bsdf) => *bsdf,
            Look::Plastic(texture, roughness) => Bsdf::plastic(texture.albedo(lookup), *roughness),
            Look::Marble(ground, vein, scale, use_intrinsic) => {
                let p = (lookup.coords)(*use_intrinsic, DVec3::ZERO);
                // `marble` takes a frequency; the scene gives the features' size.
                Bsdf::diffuse(marble(DVec3::from(p), *ground, *vein, 1.0 / scale))
            }
        }
    }
}

/// One choice of the light sampler: a light, an image of the room, and (on the sphere) which
/// way round and how many times ([`crate::lights::turned`]).
#[derive(Clone, Copy, Debug, PartialEq)]
struct Entry {
    light: usize,
    image: usize,
    /// Half-turns round the sphere past the image: 0 the short way, 1 the long way, 2 the
    /// short way once more round, … (always 0 off the sphere).
    turns: u32,
    /// What the extra times round cost at most: the mirrors' reflectance over one time round,
    /// to the power of the number of times (1 for the short and the long way).
    attenuation: f64,
    /// The image of the light's centre (ambient) and its height.
    position: DVec3,
    height: f64,
}

/// The first images (breadth first: the nearest tiles) whose light-sampling weights are worked
/// out afresh at every surface point.
const NEAR_IMAGES: usize = 24;
/// The most (light, image, way) choices weighted per surface point.
const NEAR_MAX: usize = 96;
/// The share of light samples that use the per-point weights.
const NEAR_SHARE: f64 = 0.5;
/// The candidates drawn for each light sample by default, of which one is kept and marched
/// ([`Settings::light_candidates`]; measured in docs/benchmarks.md). Each candidate weighs a
/// sphere light's triangles and finds its image's connection, which costs more than its noise
/// is worth beyond three: at 896² in `*444` three leave the same denoised noise per sample as
/// four for 15 % more samples a second (two: 22 % more samples, 5 % more noise), and in
/// `*2222` three reach a lower noise in the same time.
pub const DEFAULT_LIGHT_CANDIDATES: u32 = 3;
/// The candidates by default where light sampling has few choices of image ([`FEW_ENTRIES`]):
/// the candidates then mostly differ only in the point on the light, which a sphere light
/// already draws by solid angle, and two leave the same noise as four for 7-16 % less time
/// (docs/benchmarks.md).
pub const FEW_CANDIDATES: u32 = 2;
/// At most this many (light, image, way) choices count as few ([`FEW_CANDIDATES`]).
pub const FEW_ENTRIES: usize = 256;
/// The most candidates for one light sample.
pub const MAX_LIGHT_CANDIDATES: u32 = 16;
const LIGHT_CANDIDATES: usize = MAX_LIGHT_CANDIDATES as usize;
/// Shifts that make the later candidates' uniforms from the first's: the golden ratio's
/// fraction, and the two-dimensional R₂ sequence's (Roberts 2018), whose multiples are spread
/// evenly.
const GOLDEN: f64 = 0.618_033_988_749_894_9;
const R2: (f64, f64) = (0.754_877_666_246_692_7, 0.569_840_290_998_053_2);
/// On the sphere, light sampling follows the geodesics to each image that go round the sphere
/// up to this many times more (fewer where the mirrors take the light out sooner:
/// [`WRAP_CUTOFF`]). A bounce that reaches a light further round still counts it, unweighted.
const MAX_WRAPS: u32 = 16;
/// The times round are kept while the mirrors' reflectance over them is at least this.
const WRAP_CUTOFF: f64 = 1e-3;
/// Per-point weights treat nothing as closer than this (intrinsic units).
const NEAR_CLAMP: f64 = 0.05;
/// Per-point weights use at least this cosine (a light has a size: part of it can be above the
/// surface's horizon while its centre is below).
const COSINE_FLOOR: f64 = 0.05;

/// The footprint that a ray leaving a diffuse bounce carries to count the far mirror images of
/// sphere lights that light sampling cannot draw (beyond the image set's cutoff, thousands of
/// them in a hyperbolic room) by the share of it they cover, rather than by rare hits of
/// enormous radiance: a box of ±0.1 rad around the ray (the radiance cache's
/// [`radiance_cache::DIFFUSE_SPREAD`]), over which a Lambertian lobe hardly changes (a glossy
/// one could, so glossy bounces leave those images to ray hits). Capped at each light as a
/// camera's footprint is ([`orbifold_trace::footprint`]). Not on the sphere, whose images are few and
/// all drawn.
const BOUNCE_GLIMPSE: Footprint = Footprint {
    across: radiance_cache::DIFFUSE_SPREAD,
    up: radiance_cache::DIFFUSE_SPREAD,
    centre: [0.0; 2],
};

/// The footprint a march counts small sphere-light images with ([`orbifold_trace::footprint`]).
#[derive(Clone, Copy, Debug)]
enum Glimpses<'a> {
    /// A camera ray's pixel: every image.
    Camera(&'a Footprint),
    /// A ray from a diffuse bounce: only the images that light sampling cannot draw.
    Bounce(&'a Footprint),
}

impl Glimpses<'_> {
    fn footprint(&self) -> &Footprint {
        match self {
            Glimpses::Camera(f) | Glimpses::Bounce(f) => f,
        }
    }
}

/// A surface point to be lit by a light sample, with what its BSDF needs.
struct LitPoint<'a> {
    x: DVec3,
    h: f64,
    frame: &'a TangentFrame,
    shading: &'a Frame,
    sides: &'a Sides,
    bsdf: &'a Bsdf,
}

/// A candidate light sample, worked out up to its visibility.
#[derive(Clone, Copy, Debug)]
struct LightCandidate {
    /// The (light, image, way) entry and its probability.
    index: usize,
    pmf: f64,
    /// The point on the light (in its own copy) and the geodesic to its image.
    point: LightPoint,
    link: Connection,
    /// The direction to the light at the lit point (shading frame's ambient local), the BSDF
    /// there and the cosine.
    wi: DVec3,
    f: Rgb,
    cos_x: f64,
    /// The luminance of the contribution if nothing blocks it: the resampling weight.
    weight: f64,
}

/// A candidate of a resampled light sample ([`Integrator::direct`]).
#[derive(Clone, Copy, Debug)]
// A few live in an ArrayVec on the stack per light sample: boxing the large one would allocate.
#[allow(clippy::large_enum_variant)]
enum Candidate {
    /// Drawn in full: its point on the light is in its weight.
    Drawn(LightCandidate),
    /// A sphere light's, weighed from the light's centre ([`Integrator::sphere_weight`]): its
    /// point is drawn, with these uniforms, only if it is kept.
    Deferred {
        index: usize,
        pmf: f64,
        point_uniforms: (f64, (f64, f64)),
        weight: f64,
    },
}

impl Candidate {
    /// Its resampling weight.
    fn weight(&self) -> f64 {
        match self {
            Candidate::Drawn(c) => c.weight,
            Candidate::Deferred { weight, .. } => *weight,
        }
    }
}

/// A surface normal as the per-point light weights use it: its horizontal part (an ambient
/// tangent vector at the point, of length √(1 − up²)) and its vertical part.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
struct Normal {
    across: DVec3,
    up: f64,
}

impl Normal {
    /// The normal `local` (unit, in `frame`'s local coordinates).
    fn new(frame: &TangentFrame, local: DVec3) -> Normal {
        let (across, up) = frame.to_ambient(local);
        Normal { across, up }
    }
}

/// The near light images as the per-point weights use them, one array per quantity so that the
/// loop over them runs several images at a time in SIMD registers (it runs at every path
/// vertex, over up to `NEAR_MAX` images).
#[derive(Clone, Debug, Default)]
struct NearImages {
    /// Ambient position of the image of the light's centre.
    x: Vec<f64>,
    y: Vec<f64>,
    z: Vec<f64>,
    height: Vec<f64>,
    /// 1 for the long way round the sphere (σ → 2π − σ), else 0.
    long_way: Vec<f64>,
    /// Luminance of the light's power × the image's reflectance.
    power: Vec<f64>,
}

impl NearImages {
    fn new(images: impl Iterator<Item = (DVec3, f64, bool, f64)>) -> NearImages {
        let mut near = NearImages::default();
        for (position, height, long_way, power) in images {
            near.x.push(position.x);
            near.y.push(position.y);
            near.z.push(position.z);
            near.height.push(height);
            near.long_way.push(if long_way { 1.0 } else { 0.0 });
            near.power.push(power);
        }
        near
    }

    /// The weights at `(x, h)` with normal `(across, up)` and `floor` in a geometry of
    /// curvature `k` whose sign is `K` (see [`Integrator::near_weights`]), and their sum.
    /// Straight-line code: the inverse functions are `fastmath`'s, the branches selects.
    #[inline(always)]
    fn weights<const K: i32>(
        &self,
        k: f64,
        (x, h, normal, floor): (DVec3, f64, Normal, f64),
        weights: &mut [f64; NEAR_MAX],
    ) -> f64 {
        let Normal { across, up } = normal;
        let n = self.x.len().min(NEAR_MAX);
        let (px, py, pz) = (&self.x[..n], &self.y[..n], &self.z[..n]);
        let (height, long_way, power) = (&self.height[..n], &self.long_way[..n], &self.power[..n]);
        for i in 0..n {
            // σ and S(σ) from the chord c = 2 S(σ/2): S(σ) = c √(1 − κc²/4), with one inverse
            // function.
            let (dx, dy, dz) = (x.x - px[i], x.y - py[i], x.z - pz[i]);
            let c = (dx * dx + dy * dy + k * dz * dz).max(0.0).sqrt();
            let half = 0.5 * c;
            let sigma = match K {
                1 => 2.0 * asin_fast(half.min(1.0)),
                -1 => 2.0 * ln_fast(half + (half * half + 1.0).sqrt()),
                _ => c,
            };
            let sine = if K == 0 {
                c
            } else {
                c * (1.0 - k * half * half).max(0.0).sqrt()
            };
            // The normal's horizontal part along the initial direction u of the geodesic to the
            // image, times σ: ⟨n, y − x⟩ = S(σ)⟨n, u⟩ (σ⟨n, u⟩ in E²); the long way round
            // leaves x along −u and is 2π − σ long.
            let toward = -(across.x * dx + across.y * dy + k * across.z * dz);
            let horizontal = toward * (sigma - long_way[i] * std::f64::consts::TAU)
                / sine.max(f64::MIN_POSITIVE);
            let sigma = sigma + long_way[i] * (std::f64::consts::TAU - 2.0 * sigma);
            let dh = height[i] - h;
            let length2 = sigma * sigma + dh * dh;
            let ratio = if sigma > 1e-9 { sine / sigma } else { 1.0 };
            let cosine = ((horizontal + up * dh) / length2.sqrt()).clamp(COSINE_FLOOR, 1.0);
            weights[i] = power[i] * cosine / (length2 * ratio).max(floor);
        }
        weights[..n].iter().sum()
    }
}

/// What a ray met.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Struck {
    /// A room surface or an object.
    Surface(SurfaceId, Option<(u32, [f64; 3])>),
    /// An area light's mesh.
    Light(usize, u32, [f64; 3]),
}

/// The nearest thing along a ray.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Near {
    s: f64,
    struck: Struck,
    point: DVec3,
    /// The ray's horizontal tangent at `point`, to go on from a mirror ([`Ray::continued`]).
    tangent: DVec3,
    height: f64,
}

/// How a march along a ray through mirrors ended.
#[derive(Clone, Copy, Debug, PartialEq)]
enum MarchEnd {
    /// At something that is not a mirror.
    Hit(Near),
    /// At the requested length, with nothing in the way.
    Reached,
    /// A visibility march stopped by something that is not a mirror (what, it does not find).
    Blocked,
    /// Out through a cusp, or at the mirror-bounce limit.
    Lost,
}

/// Something other than a mirror in the way of a visibility march.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
struct Blocked;

/// A march through mirrors.
#[derive(Clone, Copy, Debug, PartialEq)]
struct March {
    end: MarchEnd,
    /// Product of the mirrors' reflectances.
    throughput: Rgb,
    /// Product of the walls' reflections, first wall first.
    chain: DMat3,
    /// Arc length travelled (to the hit, or the requested length).
    length: f64,
    /// The ray after the last mirror; the end is at arc length `rest` along it.
    ray: Ray,
    /// Arc length along `ray` to the end.
    rest: f64,
    /// Light of sphere lights whose images were counted by the footprint, passed on the way
    /// (with the mirrors' reflectances up to each).
    glimpsed: Rgb,
    /// The sphere light the march ended on, when the footprint counted its image: already
    /// counted in `glimpsed`.
    glimpsed_end: Option<usize>,
}

/// What a camera path saw first — the first surface that is not a mirror — as guides for the
/// denoiser ([`crate::denoise`]), and the two parts of its radiance that the denoiser treats
/// apart: the light seen directly, and the first surface's light sample.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct FirstHit {
    /// The surface's reflectance colour ([`Bsdf::albedo`]); 1 for a light or nothing.
    pub albedo: Rgb,
    /// Its unit normal facing the camera, in the hit point's tangent frame; 0 for nothing.
    pub normal: DVec3,
    /// Arc length from the camera, through the mirrors; 0 for nothing.
    pub depth: f64,
    /// The light the camera saw directly, through mirrors only: the images of lights that the
    /// path hit, or that its pixel's footprint glimpsed, before its first surface. It is part
    /// of the path's radiance; the denoiser leaves it as it is and smooths only the rest, so
    /// that a bright light image neither bleeds into the surfaces around it nor lends them its
    /// noise.
    pub emitted: Rgb,
    /// The light that the first surface reflected straight from a light sample there (next-event
    /// estimation): part of the path's radiance, smooth and well sampled where a light image is
    /// near, which the denoiser filters apart from the rest (the light of longer paths, far
    /// noisier) with its own variance, as SVGF filters direct and indirect light apart.
    pub direct: Rgb,
}

/// One camera path's estimate and what it saw first.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct PathSample {
    /// The radiance estimate.
    pub radiance: Rgb,
    /// The first surface that is not a mirror.
    pub first: FirstHit,
    /// The path's estimate of the light its first diffuse surface reflects, for a
    /// [`RadianceCache`] (only from [`Integrator::sample_pixel_cached`], when that surface was
    /// traced in full).
    pub deposit: Option<Deposit>,
    /// The rays the path traced: geodesic stretches between mirrors, each a search for the
    /// nearest hit or a shadow test (what "rays per second" counts).
    pub rays: u32,
}

thread_local! {
    /// Rays traced on this thread so far ([`Integrator::march`]): a path runs on one thread, so
    /// the difference before and after it is its count, at the cost of a thread-local add.
    static RAYS: std::cell::Cell<u32> = const { std::cell::Cell::new(0) };
}

fn rays_so_far() -> u32 {
    RAYS.with(std::cell::Cell::get)
}

/// The camera path's first diffuse surface, while its estimate there is being traced.
struct Pending {
    point: DVec3,
    height: f64,
    facing: u8,
    /// The path's radiance before the surface's reflected light.
    before: Rgb,
    /// The throughput times the albedo there.
    weight: Rgb,
    /// What the radiance cache holds for the surface, times `weight`, when the path probes a
    /// ready cell: the pixel takes it like any other read, and the path's own estimate only
    /// feeds the cache.
    read: Option<Rgb>,
}

impl Pending {
    /// The estimate, once the path's radiance is `after`.
    fn deposit(&self, after: Rgb) -> Deposit {
        let per_albedo = |c: usize, value: f64| value / self.weight[c];
        Deposit {
            point: self.point,
            height: self.height,
            facing: self.facing,
            total: [0, 1, 2].map(|c| per_albedo(c, after[c] - self.before[c])),
        }
    }
}

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
    floor: Look,
    ceiling: Look,
    walls: Vec<Look>,
    objects: Vec<Look>,
    centre: DVec3,
    centre_frame: TangentFrame,
    /// The sphere lights (index, as the footprint sees them, radiance).
    spheres: Vec<(usize, Sphere, Rgb)>,
}

/// How far above a shading normal's horizon the outgoing direction is kept (cosine).
const SHADING_HORIZON: f64 = 0.02;

/// The shading normal `shading`, bent towards the surface's own normal `geometric` (both on the
/// same side of the surface) just enough that the outgoing direction `wo` stays at least
/// [`SHADING_HORIZON`] above it: interpolated normals tilt away from a viewer near a silhouette,
/// and a BSDF would see the eye below its surface there and go black. Where `wo` grazes the
/// surface itself, the surface's own normal.
fn bent_shading_normal(shading: DVec3, geometric: DVec3, wo: DVec3) -> DVec3 {
    if shading == geometric {
        return shading;
    }
    // The side of the surface wo is on (a dielectric's normals may face away from it).
    let side = if wo.dot(geometric) < 0.0 { -1.0 } else { 1.0 };
    let (g, n) = (geometric * side, shading * side);
    let (above, above_g) = (wo.dot(n), wo.dot(g));
    if n.dot(g) <= 0.0 || above_g <= SHADING_HORIZON {
        return geometric;
    }
    if above >= SHADING_HORIZON {
        return shading;
    }
    // (n + t g)·wo ≥ ε|n + t g|, with |n + t g| ≤ 1 + t.
    let t = (SHADING_HORIZON - above) / (above_g - SHADING_HORIZON);
    (n + g * t).normalize() * side
}

/// Which side of a surface directions are on, by its own normal: with a smooth shading normal a
/// direction can look reflected to the BSDF and yet go into the surface, or the other way round.
/// Such directions carry no light (as in pbrt), which keeps the surface opaque.
struct Sides {
    /// The surface's own unit normal.
    geometric: DVec3,
    /// The direction towards where the path came from.
    wo: DVec3,
}

impl Sides {
    /// Whether `wi` is on the same side of the shading normal `normal` as of the surface itself
    /// (relative to `wo`).
    fn agree(&self, normal: DVec3, wi: DVec3) -> bool {
        let reflected_by_shading = wi.dot(normal) * self.wo.dot(normal) > 0.0;
        let reflected = wi.dot(self.geometric) * self.wo.dot(self.geometric) > 0.0;
        reflected_by_shading == reflected
    }
}

use orbifold_scene::color::luminance;

fn mul(a: Rgb, b: Rgb) -> Rgb {
    [a[0] * b[0], a[1] * b[1], a[2] * b[2]]
}

fn scale(a: Rgb, s: f64) -> Rgb {
    a.map(|v| v * s)
}

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
            .map(|i| Look::new(&wall_material(i), base))
            .collect::<Result<_, _>>()?;
        let objects = scene
            .objects
            .iter()
            .map(|o| Look::new(&o.material, base))
            .collect::<Result<_, _>>()?;
        let mut integrator = Integrator {
            floor: Look::new(&scene.room.floor, base)?,
            ceiling: Look::new(&scene.room.ceiling, base)?,
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

    /// The sphere lights with their clearance from the walls, the floor and the ceiling.
    fn footprint_spheres(&self) -> Vec<(usize, Sphere, Rgb)> {
        let space = self.space();
        let room = &self.tracer.room;
        self.lights
            .iter()
            .enumerate()
            .filter_map(|(l, light)| {
                let (radius, radiance) = light.sphere()?;
                let clearance = room
                    .walls
                    .iter()
                    .map(|w| space.asin(w.form.dot(light.position)).abs())
                    .fold(f64::INFINITY, f64::min);
                let headroom = light.height.min(room.height - light.height);
                let sphere = Sphere::new(
                    space,
                    light.position,
                    light.height,
                    radius,
                    clearance,
                    headroom,
                );
                Some((l, sphere, radiance))
            })
            .collect()
    }

    /// The light sampler's choices and weights: power × image reflectance / J(distance of the
    /// image from the room's centre, at least the room's size).
    fn build_light_distribution(&mut self, height: f64) {
        let space = self.tracer.space();
        let size = self
            .tracer
            .room
            .walls
            .iter()
            .map(|w| space.ambient_distance(self.centre, w.start))
            .fold(height, f64::max);
        let floor = spread(space, size, size);
        // Every geodesic of the sphere comes back round: a point is lit along the short and the
        // long way to each image and along both again after each time round, as long as the
        // mirrors on the way leave something of the light.
        let once_round = self.reflectance_once_round(height);
        let wraps = if space.kappa() > 0.0 && once_round > 0.0 {
            let cut = (WRAP_CUTOFF.ln() / once_round.ln()).ceil();
            if cut.is_finite() {
                (cut as u32).min(MAX_WRAPS)
            } else {
                MAX_WRAPS
            }
        } else {
            0
        };
        let turns = if space.kappa() > 0.0 {
            2 * (wraps + 1)
        } else {
            1
        };
        let mut weights = Vec::new();
        for (l, light) in self.lights.iter().enumerate() {
            for (k, image) in self.images.images.iter().enumerate() {
                let y = image.isometry * light.position;
                let d = space.ambient_distance(self.centre, y);
                for t in 0..turns {
                    let sigma = turned(d, t).0;
                    let attenuation = once_round.powi((t / 2) as i32);
                    // J at least the room's size's, and for the times round at least what
                    // it is that far round from a point as far from the image as the room is
                    // wide: the image's distance from the centre can put it at a focus (J → 0)
                    // that hardly any lit point is near.
                    let j = spread(space, sigma, sigma).max(floor * (sigma / size).max(1.0));
                    let w = luminance(mul(light.power, image.reflectance)) * attenuation / j;
                    if w > 0.0 && w.is_finite() {
                        if k < NEAR_IMAGES && t < 2 && self.near.len() < NEAR_MAX {
                            self.near.push(self.entries.len());
                        }
                        self.entries.push(Entry {
                            light: l,
                            image: k,
                            turns: t,
                            attenuation,
                            position: y,
                            height: light.height,
                        });
                        weights.push(w);
                    }
                }
            }
        }
        self.distribution = Distribution1d::new(&weights);
        self.near_images = NearImages::new(self.near.iter().map(|&e| {
            let entry = &self.entries[e];
            let image = &self.images.images[entry.image];
            let power = luminance(mul(self.lights[entry.light].power, image.reflectance));
            (entry.position, entry.height, entry.turns == 1, power)
        }));
    }

    /// The luminance of the mirrors' reflectance over one time round the sphere, on average
    /// over horizontal great circles from the room's centre at `height` (walls only: the
    /// objects may let the light through elsewhere); 0 off the sphere.
    fn reflectance_once_round(&self, height: f64) -> f64 {
        const DIRECTIONS: usize = 16;
        let space = self.space();
        if space.kappa() <= 0.0 {
            return 0.0;
        }
        let room = &self.tracer.room;
        let h = 0.5 * height;
        let mut sum = 0.0;
        for i in 0..DIRECTIONS {
            let angle = std::f64::consts::TAU * (i as f64 + 0.5) / DIRECTIONS as f64;
            let u = self.centre_frame.e1 * angle.cos() + self.centre_frame.e2 * angle.sin();
            let mut ray = Ray::new(space, self.centre, u, h, 0.0);
            let (mut travelled, mut carried) = (0.0, 1.0);
            while carried > 0.0 {
                let Some(exit) = room.exit(&ray) else {
                    carried = 0.0;
                    break;
                };
                // The crossings of one time round only.
                if travelled + exit.s >= std::f64::consts::TAU {
                    break;
                }
                let RoomSurface::Wall(w) = exit.surface else {
                    carried = 0.0;
                    break;
                };
                carried *= room
                    .mirror_at(w, exit.point, exit.height)
                    .map_or(0.0, |(_, m)| luminance(m.reflectance));
                travelled += exit.s;
                let form = room.wall_form_at(w, exit.point);
                ray =
                    (ray.continued(space, exit.s, exit.point, exit.tangent)).reflected(space, form);
            }
            sum += carried;
        }
        sum / DIRECTIONS as f64
    }

    /// The plane.
    pub fn space(&self) -> Space {
        self.tracer.space()
    }

    /// The per-point weights of the `near` choices at (x, h) (power × reflectance bound / J of
    /// the connection to the image's centre × the cosine there) into `weights`; returns their
    /// sum. `normal` is the unit normal at x.
    ///
    /// The cosine at x of the geodesic to an image at horizontal distance σ and height
    /// difference Δh is (⟨n_h, u⟩ σ + up·Δh)/ℓ for the unit horizontal direction u of the
    /// geodesic, where ⟨n_h, u⟩ = ⟨n_h, y − x⟩/S(σ) for the image's position y: one dot
    /// product. Images behind the surface then weigh next to nothing (the cosine's floor), and
    /// on the floor and the ceiling far images weigh as 1/ℓ³ rather than 1/ℓ².
    fn near_weights(&self, x: DVec3, h: f64, normal: Normal, weights: &mut [f64; NEAR_MAX]) -> f64 {
        orbifold_trace::with_avx512!(
            Integrator,
            self.near_weights_portable(
                x: DVec3,
                h: f64,
                normal: Normal,
                weights: &mut [f64; NEAR_MAX],
            ) -> f64
        )
    }

    #[inline(always)]
    fn near_weights_portable(
        &self,
        x: DVec3,
        h: f64,
        normal: Normal,
        weights: &mut [f64; NEAR_MAX],
    ) -> f64 {
        let space = self.space();
        let floor = spread(space, NEAR_CLAMP, NEAR_CLAMP);
        let at = (x, h, normal, floor);
        let k = space.kappa();
        if k > 0.0 {
            self.near_images.weights::<1>(k, at, weights)
        } else if k < 0.0 {
            self.near_images.weights::<-1>(k, at, weights)
        } else {
            self.near_images.weights::<0>(k, at, weights)
        }
    }

    /// Picks a light-sampling choice with the per-point weights of the near images (and their
    /// sum `total`, from [`Integrator::near_weights`]): with probability `NEAR_SHARE` among
    /// the near images by those weights, else from the scene-wide distribution. Returns the
    /// entry and its probability.
    fn pick_entry_with(
        &self,
        weights: &[f64; NEAR_MAX],
        total: f64,
        u: f64,
    ) -> Option<(usize, f64)> {
        let distribution = self.distribution.as_ref()?;
        let share = if total > 0.0 && total.is_finite() {
            NEAR_SHARE
        } else {
            0.0
        };
        let index = if u < share {
            let mut target = u / share * total;
            let mut chosen = self.near[self.near.len() - 1];
            for (w, &e) in weights.iter().zip(&self.near) {
                if target < *w {
                    chosen = e;
                    break;
                }
                target -= w;
            }
            chosen
        } else {
            distribution.sample((u - share) / (1.0 - share)).0
        };
        Some((index, self.entry_pmf(index, weights, total, share)))
    }

    /// The probability of `pick_entry` choosing `index`, given the per-point weights.
    fn entry_pmf(&self, index: usize, weights: &[f64; NEAR_MAX], total: f64, share: f64) -> f64 {
        let global = self.distribution.as_ref().map_or(0.0, |d| d.pmf(index));
        // `near` lists its entries in increasing order (they are pushed as they are made).
        let near = match self.near.binary_search(&index) {
            Ok(i) if share > 0.0 => weights[i] / total,
            _ => 0.0,
        };
        share * near + (1.0 - share) * global
    }

    /// The probability of `pick_entry` at (x, h) with unit normal `normal` choosing `index`.
    fn pmf_at(&self, x: DVec3, h: f64, normal: Normal, index: usize) -> f64 {
        let mut weights = [0.0; NEAR_MAX];
        let total = self.near_weights(x, h, normal, &mut weights);
        let share = if total > 0.0 && total.is_finite() {
            NEAR_SHARE
        } else {
            0.0
        };
        self.entry_pmf(index, &weights, total, share)
    }

    fn entry_index(&self, light: usize, image: usize, turns: u32) -> Option<usize> {
        // Entries are in (light, image, turns) order with some left out: binary search.
        let key = (light, image, turns);
        self.entries
            .binary_search_by(|e| (e.light, e.image, e.turns).cmp(&key))
            .ok()
    }

    /// Whether light sampling can draw the image of light `light` that a path sees after
    /// meeting the walls of `chain` (not round the sphere: [`BOUNCE_GLIMPSE`] is off there).
    fn samples_image(&self, light: usize, chain: &DMat3) -> bool {
        self.images
            .find_chain(chain)
            .is_some_and(|image| self.entry_index(light, image, 0).is_some())
    }

    /// The nearest room surface, object or area light along a ray, leaving out light `skip`.
    fn nearest(&self, ray: &Ray, skip: Option<usize>) -> Option<Near> {
        let space = self.space();
        let hit = self.tracer.nearest(ray);
        let mut best = hit.map(|h| Near {
            s: h.s,
            struck: Struck::Surface(h.surface, h.triangle),
            point: h.point,
            tangent: h.tangent,
            height: h.height,
        });
        for (l, light) in self.lights.iter().enumerate() {
            if skip == Some(l) {
                continue;
            }
            if let Emitter::Area { instance, .. } = &light.emitter {
                let limit = best.map_or(f64::INFINITY, |b| b.s);
                if let Some(t) = instance.intersect(space, ray, 0.0, limit) {
                    let (point, tangent, height) = ray.point_and_tangent_at(space, t.s);
                    best = Some(Near {
                        s: t.s,
                        struck: Struck::Light(l, t.triangle, t.barycentric),
                        point,
                        tangent,
                        height,
                    });
                }
            }
        }
        best
    }

    /// For a visibility march: the room surface where `ray` leaves the room before arc length
    /// `limit` (`None` if it does not), or `Err(Blocked)` if an object or an area light other
    /// than `skip` is in the way first. An any-hit search: it stops at the first triangle
    /// found, where [`Integrator::nearest`] must go on looking for a nearer one.
    fn unblocked_exit(
        &self,
        ray: &Ray,
        skip: Option<usize>,
        limit: f64,
    ) -> Result<Option<Near>, Blocked> {
        let space = self.space();
        let exit = self.tracer.room.exit(ray).filter(|e| e.s < limit);
        let reach = exit.as_ref().map_or(limit, |e| e.s);
        if self.tracer.objects.occluded(space, ray, 0.0, reach) {
            return Err(Blocked);
        }
        for (l, light) in self.lights.iter().enumerate() {
            if let Emitter::Area { instance, .. } = &light.emitter
                && skip != Some(l)
                && instance.occluded(space, ray, 0.0, reach)
            {
                return Err(Blocked);
            }
        }
        Ok(exit.map(|e| Near {
            s: e.s,
            struck: Struck::Surface(e.surface.into(), None),
            point: e.point,
            tangent: e.tangent,
            height: e.height,
        }))
    }

    /// Follows a ray through mirrors for at most `length`, not meeting light `skip`.
    ///
    /// With `roulette` (a sampler, the luminance of the path's throughput so far, and a level:
    /// `ROULETTE_LEVEL` or `FOOTPRINT_ROULETTE_LEVEL`), a path
    /// whose throughput falls below the level after a mirror goes on with probability
    /// ∝ its throughput and is weighted up when it does (Russian roulette: unbiased, and long
    /// chains of dim reflections stop early).
    ///
    /// With a `footprint` (a camera ray's pixel), sphere lights whose images are smaller than the
    /// footprint are counted by the share of it that they cover ([`orbifold_trace::footprint`]).
    ///
    /// With `visibility_only` (a connection to a light), the march only needs to know whether
    /// it gets through: it ends `Blocked` at the first thing in the way that is not a mirror.
    fn march(
        &self,
        ray: &Ray,
        length: f64,
        skip: Option<usize>,
        mut roulette: Option<(&mut Sampler, f64, f64)>,
        glimpses: Option<Glimpses<'_>>,
        visibility_only: bool,
    ) -> March {
        let space = self.space();
        // The footprint as it is carried: mirrors swap left and right.
        let mut carried = glimpses.map(|g| *g.footprint());
        let unsampled_only = matches!(glimpses, Some(Glimpses::Bounce(_)));
        let mut march = March {
            end: MarchEnd::Lost,
            throughput: [1.0; 3],
            chain: DMat3::IDENTITY,
            length: 0.0,
            ray: *ray,
            rest: 0.0,
            glimpsed: [0.0; 3],
            glimpsed_end: None,
        };
        for _ in 0..=MAX_MIRROR_BOUNCES {
            RAYS.with(|r| r.set(r.get().wrapping_add(1)));
            let remaining = length - march.length;
            let near = if visibility_only {
                match self.unblocked_exit(&march.ray, skip, remaining) {
                    Ok(near) => near,
                    Err(Blocked) => {
                        march.end = MarchEnd::Blocked;
                        return march;
                    }
                }
            } else {
                self.nearest(&march.ray, skip).filter(|n| n.s < remaining)
            };
            if let Some(footprint) = &carried {
                self.glimpse(
                    &mut march,
                    footprint,
                    near.as_ref(),
                    remaining,
                    unsampled_only,
                );
            }
            let Some(near) = near else {
                if remaining.is_finite() {
                    march.end = MarchEnd::Reached;
                    march.rest = remaining;
                    march.length = length;
                }
                return march;
            };
            let mirror = match near.struck {
                Struck::Surface(SurfaceId::Wall(w), _) => self
                    .tracer
                    .room
                    .mirror_at(w, near.point, near.height)
                    .map(|(_, m)| (w, m.reflectance)),
                _ => None,
            };
            let Some((wall, reflectance)) = mirror else {
                march.end = MarchEnd::Hit(near);
                march.rest = near.s;
                march.length += near.s;
                return march;
            };
            march.throughput = mul(march.throughput, reflectance);
            if let Some((sampler, beta, level)) = roulette.as_mut() {
                let carried = *beta * luminance(march.throughput);
                if carried < *level {
                    let survive = carried / *level;
                    if survive.is_nan()
                        || survive <= 0.0
                        || sampler.next_independent_f64() >= survive
                    {
                        return march;
                    }
                    march.throughput = scale(march.throughput, 1.0 / survive);
                }
            }
            let form = self.tracer.room.wall_form_at(wall, near.point);
            carried = carried.map(|f| f.reflected());
            march.chain *= reflection_matrix(space, form);
            march.length += near.s;
            march.ray = (march.ray)
                .continued(space, near.s, near.point, near.tangent)
                .reflected(space, form);
        }
        march
    }

    /// Adds to `march.glimpsed` the sphere lights whose images near the stretch of `march.ray`
    /// up to `near` (or to `remaining`) are at most a few footprints wide; with
    /// `unsampled_only`, only the images that light sampling cannot draw (the others are
    /// weighed against it by MIS when a ray hits them).
    fn glimpse(
        &self,
        march: &mut March,
        footprint: &Footprint,
        near: Option<&Near>,
        remaining: f64,
        unsampled_only: bool,
    ) {
        let space = self.space();
        let end = near.map_or(remaining, |n| n.s);
        for &(l, ref sphere, radiance) in &self.spheres {
            let struck =
                matches!(near, Some(Near { struck: Struck::Light(hit, ..), .. }) if *hit == l);
            let slack = if struck { 2.0 * sphere.radius() } else { 0.0 };
            let glimpse = sphere_coverage(
                space,
                &march.ray,
                march.length,
                footprint,
                sphere,
                end,
                slack,
            );
            if let Glimpse::Covered(share) = glimpse {
                if unsampled_only && self.samples_image(l, &march.chain) {
                    continue;
                }
                add(
                    &mut march.glimpsed,
                    scale(mul(march.throughput, radiance), share),
                );
                if struck {
                    march.glimpsed_end = Some(l);
                }
            }
        }
    }

    /// The unit normals (local coordinates in `frame`: the surface's own, then the shading
    /// normal, which differs on smooth-shaded objects) and the BSDF where a march ended; with the
    /// camera ray's `spread` there, textures are averaged over its pixel's footprint.
    fn surface(
        &self,
        near: &Near,
        frame: &TangentFrame,
        spread: Option<&Spread>,
    ) -> Option<(DVec3, DVec3, Bsdf)> {
        let space = self.space();
        let moved = |offset: DVec3| {
            if offset == DVec3::ZERO {
                return (near.point, near.height);
            }
            let (v, up) = frame.to_ambient(offset);
            (space.exp(near.point, v), near.height + up)
        };
        let coords = |intrinsic: bool, offset: DVec3| {
            let (x, h) = moved(offset);
            if intrinsic {
                let v = space.log(self.centre, x);
                [
                    space.point_dot(v, self.centre_frame.e1),
                    space.point_dot(v, self.centre_frame.e2),
                    h,
                ]
            } else {
                let z = space.to_model(x);
                [z.re, z.im, h]
            }
        };
        let lookup = |n: DVec3| Lookup {
            coords: &coords,
            footprint: spread.map(|s| s.axes(n)),
        };
        match near.struck {
            Struck::Surface(SurfaceId::Floor, _) => {
                Some((DVec3::Z, DVec3::Z, self.floor.bsdf(&lookup(DVec3::Z))))
            }
            Struck::Surface(SurfaceId::Ceiling, _) => {
                let n = -DVec3::Z;
                Some((n, n, self.ceiling.bsdf(&lookup(n))))
            }
            Struck::Surface(SurfaceId::Wall(w), _) => {
                let room = &self.tracer.room;
                let nu = room.wall_form_at(w, near.point);
                let n = frame
                    .to_local(space, DVec3::new(nu.x, nu.y, space.kappa() * nu.z), 0.0)
                    .try_normalize()?;
                // Walls are laid out by (length along the wall, height).
                let wall = |_: bool, offset: DVec3| {
                    let (x, h) = moved(offset);
                    [room.along(w, x) * room.walls[w].length, h, 0.0]
                };
                let lookup = Lookup {
                    coords: &wall,
                    footprint: spread.map(|s| s.axes(n)),
                };
                Some((n, n, self.walls[w].bsdf(&lookup)))
            }
            Struck::Surface(SurfaceId::Object(i), triangle) => {
                let (triangle, barycentric) = triangle?;
                let hit = TriangleHit {
                    s: 0.0,
                    triangle,
                    barycentric,
                };
                let instance = &self.tracer.objects.instances()[i];
                let (h, v) = instance.normal(space, &hit)?;
                let n = frame.to_local(space, h, v).try_normalize()?;
                let (h, v) = instance.shading_normal(space, &hit)?;
                let shading = frame.to_local(space, h, v).try_normalize().unwrap_or(n);
                Some((n, shading, self.objects[i].bsdf(&lookup(n))))
            }
            Struck::Light(..) => None,
        }
    }

    /// The unit normal of an area light's triangle at barycentrics `w`, local in `frame`.
    fn light_normal(
        &self,
        light: usize,
        triangle: u32,
        w: [f64; 3],
        frame: &TangentFrame,
    ) -> Option<DVec3> {
        let Emitter::Area { instance, .. } = &self.lights[light].emitter else {
            return None;
        };
        let hit = TriangleHit {
            s: 0.0,
            triangle,
            barycentric: w,
        };
        let (h, v) = instance.normal(self.space(), &hit)?;
        frame.to_local(self.space(), h, v).try_normalize()
    }

    /// Direct light at a surface point through next-event estimation: one light sample, chosen
    /// by resampling among [`LIGHT_CANDIDATES`] candidates (resampled importance sampling,
    /// Talbot et al. 2005).
    ///
    /// Each candidate is drawn as a plain light sample would be (a (light, image, way) choice
    /// from [`Integrator::pick_entry`]'s distribution and a point on that light), and its
    /// contribution is worked out in full except for what it costs most: the march through the
    /// mirrors that finds whether it is blocked. One candidate is then kept with probability ∝
    /// that unblocked contribution's luminance, and only it is marched. The estimate is the kept
    /// candidate's contribution (with the mirrors' actual reflectances and its visibility) times
    /// the candidates' mean luminance over its own: unbiased whatever the candidates' weights,
    /// since each candidate alone is distributed as a plain light sample. Where the per-point
    /// weights misjudge an image (the scene-wide half of the distribution, the cosine at the
    /// light, the point on a sphere light's side) the candidates' mean averages it out, and the
    /// noise left is mostly which candidate is blocked. A sphere light's candidate is weighed
    /// from the light's centre, and its point is drawn only if it is kept
    /// ([`Integrator::sphere_weight`]).
    ///
    /// The multiple-importance weight against BSDF sampling uses the plain light sample's
    /// density on both sides (as [`Integrator::light_pdf`] does), so that the two weights of any
    /// path still add up to one.
    #[allow(clippy::too_many_arguments)]
    fn direct(
        &self,
        sampler: &mut Sampler,
        x: DVec3,
        h: f64,
        frame: &TangentFrame,
        shading: &Frame,
        sides: &Sides,
        bsdf: &Bsdf,
        candidates: u32,
    ) -> Rgb {
        let normal = Normal::new(frame, shading.normal());
        let mut weights = [0.0; NEAR_MAX];
        let total = self.near_weights(x, h, normal, &mut weights);
        let at = LitPoint {
            x,
            h,
            frame,
            shading,
            sides,
            bsdf,
        };
        // The first candidate takes the bounce's stratified dimensions; the others are shifted
        // copies of them (each uniform on its own: that is all resampling needs).
        let u = sampler.next_f64();
        let u_point = sampler.next_f64();
        let v = sampler.next_2d();
        let uniforms = |j: u32| {
            let shifted = |a: f64, b: f64| (a + f64::from(j) * b).fract();
            (
                shifted(u, 1.0 / f64::from(candidates)),
                shifted(u_point, GOLDEN),
                (shifted(v.0, R2.0), shifted(v.1, R2.1)),
            )
        };
        let mut aimed = ArrayVec::new();
        if candidates <= 1 {
            return self
                .light_candidate(&at, (&weights, total), &mut aimed, uniforms(0))
                .map_or([0.0; 3], |c| self.light_contribution(&at, &c));
        }
        // Only the candidates that can light the point, in order (no slots to initialise).
        let mut drawn = ArrayVec::<Candidate, LIGHT_CANDIDATES>::new();
        let mut sum = 0.0;
        for j in 0..candidates {
            let (u, u_point, v) = uniforms(j);
            let candidate = self
                .pick_entry_with(&weights, total, u)
                .and_then(|(index, pmf)| {
                    if let Some(weight) = self.sphere_weight(&at, index, pmf) {
                        return Some(Candidate::Deferred {
                            index,
                            pmf,
                            point_uniforms: (u_point, v),
                            weight,
                        });
                    }
                    let mut c = self.candidate_at(&at, index, pmf, &mut aimed, (u_point, v))?;
                    c.weight = self.candidate_weight(&at, &c)?;
                    Some(Candidate::Drawn(c))
                });
            if let Some(candidate) = candidate {
                sum += candidate.weight();
                drawn.push(candidate);
            }
        }
        if !(sum > 0.0 && sum.is_finite()) {
            return [0.0; 3];
        }
        let mut target = sampler.next_independent_f64() * sum;
        let mut chosen = None;
        for candidate in &drawn {
            chosen = Some(candidate);
            if target < candidate.weight() {
                break;
            }
            target -= candidate.weight();
        }
        let Some(chosen) = chosen else {
            return [0.0; 3];
        };
        let value = match *chosen {
            Candidate::Drawn(ref c) => self.light_contribution(&at, c),
            // Its point is drawn only now: it did not enter the weight.
            Candidate::Deferred {
                index,
                pmf,
                point_uniforms,
                ..
            } => self
                .candidate_at(&at, index, pmf, &mut aimed, point_uniforms)
                .map_or([0.0; 3], |c| self.light_contribution(&at, &c)),
        };
        scale(value, sum / (f64::from(candidates) * chosen.weight()))
    }

    /// The resampling weight of a sphere light's candidate worked out from the light's centre
    /// alone, before any point on it is drawn: the luminance of the contribution of a small
    /// sphere of the light's radiance and radius seen from the centre's direction, with the
    /// image's bound on the mirrors' reflectance, over the light sample's density for it (the
    /// entry's probability over the solid angle πr²/J the sphere fills). `None` for other
    /// lights, and where the centre cannot light the point (part of the sphere still may: such
    /// a candidate is drawn and weighed in full instead, so that every point that can be lit
    /// keeps a positive weight).
    ///
    /// Resampling stays unbiased with this weight: the candidate's target density is this
    /// weight times the entry's probability times the density of the point drawn on the light,
    /// so the point does not change the weight and need only be drawn once the candidate is
    /// kept. That saves the candidates that are not kept the light's per-point work (weighing
    /// the sphere's hundreds of triangles for the point, drawing one and its normal).
    fn sphere_weight(&self, at: &LitPoint, index: usize, pmf: f64) -> Option<f64> {
        let space = self.space();
        let entry = self.entries[index];
        let light = &self.lights[entry.light];
        let (radius, radiance) = light.sphere()?;
        let image = &self.images.images[entry.image];
        let (wi, j) = aim_at(
            space,
            at.frame,
            (at.x, at.h),
            (entry.position, entry.height),
            entry.turns,
        )?;
        if !at.sides.agree(at.shading.normal(), wi) {
            return None;
        }
        let wo = at.shading.to_local(at.sides.wo);
        let wi_local = at.shading.to_local(wi);
        let f = at.bsdf.eval(wo, wi_local);
        let cos_x = wi.dot(at.shading.normal()).abs();
        let pdf_light = pmf * j / (std::f64::consts::PI * radius * radius);
        let weight = power_heuristic(1.0, pdf_light, 1.0, at.bsdf.pdf(wo, wi_local));
        let unblocked = scale(mul(f, image.reflectance), entry.attenuation);
        let value = luminance(mul(unblocked, radiance)) * cos_x * weight / pdf_light;
        (value > 0.0 && value.is_finite()).then_some(value)
    }

    /// One candidate of a light sample at `at` with `uniforms` (the choice of (light, image,
    /// way), of the light's triangle, and the point in it): its unblocked contribution, with the
    /// image's bound on the mirrors' reflectance. `None` when it cannot light the point.
    fn light_candidate<'a>(
        &'a self,
        at: &LitPoint,
        (weights, total): (&[f64; NEAR_MAX], f64),
        aimed: &mut ArrayVec<(usize, AimedLight<'a>), LIGHT_CANDIDATES>,
        (u, u_point, v): (f64, f64, (f64, f64)),
    ) -> Option<LightCandidate> {
        let (index, pmf) = self.pick_entry_with(weights, total, u)?;
        self.candidate_at(at, index, pmf, aimed, (u_point, v))
    }

    /// The candidate of entry `index` (picked with probability `pmf`) with the point on the
    /// light that uniforms `u_point`, `v` draw, as [`Integrator::light_candidate`] gives it.
    fn candidate_at<'a>(
        &'a self,
        at: &LitPoint,
        index: usize,
        pmf: f64,
        aimed: &mut ArrayVec<(usize, AimedLight<'a>), LIGHT_CANDIDATES>,
        (u_point, v): (f64, (f64, f64)),
    ) -> Option<LightCandidate> {
        let space = self.space();
        let entry = self.entries[index];
        let light = &self.lights[entry.light];
        let image = &self.images.images[entry.image];
        // The point to light, seen from the light's own copy of the room (the long way round
        // arrives from the other side: every triangle is a candidate then).
        // Candidates that chose the same entry share what the light works out for the point.
        let aimed = match aimed.iter().find(|(i, _)| *i == index) {
            Some((_, aimed)) => aimed,
            None => {
                let from = (entry.turns == 0).then(|| (image.inverse * at.x, at.h));
                light.push_aimed(space, from, index, aimed)
            }
        };
        let point = aimed.sample(space, u_point, v)?;
        let target = image.isometry * point.x;
        let link = connect(
            space,
            at.frame,
            (at.x, at.h),
            (target, point.h),
            entry.turns,
        )?;
        let wi = travel_direction(space, at.frame, &link.ray, 0.0);
        if !at.sides.agree(at.shading.normal(), wi) {
            return None;
        }
        let f = at
            .bsdf
            .eval(at.shading.to_local(at.sides.wo), at.shading.to_local(wi));
        let cos_x = wi.dot(at.shading.normal()).abs();
        if luminance(f) <= 0.0 || cos_x == 0.0 {
            return None;
        }
        Some(LightCandidate {
            index,
            pmf,
            point,
            link,
            wi,
            f,
            cos_x,
            weight: 1.0,
        })
    }

    /// The resampling weight of a candidate: the luminance of its contribution if nothing
    /// blocks it, with the image's bound on the mirrors' reflectance (`None` if zero).
    fn candidate_weight(&self, at: &LitPoint, candidate: &LightCandidate) -> Option<f64> {
        let space = self.space();
        let entry = self.entries[candidate.index];
        let light = &self.lights[entry.light];
        let image = &self.images.images[entry.image];
        let (point, link) = (&candidate.point, &candidate.link);
        // The direction of arrival at the light, carried back from the image to the light's
        // own copy (the isometry is linear on ambient vectors, so it maps tangents too).
        let u_end = image.inverse * link.ray.tangent_at(space, link.sigma);
        let (cos_a, sin_a) = (link.ray.cos_elevation, link.ray.sin_elevation);
        let unblocked = scale(mul(candidate.f, image.reflectance), entry.attenuation);
        let value = match (point.triangle, &light.emitter) {
            (Some((triangle, w)), Emitter::Area { instance, .. }) => {
                // The cosine at the light, in ambient terms (no frame needed there).
                let hit = TriangleHit {
                    s: 0.0,
                    triangle,
                    barycentric: w,
                };
                let (n_across, n_up) = instance.normal(space, &hit)?;
                let norm = (space.point_dot(n_across, n_across) + n_up * n_up).sqrt();
                let cos_out = -(space.point_dot(u_end, n_across) * cos_a + n_up * sin_a) / norm;
                let emitted = light.emission(DVec3::ZERO, cos_out);
                if cos_out == 0.0 || cos_out.is_nan() || luminance(emitted) <= 0.0 {
                    return None;
                }
                let pdf_light = candidate.pmf * point.pdf_area * link.spread / cos_out.abs();
                let wo = at.shading.to_local(at.sides.wo);
                let pdf_bsdf = at.bsdf.pdf(wo, at.shading.to_local(candidate.wi));
                let weight = power_heuristic(1.0, pdf_light, 1.0, pdf_bsdf);
                scale(
                    mul(unblocked, emitted),
                    candidate.cos_x * weight / pdf_light,
                )
            }
            _ => {
                let arrival = light.frame.to_local(space, u_end * cos_a, sin_a);
                let emitted = light.emission(-arrival, 1.0);
                scale(
                    mul(unblocked, emitted),
                    candidate.cos_x / (link.spread * candidate.pmf),
                )
            }
        };
        let weight = luminance(value);
        (weight > 0.0 && weight.is_finite()).then_some(weight)
    }

    /// The contribution of a light candidate once its connection is marched through the real
    /// room: zero when something other than a mirror is in the way, else with the mirrors'
    /// actual reflectances.
    fn light_contribution(&self, at: &LitPoint, candidate: &LightCandidate) -> Rgb {
        let space = self.space();
        let entry = self.entries[candidate.index];
        let light = &self.lights[entry.light];
        let image = &self.images.images[entry.image];
        let (point, link) = (&candidate.point, &candidate.link);
        let from = (entry.turns == 0).then(|| (image.inverse * at.x, at.h));
        let start = link.ray.advanced(space, RAY_EPSILON);
        // A point on the side of a sphere light that faces x is reached without meeting the
        // light first: its own mesh (hundreds of triangles) need not be tested.
        let skip = point
            .triangle
            .is_some_and(|(t, _)| light.reaches_unobstructed(space, t, from))
            .then_some(entry.light);
        let march = self.march(
            &start,
            link.length - 2.0 * RAY_EPSILON,
            skip,
            None,
            None,
            true,
        );
        if march.end != MarchEnd::Reached {
            return [0.0; 3];
        }
        // It must arrive at the light itself (the chain of walls it met is the image's).
        let (end, end_h) = march.ray.point_at(space, march.rest + RAY_EPSILON);
        let tolerance = 1e-6 * (1.0 + link.length);
        if space.ambient_distance(end, point.x) > tolerance || (end_h - point.h).abs() > tolerance {
            return [0.0; 3];
        }
        let light_frame = TangentFrame::at(space, point.x);
        let arrival = travel_direction(space, &light_frame, &march.ray, march.rest + RAY_EPSILON);
        let unoccluded = mul(candidate.f, march.throughput);
        let (cos_x, pmf) = (candidate.cos_x, candidate.pmf);
        match point.triangle {
            None => {
                // A point light: its own frame is the one at its position.
                let out =
                    -travel_direction(space, &light.frame, &march.ray, march.rest + RAY_EPSILON);
                let emitted = light.emission(out, 1.0);
                scale(mul(unoccluded, emitted), cos_x / (link.spread * pmf))
            }
            Some((triangle, w)) => {
                let Some(n) = self.light_normal(entry.light, triangle, w, &light_frame) else {
                    return [0.0; 3];
                };
                let cos_out = -arrival.dot(n);
                let emitted = light.emission(-arrival, cos_out);
                if cos_out == 0.0 || luminance(emitted) <= 0.0 {
                    return [0.0; 3];
                }
                let pdf_light = pmf * point.pdf_area * link.spread / cos_out.abs();
                let wo = at.shading.to_local(at.sides.wo);
                let pdf_bsdf = at.bsdf.pdf(wo, at.shading.to_local(candidate.wi));
                let weight = power_heuristic(1.0, pdf_light, 1.0, pdf_bsdf);
                scale(mul(unoccluded, emitted), cos_x * weight / pdf_light)
            }
        }
    }

    /// The probability density (solid angle at the previous vertex) with which light sampling
    /// would have produced a path that hit area light `light` at (`triangle`, `w`) after meeting
    /// the walls of `march.chain`.
    fn light_pdf(
        &self,
        (x, h, normal): (DVec3, f64, Normal),
        light: usize,
        triangle: u32,
        w: [f64; 3],
        march: &March,
        cos_out: f64,
    ) -> f64 {
        let space = self.space();
        let Some(image) = self.images.find_chain(&march.chain) else {
            return 0.0;
        };
        let sigma = march.length * march.ray.cos_elevation.abs();
        // The half-turns round the sphere that the path made ([`turned`]).
        let turns = if space.kappa() > 0.0 {
            (sigma / std::f64::consts::PI)
                .floor()
                .min(f64::from(u32::MAX)) as u32
        } else {
            0
        };
        let Some(index) = self.entry_index(light, image, turns) else {
            return 0.0;
        };
        let from = (turns == 0).then(|| (self.images.images[image].inverse * x, h));
        let pdf_area = self.lights[light].pdf_area(space, triangle, w, from);
        let j = spread(space, march.length, sigma);
        self.pmf_at(x, h, normal, index) * pdf_area * j / cos_out.abs().max(1e-12)
    }

    /// The radiance arriving along a camera ray (one path sample).
    pub fn radiance(&self, ray: &Ray, sampler: &mut Sampler) -> Rgb {
        self.sample(ray, sampler).radiance
    }

    /// The radiance arriving along a camera ray (one path sample) and the first surface that is
    /// not a mirror.
    pub fn sample(&self, ray: &Ray, sampler: &mut Sampler) -> PathSample {
        self.sample_pixel(ray, None, sampler)
    }

    /// [`Integrator::sample`] for a camera ray that carries its pixel's footprint: sphere lights
    /// whose mirror images are smaller than the pixel are counted by the share of the pixel
    /// they cover, not by the ray's hit or miss ([`orbifold_trace::footprint`]; what renders use).
    pub fn sample_pixel(
        &self,
        ray: &Ray,
        footprint: Option<Footprint>,
        sampler: &mut Sampler,
    ) -> PathSample {
        self.sample_pixel_cached(ray, footprint, None, sampler)
    }

    /// [`Integrator::sample_pixel`] with a radiance cache ([`crate::radiance_cache`]): where the
    /// path's first diffuse surface is a far mirror image (its pixel's footprint is wider than
    /// a cell of the cache) and the cache holds enough estimates there, the reflected light is
    /// read from the cache instead of traced; so is the light reflected by a diffuse surface
    /// that the path reaches from a diffuse bounce, over a width of
    /// [`radiance_cache::DIFFUSE_SPREAD`] times the distance, where the path may still take
    /// [`radiance_cache::DEPTH_LEFT_FOR_READS`] scatterings. A path that traces its first diffuse
    /// surface in full returns its estimate there as a [`Deposit`] for the cache: those that
    /// could not read it, and a [`radiance_cache::PROBE`] share of those that could, which take
    /// the cache's value all the same.
    pub fn sample_pixel_cached(
        &self,
        ray: &Ray,
        footprint: Option<Footprint>,
        cache: Option<&RadianceCache>,
        sampler: &mut Sampler,
    ) -> PathSample {
        let rays_before = rays_so_far();
        let space = self.space();
        let footprint =
            footprint.filter(|_| self.settings.pixel_footprint && !self.settings.straight_rays);
        let mut first: Option<FirstHit> = None;
        let mut radiance = [0.0; 3];
        let mut beta = [1.0; 3];
        let mut ray = *ray;
        // The previous scattering: specular (or the camera), and its BSDF pdf.
        let mut specular = true;
        let mut pdf_bsdf = 0.0;
        let mut previous = (DVec3::ZERO, 0.0, Normal::default());
        let mut depth = 0;
        // The camera path's first diffuse surface, while its estimate for the cache is traced.
        let mut pending: Option<Pending> = None;
        let mut previous_diffuse = false;
        // Whether the ray leaves a diffuse bounce, whose small far light images that light
        // sampling cannot draw are counted by their coverage of [`BOUNCE_GLIMPSE`].
        let mut bounce_glimpses = false;
        // The light seen before the first surface (`FirstHit::emitted`), and the first surface's
        // light sample (`FirstHit::direct`).
        let mut seen = [0.0; 3];
        let mut direct_first = [0.0; 3];
        loop {
            // The pixel's footprint is carried from the camera through mirrors only.
            let carried = footprint.as_ref().filter(|_| first.is_none());
            let level = if carried.is_some() {
                FOOTPRINT_ROULETTE_LEVEL
            } else {
                ROULETTE_LEVEL
            };
            let roulette = Some((&mut *sampler, luminance(beta), level));
            let glimpses = match carried {
                Some(footprint) => Some(Glimpses::Camera(footprint)),
                None => bounce_glimpses.then_some(Glimpses::Bounce(&BOUNCE_GLIMPSE)),
            };
            let march = self.march(&ray, f64::INFINITY, None, roulette, glimpses, false);
            let before_surfaces = first.is_none();
            add(&mut radiance, mul(beta, march.glimpsed));
            if before_surfaces {
                add(&mut seen, mul(beta, march.glimpsed));
            }
            beta = mul(beta, march.throughput);
            let MarchEnd::Hit(near) = march.end else {
                break;
            };
            let (x, h) = (near.point, near.height);
            let frame = TangentFrame::at(space, x);
            let travel = travel_direction(space, &frame, &march.ray, march.rest);
            if first.is_none() {
                first = Some(FirstHit {
                    albedo: [1.0; 3],
                    normal: -travel,
                    depth: march.length,
                    ..FirstHit::default()
                });
            }
            if let Struck::Light(l, triangle, w) = near.struck {
                if march.glimpsed_end == Some(l) {
                    break;
                }
                let Some(n) = self.light_normal(l, triangle, w, &frame) else {
                    break;
                };
                let cos_out = -travel.dot(n);
                let emitted = self.lights[l].emission(-travel, cos_out);
                let weight = if specular || !self.settings.nee {
                    1.0
                } else {
                    let pdf_light = self.light_pdf(previous, l, triangle, w, &march, cos_out);
                    power_heuristic(1.0, pdf_bsdf, 1.0, pdf_light)
                };
                add(&mut radiance, scale(mul(beta, emitted), weight));
                if before_surfaces {
                    add(&mut seen, scale(mul(beta, emitted), weight));
                }
                break;
            }
            // An odd number of mirrors has swapped left and right (as the march's own copy).
            let spread = carried.map(|f| {
                let f = if march.chain.determinant() < 0.0 {
                    f.reflected()
                } else {
                    *f
                };
                Spread::new(space, &f, march.length, march.ray.cos_elevation, travel)
            });
            let Some((geometric, normal, bsdf)) = self.surface(&near, &frame, spread.as_ref())
            else {
                break;
            };
            if !bsdf.is_transmissive() {
                add(&mut radiance, mul(beta, self.settings.glow));
            }
            // Opaque surfaces are two-sided: face the normals towards where the path came from.
            // A dielectric keeps its outward normal: which side the path is on matters.
            let wo = -travel;
            let (geometric, normal) = if geometric.dot(wo) < 0.0 && !bsdf.is_transmissive() {
                (-geometric, -normal)
            } else {
                (geometric, normal)
            };
            let normal = bent_shading_normal(normal, geometric, wo);
            let shading = Frame::from_normal(normal);
            if depth == 0 {
                first = Some(FirstHit {
                    albedo: bsdf.albedo(),
                    normal,
                    depth: march.length,
                    ..FirstHit::default()
                });
            }
            // Light from the radiance cache: all the light that a far image, or a surface reached
            // by a diffuse bounce, reflects. (A probed share of the camera's first surfaces is
            // traced on in full all the same, only to keep their cells growing.)
            if let (Some(cache), Bsdf::Diffuse { albedo }) = (cache, bsdf)
                && depth < self.settings.max_depth
            {
                // How wide the light arriving here is spread: the pixel's footprint for the
                // camera's first surface, a share of the distance after a diffuse bounce.
                let depth_left = self.settings.max_depth - depth;
                let width = match &spread {
                    Some(s) if depth == 0 => s.cache_width,
                    _ if previous_diffuse && depth_left >= radiance_cache::DEPTH_LEFT_FOR_READS => {
                        radiance_cache::DIFFUSE_SPREAD * march.length
                    }
                    _ => 0.0,
                };
                let (facing, cached) = self.cached(cache, x, h, &frame, geometric, width, sampler);
                let weight = mul(beta, albedo);
                // Only the camera's first surface deposits estimates, so only there do probes
                // feed the cache.
                let depositable = depth == 0 && albedo.iter().all(|&a| a > 1e-3);
                let probe = cached.is_some()
                    && depositable
                    && sampler.next_independent_f64() < radiance_cache::PROBE;
                match cached {
                    Some(cached) if !probe => {
                        add(&mut radiance, mul(weight, cached));
                        break;
                    }
                    _ if depositable => {
                        pending = Some(Pending {
                            point: x,
                            height: h,
                            facing,
                            before: radiance,
                            weight,
                            read: cached.map(|c| mul(weight, c)),
                        });
                    }
                    _ => {}
                }
            }
            // As in pbrt: a path has at most max_depth scattering vertices, whether its last
            // segment to the light comes from light sampling or from a hit.
            if depth == self.settings.max_depth {
                break;
            }
            // Every bounce draws its decisions from its own dimensions of a stratified sampler.
            sampler.start_bounce(depth);
            depth += 1;
            if self.settings.nee && !bsdf.is_delta() {
                let sides = Sides { geometric, wo };
                // Resampled at every bounce: with one candidate past the first bounce `*444`
                // (448², 8 spp) made as many paths a second and was noisier (denoised RMS 1.84
                // against 1.79).
                let candidates = self.light_candidates();
                let direct =
                    self.direct(sampler, x, h, &frame, &shading, &sides, &bsdf, candidates);
                add(&mut radiance, mul(beta, direct));
                if depth == 1 {
                    direct_first = mul(beta, direct);
                }
            }
            let Some(sample) =
                bsdf.sample(shading.to_local(wo), sampler.next_2d(), sampler.next_f64())
            else {
                break;
            };
            let wi = shading.to_world(sample.wi);
            if !(Sides { geometric, wo }).agree(normal, wi) {
                break;
            }
            beta = mul(beta, sample.weight);
            specular = sample.delta;
            previous_diffuse = matches!(bsdf, Bsdf::Diffuse { .. });
            bounce_glimpses = footprint.is_some()
                && self.settings.bounce_footprint
                && self.settings.nee
                && previous_diffuse
                && space.kappa() <= 0.0;
            pdf_bsdf = sample.pdf;
            previous = (x, h, Normal::new(&frame, normal));
            if depth >= 3 {
                let survive = luminance(beta).clamp(0.05, 1.0);
                if sampler.next_f64() >= survive {
                    break;
                }
                beta = scale(beta, 1.0 / survive);
            }
            if !beta.iter().all(|b| b.is_finite()) || luminance(beta) <= 0.0 {
                break;
            }
            ray = frame.ray(space, x, h, wi).advanced(space, RAY_EPSILON);
        }
        let deposit = pending.as_ref().map(|p| p.deposit(radiance));
        if let Some(Pending {
            before,
            read: Some(read),
            ..
        }) = pending
        {
            // A probe takes the cache's value: its own light sample is not in its radiance.
            radiance = before;
            add(&mut radiance, read);
            direct_first = [0.0; 3];
        }
        let finite = radiance
            .iter()
            .chain(&seen)
            .chain(&direct_first)
            .all(|v| v.is_finite());
        let mut first = first.unwrap_or(FirstHit {
            albedo: [1.0; 3],
            ..FirstHit::default()
        });
        (first.emitted, first.direct) = if finite {
            (seen, direct_first)
        } else {
            ([0.0; 3], [0.0; 3])
        };
        PathSample {
            deposit,
            rays: rays_so_far().wrapping_sub(rays_before),
            radiance: if finite { radiance } else { [0.0; 3] },
            first,
        }
    }

    /// The candidates drawn for each light sample: [`Settings::light_candidates`], or by
    /// default [`FEW_CANDIDATES`] where light sampling has at most [`FEW_ENTRIES`] choices of
    /// (light, image, way), else [`DEFAULT_LIGHT_CANDIDATES`].
    ///
    /// ```
    /// use orbifold_render::integrator::{Integrator, Settings};
    /// use orbifold_scene::Scene;
    ///
    /// let mut scene = Scene::default();
    /// scene.orbifold.signature = "*222".into();
    /// let sphere = Integrator::from_scene(&scene, None, Settings::default()).unwrap();
    /// scene.orbifold.signature = "*2222".into();
    /// let flat = Integrator::from_scene(&scene, None, Settings::default()).unwrap();
    /// assert_eq!((sphere.light_candidates(), flat.light_candidates()), (2, 3));
    /// ```
    pub fn light_candidates(&self) -> u32 {
        let default = if self.entries.len() <= FEW_ENTRIES {
            FEW_CANDIDATES
        } else {
            DEFAULT_LIGHT_CANDIDATES
        };
        self.settings
            .light_candidates
            .unwrap_or(default)
            .clamp(1, MAX_LIGHT_CANDIDATES)
    }

    /// Whether renders read far and indirect light from a radiance cache: when the settings ask
    /// for it, with light sampling and the pixel footprint (brute-force path tracing, the
    /// reference, and straight rays trace every path in full).
    pub fn uses_radiance_cache(&self) -> bool {
        let s = &self.settings;
        s.radiance_cache && s.nee && s.pixel_footprint && !s.straight_rays
    }

    /// Which way a surface at (x, h) with normal `geometric` (local to `frame`) faces, and the
    /// cache's estimate of the light it reflects per unit albedo, spread over `width`
    /// ([`RadianceCache::lookup`], jittered along the surface).
    #[allow(clippy::too_many_arguments)]
    fn cached(
        &self,
        cache: &RadianceCache,
        x: DVec3,
        h: f64,
        frame: &TangentFrame,
        geometric: DVec3,
        width: f64,
        sampler: &mut Sampler,
    ) -> (u8, Option<Rgb>) {
        let ambient = |t: DVec3| (frame.e1 * t.x + frame.e2 * t.y, t.z);
        let normal = ambient(geometric);
        let facing = facing(normal.0, normal.1);
        if width < radiance_cache::FINEST_CELL {
            return (facing, None);
        }
        let along = Frame::from_normal(geometric);
        let tangents = [ambient(along.tangent()), ambient(along.bitangent())];
        let jitter = [
            sampler.next_independent_f64(),
            sampler.next_independent_f64(),
        ];
        (facing, cache.lookup(x, h, facing, width, tangents, jitter))
    }

    /// The model point of the room's centre (for cameras and tests).
    pub fn centre(&self) -> Complex64 {
        self.tracer.layout.centre
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    fn unit_vector() -> impl Strategy<Value = DVec3> {
        (-1.0f64..1.0, -1.0f64..1.0, -1.0f64..1.0)
            .prop_filter("not too short", |v| {
                DVec3::new(v.0, v.1, v.2).length() > 0.1
            })
            .prop_map(|v| DVec3::new(v.0, v.1, v.2).normalize())
    }

    proptest! {
        /// A bent shading normal is unit, on the surface's side of the geometric one, keeps the
        /// outgoing direction above its horizon, and is the shading normal itself whenever that
        /// already does.
        #[test]
        fn a_bent_shading_normal_keeps_the_eye_above_it(
            geometric in unit_vector(),
            tilt in unit_vector(),
            wo in unit_vector(),
            amount in 0.0f64..1.5,
            outward in any::<bool>(),
        ) {
            let geometric = if outward { geometric } else { -geometric };
            let shading = (geometric + tilt * amount).normalize();
            prop_assume!(shading.dot(geometric) > 0.0);
            let bent = bent_shading_normal(shading, geometric, wo);
            prop_assert!((bent.length() - 1.0).abs() < 1e-12);
            prop_assert!(bent.dot(geometric) > 0.0);
            let side = wo.dot(geometric).signum();
            if (wo.dot(geometric) * side) > SHADING_HORIZON {
                prop_assert!(wo.dot(bent) * side >= SHADING_HORIZON - 1e-12);
            } else {
                prop_assert_eq!(bent, geometric);
            }
            if wo.dot(shading) * side >= SHADING_HORIZON && wo.dot(geometric) * side > SHADING_HORIZON {
                prop_assert_eq!(bent, shading);
            }
        }

        /// With the geometric normal as shading normal every direction agrees; with a tilted one,
        /// a direction agrees exactly when it is on the same side of both (relative to wo).
        #[test]
        fn sides_agree_when_both_normals_say_the_same(
            geometric in unit_vector(),
            tilt in unit_vector(),
            wo in unit_vector(),
            wi in unit_vector(),
        ) {
            let sides = Sides { geometric, wo };
            prop_assert!(sides.agree(geometric, wi));
            let shading = (geometric + tilt * 0.5).normalize();
            let same = |n: DVec3| (wi.dot(n) > 0.0) == (wo.dot(n) > 0.0);
            prop_assert_eq!(sides.agree(shading, wi), same(shading) == same(geometric));
        }

        /// The box-filtered square wave is the mean of the wave over the box (midpoint rule
        /// with 20 000 points), and stays in [−1, 1].
        #[test]
        fn the_filtered_checker_is_the_checker_s_mean(x in -5.0f64..5.0, w in 0.0f64..4.0) {
            let n = 20_000;
            let mean = (0..n)
                .map(|i| {
                    let t = x - 0.5 * w + w * (f64::from(i) + 0.5) / f64::from(n);
                    if t.floor().rem_euclid(2.0) == 0.0 { 1.0 } else { -1.0 }
                })
                .sum::<f64>()
                / f64::from(n);
            let filtered = box_filtered_square_wave(x, w);
            prop_assert!((filtered - mean).abs() < 1e-3 + 2e-4 / w.max(1e-9), "{} vs {}", filtered, mean);
            prop_assert!((-1.0..=1.0).contains(&filtered));
        }
    }

    proptest! {
        /// The per-point weights' cosine is the true one: on a face whose normal is level, at
        /// the light's height, turning the face round divides each image's weight by the cosine
        /// towards it and multiplies it by the cosine away from it (each at least the floor).
        /// The cosine comes from the geodesic's initial direction, `Space::log`, here.
        #[test]
        fn light_weights_face_the_images_in_front(
            g in 0usize..3, a in -0.3f64..0.3, b in -0.3f64..0.3, turn in 0.0f64..std::f64::consts::TAU,
        ) {
            let signature = ["*235", "*2222", "*2223"][g];
            let mut scene = orbifold_scene::Scene::default();
            scene.orbifold.signature = signature.into();
            scene.lights[0].kind = orbifold_scene::LightKind::Sphere;
            let integrator = Integrator::from_scene(&scene, None, Settings::default()).unwrap();
            let space = integrator.space();
            let x = space.exp(
                integrator.centre,
                space.transport(DVec3::Z, integrator.centre, DVec3::new(a, b, 0.0)),
            );
            let frame = TangentFrame::at(space, x);
            let local = DVec3::new(turn.cos(), turn.sin(), 0.0);
            let h = integrator.near_images.height[0];
            let (mut front, mut back) = ([0.0; NEAR_MAX], [0.0; NEAR_MAX]);
            integrator.near_weights_portable(x, h, Normal::new(&frame, local), &mut front);
            integrator.near_weights_portable(x, h, Normal::new(&frame, -local), &mut back);
            let images = &integrator.near_images;
            let (n_h, _) = frame.to_ambient(local);
            for i in 0..images.x.len().min(NEAR_MAX) {
                let y = DVec3::new(images.x[i], images.y[i], images.z[i]);
                let v = space.log(x, y);
                let sigma = space.point_dot(v, v).max(0.0).sqrt();
                prop_assume!(sigma > 1e-6 && (images.height[i] - h).abs() < 1e-12);
                let mut cosine = space.point_dot(n_h, v) / sigma;
                if images.long_way[i] == 1.0 {
                    cosine = -cosine;
                }
                let clamp = |c: f64| c.clamp(COSINE_FLOOR, 1.0);
                let expected = clamp(cosine) / clamp(-cosine);
                let ratio = front[i] / back[i];
                prop_assert!(
                    (ratio / expected - 1.0).abs() < 1e-6,
                    "{signature}, image {i}: {ratio} against {expected}"
                );
            }
        }
    }

    #[test]
    fn the_avx2_light_image_weights_are_the_portable_ones_bit_for_bit() {
        // What `near_weights` runs on a processor with AVX2 against the portable body, at random
        // points of a spherical, a Euclidean and a hyperbolic room of mirrors.
        for signature in ["*235", "*2222", "*2223"] {
            let mut scene = orbifold_scene::Scene::default();
            scene.orbifold.signature = signature.into();
            scene.lights[0].kind = orbifold_scene::LightKind::Sphere;
            let integrator = Integrator::from_scene(&scene, None, Settings::default()).unwrap();
            let space = integrator.space();
            let mut seed = 11u64;
            let mut u = move || {
                seed = seed
                    .wrapping_mul(6364136223846793005)
                    .wrapping_add(1442695040888963407);
                (seed >> 11) as f64 / (1u64 << 53) as f64
            };
            for _ in 0..500 {
                let v = DVec3::new(u() - 0.5, u() - 0.5, 0.0) * 0.4;
                let x = space.exp(
                    integrator.centre,
                    space.transport(DVec3::Z, integrator.centre, v),
                );
                let h = u();
                let local = DVec3::new(u() - 0.5, u() - 0.5, u() - 0.5).normalize();
                let normal = Normal::new(&TangentFrame::at(space, x), local);
                let (mut a, mut b) = ([0.0; NEAR_MAX], [0.0; NEAR_MAX]);
                let total_a = integrator.near_weights(x, h, normal, &mut a);
                let total_b = integrator.near_weights_portable(x, h, normal, &mut b);
                assert_eq!(total_a.to_bits(), total_b.to_bits(), "{signature}");
                assert_eq!(a.map(f64::to_bits), b.map(f64::to_bits), "{signature}");
                assert!(total_a > 0.0, "{signature}");
            }
        }
    }

    #[test]
    fn cache_reads_widen_only_with_the_curvature_across_the_ray() {
        // In E² a footprint's widths grow alike: the cache width is the narrower one, whatever
        // the pixel's shape. In H² the width across outgrows the height by S(σ)/(s cos α); the
        // cache width is then the geometric mean of the widths for a square pixel. In S² the
        // footprint narrows across: the narrower width again.
        let travel = DVec3::X;
        let square = Footprint {
            across: 1e-3,
            up: 1e-3,
            centre: [0.0; 2],
        };
        let wide = Footprint {
            across: 2e-3,
            up: 1e-3,
            centre: [0.0; 2],
        };
        let e2 = Space::new(orbifold::Geometry::Euclidean);
        for pixel in [square, wide] {
            let spread = Spread::new(e2, &pixel, 5.0, 1.0, travel);
            assert!((spread.cache_width - spread.widths.0.min(spread.widths.1)).abs() < 1e-15);
        }
        let h2 = Space::new(orbifold::Geometry::Hyperbolic);
        for s in [0.5, 3.0, 8.0] {
            let spread = Spread::new(h2, &square, s, 1.0, travel);
            let (across, up) = spread.widths;
            assert!(across > up);
            assert!((spread.cache_width - (across * up).sqrt()).abs() < 1e-12 * across);
        }
        let s2 = Space::new(orbifold::Geometry::Spherical);
        let spread = Spread::new(s2, &square, 2.0, 1.0, travel);
        assert_eq!(spread.cache_width, spread.widths.0.min(spread.widths.1));
    }

    #[test]
    fn a_footprint_on_the_floor_stretches_along_a_grazing_ray() {
        // A ray 10° below the horizon along +x meets the floor: the footprint's height becomes
        // height / sin 10° along x, its width stays across (y).
        let travel = DVec3::new(10f64.to_radians().cos(), 0.0, -10f64.to_radians().sin());
        let spread = Spread {
            widths: (0.02, 0.01),
            centre: (0.004, 0.002),
            travel,
            cache_width: 0.01,
        };
        let [centre, a, b] = spread.axes(DVec3::Z);
        // The pixel's centre is seen 0.004 to the left (+y) and 0.002 up: on the floor, that
        // is further along the ray.
        assert!(
            (centre.y - 0.004).abs() < 1e-12 && centre.z.abs() < 1e-12,
            "{centre}"
        );
        assert!(
            (centre.x - 0.002 / 10f64.to_radians().sin()).abs() < 1e-9,
            "{centre}"
        );
        assert!((a.length() - 0.01).abs() < 1e-12 && a.x.abs() < 1e-12 && a.z.abs() < 1e-12);
        let along = 0.005 / 10f64.to_radians().sin();
        assert!(
            (b.length() - along).abs() < 1e-9 && b.z.abs() < 1e-12,
            "{b}"
        );
    }

    #[test]
    fn a_bounce_that_reaches_a_light_round_the_sphere_could_have_been_a_light_sample() {
        // In a spherical room of mirrors, the geodesics from a point of the floor to the
        // sphere light that go round the sphere once and more reach it through the mirrors.
        // Light sampling must draw them too (a positive density at the point where such a
        // bounce meets the light), or MIS counts those bounces unweighted: the noisiest light
        // of the spherical rooms of the seed's Table 8.1.
        for signature in ["*", "*22", "*222"] {
            let mut scene = orbifold_scene::Scene::default();
            scene.orbifold.signature = signature.into();
            scene.objects.clear();
            scene.room.reflectance = [0.9; 3];
            scene.lights[0].kind = orbifold_scene::LightKind::Sphere;
            scene.lights[0].at = [
                scene.layout().unwrap().centre.re,
                scene.layout().unwrap().centre.im,
            ];
            let integrator = Integrator::from_scene(&scene, None, Settings::default()).unwrap();
            let space = integrator.space();
            let light = &integrator.lights[0];
            let offset = integrator.centre_frame.e1 * 0.2 + integrator.centre_frame.e2 * 0.1;
            let x = space.exp(integrator.centre, offset);
            let h = 1e-6;
            let frame = TangentFrame::at(space, x);
            let up = Normal::new(&frame, DVec3::Z);
            let mut reached = 0;
            for turns in 0..8 {
                let link =
                    connect(space, &frame, (x, h), (light.position, light.height), turns).unwrap();
                let start = link.ray.advanced(space, RAY_EPSILON);
                let march = integrator.march(&start, f64::INFINITY, None, None, None, false);
                let MarchEnd::Hit(near) = march.end else {
                    continue;
                };
                let Struck::Light(l, triangle, w) = near.struck else {
                    continue;
                };
                let sigma = march.length * march.ray.cos_elevation;
                assert_eq!(
                    (sigma / std::f64::consts::PI).floor() as u32,
                    turns,
                    "{signature}"
                );
                let light_frame = TangentFrame::at(space, near.point);
                let n = integrator
                    .light_normal(l, triangle, w, &light_frame)
                    .unwrap();
                let travel = travel_direction(space, &light_frame, &march.ray, march.rest);
                let pdf = integrator.light_pdf((x, h, up), l, triangle, w, &march, -travel.dot(n));
                assert!(pdf > 0.0, "{signature}: {turns} half-turns, density {pdf}");
                reached += 1;
            }
            assert!(
                reached >= 6,
                "{signature}: the light reached {reached} ways of 8"
            );
        }
    }

    #[test]
    fn a_time_round_the_sphere_crosses_every_mirror_line_twice() {
        // A great circle meets each great circle of the tiling's mirror lines twice: once round
        // a room of mirrors of reflectance 0.9 with 1, 2 and 3 such lines carries 0.9² , 0.9⁴
        // and 0.9⁶ (whatever the direction, as long as it misses the corners).
        for (signature, lines) in [("*", 1), ("*22", 2), ("*222", 3)] {
            let mut scene = orbifold_scene::Scene::default();
            scene.orbifold.signature = signature.into();
            scene.room.reflectance = [0.9; 3];
            let integrator = Integrator::from_scene(&scene, None, Settings::default()).unwrap();
            let once = integrator.reflectance_once_round(scene.room.height);
            let expected = 0.9f64.powi(2 * lines);
            assert!(
                (once - expected).abs() < 1e-9,
                "{signature}: {once} against {expected}"
            );
        }
        let mut flat = orbifold_scene::Scene::default();
        flat.orbifold.signature = "*2222".into();
        let integrator = Integrator::from_scene(&flat, None, Settings::default()).unwrap();
        assert_eq!(integrator.reflectance_once_round(flat.room.height), 0.0);
    }

    #[test]
    fn a_sphere_light_whose_centre_is_behind_the_surface_still_lights_it_through_resampling() {
        // A sphere light's resampling candidates are weighed from its centre. Where the centre
        // lies a little behind the surface while part of the sphere is in front, the candidate
        // is drawn and weighed in full instead: the resampled estimate must keep that light.
        // Without mirrors the light has one image, so losing it would lose all the light.
        for (signature, tilt) in [("*2222", 0.05f64), ("*2223", 0.1), ("*444", 0.2)] {
            let mut scene = orbifold_scene::Scene::default();
            scene.orbifold.signature = signature.into();
            scene.room.mirrors = orbifold_scene::MirrorDefault::None;
            scene.lights[0].kind = orbifold_scene::LightKind::Sphere;
            scene.lights[0].radius = 0.2;
            let integrator = Integrator::from_scene(&scene, None, Settings::default()).unwrap();
            let space = integrator.space();
            let light = &integrator.lights[0];
            // A point 0.6 from the light's centre at its height, tilted so that the centre is
            // `tilt` radians below its horizon (the sphere's angular radius is about 0.34).
            let away = space.transport(DVec3::Z, light.position, DVec3::new(0.6, 0.0, 0.0));
            let x = space.exp(light.position, away);
            let frame = TangentFrame::at(space, x);
            let link = connect(
                space,
                &frame,
                (x, light.height),
                (light.position, light.height),
                0,
            )
            .unwrap();
            let towards = travel_direction(space, &frame, &link.ray, 0.0);
            let normal = (DVec3::Z * tilt.cos() - towards * tilt.sin()).normalize();
            assert!(normal.dot(towards) < 0.0);
            let shading = Frame::from_normal(normal);
            let sides = Sides {
                geometric: normal,
                wo: normal,
            };
            let bsdf = Bsdf::Diffuse { albedo: [0.8; 3] };
            let estimate = |candidates: u32| {
                let n = 4000;
                let (mut sum, mut squares) = (0.0, 0.0);
                for i in 0..n {
                    let mut sampler = Sampler::new(7, 0, i);
                    sampler.start_bounce(0);
                    let value = luminance(integrator.direct(
                        &mut sampler,
                        x,
                        light.height,
                        &frame,
                        &shading,
                        &sides,
                        &bsdf,
                        candidates,
                    ));
                    sum += value;
                    squares += value * value;
                }
                let mean = sum / n as f64;
                (mean, ((squares / n as f64 - mean * mean) / n as f64).sqrt())
            };
            let (plain, plain_error) = estimate(1);
            let (resampled, resampled_error) = estimate(4);
            assert!(plain > 0.0, "{signature}: the sphere lights the point");
            let tolerance = 4.0 * (plain_error.powi(2) + resampled_error.powi(2)).sqrt();
            assert!(
                (plain - resampled).abs() < tolerance,
                "{signature}: plain {plain} ± {plain_error}, resampled {resampled} ± {resampled_error}"
            );
        }
    }
}
