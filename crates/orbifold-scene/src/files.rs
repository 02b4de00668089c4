//! Files a scene names (meshes, textures, glTF buffers), given by their bytes instead of read
//! from a disk.
//!
//! A scene names its mesh and texture files by path, relative to its own folder, and every
//! reader (the mesh importers, the validation's check that a named file is there, the
//! renderer's image textures, the mesh exporter's copies of textures) reads them through
//! [`read`]. [`read`] looks in a process-wide store first, and only then on the disk. The store
//! is for a program without a disk: the web studio puts a file that was dropped on the page or
//! picked in the browser's file picker here, under the name the scene then names it by, so that
//! the preview, the render and the exports find it exactly as they would find a file on the
//! disk. Nothing fills the store unless a program asks it to ([`provide`]), so the command line
//! and the desktop studio read from the disk exactly as before.
//!
//! Paths are compared as written, less any `.` parts (`./tex/wood.png` is `tex/wood.png`): the
//! store is not a file system, and a name is found only by the path it was given under (a
//! scene opened in the browser has no folder, so its files are found by the names it holds).
//!
//! ```
//! use std::path::Path;
//! use orbifold_scene::files;
//!
//! files::provide("store-example/cube.obj", b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n".to_vec());
//! assert!(files::exists(Path::new("./store-example/cube.obj")));
//! let bytes = files::read(Path::new("store-example/cube.obj")).unwrap();
//! assert!(bytes.starts_with(b"v 0 0 0"));
//! assert!(files::forget(Path::new("store-example/cube.obj")));
//! assert!(files::read(Path::new("store-example/cube.obj")).is_err());
//! ```

use std::collections::BTreeMap;
use std::io;
use std::ops::Deref;
use std::path::{Component, Path, PathBuf};
use std::sync::{Arc, PoisonError, RwLock};

/// The files given by their bytes, by normalised path.
static STORE: RwLock<BTreeMap<PathBuf, Arc<[u8]>>> = RwLock::new(BTreeMap::new());

/// `path` without its `.` parts, as the store's keys are kept.
fn key(path: &Path) -> PathBuf {
    path.components()
        .filter(|c| !matches!(c, Component::CurDir))
        .collect()
}

/// The bytes of a file: shared with the store when it was given there, or read from the disk.
/// Dereferences to `[u8]`.
///
/// ```
/// use std::path::Path;
/// use orbifold_scene::files;
/// files::provide("contents-example.txt", b"hello".to_vec());
/// let contents = files::read(Path::new("contents-example.txt")).unwrap();
/// assert_eq!(&*contents, b"hello");
/// assert_eq!(contents.len(), 5);
/// files::forget(Path::new("contents-example.txt"));
/// ```
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Contents(Source);

#[derive(Clone, Debug, PartialEq, Eq)]
enum Source {
    Given(Arc<[u8]>),
    Read(Vec<u8>),
}

impl Contents {
    /// The bytes as a vector of their own: without a copy when they were read from the disk.
    ///
    /// ```
    /// use std::path::Path;
    /// use orbifold_scene::files;
    /// files::provide("into-vec-example.bin", vec![4, 5]);
    /// let bytes = files::read(Path::new("into-vec-example.bin")).unwrap().into_vec();
    /// assert_eq!(bytes, vec![4, 5]);
    /// files::forget(Path::new("into-vec-example.bin"));
    /// ```
    pub fn into_vec(self) -> Vec<u8> {
        match self.0 {
            Source::Given(bytes) => bytes.to_vec(),
            Source::Read(bytes) => bytes,
        }
    }
}

impl Deref for Contents {
    type Target = [u8];

    fn deref(&self) -> &[u8] {
        match &self.0 {
            Source::Given(bytes) => bytes,
            Source::Read(bytes) => bytes,
        }
    }
}

impl AsRef<[u8]> for Contents {
    fn as_ref(&self) -> &[u8] {
        self
    }
}

/// Gives the file at `path` by its bytes: from now on [`read`] returns them for that path
/// (written with or without `.` parts), before looking on the disk. Replaces bytes given
/// before under the same path.
///
/// ```
/// use std::path::Path;
/// use orbifold_scene::files;
/// files::provide("provide-example.png", vec![1, 2, 3]);
/// assert_eq!(&*files::read(Path::new("provide-example.png")).unwrap(), &[1, 2, 3]);
/// files::forget(Path::new("provide-example.png"));
/// ```
pub fn provide(path: impl AsRef<Path>, bytes: impl Into<Arc<[u8]>>) {
    STORE
        .write()
        .unwrap_or_else(PoisonError::into_inner)
        .insert(key(path.as_ref()), bytes.into());
}

/// Takes the file at `path` out of the store (the disk is left alone); whether it was there.
///
/// ```
/// use std::path::Path;
/// use orbifold_scene::files;
/// files::provide("forget-example.obj", vec![0]);
/// assert!(files::forget(Path::new("forget-example.obj")));
/// assert!(!files::forget(Path::new("forget-example.obj")));
/// ```
pub fn forget(path: &Path) -> bool {
    STORE
        .write()
        .unwrap_or_else(PoisonError::into_inner)
        .remove(&key(path))
        .is_some()
}

