//! The room and its objects as GPU-ready triangle lists: vertices in ambient coordinates with
//! heights, pattern coordinates, and the index of their part in the part table.
//!
//! Objects are kept in their own frames (embedded at the origin, ARCHITECTURE.md §7) and placed by a
//! transform in the part table, so moving one uploads 64 bytes. Their parts come first in the
//! table, so that rebuilding the room (a new layout) leaves the objects' indices alone.

use std::ops::Range;
use std::path::Path;

use bytemuck::{Pod, Zeroable};
use glam::DVec3;
use num_complex::Complex64;
use orbifold::Layout;
use orbifold::embed::Placement;
use orbifold::room::{RoomMesher, Surface};
use orbifold::space::Space;
use orbifold_scene::geometry::{Part, PartKind, representative};
use orbifold_scene::{Color, Coordinates, Material, Scene};

use crate::textures::TextureTable;

/// How much of the mirror's colour the room's own mirrors lay over what is seen through them
/// (copies' mirrors show only their frames, so that far copies do not fog over).
pub const MIRROR_ALPHA: f32 = 0.06;

/// One vertex as the shader reads it.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct Vertex {
    /// Ambient coordinates of the horizontal position (in the object's own frame for objects).
    pub position: [f32; 3],
    /// Height.
    pub height: f32,
    /// Coordinates of the surface pattern (a checkerboard's squares).
    pub pattern: [f32; 3],
    /// The index of the vertex's part in the part table.
    pub part: u32,
}

/// One entry of the part table: how a part looks and where it stands.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct PartStyle {
    /// The colour (linear RGB; marble's ground); `w` is the pattern's size: a checkerboard's
    /// square, the extent of one copy of an image, the size of marble's features.
    pub color: [f32; 4],
    /// The checkerboard's second colour (marble's veins); `w` is the opacity (1, or
    /// [`MIRROR_ALPHA`]).
    pub second: [f32; 4],
    /// The part's placement: columns of an ambient isometry; `transform[0][3]` is the height
    /// offset.
    pub transform: [[f32; 4]; 3],
    /// The surface code of the tracer's surface-id AOV: 0 floor, 1 ceiling, 2 + i wall i,
    /// 1000 + i object i.
    pub code: i32,
    /// 1 for a mirror, 0 for an opaque part.
    pub mirror: u32,
    /// What the surface shows: [`PLAIN`], [`CHECKER`], [`IMAGE`] or [`MARBLE`].
    pub pattern: u32,
    /// For an image, its layer in the scene's [`TextureTable`].
    pub layer: u32,
    /// For a mirror, its rectangle in wall coordinates: from, to (arc length along the wall),
    /// bottom, top; its frame is drawn along the edges.
    pub frame: [f32; 4],
}

/// [`PartStyle::pattern`]: one colour (what stands for a material without a pattern).
pub const PLAIN: u32 = 0;
/// [`PartStyle::pattern`]: a checkerboard of `color` and `second`, squares `color.w` wide.
pub const CHECKER: u32 = 1;
/// [`PartStyle::pattern`]: an image ([`PartStyle::layer`]) repeating every `color.w`.
pub const IMAGE: u32 = 2;
/// [`PartStyle::pattern`]: marble, veins of `second` in a ground of `color`, features of size
/// `color.w` (the renderer's procedural marble, `orbifold_render::textures::marble`).
pub const MARBLE: u32 = 3;

impl PartStyle {
    /// A part that stands where it was meshed; an image material takes its layer in `textures`.
    fn new(material: &Material, code: i32, textures: &mut TextureTable) -> PartStyle {
        let plain = representative(material);
        let (pattern, color, second, size, layer) = match material {
            Material::Checker { colors, size, .. } => (CHECKER, colors[0], colors[1], *size, 0),
            Material::Marble {
                base, vein, scale, ..
            } => (MARBLE, *base, *vein, *scale, 0),
            Material::Texture { path, scale, .. } => {
                (IMAGE, plain, plain, *scale, textures.layer(path))
            }
            _ => (PLAIN, plain, plain, 0.0, 0),
        };
        let mut style = PartStyle {
            color: rgba(color, size as f32),
            second: rgba(second, 1.0),
            code,
            pattern,
            layer,
            ..PartStyle::default()
        };
        style.place(Space::new(orbifold::Geometry::Euclidean), None);
        style
    }

