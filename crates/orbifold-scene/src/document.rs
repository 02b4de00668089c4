//! The scene document: everything that describes one mirror room.

use num_complex::Complex64;
use orbifold::OrbifoldSymbol;
use orbifold::layout::{Layout, LayoutOptions, Shape};
use serde::{Deserialize, Serialize};

/// A linear RGB colour of the scene, each channel in [0, 1].
pub type Color = crate::color::Rgb;

/// A mirror room and what is in it. Every field has a default, so a file needs only what it
/// changes; [`Scene::default`] is the seed's default room `*22222` with a figure and a light.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct Scene {
    /// The orbifold and its polygon.
    pub orbifold: OrbifoldSection,
    /// The room built on the polygon.
    pub room: Room,
    /// Per-wall mirrors and materials (walls not listed use the room's defaults).
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub walls: Vec<Wall>,
    /// Objects placed in the room.
    pub objects: Vec<Object>,
    /// Lights.
    pub lights: Vec<Light>,
    /// The camera.
    pub camera: Camera,
    /// Render settings.
    pub render: Render,
    /// Real-time preview settings.
    pub preview: Preview,
    /// How the room sounds (`orbifold listen`); left out of saved scenes while it is the
    /// default.
    #[serde(skip_serializing_if = "crate::sound::Sound::is_default")]
    pub sound: crate::sound::Sound,
}

impl Scene {
    /// The layout options the scene asks for.
    pub fn layout_options(&self) -> LayoutOptions {
        let o = &self.orbifold;
        let shape = match (o.parameters.is_empty(), o.shape) {
            (false, _) => Shape::Parameters(o.parameters.clone()),
            (true, ShapeName::Incircle) => Shape::Incircle,
            (true, ShapeName::Default) => Shape::Default,
        };
        LayoutOptions {
            shape,
            at: Complex64::new(o.at[0], o.at[1]),
            angle: o.angle.to_radians(),
        }
    }

    /// The room's polygon: for a kaleidoscopic signature its polygon of mirrors, for every other
    /// orbifold symbol (`632`, `22×`, `4*2`, `o`) its fundamental polygon, whose paired walls are
    /// portals ([`Layout::of_symbol`]).
    pub fn layout(&self) -> Result<Layout, String> {
        let symbol: OrbifoldSymbol = self
            .orbifold
            .signature
            .parse()
            .map_err(|e: orbifold::ParseError| e.to_string())?;
        Layout::of_symbol(&symbol, &self.layout_options()).map_err(|e| e.to_string())
    }
}

/// Settings of the real-time preview (seed Fig. 8.6).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct Preview {
    /// How many reflections deep the copies of the room go.
    pub depth: u32,
    /// How copies fade.
    pub attenuation: Attenuation,
}

impl Default for Preview {
    fn default() -> Self {
        Preview {
            depth: 6,
            attenuation: Attenuation::Reflectance,
        }
    }
}

/// How copies of the room fade in the preview (seed Fig. 8.6).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize, Default)]
#[serde(rename_all = "lowercase")]
pub enum Attenuation {
    /// As in a real mirror room: each copy by the product of the reflectances of the mirrors
    /// its light crossed.
    #[default]
    Reflectance,
    /// Emphasise the orbifold: the room itself bright, every copy faint.
    Orbifold,
    /// Emphasise the translational cover: copies that are not mirror images (an even number of
    /// reflections) bright, mirror images faint.
    Translations,
    /// The universal cover: every copy equally bright.
    Universal,
}

/// The signature and its layout.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct OrbifoldSection {
    /// Kaleidoscopic signature, such as `*22222`.
    pub signature: String,
    /// `default` (free parameters, 1.4 each unless given) or `incircle`.
    pub shape: ShapeName,
    /// Free shape parameters (see docs/layout.md); empty means the shape's defaults.
    pub parameters: Vec<f64>,
    /// Where the polygon's centre goes, in model coordinates.
    pub at: [f64; 2],
    /// Turn of the polygon about its centre, in degrees.
    pub angle: f64,
}

/// The polygon's shape.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize, Default)]
#[serde(rename_all = "lowercase")]
pub enum ShapeName {
    /// The free parameters (seed default 1.4 each).
    #[default]
    Default,
    /// The polygon with an inscribed circle.
    Incircle,
}

