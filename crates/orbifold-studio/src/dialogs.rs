//! File dialogs: opening and saving scenes, saving the rendered picture, and picking a mesh or
//! a texture for the room panel.
//!
//! The studio asks through the [`FileDialogs`] trait, so that each platform supplies its own:
//! the desktop build the system's dialogs ([`NativeDialogs`], the `rfd` crate), the web build
//! the browser's file picker and downloads (`orbifold-web`), the tests a scripted fake that
//! answers with paths, and a build without any the studio's own window in which a path is typed
//! (`Studio::dialogs` left `None`).
//!
//! A dialog may answer later: the browser's file picker returns at once and hands the file over
//! when the user has chosen it. Such dialogs return `None` and the platform gives the studio the
//! file afterwards with `Studio::answer`, which remembers what was asked (and for which
//! surface). Dialogs that hand the files over themselves (a download in place of a path to
//! write to) say so with [`FileDialogs::hands_files_over`]: then the studio asks them whenever
//! it saves, even when the document already has a file.

use std::path::{Path, PathBuf};

/// The file types a scene file may have.
pub const SCENE_EXTENSIONS: [&str; 1] = ["toml"];
/// The mesh files an object can be made from (`orbifold_scene::mesh::import`).
pub const MESH_EXTENSIONS: [&str; 4] = ["obj", "ply", "gltf", "glb"];
/// The image files a texture can be (the `image` crate's decoders the scene crate enables).
pub const TEXTURE_EXTENSIONS: [&str; 3] = ["png", "jpg", "jpeg"];
/// The picture files a render can be saved as: the shown picture (PNG, JPEG) or its HDR image.
pub const PICTURE_EXTENSIONS: [&str; 4] = ["png", "jpg", "jpeg", "exr"];

/// What a dialog asks for.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Request {
    /// A scene file to open.
    OpenScene,
    /// Where to save the scene.
    SaveScene,
    /// Where to save the rendered picture.
    SavePicture,
    /// A mesh file for a new object.
    PickMesh,
    /// An image for the texture of a surface.
    PickTexture,
}

/// The file dialogs the studio uses. Each returns the chosen path, or `None` when the user
/// cancelled. They are called between frames, never while a panel is being drawn.
///
/// ```
/// use std::path::{Path, PathBuf};
/// use orbifold_studio::dialogs::FileDialogs;
/// /// Answers every question with one path.
/// struct Always(PathBuf);
/// impl FileDialogs for Always {
///     fn open_scene(&mut self) -> Option<PathBuf> { Some(self.0.clone()) }
///     fn save_scene(&mut self, _: &Path) -> Option<PathBuf> { Some(self.0.clone()) }
///     fn save_picture(&mut self, _: &Path) -> Option<PathBuf> { Some(self.0.clone()) }
///     fn pick_mesh(&mut self) -> Option<PathBuf> { Some(self.0.clone()) }
///     fn pick_texture(&mut self) -> Option<PathBuf> { Some(self.0.clone()) }
/// }
/// let mut dialogs = Always("room.toml".into());
/// assert_eq!(dialogs.open_scene(), Some(PathBuf::from("room.toml")));
/// ```
pub trait FileDialogs {
    /// A scene file to open.
    fn open_scene(&mut self) -> Option<PathBuf>;
    /// Where to save the scene; `suggested` is the current file or a default name.
    fn save_scene(&mut self, suggested: &Path) -> Option<PathBuf>;
    /// Where to save the rendered picture (PNG or JPEG as shown, EXR for the HDR image, by
    /// the extension); `suggested` is a default name next to the scene.
    fn save_picture(&mut self, suggested: &Path) -> Option<PathBuf>;
    /// A mesh file for a new object.
    fn pick_mesh(&mut self) -> Option<PathBuf>;
    /// An image for a surface's texture.
    fn pick_texture(&mut self) -> Option<PathBuf>;

    /// Whether these dialogs hand the saved files over themselves (the browser's downloads),
    /// so that the studio never writes to a path: then **Save** asks them every time, as
    /// **Save As…** does. `false` unless a platform says otherwise.
    ///
    /// ```
    /// use std::path::{Path, PathBuf};
    /// use orbifold_studio::dialogs::FileDialogs;
    /// struct Cancelling;
    /// impl FileDialogs for Cancelling {
    ///     fn open_scene(&mut self) -> Option<PathBuf> { None }
    ///     fn save_scene(&mut self, _: &Path) -> Option<PathBuf> { None }
    ///     fn save_picture(&mut self, _: &Path) -> Option<PathBuf> { None }
    ///     fn pick_mesh(&mut self) -> Option<PathBuf> { None }
    ///     fn pick_texture(&mut self) -> Option<PathBuf> { None }
    /// }
    /// assert!(!Cancelling.hands_files_over());
    /// ```
    fn hands_files_over(&self) -> bool {
        false
    }

    /// Asks what `request` asks for (`suggested` matters for saving only).
    fn ask(&mut self, request: Request, suggested: &Path) -> Option<PathBuf> {
        match request {
            Request::OpenScene => self.open_scene(),
            Request::SaveScene => self.save_scene(suggested),
            Request::SavePicture => self.save_picture(suggested),
            Request::PickMesh => self.pick_mesh(),
            Request::PickTexture => self.pick_texture(),
        }
    }
}

