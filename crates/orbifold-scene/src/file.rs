//! Reading and writing scene files, with errors that say where.

use std::fmt;
use std::io::Write;
use std::ops::Range;
use std::path::{Path, PathBuf};

use crate::document::Scene;
use crate::validate::validate;

/// A problem with a scene file: where (file, line, column, key) and what.
#[derive(Clone, Debug, PartialEq)]
pub struct SceneError {
    /// The file, when the scene came from one.
    pub file: Option<PathBuf>,
    /// 1-based line and column, when known.
    pub position: Option<(usize, usize)>,
    /// The key, such as `objects[1].at`, when the problem is a value.
    pub key: Option<String>,
    /// What is wrong.
    pub message: String,
}

impl fmt::Display for SceneError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if let Some(file) = &self.file {
            write!(f, "{}:", file.display())?;
        }
        if let Some((line, column)) = self.position {
            write!(f, "{line}:{column}:")?;
        }
        if self.file.is_some() || self.position.is_some() {
            f.write_str(" ")?;
        }
        if let Some(key) = &self.key {
            write!(f, "{key}: ")?;
        }
        f.write_str(&self.message)
    }
}

impl std::error::Error for SceneError {}

/// 1-based line and column of a byte offset.
fn line_column(text: &str, offset: usize) -> (usize, usize) {
    let before = &text[..offset.min(text.len())];
    let line = before.matches('\n').count() + 1;
    let column = before.rsplit('\n').next().map_or(0, |l| l.chars().count()) + 1;
    (line, column)
}

impl Scene {
    /// Reads a scene from TOML text. `origin` is the file it came from (for messages, and to
    /// resolve mesh and texture paths). Every problem is reported, each with its position.
    ///
    /// ```
    /// use orbifold_scene::Scene;
    /// let scene = Scene::from_toml("[orbifold]\nsignature = \"*2333\"\n", None).unwrap();
    /// assert_eq!(scene.orbifold.signature, "*2333");
    /// let errors = Scene::from_toml("[room]\nheight = -1\n", None).unwrap_err();
    /// assert_eq!(errors[0].position, Some((2, 10)));
    /// ```
    pub fn from_toml(text: &str, origin: Option<&Path>) -> Result<Scene, Vec<SceneError>> {
        Scene::read_toml(text, origin, false).map(|(scene, _)| scene)
    }

    /// Reads a scene from TOML as [`Scene::from_toml`] does, except that a file it names that
    /// is not there (neither given to [`crate::files`] nor on the disk) is no error: returns the
    /// scene and those files' paths, resolved as validation resolves them. For a copy of
    /// unsaved work whose files may have gone (the web studio's recovery): the scene comes back,
    /// and the user is told which files to give again.
    ///
    /// ```
    /// use std::path::PathBuf;
    /// use orbifold_scene::Scene;
    /// let mut scene = Scene::default();
    /// scene.objects[0].mesh = Some("gone.obj".into());
    /// let text = scene.to_toml();
    /// assert!(Scene::from_toml(&text, None).is_err());
    /// let (again, missing) = Scene::from_toml_missing_files(&text, None).unwrap();
    /// assert_eq!(again, scene);
    /// assert_eq!(missing, [PathBuf::from("gone.obj")]);
    /// ```
    pub fn from_toml_missing_files(
        text: &str,
        origin: Option<&Path>,
    ) -> Result<(Scene, Vec<PathBuf>), Vec<SceneError>> {
        Scene::read_toml(text, origin, true)
    }

    /// [`Scene::from_toml`], with missing files allowed (and listed) when `missing_allowed`.
    fn read_toml(
        text: &str,
        origin: Option<&Path>,
        missing_allowed: bool,
    ) -> Result<(Scene, Vec<PathBuf>), Vec<SceneError>> {
        let mut scene: Scene = toml::from_str(text).map_err(|e| {
            vec![SceneError {
                file: origin.map(Path::to_path_buf),
                position: e.span().map(|s| line_column(text, s.start)),
                key: None,
                message: e.message().trim().to_string(),
            }]
        })?;
        // What the file leaves out is placed for its room (placement.rs); what it writes is
        // checked as written.
        if let Ok(table) = text.parse::<toml::Table>() {
            scene.place_unwritten(&crate::placement::Written::of(&table));
        }
        let base = origin.and_then(Path::parent).map(Path::to_path_buf);
        let mut problems = validate(&scene, base.as_deref());
        let mut missing = Vec::new();
        if missing_allowed {
            let resolve = |name: &String| {
                base.as_ref()
                    .map_or_else(|| PathBuf::from(name), |b| b.join(name))
            };
            missing = scene
                .named_files()
                .iter()
                .map(resolve)
                .filter(|path| !crate::files::exists(path))
                .collect();
            let messages: Vec<String> = missing
                .iter()
                .map(|p| crate::files::missing_message(p))
                .collect();
            problems.retain(|(_, message)| !messages.contains(message));
        }
        if problems.is_empty() {
            return Ok((scene, missing));
        }
        let document = toml_edit::Document::parse(text.to_string()).ok();
        Err(problems
            .into_iter()
            .map(|(key, message)| SceneError {
                file: origin.map(Path::to_path_buf),
                position: document
                    .as_ref()
                    .and_then(|d| locate(d, &key))
                    .map(|span| line_column(text, span.start)),
                key: Some(key),
                message,
            })
            .collect())
    }

