//! `orbifold tiling` for every orbifold: symbols with cones, handles, cross-caps and boundaries
//! folded through their side pairings, and kaleidoscopic ones byte for byte as before.

use assert_cmd::Command;
use predicates::prelude::*;

fn orbifold() -> Command {
    Command::cargo_bin("orbifold").expect("binary built")
}

fn tempdir() -> tempfile::TempDir {
    tempfile::Builder::new()
        .prefix("orbifold-tiling-group-test-")
        .tempdir()
        .unwrap()
}

fn draw(symbol: &str, file: &std::path::Path, extra: &[&str]) -> Vec<u8> {
    orbifold()
        .args(["tiling", symbol, "--size", "64", "-o"])
        .arg(file)
        .args(extra)
        .assert()
        .success()
        .stdout(predicate::str::contains("wrote"));
    std::fs::read(file).unwrap()
}

#[test]
fn writes_png_and_svg_for_rotations_glides_and_boundaries() {
    let tmp = tempdir();
    for symbol in ["632", "22×", "4*3", "o", "**", "*×", "2223", "532", "3×"] {
        let png = draw(symbol, &tmp.path().join("t.png"), &[]);
        let image = image::load_from_memory(&png).unwrap().to_rgba8();
        assert_eq!(image.dimensions(), (64, 64), "{symbol}");
        // More than one colour: tiles, edges and the letter are drawn.
        let first = image.get_pixel(0, 0);
        assert!(image.pixels().any(|p| p != first), "{symbol} is blank");
        let svg = String::from_utf8(draw(symbol, &tmp.path().join("t.svg"), &[])).unwrap();
        assert!(svg.starts_with("<svg") && svg.trim_end().ends_with("</svg>"));
        assert!(svg.matches("<path").count() > 1, "{symbol}: tiles");
        // Every one of these has paired edges: their arrows are drawn.
        assert!(svg.contains("marker-end"), "{symbol}: arrows");
    }
}

#[test]
fn pairings_are_drawn_with_letters_and_mirrors_apart() {
    let tmp = tempdir();
    let svg = String::from_utf8(draw("4*3", &tmp.path().join("t.svg"), &[])).unwrap();
    // 4*3: two legs paired by the rotation (one letter, two arrows), a mirror base.
    assert_eq!(svg.matches("marker-end").count(), 2);
    assert!(svg.contains(">a</text>"));
    assert!(svg.contains("#1f6fd1"), "the mirror edge");
}

#[test]
fn rotation_groups_differ_from_reflection_groups() {
    let tmp = tempdir();
    for (a, b) in [
        ("632", "*632"),
        ("22×", "*2222"),
        ("2222", "*2222"),
        ("333", "3*3"),
    ] {
        let one = draw(a, &tmp.path().join("a.png"), &[]);
        let two = draw(b, &tmp.path().join("b.png"), &[]);
        assert_ne!(one, two, "{a} vs {b}");
    }
}

#[test]
fn colourings_and_models_apply() {
    let tmp = tempdir();
    let f = tmp.path().join("t.png");
    let parity = draw("2223", &f, &[]);
    let depth = draw("2223", &f, &["--color", "depth"]);
    let pair = draw("2223", &f, &["--color", "wall"]);
    assert!(parity != depth && depth != pair && parity != pair);
    draw("2223", &f, &["--model", "klein"]);
    draw("2223", &f, &["--model", "halfplane"]);
    draw("532", &f, &["--model", "sphere"]);
    draw("22×", &f, &["--zoom", "0.5", "--center", "0.3,0.1"]);
}

#[test]
fn a_motif_replaces_the_letter() {
    let tmp = tempdir();
    let motif = tmp.path().join("motif.png");
    // Red on the left, blue on the right.
    image::RgbaImage::from_fn(4, 4, |x, _| {
        image::Rgba(if x < 2 {
            [255, 0, 0, 255]
        } else {
            [0, 0, 255, 255]
        })
    })
    .save(&motif)
    .unwrap();
    let png = draw(
        "22×",
        &tmp.path().join("t.png"),
        &["--motif", motif.to_str().unwrap()][..],
    );
    let image = image::load_from_memory(&png).unwrap().to_rgba8();
    let has = |c: [u8; 3]| image.pixels().any(|p| p.0[..3] == c);
    assert!(has([255, 0, 0]) && has([0, 0, 255]));
    // The letter's ink is not drawn over a motif.
    assert!(!has([192, 57, 43]));
}

#[test]
fn kaleidoscopic_pictures_are_unchanged() {
    // Written by the binary before every symbol was accepted (fixtures/tiling).
    let tmp = tempdir();
    let fixtures = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures/tiling");
    for (symbol, file, extra) in [
        ("*237", "star237.png", &[][..]),
        ("*2222", "star2222-wall.png", &["--color", "wall"][..]),
        (
            "*235",
            "star235-sphere.png",
            &["--model", "sphere", "--color", "depth"][..],
        ),
    ] {
        let ours = draw(symbol, &tmp.path().join("t.png"), extra);
        assert_eq!(
            ours,
            std::fs::read(fixtures.join(file)).unwrap(),
            "{symbol}"
        );
    }
    let svg = tmp.path().join("t.svg");
    orbifold()
        .args(["tiling", "*333", "--size", "120", "--depth", "3", "-o"])
        .arg(&svg)
        .assert()
        .success();
    assert_eq!(
        std::fs::read(&svg).unwrap(),
        std::fs::read(fixtures.join("star333.svg")).unwrap()
    );
}

#[test]
fn bad_symbols_are_refused_clearly() {
    let tmp = tempdir();
    let out = tmp.path().join("never.png");
    for (symbol, message) in [
        ("23", "not a good orbifold"),
        ("5", "not a good orbifold"),
        ("xyz", "invalid signature"),
    ] {
        orbifold()
            .args(["tiling", symbol, "-o"])
            .arg(&out)
            .assert()
            .code(2)
            .stderr(predicate::str::contains(message));
    }
    orbifold()
        .args(["tiling", "632", "--model", "poincare", "-o"])
        .arg(&out)
        .assert()
        .code(2)
        .stderr(predicate::str::contains("does not show"));
    // Every model of the plane draws as SVG, kaleidoscopic symbols too.
    for (symbol, model) in [
        ("2223", "klein"),
        ("2223", "halfplane"),
        ("532", "sphere"),
        ("*237", "halfplane"),
    ] {
        let svg = tmp.path().join(format!("{model}.svg"));
        orbifold()
            .args(["tiling", symbol, "--model", model, "--depth", "4", "-o"])
            .arg(&svg)
            .assert()
            .success();
        let text = std::fs::read_to_string(&svg).unwrap();
        assert!(
            text.contains("<path") && !text.contains("NaN"),
            "{symbol} {model}"
        );
    }
    orbifold()
        .args(["tiling", "22×", "-o", "x.gif"])
        .assert()
        .code(2)
        .stderr(predicate::str::contains(".png or .svg"));
    assert!(!out.exists());
}
