//! The seed's Table 8.1 scenes rendered by our path tracer: how far a fixed time gets.
//!
//! `cargo run --release -p orbifold-render --example table81 -- [--size N] [--seconds T] [--spp N]
//! [--only SIG] [--mesh FILE] [--save DIR] [--uniform] [--raw-target] [--no-footprint]
//! [--no-bounce-footprint] [--no-cache] [--reference T] [--crease DEGREES] [--checkpoints T1,T2,...] [--filter
//! box|gaussian] [--light-candidates N]` (`--save`
//! writes the raw and denoised PNGs of both seeds, the difference of the two denoised images, 8 grey levels a
//! level, the samples each pixel got, and each pixel's own estimate of its raw display noise
//! (16-bit, 256 grey values a level); `--uniform`: no adaptive sampling; `--raw-target`:
//! adaptive sampling aimed at the raw image's noise, not the denoised one's; `--no-footprint`:
//! camera rays without their pixel's footprint; `--no-bounce-footprint`: far light images that
//! light sampling cannot draw, seen after a bounce, found by ray hits alone; `--no-cache`: every path traced in full, without
//! the radiance cache; `--spp N`: N samples a pixel (a mean, with adaptive sampling) instead of
//! a time limit, so that per-sample noise can be compared whatever else the machine runs;
//! `--reference T`: also the error of the first image, raw and denoised,
//! against a reference rendered for T seconds without the radiance cache: the bias of the
//! denoiser and of the cache shows there; `--crease`: the object's crease angle for smooth shading, 0 for flat faces;
//! `--checkpoints`: instead of the table, each room's two seeds rendered to the last of these
//! times, with the denoised noise measured at each of them, and the time after which its 99th
//! percentile is at most 3 levels — the time to a fixed noise level (interpolated between the
//! checkpoints either side, and fitted as a power of t to all of them, which is steadier: the
//! 8-bit percentile moves in steps of about 7 %); `--filter`: the pixel
//! reconstruction filter, the renderer's default Gaussian unless told; `--light-candidates`: the
//! candidates of each resampled light sample, 1 for the plain light sample)
//!
//! The rooms `*`, `*22`, `*222`, `*333`, `*444`, `*2222` and `*3333` as `orbifold scene new`
//! makes them (every wall a mirror of reflectance 0.9, as in the seed), with the Stanford dragon
//! (`../shared/models/dragon.ply`, 47,794 triangles; the built-in figure if it is missing) in
//! the middle, a spherical area light under the ceiling, at most 50 bounces (the seed's
//! maxDepth), an N×N image (896, the seed's size, by default) for T seconds (120 by default) on
//! all threads.
//!
//! Each scene is rendered twice with different seeds. The noise of one image is estimated from
//! the difference of the two, which holds twice its variance: the RMS over pixels and channels
//! of the tone-mapped 8-bit values, divided by √2, in grey levels ("display noise"; random noise
//! of about one level is below what the eye sees in a smooth area). It is given for the raw
//! images and for the denoised ones (`orbifold_render::denoise`; this counts the filter's
//! remaining noise, not its bias). Also: samples per pixel, the renderer's own relative-noise
//! estimate, million paths per second, and million rays per second (a path's geodesic
//! stretches between mirrors: nearest-hit searches and shadow tests).

use std::sync::atomic::AtomicBool;
use std::time::{Duration, Instant};

use orbifold_render::denoise::{DenoiseOptions, Guides, denoise};
use orbifold_render::film::PixelFilter;
use orbifold_render::film::{Film, tone_map};
use orbifold_render::integrator::{Integrator, Settings};
use orbifold_render::render::{Progressive, RenderOptions, render};
use orbifold_scene::{LightKind, Scene};
use orbifold_trace::camera::Camera;
use orbifold_trace::geodesic::Ray;
use orbifold_trace::room::AnalyticRoom;

