//! Exported rooms read back by independent parsers (tobj for OBJ, gltf for GLB) with the
//! expected groups; PLY by its header and our importer. Also the room's geometry itself:
//! mirrors split walls, objects are rigid copies of their meshes.

use std::collections::BTreeMap;

use orbifold::cover::{Bound, Cover};
use orbifold_scene::export::{
    ExportFormat, export, identifier, smooth_normals, to_glb, to_obj, to_ply,
};
use orbifold_scene::geometry::{EXPORT_SCALE, MeshGroup, PartKind};
use orbifold_scene::mesh::import::{MeshFormat, parse_mesh};
use orbifold_scene::texture::TextureImage;
use orbifold_scene::{Coordinates, Material, Mirror, Scene, Wall};
use proptest::prelude::*;

/// A fresh folder for a test's files, removed when the test ends (also when it fails).
fn temp_dir(name: &str) -> tempfile::TempDir {
    tempfile::Builder::new()
        .prefix(&format!("orbifold-export-{name}-"))
        .tempdir()
        .unwrap()
}

fn partial_mirror_scene() -> Scene {
    let mut scene = Scene::default();
    scene.orbifold.signature = "*2223".into();
    scene.objects[0].at = {
        let c = scene.layout().unwrap().centre;
        [c.re, c.im]
    };
    scene.lights.clear();
    scene.camera.at = scene.objects[0].at;
    scene.walls = vec![Wall {
        index: 1,
        material: None,
        mirrors: vec![
            Mirror {
                from: 0.1,
                to: 0.4,
                bottom: 0.2,
                top: Some(0.8),
                ..Mirror::default()
            },
            Mirror {
                from: 0.5,
                to: 0.9,
                ..Mirror::default()
            },
        ],
    }];
    scene
}

/// The room of `signature` with nothing in it, the camera at the model's origin.
fn empty_room(signature: &str) -> Scene {
    let mut scene = Scene::default();
    scene.orbifold.signature = signature.into();
    scene.objects.clear();
    scene.lights.clear();
    scene.camera.at = [0.0, 0.0];
    scene
}

fn expected_names(groups: &[MeshGroup]) -> Vec<String> {
    groups
        .iter()
        .filter(|g| !g.triangles.is_empty())
        .map(|g| identifier(&g.name))
        .collect()
}

#[test]
fn parts_are_named_and_mirrors_split_their_walls() {
    let scene = partial_mirror_scene();
    let geometry = scene.geometry(None).unwrap();
    let names: Vec<&str> = geometry.parts.iter().map(|p| p.name.as_str()).collect();
    assert_eq!(
        names,
        [
            "floor",
            "ceiling",
            "mirror 0.0",
            "mirror 1.0",
            "mirror 1.1",
            "wall 1",
            "mirror 2.0",
            "mirror 3.0",
            "object 0"
        ]
    );
    // The two mirrors and the plain part of wall 1 add up to the whole wall.
    let space = geometry.layout.space();
    let area = |kind: PartKind| {
        let s = &geometry
            .parts
            .iter()
            .find(|p| p.kind == kind)
            .unwrap()
            .surface;
        s.triangles
            .iter()
            .map(|t| {
                let [a, b, c] = t.map(|i| (s.points[i as usize], s.heights[i as usize]));
                // On a wall, distance along it and height are flat coordinates.
                let (ab, ac) = (
                    space.ambient_distance(a.0, b.0),
                    space.ambient_distance(a.0, c.0),
                );
                let bc = space.ambient_distance(b.0, c.0);
                let sc = if (ab + bc - ac).abs() < 1e-9 || (ab - ac - bc).abs() < 1e-9 {
                    ac
                } else {
                    -ac
                };
                let sb = ab;
                0.5 * (sb * (c.1 - a.1) - (b.1 - a.1) * sc).abs()
            })
            .sum::<f64>()
    };
    let length = geometry.mesher.wall_length(1).unwrap();
    let first = area(PartKind::Mirror { wall: 1, mirror: 0 });
    let second = area(PartKind::Mirror { wall: 1, mirror: 1 });
    let plain = area(PartKind::Wall(1));
    assert!((first - 0.3 * length * 0.6).abs() < 1e-9, "{first}");
    assert!((second - 0.4 * length * 1.0).abs() < 1e-9);
    assert!((first + second + plain - length).abs() < 1e-9);
}