/// The system's file dialogs (GTK, the XDG desktop portal, Windows or macOS), through `rfd`.
#[cfg(not(target_arch = "wasm32"))]
#[derive(Clone, Debug, Default)]
pub struct NativeDialogs {
    /// The folder the next dialog starts in: the last one chosen.
    folder: Option<PathBuf>,
}

#[cfg(not(target_arch = "wasm32"))]
impl NativeDialogs {
    fn dialog(&self, title: &str, filter: &str, extensions: &[&str]) -> rfd::FileDialog {
        let dialog = rfd::FileDialog::new()
            .set_title(title)
            .add_filter(filter, extensions);
        match &self.folder {
            Some(folder) => dialog.set_directory(folder),
            None => dialog,
        }
    }

    fn chosen(&mut self, path: Option<PathBuf>) -> Option<PathBuf> {
        if let Some(folder) = path.as_deref().and_then(Path::parent) {
            self.folder = Some(folder.to_path_buf());
        }
        path
    }

    fn save(
        &mut self,
        title: &str,
        filter: &str,
        extensions: &[&str],
        suggested: &Path,
    ) -> Option<PathBuf> {
        let mut dialog = self.dialog(title, filter, extensions);
        if let Some(folder) = suggested.parent().filter(|f| f.is_dir()) {
            dialog = dialog.set_directory(folder);
        }
        if let Some(name) = suggested.file_name() {
            dialog = dialog.set_file_name(name.to_string_lossy());
        }
        let path = dialog.save_file();
        self.chosen(path)
    }
}

#[cfg(not(target_arch = "wasm32"))]
impl FileDialogs for NativeDialogs {
    fn open_scene(&mut self) -> Option<PathBuf> {
        let path = self
            .dialog("Open a scene", "scene", &SCENE_EXTENSIONS)
            .pick_file();
        self.chosen(path)
    }

    fn save_scene(&mut self, suggested: &Path) -> Option<PathBuf> {
        self.save("Save the scene as", "scene", &SCENE_EXTENSIONS, suggested)
    }

    fn save_picture(&mut self, suggested: &Path) -> Option<PathBuf> {
        self.save(
            "Save the picture as",
            "picture (PNG, JPEG or EXR)",
            &PICTURE_EXTENSIONS,
            suggested,
        )
    }

    fn pick_mesh(&mut self) -> Option<PathBuf> {
        let path = self
            .dialog("Pick a mesh", "mesh (OBJ, PLY, glTF)", &MESH_EXTENSIONS)
            .pick_file();
        self.chosen(path)
    }

    fn pick_texture(&mut self) -> Option<PathBuf> {
        let path = self
            .dialog("Pick a texture", "image (PNG, JPEG)", &TEXTURE_EXTENSIONS)
            .pick_file();
        self.chosen(path)
    }
}

/// What kind of file a path is, by its extension (case-insensitive): the kinds of
/// [`SCENE_EXTENSIONS`], [`MESH_EXTENSIONS`] and [`TEXTURE_EXTENSIONS`].
///
/// ```
/// use orbifold_studio::dialogs::{FileKind, kind_of};
/// assert_eq!(kind_of("room.TOML".as_ref()), Some(FileKind::Scene));
/// assert_eq!(kind_of("bunny.ply".as_ref()), Some(FileKind::Mesh));
/// assert_eq!(kind_of("wood.jpg".as_ref()), Some(FileKind::Texture));
/// assert_eq!(kind_of("notes.txt".as_ref()), None);
/// ```
pub fn kind_of(path: &Path) -> Option<FileKind> {
    let extension = path.extension()?.to_str()?.to_ascii_lowercase();
    let is = |list: &[&str]| list.contains(&extension.as_str());
    if is(&SCENE_EXTENSIONS) {
        Some(FileKind::Scene)
    } else if is(&MESH_EXTENSIONS) {
        Some(FileKind::Mesh)
    } else if is(&TEXTURE_EXTENSIONS) {
        Some(FileKind::Texture)
    } else {
        None
    }
}

/// The kinds of file the studio takes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FileKind {
    /// A scene file.
    Scene,
    /// A mesh, for a new object.
    Mesh,
    /// An image, for a texture.
    Texture,
}

/// `path` as the scene should hold it: relative to the scene's folder `base` when it lies
/// inside it (so that the folder can move with its files), otherwise as it is.
///
/// ```
/// use std::path::Path;
/// use orbifold_studio::dialogs::relative_to;
/// let base = Path::new("/rooms");
/// assert_eq!(relative_to(Path::new("/rooms/tex/wood.png"), Some(base)), "tex/wood.png");
/// assert_eq!(relative_to(Path::new("/elsewhere/wood.png"), Some(base)), "/elsewhere/wood.png");
/// ```
pub fn relative_to(path: &Path, base: Option<&Path>) -> String {
    let inside = base.and_then(|b| path.strip_prefix(b).ok());
    inside.unwrap_or(path).to_string_lossy().into_owned()
}
