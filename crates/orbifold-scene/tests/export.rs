//! Exported rooms read back by independent parsers (tobj for OBJ, gltf for GLB) with the
//! expected groups; PLY by its header and our importer. Also the room's geometry itself:
//! mirrors split walls, objects are rigid copies of their meshes.

use std::collections::BTreeMap;

use orbifold::cover::{Bound, Cover};
use orbifold_scene::export::{ExportFormat, export, identifier, to_glb, to_obj, to_ply};
use orbifold_scene::geometry::{MeshGroup, PartKind};
use orbifold_scene::mesh::import::{MeshFormat, parse_mesh};
use orbifold_scene::{Mirror, Scene, Wall};

fn temp_dir(name: &str) -> std::path::PathBuf {
    let dir = std::env::temp_dir().join(format!("orbifold-export-{name}-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir
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
    let dir = temp_dir("obj");
    let path = dir.join("room.obj");
    let written = export(&groups, ExportFormat::Obj, &path, "test").unwrap();
    assert_eq!(written, [path.clone(), dir.join("room.mtl")]);
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
        let material = &materials[model.mesh.material_id.unwrap()];
        assert_eq!(material.name, identifier(&group.name));
    }
    std::fs::remove_dir_all(dir).unwrap();
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
        assert_eq!(positions.len(), group.positions.len());
        // glTF is Y up: (x, y, h) is stored as (x, h, −y).
        for (p, q) in positions.iter().zip(&group.positions) {
            assert!(
                (p[0] as f64 - q[0]).abs() < 1e-6
                    && (p[1] as f64 - q[2]).abs() < 1e-6
                    && (p[2] as f64 + q[1]).abs() < 1e-6
            );
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
        groups.iter().map(|g| g.positions.len()).sum::<usize>()
    );
}

#[test]
fn cover_copies_are_whole_rooms() {
    let mut scene = Scene::default();
    scene.orbifold.signature = "*333".into();
    scene.objects.clear();
    scene.lights.clear();
    scene.camera.at = [0.0, 0.0];
    let geometry = scene.geometry(None).unwrap();
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
