//! The room of a scene as geometry: floor, ceiling, walls split into their mirrors and plain
//! parts, and the objects, each an intrinsically flat triangle mesh in the room's plane
//! (ARCHITECTURE.md §7) — what exports, the preview and the tracer's mesh path start from.
//!
//! A mesh is embedded in the room in one place, [`embed_object`]: the scene's objects (through
//! [`Scene::embedded_object`], for the tracer, the preview and the exports) and the meshes of
//! area lights (in `orbifold-render`) alike.

use std::path::Path;

use glam::DVec3;
use num_complex::Complex64;
use orbifold::Layout;
use orbifold::cover::Tile;
use orbifold::embed::{Embedded, Placement, centre_of_mass, embed, place};
use orbifold::room::wall::WallRect;
use orbifold::room::{FloorMethod, RoomMesher, RoomOptions, Surface};
use orbifold::space::Space;

use crate::document::{Color, Material, MetalName, Mirror, MirrorDefault, Scene, Tessellation};
use crate::mesh::TriangleMesh;
use crate::mesh::import::load_mesh;
use crate::mesh::procedural::builtin;
use crate::texture::{PartTexture, TextureImage};

pub use crate::part::{Part, PartKind, ROOM_CREASE};

/// The meshed room.
#[derive(Clone, Debug)]
pub struct RoomGeometry {
    /// The polygon.
    pub layout: Layout,
    /// The mesher, with the boundary that was meshed.
    pub mesher: RoomMesher,
    /// Floor, ceiling, wall and mirror parts, then objects.
    pub parts: Vec<Part>,
    /// Each part's texture in exports, where it has one ([`crate::texture`]).
    pub textures: Vec<Option<PartTexture>>,
}

/// A group of an exported mesh: a part (or all copies of a part) in output coordinates.
#[derive(Clone, Debug, PartialEq)]
pub struct MeshGroup {
    /// The group's name.
    pub name: String,
    /// Its colour.
    pub color: Color,
    /// Whether it is a mirror (exported as a shiny metal of this colour).
    pub mirror: bool,
    /// The crease angle of its exported vertex normals, in degrees
    /// ([`crate::export::smooth_normals`]).
    pub crease: f64,
    /// Vertex positions: [`EXPORT_SCALE`] × model x, [`EXPORT_SCALE`] × model y, height.
    pub positions: Vec<[f64; 3]>,
    /// Triangles, counter-clockwise seen from the front.
    pub triangles: Vec<[u32; 3]>,
    /// Texture coordinates, one (u, v) per position (v upwards, as in OBJ), or none.
    pub uv: Vec<[f64; 2]>,
    /// The image the texture coordinates index, if any ([`crate::texture`]).
    pub texture: Option<TextureImage>,
}

/// Model coordinates farther than this from the origin are left out of exports (on the sphere,
/// the stereographic image of the antipode of the model's centre is at infinity).
pub const FARTHEST_EXPORTED: f64 = 1e3;

/// Exported horizontal coordinates are the model's times this: the model's metric at its
/// centre, λ(0) = 2 (DESIGN.md §3), so that the horizontal and the height have the same scale.
/// A Euclidean room is then exported in its true shape and size, and in the curved geometries
/// lengths are true at the model's centre and shrink outwards by λ(z)/2. (In bare model
/// coordinates every room and object would come out squashed to half its width.)
///
/// ```
/// use orbifold_scene::Scene;
/// use orbifold_scene::geometry::EXPORT_SCALE;
///
/// // A Euclidean room's first wall is as long in the export as it is intrinsically.
/// let mut scene = Scene::default();
/// scene.orbifold.signature = "*2222".into();
/// let layout = scene.layout().unwrap();
/// let [a, b] = [0, 1].map(|i| layout.vertices[i].position * EXPORT_SCALE);
/// assert!(((b - a).norm() - layout.edges[0].length).abs() < 1e-9);
/// ```
pub const EXPORT_SCALE: f64 = 2.0;

impl Scene {
    /// The mirrors of wall `index`, as the file gives them or from the room's default. The
    /// default (`[room] mirrors = "all"`) covers the walls that are mirrors of the orbifold; a
    /// portal (a wall paired with another) has only the mirrors its `[[walls]]` entry gives.
    ///
    /// For a symbol with portals this builds the layout to tell; a caller that has it, or knows
    /// whether the wall is a portal, calls [`Scene::mirrors_of_wall`].
    pub fn wall_mirrors(&self, index: usize) -> Vec<Mirror> {
        let explicit = self.walls.iter().any(|w| w.index == index);
        self.mirrors_of_wall(index, !explicit && self.is_portal(index))
    }

