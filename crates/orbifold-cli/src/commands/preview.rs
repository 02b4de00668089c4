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
    /// With `--time-frames`: the frames timed and their median time.
    #[serde(skip_serializing_if = "Option::is_none")]
    frames_timed: Option<u32>,
    #[serde(skip_serializing_if = "Option::is_none")]
    frame_ms: Option<f64>,
    #[serde(skip_serializing_if = "Option::is_none")]
    frames_per_second: Option<f64>,
}

/// The median time of `frames` frames, from submitting each until the GPU has finished it,
/// with the camera turning a degree a frame.
fn time_frames(
    preview: &mut Preview,
    camera: &orbifold_scene::Camera,
    frames: u32,
    (width, height): (u32, u32),
) -> Result<f64, CliError> {
    let runtime = |e: PreviewError| CliError::Runtime(e.to_string());
    let mut times = Vec::with_capacity(frames as usize);
    for k in 0..frames {
        let mut turned = camera.clone();
        turned.yaw += f64::from(k + 1);
        preview.set_camera(&turned);
        let start = Instant::now();
        preview.draw(width, height).map_err(runtime)?;
        preview.finish().map_err(runtime)?;
        times.push(start.elapsed().as_secs_f64());
    }
    times.sort_by(f64::total_cmp);
    Ok(times[times.len() / 2])
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
    for unread in preview.unread_textures() {
        eprintln!("warning: {unread}; the preview draws its parts in their plain colour");
    }
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
    let seconds = start.elapsed().as_secs_f64();
    // The picture's own counts, before the timed frames turn the camera.
    let stats = preview.stats();
    let median = match args.time_frames {
        Some(frames) => Some(time_frames(
            &mut preview,
            &scene.camera,
            frames,
            (width, height),
        )?),
        None => None,
    };
    let summary = Summary {
        output: args.output.display().to_string(),
        width,
        height,
        adapter,
        copies: stats.copies,
        instances: stats.instances,
        triangles_per_copy: stats.triangles_per_copy,
        triangles: stats.triangles,
        seconds,
        frames_timed: args.time_frames,
        frame_ms: median.map(|m| m * 1e3),
        frames_per_second: median.map(|m| 1.0 / m),
    };
    output::summary(args.json, &summary, || {
        let mut text = format!(
            "wrote {} ({}x{}: {} copies, {} drawn, {} triangles, on {}, {:.2} s)",
            summary.output,
            width,
            height,
            summary.copies,
            summary.instances,
            summary.triangles,
            summary.adapter,
            summary.seconds
        );
        if let (Some(n), Some(ms), Some(fps)) = (
            summary.frames_timed,
            summary.frame_ms,
            summary.frames_per_second,
        ) {
            text += &format!("\n{ms:.2} ms a frame, {fps:.1} frames/s (median of {n} frames)");
        }
        text
    })
}
