//! The Wavefront OBJ writer, with its MTL material library.
//!
//! The formats are Wavefront's "Object Files (.obj)" and "Material Library File (.mtl)",
//! appendices B1 and B2 of the Advanced Visualizer manual (mirrored at
//! <https://paulbourke.net/dataformats/obj/> and <https://paulbourke.net/dataformats/mtl/>).
//! Each group of the room is an `o` object with a material of its name, so that a modelling
//! tool shows the walls, mirrors, floor, ceiling and objects as separate, named parts. The text
//! has positions, vertex normals (`vn`, so viewers shade it smooth) and texture coordinates
//! (`vt`) where a group has an image.

use std::fmt::Write as _;

use super::{COORDINATES_NOTE, identifier, smooth_normals};
use crate::geometry::MeshGroup;

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
        let [red, green, blue] = g.color;
        let _ = writeln!(out, "newmtl {}", identifier(&g.name));
        if g.mirror {
            let _ = writeln!(out, "Kd 0 0 0\nKs {red} {green} {blue}\nNs 1000\nillum 3\n");
        } else if let Some(Some(image)) = images.get(i) {
            let _ = writeln!(out, "Kd 1 1 1\nKs 0 0 0\nillum 1\nmap_Kd {image}\n");
        } else {
            let _ = writeln!(out, "Kd {red} {green} {blue}\nKs 0 0 0\nillum 1\n");
        }
    }
    out
}
