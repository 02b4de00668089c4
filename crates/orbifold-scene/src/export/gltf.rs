//! The binary glTF (GLB) writer.
//!
//! The format is the Khronos glTF 2.0 specification
//! (<https://registry.khronos.org/glTF/specs/2.0/glTF-2.0.html>), in its binary container: a
//! JSON chunk describing the scene and one binary chunk holding the vertices, indices and
//! embedded images, so the room travels as a single file. glTF is Y up, so a room point
//! (x, y, height h) is stored as (x, h, −y); each group is a mesh and a node of its name, with a
//! metallic-roughness material.

use serde_json::json;

use super::smooth_normals;
use crate::geometry::MeshGroup;

// The OpenGL enumerants that glTF uses for buffer-view targets, accessor component types,
// primitive modes and sampler wrapping.
/// A buffer view of vertex attributes.
const ARRAY_BUFFER: u32 = 34962;
/// A buffer view of vertex indices.
const ELEMENT_ARRAY_BUFFER: u32 = 34963;
/// 32-bit float components.
const FLOAT: u32 = 5126;
/// 32-bit unsigned integer components.
const UNSIGNED_INT: u32 = 5125;
/// A primitive of separate triangles.
const TRIANGLES: u32 = 4;
/// A texture that repeats.
const REPEAT: u32 = 10497;

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
        views.push(json!({"buffer": 0, "byteOffset": bin.len(), "byteLength": positions.len() * 12, "target": ARRAY_BUFFER}));
        for p in &positions {
            for c in p {
                bin.extend_from_slice(&c.to_le_bytes());
            }
        }
        let normal_view = views.len();
        views.push(json!({"buffer": 0, "byteOffset": bin.len(), "byteLength": positions.len() * 12, "target": ARRAY_BUFFER}));
        for n in &shaded.normals {
            for c in [n[0], n[2], -n[1]] {
                bin.extend_from_slice(&c.to_le_bytes());
            }
        }
        let index_view = views.len();
        views.push(json!({"buffer": 0, "byteOffset": bin.len(), "byteLength": shaded.triangles.len() * 12, "target": ELEMENT_ARRAY_BUFFER}));
        for t in &shaded.triangles {
            for v in t {
                bin.extend_from_slice(&v.to_le_bytes());
            }
        }
        let position_accessor = accessors.len();
        accessors.push(json!({"bufferView": position_view, "componentType": FLOAT, "count": positions.len(), "type": "VEC3", "min": lo, "max": hi}));
        accessors.push(json!({"bufferView": normal_view, "componentType": FLOAT, "count": positions.len(), "type": "VEC3"}));
        accessors.push(json!({"bufferView": index_view, "componentType": UNSIGNED_INT, "count": shaded.triangles.len() * 3, "type": "SCALAR"}));
        let mut attributes =
            json!({"POSITION": position_accessor, "NORMAL": position_accessor + 1});
        let image = images.get(index).copied().flatten();
        let mut pbr = match image {
            Some(bytes) if !shaded.uv.is_empty() && !g.mirror => {
                let uv_view = views.len();
                views.push(json!({"buffer": 0, "byteOffset": bin.len(), "byteLength": shaded.uv.len() * 8, "target": ARRAY_BUFFER}));
                for t in &shaded.uv {
                    for c in [t[0] as f32, (1.0 - t[1]) as f32] {
                        bin.extend_from_slice(&c.to_le_bytes());
                    }
                }
                attributes["TEXCOORD_0"] = json!(accessors.len());
                accessors.push(json!({"bufferView": uv_view, "componentType": FLOAT, "count": shaded.uv.len(), "type": "VEC2"}));
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
                let [red, green, blue] = g.color;
                json!({"baseColorFactor": [red, green, blue, 1.0]})
            }
        };
        let (metallic, roughness) = if g.mirror { (1.0, 0.02) } else { (0.0, 0.8) };
        pbr["metallicFactor"] = json!(metallic);
        pbr["roughnessFactor"] = json!(roughness);
        materials.push(json!({"name": g.name, "doubleSided": true, "pbrMetallicRoughness": pbr}));
        meshes.push(json!({"name": g.name, "primitives": [{
            "attributes": attributes,
            "indices": position_accessor + 2,
            "material": materials.len() - 1, "mode": TRIANGLES}]}));
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
        document["samplers"] = json!([{"wrapS": REPEAT, "wrapT": REPEAT}]);
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

/// The MIME type of an image's bytes, as glTF names it (PNG or JPEG, what scenes may hold).
fn mime_type(bytes: &[u8]) -> &'static str {
    if bytes.starts_with(&[0xFF, 0xD8]) {
        "image/jpeg"
    } else {
        "image/png"
    }
}
