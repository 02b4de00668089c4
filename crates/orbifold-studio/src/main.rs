//! `orbifold-studio [SCENE.toml] [--screenshot FILE.png]`: the interactive designer.
//!
//! With `--screenshot` the studio draws a few frames, writes a screenshot of its window and
//! quits (used by CI under a virtual display).

use std::path::PathBuf;
use std::process::ExitCode;

use orbifold_studio::Studio;
use orbifold_studio::document::{self, Document};

const HELP: &str = "\
orbifold-studio: design orbifold mirror rooms and see them

Usage: orbifold-studio [SCENE.toml] [--screenshot FILE.png]

Opens SCENE.toml, or the seed's default *22222 room. File > Examples lists the example scenes;
scenes, meshes and images can be dropped on the window. --screenshot writes a picture of the window
after the first frames and quits. Keys: Ctrl+N new, Ctrl+O open, Ctrl+S save, Ctrl+Z undo,
Ctrl+Shift+Z or Ctrl+Y redo; in the 3D view W/S walk, A/D turn, Q/E look up and down, drag to
look around. See docs/guide.md.";

fn main() -> ExitCode {
    let mut scene_path = None;
    let mut screenshot = None;
    let mut args = std::env::args().skip(1);
    while let Some(arg) = args.next() {
        match arg.as_str() {
            "-h" | "--help" => {
                println!("{HELP}");
                return ExitCode::SUCCESS;
            }
            "--screenshot" => match args.next() {
                Some(path) => screenshot = Some(PathBuf::from(path)),
                None => {
                    eprintln!("error: --screenshot needs a file name");
                    return ExitCode::from(2);
                }
            },
            other if other.starts_with('-') => {
                eprintln!("error: unknown option {other}\n\n{HELP}");
                return ExitCode::from(2);
            }
            other => scene_path = Some(PathBuf::from(other)),
        }
    }
    let data = document::data_folder();
    let recovery = data.as_ref().map(|d| d.join("recovery.toml"));
    let recovered = recovery.as_deref().and_then(document::recovered);
    let document = match &scene_path {
        Some(path) => match Document::open(path, recovery.clone()) {
            Ok(d) => d,
            Err(e) => {
                eprintln!("error: cannot open {}: {e}", path.display());
                return ExitCode::from(2);
            }
        },
        None => Document::new(recovery),
    };
    let mut studio = Studio::new(document, data);
    studio.dialogs = Some(Box::new(orbifold_studio::dialogs::NativeDialogs::default()));
    studio.recovered = recovered.filter(|_| screenshot.is_none());
    studio.screenshot = screenshot.map(|p| (p, 8));
    let options = eframe::NativeOptions {
        viewport: egui::ViewportBuilder::default()
            .with_title("orbifold studio")
            .with_inner_size([1440.0, 900.0]),
        ..Default::default()
    };
    match eframe::run_native(
        "orbifold studio",
        options,
        Box::new(|_| Ok(Box::new(studio))),
    ) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: the studio could not start: {e}");
            ExitCode::from(1)
        }
    }
}
