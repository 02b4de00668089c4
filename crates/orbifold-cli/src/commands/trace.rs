//! `orbifold trace`: follow one geodesic ray through a mirror room, or write a camera's AOVs.

use std::io::Write;

use num_complex::Complex64;
use orbifold_scene::Scene;
use orbifold_trace::aov;
use orbifold_trace::camera::Camera;
use orbifold_trace::geodesic::Ray;
use orbifold_trace::tracer::{PathEnd, Tracer};
use serde::Serialize;

use crate::args::TraceArgs;
use crate::commands::room::load;
use crate::error::CliError;
use crate::output;

#[derive(Serialize)]
struct HitJson {
    surface: String,
    mirror: bool,
    /// `mirror`, `portal` (the ray went on from wall `to`), or `surface` (where it ended).
    kind: &'static str,
    #[serde(skip_serializing_if = "Option::is_none")]
    to: Option<usize>,
    x: f64,
    y: f64,
    h: f64,
    s: f64,
    throughput: [f64; 3],
}

#[derive(Serialize)]
struct TraceJson {
    hits: Vec<HitJson>,
    end: &'static str,
}

pub fn run(args: &TraceArgs) -> Result<(), CliError> {
    let (mut scene, base) = load(&args.input)?;
    let bare = base.is_none() && !args.input.ends_with(".toml");
    if let Some(h) = args.height {
        scene.room.height = h;
    }
    if let Some([x, y, h]) = args.from {
        scene.camera.at = [x, y];
        scene.camera.height = h;
    }
    if let Some(yaw) = args.yaw {
        scene.camera.yaw = yaw;
    }
    if let Some(pitch) = args.pitch {
        scene.camera.pitch = pitch;
    }
    let tracer = if bare {
        let layout = scene.layout().map_err(CliError::Input)?;
        Tracer::mirror_room(layout, scene.room.height)
    } else {
        Tracer::from_scene(&scene, base.as_deref())
    }
    .map_err(CliError::Input)?;
    check_inside(&tracer, &scene)?;
    if let Some(path) = &args.aov {
        return write_aovs(&tracer, &scene, args, path);
    }
    if args.from.is_none() && bare {
        return Err(CliError::Input(
            "give the ray's start with --from x,y,h (and its direction with --yaw and --pitch)"
                .into(),
        ));
    }
    let space = tracer.space();
    let camera = &scene.camera;
    let ray = Ray::from_model(
        space,
        Complex64::new(camera.at[0], camera.at[1]),
        camera.height,
        camera.yaw.to_radians(),
        camera.pitch.to_radians(),
    );
    let path = tracer.follow(&ray, args.bounces);
    let hits: Vec<HitJson> = path
        .hits
        .iter()
        .map(|h| {
            let z = space.to_model(h.hit.point);
            HitJson {
                surface: tracer.surface_name(h.hit.surface),
                mirror: h.mirror.is_some(),
                kind: match (h.mirror, h.portal) {
                    (Some(_), _) => "mirror",
                    (None, Some(_)) => "portal",
                    (None, None) => "surface",
                },
                to: h.portal,
                x: z.re,
                y: z.im,
                h: h.hit.height,
                s: h.s,
                throughput: h.throughput,
            }
        })
        .collect();
    let end = match path.end {
        PathEnd::Surface => "surface",
        PathEnd::BounceLimit => "bounce limit",
        PathEnd::Escaped => "escaped",
    };
    let mut out = output::stdout();
    if args.json {
        serde_json::to_writer_pretty(&mut out, &TraceJson { hits, end })?;
        writeln!(out)?;
    } else {
        writeln!(
            out,
            "{}  {}  from ({}, {}) at height {}, yaw {}°, pitch {}°",
            tracer.layout.symbol,
            tracer.layout.model_name(),
            camera.at[0],
            camera.at[1],
            camera.height,
            camera.yaw,
            camera.pitch
        )?;
        writeln!(
            out,
            "{:>4}  {:<16} {:<9} {:>12} {:>12} {:>10} {:>12}",
            "#", "surface", "passes", "x", "y", "h", "s"
        )?;
        for (k, h) in hits.iter().enumerate() {
            writeln!(
                out,
                "{:>4}  {:<16} {:<9} {:>12.8} {:>12.8} {:>10.6} {:>12.8}",
                k + 1,
                h.surface,
                match h.to {
                    Some(to) => format!("→ wall {to}"),
                    None if h.mirror => "mirror".into(),
                    None => "-".into(),
                },
                h.x,
                h.y,
                h.h,
                h.s
            )?;
        }
        let why = match path.end {
            PathEnd::Surface => "at the last surface".to_string(),
            PathEnd::BounceLimit => {
                format!("after {} mirrors and portals (--bounces)", args.bounces)
            }
            PathEnd::Escaped => "running out through an ideal corner".to_string(),
        };
        writeln!(out, "ended {why}")?;
    }
    out.flush()?;
    Ok(())
}

/// The start must be inside the room.
fn check_inside(tracer: &Tracer, scene: &Scene) -> Result<(), CliError> {
    let space = tracer.space();
    let [x, y] = scene.camera.at;
    let p = space.to_ambient(Complex64::new(x, y));
    if !(x.is_finite() && y.is_finite() && tracer.room.contains(p, scene.camera.height, 1e-12)) {
        return Err(CliError::Input(format!(
            "the start ({x}, {y}) at height {} is not inside the room of {} (the polygon of \
             `orbifold layout`, heights 0 to {})",
            scene.camera.height, tracer.layout.symbol, tracer.room.height
        )));
    }
    Ok(())
}

fn write_aovs(
    tracer: &Tracer,
    scene: &Scene,
    args: &TraceArgs,
    path: &std::path::Path,
) -> Result<(), CliError> {
    if !path
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("exr"))
    {
        return Err(CliError::Input(format!(
            "the AOV file must end in .exr, not {}",
            path.display()
        )));
    }
    let camera = Camera::new(tracer.space(), &scene.camera);
    let (w, h) = args.size;
    let aovs = aov::render(tracer, &camera, w, h, args.bounces);
    let bytes = aovs
        .to_exr()
        .map_err(|e| CliError::Io(std::io::Error::other(e)))?;
    output::write_atomic(path, &bytes)?;
    let hit = aovs.surface.iter().filter(|&&s| s >= 0).count();
    let mut out = output::stdout();
    if args.json {
        serde_json::to_writer_pretty(
            &mut out,
            &serde_json::json!({"file": path.display().to_string(), "width": w, "height": h,
                "pixels_on_a_surface": hit}),
        )?;
        writeln!(out)?;
    } else {
        writeln!(
            out,
            "wrote {} ({w}×{h}: Z, P, N, id, bounces); {hit} of {} pixels end on a surface",
            path.display(),
            w * h
        )?;
    }
    out.flush()?;
    Ok(())
}
