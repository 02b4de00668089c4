//! Mesh export: Wavefront OBJ (with an MTL file of named materials), binary PLY and glTF binary
//! (GLB), one named group per part of the room, with smooth vertex normals
//! ([`smooth_normals`]).
//!
//! Coordinates are the model's x and y, times [`EXPORT_SCALE`] (the model's metric at its centre,
//! so that a Euclidean room has its true size and shape), and the height above the floor, in that
//! order, for OBJ and PLY (Z up: in Blender choose "Up: Z" when importing OBJ). glTF is Y up by specification,
//! so there a vertex (x, y, h) is written as (x, h, −y); every importer then shows the room
//! upright. The files say so in their headers (a comment in OBJ and PLY, `asset.extras` in glTF).

use std::collections::HashMap;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use glam::DVec3;

use serde_json::json;

use crate::file::write_atomic;
#[cfg(doc)]
use crate::geometry::EXPORT_SCALE;
use crate::geometry::MeshGroup;
use crate::texture::TextureImage;

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

/// The OBJ text: one `o` object with its `usemtl` per group, positions, vertex normals and, for
/// a textured group, texture coordinates (`vt`).
pub fn to_obj(groups: &[MeshGroup], mtl_name: &str, title: &str) -> String {
    let mut out = String::new();
    let _ = writeln!(out, "# {title}\n# {COORDINATES_NOTE}\nmtllib {mtl_name}");
    let (mut base, mut uv_base) = (1, 1);
    for g in groups {
        if g.triangles.is_empty() {
            continue;
        }
        let shaded = smooth_normals(g);
        let id = identifier(&g.name);
        let _ = writeln!(out, "o {id}\nusemtl {id}");
        for p in &shaded.positions {
            let _ = writeln!(out, "v {} {} {}", p[0] as f32, p[1] as f32, p[2] as f32);
        }
        for n in &shaded.normals {
            let _ = writeln!(out, "vn {} {} {}", n[0], n[1], n[2]);
        }
        for t in &shaded.uv {
            let _ = writeln!(out, "vt {} {}", t[0] as f32, t[1] as f32);
        }
        let textured = !shaded.uv.is_empty();
        for t in &shaded.triangles {
            let [a, b, c] = t.map(|v| v + base);
            if textured {
                let [ta, tb, tc] = t.map(|v| v + uv_base);
                let _ = writeln!(out, "f {a}/{ta}/{a} {b}/{tb}/{b} {c}/{tc}/{c}");
            } else {
                let _ = writeln!(out, "f {a}//{a} {b}//{b} {c}//{c}");
            }
        }
        base += shaded.positions.len() as u32;
        uv_base += shaded.uv.len() as u32;
    }
    out
}

/// The MTL text: a diffuse colour per group; mirrors get a specular colour and `illum 3`
/// (reflection) as well. A textured group gets `map_Kd` with its image's file name from
/// `images` (by the group's index; none there: its colour alone) and a white `Kd`, which
/// viewers multiply the image by.
pub fn to_mtl(groups: &[MeshGroup], images: &[Option<String>]) -> String {
    let mut out = String::from("# orbifold room materials\n");
    for (i, g) in groups.iter().enumerate() {
        let [r, gr, b] = g.color;
        let _ = writeln!(out, "newmtl {}", identifier(&g.name));
        if g.mirror {
            let _ = writeln!(out, "Kd 0 0 0\nKs {r} {gr} {b}\nNs 1000\nillum 3\n");
        } else if let Some(Some(image)) = images.get(i) {
            let _ = writeln!(out, "Kd 1 1 1\nKs 0 0 0\nillum 1\nmap_Kd {image}\n");
        } else {
            let _ = writeln!(out, "Kd {r} {gr} {b}\nKs 0 0 0\nillum 1\n");
        }
    }
    out
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
                    let bytes = std::fs::read(file).map_err(|e| {
                        std::io::Error::new(
                            e.kind(),
                            format!("cannot read the texture {}: {e}", file.display()),
                        )
                    })?;
                    (identifier(&format!("{stem}-{own}")), bytes)
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

/// The MIME type of an image's bytes, as glTF names it (PNG or JPEG, what scenes may hold).
fn mime_type(bytes: &[u8]) -> &'static str {
    if bytes.starts_with(&[0xFF, 0xD8]) {
        "image/jpeg"
    } else {
        "image/png"
    }
}

