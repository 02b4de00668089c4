//! `orbifold render` as a process: images of the right size in PNG and EXR, the same image for
//! the same seed, the time limit, and clear errors with exit code 2 and no file left behind.

use std::path::{Path, PathBuf};

use assert_cmd::Command;
use predicates::prelude::*;
use serde_json::Value;

fn orbifold() -> Command {
    Command::cargo_bin("orbifold").unwrap()
}

fn scenes() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/scenes")
}

/// A fresh folder for a test's files, removed when the test ends (also when it fails).
fn temp() -> tempfile::TempDir {
    tempfile::Builder::new()
        .prefix("orbifold-render-cli-")
        .tempdir()
        .unwrap()
}

fn render(args: &[&str]) -> Value {
    let out = orbifold()
        .arg("render")
        .args(args)
        .arg("--json")
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{args:?}: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    serde_json::from_slice(&out.stdout).unwrap()
}

#[test]
fn renders_the_default_scene_to_png() {
    let tmp = temp();
    let png = tmp.path().join("default.png");
    let summary = render(&["-o", png.to_str().unwrap(), "--size", "24x16", "--spp", "2"]);
    assert_eq!(summary["width"], 24);
    assert_eq!(summary["samples"], 2);
    assert_eq!(summary["dropped_samples"], 0);
    // Every pixel's two paths; each traces at least its camera ray, and the mirrors more.
    assert_eq!(summary["paths"], 24 * 16 * 2);
    assert!(summary["rays"].as_u64().unwrap() > 2 * 24 * 16 * 2);
    let image = image::open(&png).unwrap();
    assert_eq!((image.width(), image.height()), (24, 16));
    // Not a black picture: the figure, the floor and the light's images are lit.
    assert!(
        image
            .to_rgb8()
            .pixels()
            .any(|p| p.0.iter().any(|&c| c > 20))
    );
}

#[test]
fn a_scene_file_renders_to_exr_and_a_seed_repeats() {
    let scene = scenes().join("fig-1.2-333.toml");
    let tmp = temp();
    let a = tmp.path().join("a.exr");
    let b = tmp.path().join("b.exr");
    for path in [&a, &b] {
        render(&[
            scene.to_str().unwrap(),
            "-o",
            path.to_str().unwrap(),
            "--size",
            "16x12",
            "--spp",
            "2",
            "--seed",
            "7",
            "--threads",
            "1",
        ]);
    }
    assert_eq!(std::fs::read(&a).unwrap(), std::fs::read(&b).unwrap());
    let image = exr::prelude::read_first_rgba_layer_from_file(
        &a,
        |resolution, _| vec![[0f32; 3]; resolution.width() * resolution.height()],
        |pixels: &mut Vec<[f32; 3]>, position, (r, g, b, _): (f32, f32, f32, f32)| {
            pixels[position.y() * 16 + position.x()] = [r, g, b];
        },
    )
    .unwrap();
    let pixels = &image.layer_data.channel_data.pixels;
    assert_eq!(pixels.len(), 16 * 12);
    assert!(
        pixels
            .iter()
            .all(|p| p.iter().all(|c| c.is_finite() && *c >= 0.0))
    );
    assert!(pixels.iter().any(|p| p[1] > 0.0));
}

#[test]
fn a_signature_and_the_time_limit() {
    let tmp = temp();
    let png = tmp.path().join("sig.png");
    let summary = render(&[
        "*2223",
        "-o",
        png.to_str().unwrap(),
        "--size",
        "8x8",
        "--spp",
        "100000",
        "--time-limit",
        "0.2",
    ]);
    assert_eq!(summary["stopped_early"], true);
    assert!(summary["samples"].as_u64().unwrap() < 100000);
    assert!(png.exists());
}

#[test]
fn bad_input_is_a_clear_error_and_writes_nothing() {
    let tmp = temp();
    let out = tmp.path().join("never.png");
    for (args, message) in [
        (vec!["*23"], "bad orbifold"),
        (vec!["*2223", "-o", "x.bmp"], ".png, .exr or .jpg"),
        (vec!["*2223", "--size", "0x10"], "between 1 and 16384"),
        (
            vec!["*2223", "--time-limit", "-1"],
            "positive number of seconds",
        ),
        (vec!["missing.toml"], "missing.toml"),
        (vec!["*2223", "--filter", "mitchell"], "box, gaussian"),
    ] {
        let mut command = orbifold();
        command.arg("render").args(&args);
        if !args.contains(&"-o") {
            command.args(["-o", out.to_str().unwrap()]);
        }
        command
            .assert()
            .code(2)
            .stderr(predicate::str::contains(message));
    }
    assert!(!out.exists());
}

