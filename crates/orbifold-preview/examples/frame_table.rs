//! Frame time of the real-time preview against triangles and depth, as a Markdown table for
//! docs/benchmarks.md:
//!
//! ```text
//! cargo run --release -p orbifold-preview --example frame_table [-- WxH FRAMES [full]]
//! ```
//!
//! `full` draws every object at full detail in every copy (no levels of detail).
//!
//! Scenes: the seed's Fig. 8.4 pair (`*235` and `*2352` rooms with a dragon,
//! `../shared/models/dragon.ply`, 47,794 triangles, or `$ORBIFOLD_MODELS/dragon.ply`; the built-in
//! figure if it is missing) and the default `*22222` room at growing depths. Each row draws FRAMES frames with the camera turning
//! (so the copies' matrices are rewritten every frame, as when walking in the studio) and reports
//! the median time from submitting a frame until the GPU has finished it.

use std::time::Instant;

use orbifold_preview::{Gpu, Preview};
use orbifold_scene::{Object, Scene};

/// The dragon from `$ORBIFOLD_MODELS/dragon.ply` (default: the workspace's `../shared/models`),
/// so that a binary built here can be run on another machine with the mesh beside it.
fn dragon() -> Option<String> {
    let folder = std::env::var("ORBIFOLD_MODELS").unwrap_or_else(|_| {
        concat!(env!("CARGO_MANIFEST_DIR"), "/../../../shared/models").to_string()
    });
    let path = format!("{folder}/dragon.ply");
    std::path::Path::new(&path).exists().then_some(path)
}

fn scene(signature: &str, depth: u32, model: Option<&str>) -> Scene {
    let mut scene = Scene::default();
    scene.orbifold.signature = signature.into();
    scene.preview.depth = depth;
    let centre = scene.layout().expect("a good signature").centre;
    if let Some(path) = model {
        scene.objects = vec![Object {
            name: Some("dragon".into()),
            mesh: Some(path.into()),
            size: 0.45,
            ..scene.objects[0].clone()
        }];
    }
    scene.objects[0].at = [centre.re, centre.im];
    scene.camera.at = [centre.re - 0.15, centre.im];
    scene.camera.pitch = -10.0;
    scene
}

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let (width, height) = args
        .first()
        .and_then(|s| s.split_once('x'))
        .map_or((1280, 720), |(w, h)| {
            (w.parse().unwrap(), h.parse().unwrap())
        });
    let frames: usize = args.get(1).map_or(30, |s| s.parse().unwrap());
    let lod = args.get(2).is_none_or(|a| a != "full");
    let gpu = Gpu::headless().expect("an adapter");
    let detail = if lod { "on" } else { "off" };
    println!(
        "adapter: {}; {width}x{height}, median of {frames} frames, levels of detail {detail}\n",
        gpu.describe()
    );
    println!(
        "| scene | depth | copies | drawn | triangles drawn | ms / frame | frames / s | M triangles / s |"
    );
    println!("|---|---:|---:|---:|---:|---:|---:|---:|");
    let mut preview = Preview::new(gpu);
    let model = dragon();
    let mut rows: Vec<(String, Scene)> = Vec::new();
    let name = if model.is_some() { "dragon" } else { "figure" };
    for (signature, depth) in [
        ("*235", 0),
        ("*2352", 4),
        ("*2352", 5),
        ("*2352", 6),
        ("*2352", 7),
    ] {
        rows.push((
            format!("`{signature}` + {name}"),
            scene(signature, depth, model.as_deref()),
        ));
    }
    for depth in [2, 4, 6, 8] {
        rows.push(("`*22222` default".into(), scene("*22222", depth, None)));
    }
    for (label, scene) in rows {
        preview.load(&scene, None).expect("the scene loads");
        let mut settings = preview.settings();
        settings.lod = lod;
        preview.set_settings(settings).expect("settings");
        let mut times = Vec::with_capacity(frames);
        for k in 0..frames + 2 {
            let mut camera = scene.camera.clone();
            camera.yaw += k as f64;
            preview.set_camera(&camera);
            let start = Instant::now();
            preview.draw(width, height).expect("a frame");
            preview.finish().expect("the GPU finishes");
            if k >= 2 {
                times.push(start.elapsed().as_secs_f64());
            }
        }
        times.sort_by(f64::total_cmp);
        let median = times[times.len() / 2];
        let stats = preview.stats();
        println!(
            "| {label} | {} | {} | {} | {} | {:.2} | {:.1} | {:.0} |",
            scene.preview.depth,
            stats.copies,
            stats.instances,
            stats.triangles,
            median * 1e3,
            1.0 / median,
            stats.triangles as f64 / median / 1e6
        );
    }
}