/// The prism over the polygon.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct Room {
    /// Height of the walls, in intrinsic units (> 0).
    pub height: f64,
    /// Whether walls not listed in `[[walls]]` are whole mirrors (`all`) or plain walls (`none`).
    pub mirrors: MirrorDefault,
    /// Reflectance of those default mirrors.
    pub reflectance: Color,
    /// Material of wall parts without a mirror.
    pub wall_material: Material,
    /// The floor.
    pub floor: Material,
    /// The ceiling.
    pub ceiling: Material,
    /// Mesh resolution: the longest edge wanted, in intrinsic units (> 0).
    pub resolution: f64,
    /// How the floor and ceiling are meshed: `contour` (the seed's) or `geodesic`.
    pub tessellation: Tessellation,
    /// Ideal corners are cut off at this intrinsic distance from the polygon's centre (absent: 3
    /// beyond the farthest finite corner).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub cusp_distance: Option<f64>,
    /// The width of the solid frame along the edges of a portal (a wall the orbifold's group
    /// pairs with another), in intrinsic units; 0 for none.
    pub portal_frame: f64,
    /// The share of light a portal passes on, per channel.
    pub portal_transmittance: Color,
}

/// The floor and ceiling tessellation method (see `orbifold::room`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize, Default)]
#[serde(rename_all = "lowercase")]
pub enum Tessellation {
    /// The seed's contour-based tessellation.
    #[default]
    Contour,
    /// A fan from the centre refined by geodesic midpoint subdivision.
    Geodesic,
}

/// What a wall without an entry is.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize, Default)]
#[serde(rename_all = "lowercase")]
pub enum MirrorDefault {
    /// A whole mirror.
    #[default]
    All,
    /// A plain wall.
    None,
}

/// One wall's mirrors and material.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, Default)]
#[serde(deny_unknown_fields, default)]
pub struct Wall {
    /// The wall's index: wall i joins corner i to corner i + 1.
    pub index: usize,
    /// The wall's material where there is no mirror (default: the room's).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub material: Option<Material>,
    /// Mirrors on this wall (none means a plain wall).
    pub mirrors: Vec<Mirror>,
}

/// A rectangular mirror in the wall's own coordinates: arc length along the wall from its first
/// corner (as fractions of the wall's length, 0 to 1) × height (intrinsic units from the floor).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct Mirror {
    /// Where the mirror starts along the wall, as a fraction of its length.
    pub from: f64,
    /// Where it ends along the wall.
    pub to: f64,
    /// Its lower edge, above the floor.
    pub bottom: f64,
    /// Its upper edge (at most the room's height; absent means up to the ceiling).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub top: Option<f64>,
    /// Reflectance per channel, in [0, 1].
    pub reflectance: Color,
}

impl Default for Mirror {
    fn default() -> Self {
        Mirror {
            from: 0.0,
            to: 1.0,
            bottom: 0.0,
            top: None,
            reflectance: [0.9; 3],
        }
    }
}

/// A surface's look.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, tag = "kind", rename_all = "lowercase")]
pub enum Material {
    /// One colour.
    Color {
        /// The colour.
        color: Color,
    },
    /// A checkerboard.
    Checker {
        /// The two colours.
        colors: [Color; 2],
        /// The size of a square.
        size: f64,
        /// Whether squares are laid out in model or intrinsic coordinates.
        #[serde(default)]
        coordinates: Coordinates,
    },
    /// An image.
    Texture {
        /// A PNG or JPEG file, relative to the scene file.
        path: String,
        /// The size the image covers.
        scale: f64,
        /// Model or intrinsic coordinates.
        #[serde(default)]
        coordinates: Coordinates,
    },
    /// Smooth glass (a dielectric): Fresnel reflection and refraction. Closed objects only;
    /// their triangles' normals point out.
    Glass {
        /// The colour that light passing through takes (1 = clear).
        #[serde(default = "clear")]
        tint: Color,
        /// Index of refraction, inside over outside (1.5 for glass, 1.33 for water).
        #[serde(default = "glass_index")]
        ior: f64,
    },
    /// A metal: a conductor's Fresnel reflectance over a GGX microfacet surface.
    Metal {
        /// Which metal.
        #[serde(default)]
        metal: MetalName,
        /// GGX roughness α in [0, 1]: 0 is a polished mirror, 0.3 brushed, 1 very dull.
        #[serde(default = "metal_roughness")]
        roughness: f64,
    },
    /// Plastic: a glossy dielectric coat (GGX) over a coloured diffuse base.
    Plastic {
        /// The base colour.
        color: Color,
        /// GGX roughness α of the coat in [0, 1].
        #[serde(default = "plastic_roughness")]
        roughness: f64,
    },
    /// Procedural marble: veins of one colour in a ground of another (Perlin turbulence), laid
    /// out in the chosen coordinates.
    Marble {
        /// The ground colour.
        #[serde(default = "marble_base")]
        base: Color,
        /// The veins' colour.
        #[serde(default = "marble_vein")]
        vein: Color,
        /// The size of the pattern's features.
        #[serde(default = "marble_scale")]
        scale: f64,
        /// Model or intrinsic coordinates.
        #[serde(default)]
        coordinates: Coordinates,
    },
}