struct Args {
    size: u32,
    seconds: f64,
    spp: Option<u32>,
    only: Option<String>,
    mesh: Option<String>,
    save: Option<std::path::PathBuf>,
    uniform: bool,
    raw_target: bool,
    no_footprint: bool,
    no_bounce_footprint: bool,
    no_cache: bool,
    light_candidates: Option<u32>,
    reference: Option<f64>,
    crease: Option<f64>,
    checkpoints: Vec<f64>,
    filter: PixelFilter,
}

fn parse_args() -> Args {
    let mut args = Args {
        size: 896,
        seconds: 120.0,
        spp: None,
        only: None,
        mesh: None,
        save: None,
        uniform: false,
        raw_target: false,
        no_footprint: false,
        no_bounce_footprint: false,
        no_cache: false,
        light_candidates: None,
        reference: None,
        crease: None,
        checkpoints: Vec::new(),
        filter: PixelFilter::default(),
    };
    let default_mesh = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../../shared/models/dragon.ply"
    );
    if std::path::Path::new(default_mesh).is_file() {
        args.mesh = Some(default_mesh.into());
    }
    let mut it = std::env::args().skip(1);
    while let Some(a) = it.next() {
        let mut value = || it.next().unwrap_or_else(|| panic!("{a} needs a value"));
        match a.as_str() {
            "--size" => args.size = value().parse().expect("--size N"),
            "--seconds" => args.seconds = value().parse().expect("--seconds T"),
            "--spp" => args.spp = Some(value().parse().expect("--spp N")),
            "--only" => args.only = Some(value()),
            "--mesh" => args.mesh = Some(value()),
            "--save" => args.save = Some(value().into()),
            "--uniform" => args.uniform = true,
            "--raw-target" => args.raw_target = true,
            "--no-footprint" => args.no_footprint = true,
            "--no-bounce-footprint" => args.no_bounce_footprint = true,
            "--no-cache" => args.no_cache = true,
            "--light-candidates" => {
                args.light_candidates =
                    Some(value().parse().expect("--light-candidates takes a count"))
            }
            "--reference" => args.reference = Some(value().parse().expect("--reference T")),
            "--crease" => args.crease = Some(value().parse().expect("--crease DEGREES")),
            "--checkpoints" => {
                args.checkpoints = value()
                    .split(',')
                    .map(|t| t.parse().expect("--checkpoints T1,T2,..."))
                    .collect();
                args.checkpoints.sort_by(f64::total_cmp);
            }
            "--filter" => args.filter = PixelFilter::from_name(&value()).expect("--filter"),
            other => panic!("unknown argument {other}"),
        }
    }
    args
}

fn scene(signature: &str, mesh: Option<&str>, crease: Option<f64>) -> Scene {
    let mut scene = Scene::default();
    scene.orbifold.signature = signature.into();
    let layout = scene.layout().expect("a valid room");
    let centre = [layout.centre.re, layout.centre.im];
    scene.room.reflectance = [0.9; 3];
    let object = &mut scene.objects[0];
    object.at = centre;
    object.size = 0.5;
    if let Some(crease) = crease {
        object.crease = crease;
    }
    if let Some(mesh) = mesh {
        object.mesh = Some(mesh.into());
        object.name = Some("dragon".into());
    }
    let light = &mut scene.lights[0];
    light.kind = LightKind::Sphere;
    light.at = centre;
    light.height = 0.85;
    light.radius = 0.05;
    light.power = 30.0;
    // Three quarters of the way to the −x wall, 20° down, as `orbifold scene new` puts it.
    let space = layout.space();
    let ray = Ray::from_model(space, layout.centre, 0.5, std::f64::consts::PI, 0.0);
    let reach = AnalyticRoom::all_mirrors(&layout, 1.0, [0.9; 3])
        .ok()
        .and_then(|room| room.exit(&ray))
        .map_or(0.3, |exit| 0.75 * exit.s);
    let z = space.to_model(ray.point_at(space, reach).0);
    scene.camera.at = [z.re, z.im];
    scene.render.max_depth = 50;
    scene
}