/// The bytes given for `path`, if any (the disk is not looked at).
///
/// ```
/// use std::path::Path;
/// use orbifold_scene::files;
/// assert!(files::provided(Path::new("never-given.obj")).is_none());
/// ```
pub fn provided(path: &Path) -> Option<Arc<[u8]>> {
    STORE
        .read()
        .unwrap_or_else(PoisonError::into_inner)
        .get(&key(path))
        .cloned()
}

/// The paths of every file in the store, in order.
///
/// ```
/// use std::path::{Path, PathBuf};
/// use orbifold_scene::files;
/// files::provide("listed-example.ply", vec![0]);
/// assert!(files::provided_paths().contains(&PathBuf::from("listed-example.ply")));
/// files::forget(Path::new("listed-example.ply"));
/// ```
pub fn provided_paths() -> Vec<PathBuf> {
    STORE
        .read()
        .unwrap_or_else(PoisonError::into_inner)
        .keys()
        .cloned()
        .collect()
}

/// The bytes of the file at `path`: those given for it ([`provide`]), or else the file's on the
/// disk (`std::fs::read`, with its error).
///
/// ```
/// use std::path::Path;
/// use orbifold_scene::files;
/// let error = files::read(Path::new("no/such/file.obj")).unwrap_err();
/// assert_eq!(error.kind(), std::io::ErrorKind::NotFound);
/// ```
pub fn read(path: &Path) -> io::Result<Contents> {
    match provided(path) {
        Some(bytes) => Ok(Contents(Source::Given(bytes))),
        None => std::fs::read(path).map(|bytes| Contents(Source::Read(bytes))),
    }
}

/// The image texture at `path` ([`read`]), decoded: PNG or JPEG, its format its extension's, as
/// `image::open` takes it. The error names the file; an image without pixels is one.
///
/// ```
/// use std::path::Path;
/// use orbifold_scene::files;
/// let error = files::read_image(Path::new("no/such/wood.png")).unwrap_err();
/// assert!(error.starts_with("cannot read texture no/such/wood.png"), "{error}");
/// ```
pub fn read_image(path: &Path) -> Result<image::DynamicImage, String> {
    let cannot = |e: &dyn std::fmt::Display| format!("cannot read texture {}: {e}", path.display());
    let bytes = read(path).map_err(|e| cannot(&e))?;
    let mut reader = image::ImageReader::new(io::Cursor::new(&*bytes));
    if let Ok(format) = image::ImageFormat::from_path(path) {
        reader.set_format(format);
    }
    let image = reader.decode().map_err(|e| cannot(&e))?;
    if image.width() == 0 || image.height() == 0 {
        return Err(format!("texture {} has no pixels", path.display()));
    }
    Ok(image)
}

/// Whether there is a file at `path`: given to the store, or a file on the disk.
///
/// ```
/// use std::path::Path;
/// use orbifold_scene::files;
/// assert!(files::exists(Path::new("Cargo.toml")));
/// assert!(!files::exists(Path::new("no/such/file.png")));
/// ```
pub fn exists(path: &Path) -> bool {
    provided(path).is_some() || path.is_file()
}

impl crate::Scene {
    /// The files the scene names, as it names them (relative to its folder unless absolute), in
    /// order, each once: its objects' meshes and the images of its textures.
    ///
    /// ```
    /// use orbifold_scene::{Material, Scene};
    /// let mut scene = Scene::default();
    /// assert!(scene.named_files().is_empty());
    /// scene.objects[0].mesh = Some("bunny.obj".into());
    /// scene.room.floor = Material::Texture {
    ///     path: "wood.png".into(),
    ///     scale: 0.5,
    ///     coordinates: Default::default(),
    /// };
    /// assert_eq!(scene.named_files(), ["wood.png", "bunny.obj"]);
    /// ```
    pub fn named_files(&self) -> Vec<String> {
        let room = &self.room;
        let materials = [&room.wall_material, &room.floor, &room.ceiling]
            .into_iter()
            .chain(self.walls.iter().filter_map(|w| w.material.as_ref()))
            .chain(self.objects.iter().map(|o| &o.material));
        let textures = materials.filter_map(|m| match m {
            crate::Material::Texture { path, .. } => Some(path),
            _ => None,
        });
        let meshes = self.objects.iter().filter_map(|o| o.mesh.as_ref());
        let mut names: Vec<String> = Vec::new();
        for name in textures.chain(meshes) {
            if !names.contains(name) {
                names.push(name.clone());
            }
        }
        names
    }
}

/// What validation says of a named file at `path` that is neither given nor on the disk.
pub(crate) fn missing_message(path: &Path) -> String {
    format!("the file {} does not exist", path.display())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn given_files_come_before_the_disk_and_can_be_forgotten() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("mesh.obj");
        std::fs::write(&path, b"on the disk").unwrap();
        assert_eq!(&*read(&path).unwrap(), b"on the disk");
        provide(&path, b"given".to_vec());
        assert_eq!(&*read(&path).unwrap(), b"given");
        assert!(forget(&path));
        assert_eq!(&*read(&path).unwrap(), b"on the disk");
    }

    #[test]
    fn dot_parts_do_not_matter_but_other_parts_do() {
        provide("./unit-store/a/./b.png", vec![7]);
        assert!(exists(Path::new("unit-store/a/b.png")));
        assert!(!exists(Path::new("unit-store/b.png")));
        assert!(!exists(Path::new("b.png")));
        assert!(forget(Path::new("unit-store/a/b.png")));
        assert!(!exists(Path::new("unit-store/a/b.png")));
    }
}
