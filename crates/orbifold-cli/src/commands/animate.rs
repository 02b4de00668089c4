//! `orbifold animate`: the frames of a walk, an orbit, a turn or a keyframed path, restartable
//! and in slices.

use std::io::Write;
use std::path::{Path as FilePath, PathBuf};
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Instant;

use indicatif::{ProgressBar, ProgressStyle};
use num_complex::Complex64;
use orbifold::Layout;
use orbifold_render::integrator::{Integrator, Settings};
use orbifold_render::render::{RenderOptions, render, render_picture};
use orbifold_scene::Scene;
use orbifold_scene::animation::{Path, Pose};
use orbifold_trace::camera::Camera;
use serde::Serialize;

use crate::args::AnimateArgs;
use crate::commands::render::{check_image_args, load, settings_and_options, thread_pool};
use crate::error::CliError;
use crate::output;

/// Frames of a built-in path unless `--count` says otherwise.
const DEFAULT_FRAMES: u32 = 120;

/// What moves along the path.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Walker {
    Camera,
    Object(usize),
}

#[derive(Serialize)]
struct FrameLine {
    frame: u32,
    output: String,
    skipped: bool,
    seconds: f64,
    samples: u32,
    relative_noise: Option<f64>,
}

#[derive(Serialize)]
struct SummaryLine {
    frames: u32,
    rendered: u32,
    skipped: u32,
    seconds: f64,
    exposure: Option<f64>,
}

fn read_path(text: &str) -> Result<Path, CliError> {
    match text {
        "walls" => Ok(Path::Walls),
        "orbit" => Ok(Path::Orbit),
        "turn" => Ok(Path::Turn),
        file => {
            let contents = std::fs::read_to_string(file).map_err(|e| {
                CliError::Input(format!(
                    "--path {file}: not walls, orbit or turn, and cannot read it as a keyframe \
                     file: {e}"
                ))
            })?;
            Path::parse_keyframes(&contents).map_err(|e| CliError::Input(format!("{file}: {e}")))
        }
    }
}

fn find_walker(scene: &Scene, name: &str) -> Result<Walker, CliError> {
    if name == "camera" {
        return Ok(Walker::Camera);
    }
    let by_name = scene
        .objects
        .iter()
        .position(|o| o.name.as_deref() == Some(name));
    let by_index = name
        .parse::<usize>()
        .ok()
        .filter(|&i| i < scene.objects.len());
    by_name.or(by_index).map(Walker::Object).ok_or_else(|| {
        let names: Vec<String> = scene
            .objects
            .iter()
            .enumerate()
            .map(|(i, o)| o.name.clone().unwrap_or_else(|| i.to_string()))
            .collect();
        CliError::Input(format!(
            "--walker {name}: no such object (the scene has: camera{}{})",
            if names.is_empty() { "" } else { ", " },
            names.join(", ")
        ))
    })
}

fn start_pose(scene: &Scene, walker: Walker) -> Pose {
    match walker {
        Walker::Camera => Pose {
            at: scene.camera.at,
            height: scene.camera.height,
            yaw: scene.camera.yaw,
            pitch: scene.camera.pitch,
        },
        Walker::Object(i) => Pose {
            at: scene.objects[i].at,
            height: scene.objects[i].height,
            yaw: scene.objects[i].yaw,
            pitch: 0.0,
        },
    }
}

fn inside(layout: &Layout, at: [f64; 2]) -> bool {
    let space = layout.space();
    let z = Complex64::new(at[0], at[1]);
    if !(z.re.is_finite() && z.im.is_finite()) || (space.kappa() < 0.0 && z.norm() >= 1.0) {
        return false;
    }
    let p = space.to_ambient(z);
    layout.edges.iter().all(|e| e.wall.dot(p) > 0.0)
}

