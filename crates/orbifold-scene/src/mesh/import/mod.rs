//! Reading triangle meshes from OBJ, PLY and glTF/GLB files.
//!
//! Only the shape is read: vertex positions and triangles (polygons are split into fans; an
//! OBJ file's vertices come back numbered in order of first use, unused ones dropped).
//! Normals, texture coordinates, colours and materials are ignored. Every reader takes
//! arbitrary bytes without panicking, sizes its allocations by the input (never by a count that
//! the file merely claims), and rejects non-finite coordinates, indices out of range and files
//! without a single triangle, with a [`MeshError`] that says what and where.
//!
//! This module holds what the formats share: the entry points ([`load_mesh`], [`parse_mesh`]),
//! the format a file name asks for ([`MeshFormat`]), the errors, and the checks every reader's
//! result passes. Each format has a file of its own, which cites its specification:
//! `obj.rs` (Wavefront OBJ, through `tobj`), `ply.rs` (Stanford PLY, ASCII and binary) and
//! `gltf.rs` (glTF 2.0 and GLB, through `gltf`).
//!
//! ```
//! use orbifold_scene::mesh::import::{MeshFormat, parse_mesh};
//! let obj = b"v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n";
//! let mesh = parse_mesh(obj, MeshFormat::Obj, None).unwrap();
//! assert_eq!((mesh.positions.len(), mesh.triangles.len()), (4, 4));
//! let error = parse_mesh(b"v 0 0 0\nf 1 2 3\n", MeshFormat::Obj, None).unwrap_err();
//! assert_eq!(
//!     error.to_string(),
//!     "OBJ line 2: the face refers to vertex 3, but only 1 vertex is defined"
//! );
//! ```

use std::fmt;
use std::path::{Path, PathBuf};

use super::TriangleMesh;

mod gltf;
mod obj;
mod ply;

/// Most vertices (and most triangles) a mesh read from a file may have.
const MAX_ELEMENTS: usize = 1 << 26;

/// A mesh file format.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum MeshFormat {
    /// Wavefront OBJ (text).
    Obj,
    /// Stanford PLY: ASCII, or binary little or big endian.
    Ply,
    /// glTF 2.0 JSON, with buffers in data URIs or in files next to it.
    Gltf,
    /// Binary glTF 2.0 (GLB).
    Glb,
}

impl MeshFormat {
    /// The format a file name's extension names (`.obj`, `.ply`, `.gltf`, `.glb`, in any
    /// case); `None` for any other.
    ///
    /// ```
    /// use orbifold_scene::mesh::import::MeshFormat;
    /// use std::path::Path;
    /// assert_eq!(MeshFormat::from_path(Path::new("bunny.PLY")), Some(MeshFormat::Ply));
    /// assert_eq!(MeshFormat::from_path(Path::new("teapot.stl")), None);
    /// ```
    pub fn from_path(path: &Path) -> Option<MeshFormat> {
        let extension = path.extension()?.to_str()?.to_ascii_lowercase();
        match extension.as_str() {
            "obj" => Some(MeshFormat::Obj),
            "ply" => Some(MeshFormat::Ply),
            "gltf" => Some(MeshFormat::Gltf),
            "glb" => Some(MeshFormat::Glb),
            _ => None,
        }
    }

    /// The format's usual name: `OBJ`, `PLY`, `glTF` or `GLB`.
    pub fn name(self) -> &'static str {
        match self {
            MeshFormat::Obj => "OBJ",
            MeshFormat::Ply => "PLY",
            MeshFormat::Gltf => "glTF",
            MeshFormat::Glb => "GLB",
        }
    }
}

impl fmt::Display for MeshFormat {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// What kind of problem a [`MeshError`] is.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
#[non_exhaustive]
pub enum MeshErrorKind {
    /// The file (or a buffer file it names) could not be read.
    Io,
    /// The file name has no known mesh extension.
    UnknownFormat,
    /// The content is malformed.
    Syntax,
    /// The content is valid but uses something this reader does not support.
    Unsupported,
    /// The content ends before the data its header or structure announces.
    Truncated,
    /// A coordinate is NaN or infinite.
    NonFinite,
    /// A face refers to a vertex that does not exist.
    IndexOutOfRange,
    /// There is not a single triangle.
    Empty,
    /// The mesh is larger than this reader accepts.
    TooLarge,
}

/// A problem reading a mesh: what kind, where (file, and line, byte or element when known) and
/// what exactly.
#[derive(Clone, Debug, PartialEq)]
pub struct MeshError {
    /// The kind of problem.
    pub kind: MeshErrorKind,
    /// The file, when the mesh came from one ([`load_mesh`]).
    pub file: Option<PathBuf>,
    /// Where in the content, such as `PLY line 12` or `glTF accessor 3`, when known.
    pub location: Option<String>,
    /// What is wrong.
    pub message: String,
}

impl MeshError {
    fn new(kind: MeshErrorKind, location: Option<String>, message: impl Into<String>) -> Self {
        MeshError {
            kind,
            file: None,
            location,
            message: message.into(),
        }
    }

