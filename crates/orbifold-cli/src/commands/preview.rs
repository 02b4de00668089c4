//! `orbifold preview`: one frame of the real-time preview, drawn offscreen.

use std::time::Instant;

use orbifold_preview::{Gpu, Preview, PreviewError, Projection, Settings};
use serde::Serialize;

use crate::args::PreviewArgs;
use crate::commands::render::load;
use crate::error::CliError;
use crate::output;

#[derive(Serialize)]
struct Summary {
    output: String,
    width: u32,
    height: u32,
    adapter: String,
    copies: usize,
    instances: usize,
    triangles_per_copy: usize,
    triangles: usize,
    seconds: f64,
}

pub fn run(args: &PreviewArgs) -> Result<(), CliError> {
    let extension = args
        .output
        .extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase);
    if !matches!(extension.as_deref(), Some("png" | "jpg" | "jpeg")) {
        return Err(CliError::Input(format!(
            "cannot write {}: the preview writes .png or .jpg pictures",
            args.output.display()
        )));
    }
    let (width, height) = args.size;
    let (mut scene, base) = load(args.input.as_deref())?;
    if let Some(yaw) = args.yaw {
        scene.camera.yaw = yaw;
    }
    if let Some(pitch) = args.pitch {
        if !(-90.0..=90.0).contains(&pitch) {
            return Err(CliError::Input(format!(
                "--pitch {pitch}: expected an elevation from -90 to 90 degrees"
            )));
        }
        scene.camera.pitch = pitch;
    }
    let start = Instant::now();
    // No adapter is the machine's fault, not the input's: exit code 1.
    let gpu = Gpu::headless().map_err(|e| CliError::Runtime(e.to_string()))?;
    let adapter = gpu.describe();
    let mut preview = Preview::new(gpu);
    preview
        .load(&scene, base.as_deref())
        .map_err(|e| CliError::Input(e.to_string()))?;
    preview
        .set_settings(Settings {
            depth: args.depth.unwrap_or(scene.preview.depth),
            attenuation: args.attenuation.unwrap_or(scene.preview.attenuation),
            projection: if args.straight {
                Projection::Straight
            } else {
                Projection::Curved
            },
            cull: !args.no_cull,
            turns: preview.settings().turns,
            lod: !args.no_lod,
        })
        .map_err(|e| CliError::Input(e.to_string()))?;
    let frame = preview.render(width, height).map_err(|e| match e {
        PreviewError::Size(..) => CliError::Input(e.to_string()),
        other => CliError::Runtime(other.to_string()),
    })?;
    frame
        .save_png(&args.output)
        .map_err(|e| CliError::Io(std::io::Error::other(e.to_string())))?;
    let stats = preview.stats();
    let summary = Summary {
        output: args.output.display().to_string(),
        width,
        height,
        adapter,
        copies: stats.copies,
        instances: stats.instances,
        triangles_per_copy: stats.triangles_per_copy,
        triangles: stats.triangles,
        seconds: start.elapsed().as_secs_f64(),
    };
    output::summary(args.json, &summary, || {
        format!(
            "wrote {} ({}x{}: {} copies, {} drawn, {} triangles, on {}, {:.2} s)",
            summary.output,
            width,
            height,
            summary.copies,
            summary.instances,
            summary.triangles,
            summary.adapter,
            summary.seconds
        )
    })
}
