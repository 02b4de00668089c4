//! Mesh export: Wavefront OBJ (with an MTL file of named materials), binary PLY and glTF binary
//! (GLB), one named group per part of the room, with smooth vertex normals
//! ([`smooth_normals`]).
//!
//! Coordinates are the model's x and y, times [`EXPORT_SCALE`] (the model's metric at its centre,
//! so that a Euclidean room has its true size and shape), and the height above the floor, in that
//! order, for OBJ and PLY (Z up: in Blender choose "Up: Z" when importing OBJ). glTF is Y up by
//! specification, so there a vertex (x, y, h) is written as (x, h, −y); every importer then shows
//! the room upright. The files say so in their headers (a comment in OBJ and PLY,
//! `asset.extras` in glTF).
//!
//! This module holds what the formats share: [`export`], which writes a file and whatever goes
//! beside it, the smooth normals every format writes, and the gathering of the textured groups'
//! images. Each format has a file of its own, which cites its specification: `obj.rs` ([`to_obj`],
//! [`to_mtl`]), `ply.rs` ([`to_ply`], [`to_ply_textured`]) and `gltf.rs` ([`to_glb`],
//! [`to_glb_textured`]).

use std::collections::HashMap;
use std::path::{Path, PathBuf};

use glam::DVec3;

use crate::file::write_atomic;
#[cfg(doc)]
use crate::geometry::EXPORT_SCALE;
use crate::geometry::MeshGroup;
use crate::texture::TextureImage;

mod gltf;
mod obj;
mod ply;

pub use gltf::{to_glb, to_glb_textured};
pub use obj::{to_mtl, to_obj};
pub use ply::{to_ply, to_ply_textured};

/// A mesh file format.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ExportFormat {
    /// Wavefront OBJ, with a `.mtl` beside it.
    Obj,
    /// Binary little-endian PLY, with a per-face group index.
    Ply,
    /// glTF 2.0 binary.
    Glb,
}

impl ExportFormat {
    /// The format a file name's extension asks for (`.obj`, `.ply`, `.glb`), if any.
    pub fn from_path(path: &Path) -> Option<ExportFormat> {
        let ext = path.extension()?.to_str()?.to_ascii_lowercase();
        match ext.as_str() {
            "obj" => Some(ExportFormat::Obj),
            "ply" => Some(ExportFormat::Ply),
            "glb" => Some(ExportFormat::Glb),
            _ => None,
        }
    }
}

/// What the header of every export says about its coordinates.
pub const COORDINATES_NOTE: &str = "coordinates: 2 model x, 2 model y, height above the floor (the model is the stereographic plane, \
     the Euclidean plane or the Poincare disk, scaled by its metric at the centre so that a Euclidean room has its true size; \
     see docs/room.md)";

/// Writes `groups` to `path` in `format`, atomically (for OBJ also `path` with `.mtl`, and the
/// images of textured groups beside it; glTF embeds them: [`crate::texture`]). Returns the files
/// written.
pub fn export(
    groups: &[MeshGroup],
    format: ExportFormat,
    path: &Path,
    title: &str,
) -> std::io::Result<Vec<PathBuf>> {
    match format {
        ExportFormat::Obj => {
            let mtl = path.with_extension("mtl");
            let mtl_name = mtl
                .file_name()
                .map(|n| n.to_string_lossy().into_owned())
                .unwrap_or_else(|| "room.mtl".into());
            let images = Images::gather(groups, path)?;
            let folder = path.parent().unwrap_or(Path::new(""));
            let mut written = vec![path.to_path_buf(), mtl.clone()];
            for (name, bytes) in &images.files {
                let file = folder.join(name);
                write_atomic(&file, bytes)?;
                written.push(file);
            }
            write_atomic(&mtl, to_mtl(groups, &images.names()).as_bytes())?;
            write_atomic(path, to_obj(groups, &mtl_name, title).as_bytes())?;
            Ok(written)
        }
        ExportFormat::Ply => {
            let images = Images::gather(groups, path)?;
            let folder = path.parent().unwrap_or(Path::new(""));
            let mut written = vec![path.to_path_buf()];
            for (name, bytes) in &images.files {
                let file = folder.join(name);
                write_atomic(&file, bytes)?;
                written.push(file);
            }
            let names: Vec<&str> = images.files.iter().map(|(n, _)| n.as_str()).collect();
            write_atomic(
                path,
                &to_ply_textured(groups, title, &names, &images.of_group),
            )?;
            Ok(written)
        }
        ExportFormat::Glb => {
            let images = Images::gather(groups, path)?;
            let embedded: Vec<Option<&[u8]>> = images
                .of_group
                .iter()
                .map(|k| k.map(|k| images.files[k].1.as_slice()))
                .collect();
            write_atomic(path, &to_glb_textured(groups, title, &embedded))?;
            Ok(vec![path.to_path_buf()])
        }
    }
}