#[test]
fn denoising_is_the_default_for_png_and_jpeg_only_and_straight_rays_render() {
    let tmp = temp();
    let png = tmp.path().join("denoised.png");
    let summary = render(&[
        "*2223",
        "-o",
        png.to_str().unwrap(),
        "--size",
        "12x8",
        "--spp",
        "2",
    ]);
    assert_eq!(summary["denoised"], true);
    let raw = render(&[
        "*2223",
        "-o",
        png.to_str().unwrap(),
        "--size",
        "12x8",
        "--spp",
        "2",
        "--no-denoise",
    ]);
    assert_eq!(raw["denoised"], false);
    let exr = tmp.path().join("raw.exr");
    let summary = render(&[
        "*2223",
        "-o",
        exr.to_str().unwrap(),
        "--size",
        "12x8",
        "--spp",
        "2",
    ]);
    assert_eq!(summary["denoised"], false);
    let summary = render(&[
        "*2223",
        "-o",
        exr.to_str().unwrap(),
        "--size",
        "12x8",
        "--spp",
        "2",
        "--denoise",
        "--straight-rays",
    ]);
    assert_eq!(summary["denoised"], true);
    orbifold()
        .args(["render", "--denoise", "--no-denoise"])
        .assert()
        .code(2)
        .stderr(predicate::str::contains("cannot be used with"));
}

#[test]
fn a_scene_s_render_table_can_ask_for_straight_rays() {
    // fig-8.1-a-straight.toml is fig-1.2-444.toml with `straight_rays = true` in `[render]`.
    let tmp = temp();
    let picture = |scene: &str, name: &str, flags: &[&str]| {
        let out = tmp.path().join(name);
        let path = scenes().join(scene);
        let mut args = vec![
            path.to_str().unwrap(),
            "-o",
            out.to_str().unwrap(),
            "--size",
            "24x16",
            "--spp",
            "2",
            "--no-denoise",
        ];
        args.extend_from_slice(flags);
        render(&args);
        std::fs::read(&out).unwrap()
    };
    let from_the_table = picture("fig-8.1-a-straight.toml", "table.png", &[]);
    let from_the_flag = picture("fig-1.2-444.toml", "flag.png", &["--straight-rays"]);
    let geodesics = picture("fig-1.2-444.toml", "geodesics.png", &[]);
    assert_eq!(from_the_table, from_the_flag);
    assert_ne!(from_the_table, geodesics);
}

/// Renders the default room twice with the same seed (24×16, `spp` samples, raw), the second
/// time with `flag`, and checks that the two images differ.
fn assert_flag_changes_the_image(flag: &str, spp: u32) {
    let name = flag.trim_start_matches('-');
    let tmp = temp();
    let (a, b) = (
        tmp.path().join(format!("with-{name}.png")),
        tmp.path().join(format!("{name}.png")),
    );
    let args = |out: &PathBuf| {
        vec![
            "-o".to_string(),
            out.to_str().unwrap().to_string(),
            "--size".into(),
            "24x16".into(),
            "--spp".into(),
            spp.to_string(),
            "--no-denoise".into(),
        ]
    };
    let with: Vec<String> = args(&a);
    let mut without = args(&b);
    without.push(flag.into());
    render(&with.iter().map(String::as_str).collect::<Vec<_>>());
    render(&without.iter().map(String::as_str).collect::<Vec<_>>());
    let (a, b) = (image::open(&a).unwrap(), image::open(&b).unwrap());
    assert_eq!((a.width(), a.height()), (b.width(), b.height()));
    assert_ne!(a.to_rgb8().into_raw(), b.to_rgb8().into_raw(), "{flag}");
}