/// Binary little-endian PLY: vertices with a normal and a colour, faces with a `group` index;
/// the header's comments name the groups (`comment group 3 wall 0`). No texture coordinates:
/// see [`to_ply_textured`].
pub fn to_ply(groups: &[MeshGroup], title: &str) -> Vec<u8> {
    to_ply_textured(groups, title, &[], &[])
}

/// [`to_ply`] with the textured groups' images: `images` are the images' file names, and
/// `of_group` holds each group's index into them (none there: its colour alone). With any
/// image, the vertices get texture coordinates `s` and `t` (as OBJ's `vt`; 0 on untextured
/// groups), which PLY readers such as Mitsuba 3's take as the mesh's UVs, and the header names
/// the images in order (`comment TextureFile NAME`, MeshLab's convention) that each face's
/// `texnumber` counts (−1 for none).
pub fn to_ply_textured(
    groups: &[MeshGroup],
    title: &str,
    images: &[&str],
    of_group: &[Option<usize>],
) -> Vec<u8> {
    let shaded: Vec<Shaded> = groups.iter().map(smooth_normals).collect();
    let image_of = |i: usize| {
        of_group
            .get(i)
            .copied()
            .flatten()
            .filter(|&k| k < images.len() && !shaded[i].uv.is_empty())
    };
    let textured = (0..groups.len()).any(|i| image_of(i).is_some());
    let vertices: usize = shaded.iter().map(|g| g.positions.len()).sum();
    let faces: usize = groups.iter().map(|g| g.triangles.len()).sum();
    let mut header = format!(
        "ply\nformat binary_little_endian 1.0\ncomment {title}\ncomment {COORDINATES_NOTE}\n"
    );
    for (i, g) in groups.iter().enumerate() {
        let _ = writeln!(header, "comment group {i} {}", g.name);
    }
    if textured {
        for image in images {
            let _ = writeln!(header, "comment TextureFile {image}");
        }
    }
    let _ = write!(
        header,
        "element vertex {vertices}\nproperty float x\nproperty float y\nproperty float z\n\
         property float nx\nproperty float ny\nproperty float nz\n\
         property uchar red\nproperty uchar green\nproperty uchar blue\n"
    );
    if textured {
        header.push_str("property float s\nproperty float t\n");
    }
    let _ = write!(
        header,
        "element face {faces}\nproperty list uchar int vertex_indices\nproperty int group\n"
    );
    if textured {
        header.push_str("property int texnumber\n");
    }
    header.push_str("end_header\n");
    let mut out = header.into_bytes();
    out.reserve(vertices * 35 + faces * 21);
    for (i, (g, s)) in groups.iter().zip(&shaded).enumerate() {
        let rgb = g.color.map(|c| (c.clamp(0.0, 1.0) * 255.0).round() as u8);
        let uv = |v: usize| match image_of(i) {
            Some(_) => s.uv[v].map(|c| c as f32),
            None => [0.0; 2],
        };
        for (v, (p, n)) in s.positions.iter().zip(&s.normals).enumerate() {
            for c in p {
                out.extend_from_slice(&(*c as f32).to_le_bytes());
            }
            for c in n {
                out.extend_from_slice(&c.to_le_bytes());
            }
            out.extend_from_slice(&rgb);
            if textured {
                for c in uv(v) {
                    out.extend_from_slice(&c.to_le_bytes());
                }
            }
        }
    }
    let mut base = 0u32;
    for (i, g) in shaded.iter().enumerate() {
        let texnumber = image_of(i).map_or(-1, |k| k as i32);
        for t in &g.triangles {
            out.push(3);
            for v in t {
                out.extend_from_slice(&((v + base) as i32).to_le_bytes());
            }
            out.extend_from_slice(&(i as i32).to_le_bytes());
            if textured {
                out.extend_from_slice(&texnumber.to_le_bytes());
            }
        }
        base += g.positions.len() as u32;
    }
    out
}

