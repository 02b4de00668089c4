//! `orbifold animate` as a process: frames for every path, restarts that skip finished frames,
//! slices, a walking object, and clear errors (exit code 2) before any frame is written.

use std::path::PathBuf;

use assert_cmd::Command;
use predicates::prelude::*;
use serde_json::Value;

fn orbifold() -> Command {
    Command::cargo_bin("orbifold").unwrap()
}

/// A fresh folder for a test's files, removed when the test ends (also when it fails).
fn temp() -> tempfile::TempDir {
    tempfile::Builder::new()
        .prefix("orbifold-animate-cli-")
        .tempdir()
        .unwrap()
}

/// Runs `animate` with `--json` and tiny frames; returns the JSON lines.
fn animate(args: &[&str]) -> Vec<Value> {
    let out = orbifold()
        .arg("animate")
        .args(args)
        .args(["--size", "12x8", "--spp", "1", "--json"])
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{args:?}: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    String::from_utf8(out.stdout)
        .unwrap()
        .lines()
        .map(|l| serde_json::from_str(l).unwrap())
        .collect()
}

fn frames(dir: &PathBuf) -> Vec<String> {
    let mut names: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    names
}

#[test]
fn every_built_in_path_writes_its_frames() {
    let tmp = temp();
    for path in ["walls", "orbit", "turn"] {
        for signature in ["*235", "*333", "*2223"] {
            let dir = tmp
                .path()
                .join(format!("{path}-{}", signature.trim_start_matches('*')));
            let lines = animate(&[
                signature,
                "--path",
                path,
                "--count",
                "3",
                "-o",
                dir.to_str().unwrap(),
            ]);
            assert_eq!(lines.len(), 4, "{lines:?}");
            assert_eq!(lines[3]["rendered"], 3);
            assert!(lines[3]["exposure"].is_number());
            assert_eq!(
                frames(&dir),
                ["frame-00000.png", "frame-00001.png", "frame-00002.png"]
            );
            let image = image::open(dir.join("frame-00001.png")).unwrap();
            assert_eq!((image.width(), image.height()), (12, 8));
        }
    }
}

#[test]
fn a_restart_skips_finished_frames_and_slices_add_up() {
    let tmp = temp();
    let dir = tmp.path().join("slices");
    let out = dir.to_str().unwrap();
    let first = animate(&[
        "*2222", "--path", "walls", "--count", "5", "--frames", "0..1", "-o", out,
    ]);
    assert_eq!(first.last().unwrap()["rendered"], 2);
    let second = animate(&[
        "*2222", "--path", "walls", "--count", "5", "--frames", "3..4", "-o", out,
    ]);
    assert_eq!(second.last().unwrap()["rendered"], 2);
    // The whole animation again: only frame 2 is missing.
    let all = animate(&[
        "*2222", "--path", "walls", "--count", "5", "-o", out, "--format", "png",
    ]);
    let summary = all.last().unwrap();
    assert_eq!(
        (summary["rendered"].as_u64(), summary["skipped"].as_u64()),
        (Some(1), Some(4))
    );
    assert_eq!(all[2]["skipped"], false);
    assert_eq!(all[0]["skipped"], true);
    assert_eq!(frames(&dir).len(), 5);
    // --force renders again.
    let again = animate(&[
        "*2222", "--path", "walls", "--count", "5", "--frames", "4", "-o", out, "--force",
    ]);
    assert_eq!(again.last().unwrap()["rendered"], 1);
}

#[test]
fn keyframes_and_a_walking_object() {
    let tmp = temp();
    let keys = tmp.path().join("keys.txt");
    std::fs::write(
        &keys,
        "# x y height yaw pitch\n-0.08 0 0.5 0 -10\n0.05, 0.05, 0.4, 90\n",
    )
    .unwrap();
    let dir = tmp.path().join("keys");
    let lines = animate(&[
        "*2223",
        "--path",
        keys.to_str().unwrap(),
        "--count",
        "3",
        "-o",
        dir.to_str().unwrap(),
        "--format",
        "jpg",
    ]);
    assert_eq!(lines.last().unwrap()["rendered"], 3);
    assert!(dir.join("frame-00002.jpg").is_file());
    let dir = tmp.path().join("walker");
    let lines = animate(&[
        "*333",
        "--path",
        "walls",
        "--walker",
        "0",
        "--count",
        "2",
        "-o",
        dir.to_str().unwrap(),
        "--format",
        "exr",
    ]);
    assert_eq!(lines.last().unwrap()["rendered"], 2);
    assert!(
        lines.last().unwrap()["exposure"].is_null(),
        "EXR frames are linear"
    );
}

#[test]
fn bad_input_is_refused_before_any_frame() {
    let tmp = temp();
    let dir = tmp.path().join("refused");
    let out = dir.to_str().unwrap();
    let cases: [(&[&str], &str); 6] = [
        (
            &["--path", "walls", "--count", "4", "--frames", "2..9"],
            "frames 0 to 3",
        ),
        (&["--path", "spiral"], "cannot read it as a keyframe file"),
        (&["--path", "walls", "--walker", "teapot"], "no such object"),
        (&["--path", "walls", "--format", "gif"], "png, jpg or exr"),
        (&["--path", "walls", "--frames", "5..2"], "comes after"),
        (&["--path", "walls", "--time-limit", "-1"], "positive"),
    ];
    for (args, message) in cases {
        orbifold()
            .args(["animate", "*333", "-o", out])
            .args(args)
            .assert()
            .code(2)
            .stderr(predicate::str::contains(message));
    }
    let keys = tmp.path().join("outside.txt");
    std::fs::write(&keys, "0 0 0.5 0\n5 5 0.5 0\n").unwrap();
    orbifold()
        .args([
            "animate",
            "*333",
            "-o",
            out,
            "--path",
            keys.to_str().unwrap(),
        ])
        .assert()
        .code(2)
        .stderr(predicate::str::contains("leaves the room"));
    let keys = tmp.path().join("garbled.txt");
    std::fs::write(&keys, "0 0 0.5 0\n0 0 high 0\n").unwrap();
    orbifold()
        .args([
            "animate",
            "*333",
            "-o",
            out,
            "--path",
            keys.to_str().unwrap(),
        ])
        .assert()
        .code(2)
        .stderr(predicate::str::contains("line 2"));
    assert!(!dir.exists(), "nothing written");
}