/// A name usable as an OBJ/MTL identifier (no spaces).
pub fn identifier(name: &str) -> String {
    name.chars()
        .map(|c| if c.is_whitespace() { '_' } else { c })
        .collect()
}

/// A group's mesh with a unit normal at every vertex: what the formats write.
#[derive(Clone, Debug, PartialEq)]
pub struct Shaded {
    /// Vertex positions: 2 model x, 2 model y, height (a vertex of the group appears once per
    /// distinct normal of its corners).
    pub positions: Vec<[f64; 3]>,
    /// A unit normal per vertex, in the same coordinates.
    pub normals: Vec<[f32; 3]>,
    /// The group's triangles, in its order, over these vertices.
    pub triangles: Vec<[u32; 3]>,
    /// Texture coordinates per vertex (empty when the group has none).
    pub uv: Vec<[f64; 2]>,
}

/// The group's mesh with smooth vertex normals, as a viewer of the exported file should shade
/// it: each corner's normal is the mean of the normals of the faces round its vertex that bend
/// from the corner's own face by less than the group's crease angle, weighted by their angles
/// at the vertex (Thürmer and Wüthrich, as the renderer does). A vertex whose corners get
/// different normals is written once per normal, so the creases stay sharp. The normals are
/// those of the exported surface in its own coordinates, which is what other tools see.
/// A corner of a degenerate face takes the mean of all the faces round its vertex (straight up
/// if there is none).
///
/// ```
/// use orbifold_scene::export::smooth_normals;
/// use orbifold_scene::geometry::MeshGroup;
///
/// // Two faces folded by 90° along the edge 0-1: the edge's vertices are split.
/// let group = MeshGroup {
///     name: "fold".into(),
///     color: [1.0; 3],
///     mirror: false,
///     crease: 60.0,
///     positions: vec![[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]],
///     triangles: vec![[0, 1, 2], [1, 0, 3]],
///     uv: Vec::new(),
///     texture: None,
/// };
/// let shaded = smooth_normals(&group);
/// assert_eq!(shaded.positions.len(), 6);
/// assert_eq!(shaded.normals[shaded.triangles[0][0] as usize], [0.0, 0.0, 1.0]);
/// assert_eq!(shaded.normals[shaded.triangles[1][0] as usize], [0.0, 1.0, 0.0]);
/// ```
pub fn smooth_normals(group: &MeshGroup) -> Shaded {
    let point = |i: u32| DVec3::from_array(group.positions[i as usize]);
    // Each face's unit normal (None if degenerate) and its angle at each corner.
    let faces: Vec<(Option<DVec3>, [f64; 3])> = group
        .triangles
        .iter()
        .map(|t| {
            let [a, b, c] = t.map(point);
            let normal = (b - a).cross(c - a).try_normalize();
            let angle = |p: DVec3, q: DVec3, r: DVec3| (q - p).angle_between(r - p);
            let angles = [angle(a, b, c), angle(b, c, a), angle(c, a, b)];
            (normal, angles.map(|x| if x.is_finite() { x } else { 0.0 }))
        })
        .collect();
    let mut around: Vec<Vec<(usize, usize)>> = vec![Vec::new(); group.positions.len()];
    for (f, t) in group.triangles.iter().enumerate() {
        for (k, &v) in t.iter().enumerate() {
            around[v as usize].push((f, k));
        }
    }
    let cos_crease = group.crease.clamp(0.0, 180.0).to_radians().cos();
    let corner_normal = |f: usize, v: u32| {
        let own = faces[f].0;
        let sum: DVec3 = around[v as usize]
            .iter()
            .filter_map(|&(g, k)| {
                let n = faces[g].0?;
                let kept = own.is_none_or(|own| g == f || own.dot(n) >= cos_crease);
                kept.then_some(n * faces[g].1[k])
            })
            .sum();
        let n = sum.try_normalize().or(own).unwrap_or(DVec3::Z);
        n.as_vec3().to_array()
    };
    let mut shaded = Shaded {
        positions: Vec::new(),
        normals: Vec::new(),
        triangles: Vec::with_capacity(group.triangles.len()),
        uv: Vec::new(),
    };
    let textured = group.uv.len() == group.positions.len() && !group.uv.is_empty();
    let mut index: HashMap<(u32, [u32; 3]), u32> = HashMap::new();
    for (f, t) in group.triangles.iter().enumerate() {
        let triangle = t.map(|v| {
            let n = corner_normal(f, v);
            *index.entry((v, n.map(f32::to_bits))).or_insert_with(|| {
                shaded.positions.push(group.positions[v as usize]);
                shaded.normals.push(n);
                if textured {
                    shaded.uv.push(group.uv[v as usize]);
                }
                (shaded.positions.len() - 1) as u32
            })
        });
        shaded.triangles.push(triangle);
    }
    shaded
}