/// glTF 2.0 binary: one mesh and one node per group, named as the group, with a PBR material
/// (mirrors metallic and smooth).
pub fn to_glb(groups: &[MeshGroup], title: &str) -> Vec<u8> {
    to_glb_textured(groups, title, &[])
}

/// [`to_glb`] with the textured groups' images embedded: `images` holds each group's PNG or
/// JPEG bytes (by the group's index; none there: its colour alone). A group with an image gets
/// `TEXCOORD_0` (glTF's v runs down the image: 1 − v) and a base-colour texture that repeats.
pub fn to_glb_textured(groups: &[MeshGroup], title: &str, images: &[Option<&[u8]>]) -> Vec<u8> {
    let mut bin: Vec<u8> = Vec::new();
    let (mut views, mut accessors, mut meshes, mut nodes, mut materials) =
        (vec![], vec![], vec![], vec![], vec![]);
    // Embedded images, once each: the same bytes share an image and a texture.
    let mut embedded: Vec<&[u8]> = Vec::new();
    let mut image_json = Vec::new();
    for (index, g) in groups.iter().enumerate() {
        if g.triangles.is_empty() {
            continue;
        }
        let shaded = smooth_normals(g);
        // glTF is Y up: (x, y, h) ↦ (x, h, −y), a rotation, keeps handedness and puts the
        // floor down; the normals turn with it.
        let positions: Vec<[f32; 3]> = shaded
            .positions
            .iter()
            .map(|p| [p[0] as f32, p[2] as f32, -p[1] as f32])
            .collect();
        let (mut lo, mut hi) = ([f32::INFINITY; 3], [f32::NEG_INFINITY; 3]);
        for p in &positions {
            for k in 0..3 {
                lo[k] = lo[k].min(p[k]);
                hi[k] = hi[k].max(p[k]);
            }
        }
        let position_view = views.len();
        views.push(json!({"buffer": 0, "byteOffset": bin.len(), "byteLength": positions.len() * 12, "target": 34962}));
        for p in &positions {
            for c in p {
                bin.extend_from_slice(&c.to_le_bytes());
            }
        }
        let normal_view = views.len();
        views.push(json!({"buffer": 0, "byteOffset": bin.len(), "byteLength": positions.len() * 12, "target": 34962}));
        for n in &shaded.normals {
            for c in [n[0], n[2], -n[1]] {
                bin.extend_from_slice(&c.to_le_bytes());
            }
        }
        let index_view = views.len();
        views.push(json!({"buffer": 0, "byteOffset": bin.len(), "byteLength": shaded.triangles.len() * 12, "target": 34963}));
        for t in &shaded.triangles {
            for v in t {
                bin.extend_from_slice(&v.to_le_bytes());
            }
        }
        let position_accessor = accessors.len();
        accessors.push(json!({"bufferView": position_view, "componentType": 5126, "count": positions.len(), "type": "VEC3", "min": lo, "max": hi}));
        accessors.push(json!({"bufferView": normal_view, "componentType": 5126, "count": positions.len(), "type": "VEC3"}));
        accessors.push(json!({"bufferView": index_view, "componentType": 5125, "count": shaded.triangles.len() * 3, "type": "SCALAR"}));
        let mut attributes =
            json!({"POSITION": position_accessor, "NORMAL": position_accessor + 1});
        let image = images.get(index).copied().flatten();
        let mut pbr = match image {
            Some(bytes) if !shaded.uv.is_empty() && !g.mirror => {
                let uv_view = views.len();
                views.push(json!({"buffer": 0, "byteOffset": bin.len(), "byteLength": shaded.uv.len() * 8, "target": 34962}));
                for t in &shaded.uv {
                    for c in [t[0] as f32, (1.0 - t[1]) as f32] {
                        bin.extend_from_slice(&c.to_le_bytes());
                    }
                }
                attributes["TEXCOORD_0"] = json!(accessors.len());
                accessors.push(json!({"bufferView": uv_view, "componentType": 5126, "count": shaded.uv.len(), "type": "VEC2"}));
                let texture = embedded.iter().position(|e| *e == bytes).unwrap_or_else(|| {
                    views.push(json!({"buffer": 0, "byteOffset": bin.len(), "byteLength": bytes.len()}));
                    bin.extend_from_slice(bytes);
                    // The accessors that follow stay aligned to 4 bytes.
                    bin.resize(bin.len().next_multiple_of(4), 0);
                    image_json.push(json!({"bufferView": views.len() - 1, "mimeType": mime_type(bytes)}));
                    embedded.push(bytes);
                    embedded.len() - 1
                });
                json!({"baseColorFactor": [1.0, 1.0, 1.0, 1.0], "baseColorTexture": {"index": texture}})
            }
            _ => {
                let [r, gr, b] = g.color;
                json!({"baseColorFactor": [r, gr, b, 1.0]})
            }
        };
        let (metallic, roughness) = if g.mirror { (1.0, 0.02) } else { (0.0, 0.8) };
        pbr["metallicFactor"] = json!(metallic);
        pbr["roughnessFactor"] = json!(roughness);
        materials.push(json!({"name": g.name, "doubleSided": true, "pbrMetallicRoughness": pbr}));
        meshes.push(json!({"name": g.name, "primitives": [{
            "attributes": attributes,
            "indices": position_accessor + 2,
            "material": materials.len() - 1, "mode": 4}]}));
        nodes.push(json!({"name": g.name, "mesh": meshes.len() - 1}));
    }
    let mut document = json!({
        "asset": {"version": "2.0", "generator": "orbifold", "extras": {"title": title, "coordinates":
            "glTF is Y up: a room point (x, y, height h), x and y twice the model coordinates, is stored as (x, h, -y)"}},
        "scene": 0,
        "scenes": [{"name": title, "nodes": (0..nodes.len()).collect::<Vec<_>>()}],
        "nodes": nodes, "meshes": meshes, "materials": materials,
        "accessors": accessors, "bufferViews": views,
        "buffers": [{"byteLength": bin.len()}],
    });
    if !image_json.is_empty() {
        let textures: Vec<_> = (0..image_json.len())
            .map(|k| json!({"sampler": 0, "source": k}))
            .collect();
        document["images"] = json!(image_json);
        document["textures"] = json!(textures);
        document["samplers"] = json!([{"wrapS": 10497, "wrapT": 10497}]);
    }
    glb_container(document.to_string().into_bytes(), bin)
}

/// The GLB container: a 12-byte header, the JSON chunk padded with spaces and the BIN chunk
/// padded with zeros to 4 bytes.
fn glb_container(mut json: Vec<u8>, mut bin: Vec<u8>) -> Vec<u8> {
    while !json.len().is_multiple_of(4) {
        json.push(b' ');
    }
    while !bin.len().is_multiple_of(4) {
        bin.push(0);
    }
    let total = 12 + 8 + json.len() + 8 + bin.len();
    let mut out = Vec::with_capacity(total);
    out.extend_from_slice(b"glTF");
    out.extend_from_slice(&2u32.to_le_bytes());
    out.extend_from_slice(&(total as u32).to_le_bytes());
    out.extend_from_slice(&(json.len() as u32).to_le_bytes());
    out.extend_from_slice(b"JSON");
    out.extend_from_slice(&json);
    out.extend_from_slice(&(bin.len() as u32).to_le_bytes());
    out.extend_from_slice(b"BIN\0");
    out.extend_from_slice(&bin);
    out
}