    /// The mirrors of wall `index` as [`Scene::wall_mirrors`] gives them, told whether the wall
    /// is a portal (its layout edge has a partner).
    ///
    /// ```
    /// use orbifold_scene::Scene;
    /// let mut scene = Scene::default();
    /// scene.orbifold.signature = "632".into();
    /// let layout = scene.layout().unwrap();
    /// for (i, edge) in layout.edges.iter().enumerate() {
    ///     assert_eq!(scene.mirrors_of_wall(i, edge.partner().is_some()), scene.wall_mirrors(i));
    /// }
    /// ```
    pub fn mirrors_of_wall(&self, index: usize, portal: bool) -> Vec<Mirror> {
        match self.walls.iter().find(|w| w.index == index) {
            Some(wall) => wall.mirrors.clone(),
            None if portal => Vec::new(),
            None => match self.room.mirrors {
                MirrorDefault::All => vec![Mirror {
                    reflectance: self.room.reflectance,
                    ..Mirror::default()
                }],
                MirrorDefault::None => Vec::new(),
            },
        }
    }

    /// Whether wall `index` is a portal: the orbifold's group pairs it with another wall
    /// (`false` for every wall of a kaleidoscopic signature, and when the layout fails).
    pub fn is_portal(&self, index: usize) -> bool {
        let kaleidoscopic = self
            .orbifold
            .signature
            .parse::<orbifold::OrbifoldSymbol>()
            .map_or(true, |s| s.as_kaleidoscopic().is_some());
        !kaleidoscopic
            && self
                .layout()
                .is_ok_and(|l| l.edges.get(index).is_some_and(|e| e.partner().is_some()))
    }

    /// The material of wall `index` where it has no mirror.
    pub fn wall_material(&self, index: usize) -> &Material {
        self.walls
            .iter()
            .find(|w| w.index == index)
            .and_then(|w| w.material.as_ref())
            .unwrap_or(&self.room.wall_material)
    }

    /// The room mesher for this scene's layout and `[room]` settings.
    pub fn room_mesher(&self, layout: &Layout) -> Result<RoomMesher, String> {
        let options = RoomOptions {
            height: self.room.height,
            resolution: self.room.resolution,
            method: match self.room.tessellation {
                Tessellation::Contour => FloorMethod::Contour,
                Tessellation::Geodesic => FloorMethod::Geodesic,
            },
            cusp_distance: self.room.cusp_distance,
        };
        RoomMesher::new(layout, &options).map_err(|e| e.to_string())
    }

    /// The object-space mesh of object `i`: its mesh file (relative to `base`) or built-in shape.
    pub fn object_mesh(&self, i: usize, base: Option<&Path>) -> Result<TriangleMesh, String> {
        let object = &self.objects[i];
        match &object.mesh {
            Some(file) => {
                let path = base.map_or_else(|| Path::new(file).to_path_buf(), |b| b.join(file));
                load_mesh(&path).map_err(|e| e.to_string())
            }
            None => builtin(&object.shape)
                .ok_or_else(|| format!("objects[{i}]: unknown shape {:?}", object.shape)),
        }
    }

    /// The name of object `i` in exports and reports.
    pub fn object_name(&self, i: usize) -> String {
        self.objects[i]
            .name
            .clone()
            .unwrap_or_else(|| format!("object {i}"))
    }

    /// Meshes the room and its objects. `base` resolves mesh file names.
    ///
    /// ```
    /// use orbifold_scene::Scene;
    /// let geometry = Scene::default().geometry(None)?;
    /// let names: Vec<&str> = geometry.parts.iter().map(|p| p.name.as_str()).collect();
    /// assert_eq!(names[..3], ["floor", "ceiling", "mirror 0.0"]);
    /// assert_eq!(names.last(), Some(&"object 0"));
    /// # Ok::<(), String>(())
    /// ```
    pub fn geometry(&self, base: Option<&Path>) -> Result<RoomGeometry, String> {
        let layout = self.layout()?;
        let mesher = self.room_mesher(&layout)?;
        let mut parts = self.room_parts(&layout, &mesher);
        for i in 0..self.objects.len() {
            parts.push(self.object_part(&layout, i, base)?);
        }
        let textures = self.part_textures(&layout, &mesher, &parts, base);
        Ok(RoomGeometry {
            layout,
            mesher,
            parts,
            textures,
        })
    }