#[test]
fn no_footprint_renders_without_the_pixel_footprint() {
    // The default room's checkerboard floor is filtered over each pixel's footprint; without it
    // the floor is point-sampled, so the same seed gives another image.
    assert_flag_changes_the_image("--no-footprint", 2);
}

#[test]
fn no_radiance_cache_traces_every_path_in_full() {
    // From the second pass on, far surfaces and the ends of diffuse bounces read the radiance
    // cache; without it every path is traced in full, so the same seed gives another image.
    assert_flag_changes_the_image("--no-radiance-cache", 4);
}

#[test]
fn the_box_filter_is_sharper_than_the_default_gaussian() {
    // The same seed and samples, each sample counted for its own pixel only: another image, and
    // the summary says which filter made it.
    assert_flag_changes_the_image("--filter=box", 2);
    let tmp = temp();
    let png = tmp.path().join("box.png");
    let out = png.to_str().unwrap();
    for (args, filter) in [(vec![], "gaussian"), (vec!["--filter", "box"], "box")] {
        let mut all = vec!["-o", out, "--size", "16x12", "--spp", "1"];
        all.extend(args);
        assert_eq!(render(&all)["filter"], filter);
    }
}

#[test]
fn a_scene_s_render_table_names_its_filter_and_the_flag_overrides_it() {
    let tmp = temp();
    let base = std::fs::read_to_string(scenes().join("default.toml")).unwrap();
    let scene = |name: &str, filter: &str| {
        let path = tmp.path().join(name);
        std::fs::write(&path, format!("{base}\n[render]\nfilter = \"{filter}\"\n")).unwrap();
        path
    };
    let (boxed, gaussian) = (scene("box.toml", "box"), scene("gaussian.toml", "gaussian"));
    let png = tmp.path().join("out.png");
    let summary = |scene: &PathBuf, flags: &[&str]| {
        let mut args = vec![scene.to_str().unwrap(), "-o", png.to_str().unwrap()];
        args.extend_from_slice(&["--size", "16x12", "--spp", "1"]);
        args.extend_from_slice(flags);
        render(&args)["filter"].as_str().unwrap().to_string()
    };
    assert_eq!(summary(&boxed, &[]), "box");
    assert_eq!(summary(&gaussian, &[]), "gaussian");
    assert_eq!(summary(&boxed, &["--filter", "gaussian"]), "gaussian");
    // A filter the scene format does not know is an error that names the field.
    let bad = scene("bad.toml", "mitchell");
    orbifold()
        .arg("render")
        .arg(&bad)
        .args(["-o", png.to_str().unwrap()])
        .assert()
        .code(2)
        .stderr(predicate::str::contains("mitchell"));
}

/// `orbifold render` makes its picture with the library's one render pipeline
/// (`orbifold_render::render::render_picture`): a scene rendered by the command line with its
/// default settings is, byte for byte, the pipeline's picture of that scene and camera (the
/// studio's render tab is checked against the same pipeline in its own tests).
#[test]
fn the_command_line_picture_is_the_library_pipeline_s() {
    use orbifold_render::integrator::{Integrator, Settings};
    use orbifold_render::render::{RenderOptions, render_picture};
    use orbifold_trace::camera::Camera;

    let tmp = temp();
    let input = scenes().join("fig-1.2-333.toml");
    let cli = tmp.path().join("cli.png");
    render(&[
        input.to_str().unwrap(),
        "-o",
        cli.to_str().unwrap(),
        "--size",
        "40x30",
        "--spp",
        "4",
    ]);
    let scene = orbifold_scene::Scene::load(&input).unwrap();
    let integrator =
        Integrator::from_scene(&scene, input.parent(), Settings::of_scene(&scene)).unwrap();
    let camera = Camera::new(integrator.space(), &scene.camera);
    let options = RenderOptions {
        denoised: true,
        filter: scene.render.filter.into(),
        ..RenderOptions::new(40, 30, 4, 0)
    };
    let stop = std::sync::atomic::AtomicBool::new(false);
    let picture = render_picture(&integrator, &camera, &options, None, &stop, &|_, _| {});
    assert!(picture.denoised);
    let library = tmp.path().join("library.png");
    picture.write(&library).unwrap();
    assert!(std::fs::read(&cli).unwrap() == std::fs::read(&library).unwrap());
}
