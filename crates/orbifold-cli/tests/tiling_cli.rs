//! `orbifold tiling` as a process.

use assert_cmd::Command;
use predicates::prelude::*;

fn orbifold() -> Command {
    Command::cargo_bin("orbifold").expect("binary built")
}

#[test]
fn writes_png_and_svg() {
    let tmp = tempfile::Builder::new()
        .prefix("orbifold-tiling-test-")
        .tempdir()
        .unwrap();
    let dir = tmp.path();
    let png = dir.join("t.png");
    orbifold()
        .args(["tiling", "*237", "--size", "64", "-o"])
        .arg(&png)
        .assert()
        .success();
    assert_eq!(&std::fs::read(&png).unwrap()[..8], b"\x89PNG\r\n\x1a\n");
    for (model, sig) in [
        ("klein", "*2∞∞"),
        ("halfplane", "*∞∞∞"),
        ("sphere", "*235"),
        ("euclidean", "*333"),
    ] {
        orbifold()
            .args([
                "tiling", sig, "--size", "48", "--model", model, "--color", "depth", "-o",
            ])
            .arg(&png)
            .assert()
            .success();
    }
    let svg = dir.join("t.svg");
    orbifold()
        .args(["tiling", "*2323", "--depth", "3", "--size", "200", "-o"])
        .arg(&svg)
        .assert()
        .success();
    let text = std::fs::read_to_string(&svg).unwrap();
    assert!(text.starts_with("<svg") && text.trim_end().ends_with("</svg>"));
    // Tiles to depth 3 of *2323, each one path, plus the title and disk.
    assert!(text.matches("<path").count() > 20);
    // A motif.
    let motif = dir.join("motif.png");
    image::RgbaImage::from_fn(4, 4, |x, _| {
        if x < 2 {
            image::Rgba([255, 0, 0, 255])
        } else {
            image::Rgba([0, 0, 255, 255])
        }
    })
    .save(&motif)
    .unwrap();
    orbifold()
        .args(["tiling", "*2222", "--size", "48", "--motif"])
        .arg(&motif)
        .arg("-o")
        .arg(&png)
        .assert()
        .success();
}

#[test]
fn bad_requests_exit_2() {
    let tmp = tempfile::Builder::new()
        .prefix("orbifold-tiling-test-")
        .tempdir()
        .unwrap();
    let out = tmp.path().join("orbifold-tiling-never.png");
    orbifold()
        .args(["tiling", "*237", "--model", "sphere", "-o"])
        .arg(&out)
        .assert()
        .code(2)
        .stderr(predicate::str::contains("does not show"));
    orbifold()
        .args(["tiling", "*23", "-o"])
        .arg(&out)
        .assert()
        .code(2)
        .stderr(predicate::str::contains("bad orbifold"));
    orbifold()
        .args(["tiling", "*237", "-o", "x.gif"])
        .assert()
        .code(2)
        .stderr(predicate::str::contains(".png or .svg"));
    orbifold()
        .args(["tiling", "*237", "--motif", "/nonexistent.png", "-o"])
        .arg(&out)
        .assert()
        .code(2)
        .stderr(predicate::str::contains("cannot read the motif"));
    orbifold()
        .args(["tiling", "*237", "--center", "0.99,0.5", "-o"])
        .arg(&out)
        .assert()
        .code(2);
    orbifold()
        .args(["tiling", "*237", "--zoom", "0", "-o"])
        .arg(&out)
        .assert()
        .code(2);
    assert!(!out.exists());
}
