//! `orbifold scene` as a process.

use assert_cmd::Command;
use predicates::prelude::*;

#[test]
fn new_and_check() {
    let dir = std::env::temp_dir().join(format!("orbifold-scene-cli-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
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
    std::fs::remove_dir_all(&dir).unwrap();
}