/// RMS, median and 99th percentile over pixels of |A − B|/√2 in 8-bit levels (mean of the
/// channels per pixel): the noise of one of two independent images.
fn display_noise(a: &Film, b: &Film, exposure: f64) -> (f64, f64, f64) {
    let (rms, median, p99) = display_difference(a, b, exposure);
    let r = std::f64::consts::SQRT_2;
    (rms / r, median / r, p99 / r)
}

/// RMS, median and 99th percentile over pixels of |A − B| in 8-bit levels (mean of the
/// channels per pixel).
fn display_difference(a: &Film, b: &Film, exposure: f64) -> (f64, f64, f64) {
    let mut per_pixel = Vec::new();
    let mut sum = 0.0;
    for y in 0..a.height() {
        for x in 0..a.width() {
            let (p, q) = (
                tone_map(a.pixel(x, y), exposure),
                tone_map(b.pixel(x, y), exposure),
            );
            let d: f64 = (0..3)
                .map(|c| (f64::from(p[c]) - f64::from(q[c])).powi(2))
                .sum::<f64>()
                / 3.0;
            sum += d;
            per_pixel.push(d.sqrt());
        }
    }
    per_pixel.sort_by(f64::total_cmp);
    let rms = (sum / per_pixel.len() as f64).sqrt();
    let quantile = |q: f64| per_pixel[((per_pixel.len() - 1) as f64 * q) as usize];
    (rms, quantile(0.5), quantile(0.99))
}

/// Writes |A − B| (the mean of the channels) as a grey PNG, 8 grey levels per level of
/// difference: where two renders of the same scene disagree.
fn write_difference(a: &Film, b: &Film, exposure: f64, path: &std::path::Path) {
    let grey: Vec<u8> = (0..a.height())
        .flat_map(|y| (0..a.width()).map(move |x| (x, y)))
        .map(|(x, y)| {
            let (p, q) = (
                tone_map(a.pixel(x, y), exposure),
                tone_map(b.pixel(x, y), exposure),
            );
            let d = (0..3).map(|c| f64::from(p[c].abs_diff(q[c]))).sum::<f64>() / 3.0;
            (8.0 * d).min(255.0) as u8
        })
        .collect();
    image::save_buffer(path, &grey, a.width(), a.height(), image::ColorType::L8)
        .expect("the difference is written");
}

/// Writes the samples each pixel got as a grey PNG (white: the most any pixel got).
fn write_samples(film: &Film, path: &std::path::Path) {
    let counts: Vec<u64> = (0..film.height())
        .flat_map(|y| (0..film.width()).map(move |x| film.samples(x, y)))
        .collect();
    let most = counts.iter().copied().max().unwrap_or(1).max(1) as f64;
    let grey: Vec<u8> = counts
        .iter()
        .map(|&n| (255.0 * (n as f64 / most).sqrt()) as u8)
        .collect();
    image::save_buffer(
        path,
        &grey,
        film.width(),
        film.height(),
        image::ColorType::L8,
    )
    .expect("the sample map is written");
}

/// Writes each pixel's own estimate of its display noise ([`Film::display_errors`], one
/// standard error in 8-bit levels) as a 16-bit grey PNG, 256 grey values a level: to set beside
/// the noise measured between two seeds (which also holds what no pixel's error sees, such as
/// the radiance cache's).
fn write_estimated_errors(film: &Film, exposure: f64, path: &std::path::Path) {
    let grey: Vec<u16> = film
        .display_errors(exposure)
        .iter()
        .map(|&e| (256.0 * e).round().clamp(0.0, 65535.0) as u16)
        .collect();
    let buffer =
        image::ImageBuffer::<image::Luma<u16>, _>::from_raw(film.width(), film.height(), grey)
            .expect("one value a pixel");
    buffer.save(path).expect("the error map is written");
}