#[test]
fn obj_reads_back_with_its_groups() {
    let scene = partial_mirror_scene();
    let geometry = scene.geometry(None).unwrap();
    let (groups, omitted) = geometry.groups(&[]);
    assert_eq!(omitted, 0);
    let tmp = temp_dir("obj");
    let dir = tmp.path();
    let path = dir.join("room.obj");
    let written = export(&groups, ExportFormat::Obj, &path, "test").unwrap();
    // The default floor is a checkerboard: its image is written beside the OBJ.
    assert_eq!(
        written,
        [
            path.clone(),
            dir.join("room.mtl"),
            dir.join("room-checker-0.png")
        ]
    );
    let (models, materials) = tobj::load_obj(&path, &tobj::GPU_LOAD_OPTIONS).unwrap();
    let materials = materials.unwrap();
    let names: Vec<String> = models.iter().map(|m| m.name.clone()).collect();
    assert_eq!(names, expected_names(&groups));
    for (model, group) in models
        .iter()
        .zip(groups.iter().filter(|g| !g.triangles.is_empty()))
    {
        assert_eq!(
            model.mesh.indices.len(),
            3 * group.triangles.len(),
            "{}",
            group.name
        );
        // A unit normal per vertex.
        let shaded = smooth_normals(group);
        assert_eq!(model.mesh.positions.len(), 3 * shaded.positions.len());
        assert_eq!(model.mesh.normals.len(), model.mesh.positions.len());
        for n in model.mesh.normals.chunks(3) {
            let length = (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt();
            assert!((length - 1.0).abs() < 1e-4, "{}: {n:?}", group.name);
        }
        let material = &materials[model.mesh.material_id.unwrap()];
        assert_eq!(material.name, identifier(&group.name));
    }
}

#[test]
fn glb_reads_back_with_its_groups() {
    let scene = partial_mirror_scene();
    let (groups, _) = scene.geometry(None).unwrap().groups(&[]);
    let bytes = to_glb(&groups, "test");
    let gltf = gltf::Gltf::from_slice(&bytes).unwrap();
    let blob = gltf.blob.clone().unwrap();
    let document = gltf.document;
    let names: Vec<String> = document
        .nodes()
        .map(|n| n.name().unwrap().to_string())
        .collect();
    let expected: Vec<String> = groups
        .iter()
        .filter(|g| !g.triangles.is_empty())
        .map(|g| g.name.clone())
        .collect();
    assert_eq!(names, expected);
    for (mesh, group) in document
        .meshes()
        .zip(groups.iter().filter(|g| !g.triangles.is_empty()))
    {
        let primitive = mesh.primitives().next().unwrap();
        let reader = primitive.reader(|b| (b.index() == 0).then_some(blob.as_slice()));
        let positions: Vec<[f32; 3]> = reader.read_positions().unwrap().collect();
        let normals: Vec<[f32; 3]> = reader.read_normals().unwrap().collect();
        let shaded = smooth_normals(group);
        assert_eq!(positions.len(), shaded.positions.len());
        assert_eq!(normals.len(), shaded.normals.len());
        // glTF is Y up: (x, y, h) is stored as (x, h, −y), and so are the normals.
        for (p, q) in positions.iter().zip(&shaded.positions) {
            assert!(
                (p[0] as f64 - q[0]).abs() < 1e-6
                    && (p[1] as f64 - q[2]).abs() < 1e-6
                    && (p[2] as f64 + q[1]).abs() < 1e-6
            );
        }
        for (n, m) in normals.iter().zip(&shaded.normals) {
            assert_eq!(*n, [m[0], m[2], -m[1]]);
        }
        let indices = reader.read_indices().unwrap().into_u32().count();
        assert_eq!(indices, 3 * group.triangles.len());
        let mirror = primitive
            .material()
            .pbr_metallic_roughness()
            .metallic_factor()
            == 1.0;
        assert_eq!(mirror, group.mirror);
    }
}

#[test]
fn ply_names_its_groups_and_reads_back() {
    let scene = partial_mirror_scene();
    let (groups, _) = scene.geometry(None).unwrap().groups(&[]);
    let bytes = to_ply(&groups, "test");
    let text = String::from_utf8_lossy(&bytes[..2000]);
    for (i, g) in groups.iter().enumerate() {
        assert!(text.contains(&format!("comment group {i} {}\n", g.name)));
    }
    let mesh = parse_mesh(&bytes, MeshFormat::Ply, None).unwrap();
    let triangles: usize = groups.iter().map(|g| g.triangles.len()).sum();
    assert_eq!(mesh.triangles.len(), triangles);
    assert_eq!(
        mesh.positions.len(),
        groups
            .iter()
            .map(|g| smooth_normals(g).positions.len())
            .sum::<usize>()
    );
}

#[test]
fn cover_copies_are_whole_rooms() {
    let geometry = empty_room("*333").geometry(None).unwrap();
    let cover = Cover::enumerate_layout(geometry.layout.clone(), Bound::Depth(3), true).unwrap();
    let (groups, omitted) = geometry.groups(&cover.tiles);
    assert_eq!(omitted, 0);
    let copies = cover.tiles.iter().filter(|t| t.depth > 0).count();
    let by_name: BTreeMap<&str, &MeshGroup> = groups.iter().map(|g| (g.name.as_str(), g)).collect();
    assert_eq!(
        by_name["floor copies"].triangles.len(),
        copies * by_name["floor"].triangles.len()
    );
    // Every copy of the floor keeps facing up: in the Euclidean model, counter-clockwise.
    let floor = by_name["floor copies"];
    for t in &floor.triangles {
        let [a, b, c] = t.map(|i| floor.positions[i as usize]);
        let cross = (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
        assert!(cross > 0.0);
    }
    let obj = to_obj(&groups, "room.mtl", "t");
    assert!(obj.contains("o floor_copies\n"));
}

#[test]
fn the_room_exports_the_normals_of_its_surfaces() {
    // The floor faces up, the ceiling down, the walls are vertical: in every geometry.
    for signature in ["*235", "*2222", "*2223"] {
        let mut scene = partial_mirror_scene();
        scene.orbifold.signature = signature.into();
        scene.walls.clear();
        scene.camera.at = [0.0, 0.0];
        let (groups, _) = scene.geometry(None).unwrap().groups(&[]);
        for g in &groups {
            let shaded = smooth_normals(g);
            for n in &shaded.normals {
                let ok = match g.name.as_str() {
                    "floor" => *n == [0.0, 0.0, 1.0],
                    "ceiling" => *n == [0.0, 0.0, -1.0],
                    name if name.starts_with("wall") || name.starts_with("mirror") => {
                        n[2].abs() < 1e-6
                    }
                    _ => true,
                };
                assert!(ok, "{signature}, {}: {n:?}", g.name);
            }
        }
    }
}

/// A triangle soup over a 3×3×2 grid of points (so that faces share vertices and fold).
fn soup() -> impl Strategy<Value = MeshGroup> {
    let corner = 0u32..18;
    (
        proptest::collection::vec([corner.clone(), corner.clone(), corner], 1..24),
        0.0f64..180.0,
        -0.3f64..0.3,
    )
        .prop_map(|(triangles, crease, bend)| MeshGroup {
            name: "soup".into(),
            color: [1.0; 3],
            mirror: false,
            crease,
            positions: (0..18)
                .map(|i| {
                    let (x, y, z) = (f64::from(i % 3), f64::from(i / 3 % 3), f64::from(i / 9));
                    [x, y + bend * x * x, z]
                })
                .collect(),
            triangles,
            uv: Vec::new(),
            texture: None,
        })
}

proptest! {
    #[test]
    fn smooth_normals_keep_the_faces_and_bend_within_the_crease(group in soup()) {
        let shaded = smooth_normals(&group);
        prop_assert_eq!(shaded.triangles.len(), group.triangles.len());
        prop_assert_eq!(shaded.normals.len(), shaded.positions.len());
        let cos_crease = group.crease.to_radians().cos();
        for (t, s) in group.triangles.iter().zip(&shaded.triangles) {
            let [a, b, c] = t.map(|v| glam::DVec3::from_array(group.positions[v as usize]));
            // The same triangle, corner by corner.
            for k in 0..3 {
                prop_assert_eq!(shaded.positions[s[k] as usize], group.positions[t[k] as usize]);
            }
            let face = (b - a).cross(c - a).try_normalize();
            for &v in s {
                let n = glam::DVec3::from_array(shaded.normals[v as usize].map(f64::from));
                prop_assert!((n.length() - 1.0).abs() < 1e-5, "{n}");
                // A mean of normals within the crease of the face is within it too (a cone no
                // wider than a half-space is convex).
                if let Some(face) = face.filter(|_| group.crease <= 90.0) {
                    prop_assert!(n.dot(face) >= cos_crease.min(1.0) - 1e-5, "{n} {face}");
                }
            }
        }
        // Every vertex is written once per distinct normal.
        let mut seen = std::collections::HashSet::new();
        for (p, n) in shaded.positions.iter().zip(&shaded.normals) {
            prop_assert!(seen.insert((p.map(f64::to_bits), n.map(f32::to_bits))));
        }
    }
}

/// Exports keep proportions: horizontal coordinates are scaled by the model's metric at its
/// centre (`EXPORT_SCALE`), so a sphere at the centre comes out round, and a Euclidean room's
/// walls are as long in the file as they are intrinsically.
#[test]
fn exports_keep_the_proportions_of_the_room_and_its_objects() {
    use orbifold_scene::geometry::EXPORT_SCALE;
    for (signature, tolerance) in [("*2222", 1e-9), ("*235", 0.01), ("*22222", 0.01)] {
        let mut scene = Scene::default();
        scene.orbifold.signature = signature.into();
        scene.lights.clear();
        scene.camera.at = [0.0, 0.0];
        scene.objects.truncate(1);
        scene.objects[0].shape = "sphere".into();
        scene.objects[0].at = [0.0, 0.0];
        scene.objects[0].size = 0.2;
        scene.objects[0].height = 0.1;
        let geometry = scene.geometry(None).unwrap();
        let (groups, _) = geometry.groups(&[]);
        let sphere = groups.iter().find(|g| g.name == "object 0").unwrap();
        let extent = |k: usize| {
            let values = sphere.positions.iter().map(|p| p[k]);
            values.clone().fold(f64::MIN, f64::max) - values.fold(f64::MAX, f64::min)
        };
        let (x, y, h) = (extent(0), extent(1), extent(2));
        assert!((h - 0.2).abs() < 1e-9, "{signature}: height {h}");
        for width in [x, y] {
            assert!(
                (width / h - 1.0).abs() < tolerance,
                "{signature}: the sphere is {x} × {y} × {h} in the export"
            );
        }
    }
    // A Euclidean room's floor corners are the polygon's, at true scale.
    let geometry = empty_room("*333").geometry(None).unwrap();
    let (groups, _) = geometry.groups(&[]);
    let floor = groups.iter().find(|g| g.name == "floor").unwrap();
    for (i, edge) in geometry.layout.edges.iter().enumerate() {
        let corner = geometry.layout.vertices[i].position * EXPORT_SCALE;
        let nearest = floor
            .positions
            .iter()
            .map(|p| (p[0] - corner.re).hypot(p[1] - corner.im))
            .fold(f64::MAX, f64::min);
        assert!(
            nearest < 1e-9,
            "corner {i} is {nearest} from the floor's vertices"
        );
        let next = geometry.layout.vertices[(i + 1) % 3].position * EXPORT_SCALE;
        assert!(((next - corner).norm() - edge.length).abs() < 1e-9);
    }
}

/// A room whose floor, a wall and an object carry images and whose ceiling and another wall
/// carry checkerboards, in a folder of its own with its image.
fn textured_scene(dir: &std::path::Path) -> Scene {
    let tiles = image::RgbImage::from_fn(4, 2, |x, y| {
        image::Rgb([(60 * x) as u8, (200 * y) as u8, 90])
    });
    tiles.save(dir.join("tiles.png")).unwrap();
    let mut scene = Scene::default();
    scene.orbifold.signature = "*2222".into();
    scene.lights.clear();
    scene.room.mirrors = orbifold_scene::MirrorDefault::None;
    let image = |scale, coordinates| Material::Texture {
        path: "tiles.png".into(),
        scale,
        coordinates,
    };
    scene.room.floor = image(0.5, Coordinates::Model);
    scene.room.ceiling = Material::Checker {
        colors: [[1.0, 0.0, 0.0], [0.0, 0.0, 1.0]],
        size: 0.3,
        coordinates: Coordinates::Model,
    };
    scene.walls = vec![
        Wall {
            index: 0,
            material: Some(Material::Checker {
                colors: [[0.0; 3], [1.0; 3]],
                size: 0.2,
                coordinates: Coordinates::Model,
            }),
            mirrors: Vec::new(),
        },
        Wall {
            index: 1,
            material: Some(image(0.4, Coordinates::Model)),
            mirrors: Vec::new(),
        },
    ];
    scene.objects[0].material = image(0.25, Coordinates::Intrinsic);
    scene
}

#[test]
fn textures_export_with_the_renderer_s_coordinates() {
    let tmp = temp_dir("textures");
    let dir = tmp.path();
    let scene = textured_scene(dir);
    let geometry = scene.geometry(Some(dir)).unwrap();
    let (groups, _) = geometry.groups(&[]);
    let group = |name: &str| groups.iter().find(|g| g.name == name).unwrap();
    // The floor in model coordinates: u, v = model x, y over the scale (exports double x, y).
    let floor = group("floor");
    assert_eq!(floor.uv.len(), floor.positions.len());
    for (p, uv) in floor.positions.iter().zip(&floor.uv) {
        assert!((uv[0] - p[0] / EXPORT_SCALE / 0.5).abs() < 1e-9);
        assert!((uv[1] - p[1] / EXPORT_SCALE / 0.5).abs() < 1e-9);
    }
    // Wall 1 from its first corner: u·scale is the distance along it (true size in E²), v·scale
    // the height.
    let layout = scene.layout().unwrap();
    let corner = layout.vertices[layout.edges[1].from.unwrap()].position * EXPORT_SCALE;
    let wall = group("wall 1");
    for (p, uv) in wall.positions.iter().zip(&wall.uv) {
        let along = (p[0] - corner.re).hypot(p[1] - corner.im);
        assert!((uv[0] * 0.4 - along).abs() < 1e-6, "{uv:?} at {along}");
        assert!((uv[1] * 0.4 - p[2]).abs() < 1e-9);
    }
    // The ceiling at height 1: ⌊1/0.3⌋ = 3 is odd, so its squares swap colours.
    assert_eq!(
        group("ceiling").texture,
        Some(TextureImage::Checker([[0.0, 0.0, 1.0], [1.0, 0.0, 0.0]]))
    );
    // The object in intrinsic coordinates: in E² the offset from the centre, at true size.
    let object = group("object 0");
    let c = layout.centre * EXPORT_SCALE;
    for (p, uv) in object.positions.iter().zip(&object.uv) {
        assert!((uv[0] * 0.25 - (p[0] - c.re)).abs() < 1e-6);
        assert!((uv[1] * 0.25 - (p[1] - c.im)).abs() < 1e-6);
    }
    // Read back by tobj: texture coordinates, and each image beside the OBJ.
    let path = dir.join("room.obj");
    let written = export(&groups, ExportFormat::Obj, &path, "test").unwrap();
    for name in ["room-tiles.png", "room-checker-1.png", "room-checker-2.png"] {
        assert!(written.contains(&dir.join(name)), "{name} in {written:?}");
    }
    let (models, materials) = tobj::load_obj(&path, &tobj::GPU_LOAD_OPTIONS).unwrap();
    let materials = materials.unwrap();
    for model in &models {
        let textured = group(&model.name.replace('_', " ")).texture.is_some();
        assert_eq!(!model.mesh.texcoords.is_empty(), textured, "{}", model.name);
        let material = &materials[model.mesh.material_id.unwrap()];
        assert_eq!(
            material.diffuse_texture.is_some(),
            textured,
            "{}",
            model.name
        );
        if let Some(file) = &material.diffuse_texture {
            assert!(dir.join(file).is_file(), "{file}");
        }
    }
    // The wall's checker image: colours[0] at the bottom left (v upwards), sRGB.
    let checker = image::open(dir.join("room-checker-2.png"))
        .unwrap()
        .to_rgb8();
    let (w, h) = checker.dimensions();
    assert_eq!(checker.get_pixel(0, h - 1).0, [0, 0, 0]);
    assert_eq!(checker.get_pixel(w - 1, h - 1).0, [255, 255, 255]);
    assert_eq!(checker.get_pixel(0, 0).0, [255, 255, 255]);
    // glTF embeds the images: each textured mesh has TEXCOORD_0 (v down the image) and a
    // base-colour texture whose image is the same PNG.
    let glb = dir.join("room.glb");
    export(&groups, ExportFormat::Glb, &glb, "test").unwrap();
    let gltf = gltf::Gltf::from_slice(&std::fs::read(&glb).unwrap()).unwrap();
    let blob = gltf.blob.clone().unwrap();
    assert_eq!(gltf.document.images().count(), 3);
    for mesh in gltf.document.meshes() {
        let group = group(mesh.name().unwrap());
        let primitive = mesh.primitives().next().unwrap();
        let reader = primitive.reader(|b| (b.index() == 0).then_some(blob.as_slice()));
        let texture = primitive
            .material()
            .pbr_metallic_roughness()
            .base_color_texture();
        assert_eq!(texture.is_some(), group.texture.is_some(), "{}", group.name);
        let Some(texture) = texture else {
            assert!(reader.read_tex_coords(0).is_none());
            continue;
        };
        let uv: Vec<[f32; 2]> = reader.read_tex_coords(0).unwrap().into_f32().collect();
        let shaded = smooth_normals(group);
        assert_eq!(uv.len(), shaded.uv.len());
        for (a, b) in uv.iter().zip(&shaded.uv) {
            assert!(
                (f64::from(a[0]) - b[0]).abs() < 1e-5
                    && (f64::from(a[1]) - (1.0 - b[1])).abs() < 1e-5
            );
        }
        let gltf::image::Source::View { view, mime_type } = texture.texture().source().source()
        else {
            panic!("an embedded image");
        };
        assert_eq!(mime_type, "image/png");
        let bytes = &blob[view.offset()..view.offset() + view.length()];
        assert!(image::load_from_memory(bytes).is_ok());
    }
    // A copy under the group carries its texture along.
    let cover = Cover::enumerate_layout(layout, Bound::Depth(1), true).unwrap();
    let (copies, _) = geometry.groups(&cover.tiles);
    let floors = copies.iter().find(|g| g.name == "floor copies").unwrap();
    assert_eq!(floors.uv.len(), floors.positions.len());
    assert_eq!(floors.uv[..floor.uv.len()], floor.uv[..]);
}

#[test]
fn the_closed_wall_of_star_runs_its_texture_once_round() {
    // `*` has one wall, a great circle: its last column of vertices sits on its first.
    let tmp = temp_dir("star");
    let dir = tmp.path();
    let mut scene = textured_scene(dir);
    scene.orbifold.signature = "*".into();
    scene.walls.clear();
    scene.room.wall_material = Material::Texture {
        path: "tiles.png".into(),
        scale: 1.0,
        coordinates: Coordinates::Model,
    };
    let (groups, _) = scene.geometry(Some(dir)).unwrap().groups(&[]);
    let wall = groups.iter().find(|g| g.name == "wall 0").unwrap();
    let most = wall
        .uv
        .iter()
        .map(|t| t[0])
        .fold(f64::NEG_INFINITY, f64::max);
    assert!((most - std::f64::consts::TAU).abs() < 1e-9, "{most}");
    for t in &wall.triangles {
        let u = t.map(|i| wall.uv[i as usize][0]);
        let spread = u.iter().cloned().fold(f64::NEG_INFINITY, f64::max)
            - u.iter().cloned().fold(f64::INFINITY, f64::min);
        assert!(spread < 0.5, "a triangle across the seam: {u:?}");
    }
}

#[test]
fn ply_carries_texture_coordinates_and_names_its_images() {
    let tmp = temp_dir("ply-textures");
    let dir = tmp.path();
    let scene = textured_scene(dir);
    let geometry = scene.geometry(Some(dir)).unwrap();
    let (groups, _) = geometry.groups(&[]);
    let path = dir.join("room.ply");
    let written = export(&groups, ExportFormat::Ply, &path, "test").unwrap();
    let bytes = std::fs::read(&path).unwrap();
    let end = bytes
        .windows(11)
        .position(|w| w == b"end_header\n")
        .unwrap()
        + 11;
    let header = std::str::from_utf8(&bytes[..end]).unwrap();
    // One `TextureFile` per image, written beside the PLY, in the order faces count them.
    let images: Vec<&str> = header
        .lines()
        .filter_map(|l| l.strip_prefix("comment TextureFile "))
        .collect();
    assert_eq!(
        images,
        ["room-tiles.png", "room-checker-1.png", "room-checker-2.png"]
    );
    for name in &images {
        assert!(written.contains(&dir.join(name)), "{name} in {written:?}");
    }
    for property in ["float s", "float t", "int texnumber"] {
        assert!(
            header.contains(&format!("property {property}\n")),
            "{property}"
        );
    }
    // The body: 35-byte vertices (position, normal, colour, s, t) and 21-byte faces.
    let float = |at: usize| f32::from_le_bytes(bytes[at..at + 4].try_into().unwrap());
    let int = |at: usize| i32::from_le_bytes(bytes[at..at + 4].try_into().unwrap());
    let shaded: Vec<_> = groups.iter().map(smooth_normals).collect();
    let vertices: usize = shaded.iter().map(|s| s.positions.len()).sum();
    let mut face = end + 35 * vertices;
    let mut base = 0;
    for (g, (group, s)) in groups.iter().zip(&shaded).enumerate() {
        let image = group.texture.as_ref().map(|_| match group.name.as_str() {
            "ceiling" => 1,
            "wall 0" => 2,
            _ => 0,
        });
        for v in 0..s.positions.len() {
            let at = end + 35 * (base + v) + 27;
            let uv = s.uv.get(v).copied().unwrap_or([0.0; 2]);
            assert!((f64::from(float(at)) - uv[0]).abs() < 1e-5);
            assert!((f64::from(float(at + 4)) - uv[1]).abs() < 1e-5);
        }
        for t in &s.triangles {
            assert_eq!(bytes[face], 3);
            assert_eq!(int(face + 13), g as i32);
            assert_eq!(int(face + 17), image.map_or(-1, |k| k), "{}", group.name);
            for (k, &v) in t.iter().enumerate() {
                assert_eq!(int(face + 1 + 4 * k), (base + v as usize) as i32);
            }
            face += 21;
        }
        base += s.positions.len();
    }
    assert_eq!(face, bytes.len());
    // Readers that do not know the texture properties skip them: ours reads the mesh back.
    let mesh = parse_mesh(&bytes, MeshFormat::Ply, None).unwrap();
    let triangles: usize = groups.iter().map(|g| g.triangles.len()).sum();
    assert_eq!(mesh.triangles.len(), triangles);
}
