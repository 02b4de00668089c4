//! The binary PLY writer.
//!
//! The format is Greg Turk's "The PLY Polygon File Format" (mirrored at
//! <https://paulbourke.net/dataformats/ply/>), written binary little-endian. PLY has no
//! objects or materials, so each face carries the index of its group (a `group` property) and
//! the header's comments name the groups; each vertex carries its group's colour. For images
//! it follows two conventions that readers know: MeshLab's `comment TextureFile NAME` lines,
//! which a face's `texnumber` counts, and per-vertex `s` and `t`, which PLY readers such as
//! Mitsuba 3's take as texture coordinates.

use std::fmt::Write as _;

use super::{COORDINATES_NOTE, Shaded, smooth_normals};
use crate::geometry::MeshGroup;

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
    // The most bytes a vertex (position, normal, colour, texture coordinates) and a face
    // (count, three indices, group, texnumber) take.
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