/// Where the noisiest pixels' noise comes from: for the pixels in the top 1 % of the two
/// denoised images' difference, and for all pixels, the mean squared standard error of each part
/// of the first image's luminance (light seen directly, first light sample, the rest), their
/// paths' mean coherence and samples, and the denoised difference's RMS.
fn noise_parts(da: &Film, db: &Film, film: &Film, guides: &Guides, exposure: f64) -> String {
    let (w, h) = (film.width(), film.height());
    let pixels: Vec<(u32, u32)> = (0..h).flat_map(|y| (0..w).map(move |x| (x, y))).collect();
    let difference: Vec<f64> = pixels
        .iter()
        .map(|&(x, y)| {
            let (p, q) = (
                tone_map(da.pixel(x, y), exposure),
                tone_map(db.pixel(x, y), exposure),
            );
            ((0..3)
                .map(|c| (f64::from(p[c]) - f64::from(q[c])).powi(2))
                .sum::<f64>()
                / 3.0)
                .sqrt()
        })
        .collect();
    let mut sorted = difference.clone();
    sorted.sort_by(f64::total_cmp);
    let threshold = sorted[(sorted.len() - 1) * 99 / 100];
    let summary = |keep: &dyn Fn(usize) -> bool| {
        let (mut n, mut parts, mut coherence, mut samples, mut d2) = (0.0, [0.0; 3], 0.0, 0.0, 0.0);
        for (i, &(x, y)) in pixels.iter().enumerate().filter(|&(i, _)| keep(i)) {
            let (errors, c) = guides.part_errors(x, y);
            for k in 0..3 {
                parts[k] += if errors[k].is_finite() {
                    errors[k] * errors[k]
                } else {
                    0.0
                };
            }
            coherence += c;
            samples += film.samples(x, y) as f64;
            d2 += difference[i] * difference[i];
            n += 1.0;
        }
        format!(
            "squared standard error seen directly / light sample / rest {:.2e} / {:.2e} / {:.2e}, coherence {:.2}, samples {:.0}, denoised difference RMS {:.1}",
            parts[0] / n,
            parts[1] / n,
            parts[2] / n,
            coherence / n,
            samples / n,
            (d2 / n).sqrt() / std::f64::consts::SQRT_2
        )
    };
    format!(
        "|   top 1 % of the denoised difference: {} |\n|   all pixels: {} |",
        summary(&|i| difference[i] >= threshold),
        summary(&|_| true)
    )
}

/// One seed's image at a checkpoint, raw and denoised, with the exposure of the raw one.
struct Checkpoint {
    seconds: f64,
    paths: u64,
    exposure: f64,
    raw: Film,
    denoised: Film,
}

/// Renders one seed round after round to the last of `args.checkpoints` (render time; the
/// denoising at the checkpoints is not counted) and keeps the denoised image at each: the same
/// rounds that `render` with that time limit would have run.
fn render_to_checkpoints(
    args: &Args,
    integrator: &Integrator,
    camera: &Camera,
    seed: u64,
) -> Vec<Checkpoint> {
    let options = RenderOptions {
        width: args.size,
        height: args.size,
        samples: u32::MAX,
        seed,
        time_limit: None,
        noise_target: None,
        adaptive: !args.uniform,
        denoised: !args.raw_target,
        filter: args.filter,
    };
    let mut progressive = Progressive::new(integrator, camera, &options);
    let mut rendering = Duration::ZERO;
    let mut out = Vec::new();
    for &checkpoint in &args.checkpoints {
        while rendering.as_secs_f64() < checkpoint {
            let start = Instant::now();
            progressive.round();
            rendering += start.elapsed();
        }
        out.push(Checkpoint {
            seconds: rendering.as_secs_f64(),
            paths: progressive.paths(),
            exposure: progressive.film().auto_exposure(),
            raw: progressive.film().clone(),
            denoised: denoise(
                progressive.film(),
                progressive.guides(),
                &DenoiseOptions::default(),
            ),
        });
    }
    out
}