    /// The room's own parts: floor, ceiling, then each wall's mirrors and plain part.
    pub fn room_parts(&self, layout: &Layout, mesher: &RoomMesher) -> Vec<Part> {
        let floor = mesher.floor();
        let mut ceiling = floor.clone();
        ceiling
            .heights
            .iter_mut()
            .for_each(|h| *h = self.room.height);
        ceiling.flip();
        let mut parts = vec![
            Part {
                name: "floor".into(),
                kind: PartKind::Floor,
                color: representative(&self.room.floor),
                reflectance: None,
                crease: ROOM_CREASE,
                surface: floor,
            },
            Part {
                name: "ceiling".into(),
                kind: PartKind::Ceiling,
                color: representative(&self.room.ceiling),
                reflectance: None,
                crease: ROOM_CREASE,
                surface: ceiling,
            },
        ];
        for (wall, edge) in layout.edges.iter().enumerate() {
            parts.extend(self.wall_parts(mesher, wall, edge.partner().is_some()));
        }
        parts
    }

    /// A wall cut along every mirror's edges into a grid of cells; each cell is part of the first
    /// mirror that covers it, or of the plain wall. On a portal (`portal`: the group pairs the
    /// wall with another) the plain wall is only the portal's frame, `room.portal_frame` wide
    /// along its ends, floor and ceiling; the rest is open, and no part.
    fn wall_parts(&self, mesher: &RoomMesher, wall: usize, portal: bool) -> Vec<Part> {
        let height = self.room.height;
        let mirrors = self.mirrors_of_wall(wall, portal);
        // The portal's opening, as fractions of the wall's length and heights.
        let frame = self.room.portal_frame;
        let length = mesher.wall_length(wall).unwrap_or(0.0);
        let opening = (portal && length > 0.0).then(|| {
            let f = if frame > 0.0 { frame / length } else { 0.0 };
            (
                [f.min(0.5), (1.0 - f).max(0.5)],
                [frame.min(0.5 * height), (height - frame).max(0.5 * height)],
            )
        });
        let cuts = |values: &mut Vec<f64>| {
            values.sort_by(f64::total_cmp);
            values.dedup_by(|a, b| (*a - *b).abs() < 1e-12);
        };
        let mut along = vec![0.0, 1.0];
        let mut heights = vec![0.0, height];
        for m in &mirrors {
            along.extend([m.from, m.to]);
            heights.extend([m.bottom, m.top.unwrap_or(height).min(height)]);
        }
        if let Some((a, h)) = opening {
            along.extend(a);
            heights.extend(h);
        }
        cuts(&mut along);
        cuts(&mut heights);
        let mut plain = Surface::default();
        let mut glass = vec![Surface::default(); mirrors.len()];
        for a in along.windows(2) {
            for h in heights.windows(2) {
                let (s, t) = (0.5 * (a[0] + a[1]), 0.5 * (h[0] + h[1]));
                let rect = WallRect {
                    along: [a[0], a[1]],
                    heights: [h[0], h[1]],
                };
                let Some(cell) = mesher.wall(wall, rect) else {
                    continue;
                };
                let covering = mirrors.iter().position(|m| {
                    m.from <= s && s <= m.to && m.bottom <= t && t <= m.top.unwrap_or(height)
                });
                let open =
                    opening.is_some_and(|(a, h)| a[0] < s && s < a[1] && h[0] < t && t < h[1]);
                match covering {
                    Some(j) => glass[j].append(&cell),
                    None if open => {}
                    None => plain.append(&cell),
                }
            }
        }
        let mut parts: Vec<Part> = glass
            .into_iter()
            .enumerate()
            .filter(|(_, s)| !s.triangles.is_empty())
            .map(|(j, surface)| Part {
                name: format!("mirror {wall}.{j}"),
                kind: PartKind::Mirror { wall, mirror: j },
                color: mirrors[j].reflectance,
                reflectance: Some(mirrors[j].reflectance),
                crease: ROOM_CREASE,
                surface,
            })
            .collect();
        if !plain.triangles.is_empty() {
            parts.push(Part {
                name: format!("wall {wall}"),
                kind: PartKind::Wall(wall),
                color: representative(self.wall_material(wall)),
                reflectance: None,
                crease: ROOM_CREASE,
                surface: plain,
            });
        }
        parts
    }

