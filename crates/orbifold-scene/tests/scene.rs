//! Scene files: defaults, round trips, and every kind of invalid file with its position.

use orbifold_scene::{Light, LightKind, Material, Mirror, Object, Scene, Wall};
use proptest::prelude::*;

/// (position, key, message) of each error.
type Found = (Option<(usize, usize)>, Option<String>, String);

fn errors(text: &str) -> Vec<Found> {
    Scene::from_toml(text, None)
        .unwrap_err()
        .into_iter()
        .map(|e| (e.position, e.key, e.message))
        .collect()
}

#[test]
fn the_default_scene_is_valid_and_round_trips() {
    let scene = Scene::default();
    let text = scene.to_toml();
    assert_eq!(Scene::from_toml(&text, None).unwrap(), scene);
    assert_eq!(
        Scene::from_toml("", None).unwrap(),
        scene,
        "an empty file is the default scene"
    );
}

#[test]
fn syntax_errors_and_unknown_keys_have_positions() {
    let e = errors("[room]\nheight = \n");
    assert_eq!(e[0].0.map(|p| p.0), Some(2), "{e:?}");
    let e = errors("[room]\nheigth = 2.0\n");
    assert_eq!(e[0].0, Some((2, 1)), "{e:?}");
    assert!(e[0].2.contains("heigth"), "{e:?}");
    let e = errors("[camera]\nkind = \"fisheye\"\n");
    assert_eq!(e[0].0.map(|p| p.0), Some(2));
    assert!(e[0].2.contains("fisheye"));
}

#[test]
fn range_errors_name_the_key_and_line() {
    let text =
        "[orbifold]\nsignature = \"*2333\"\n\n[room]\nheight = 0\nreflectance = [0.5, 1.5, 0.5]\n";
    let e = errors(text);
    let keys: Vec<_> = e
        .iter()
        .map(|x| (x.1.clone().unwrap_or_default(), x.0.map_or(0, |p| p.0)))
        .collect();
    assert!(keys.contains(&("room.height".into(), 5)), "{keys:?}");
    assert!(keys.contains(&("room.reflectance".into(), 6)), "{keys:?}");
}

#[test]
fn material_problems() {
    let text = r#"
[room]
floor = { kind = "glass" }
ceiling = { kind = "marble", scale = -1 }

[[objects]]
material = { kind = "metal", metal = "gold", roughness = 1.5 }

[[objects]]
material = { kind = "glass", ior = 0.5, tint = [1.0, 1.0, 2.0] }

[[objects]]
material = { kind = "plastic", color = [0.5, 0.5, 0.5], roughness = -0.1 }

[[objects]]
material = { kind = "metal", metal = "tin" }
"#;
    let e = errors(text);
    // The unknown metal is a syntax-level error; it comes alone.
    assert_eq!(e.len(), 1, "{e:?}");
    assert_eq!(e[0].0.map(|p| p.0), Some(16), "{e:?}");
    assert!(e[0].2.contains("tin"), "{e:?}");
    let text = text.replace("metal = \"tin\"", "metal = \"copper\"");
    let e = errors(&text);
    let keys: Vec<(String, usize)> = e
        .iter()
        .map(|x| (x.1.clone().unwrap(), x.0.unwrap().0))
        .collect();
    for (key, line) in [
        ("room.floor", 3),
        ("room.ceiling.scale", 4),
        ("objects[0].material.roughness", 7),
        ("objects[1].material.ior", 10),
        ("objects[1].material.tint", 10),
        ("objects[2].material.roughness", 13),
    ] {
        assert!(
            keys.contains(&(key.to_string(), line)),
            "{key} at line {line} not in {keys:?}"
        );
    }
    assert!(
        e.iter().any(|x| x.2.contains("glass is for objects")),
        "{e:?}"
    );
}

#[test]
fn orbifold_problems() {
    let e = errors("[orbifold]\nsignature = \"*23\"\n");
    assert_eq!(e[0].1.as_deref(), Some("orbifold.signature"));
    assert_eq!(e[0].0.map(|p| p.0), Some(2));
    assert!(e[0].2.contains("bad orbifold"));
    let e = errors("[orbifold]\nsignature = \"*2q\"\n");
    assert!(e[0].2.contains("position 3"));
    let e = errors("[orbifold]\nsignature = \"*22222\"\nparameters = [1.0]\n");
    assert_eq!(
        (e[0].1.as_deref(), e[0].0.map(|p| p.0)),
        (Some("orbifold.parameters"), Some(3))
    );
    let e = errors("[orbifold]\nsignature = \"*22222\"\nparameters = [1.0, -2]\n");
    assert!(e[0].2.contains("positive"), "{e:?}");
}

#[test]
fn objects_lights_camera_and_walls() {
    let text = r#"
[[objects]]
shape = "teapot"

[[objects]]
mesh = "no/such/file.obj"
at = [0.99, 0.0]
crease = 200

[[lights]]
height = 5.0

[camera]
fov = 200

[[walls]]
index = 7

[[walls.mirrors]]
from = 0.8
to = 0.2
"#;
    let e = errors(text);
    let keys: Vec<(String, usize)> = e
        .iter()
        .map(|x| (x.1.clone().unwrap(), x.0.unwrap().0))
        .collect();
    for (key, line) in [
        ("objects[0].shape", 3),
        ("objects[1].mesh", 6),
        ("objects[1].at", 7),
        ("objects[1].crease", 8),
        ("lights[0].height", 11),
        ("camera.fov", 14),
        ("walls[0].index", 17),
        ("walls[0].mirrors[0].from", 20),
    ] {
        assert!(
            keys.contains(&(key.to_string(), line)),
            "{key} at line {line} not in {keys:?}"
        );
    }
}

