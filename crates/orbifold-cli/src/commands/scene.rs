//! `orbifold scene`: create, check and show scene files.

use std::io::Write;

use orbifold_scene::Scene;

use crate::args::SceneCommand;
use crate::error::CliError;
use crate::output;

pub fn run(command: &SceneCommand) -> Result<(), CliError> {
    let mut out = output::stdout();
    match command {
        SceneCommand::New { signature, output } => {
            // Objects, lights and camera placed for the new room (orbifold_scene::placement).
            let scene = match signature {
                Some(signature) => Scene::for_signature(signature).map_err(CliError::Input)?,
                None => Scene::default(),
            };
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
