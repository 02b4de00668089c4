//! The checks shared by the mesh targets.

use orbifold_scene::mesh::import::{MeshFormat, parse_mesh};

/// Reads `data` as `format`: it must not panic, and a mesh it returns has at least one
/// triangle, every index within the vertices and every coordinate finite.
pub fn check(data: &[u8], format: MeshFormat) {
    match parse_mesh(data, format, None) {
        Ok(mesh) => {
            let n = mesh.positions.len();
            assert!(
                !mesh.triangles.is_empty(),
                "{format}: a mesh without triangles"
            );
            for (t, triangle) in mesh.triangles.iter().enumerate() {
                for &i in triangle {
                    assert!(
                        (i as usize) < n,
                        "{format}: triangle {t} has index {i} of {n}"
                    );
                }
            }
            for (v, p) in mesh.positions.iter().enumerate() {
                assert!(
                    p.iter().all(|c| c.is_finite()),
                    "{format}: vertex {v} is not finite: {p:?}"
                );
            }
            let _ = (mesh.bounds(), mesh.signed_volume(), mesh.centre_of_mass());
        }
        Err(e) => {
            let _ = e.to_string();
        }
    }
}
