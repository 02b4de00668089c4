//! `orbifold cover` as a process.

use assert_cmd::Command;
use predicates::prelude::*;
use serde_json::Value;

fn orbifold() -> Command {
    Command::cargo_bin("orbifold").expect("binary built")
}

fn json(args: &[&str]) -> Value {
    let output = orbifold()
        .arg("cover")
        .args(args)
        .arg("--json")
        .output()
        .unwrap();
    assert!(
        output.status.success(),
        "{args:?}: {}",
        String::from_utf8_lossy(&output.stderr)
    );
    serde_json::from_slice(&output.stdout).unwrap()
}

#[test]
fn counts_by_depth_in_json() {
    let v = json(&["*2222222", "--depth", "4"]);
    assert_eq!(
        v["counts_by_depth"],
        serde_json::json!([1, 7, 35, 168, 805])
    );
    assert_eq!(v["total"], 1016);
    assert!(v.get("tiles").is_none());
    let v = json(&["*235"]);
    assert_eq!(v["total"], 120);
    let v = json(&["*2323", "--max-tiles", "100", "--tiles"]);
    let tiles = v["tiles"].as_array().unwrap();
    assert!(tiles.len() <= 100);
    assert_eq!(tiles.len() as u64, v["total"].as_u64().unwrap());
    assert_eq!(tiles[0]["depth"], 0);
    assert_eq!(
        tiles[0]["isometry"],
        serde_json::json!([[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]])
    );
    assert!(tiles[1]["reflected"].as_bool().unwrap());
}

#[test]
fn text_reports_agreement_and_rate() {
    orbifold()
        .args(["cover", "*237", "--depth", "12"])
        .assert()
        .success()
        .stdout(predicate::str::contains(
            "growth series (Steinberg's formula) agrees",
        ))
        .stdout(predicate::str::contains("million tiles per second"));
}

#[test]
fn refusals_are_clear() {
    orbifold()
        .args(["cover", "*2222"])
        .assert()
        .code(2)
        .stderr(predicate::str::contains("infinite"));
    orbifold()
        .args(["cover", "*23"])
        .assert()
        .code(2)
        .stderr(predicate::str::contains("bad orbifold"));
    orbifold()
        .args(["cover", "*(3/2)33"])
        .assert()
        .code(2)
        .stderr(predicate::str::contains("not an integer"));
    orbifold()
        .args(["cover", "*2222222", "--depth", "40"])
        .assert()
        .code(2)
        .stdout(predicate::str::is_empty())
        .stderr(predicate::str::contains("refused before starting"));
    orbifold()
        .args(["cover", "*2222", "--radius", "-1"])
        .assert()
        .code(2);
    orbifold()
        .args(["cover", "*2222", "--depth", "2", "--radius", "1"])
        .assert()
        .code(2);
}
