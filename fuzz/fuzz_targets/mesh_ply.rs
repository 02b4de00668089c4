//! PLY mesh import: `parse_mesh(data, MeshFormat::Ply, None)` never panics, and a mesh it
//! returns has triangles, in-range indices and finite coordinates.

#![no_main]

mod common;

use libfuzzer_sys::fuzz_target;
use orbifold_scene::mesh::import::MeshFormat;

fuzz_target!(|data: &[u8]| common::check(data, MeshFormat::Ply));