/// The scene of frame `index`: the walker moved to its pose.
fn frame_scene(
    scene: &Scene,
    layout: &Layout,
    path: &Path,
    walker: Walker,
    (index, count): (u32, u32),
) -> Result<Scene, CliError> {
    let pose = path.pose(
        layout,
        start_pose(scene, walker),
        index as usize,
        count as usize,
    );
    if !inside(layout, pose.at) {
        return Err(CliError::Input(format!(
            "frame {index}: the path leaves the room at ({:.4}, {:.4})",
            pose.at[0], pose.at[1]
        )));
    }
    let mut scene = scene.clone();
    match walker {
        Walker::Camera => {
            let camera = &mut scene.camera;
            (camera.at, camera.height, camera.yaw, camera.pitch) =
                (pose.at, pose.height, pose.yaw, pose.pitch);
        }
        Walker::Object(i) => {
            let object = &mut scene.objects[i];
            (object.at, object.height, object.yaw) = (pose.at, pose.height, pose.yaw);
        }
    }
    Ok(scene)
}

fn check_numbers(args: &AnimateArgs) -> Result<String, CliError> {
    let format = args.format.to_ascii_lowercase();
    if !matches!(format.as_str(), "png" | "jpg" | "exr") {
        return Err(CliError::Input(format!(
            "--format {}: expected png, jpg or exr",
            args.format
        )));
    }
    check_image_args(&args.image)?;
    Ok(format)
}

/// Everything that stays the same from frame to frame.
struct Job {
    scene: Scene,
    base: Option<PathBuf>,
    layout: Layout,
    path: Path,
    walker: Walker,
    count: u32,
    settings: Settings,
    options: RenderOptions,
}

impl Job {
    fn integrator(&self, scene: &Scene) -> Result<Integrator, CliError> {
        Integrator::from_scene(scene, self.base.as_deref(), self.settings).map_err(CliError::Input)
    }

    /// A small render of frame 0 whose log-average sets the exposure of every frame.
    fn exposure(&self, cancel: &AtomicBool) -> Result<f64, CliError> {
        let scene = frame_scene(
            &self.scene,
            &self.layout,
            &self.path,
            self.walker,
            (0, self.count),
        )?;
        let integrator = self.integrator(&scene)?;
        let camera = Camera::new(integrator.space(), &scene.camera);
        let aspect = f64::from(self.options.width) / f64::from(self.options.height.max(1));
        let options = RenderOptions {
            width: 64,
            height: ((64.0 / aspect).round() as u32).clamp(1, 256),
            samples: 8,
            time_limit: None,
            noise_target: None,
            ..self.options
        };
        let rendered = render(&integrator, &camera, &options, cancel, &|_, _| {});
        Ok(rendered.film.auto_exposure())
    }
}

fn frame_file(dir: &FilePath, index: u32, format: &str) -> PathBuf {
    dir.join(format!("frame-{index:05}.{format}"))
}

pub fn run(args: &AnimateArgs) -> Result<(), CliError> {
    let format = check_numbers(args)?;
    let (scene, base) = load(args.input.as_deref())?;
    let layout = scene.layout().map_err(CliError::Input)?;
    let path = read_path(&args.path)?;
    let walker = find_walker(&scene, &args.walker)?;
    let count = args.count.unwrap_or(match &path {
        Path::Keyframes(keys) => keys.len() as u32,
        _ => DEFAULT_FRAMES,
    });
    let (first, last) = args.frames.unwrap_or((0, count - 1));
    if last >= count {
        return Err(CliError::Input(format!(
            "--frames {first}..{last}: the animation has frames 0 to {}",
            count - 1
        )));
    }
    let (settings, options) = settings_and_options(&args.image, &scene, &format);
    let job = Job {
        settings,
        options,
        scene,
        base,
        layout,
        path,
        walker,
        count,
    };
    // Every frame's pose is checked before any time is spent rendering.
    for index in first..=last {
        frame_scene(&job.scene, &job.layout, &job.path, walker, (index, count))?;
    }
    std::fs::create_dir_all(&args.output)
        .map_err(|e| CliError::Input(format!("cannot create {}: {e}", args.output.display())))?;

    let cancel = Arc::new(AtomicBool::new(false));
    {
        let cancel = cancel.clone();
        let _ = ctrlc::set_handler(move || cancel.store(true, Ordering::Relaxed));
    }
    let pool = thread_pool(args.image.threads)?;
    pool.install(|| animate(args, &job, &format, (first, last), &cancel))
}

