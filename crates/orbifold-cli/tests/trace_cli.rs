//! `orbifold trace` as a process: hits read back from JSON lie on their walls (checked against
//! `orbifold layout --json`'s wall circles), arc lengths add up, errors exit with 2.

use std::path::{Path, PathBuf};

use assert_cmd::Command;
use predicates::prelude::*;
use serde_json::Value;

fn orbifold() -> Command {
    Command::cargo_bin("orbifold").unwrap()
}

fn json(args: &[&str]) -> Value {
    let out = orbifold().args(args).output().unwrap();
    assert!(
        out.status.success(),
        "{args:?}: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    serde_json::from_slice(&out.stdout).unwrap()
}

fn scenes() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/scenes")
}

/// The distance of a model point from a wall drawn as a circle or a line.
fn off_wall(edge: &Value, x: f64, y: f64) -> f64 {
    if let Some(c) = edge.get("circle") {
        let (cx, cy, r) = (
            c["cx"].as_f64().unwrap(),
            c["cy"].as_f64().unwrap(),
            c["r"].as_f64().unwrap(),
        );
        ((x - cx).hypot(y - cy) - r).abs()
    } else {
        let l = &edge["line"];
        let (px, py, dx, dy) = (
            l["px"].as_f64().unwrap(),
            l["py"].as_f64().unwrap(),
            l["dx"].as_f64().unwrap(),
            l["dy"].as_f64().unwrap(),
        );
        ((x - px) * dy - (y - py) * dx).abs()
    }
}

#[test]
fn every_hit_lies_on_its_surface_in_every_geometry() {
    for sig in ["*235", "*333", "*2223", "*∞∞∞"] {
        let layout = json(&["layout", sig, "--json"]);
        let edges = layout["edges"].as_array().unwrap();
        for (yaw, pitch) in [("17", "3"), ("-100", "-2"), ("200", "1.5")] {
            let trace = json(&[
                "trace",
                sig,
                "--from",
                "0.01,0.02,0.5",
                "--yaw",
                yaw,
                "--pitch",
                pitch,
                "--bounces",
                "12",
                "--json",
            ]);
            let hits = trace["hits"].as_array().unwrap();
            assert!(!hits.is_empty(), "{sig}");
            let mut last_s = 0.0;
            for hit in hits {
                let surface = hit["surface"].as_str().unwrap();
                let (x, y, h, s) = (
                    hit["x"].as_f64().unwrap(),
                    hit["y"].as_f64().unwrap(),
                    hit["h"].as_f64().unwrap(),
                    hit["s"].as_f64().unwrap(),
                );
                assert!(s > last_s, "{sig}: arc lengths must grow");
                last_s = s;
                match surface {
                    "floor" => assert!(h.abs() < 1e-12),
                    "ceiling" => assert!((h - 1.0).abs() < 1e-12),
                    wall => {
                        let i: usize = wall.strip_prefix("wall ").unwrap().parse().unwrap();
                        assert!(off_wall(&edges[i], x, y) < 1e-9, "{sig}: {hit}");
                        assert_eq!(
                            hit["mirror"], true,
                            "every wall of a bare signature is a mirror"
                        );
                    }
                }
            }
            let end = trace["end"].as_str().unwrap();
            assert!(["surface", "bounce limit", "escaped"].contains(&end));
        }
    }
}

#[test]
fn a_level_ray_in_a_full_mirror_room_bounces_until_the_limit() {
    let trace = json(&[
        "trace",
        "*2222",
        "--from",
        "0,0,0.5",
        "--yaw",
        "30",
        "--pitch",
        "0",
        "--bounces",
        "7",
        "--json",
    ]);
    assert_eq!(trace["hits"].as_array().unwrap().len(), 7);
    assert_eq!(trace["end"], "bounce limit");
}

#[test]
fn in_the_euclidean_square_the_unfolded_ray_is_straight() {
    // In E²×R the total arc length to the ceiling is (height − h₀)/sin(pitch) whatever the
    // mirrors do.
    let trace = json(&[
        "trace",
        "*2222",
        "--from",
        "0.1,0.05,0.2",
        "--yaw",
        "33",
        "--pitch",
        "5",
        "--json",
    ]);
    let hits = trace["hits"].as_array().unwrap();
    let last = hits.last().unwrap();
    assert_eq!(last["surface"], "ceiling");
    let expected = 0.8 / 5f64.to_radians().sin();
    assert!((last["s"].as_f64().unwrap() - expected).abs() < 1e-9);
}

#[test]
fn a_scene_camera_sees_its_object() {
    let scene = scenes().join("default.toml");
    let trace = json(&["trace", scene.to_str().unwrap(), "--json"]);
    let hits = trace["hits"].as_array().unwrap();
    let last = hits.last().unwrap();
    assert!(
        last["surface"].as_str().unwrap().starts_with("object"),
        "{trace}"
    );
    assert_eq!(last["mirror"], false);
}

#[test]
fn aovs_are_written_as_exr() {
    let tmp = tempfile::Builder::new()
        .prefix("orbifold-trace-cli-")
        .tempdir()
        .unwrap();
    let dir = tmp.path();
    let file = dir.join("aov.exr");
    let scene = scenes().join("default.toml");
    orbifold()
        .args(["trace", scene.to_str().unwrap(), "--aov"])
        .arg(&file)
        .args(["--size", "32x24", "--bounces", "4"])
        .assert()
        .success();
    let image = exr::prelude::read_all_flat_layers_from_file(&file).unwrap();
    let layer = &image.layer_data[0];
    assert_eq!(layer.size, exr::prelude::Vec2(32, 24));
    let names: Vec<String> = layer
        .channel_data
        .list
        .iter()
        .map(|c| c.name.to_string())
        .collect();
    for name in ["Z", "P.X", "N.Z", "id", "bounces"] {
        assert!(names.iter().any(|n| n == name), "{names:?}");
    }
}

#[test]
fn bad_input_is_an_error_with_exit_code_2() {
    for args in [
        vec!["trace", "*333", "--from", "5,5,0.5"],
        vec!["trace", "*333", "--from", "0,0,2"],
        vec!["trace", "*333", "--from", "0,0"],
        vec!["trace", "*333", "--from", "0,0,x"],
        vec!["trace", "*23", "--from", "0,0,0.5"],
        vec!["trace", "*333"],
        vec!["trace", "*333", "--from", "0,0,0.5", "--height", "-1"],
    ] {
        orbifold()
            .args(&args)
            .assert()
            .code(2)
            .stdout(predicate::str::is_empty())
            .stderr(predicate::str::contains("error"));
    }
}
