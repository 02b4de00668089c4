//! Scene files that give only a signature: `orbifold scene check`, `room`, `render` and
//! `preview` take them in every geometry, with the camera, object and light placed for the room
//! (`orbifold_scene::placement`), while a camera written outside the room is still refused at
//! its line.

use assert_cmd::Command;
use predicates::prelude::*;

fn orbifold() -> Command {
    Command::cargo_bin("orbifold").unwrap()
}

/// Euclidean, spherical, hyperbolic and ideal-cornered rooms.
const SIGNATURES: [&str; 5] = ["*444", "*235", "*2333", "*∞∞∞", "*2∞3"];

/// A folder holding one signature-only scene file per signature, named by index.
fn scenes() -> tempfile::TempDir {
    let tmp = tempfile::Builder::new()
        .prefix("orbifold-minimal-cli-")
        .tempdir()
        .unwrap();
    for (i, signature) in SIGNATURES.iter().enumerate() {
        let text = format!("[orbifold]\nsignature = \"{signature}\"\n");
        std::fs::write(tmp.path().join(format!("room-{i}.toml")), text).unwrap();
    }
    tmp
}

#[test]
fn signature_only_files_check_mesh_and_render() {
    let tmp = scenes();
    for (i, signature) in SIGNATURES.iter().enumerate() {
        let scene = tmp.path().join(format!("room-{i}.toml"));
        orbifold()
            .args(["scene", "check"])
            .arg(&scene)
            .assert()
            .success()
            .stdout(predicate::str::contains("ok"));
        let obj = tmp.path().join(format!("room-{i}.obj"));
        orbifold()
            .arg("room")
            .arg(&scene)
            .args(["--resolution", "0.3", "-o"])
            .arg(&obj)
            .assert()
            .success();
        assert!(obj.is_file(), "{signature}: no mesh");
        let png = tmp.path().join(format!("room-{i}.png"));
        orbifold()
            .arg("render")
            .arg(&scene)
            .args(["--size", "16x12", "--spp", "1", "-o"])
            .arg(&png)
            .assert()
            .success();
        let image = image::open(&png).unwrap();
        assert_eq!((image.width(), image.height()), (16, 12), "{signature}");
    }
}

#[test]
fn a_signature_only_file_previews_when_there_is_an_adapter() {
    if std::env::var_os("ORBIFOLD_REQUIRE_GPU").is_none()
        && orbifold_preview::Gpu::headless().is_err()
    {
        eprintln!("skipped: no wgpu adapter");
        return;
    }
    let tmp = scenes();
    let scene = tmp.path().join("room-0.toml");
    let png = tmp.path().join("preview.png");
    orbifold()
        .arg("preview")
        .arg(&scene)
        .args(["--size", "32x24", "-o"])
        .arg(&png)
        .assert()
        .success();
    assert!(png.is_file());
}

#[test]
fn a_camera_written_outside_the_room_is_still_an_error_at_its_line() {
    let tmp = scenes();
    let scene = tmp.path().join("outside.toml");
    std::fs::write(
        &scene,
        "[orbifold]\nsignature = \"*444\"\n\n[camera]\nat = [-0.2, 0.0]\n",
    )
    .unwrap();
    orbifold()
        .args(["scene", "check"])
        .arg(&scene)
        .assert()
        .failure()
        .stderr(
            predicate::str::contains("outside.toml:5:").and(predicate::str::contains(
                "camera.at: (-0.2, 0) is not inside the room",
            )),
        );
}