    /// A mirror of this reflectance on wall `wall`, spanning `frame` (see [`PartStyle::frame`]).
    fn mirror(reflectance: Color, wall: usize, frame: [f32; 4]) -> PartStyle {
        let plain = Material::Color { color: reflectance };
        let mut style = PartStyle::new(&plain, 2 + wall as i32, &mut TextureTable::default());
        style.second[3] = MIRROR_ALPHA;
        style.mirror = 1;
        style.frame = frame;
        style
    }

    /// Sets the placement (`None`: the identity).
    pub fn place(&mut self, space: Space, placement: Option<&Placement>) {
        let (m, h) = placement.map_or((glam::DMat3::IDENTITY, 0.0), |p| {
            (p.isometry(space).matrix(), p.height)
        });
        self.transform =
            [m.x_axis, m.y_axis, m.z_axis].map(|c| [c.x, c.y, c.z, 0.0].map(|v| v as f32));
        self.transform[0][3] = h as f32;
    }
}

fn rgba(c: Color, w: f32) -> [f32; 4] {
    [c[0] as f32, c[1] as f32, c[2] as f32, w]
}

/// A triangle list with its opaque triangles first and its mirrors after.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct MeshData {
    /// The vertices.
    pub vertices: Vec<Vertex>,
    /// Three indices a triangle.
    pub indices: Vec<u32>,
    /// The range of `indices` drawn opaque.
    pub opaque: Range<u32>,
    /// The range of `indices` drawn as translucent mirrors.
    pub mirrors: Range<u32>,
}

impl MeshData {
    /// The number of triangles.
    pub fn triangles(&self) -> usize {
        self.indices.len() / 3
    }

    fn push(&mut self, surface: &Surface, part: u32, pattern: impl Fn(DVec3, f64) -> [f64; 3]) {
        let offset = self.vertices.len() as u32;
        self.vertices.extend(
            surface
                .points
                .iter()
                .zip(&surface.heights)
                .map(|(&p, &h)| Vertex {
                    position: [p.x as f32, p.y as f32, p.z as f32],
                    height: h as f32,
                    pattern: pattern(p, h).map(|v| v as f32),
                    part,
                }),
        );
        let ordered = for_vertex_cache(&surface.triangles, surface.points.len());
        self.indices.extend(ordered.into_iter().map(|i| i + offset));
    }
}

/// The objects of a scene: their meshes in their own frames, their styles and placements.
#[derive(Clone, Debug, Default)]
pub struct ObjectMeshes {
    /// All objects' triangles (part index i is object i), at full detail; `levels` lists the
    /// index ranges of each level of detail.
    pub mesh: MeshData,
    /// The index ranges of the levels of detail, finest first: level 0 is every triangle, each
    /// further level about a quarter of the one before (see [`LEVELS`]).
    pub levels: Vec<Range<u32>>,
    /// One style per object, placed.
    pub styles: Vec<PartStyle>,
    /// Each object's radius: the largest intrinsic distance of a vertex from its centre, and
    /// its highest point.
    pub extents: Vec<(f64, f64)>,
}

/// Meshes every object of `scene` (mesh files relative to `base`); image materials take their
/// layers in `textures`.
pub fn objects(
    scene: &Scene,
    layout: &Layout,
    base: Option<&Path>,
    textures: &mut TextureTable,
) -> Result<ObjectMeshes, String> {
    let space = layout.space();
    let mut out = ObjectMeshes::default();
    for (i, object) in scene.objects.iter().enumerate() {
        let (embedded, triangles, placement) = scene.embedded_object(layout, i, base)?;
        let surface = Surface {
            points: embedded.points,
            heights: embedded.heights,
            triangles,
        };
        let moved = placement.isometry(space).matrix();
        let patterns = Patterns::new(space, layout, &object.material);
        out.mesh.push(&surface, i as u32, |p, h| {
            patterns.floor(moved * p, h + placement.height)
        });
        let mut style = PartStyle::new(&object.material, 1000 + i as i32, textures);
        style.place(space, Some(&placement));
        out.styles.push(style);
        let origin = DVec3::Z;
        let radius = surface
            .points
            .iter()
            .map(|&p| space.ambient_distance(origin, p))
            .fold(0.0, f64::max);
        let top = surface.heights.iter().copied().fold(0.0, f64::max);
        out.extents.push((radius, top));
    }
    let end = out.mesh.indices.len() as u32;
    out.mesh.opaque = 0..end;
    out.mesh.mirrors = end..end;
    out.levels = std::iter::once(0..end).collect();
    add_levels(&mut out);
    Ok(out)
}