/// The denoised noise of one room at each checkpoint, and the time after which its 99th
/// percentile is at most `GOAL_P99` levels: interpolated between the checkpoints on either side
/// of it, or extrapolated from the last two when none reaches it, with the power of t they fell
/// by (slower than 1/√t in these rooms: their worst pixels converge slowly).
fn checkpoint_rows(args: &Args, signature: &str, integrator: &Integrator, camera: &Camera) {
    const GOAL_P99: f64 = 3.0;
    let a = render_to_checkpoints(args, integrator, camera, 1);
    let b = render_to_checkpoints(args, integrator, camera, 2);
    let pixels = f64::from(args.size).powi(2);
    let mut seen: Vec<(f64, f64)> = Vec::new();
    for (x, y) in a.iter().zip(&b) {
        let raw = display_noise(&x.raw, &y.raw, x.exposure);
        let (rms, median, p99) = display_noise(&x.denoised, &y.denoised, x.exposure);
        println!(
            "| `{signature}` | {} | {:.1} | {:.1}, {:.1}, {:.1} | {rms:.2}, {median:.2}, {p99:.2} |",
            seconds(x.seconds),
            x.paths as f64 / pixels,
            raw.0,
            raw.1,
            raw.2,
        );
        seen.push((x.seconds, p99));
    }
    // p99 ∝ t^−a between two checkpoints: the time at which it is GOAL_P99.
    let time_to_goal = |(t0, p0): (f64, f64), (t1, p1): (f64, f64)| {
        let a = (p0 / p1).ln() / (t1 / t0).ln();
        (a > 0.0).then(|| (t1 * (p1 / GOAL_P99).powf(1.0 / a), a))
    };
    let first = seen.iter().position(|&(_, p99)| p99 <= GOAL_P99);
    let line = match first {
        Some(0) => format!("at the first checkpoint, {} s", seconds(seen[0].0)),
        Some(i) => match time_to_goal(seen[i - 1], seen[i]) {
            Some((t, a)) => format!(
                "after about {} s (between {} s and {} s, interpolated as t^−{a:.2})",
                seconds(t),
                seconds(seen[i - 1].0),
                seconds(seen[i].0)
            ),
            None => format!("after {} s", seconds(seen[i].0)),
        },
        None if seen.len() >= 2 => {
            let (t0, t1) = (seen[seen.len() - 2], seen[seen.len() - 1]);
            match time_to_goal(t0, t1) {
                Some((t, a)) => format!(
                    "after about {} s (extrapolated from {} s and {} s as t^−{a:.2})",
                    seconds(t),
                    seconds(t0.0),
                    seconds(t1.0)
                ),
                None => "not reached, and not falling".to_string(),
            }
        }
        None => "not reached".to_string(),
    };
    println!("|   99th percentile ≤ {GOAL_P99}: {line} |");
    // The 8-bit 99th percentile moves in steps of about 7 % (2.89, 3.08, 3.32, … levels), so
    // two checkpoints on either side of the goal can put the time off by ±10 %; a power law
    // fitted to all of them (least squares in log-log) averages the steps out.
    if let Some((t, a)) = power_law_time(&seen, GOAL_P99) {
        println!(
            "|   fitted to all {} checkpoints as p99 ∝ t^−{a:.2}: ≤ {GOAL_P99} after about {} s |",
            seen.len(),
            seconds(t)
        );
    }
}

