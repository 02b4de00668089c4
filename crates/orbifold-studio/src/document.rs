//! The open document: a scene, where it is saved, its undo history, and the recovery copy that
//! survives a crash.
//!
//! Every edit goes through [`Document::edit`], which keeps the scene as it was for undo. Saving
//! is atomic (a temporary file renamed into place, `orbifold_scene::write_atomic`). While there
//! are unsaved changes a recovery copy is kept in the data folder; it is removed when the
//! document is saved or closed cleanly, so one found at start-up means the last session crashed.

use std::path::{Path, PathBuf};

use orbifold_scene::Scene;

/// How many edits undo remembers.
pub const UNDO_DEPTH: usize = 200;
/// How many recently opened files the studio lists.
pub const RECENT: usize = 10;

/// A scene being edited.
///
/// ```
/// use orbifold_studio::document::Document;
/// let mut doc = Document::new(None);
/// doc.edit(|scene| scene.room.height = 2.0);
/// assert!(doc.is_dirty());
/// doc.undo();
/// assert_eq!(doc.scene().room.height, orbifold_scene::Scene::default().room.height);
/// doc.redo();
/// assert_eq!(doc.scene().room.height, 2.0);
/// ```
#[derive(Clone, Debug)]
pub struct Document {
    scene: Scene,
    path: Option<PathBuf>,
    undo: Vec<Scene>,
    redo: Vec<Scene>,
    /// The scene as last saved or opened.
    saved: Scene,
    /// Where the recovery copy goes (`None`: no recovery, as in tests).
    recovery: Option<PathBuf>,
    /// Bumped by every change, so that views know when to redraw.
    revision: u64,
    /// While set (a drag under way), edits after the first join it as one undo step.
    gesture: Gesture,
}

/// Whether edits are joining one gesture.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
enum Gesture {
    #[default]
    None,
    /// A gesture has begun; its first edit has not come yet.
    Open,
    /// Its first edit is on the undo stack; later ones replace the scene only.
    Recorded,
}

impl Document {
    /// A new document with the default scene (the seed's `*22222` room). `recovery` is where the
    /// recovery copy of unsaved work goes.
    pub fn new(recovery: Option<PathBuf>) -> Document {
        Document::with_scene(Scene::default(), None, recovery)
    }

    /// A document holding `scene`, saved at `path` if given.
    pub fn with_scene(scene: Scene, path: Option<PathBuf>, recovery: Option<PathBuf>) -> Document {
        Document {
            saved: scene.clone(),
            scene,
            path,
            undo: Vec::new(),
            redo: Vec::new(),
            recovery,
            revision: 0,
            gesture: Gesture::None,
        }
    }

    /// Starts or ends a gesture (a drag): the edits made during one are undone as one.
    ///
    /// ```
    /// use orbifold_studio::document::Document;
    /// let mut doc = Document::new(None);
    /// doc.set_gesture(true);
    /// for k in 1..=10 {
    ///     doc.edit(|scene| scene.room.height = 1.0 + 0.1 * f64::from(k));
    /// }
    /// doc.set_gesture(false);
    /// doc.undo();
    /// assert_eq!(doc.scene().room.height, 1.0);
    /// ```
    pub fn set_gesture(&mut self, active: bool) {
        self.gesture = match (active, self.gesture) {
            (false, _) => Gesture::None,
            (true, Gesture::None) => Gesture::Open,
            (true, g) => g,
        };
    }

    /// Opens a scene file.
    pub fn open(path: &Path, recovery: Option<PathBuf>) -> Result<Document, String> {
        let scene = Scene::load(path).map_err(|errors| {
            errors
                .iter()
                .map(ToString::to_string)
                .collect::<Vec<_>>()
                .join("\n")
        })?;
        Ok(Document::with_scene(
            scene,
            Some(path.to_path_buf()),
            recovery,
        ))
    }

    /// The scene.
    pub fn scene(&self) -> &Scene {
        &self.scene
    }

    /// Where the document is saved.
    pub fn path(&self) -> Option<&Path> {
        self.path.as_deref()
    }

    /// The folder that relative mesh and texture names are resolved against.
    pub fn base(&self) -> Option<&Path> {
        self.path.as_deref().and_then(Path::parent)
    }

    /// A counter that changes with every change of the scene.
    pub fn revision(&self) -> u64 {
        self.revision
    }

    /// Whether there are unsaved changes.
    pub fn is_dirty(&self) -> bool {
        self.scene != self.saved
    }

    /// The name to show: the file's name, or "untitled".
    pub fn title(&self) -> String {
        let name = self
            .path
            .as_deref()
            .and_then(Path::file_name)
            .map_or_else(|| "untitled".into(), |n| n.to_string_lossy().into_owned());
        if self.is_dirty() {
            format!("{name} •")
        } else {
            name
        }
    }

    /// Changes the scene; the old one is kept for undo. An edit that changes nothing is not
    /// recorded.
    pub fn edit(&mut self, change: impl FnOnce(&mut Scene)) {
        let mut next = self.scene.clone();
        change(&mut next);
        self.replace(next);
    }