    /// Every problem with a scene built or changed in memory (keys, no positions); `base` is the
    /// folder that mesh and texture paths are relative to (the scene file's).
    ///
    /// ```
    /// use orbifold_scene::Scene;
    /// let mut scene = Scene::default();
    /// assert!(scene.check(None).is_ok());
    /// scene.room.height = -1.0;
    /// let errors = scene.check(None).unwrap_err();
    /// assert_eq!(errors[0].key.as_deref(), Some("room.height"));
    /// ```
    pub fn check(&self, base: Option<&Path>) -> Result<(), Vec<SceneError>> {
        let problems = validate(self, base);
        if problems.is_empty() {
            return Ok(());
        }
        Err(problems
            .into_iter()
            .map(|(key, message)| SceneError {
                file: None,
                position: None,
                key: Some(key),
                message,
            })
            .collect())
    }

    /// Reads and validates a scene file.
    pub fn load(path: &Path) -> Result<Scene, Vec<SceneError>> {
        let text = std::fs::read_to_string(path).map_err(|e| {
            vec![SceneError {
                file: Some(path.to_path_buf()),
                position: None,
                key: None,
                message: format!("cannot read: {e}"),
            }]
        })?;
        Scene::from_toml(&text, Some(path))
    }

    /// The scene as TOML text; reading it back gives an equal scene.
    pub fn to_toml(&self) -> String {
        toml::to_string(self).expect("scenes have no values TOML cannot hold")
    }

    /// Writes the scene to `path` through a temporary file and a rename, so that an interrupted
    /// save never leaves half a file or loses the previous one.
    pub fn save(&self, path: &Path) -> std::io::Result<()> {
        write_atomic(path, self.to_toml().as_bytes())
    }
}

/// The span of the value at `key` (such as `objects[1].at` or `room.floor.color`), or of the
/// nearest enclosing table that the file spells out.
fn locate(document: &toml_edit::Document<String>, key: &str) -> Option<Range<usize>> {
    enum Node<'a> {
        Item(&'a toml_edit::Item),
        Value(&'a toml_edit::Value),
        Table(&'a toml_edit::Table),
    }
    let mut node = Node::Table(document.as_table());
    let mut best = None;
    for segment in key.split('.') {
        let (name, index) = match segment.split_once('[') {
            Some((name, rest)) => (name, rest.trim_end_matches(']').parse::<usize>().ok()),
            None => (segment, None),
        };
        let child = match &node {
            Node::Table(t) => t.get(name).map(Node::Item),
            Node::Item(item) => match item {
                toml_edit::Item::Table(t) => t.get(name).map(Node::Item),
                toml_edit::Item::Value(toml_edit::Value::InlineTable(t)) => {
                    t.get(name).map(Node::Value)
                }
                _ => None,
            },
            Node::Value(toml_edit::Value::InlineTable(t)) => t.get(name).map(Node::Value),
            Node::Value(_) => None,
        };
        let Some(mut child) = child else { break };
        if let Some(i) = index {
            let element = match &child {
                Node::Item(toml_edit::Item::ArrayOfTables(a)) => a.get(i).map(Node::Table),
                Node::Item(toml_edit::Item::Value(toml_edit::Value::Array(a)))
                | Node::Value(toml_edit::Value::Array(a)) => a.get(i).map(Node::Value),
                _ => None,
            };
            match element {
                Some(e) => child = e,
                None => break,
            }
        }
        let span = match &child {
            Node::Item(item) => item.span(),
            Node::Value(value) => value.span(),
            Node::Table(table) => table.span(),
        };
        best = span.or(best);
        node = child;
    }
    best
}

/// Writes `bytes` to `path` through a temporary file in the same directory and a rename, so that
/// a reader never sees half a file and a failure leaves any earlier file untouched.
pub fn write_atomic(path: &Path, bytes: &[u8]) -> std::io::Result<()> {
    let dir = path
        .parent()
        .filter(|p| !p.as_os_str().is_empty())
        .unwrap_or(Path::new("."));
    let name = path
        .file_name()
        .ok_or_else(|| std::io::Error::other("the output path names no file"))?;
    let temporary = dir.join(format!(
        ".{}.{}.tmp",
        name.to_string_lossy(),
        std::process::id()
    ));
    let result = (|| {
        let mut file = std::fs::File::create(&temporary)?;
        file.write_all(bytes)?;
        file.sync_all()?;
        std::fs::rename(&temporary, path)
    })();
    if result.is_err() {
        let _ = std::fs::remove_file(&temporary);
    }
    result
}