/// The time at which p ∝ t^−a, fitted by least squares to the (t, p) points in log-log, reaches
/// `goal`, and the fitted a; `None` with fewer than two distinct times or if p does not fall.
fn power_law_time(points: &[(f64, f64)], goal: f64) -> Option<(f64, f64)> {
    let logs: Vec<(f64, f64)> = points
        .iter()
        .filter(|(t, p)| *t > 0.0 && *p > 0.0)
        .map(|(t, p)| (t.ln(), p.ln()))
        .collect();
    let n = logs.len() as f64;
    let (mx, my) = logs
        .iter()
        .fold((0.0, 0.0), |(x, y), (a, b)| (x + a / n, y + b / n));
    let sxx: f64 = logs.iter().map(|(x, _)| (x - mx).powi(2)).sum();
    let sxy: f64 = logs.iter().map(|(x, y)| (x - mx) * (y - my)).sum();
    if logs.len() < 2 || sxx <= 0.0 || sxy >= 0.0 {
        return None;
    }
    let slope = sxy / sxx;
    Some(((mx + (goal.ln() - my) / slope).exp(), -slope))
}

/// Seconds to show: whole ones from 10 s on, tenths below.
fn seconds(t: f64) -> String {
    if t >= 10.0 {
        format!("{t:.0}")
    } else {
        format!("{t:.1}")
    }
}

