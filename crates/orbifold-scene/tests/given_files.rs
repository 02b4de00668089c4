//! Files a scene names, given by their bytes (`orbifold_scene::files`): a scene that names a
//! mesh and a texture nobody wrote to a disk opens, meshes its object and exports its texture;
//! a file that was not given is still an error that names its path.
//!
//! Each test uses paths of its own: the store is shared by the whole test process.

use std::path::Path;

use orbifold_scene::export::{ExportFormat, export};
use orbifold_scene::files;
use orbifold_scene::{Material, Scene};

/// A tetrahedron, as OBJ.
const TETRAHEDRON: &[u8] =
    b"v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n";

/// A 2×2 PNG, all red.
fn red_png() -> Vec<u8> {
    let image = image::RgbImage::from_pixel(2, 2, image::Rgb([255, 0, 0]));
    let mut bytes = Vec::new();
    image
        .write_to(
            &mut std::io::Cursor::new(&mut bytes),
            image::ImageFormat::Png,
        )
        .unwrap();
    bytes
}

/// The default scene with its object made from `mesh` and its floor showing `texture`, as
/// the TOML a browser would hand over.
fn scene_text(mesh: &str, texture: &str) -> String {
    let mut scene = Scene::default();
    scene.objects[0].mesh = Some(mesh.into());
    scene.room.floor = Material::Texture {
        path: texture.into(),
        scale: 0.5,
        coordinates: Default::default(),
    };
    scene.to_toml()
}

#[test]
fn a_scene_opens_with_a_mesh_and_a_texture_given_by_bytes() {
    files::provide("given-a/tetrahedron.obj", TETRAHEDRON.to_vec());
    files::provide("given-a/red.png", red_png());
    // A scene opened in a browser: a name without a folder on the disk.
    let origin = Path::new("given-a/room.toml");
    let text = scene_text("tetrahedron.obj", "red.png");
    let scene = Scene::from_toml(&text, Some(origin)).expect("the named files are given");
    let base = origin.parent();
    let mesh = scene.object_mesh(0, base).unwrap();
    assert_eq!((mesh.positions.len(), mesh.triangles.len()), (4, 4));
    let geometry = scene.geometry(base).unwrap();
    let object = geometry.parts.last().unwrap();
    assert_eq!(object.name, "object 0");
    // An OBJ export copies the texture beside it: the given bytes, unchanged.
    let dir = tempfile::tempdir().unwrap();
    let (groups, _) = geometry.groups(&[]);
    let written = export(
        &groups,
        ExportFormat::Obj,
        &dir.path().join("room.obj"),
        "t",
    )
    .unwrap();
    let copy = written
        .iter()
        .find(|p| p.extension().is_some_and(|e| e == "png"))
        .expect("the texture is written beside the export");
    assert_eq!(std::fs::read(copy).unwrap(), red_png());
}

#[test]
fn a_file_not_given_is_an_error_with_its_path_as_before() {
    files::provide("given-b/tetrahedron.obj", TETRAHEDRON.to_vec());
    let origin = Path::new("given-b/room.toml");
    let errors = Scene::from_toml(&scene_text("missing.obj", "missing.png"), Some(origin))
        .expect_err("neither file is there");
    let messages: Vec<String> = errors.iter().map(ToString::to_string).collect();
    let text = messages.join("\n");
    assert!(
        text.contains("the file given-b/missing.obj does not exist"),
        "{text}"
    );
    assert!(
        text.contains("the file given-b/missing.png does not exist"),
        "{text}"
    );
    // Read directly: the mesh reader's error, naming the file, as for a file on a disk.
    let mut scene = Scene::default();
    scene.objects[0].mesh = Some("missing.obj".into());
    let error = scene.object_mesh(0, origin.parent()).unwrap_err();
    assert!(
        error.starts_with("given-b/missing.obj: cannot read the file:"),
        "{error}"
    );
    // The given mesh, once forgotten, is missing too.
    assert!(files::forget(Path::new("given-b/tetrahedron.obj")));
    scene.objects[0].mesh = Some("tetrahedron.obj".into());
    assert!(scene.object_mesh(0, origin.parent()).is_err());
}

#[test]
fn a_gltf_file_finds_its_external_buffer_among_the_given_files() {
    // One triangle: three f32 positions and three u16 indices (padded to 4 bytes).
    let mut buffer = Vec::new();
    for p in [[0.0f32, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]] {
        for c in p {
            buffer.extend_from_slice(&c.to_le_bytes());
        }
    }
    for i in [0u16, 1, 2, 0] {
        buffer.extend_from_slice(&i.to_le_bytes());
    }
    let gltf = r#"{
  "asset": {"version": "2.0"},
  "buffers": [{"uri": "triangle.bin", "byteLength": 44}],
  "bufferViews": [
    {"buffer": 0, "byteOffset": 0, "byteLength": 36},
    {"buffer": 0, "byteOffset": 36, "byteLength": 6}
  ],
  "accessors": [
    {"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3",
     "min": [0, 0, 0], "max": [1, 1, 0]},
    {"bufferView": 1, "componentType": 5123, "count": 3, "type": "SCALAR"}
  ],
  "meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "indices": 1}]}],
  "nodes": [{"mesh": 0}],
  "scenes": [{"nodes": [0]}],
  "scene": 0
}"#;
    files::provide("given-c/triangle.gltf", gltf.as_bytes().to_vec());
    let path = Path::new("given-c/triangle.gltf");
    let error = orbifold_scene::mesh::import::load_mesh(path).unwrap_err();
    assert!(
        error.to_string().contains("given-c/triangle.bin"),
        "{error}"
    );
    files::provide("given-c/triangle.bin", buffer);
    let mesh = orbifold_scene::mesh::import::load_mesh(path).unwrap();
    assert_eq!(mesh.triangles.len(), 1);
}

#[test]
fn a_recovered_scene_comes_back_with_the_files_that_are_missing() {
    files::provide("given-d/tetrahedron.obj", TETRAHEDRON.to_vec());
    let origin = Path::new("given-d/room.toml");
    let text = scene_text("tetrahedron.obj", "gone.png");
    let (scene, missing) = Scene::from_toml_missing_files(&text, Some(origin)).unwrap();
    assert_eq!(scene.objects[0].mesh.as_deref(), Some("tetrahedron.obj"));
    assert_eq!(missing, [Path::new("given-d/gone.png")]);
    assert_eq!(scene.named_files(), ["gone.png", "tetrahedron.obj"]);
    // Other problems are still errors.
    let bad = text.replace("height = 1", "height = -1");
    assert_ne!(bad, text);
    assert!(Scene::from_toml_missing_files(&bad, Some(origin)).is_err());
}