/// The metals of [`Material::Metal`], with measured complex indices of refraction.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize, Default)]
#[serde(rename_all = "lowercase")]
pub enum MetalName {
    /// Silver.
    #[default]
    Silver,
    /// Gold.
    Gold,
    /// Copper.
    Copper,
    /// Aluminium.
    Aluminium,
}

fn clear() -> Color {
    [1.0; 3]
}

fn glass_index() -> f64 {
    1.5
}

fn metal_roughness() -> f64 {
    0.1
}

fn plastic_roughness() -> f64 {
    0.2
}

fn marble_base() -> Color {
    [0.92, 0.9, 0.86]
}

fn marble_vein() -> Color {
    [0.25, 0.27, 0.32]
}

fn marble_scale() -> f64 {
    0.3
}

/// Where a pattern is laid out.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize, Default)]
#[serde(rename_all = "lowercase")]
pub enum Coordinates {
    /// Model coordinates (the picture of the floor in the model).
    #[default]
    Model,
    /// Intrinsic coordinates (exponential map at the polygon's centre).
    Intrinsic,
}

/// Something placed in the room.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct Object {
    /// A name for the object in exports and hit reports (absent: `object i`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub name: Option<String>,
    /// A built-in shape: `sphere`, `torus`, `cube`, `figure`, `letter-p`, `letter-q`,
    /// `letter-b`, `letter-d`, `letter-f`; ignored when `mesh` is given.
    pub shape: String,
    /// An OBJ, PLY, glTF or GLB file, relative to the scene file.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub mesh: Option<String>,
    /// Model position of the object's centre of mass.
    pub at: [f64; 2],
    /// Height of the object's lowest point above the floor.
    pub height: f64,
    /// Turn about the vertical axis, in degrees.
    pub yaw: f64,
    /// Size: the object's largest extent, in intrinsic units.
    pub size: f64,
    /// Crease angle in degrees for smooth shading: faces that meet at a vertex with normals
    /// less than this apart are shaded as one smooth surface, and bend more than this stays a
    /// sharp edge. 0 shades every face flat.
    pub crease: f64,
    /// Its material.
    pub material: Material,
}

impl Default for Object {
    fn default() -> Self {
        Object {
            name: None,
            shape: "figure".into(),
            mesh: None,
            at: [0.0, 0.0],
            height: 0.0,
            yaw: 0.0,
            size: 0.5,
            crease: 60.0,
            material: Material::Color {
                color: [0.85, 0.85, 0.8],
            },
        }
    }
}

/// A light source.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct Light {
    /// `point`, `spot`, `sphere` or `rectangle`.
    pub kind: LightKind,
    /// Model position.
    pub at: [f64; 2],
    /// Height above the floor.
    pub height: f64,
    /// Colour.
    pub color: Color,
    /// Power, in watts.
    pub power: f64,
    /// Direction (spot and rectangle): bearing from the model's +x axis, degrees.
    pub yaw: f64,
    /// Direction (spot and rectangle): elevation, degrees (−90 points down).
    pub pitch: f64,
    /// Spot cone half-angle in degrees.
    pub cone: f64,
    /// Sphere radius, intrinsic units.
    pub radius: f64,
    /// Rectangle size, intrinsic units.
    pub size: [f64; 2],
}

impl Default for Light {
    fn default() -> Self {
        Light {
            kind: LightKind::Point,
            at: [0.0, 0.0],
            height: 0.9,
            color: [1.0, 0.95, 0.9],
            power: 20.0,
            yaw: 0.0,
            pitch: -90.0,
            cone: 30.0,
            radius: 0.05,
            size: [0.2, 0.2],
        }
    }
}

/// The kind of a light.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize, Default)]
#[serde(rename_all = "lowercase")]
pub enum LightKind {
    /// A point.
    #[default]
    Point,
    /// A spot light.
    Spot,
    /// A spherical area light.
    Sphere,
    /// A rectangular area light.
    Rectangle,
}

/// The camera (ARCHITECTURE.md §8).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct Camera {
    /// `pinhole` or `panorama`.
    pub kind: CameraKind,
    /// Model position.
    pub at: [f64; 2],
    /// Eye height above the floor.
    pub height: f64,
    /// Bearing from the model's +x direction, counter-clockwise, degrees.
    pub yaw: f64,
    /// Elevation, degrees.
    pub pitch: f64,
    /// Vertical field of view, degrees (pinhole).
    pub fov: f64,
    /// Whether the camera sees the world mirrored, left and right swapped: what a person sees
    /// after walking through a glide reflection's portal (an odd number of them), so that the
    /// view goes on without a jump. Written only when true.
    #[serde(skip_serializing_if = "std::ops::Not::not")]
    pub mirrored: bool,
}

