//! `orbifold preview` as a process: pictures of the right size, the copies counted as the growth
//! series says, and clear errors with exit code 2 and no file left behind.
//!
//! The preview needs a wgpu adapter (Mesa's lavapipe will do); without one these tests skip,
//! unless ORBIFOLD_REQUIRE_GPU is set (as CI sets it).

use std::path::Path;

use assert_cmd::Command;
use serde_json::Value;

fn orbifold() -> Command {
    Command::cargo_bin("orbifold").unwrap()
}

/// A fresh folder for a test's files, removed when the test ends (also when it fails).
fn temp() -> tempfile::TempDir {
    tempfile::Builder::new()
        .prefix("orbifold-preview-cli-")
        .tempdir()
        .unwrap()
}

/// Runs `orbifold preview ARGS --json`; `None` when there is no adapter and none is required.
fn preview(args: &[&str]) -> Option<Value> {
    let out = orbifold()
        .arg("preview")
        .args(args)
        .arg("--json")
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    if !out.status.success()
        && stderr.contains("no GPU adapter")
        && std::env::var_os("ORBIFOLD_REQUIRE_GPU").is_none()
    {
        eprintln!("skipped: {stderr}");
        return None;
    }
    assert!(out.status.success(), "{args:?}: {stderr}");
    Some(serde_json::from_slice(&out.stdout).unwrap())
}

#[test]
fn previews_the_default_scene() {
    let tmp = temp();
    let png = tmp.path().join("default.png");
    let Some(summary) = preview(&["-o", png.to_str().unwrap(), "--size", "96x64"]) else {
        return;
    };
    assert_eq!(
        (summary["width"].as_u64(), summary["height"].as_u64()),
        (Some(96), Some(64))
    );
    assert!(summary["instances"].as_u64().unwrap() >= 1);
    assert!(summary["triangles"].as_u64().unwrap() > 1000);
    let image = image::open(&png).unwrap().to_rgb8();
    assert_eq!(image.dimensions(), (96, 64));
    // The checkered floor and the figure: many colours, not a flat picture.
    let mut colours: Vec<[u8; 3]> = image.pixels().map(|p| p.0).collect();
    colours.sort_unstable();
    colours.dedup();
    assert!(colours.len() > 50, "{} colours", colours.len());
}

#[test]
fn copies_follow_the_depth_and_straight_rays_change_the_picture() {
    let tmp = temp();
    let (a, b) = (
        tmp.path().join("curved.png"),
        tmp.path().join("straight.png"),
    );
    let common = ["*2222", "--depth", "3", "--size", "80x60", "--no-cull"];
    let Some(curved) = preview(&[&common[..], &["-o", a.to_str().unwrap()]].concat()) else {
        return;
    };
    // *2222: 1 + 4 + 8 + 12 copies up to word length 3.
    assert_eq!(curved["copies"], 25);
    assert_eq!(curved["instances"], 25);
    let hyperbolic = ["*2352", "--size", "80x60", "--attenuation", "universal"];
    preview(&[&hyperbolic[..], &["-o", a.to_str().unwrap()]].concat()).unwrap();
    preview(&[&hyperbolic[..], &["--straight", "-o", b.to_str().unwrap()]].concat()).unwrap();
    let (a, b) = (
        image::open(&a).unwrap().to_rgb8(),
        image::open(&b).unwrap().to_rgb8(),
    );
    let differing = a.pixels().zip(b.pixels()).filter(|(p, q)| p != q).count();
    assert!(differing > 500, "{differing} pixels differ");
}

#[test]
fn time_frames_reports_the_median_frame_time() {
    let tmp = temp();
    let png = tmp.path().join("timed.png");
    let args = ["*2222", "--size", "64x48", "--time-frames", "3"];
    let Some(summary) = preview(&[&args[..], &["-o", png.to_str().unwrap()]].concat()) else {
        return;
    };
    assert_eq!(summary["frames_timed"], 3);
    let ms = summary["frame_ms"].as_f64().unwrap();
    let fps = summary["frames_per_second"].as_f64().unwrap();
    assert!(ms > 0.0 && ms.is_finite(), "{ms} ms");
    assert!(
        (ms * fps - 1e3).abs() < 1e-6 * 1e3,
        "{ms} ms, {fps} frames/s"
    );
    // Without the flag the summary has no timings.
    let Some(plain) = preview(&["*2222", "--size", "64x48", "-o", png.to_str().unwrap()]) else {
        return;
    };
    assert!(plain.get("frame_ms").is_none());
}

fn fails_with_2(args: &[&str], output: &Path, message: &str) {
    let out = orbifold().arg("preview").args(args).output().unwrap();
    assert_eq!(out.status.code(), Some(2), "{args:?}");
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(stderr.contains(message), "{args:?}: {stderr}");
    assert!(!output.exists(), "{} was written", output.display());
}

#[test]
fn bad_input_is_refused_before_anything_is_written() {
    let tmp = temp();
    let png = tmp.path().join("bad.png");
    let out = png.to_str().unwrap();
    fails_with_2(
        &["-o", &png.with_extension("gif").display().to_string()],
        &png.with_extension("gif"),
        ".png or .jpg",
    );
    fails_with_2(&["*23", "-o", out], &png, "bad orbifold");
    fails_with_2(
        &["*333", "--attenuation", "bright", "-o", out],
        &png,
        "expected reflectance",
    );
    fails_with_2(&["*333", "--pitch", "120", "-o", out], &png, "--pitch 120");
    fails_with_2(&["*333", "--size", "0x10", "-o", out], &png, "size");
    fails_with_2(
        &["*333", "--time-frames", "0", "-o", out],
        &png,
        "--time-frames",
    );
    fails_with_2(&["missing.toml", "-o", out], &png, "missing.toml");
}
