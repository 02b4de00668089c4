//! Files dropped on the window: a scene file opens, a mesh becomes a new object at the room's
//! centre, and an image goes onto the surface the room panel names ("dropped images go on").
//! Anything else is reported on the status line and left alone.

use std::path::{Path, PathBuf};

use crate::dialogs::{FileKind, kind_of};

/// What to do with one dropped file.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Dropped {
    /// Open this scene file.
    Scene(PathBuf),
    /// Add an object made from this mesh file.
    Mesh(PathBuf),
    /// Put this image on the chosen surface.
    Texture(PathBuf),
    /// A file the studio does not take (why, for the status line).
    Refused(String),
}

/// What the files dropped in this frame ask for, in order. (In a browser a dropped file's
/// path is its name only: the web build reads such files itself.)
pub fn dropped(ctx: &egui::Context) -> Vec<Dropped> {
    if cfg!(target_arch = "wasm32") {
        // Names without a file system behind them: the web build (orbifold-web) reads the bytes.
        return Vec::new();
    }
    let files = ctx.input(|i| i.raw.dropped_files.clone());
    files.iter().map(|file| classify(file.path())).collect()
}

/// What a dropped file at `path` asks for, by its extension.
///
/// ```
/// use std::path::PathBuf;
/// use orbifold_studio::drop::{Dropped, classify};
/// assert_eq!(classify("a/room.toml".as_ref()), Dropped::Scene(PathBuf::from("a/room.toml")));
/// assert!(matches!(classify("notes.txt".as_ref()), Dropped::Refused(_)));
/// ```
pub fn classify(path: &Path) -> Dropped {
    match kind_of(path) {
        Some(FileKind::Scene) => Dropped::Scene(path.to_path_buf()),
        Some(FileKind::Mesh) => Dropped::Mesh(path.to_path_buf()),
        Some(FileKind::Texture) => Dropped::Texture(path.to_path_buf()),
        None => Dropped::Refused(format!(
            "cannot take {}: drop a scene (.toml), a mesh (.obj, .ply, .gltf, .glb) or an \
             image (.png, .jpg)",
            path.display()
        )),
    }
}