/// The distinct images of the textured groups of an export, each with the name it has beside
/// an OBJ (`STEM-checker-N.png` for a checker, `STEM-NAME` for a copied file) and its bytes,
/// and for each group the index of its image. An image file that cannot be read is an error.
struct Images {
    /// (file name, bytes) of each distinct image.
    files: Vec<(String, Vec<u8>)>,
    /// Each group's image, by index into `files`.
    of_group: Vec<Option<usize>>,
}

impl Images {
    fn gather(groups: &[MeshGroup], path: &Path) -> std::io::Result<Images> {
        let stem = path
            .file_stem()
            .map_or_else(|| "room".into(), |s| identifier(&s.to_string_lossy()));
        let mut seen: Vec<&TextureImage> = Vec::new();
        let mut files = Vec::new();
        let mut of_group = Vec::with_capacity(groups.len());
        for g in groups {
            let Some(image) = g.texture.as_ref().filter(|_| !g.uv.is_empty()) else {
                of_group.push(None);
                continue;
            };
            if let Some(k) = seen.iter().position(|i| *i == image) {
                of_group.push(Some(k));
                continue;
            }
            let file = match image {
                TextureImage::File(file) => {
                    let own = file
                        .file_name()
                        .map_or_else(|| "texture".into(), |n| n.to_string_lossy().into_owned());
                    let bytes = crate::files::read(file).map_err(|e| {
                        std::io::Error::new(
                            e.kind(),
                            format!("cannot read the texture {}: {e}", file.display()),
                        )
                    })?;
                    (identifier(&format!("{stem}-{own}")), bytes.into_vec())
                }
                TextureImage::Checker(_) => {
                    let bytes = image
                        .checker_png()
                        .ok_or_else(|| std::io::Error::other("cannot encode a checker image"))?;
                    (format!("{stem}-checker-{}.png", files.len()), bytes)
                }
            };
            of_group.push(Some(files.len()));
            files.push(file);
            seen.push(image);
        }
        Ok(Images { files, of_group })
    }

    /// Each group's image file name, for the MTL.
    fn names(&self) -> Vec<Option<String>> {
        self.of_group
            .iter()
            .map(|k| k.map(|k| self.files[k].0.clone()))
            .collect()
    }
}