/// The triangles reordered for the GPU's post-transform vertex cache (meshoptimizer), so that
/// the vertex shader, which runs the projection's transcendental functions, runs about once per
/// vertex rather than once per corner: scanned meshes come in an order that shares few vertices
/// between neighbouring triangles. On a GPU whose graphics units are few this is most of the
/// time of a frame with millions of triangles (docs/benchmarks.md).
fn for_vertex_cache(triangles: &[[u32; 3]], vertex_count: usize) -> Vec<u32> {
    let flat: Vec<u32> = triangles.iter().flatten().copied().collect();
    meshopt::optimize_vertex_cache(&flat, vertex_count)
}

/// Levels of detail of the objects: every triangle, then about 1/4, 1/16 and 1/64 of them.
pub const LEVELS: usize = 4;

/// Appends the coarser levels of detail of the objects to their index list: each object
/// simplified (meshoptimizer, in the object's tangent-plane coordinates: x, y, height) to about
/// a quarter of the triangles of the level before, keeping at least 16.
fn add_levels(out: &mut ObjectMeshes) {
    let positions: Vec<[f32; 3]> = out
        .mesh
        .vertices
        .iter()
        .map(|v| [v.position[0], v.position[1], v.height])
        .collect();
    let bytes: &[u8] = bytemuck::cast_slice(&positions);
    let Ok(adapter) = meshopt::VertexDataAdapter::new(bytes, 12, 0) else {
        return;
    };
    // Each object's triangles at full detail.
    let full = out.mesh.indices.clone();
    let mut objects: Vec<Vec<u32>> = vec![Vec::new(); out.styles.len()];
    for t in full.chunks_exact(3) {
        let part = out.mesh.vertices[t[0] as usize].part as usize;
        if let Some(list) = objects.get_mut(part) {
            list.extend_from_slice(t);
        }
    }
    for _ in 1..LEVELS {
        let start = out.mesh.indices.len() as u32;
        for list in &mut objects {
            let target = (list.len() / 4 / 3 * 3).max(48).min(list.len());
            let mut coarser = meshopt::simplify(
                list,
                &adapter,
                target,
                0.05,
                meshopt::SimplifyOptions::empty(),
                None,
            );
            if !coarser.is_empty() && coarser.len() < list.len() {
                meshopt::optimize_vertex_cache_in_place(&mut coarser, positions.len());
                *list = coarser;
            }
            out.mesh.indices.extend_from_slice(list);
        }
        out.levels.push(start..out.mesh.indices.len() as u32);
    }
}

/// The room's floor, ceiling, walls and mirrors, with their styles; part indices start at
/// `first_part`; image materials take their layers in `textures`.
pub fn room(
    scene: &Scene,
    layout: &Layout,
    mesher: &RoomMesher,
    first_part: u32,
    textures: &mut TextureTable,
) -> (MeshData, Vec<PartStyle>) {
    let space = layout.space();
    let parts = scene.room_parts(layout, mesher);
    let mut mesh = MeshData::default();
    let mut styles = Vec::new();
    // Opaque parts first, mirrors after.
    let (mirrors, opaque): (Vec<&Part>, Vec<&Part>) =
        parts.iter().partition(|p| p.reflectance.is_some());
    for (pass, list) in [opaque, mirrors].iter().enumerate() {
        let start = mesh.indices.len() as u32;
        for part in list {
            let index = first_part + styles.len() as u32;
            match part.kind {
                PartKind::Floor | PartKind::Ceiling => {
                    let material = if part.kind == PartKind::Floor {
                        &scene.room.floor
                    } else {
                        &scene.room.ceiling
                    };
                    let patterns = Patterns::new(space, layout, material);
                    mesh.push(&part.surface, index, |p, h| patterns.floor(p, h));
                    let code = if part.kind == PartKind::Floor { 0 } else { 1 };
                    styles.push(PartStyle::new(material, code, textures));
                }
                PartKind::Wall(w) | PartKind::Mirror { wall: w, .. } => {
                    let start_point = mesher.wall_point(w, 0.0);
                    let first = mesh.vertices.len();
                    mesh.push(&part.surface, index, |p, h| {
                        let along = start_point.map_or(0.0, |s| space.ambient_distance(s, p));
                        [along, h, 0.0]
                    });
                    styles.push(match part.reflectance {
                        Some(r) => PartStyle::mirror(r, w, extent(&mesh.vertices[first..])),
                        None => PartStyle::new(scene.wall_material(w), 2 + w as i32, textures),
                    });
                }
                PartKind::Object(_) => {}
            }
        }
        let end = mesh.indices.len() as u32;
        if pass == 0 {
            mesh.opaque = start..end;
        } else {
            mesh.mirrors = start..end;
        }
    }
    (mesh, styles)
}