    /// Object `i` embedded at its centre of mass and scaled to its size ([`embed_object`] with
    /// [`Fit::Size`]), not yet placed: its points, heights and triangles, and the placement the
    /// scene gives it. Placing is an isometry and a height offset ([`Placement::isometry`]), so
    /// a moved object needs no new embedding.
    pub fn embedded_object(
        &self,
        layout: &Layout,
        i: usize,
        base: Option<&Path>,
    ) -> Result<(Embedded, Vec<[u32; 3]>, Placement), String> {
        let mesh = self.object_mesh(i, base)?;
        let embedded = embed_object(layout.space(), &mesh, Fit::Size(self.objects[i].size))
            .map_err(|e| format!("objects[{i}]: {e}"))?;
        Ok((embedded, mesh.triangles, self.object_placement(i)))
    }

    /// Where object `i` stands: its model position, height and yaw (radians).
    pub fn object_placement(&self, i: usize) -> Placement {
        let object = &self.objects[i];
        Placement {
            at: Complex64::new(object.at[0], object.at[1]),
            height: object.height,
            yaw: object.yaw.to_radians(),
        }
    }

    /// Object `i` embedded at its centre of mass, scaled to its size and placed.
    fn object_part(&self, layout: &Layout, i: usize, base: Option<&Path>) -> Result<Part, String> {
        let object = &self.objects[i];
        let (embedded, triangles, placement) = self.embedded_object(layout, i, base)?;
        let placed = place(layout.space(), &embedded, &placement);
        Ok(Part {
            name: self.object_name(i),
            kind: PartKind::Object(i),
            color: representative(&object.material),
            reflectance: None,
            crease: object.crease,
            surface: Surface {
                points: placed.points,
                heights: placed.heights,
                triangles,
            },
        })
    }
}

/// How [`embed_object`] sets a mesh's object coordinates into the room.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Fit {
    /// About the mesh's centre of mass ([`centre_of_mass`]), scaled so that its largest extent
    /// along the object axes is this size: the scene's objects and sphere lights.
    Size(f64),
    /// As modelled: about the origin of the object coordinates, unscaled. For meshes built at
    /// their size about the point they stand at (rectangle lights).
    AsModelled,
}

/// A triangle mesh in object coordinates (Y up) embedded at the origin of the room's plane,
/// not yet placed; `fit` says about which point and at what scale. [`embed`] keeps distances
/// and bearings from that point and makes Y the height, the lowest vertex at 0. Placing the
/// result is an isometry and a height offset ([`Placement::isometry`]), so a moved object needs
/// no new embedding.
///
/// Every mesh of a scene is embedded here: the objects ([`Scene::embedded_object`], which the
/// tracer and the preview call) and the sphere and rectangle lights of `orbifold-render`.
///
/// # Errors
///
/// With [`Fit::Size`], when the mesh is empty or has no finite, positive extent.
///
/// ```
/// use orbifold::{Geometry, space::Space};
/// use orbifold_scene::geometry::{Fit, embed_object};
/// use orbifold_scene::mesh::procedural::cube;
///
/// let h2 = Space::new(Geometry::Hyperbolic);
/// let cube = cube(2.0);
/// // Scaled to an edge of 0.5 about its centre: it stands at height 0 and is 0.5 tall.
/// let embedded = embed_object(h2, &cube, Fit::Size(0.5))?;
/// assert_eq!(embedded.points.len(), cube.positions.len());
/// let top = embedded.heights.iter().copied().fold(0.0, f64::max);
/// assert!((top - 0.5).abs() < 1e-12);
/// // As modelled, its edge stays 2.
/// let modelled = embed_object(h2, &cube, Fit::AsModelled)?;
/// let top = modelled.heights.iter().copied().fold(0.0, f64::max);
/// assert!((top - 2.0).abs() < 1e-12);
/// # Ok::<(), String>(())
/// ```
pub fn embed_object(space: Space, mesh: &TriangleMesh, fit: Fit) -> Result<Embedded, String> {
    let (centre, scale) = match fit {
        Fit::Size(size) => {
            let (lo, hi) = mesh.bounds().ok_or("the mesh is empty")?;
            let extent = (0..3).map(|k| hi[k] - lo[k]).fold(0.0, f64::max);
            if !(extent.is_finite() && extent > 0.0) {
                return Err("the mesh has no extent".into());
            }
            (
                centre_of_mass(&mesh.positions, &mesh.triangles),
                size / extent,
            )
        }
        Fit::AsModelled => (DVec3::ZERO, 1.0),
    };
    Ok(embed(space, &mesh.positions, centre, scale))
}

