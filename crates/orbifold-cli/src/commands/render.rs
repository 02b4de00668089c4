//! `orbifold render`: a photo-realistic image of a mirror room.

use std::path::PathBuf;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Duration;

use indicatif::{ProgressBar, ProgressStyle};
use orbifold_render::integrator::{Integrator, Settings};
use orbifold_render::render::{RenderOptions, render_picture};
use orbifold_scene::Scene;
use orbifold_trace::camera::Camera;
use serde::Serialize;

use crate::args::{ImageArgs, RenderArgs};
use crate::error::CliError;
use crate::output;

#[derive(Serialize)]
struct Summary {
    output: String,
    width: u32,
    height: u32,
    samples: u32,
    paths: u64,
    rays: u64,
    seconds: f64,
    stopped_early: bool,
    relative_noise: f64,
    dropped_samples: u64,
    exposure: f64,
    denoised: bool,
    /// The pixel reconstruction filter's name.
    filter: &'static str,
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
    let signature: orbifold::OrbifoldSymbol = input
        .parse()
        .map_err(|e: orbifold::ParseError| CliError::Input(format!("{e}\n{}", e.snippet())))?;
    let scene = Scene::for_signature(&signature.to_string()).map_err(CliError::Input)?;
    Ok((scene, None))
}

/// Checks the numbers of the shared image options.
pub(crate) fn check_image_args(args: &ImageArgs) -> Result<(), CliError> {
    let bad = |option: &str, value: f64, wanted: &str| {
        Err(CliError::Input(format!(
            "{option} {value}: expected {wanted}"
        )))
    };
    match (args.time_limit, args.noise_target, args.glow) {
        (Some(t), _, _) if !(t.is_finite() && t > 0.0) => {
            bad("--time-limit", t, "a positive number of seconds")
        }
        (_, Some(x), _) if !(x.is_finite() && x > 0.0) => {
            bad("--noise-target", x, "a positive number such as 0.02")
        }
        (_, _, Some(g)) if !(g.is_finite() && g >= 0.0) => {
            bad("--glow", g, "a radiance of 0 or more, such as 0.2")
        }
        _ => Ok(()),
    }
}

/// The light transport settings and render options of the shared image options, with the
/// scene's `[render]` table for what they leave out, for an image written as `extension` (lower
/// case): when it will be denoised (PNG and JPEG by default), adaptive sampling aims at the
/// denoised image's noise.
pub(crate) fn settings_and_options(
    args: &ImageArgs,
    scene: &Scene,
    extension: &str,
) -> (Settings, RenderOptions) {
    let of_scene = Settings::of_scene(scene);
    let settings = Settings {
        max_depth: args.max_depth.unwrap_or(of_scene.max_depth),
        nee: !args.no_nee,
        glow: [args.glow.unwrap_or(0.0); 3],
        straight_rays: args.straight_rays || of_scene.straight_rays,
        pixel_footprint: !args.no_footprint,
        bounce_footprint: !args.no_footprint,
        radiance_cache: !args.no_radiance_cache,
        light_candidates: args.light_candidates,
    };
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
        adaptive: !args.no_adaptive,
        denoised: denoises(args, extension),
        filter: args.filter.unwrap_or(scene.render.filter.into()),
    };
    (settings, options)
}

/// Whether to denoise an image written with this extension (lower case).
fn denoises(args: &ImageArgs, extension: &str) -> bool {
    args.denoise || (!args.no_denoise && extension != "exr")
}

/// A pool of `threads` workers (all cores when absent).
pub(crate) fn thread_pool(threads: Option<u32>) -> Result<rayon::ThreadPool, CliError> {
    rayon::ThreadPoolBuilder::new()
        .num_threads(threads.map_or(0, |n| n as usize))
        .build()
        .map_err(|e| CliError::Input(format!("cannot start threads: {e}")))
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
    check_image_args(&args.image)?;
    let (scene, base) = load(args.input.as_deref())?;
    let (settings, options) =
        settings_and_options(&args.image, &scene, extension.as_deref().unwrap_or(""));
    let (width, height) = (options.width, options.height);
    let integrator =
        Integrator::from_scene(&scene, base.as_deref(), settings).map_err(CliError::Input)?;
    let camera = Camera::new(integrator.space(), &scene.camera);

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
    let pool = thread_pool(args.image.threads)?;
    let picture = pool.install(|| {
        render_picture(
            &integrator,
            &camera,
            &options,
            args.image.exposure,
            &cancel,
            &|done, _| bar.set_position(u64::from(done)),
        )
    });
    bar.finish_and_clear();
    picture
        .write(&args.output)
        .map_err(|e| CliError::Input(format!("cannot write {}: {e}", args.output.display())))?;
    let (rendered, exposure, denoised) = (&picture.rendered, picture.exposure, picture.denoised);

    let summary = Summary {
        output: args.output.display().to_string(),
        width,
        height,
        samples: rendered.samples,
        paths: rendered.paths,
        rays: rendered.rays,
        seconds: rendered.elapsed.as_secs_f64(),
        stopped_early: rendered.stopped_early,
        relative_noise: rendered.film.relative_noise(),
        dropped_samples: rendered.film.dropped(),
        exposure,
        denoised,
        filter: options.filter.name(),
    };
    output::summary(args.json, &summary, || {
        format!(
            "wrote {} ({}x{}, {} spp{} in {:.1} s, {:.2} M rays/s; relative noise {:.4}{})",
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
            summary.rays as f64 / summary.seconds.max(1e-9) / 1e6,
            summary.relative_noise,
            if denoised { " before denoising" } else { "" }
        )
    })
}