    /// The same error, said of the file `path` (unless it already names one).
    pub fn in_file(mut self, path: &Path) -> Self {
        self.file.get_or_insert_with(|| path.to_path_buf());
        self
    }
}

impl fmt::Display for MeshError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if let Some(file) = &self.file {
            write!(f, "{}: ", file.display())?;
        }
        if let Some(location) = &self.location {
            write!(f, "{location}: ")?;
        }
        f.write_str(&self.message)
    }
}

impl std::error::Error for MeshError {}

/// Reads a mesh from the bytes of a file in `format`. `base` is the directory that relative
/// paths in the file are taken from (external glTF buffers; OBJ material libraries are
/// ignored); without it, a glTF file that needs an external buffer is an error. A glTF file
/// that is really GLB, or the other way round, is read all the same.
pub fn parse_mesh(
    bytes: &[u8],
    format: MeshFormat,
    base: Option<&Path>,
) -> Result<TriangleMesh, MeshError> {
    let mesh = match format {
        MeshFormat::Obj => obj::parse(bytes)?,
        MeshFormat::Ply => ply::parse(bytes)?,
        MeshFormat::Gltf | MeshFormat::Glb => gltf::parse(bytes, base)?,
    };
    check(mesh, format)
}

/// Reads a mesh file, its format given by its extension (see [`MeshFormat::from_path`]),
/// through [`crate::files::read`]: bytes given to the store under `path` come before the disk
/// (and so do a glTF file's external buffers beside it).
///
/// ```
/// use std::path::Path;
/// use orbifold_scene::{files, mesh::import::load_mesh};
/// let obj = b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";
/// files::provide("load-mesh-example/triangle.obj", obj.to_vec());
/// let mesh = load_mesh(Path::new("load-mesh-example/triangle.obj")).unwrap();
/// assert_eq!(mesh.triangles.len(), 1);
/// files::forget(Path::new("load-mesh-example/triangle.obj"));
/// ```
pub fn load_mesh(path: &Path) -> Result<TriangleMesh, MeshError> {
    let format = MeshFormat::from_path(path).ok_or_else(|| {
        MeshError::new(
            MeshErrorKind::UnknownFormat,
            None,
            "unknown mesh file extension (expected .obj, .ply, .gltf or .glb)",
        )
        .in_file(path)
    })?;
    let bytes = crate::files::read(path).map_err(|e| {
        MeshError::new(
            MeshErrorKind::Io,
            None,
            format!("cannot read the file: {e}"),
        )
        .in_file(path)
    })?;
    parse_mesh(&bytes, format, path.parent()).map_err(|e| e.in_file(path))
}

/// The checks every reader's result passes: some triangles, indices in range, finite
/// coordinates, not too large. Each reader reports these with a location first; this is the
/// net beneath.
fn check(mesh: TriangleMesh, format: MeshFormat) -> Result<TriangleMesh, MeshError> {
    let here = || Some(format.name().to_string());
    if mesh.positions.len() > MAX_ELEMENTS || mesh.triangles.len() > MAX_ELEMENTS {
        return Err(too_large(
            here(),
            mesh.positions.len().max(mesh.triangles.len()),
        ));
    }
    if let Some(i) = mesh
        .positions
        .iter()
        .position(|p| !p.iter().all(|c| c.is_finite()))
    {
        return Err(MeshError::new(
            MeshErrorKind::NonFinite,
            here(),
            format!("vertex {i} has a coordinate that is not a finite number"),
        ));
    }
    let n = mesh.positions.len();
    if let Some(t) = mesh
        .triangles
        .iter()
        .position(|t| t.iter().any(|&i| i as usize >= n))
    {
        return Err(MeshError::new(
            MeshErrorKind::IndexOutOfRange,
            here(),
            format!("triangle {t} refers to a vertex beyond the {n} there are"),
        ));
    }
    if mesh.triangles.is_empty() {
        return Err(MeshError::new(
            MeshErrorKind::Empty,
            here(),
            "the file has no triangles",
        ));
    }
    Ok(mesh)
}

fn too_large(location: Option<String>, count: usize) -> MeshError {
    MeshError::new(
        MeshErrorKind::TooLarge,
        location,
        format!("the mesh is too large ({count} elements; at most {MAX_ELEMENTS} are accepted)"),
    )
}

/// `n` followed by the singular or the plural form.
fn counted(n: impl Into<u128>, one: &str, many: &str) -> String {
    let n = n.into();
    format!("{n} {}", if n == 1 { one } else { many })
}

/// A short, printable excerpt of a token for messages.
fn excerpt(token: &[u8]) -> String {
    let text = String::from_utf8_lossy(token);
    let mut short: String = text.chars().take(24).collect();
    if short.len() < text.len() {
        short.push('…');
    }
    format!("{short:?}")
}
