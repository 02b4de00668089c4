//! `orbifold room` as a process.

use std::path::{Path, PathBuf};

use assert_cmd::Command;
use predicates::prelude::*;

/// A fresh, empty folder for a test's files, removed when the test ends (also when it fails).
fn dir(name: &str) -> tempfile::TempDir {
    tempfile::Builder::new()
        .prefix(&format!("orbifold-room-cli-{name}-"))
        .tempdir()
        .unwrap()
}

fn orbifold() -> Command {
    Command::cargo_bin("orbifold").unwrap()
}

fn scenes() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/scenes")
}

#[test]
fn a_signature_becomes_an_obj_with_named_groups() {
    let tmp = dir("sig");
    let d = tmp.path();
    let file = d.join("room.obj");
    orbifold()
        .args(["room", "*2223", "-o"])
        .arg(&file)
        .assert()
        .success()
        .stdout(predicate::str::contains("smallest angle"));
    let (models, _) = tobj::load_obj(&file, &tobj::GPU_LOAD_OPTIONS).unwrap();
    let names: Vec<&str> = models.iter().map(|m| m.name.as_str()).collect();
    assert_eq!(
        names,
        [
            "floor",
            "ceiling",
            "mirror_0.0",
            "mirror_1.0",
            "mirror_2.0",
            "mirror_3.0"
        ]
    );
    let text = std::fs::read_to_string(&file).unwrap();
    assert!(text.contains("coordinates: 2 model x, 2 model y, height"));
}

#[test]
fn a_scene_with_cover_as_json() {
    let tmp = dir("scene");
    let d = tmp.path();
    let file = d.join("room.glb");
    let out = orbifold()
        .arg("room")
        .arg(scenes().join("default.toml"))
        .args(["--cover", "2", "--resolution", "0.2", "--json", "-o"])
        .arg(&file)
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let report: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(report["signature"], "*22222");
    // The groups' vertices are those written, normals split on creases included.
    let bytes = std::fs::read(&file).unwrap();
    let gltf = gltf::Gltf::from_slice(&bytes).unwrap();
    let written: Vec<usize> = gltf
        .document
        .meshes()
        .map(|m| {
            let primitive = m.primitives().next().unwrap();
            primitive.get(&gltf::Semantic::Positions).unwrap().count()
        })
        .collect();
    let reported: Vec<usize> = report["groups"]
        .as_array()
        .unwrap()
        .iter()
        .filter(|g| g["triangles"].as_u64().unwrap() > 0)
        .map(|g| g["vertices"].as_u64().unwrap() as usize)
        .collect();
    assert_eq!(written, reported);
    // *22222 has 5 tiles at depth 1 and 15 at depth 2.
    assert_eq!(report["copies"], 20);
    assert_eq!(report["resolution"], 0.2);
    let names: Vec<&str> = report["groups"]
        .as_array()
        .unwrap()
        .iter()
        .map(|g| g["name"].as_str().unwrap())
        .collect();
    assert!(names.contains(&"object 0") && names.contains(&"object 0 copies"));
    assert!(report["floor"]["triangles"].as_u64().unwrap() > 0);
    assert!(std::fs::metadata(&file).unwrap().len() > 1000);
}

#[test]
fn ideal_corners_report_their_cut() {
    let tmp = dir("ideal");
    let d = tmp.path();
    orbifold()
        .args(["room", "*∞∞∞", "--cusp", "2.5", "-o"])
        .arg(d.join("r.ply"))
        .assert()
        .success()
        .stdout(predicate::str::contains("cut off at distance 2.5000"));
}

#[test]
fn bad_requests_fail_cleanly_and_write_nothing() {
    let tmp = dir("bad");
    let d = tmp.path();
    for (args, message) in [
        (
            vec!["room", "*2223", "-o", "room.stl"],
            "must end in .obj, .ply or .glb",
        ),
        (vec!["room", "*23", "-o", "room.obj"], "bad orbifold"),
        (vec!["room", "*2x3", "-o", "room.obj"], "position"),
        (
            vec!["room", "*333", "--resolution=-1", "-o", "room.obj"],
            "room.resolution",
        ),
        (
            vec!["room", "*333", "--resolution=0.0001", "-o", "room.obj"],
            "coarser",
        ),
        (
            vec!["room", "missing.toml", "-o", "room.obj"],
            "missing.toml",
        ),
        (
            vec!["room", "*2223", "--cover", "40", "-o", "room.obj"],
            "budget",
        ),
        (
            vec![
                "room",
                "*2223",
                "--cover",
                "14",
                "--resolution",
                "0.05",
                "-o",
                "room.obj",
            ],
            "triangles",
        ),
    ] {
        orbifold()
            .current_dir(d)
            .args(&args)
            .assert()
            .code(2)
            .stderr(predicate::str::contains(message));
    }
    assert_eq!(std::fs::read_dir(d).unwrap().count(), 0, "nothing written");
}

#[test]
fn texture_paths_stay_relative_to_the_scene_file() {
    // The peer scene's textures sit beside it; the test runs in another folder.
    let tmp = dir("textures");
    let d = tmp.path();
    let file = d.join("room.obj");
    let scene =
        Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/peer/textures-2222.toml");
    orbifold()
        .arg("room")
        .arg(&scene)
        .args(["--height", "0.9", "-o"])
        .arg(&file)
        .assert()
        .success();
    assert!(file.is_file());
    // An option that breaks the scene is named as the key it sets.
    orbifold()
        .arg("room")
        .arg(&scene)
        .args(["--height=-1", "-o"])
        .arg(d.join("bad.obj"))
        .assert()
        .code(2)
        .stderr(predicate::str::contains(
            "room.height: the room's height must be",
        ));
    assert!(!d.join("bad.obj").exists());
}