impl Camera {
    /// The pinhole camera's forward, right and up vectors in the eye's orthonormal frame
    /// (model +x, model +y, up), ARCHITECTURE.md §8: forward = (cos pitch cos yaw, cos pitch sin yaw,
    /// sin pitch), right = normalise(forward × up_world), up = right × forward. Straight up or
    /// down, right is the one of the yaw alone. The tracer and the preview share it.
    ///
    /// ```
    /// use orbifold_scene::Camera;
    /// let [forward, right, up] = Camera { yaw: 90.0, pitch: 0.0, ..Camera::default() }.basis();
    /// assert!((forward - glam::DVec3::Y).length() < 1e-15);
    /// assert!((right - glam::DVec3::X).length() < 1e-15);
    /// assert!((up - glam::DVec3::Z).length() < 1e-15);
    /// ```
    pub fn basis(&self) -> [glam::DVec3; 3] {
        use glam::DVec3;
        let (yaw, pitch) = (self.yaw.to_radians(), self.pitch.to_radians());
        let forward = DVec3::new(
            pitch.cos() * yaw.cos(),
            pitch.cos() * yaw.sin(),
            pitch.sin(),
        );
        let right = forward
            .cross(DVec3::Z)
            .try_normalize()
            .unwrap_or(DVec3::new(yaw.sin(), -yaw.cos(), 0.0));
        let up = right.cross(forward);
        // A mirrored camera's right is the world's left: the picture is swapped left for right.
        let right = if self.mirrored { -right } else { right };
        [forward, right, up]
    }
}

impl Default for Camera {
    fn default() -> Self {
        Camera {
            kind: CameraKind::Pinhole,
            at: [-0.2, 0.0],
            height: 0.5,
            yaw: 0.0,
            // Looking a little down, at the figure in the middle of the default room.
            pitch: -20.0,
            fov: 70.0,
            mirrored: false,
        }
    }
}

/// The kind of camera.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize, Default)]
#[serde(rename_all = "lowercase")]
pub enum CameraKind {
    /// A pinhole camera.
    #[default]
    Pinhole,
    /// An equirectangular panorama.
    Panorama,
}

/// Render settings.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct Render {
    /// Image width in pixels.
    pub width: u32,
    /// Image height in pixels.
    pub height: u32,
    /// Samples per pixel.
    pub samples: u32,
    /// Maximum path depth (bounces).
    pub max_depth: u32,
    /// Light as if space were flat: straight rays through the room's model picture instead of
    /// the geodesics (the seed's Fig. 8.1a; `orbifold render --straight-rays`). Off by default.
    pub straight_rays: bool,
    /// How each sample counts for the pixels around it (`orbifold render --filter`).
    pub filter: ReconstructionFilter,
}

/// The pixel reconstruction filter of a render (`orbifold_render::film::PixelFilter`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize, Default)]
#[serde(rename_all = "lowercase")]
pub enum ReconstructionFilter {
    /// pbrt's Gaussian, σ = 0.5 pixel, cut off at 1.5: each sample counts for the pixels within
    /// 1.5 pixels of it (less noise, a softer image).
    #[default]
    Gaussian,
    /// Each sample counts for its own pixel only (sharper, noisier).
    Box,
}

impl Default for Render {
    fn default() -> Self {
        Render {
            width: 640,
            height: 480,
            samples: 64,
            max_depth: 32,
            straight_rays: false,
            filter: ReconstructionFilter::Gaussian,
        }
    }
}

impl Default for OrbifoldSection {
    fn default() -> Self {
        OrbifoldSection {
            signature: "*22222".into(),
            shape: ShapeName::Default,
            parameters: Vec::new(),
            at: [0.0, 0.0],
            angle: 0.0,
        }
    }
}

impl Default for Room {
    fn default() -> Self {
        Room {
            height: 1.0,
            mirrors: MirrorDefault::All,
            reflectance: [0.9; 3],
            wall_material: Material::Color {
                color: [0.75, 0.82, 0.9],
            },
            floor: Material::Checker {
                colors: [[0.9, 0.8, 0.7], [0.6, 0.45, 0.35]],
                size: 0.1,
                coordinates: Coordinates::Intrinsic,
            },
            ceiling: Material::Color {
                color: [0.25, 0.3, 0.5],
            },
            resolution: 0.1,
            tessellation: Tessellation::Contour,
            cusp_distance: None,
            portal_frame: 0.02,
            portal_transmittance: [1.0; 3],
        }
    }
}

impl Default for Scene {
    /// The seed's default room `*22222`: all walls mirrors, a figure, a light, a camera.
    fn default() -> Self {
        Scene {
            orbifold: OrbifoldSection::default(),
            room: Room::default(),
            walls: Vec::new(),
            objects: vec![Object::default()],
            lights: vec![Light {
                at: [0.1, 0.1],
                ..Light::default()
            }],
            camera: Camera::default(),
            render: Render::default(),
            preview: Preview::default(),
            sound: crate::sound::Sound::default(),
        }
    }
}