    /// Replaces the scene as one edit (a whole-scene change, such as a widget's new value).
    pub fn replace(&mut self, next: Scene) {
        if next == self.scene {
            return;
        }
        let previous = std::mem::replace(&mut self.scene, next);
        if self.gesture != Gesture::Recorded {
            self.undo.push(previous);
            if self.undo.len() > UNDO_DEPTH {
                self.undo.remove(0);
            }
        }
        if self.gesture == Gesture::Open {
            self.gesture = Gesture::Recorded;
        }
        self.redo.clear();
        self.changed();
    }

    /// Whether there is an edit to undo.
    pub fn can_undo(&self) -> bool {
        !self.undo.is_empty()
    }

    /// Whether there is an edit to redo.
    pub fn can_redo(&self) -> bool {
        !self.redo.is_empty()
    }

    /// Undoes the last edit.
    pub fn undo(&mut self) {
        if let Some(previous) = self.undo.pop() {
            let current = std::mem::replace(&mut self.scene, previous);
            self.redo.push(current);
            self.changed();
        }
    }

    /// Redoes the last undone edit.
    pub fn redo(&mut self) {
        if let Some(next) = self.redo.pop() {
            let current = std::mem::replace(&mut self.scene, next);
            self.undo.push(current);
            self.changed();
        }
    }

    /// Saves to the document's path (atomically).
    pub fn save(&mut self) -> Result<(), String> {
        let path = self
            .path
            .clone()
            .ok_or_else(|| "the document has no file yet: use Save As".to_string())?;
        self.save_as(&path)
    }

    /// Saves to `path` (atomically) and makes it the document's path.
    pub fn save_as(&mut self, path: &Path) -> Result<(), String> {
        self.scene
            .save(path)
            .map_err(|e| format!("cannot save {}: {e}", path.display()))?;
        self.path = Some(path.to_path_buf());
        self.saved = self.scene.clone();
        self.remove_recovery();
        self.revision += 1;
        Ok(())
    }

    /// Records that the scene as it is now was saved as `path` by someone else (the web studio
    /// hands it to the browser as a download): it becomes the document's name, and the
    /// document is no longer dirty.
    ///
    /// ```
    /// use orbifold_studio::document::Document;
    /// let mut doc = Document::new(None);
    /// doc.edit(|scene| scene.room.height = 2.0);
    /// doc.mark_saved("room.toml".into());
    /// assert!(!doc.is_dirty());
    /// assert_eq!(doc.title(), "room.toml");
    /// ```
    pub fn mark_saved(&mut self, path: PathBuf) {
        self.path = Some(path);
        self.saved = self.scene.clone();
        self.remove_recovery();
        self.revision += 1;
    }

    /// Writes the recovery copy if there are unsaved changes (and removes it if there are
    /// none). Errors are returned for the status line; they never stop editing.
    pub fn write_recovery(&self) -> Result<(), String> {
        let Some(recovery) = &self.recovery else {
            return Ok(());
        };
        if !self.is_dirty() {
            self.remove_recovery();
            return Ok(());
        }
        if let Some(folder) = recovery.parent() {
            std::fs::create_dir_all(folder).map_err(|e| e.to_string())?;
        }
        let mut text = String::new();
        if let Some(path) = &self.path {
            text.push_str(&format!("# recovered from {}\n", path.display()));
        }
        text.push_str(&self.scene.to_toml());
        orbifold_scene::write_atomic(recovery, text.as_bytes()).map_err(|e| e.to_string())
    }

    /// Removes the recovery copy (the work is saved, or was thrown away on purpose).
    pub fn remove_recovery(&self) {
        if let Some(recovery) = &self.recovery {
            let _ = std::fs::remove_file(recovery);
        }
    }

    fn changed(&mut self) {
        self.revision += 1;
    }
}

/// The recovery copy left by a session that did not close cleanly, if there is one.
pub fn recovered(recovery: &Path) -> Option<Scene> {
    let text = std::fs::read_to_string(recovery).ok()?;
    Scene::from_toml(&text, None).ok()
}

/// The studio's folder for its own files: `$XDG_DATA_HOME/orbifold-studio` or
/// `~/.local/share/orbifold-studio` (`None` without a home).
pub fn data_folder() -> Option<PathBuf> {
    std::env::var_os("XDG_DATA_HOME")
        .map(PathBuf::from)
        .or_else(|| std::env::var_os("HOME").map(|h| PathBuf::from(h).join(".local/share")))
        .map(|d| d.join("orbifold-studio"))
}

/// The recently opened files, newest first, from `folder/recent.txt`.
pub fn recent_files(folder: &Path) -> Vec<PathBuf> {
    std::fs::read_to_string(folder.join("recent.txt"))
        .unwrap_or_default()
        .lines()
        .filter(|l| !l.trim().is_empty())
        .map(PathBuf::from)
        .take(RECENT)
        .collect()
}

/// Puts `path` first in the recent files of `folder`.
pub fn remember(folder: &Path, path: &Path) -> Result<(), String> {
    let path = path.canonicalize().unwrap_or_else(|_| path.to_path_buf());
    let mut list = recent_files(folder);
    list.retain(|p| p != &path);
    list.insert(0, path);
    list.truncate(RECENT);
    let text: String = list.iter().map(|p| format!("{}\n", p.display())).collect();
    std::fs::create_dir_all(folder).map_err(|e| e.to_string())?;
    orbifold_scene::write_atomic(&folder.join("recent.txt"), text.as_bytes())
        .map_err(|e| e.to_string())
}