fn main() {
    let args = parse_args();
    println!(
        "{}×{} for {} s per image, {} threads, object: {}",
        args.size,
        args.size,
        args.seconds,
        rayon::current_num_threads(),
        args.mesh.as_deref().unwrap_or("the built-in figure")
    );
    println!();
    if args.checkpoints.is_empty() {
        println!(
            "| room | geometry | mean spp | relative noise | display noise raw: RMS, median | denoised: RMS, median, 99th percentile | denoise s | M paths/s | M rays/s |"
        );
        println!("|---|---|---:|---:|---:|---:|---:|---:|---:|");
    } else {
        println!(
            "| room | render s | mean spp | raw display noise: RMS, median, 99th percentile | denoised: RMS, median, 99th percentile |"
        );
        println!("|---|---:|---:|---:|---:|");
    }
    for signature in ["*", "*22", "*222", "*333", "*444", "*2222", "*3333"] {
        if args.only.as_deref().is_some_and(|o| o != signature) {
            continue;
        }
        let scene = scene(signature, args.mesh.as_deref(), args.crease);
        let settings = Settings {
            max_depth: 50,
            pixel_footprint: !args.no_footprint,
            bounce_footprint: !args.no_bounce_footprint,
            radiance_cache: !args.no_cache,
            light_candidates: args.light_candidates,
            ..Settings::default()
        };
        let integrator = Integrator::from_scene(&scene, None, settings).expect("the scene builds");
        let camera = Camera::new(integrator.space(), &scene.camera);
        if !args.checkpoints.is_empty() {
            checkpoint_rows(&args, signature, &integrator, &camera);
            continue;
        }
        let run_with = |integrator: &Integrator, seed, seconds: f64| {
            let options = RenderOptions {
                width: args.size,
                height: args.size,
                samples: args.spp.unwrap_or(u32::MAX),
                seed,
                time_limit: args.spp.is_none().then(|| Duration::from_secs_f64(seconds)),
                noise_target: None,
                adaptive: !args.uniform,
                denoised: !args.raw_target,
                filter: args.filter,
            };
            render(
                integrator,
                &camera,
                &options,
                &AtomicBool::new(false),
                &|_, _| {},
            )
        };
        let run = |seed| run_with(&integrator, seed, args.seconds);
        let (a, b) = (run(1), run(2));
        let exposure = a.film.auto_exposure();
        let start = Instant::now();
        let (da, db) = (
            denoise(&a.film, &a.guides, &DenoiseOptions::default()),
            denoise(&b.film, &b.guides, &DenoiseOptions::default()),
        );
        let denoise_seconds = start.elapsed().as_secs_f64() / 2.0;
        let name = if signature == "*" {
            "star".to_string()
        } else {
            signature.replace('*', "star")
        };
        if let Some(dir) = &args.save {
            std::fs::create_dir_all(dir).expect("the --save directory");
            for (film, tag) in [
                (&a.film, "raw"),
                (&b.film, "raw-2"),
                (&da, "denoised"),
                (&db, "denoised-2"),
            ] {
                film.write(&dir.join(format!("{name}-{tag}.png")), exposure)
                    .expect("the image is written");
            }
            write_difference(
                &da,
                &db,
                exposure,
                &dir.join(format!("{name}-difference.png")),
            );
            write_samples(&a.film, &dir.join(format!("{name}-samples.png")));
            write_estimated_errors(
                &a.film,
                exposure,
                &dir.join(format!("{name}-estimated-errors.png")),
            );
        }
        let raw = display_noise(&a.film, &b.film, exposure);
        let clean = display_noise(&da, &db, exposure);
        // Over both seeds' renders: twice the time to average the machine's drift over.
        let elapsed = (a.elapsed + b.elapsed).as_secs_f64();
        let paths = (a.paths + b.paths) as f64 / elapsed;
        let rays = (a.rays + b.rays) as f64 / elapsed;
        println!(
            "| `{signature}` | {:?} | {:.1} | {:.3} | {:.1}, {:.1} | {:.2}, {:.2}, {:.2} | {:.2} | {:.4} | {:.2} |",
            integrator.space().geometry(),
            a.paths as f64 / f64::from(args.size).powi(2),
            a.film.relative_noise(),
            raw.0,
            raw.1,
            clean.0,
            clean.1,
            clean.2,
            denoise_seconds,
            paths / 1e6,
            rays / 1e6
        );
        {
            let mut spp: Vec<u64> = (0..args.size * args.size)
                .map(|p| a.film.samples(p % args.size, p / args.size))
                .collect();
            spp.sort_unstable();
            let q = |f: f64| spp[((spp.len() - 1) as f64 * f) as usize];
            println!(
                "|   samples per pixel: median {}, 90th percentile {}, 99th {}, most {}; raw display noise 99th percentile {:.1} |",
                q(0.5),
                q(0.9),
                q(0.99),
                q(1.0),
                raw.2
            );
        }
        if args.save.is_some() {
            println!("{}", noise_parts(&da, &db, &a.film, &a.guides, exposure));
        }
        if let Some(seconds) = args.reference {
            // The reference traces every path in full: no radiance cache, whose bias shows.
            let full = Integrator::from_scene(
                &scene,
                None,
                Settings {
                    radiance_cache: false,
                    ..settings
                },
            )
            .expect("the scene builds");
            let reference = run_with(&full, 3, seconds);
            let spp = reference.paths as f64 / f64::from(args.size).powi(2);
            if let Some(dir) = &args.save {
                reference
                    .film
                    .write(&dir.join(format!("{name}-reference.png")), exposure)
                    .expect("the reference is written");
            }
            let (raw_error, clean_error) = (
                display_difference(&a.film, &reference.film, exposure),
                display_difference(&da, &reference.film, exposure),
            );
            // The reference is noisy too (and adaptive sampling gives its smooth parts the fewest
            // samples): its own standard error, and what is left of the denoised image's error
            // once both images' noise is taken out, err² − noise² − reference noise².
            let errors = reference.film.display_errors(exposure);
            let reference_noise =
                (errors.iter().map(|e| e * e).sum::<f64>() / errors.len() as f64).sqrt();
            let bias = |error: f64, noise: f64| {
                (error.powi(2) - noise.powi(2) - reference_noise.powi(2))
                    .max(0.0)
                    .sqrt()
            };
            // The raw image's should be about 0: a check of the estimate.
            let (raw_bias, clean_bias) = (bias(raw_error.0, raw.0), bias(clean_error.0, clean.0));
            println!(
                "|   against a {seconds} s reference ({spp:.0} spp, its noise RMS {reference_noise:.1}): raw RMS, median, p99 | {:.1}, {:.1}, {:.1} | denoised | {:.1}, {:.1}, {:.1} | bias RMS ≈ {clean_bias:.1} (raw: {raw_bias:.1}) |",
                raw_error.0, raw_error.1, raw_error.2, clean_error.0, clean_error.1, clean_error.2
            );
        }
    }
}
