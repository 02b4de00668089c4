//! `orbifold scene`: create, check and show scene files.

use std::io::Write;

use orbifold_scene::Scene;

use crate::args::SceneCommand;
use crate::error::CliError;
use crate::output;

/// Where a new scene's camera stands: on the −x side of the centre, three quarters of the way to
/// the wall, so that it looks across the room at the object in the middle rather than from
/// inside it.
pub(crate) fn camera_position(layout: &orbifold::Layout) -> [f64; 2] {
    let space = layout.space();
    let inside = |t: f64| {
        let z = layout.centre - t;
        (space.kappa() >= 0.0 || z.norm() < 1.0)
            && layout
                .edges
                .iter()
                .all(|e| e.wall.dot(space.to_ambient(z)) > 0.0)
    };
    // The model distance to the wall by bisection; rooms open to infinity stop at 1.
    let (mut lo, mut hi) = (0.0, 1.0);
    if inside(hi) {
        lo = hi;
    } else {
        for _ in 0..60 {
            let mid = 0.5 * (lo + hi);
            if inside(mid) {
                lo = mid;
            } else {
                hi = mid;
            }
        }
    }
    [layout.centre.re - 0.75 * lo, layout.centre.im]
}

pub fn run(command: &SceneCommand) -> Result<(), CliError> {
    let mut out = output::stdout();
    match command {
        SceneCommand::New { signature, output } => {
            let mut scene = Scene::default();
            if let Some(signature) = signature {
                scene.orbifold.signature = signature.clone();
                // Keep the default objects, lights and camera only where they fit the new room.
                let layout = scene.layout().map_err(CliError::Input)?;
                let centre = [layout.centre.re, layout.centre.im];
                scene.objects.iter_mut().for_each(|o| o.at = centre);
                scene.lights.iter_mut().for_each(|l| l.at = centre);
                scene.camera.at = camera_position(&layout);
            }
            let text = scene.to_toml();
            if let Err(errors) = Scene::from_toml(&text, None) {
                let list: Vec<String> = errors.iter().map(ToString::to_string).collect();
                return Err(CliError::Input(list.join("\n")));
            }
            orbifold_scene::write_atomic(output, text.as_bytes())
                .map_err(|e| CliError::Input(format!("cannot write {}: {e}", output.display())))?;
            writeln!(out, "wrote {}", output.display())?;
        }
        SceneCommand::Check { files } => {
            let mut problems = Vec::new();
            for file in files {
                match Scene::load(file) {
                    Ok(_) => writeln!(out, "{}: ok", file.display())?,
                    Err(errors) => problems.extend(errors.iter().map(ToString::to_string)),
                }
            }
            out.flush()?;
            if !problems.is_empty() {
                return Err(CliError::Input(problems.join("\nerror: ")));
            }
        }
        SceneCommand::Show { file, json } => {
            let scene = Scene::load(file).map_err(|errors| {
                let list: Vec<String> = errors.iter().map(ToString::to_string).collect();
                CliError::Input(list.join("\nerror: "))
            })?;
            if *json {
                let value = serde_json::to_value(&scene)
                    .map_err(|e| CliError::Input(format!("cannot write the scene as JSON: {e}")))?;
                writeln!(
                    out,
                    "{}",
                    serde_json::to_string_pretty(&value).unwrap_or_default()
                )?;
            } else {
                write!(out, "{}", scene.to_toml())?;
            }
        }
    }
    out.flush()?;
    Ok(())
}
