//! `orbifold scene` as a process.

use assert_cmd::Command;
use predicates::prelude::*;

#[test]
fn new_and_check() {
    let tmp = tempfile::Builder::new()
        .prefix("orbifold-scene-cli-")
        .tempdir()
        .unwrap();
    let dir = tmp.path();
    let file = dir.join("room.toml");
    Command::cargo_bin("orbifold")
        .unwrap()
        .args(["scene", "new", "*2333", "-o"])
        .arg(&file)
        .assert()
        .success();
    Command::cargo_bin("orbifold")
        .unwrap()
        .args(["scene", "check"])
        .arg(&file)
        .assert()
        .success()
        .stdout(predicate::str::contains("ok"));
    std::fs::write(&file, "[room]\nheight = -1\n").unwrap();
    Command::cargo_bin("orbifold")
        .unwrap()
        .args(["scene", "check"])
        .arg(&file)
        .assert()
        .code(2)
        .stderr(predicate::str::contains("room.toml:2:10: room.height"));
    Command::cargo_bin("orbifold")
        .unwrap()
        .args(["scene", "new", "*23", "-o"])
        .arg(dir.join("bad.toml"))
        .assert()
        .code(2);
    assert!(!dir.join("bad.toml").exists());
}

/// `scene show` fills in every default: its TOML is the same scene, and its JSON has the
/// defaults a script needs (the light's colour, the camera's field of view).
#[test]
fn show_fills_in_the_defaults() {
    let tmp = tempfile::Builder::new()
        .prefix("orbifold-scene-show-")
        .tempdir()
        .unwrap();
    let dir = tmp.path();
    let file = dir.join("room.toml");
    std::fs::write(
        &file,
        "[orbifold]\nsignature = \"*333\"\n\n[[lights]]\nkind = \"sphere\"\npower = 5.0\n",
    )
    .unwrap();
    let toml = Command::cargo_bin("orbifold")
        .unwrap()
        .args(["scene", "show"])
        .arg(&file)
        .output()
        .unwrap();
    assert!(toml.status.success());
    let shown = String::from_utf8(toml.stdout).unwrap();
    let original = orbifold_scene::Scene::load(&file).unwrap();
    assert_eq!(
        orbifold_scene::Scene::from_toml(&shown, None).unwrap(),
        original
    );
    assert!(shown.contains("fov = "), "{shown}");

    let json = Command::cargo_bin("orbifold")
        .unwrap()
        .args(["scene", "show", "--json"])
        .arg(&file)
        .output()
        .unwrap();
    assert!(json.status.success());
    let value: serde_json::Value = serde_json::from_slice(&json.stdout).unwrap();
    assert_eq!(value["orbifold"]["signature"], "*333");
    assert_eq!(value["lights"][0]["kind"], "sphere");
    assert_eq!(value["lights"][0]["power"], 5.0);
    assert_eq!(
        value["lights"][0]["color"],
        serde_json::json!([1.0, 0.95, 0.9])
    );
    assert!(value["camera"]["fov"].is_number());

    std::fs::write(&file, "[room]\nheight = -1\n").unwrap();
    Command::cargo_bin("orbifold")
        .unwrap()
        .args(["scene", "show"])
        .arg(&file)
        .assert()
        .code(2)
        .stdout(predicate::str::is_empty())
        .stderr(predicate::str::contains("room.height"));
}