fn animate(
    args: &AnimateArgs,
    job: &Job,
    format: &str,
    (first, last): (u32, u32),
    cancel: &AtomicBool,
) -> Result<(), CliError> {
    let start = Instant::now();
    let todo: Vec<u32> = (first..=last)
        .filter(|&i| args.force || !frame_file(&args.output, i, format).exists())
        .collect();
    let exposure = match args.image.exposure {
        Some(e) => Some(e),
        None if !todo.is_empty() && format != "exr" => Some(job.exposure(cancel)?),
        None => None,
    };
    let bar = if args.json {
        ProgressBar::hidden()
    } else {
        ProgressBar::new(todo.len() as u64 * u64::from(job.options.samples))
    };
    bar.set_style(
        ProgressStyle::with_template("{spinner} [{elapsed_precise}] {bar:40} {msg}, {eta} left")
            .expect("a valid template"),
    );
    let shared = match job.walker {
        Walker::Camera => Some(job.integrator(&job.scene)?),
        Walker::Object(_) => None,
    };
    let mut out = output::stdout();
    let (mut rendered, mut skipped) = (0, 0);
    for index in first..=last {
        let file = frame_file(&args.output, index, format);
        if !todo.contains(&index) {
            skipped += 1;
            report(
                &mut out,
                args.json,
                &FrameLine {
                    frame: index,
                    output: file.display().to_string(),
                    skipped: true,
                    seconds: 0.0,
                    samples: 0,
                    relative_noise: None,
                },
            )?;
            continue;
        }
        let scene = frame_scene(
            &job.scene,
            &job.layout,
            &job.path,
            job.walker,
            (index, job.count),
        )?;
        let own;
        let integrator = match &shared {
            Some(integrator) => integrator,
            None => {
                own = job.integrator(&scene)?;
                &own
            }
        };
        let camera = Camera::new(integrator.space(), &scene.camera);
        bar.set_message(format!("frame {index} of {first}..{last}"));
        let done_before = bar.position();
        // Every frame at one exposure, so that the animation does not flicker (an EXR's
        // exposure is unused).
        let picture = render_picture(
            integrator,
            &camera,
            &job.options,
            Some(exposure.unwrap_or(0.0)),
            cancel,
            &|done, _| bar.set_position(done_before + u64::from(done)),
        );
        bar.set_position(done_before + u64::from(job.options.samples));
        if cancel.load(Ordering::Relaxed) {
            bar.finish_and_clear();
            return Err(CliError::Interrupted(format!(
                "stopped: {rendered} frames written, frame {index} was not; run the same command \
                 again to go on"
            )));
        }
        picture
            .write(&file)
            .map_err(|e| CliError::Input(format!("cannot write {}: {e}", file.display())))?;
        rendered += 1;
        bar.suspend(|| {
            report(
                &mut out,
                args.json,
                &FrameLine {
                    frame: index,
                    output: file.display().to_string(),
                    skipped: false,
                    seconds: picture.rendered.elapsed.as_secs_f64(),
                    samples: picture.rendered.samples,
                    relative_noise: Some(picture.rendered.film.relative_noise()),
                },
            )
        })?;
    }
    bar.finish_and_clear();
    let summary = SummaryLine {
        frames: last - first + 1,
        rendered,
        skipped,
        seconds: start.elapsed().as_secs_f64(),
        exposure,
    };
    if args.json {
        serde_json::to_writer(&mut out, &summary)?;
        writeln!(out)?;
    } else {
        writeln!(
            out,
            "frames {first}..{last}: {rendered} rendered, {skipped} already there, in {:.1} s",
            summary.seconds
        )?;
    }
    out.flush()?;
    Ok(())
}

fn report(out: &mut impl Write, json: bool, line: &FrameLine) -> Result<(), CliError> {
    if json {
        serde_json::to_writer(&mut *out, line)?;
        writeln!(out)?;
    } else if line.skipped {
        writeln!(
            out,
            "frame {}: {} is already there",
            line.frame, line.output
        )?;
    } else {
        writeln!(
            out,
            "frame {}: wrote {} ({} spp in {:.1} s; relative noise {:.4})",
            line.frame,
            line.output,
            line.samples,
            line.seconds,
            line.relative_noise.unwrap_or(f64::NAN)
        )?;
    }
    Ok(())
}