/// One colour that stands for a material in formats without textures.
pub fn representative(material: &Material) -> Color {
    match material {
        Material::Color { color } => *color,
        Material::Checker { colors, .. } => [0, 1, 2].map(|k| 0.5 * (colors[0][k] + colors[1][k])),
        Material::Texture { .. } => [0.8; 3],
        Material::Glass { tint, .. } => tint.map(|c| 0.9 * c),
        Material::Metal { metal, .. } => match metal {
            MetalName::Silver => [0.95, 0.93, 0.88],
            MetalName::Gold => [1.0, 0.78, 0.34],
            MetalName::Copper => [0.95, 0.64, 0.54],
            MetalName::Aluminium => [0.91, 0.92, 0.92],
        },
        Material::Plastic { color, .. } => *color,
        Material::Marble { base, vein, .. } => [0, 1, 2].map(|k| 0.8 * base[k] + 0.2 * vein[k]),
    }
}

impl RoomGeometry {
    /// The parts as export groups in export coordinates ([`EXPORT_SCALE`] × model x and y,
    /// height), followed — for each tile of `copies` but the room itself — by the images of
    /// every part, gathered per part into groups named `<part> copies`. Mirror images are turned inside out back again, so that
    /// every triangle keeps facing the front. Returns the groups and the number of triangles left
    /// out because a vertex is farther than [`FARTHEST_EXPORTED`] in the model.
    pub fn groups(&self, copies: &[Tile]) -> (Vec<MeshGroup>, usize) {
        let space = self.layout.space();
        let mut omitted = 0;
        let mut groups = Vec::with_capacity(self.parts.len() * 2);
        let no_textures = vec![None; self.parts.len()];
        let textures = if self.textures.len() == self.parts.len() {
            &self.textures
        } else {
            &no_textures
        };
        for (part, texture) in self.parts.iter().zip(textures) {
            let mut group = MeshGroup {
                name: part.name.clone(),
                color: part.color,
                mirror: part.reflectance.is_some(),
                crease: part.crease,
                positions: Vec::new(),
                triangles: Vec::new(),
                uv: Vec::new(),
                texture: texture.as_ref().map(|t| t.image.clone()),
            };
            omitted += add_copy(&mut group, space, &part.surface, texture.as_ref(), None);
            groups.push(group);
        }
        let images = copies.iter().filter(|t| t.depth > 0);
        if copies.iter().any(|t| t.depth > 0) {
            let mut image_groups: Vec<MeshGroup> = groups
                .iter()
                .map(|g| MeshGroup {
                    name: format!("{} copies", g.name),
                    positions: Vec::new(),
                    triangles: Vec::new(),
                    uv: Vec::new(),
                    ..g.clone()
                })
                .collect();
            for tile in images {
                for ((part, texture), group) in
                    self.parts.iter().zip(textures).zip(&mut image_groups)
                {
                    omitted += add_copy(group, space, &part.surface, texture.as_ref(), Some(tile));
                }
            }
            groups.extend(image_groups);
        }
        (groups, omitted)
    }
}

/// Appends the image of `surface` under `tile` (or the surface itself) to `group` in export
/// coordinates, with the texture coordinates of the surface's own vertices (a copy carries its
/// texture along); returns how many triangles were left out for being too far out.
fn add_copy(
    group: &mut MeshGroup,
    space: orbifold::space::Space,
    surface: &Surface,
    texture: Option<&PartTexture>,
    tile: Option<&Tile>,
) -> usize {
    let offset = group.positions.len() as u32;
    if let Some(texture) = texture {
        group.uv.extend_from_slice(&texture.uv);
    }
    let moved = |p: DVec3| tile.map_or(p, |t| t.matrix * p);
    group
        .positions
        .extend(surface.points.iter().zip(&surface.heights).map(|(&p, &h)| {
            let z = space.to_model(moved(p)) * EXPORT_SCALE;
            [z.re, z.im, h]
        }));
    let reflected = tile.is_some_and(|t| t.reflected);
    let far = |i: u32| {
        let p = group.positions[(offset + i) as usize];
        let r = p[0].hypot(p[1]);
        r.is_nan() || r > FARTHEST_EXPORTED * EXPORT_SCALE
    };
    let mut omitted = 0;
    for t in &surface.triangles {
        if t.iter().any(|&i| far(i)) {
            omitted += 1;
            continue;
        }
        let t = if reflected { [t[0], t[2], t[1]] } else { *t };
        group.triangles.push(t.map(|i| i + offset));
    }
    omitted
}
