//! glTF and GLB mesh import: `parse_mesh` never panics, and a mesh it returns has triangles,
//! in-range indices and finite coordinates. Inputs that begin with the GLB magic `glTF` are
//! read as `MeshFormat::Glb`, the others as `MeshFormat::Gltf` (JSON); both go through the same
//! reader, which looks at the magic itself. No base directory is given, so buffers in external
//! files are refused rather than read.

#![no_main]

mod common;

use libfuzzer_sys::fuzz_target;
use orbifold_scene::mesh::import::MeshFormat;

fuzz_target!(|data: &[u8]| {
    let format = if data.starts_with(b"glTF") {
        MeshFormat::Glb
    } else {
        MeshFormat::Gltf
    };
    common::check(data, format);
});