/// The rectangle the pattern coordinates of wall vertices span: from, to, bottom, top.
fn extent(vertices: &[Vertex]) -> [f32; 4] {
    vertices.iter().fold(
        [
            f32::INFINITY,
            f32::NEG_INFINITY,
            f32::INFINITY,
            f32::NEG_INFINITY,
        ],
        |e, v| {
            [
                e[0].min(v.pattern[0]),
                e[1].max(v.pattern[0]),
                e[2].min(v.pattern[1]),
                e[3].max(v.pattern[1]),
            ]
        },
    )
}

/// The coordinates a floor, ceiling or object pattern is laid out in (as the renderer does):
/// model coordinates, or the logarithm map at the room's centre in the model's frame there.
struct Patterns {
    space: Space,
    intrinsic: bool,
    centre: DVec3,
    frame: [DVec3; 2],
}

impl Patterns {
    fn new(space: Space, layout: &Layout, material: &Material) -> Patterns {
        let intrinsic = matches!(
            material,
            Material::Checker {
                coordinates: Coordinates::Intrinsic,
                ..
            } | Material::Texture {
                coordinates: Coordinates::Intrinsic,
                ..
            } | Material::Marble {
                coordinates: Coordinates::Intrinsic,
                ..
            }
        );
        Patterns {
            space,
            intrinsic,
            centre: space.to_ambient(layout.centre),
            frame: [
                space.model_tangent(layout.centre, Complex64::new(1.0, 0.0)),
                space.model_tangent(layout.centre, Complex64::new(0.0, 1.0)),
            ],
        }
    }

    fn floor(&self, p: DVec3, h: f64) -> [f64; 3] {
        if self.intrinsic {
            let v = self.space.log(self.centre, p);
            [
                self.space.point_dot(v, self.frame[0]),
                self.space.point_dot(v, self.frame[1]),
                h,
            ]
        } else {
            let z = self.space.to_model(p);
            [z.re, z.im, h]
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Average cache miss ratio (vertex shader runs per triangle) of a 16-entry FIFO cache.
    fn acmr(indices: &[u32], vertex_count: usize) -> f32 {
        meshopt::analyze_vertex_cache(indices, vertex_count, 16, 0, 0).acmr
    }

    #[test]
    fn every_level_of_detail_is_ordered_for_the_vertex_cache() {
        let scene = Scene::default();
        let layout = scene.layout().unwrap();
        let objects = objects(&scene, &layout, None, &mut TextureTable::default()).unwrap();
        let count = objects.mesh.vertices.len();
        assert_eq!(objects.levels.len(), LEVELS);
        for level in &objects.levels {
            let indices = &objects.mesh.indices[level.start as usize..level.end as usize];
            let ordered = acmr(indices, count);
            // The same triangles in a scrambled order (a fixed stride through them).
            let triangles: Vec<&[u32]> = indices.chunks_exact(3).collect();
            let n = triangles.len();
            let stride = (0..)
                .map(|k| n / 2 + 1 + k)
                .find(|s| gcd(*s, n) == 1)
                .unwrap();
            let scrambled: Vec<u32> = (0..n)
                .flat_map(|i| triangles[i * stride % n].iter().copied())
                .collect();
            let before = acmr(&scrambled, count);
            assert!(
                ordered < 0.8 && ordered < 0.6 * before,
                "level {level:?}: ACMR {ordered} ordered, {before} scrambled"
            );
        }
    }

    fn gcd(a: usize, b: usize) -> usize {
        if b == 0 { a } else { gcd(b, a % b) }
    }
}
