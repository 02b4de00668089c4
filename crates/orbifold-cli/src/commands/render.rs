//! `orbifold render`: a photo-realistic image of a mirror room.

use std::io::Write;
use std::path::PathBuf;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Duration;

use indicatif::{ProgressBar, ProgressStyle};
use orbifold_render::camera::Camera;
use orbifold_render::denoise::{DenoiseOptions, denoise};
use orbifold_render::integrator::{Integrator, Settings};
use orbifold_render::render::{RenderOptions, render};
use orbifold_scene::Scene;
use serde::Serialize;

use crate::args::RenderArgs;
use crate::commands::scene::camera_position;
use crate::error::CliError;
use crate::output;

#[derive(Serialize)]
struct Summary {
    output: String,
    width: u32,
    height: u32,
    samples: u32,
    seconds: f64,
    stopped_early: bool,
    relative_noise: f64,
    dropped_samples: u64,
    exposure: f64,
    denoised: bool,
}

/// The scene to render: a file, the default room of a signature, or the built-in default.
pub(crate) fn load(input: Option<&str>) -> Result<(Scene, Option<PathBuf>), CliError> {
    let Some(input) = input else {
        return Ok((Scene::default(), None));
    };
    let path = std::path::Path::new(input);
    if input.ends_with(".toml") || path.is_file() {
        let scene = Scene::load(path).map_err(|errors| {
            let list: Vec<String> = errors.iter().map(ToString::to_string).collect();
            CliError::Input(list.join("\nerror: "))
        })?;
        return Ok((scene, path.parent().map(std::path::Path::to_path_buf)));
    }
    let signature: orbifold::Signature = input
        .parse()
        .map_err(|e: orbifold::ParseError| CliError::Input(format!("{e}\n{}", e.snippet())))?;
    let mut scene = Scene::default();
    scene.orbifold.signature = signature.to_string();
    let layout = scene.layout().map_err(CliError::Input)?;
    let centre = [layout.centre.re, layout.centre.im];
    scene.objects.iter_mut().for_each(|o| o.at = centre);
    scene.lights.iter_mut().for_each(|l| l.at = centre);
    scene.camera.at = camera_position(&layout);
    Ok((scene, None))
}

pub fn run(args: &RenderArgs) -> Result<(), CliError> {
    let extension = args
        .output
        .extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase);
    if !matches!(extension.as_deref(), Some("png" | "exr" | "jpg" | "jpeg")) {
        return Err(CliError::Input(format!(
            "cannot write {}: the output must end in .png, .exr or .jpg",
            args.output.display()
        )));
    }
    if let Some(t) = args.time_limit
        && !(t.is_finite() && t > 0.0)
    {
        return Err(CliError::Input(format!(
            "--time-limit {t}: expected a positive number of seconds"
        )));
    }
    if let Some(x) = args.noise_target
        && !(x.is_finite() && x > 0.0)
    {
        return Err(CliError::Input(format!(
            "--noise-target {x}: expected a positive number such as 0.02"
        )));
    }
    if let Some(g) = args.glow
        && !(g.is_finite() && g >= 0.0)
    {
        return Err(CliError::Input(format!(
            "--glow {g}: expected a radiance of 0 or more, such as 0.2"
        )));
    }
    let (scene, base) = load(args.input.as_deref())?;
    let settings = Settings {
        max_depth: args.max_depth.unwrap_or(scene.render.max_depth),
        nee: !args.no_nee,
        glow: [args.glow.unwrap_or(0.0); 3],
        straight_rays: args.straight_rays,
    };
    let integrator =
        Integrator::from_scene(&scene, base.as_deref(), settings).map_err(CliError::Input)?;
    let camera = Camera::new(integrator.space(), &scene.camera);
    let (width, height) = args
        .size
        .unwrap_or((scene.render.width, scene.render.height));
    let options = RenderOptions {
        width,
        height,
        samples: args.spp.unwrap_or(scene.render.samples).max(1),
        seed: args.seed,
        time_limit: args.time_limit.map(Duration::from_secs_f64),
        noise_target: args.noise_target,
    };

    let cancel = Arc::new(AtomicBool::new(false));
    {
        let cancel = cancel.clone();
        // A second Ctrl-C is the default: the handler can only be set once per process.
        let _ = ctrlc::set_handler(move || cancel.store(true, Ordering::Relaxed));
    }
    let bar = if args.json {
        ProgressBar::hidden()
    } else {
        ProgressBar::new(u64::from(options.samples))
    };
    bar.set_style(
        ProgressStyle::with_template(
            "{spinner} [{elapsed_precise}] {bar:40} {pos}/{len} spp, {eta} left",
        )
        .expect("a valid template"),
    );
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(args.threads.map_or(0, |n| n as usize))
        .build()
        .map_err(|e| CliError::Input(format!("cannot start threads: {e}")))?;
    let rendered = pool.install(|| {
        render(&integrator, &camera, &options, &cancel, &|done, _| {
            bar.set_position(u64::from(done));
        })
    });
    bar.finish_and_clear();
    let exposure = args
        .exposure
        .unwrap_or_else(|| rendered.film.auto_exposure());
    let denoised = args.denoise || (!args.no_denoise && extension.as_deref() != Some("exr"));
    let image = if denoised {
        denoise(&rendered.film, &rendered.guides, &DenoiseOptions::default())
    } else {
        rendered.film.clone()
    };
    image
        .write(&args.output, exposure)
        .map_err(|e| CliError::Input(format!("cannot write {}: {e}", args.output.display())))?;

    let summary = Summary {
        output: args.output.display().to_string(),
        width,
        height,
        samples: rendered.samples,
        seconds: rendered.elapsed.as_secs_f64(),
        stopped_early: rendered.stopped_early,
        relative_noise: rendered.film.relative_noise(),
        dropped_samples: rendered.film.dropped(),
        exposure,
        denoised,
    };
    let mut out = output::stdout();
    if args.json {
        serde_json::to_writer_pretty(&mut out, &summary)?;
        writeln!(out)?;
    } else {
        writeln!(
            out,
            "wrote {} ({}x{}, {} spp{} in {:.1} s; relative noise {:.4}{})",
            summary.output,
            width,
            height,
            summary.samples,
            if summary.stopped_early {
                ", stopped early"
            } else {
                ""
            },
            summary.seconds,
            summary.relative_noise,
            if denoised { " before denoising" } else { "" }
        )?;
    }
    out.flush()?;
    Ok(())
}