#[test]
fn a_camera_inside_a_sphere_light_is_an_error() {
    // Distances are intrinsic: near the centre of a hyperbolic room (Poincaré disc) a model
    // offset of 0.08 is at least 0.16 away, outside a light of radius 0.12; 0.04 is inside.
    let mut scene = Scene::default();
    scene.orbifold.signature = "*2223".into();
    let layout = scene.layout().unwrap();
    let c = [layout.centre.re, layout.centre.im];
    scene.lights[0].kind = LightKind::Sphere;
    (
        scene.lights[0].at,
        scene.lights[0].height,
        scene.lights[0].radius,
    ) = (c, 0.6, 0.12);
    scene.camera.height = 0.6;
    for (offset, inside) in [(0.04, true), (0.08, false)] {
        scene.camera.at = [c[0] + offset, c[1]];
        let result = scene.check(None);
        assert_eq!(result.is_err(), inside, "{offset}: {result:?}");
        if let Err(errors) = result {
            assert_eq!(errors[0].key.as_deref(), Some("camera.at"));
            assert!(errors[0].message.contains("inside lights[0]"));
        }
    }
    // Above the light, beyond its radius: fine. A point light has no inside.
    scene.camera.at = c;
    scene.camera.height = 0.75;
    assert!(scene.check(None).is_ok());
    scene.camera.height = 0.6;
    scene.lights[0].kind = LightKind::Point;
    assert!(scene.check(None).is_ok());
}

#[test]
fn load_and_save_through_files() {
    let tmp = tempfile::Builder::new()
        .prefix("orbifold-scene-test-")
        .tempdir()
        .unwrap();
    let dir = tmp.path();
    let path = dir.join("room.toml");
    let mut scene = Scene::default();
    scene.orbifold.signature = "*2333".into();
    scene.save(&path).unwrap();
    assert_eq!(Scene::load(&path).unwrap(), scene);
    std::fs::write(dir.join("bunny.obj"), "v 0 0 0\n").unwrap();
    std::fs::write(&path, "[[objects]]\nmesh = \"bunny.obj\"\n").unwrap();
    assert!(
        Scene::load(&path).is_ok(),
        "mesh paths are relative to the scene file"
    );
    // Texture files too, on the floor, a wall and an object alike (the process's working
    // directory is not the scene's folder).
    std::fs::write(dir.join("tiles.png"), "not read by validation").unwrap();
    let texture = "{ kind = \"texture\", path = \"tiles.png\", scale = 0.5 }";
    std::fs::write(
        &path,
        format!(
            "[room]\nfloor = {texture}\n[[walls]]\nindex = 1\nmaterial = {texture}\n\
             [[objects]]\nmaterial = {texture}\n"
        ),
    )
    .unwrap();
    assert!(
        Scene::load(&path).is_ok(),
        "texture paths are relative to the scene file: {:?}",
        Scene::load(&path).err()
    );
    let missing = Scene::load(&dir.join("none.toml")).unwrap_err();
    assert!(missing[0].to_string().contains("cannot read"));
    std::fs::write(&path, "[room]\nheight = -1\n").unwrap();
    let e = Scene::load(&path).unwrap_err();
    assert!(
        e[0].to_string()
            .starts_with(&format!("{}:2:10: room.height:", path.display())),
        "{}",
        e[0]
    );
}

fn unit() -> impl Strategy<Value = f64> {
    0.0f64..=1.0
}

proptest! {
    /// Saving and loading round-trip exactly, whatever the values.
    #[test]
    fn round_trip(
        height in 1.0f64..5.0,
        reflectance in [unit(), unit(), unit()],
        from in 0.0f64..0.5,
        to in 0.5f64..=1.0,
        at in (-0.12f64..0.12, -0.12f64..0.12),
        yaw in -360.0f64..360.0,
        size in 0.01f64..1.0,
        power in 0.0f64..1000.0,
        kind in prop::sample::select(vec![LightKind::Point, LightKind::Spot, LightKind::Sphere, LightKind::Rectangle]),
    ) {
        let mut scene = Scene::default();
        scene.room.height = height;
        scene.walls.push(Wall { index: 2, material: Some(Material::Color { color: reflectance }), mirrors: vec![Mirror { from, to, bottom: 0.0, top: Some(height / 2.0), reflectance }] });
        scene.objects.push(Object { at: [at.0, at.1], yaw, size, shape: "letter-p".into(), ..Object::default() });
        scene.lights.push(Light { kind, power, at: [at.1, at.0], height: height / 2.0, ..Light::default() });
        let text = scene.to_toml();
        let back = Scene::from_toml(&text, None).unwrap();
        prop_assert_eq!(back, scene);
    }
}

#[test]
fn every_example_scene_loads_and_validates() {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/scenes");
    let mut count = 0;
    for entry in std::fs::read_dir(&dir).unwrap() {
        let path = entry.unwrap().path();
        if path.extension().is_some_and(|e| e == "toml") {
            let scene =
                Scene::load(&path).unwrap_or_else(|e| panic!("{}: {}", path.display(), e[0]));
            // And each round-trips.
            assert_eq!(Scene::from_toml(&scene.to_toml(), None).unwrap(), scene);
            count += 1;
        }
    }
    assert!(count >= 20, "only {count} example scenes");
}
