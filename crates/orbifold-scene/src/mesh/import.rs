//! Reading triangle meshes from OBJ, PLY and glTF/GLB files.
//!
//! Only the shape is read: vertex positions and triangles (polygons are split into fans; an
//! OBJ file's vertices come back numbered in order of first use, unused ones dropped).
//! Normals, texture coordinates, colours and materials are ignored. Every reader takes
//! arbitrary bytes without panicking, sizes its allocations by the input (never by a count that
//! the file merely claims), and rejects non-finite coordinates, indices out of range and files
//! without a single triangle, with a [`MeshError`] that says what and where.
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
use std::io::{self, BufRead, Read};
use std::path::{Path, PathBuf};

use super::TriangleMesh;

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
        MeshFormat::Gltf | MeshFormat::Glb => gltf_file::parse(bytes, base)?,
    };
    check(mesh, format)
}

/// Reads a mesh file, its format given by its extension (see [`MeshFormat::from_path`]).
pub fn load_mesh(path: &Path) -> Result<TriangleMesh, MeshError> {
    let format = MeshFormat::from_path(path).ok_or_else(|| {
        MeshError::new(
            MeshErrorKind::UnknownFormat,
            None,
            "unknown mesh file extension (expected .obj, .ply, .gltf or .glb)",
        )
        .in_file(path)
    })?;
    let bytes = std::fs::read(path).map_err(|e| {
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

/// OBJ through `tobj`, behind a line filter that keeps only what the shape needs.
mod obj {
    use super::*;

    /// Feeds `tobj` one line at a time, counting lines (for messages) and vertices (to resolve
    /// relative indices and check every index against the vertices defined so far). Face
    /// corners are cut down to their position index, made absolute; lines that only concern
    /// attributes, groups, materials or polylines are blanked; so `tobj` sees one object of
    /// positions and faces.
    struct Lines<'a> {
        rest: &'a [u8],
        /// Lines handed out so far (the 1-based number of the current line).
        line: usize,
        /// `v` lines so far.
        vertices: usize,
        /// The largest position index a face has used, and its line.
        largest: (usize, usize),
        /// The current line as `tobj` gets it, and how much of it it has taken.
        buf: Vec<u8>,
        pos: usize,
        /// The first problem the filter found; it stops the reading.
        error: Option<MeshError>,
    }

    impl Lines<'_> {
        fn here(&self) -> Option<String> {
            Some(format!("OBJ line {}", self.line))
        }

        fn fail(&mut self, kind: MeshErrorKind, message: String) -> io::Error {
            self.error = Some(MeshError::new(kind, self.here(), message));
            io::Error::other("stopped by the line filter")
        }

        fn next_line(&mut self) -> io::Result<()> {
            let end = self
                .rest
                .iter()
                .position(|&b| b == b'\n')
                .map_or(self.rest.len(), |i| i + 1);
            let (raw, rest) = self.rest.split_at(end);
            self.rest = rest;
            self.line += 1;
            self.buf.clear();
            self.pos = 0;
            let Ok(text) = std::str::from_utf8(raw) else {
                return Err(self.fail(MeshErrorKind::Syntax, "the line is not UTF-8 text".into()));
            };
            let mut words = text.split_whitespace();
            match words.next() {
                Some("v") => {
                    self.vertices += 1;
                    let words: Vec<&str> = words.collect();
                    let coordinates: Vec<f64> =
                        words.iter().take(3).map_while(|w| w.parse().ok()).collect();
                    if coordinates.iter().any(|c| !c.is_finite()) {
                        return Err(self.fail(
                            MeshErrorKind::NonFinite,
                            "the vertex has a coordinate that is not a finite number".into(),
                        ));
                    }
                    if words.len() == 6 {
                        // x y z r g b: the colour is dropped.
                        self.buf
                            .extend_from_slice(format!("v {}\n", words[..3].join(" ")).as_bytes());
                    } else {
                        self.buf.extend_from_slice(raw);
                    }
                }
                Some("f") => {
                    self.buf.extend_from_slice(b"f");
                    for corner in words {
                        let index = corner.split('/').next().unwrap_or_default();
                        let Ok(index) = index.parse::<i64>() else {
                            return Err(self.fail(
                                MeshErrorKind::Syntax,
                                format!(
                                    "expected a vertex index, found {}",
                                    excerpt(corner.as_bytes())
                                ),
                            ));
                        };
                        let absolute = match index {
                            0 => {
                                return Err(self.fail(
                                    MeshErrorKind::IndexOutOfRange,
                                    "vertex index 0 (OBJ counts vertices from 1)".into(),
                                ));
                            }
                            i if i > 0 => i as u64,
                            i => {
                                let back = i.unsigned_abs();
                                if back > self.vertices as u64 {
                                    return Err(self.fail(
                                        MeshErrorKind::IndexOutOfRange,
                                        format!(
                                            "the face refers to vertex {index} (counting back), \
                                             but only {} defined",
                                            counted(
                                                self.vertices as u64,
                                                "vertex is",
                                                "vertices are"
                                            )
                                        ),
                                    ));
                                }
                                self.vertices as u64 + 1 - back
                            }
                        };
                        if absolute > self.largest.0 as u64 {
                            self.largest = (absolute as usize, self.line);
                        }
                        // Positive indices may point ahead; they are checked at the end.
                        if absolute > (isize::MAX as u64) / 4 {
                            return Err(self.fail(
                                MeshErrorKind::IndexOutOfRange,
                                format!("vertex index {index} is out of range"),
                            ));
                        }
                        self.buf
                            .extend_from_slice(format!(" {absolute}").as_bytes());
                    }
                    self.buf.push(b'\n');
                }
                Some("vt" | "vn" | "vp" | "l" | "o" | "g" | "s" | "usemtl" | "mtllib") => {
                    self.buf.push(b'\n');
                }
                _ => self.buf.extend_from_slice(raw),
            }
            Ok(())
        }
    }

    impl Read for Lines<'_> {
        fn read(&mut self, out: &mut [u8]) -> io::Result<usize> {
            let available = self.fill_buf()?;
            let n = available.len().min(out.len());
            out[..n].copy_from_slice(&available[..n]);
            self.consume(n);
            Ok(n)
        }
    }

    impl BufRead for Lines<'_> {
        fn fill_buf(&mut self) -> io::Result<&[u8]> {
            if self.pos >= self.buf.len() && !self.rest.is_empty() {
                self.next_line()?;
            }
            Ok(&self.buf[self.pos..])
        }

        fn consume(&mut self, amount: usize) {
            self.pos = (self.pos + amount).min(self.buf.len());
        }
    }

    pub(super) fn parse(bytes: &[u8]) -> Result<TriangleMesh, MeshError> {
        let mut lines = Lines {
            rest: bytes,
            line: 0,
            vertices: 0,
            largest: (0, 0),
            buf: Vec::new(),
            pos: 0,
            error: None,
        };
        // The rest names fields that exist only with some features of tobj.
        #[allow(clippy::needless_update)]
        let options = tobj::LoadOptions {
            single_index: true,
            triangulate: true,
            ignore_points: true,
            ignore_lines: true,
            ..Default::default()
        };
        let result = tobj::load_obj_buf(&mut lines, &options, |_| {
            Err(tobj::LoadError::OpenFileFailed)
        });
        if let Some(error) = lines.error.take() {
            return Err(error);
        }
        let (largest, line) = lines.largest;
        if largest > lines.vertices {
            return Err(MeshError::new(
                MeshErrorKind::IndexOutOfRange,
                Some(format!("OBJ line {line}")),
                format!(
                    "the face refers to vertex {largest}, but only {} defined",
                    counted(lines.vertices as u64, "vertex is", "vertices are")
                ),
            ));
        }
        let models = result.map_err(|e| {
            use tobj::LoadError as E;
            let message = match e {
                E::PositionParseError => "expected three numbers after v".into(),
                E::ScalingByZeroError => "the vertex has weight w = 0".into(),
                E::ColorParseError => "a vertex colour needs three numbers".into(),
                E::FaceParseError => "cannot read the face".into(),
                E::InvalidPolygon => "invalid polygon".into(),
                other => format!("cannot read the file ({other})"),
            };
            MeshError::new(MeshErrorKind::Syntax, lines.here(), message)
        })?;
        let mut mesh = TriangleMesh::default();
        for model in models.0 {
            let m = &model.mesh;
            let base = mesh.positions.len();
            if base + m.positions.len() / 3 > MAX_ELEMENTS {
                return Err(too_large(Some("OBJ".into()), base + m.positions.len() / 3));
            }
            mesh.positions
                .extend(m.positions.chunks_exact(3).map(|p| [p[0], p[1], p[2]]));
            mesh.triangles.extend(
                m.indices
                    .chunks_exact(3)
                    .map(|t| [t[0], t[1], t[2]].map(|i| i + base as u32)),
            );
        }
        Ok(mesh)
    }
}

/// PLY: a careful reader of the header and of ASCII and binary data.
mod ply {
    use super::*;

    /// A PLY scalar type.
    #[derive(Clone, Copy, Debug, PartialEq)]
    enum Scalar {
        I8,
        U8,
        I16,
        U16,
        I32,
        U32,
        F32,
        F64,
    }

    impl Scalar {
        fn parse(name: &str) -> Option<Scalar> {
            Some(match name {
                "char" | "int8" => Scalar::I8,
                "uchar" | "uint8" => Scalar::U8,
                "short" | "int16" => Scalar::I16,
                "ushort" | "uint16" => Scalar::U16,
                "int" | "int32" => Scalar::I32,
                "uint" | "uint32" => Scalar::U32,
                "float" | "float32" => Scalar::F32,
                "double" | "float64" => Scalar::F64,
                _ => return None,
            })
        }

        fn size(self) -> usize {
            match self {
                Scalar::I8 | Scalar::U8 => 1,
                Scalar::I16 | Scalar::U16 => 2,
                Scalar::I32 | Scalar::U32 | Scalar::F32 => 4,
                Scalar::F64 => 8,
            }
        }
    }

    #[derive(Clone, Copy, Debug)]
    enum Kind {
        Scalar(Scalar),
        /// A list: the type of its length, the type of its items.
        List(Scalar, Scalar),
    }

    #[derive(Debug)]
    struct Property {
        name: String,
        kind: Kind,
    }

    #[derive(Debug)]
    struct Element {
        name: String,
        count: u64,
        properties: Vec<Property>,
    }

    impl Element {
        /// The fewest bytes one instance takes in a binary file.
        fn min_size(&self) -> u128 {
            self.properties
                .iter()
                .map(|p| match p.kind {
                    Kind::Scalar(s) | Kind::List(s, _) => s.size() as u128,
                })
                .sum()
        }
    }

    #[derive(Clone, Copy, Debug, PartialEq)]
    enum Encoding {
        Ascii,
        Binary { big_endian: bool },
    }

    struct Header {
        encoding: Encoding,
        elements: Vec<Element>,
        /// Where the data begins, and the number of header lines.
        data: usize,
        lines: usize,
    }

    fn header_error(kind: MeshErrorKind, line: usize, message: impl Into<String>) -> MeshError {
        MeshError::new(kind, Some(format!("PLY header line {line}")), message)
    }

    fn header(bytes: &[u8]) -> Result<Header, MeshError> {
        let mut encoding = None;
        let mut elements: Vec<Element> = Vec::new();
        let mut pos = 0;
        let mut line = 0;
        loop {
            let Some(length) = bytes[pos..].iter().position(|&b| b == b'\n') else {
                return Err(if line == 0 {
                    not_ply()
                } else {
                    header_error(
                        MeshErrorKind::Truncated,
                        line + 1,
                        "the header ends without end_header",
                    )
                });
            };
            let raw = &bytes[pos..pos + length];
            pos += length + 1;
            line += 1;
            let raw = raw.strip_suffix(b"\r").unwrap_or(raw);
            if line == 1 {
                if raw != b"ply" {
                    return Err(not_ply());
                }
                continue;
            }
            let Ok(text) = std::str::from_utf8(raw) else {
                return Err(header_error(
                    MeshErrorKind::Syntax,
                    line,
                    "the header line is not text",
                ));
            };
            let words: Vec<&str> = text.split_whitespace().collect();
            let bad = |what: &str| header_error(MeshErrorKind::Syntax, line, what.to_string());
            match words.as_slice() {
                [] | ["comment" | "obj_info", ..] => {}
                ["format", format, ..] => {
                    encoding = Some(match *format {
                        "ascii" => Encoding::Ascii,
                        "binary_little_endian" => Encoding::Binary { big_endian: false },
                        "binary_big_endian" => Encoding::Binary { big_endian: true },
                        other => {
                            return Err(header_error(
                                MeshErrorKind::Unsupported,
                                line,
                                format!("unknown format {}", excerpt(other.as_bytes())),
                            ));
                        }
                    });
                }
                ["element", name, count] => {
                    let count = count.parse::<u64>().map_err(|_| {
                        bad(&format!(
                            "the element count {} is not a whole number",
                            excerpt(count.as_bytes())
                        ))
                    })?;
                    elements.push(Element {
                        name: name.to_string(),
                        count,
                        properties: Vec::new(),
                    });
                }
                ["property", rest @ ..] => {
                    let scalar = |name: &str| {
                        Scalar::parse(name).ok_or_else(|| {
                            bad(&format!(
                                "unknown property type {}",
                                excerpt(name.as_bytes())
                            ))
                        })
                    };
                    let property = match rest {
                        ["list", count, item, name] => Property {
                            name: name.to_string(),
                            kind: Kind::List(scalar(count)?, scalar(item)?),
                        },
                        [ty, name] if *ty != "list" => Property {
                            name: name.to_string(),
                            kind: Kind::Scalar(scalar(ty)?),
                        },
                        _ => return Err(bad("malformed property line")),
                    };
                    let Some(element) = elements.last_mut() else {
                        return Err(bad("a property before any element"));
                    };
                    element.properties.push(property);
                }
                ["end_header"] => break,
                [word, ..] => {
                    return Err(bad(&format!(
                        "unknown header line starting with {}",
                        excerpt(word.as_bytes())
                    )));
                }
            }
        }
        let encoding = encoding.ok_or_else(|| {
            header_error(MeshErrorKind::Syntax, line, "the header has no format line")
        })?;
        Ok(Header {
            encoding,
            elements,
            data: pos,
            lines: line,
        })
    }

    fn not_ply() -> MeshError {
        MeshError::new(
            MeshErrorKind::Syntax,
            Some("PLY header line 1".into()),
            "not a PLY file (it does not begin with a line \"ply\")",
        )
    }

    /// Where the data reader is and what it reads there.
    struct Data<'a> {
        bytes: &'a [u8],
        pos: usize,
        encoding: Encoding,
        /// ASCII: the current line number in the file.
        line: usize,
        /// Offset of `bytes` in the file, for binary positions.
        offset: usize,
        /// The element and instance being read.
        element: &'a str,
        instance: u64,
    }

    impl Data<'_> {
        fn here(&self) -> Option<String> {
            Some(match self.encoding {
                Encoding::Ascii => format!(
                    "PLY line {} ({} {})",
                    self.line, self.element, self.instance
                ),
                Encoding::Binary { .. } => format!(
                    "PLY byte {} ({} {})",
                    self.offset + self.pos,
                    self.element,
                    self.instance
                ),
            })
        }

        fn error(&self, kind: MeshErrorKind, message: impl Into<String>) -> MeshError {
            MeshError::new(kind, self.here(), message)
        }

        fn truncated(&self) -> MeshError {
            self.error(
                MeshErrorKind::Truncated,
                format!("the file ends inside {} {}", self.element, self.instance),
            )
        }

        fn remaining(&self) -> usize {
            self.bytes.len() - self.pos
        }

        /// Reads one value; integers of every PLY type are exact in an f64.
        fn scalar(&mut self, ty: Scalar) -> Result<f64, MeshError> {
            match self.encoding {
                Encoding::Ascii => {
                    while let Some(&b) = self.bytes.get(self.pos) {
                        if !b.is_ascii_whitespace() {
                            break;
                        }
                        if b == b'\n' {
                            self.line += 1;
                        }
                        self.pos += 1;
                    }
                    let start = self.pos;
                    while self
                        .bytes
                        .get(self.pos)
                        .is_some_and(|b| !b.is_ascii_whitespace())
                    {
                        self.pos += 1;
                    }
                    let token = &self.bytes[start..self.pos];
                    if token.is_empty() {
                        return Err(self.truncated());
                    }
                    std::str::from_utf8(token)
                        .ok()
                        .and_then(|t| t.parse::<f64>().ok())
                        .ok_or_else(|| {
                            self.error(
                                MeshErrorKind::Syntax,
                                format!("expected a number, found {}", excerpt(token)),
                            )
                        })
                }
                Encoding::Binary { big_endian } => {
                    let size = ty.size();
                    let Some(raw) = self.bytes.get(self.pos..self.pos + size) else {
                        return Err(self.truncated());
                    };
                    self.pos += size;
                    let mut b = [0u8; 8];
                    b[..size].copy_from_slice(raw);
                    if big_endian {
                        b[..size].reverse();
                    }
                    Ok(match ty {
                        Scalar::I8 => i8::from_le_bytes([b[0]]) as f64,
                        Scalar::U8 => b[0] as f64,
                        Scalar::I16 => i16::from_le_bytes([b[0], b[1]]) as f64,
                        Scalar::U16 => u16::from_le_bytes([b[0], b[1]]) as f64,
                        Scalar::I32 => i32::from_le_bytes([b[0], b[1], b[2], b[3]]) as f64,
                        Scalar::U32 => u32::from_le_bytes([b[0], b[1], b[2], b[3]]) as f64,
                        Scalar::F32 => f32::from_le_bytes([b[0], b[1], b[2], b[3]]) as f64,
                        Scalar::F64 => f64::from_le_bytes(b),
                    })
                }
            }
        }

        /// Reads a list length, checking that so many items can still follow.
        fn list_length(&mut self, count: Scalar, item: Scalar) -> Result<usize, MeshError> {
            let n = self.scalar(count)?;
            if !(n >= 0.0 && n.fract() == 0.0) {
                return Err(self.error(
                    MeshErrorKind::Syntax,
                    format!("the list length {n} is not a whole number ≥ 0"),
                ));
            }
            // Every item takes at least its size (binary) or a character and a separator.
            let room = match self.encoding {
                Encoding::Ascii => self.remaining() / 2 + 1,
                Encoding::Binary { .. } => self.remaining() / item.size(),
            };
            if n > room as f64 {
                return Err(self.error(
                    MeshErrorKind::Truncated,
                    format!("a list of {n} items does not fit in the rest of the file"),
                ));
            }
            Ok(n as usize)
        }
    }

    pub(super) fn parse(bytes: &[u8]) -> Result<TriangleMesh, MeshError> {
        let header = header(bytes)?;
        let elements = &header.elements;
        let bad = |message: &str| {
            MeshError::new(
                MeshErrorKind::Syntax,
                Some("PLY header".into()),
                message.to_string(),
            )
        };
        let vertex = elements
            .iter()
            .position(|e| e.name == "vertex")
            .ok_or_else(|| bad("there is no vertex element"))?;
        let axis = |name: &str| {
            elements[vertex]
                .properties
                .iter()
                .position(|p| p.name == name && matches!(p.kind, Kind::Scalar(_)))
                .ok_or_else(|| bad(&format!("the vertex element has no scalar property {name}")))
        };
        let xyz = [axis("x")?, axis("y")?, axis("z")?];
        let face = elements
            .iter()
            .position(|e| e.name == "face")
            .ok_or_else(|| {
                MeshError::new(
                    MeshErrorKind::Empty,
                    Some("PLY header".into()),
                    "there is no face element (a point cloud is not a mesh)",
                )
            })?;
        let indices = elements[face]
            .properties
            .iter()
            .position(|p| {
                matches!(p.kind, Kind::List(..))
                    && (p.name == "vertex_indices" || p.name == "vertex_index")
            })
            .ok_or_else(|| bad("the face element has no list property vertex_indices"))?;

        // The data must be able to hold what the header announces.
        let data = &bytes[header.data..];
        let (needed, available) = match header.encoding {
            Encoding::Ascii => (
                elements
                    .iter()
                    .map(|e| e.count as u128 * e.properties.len() as u128)
                    .sum::<u128>(),
                (data.len() as u128).div_ceil(2),
            ),
            Encoding::Binary { .. } => (
                elements
                    .iter()
                    .map(|e| e.count as u128 * e.min_size())
                    .sum::<u128>(),
                data.len() as u128,
            ),
        };
        if needed > available {
            let what: Vec<String> = elements
                .iter()
                .map(|e| format!("{} {}", e.count, e.name))
                .collect();
            return Err(MeshError::new(
                MeshErrorKind::Truncated,
                Some("PLY header".into()),
                format!(
                    "the header announces {} but only {} of data follow",
                    what.join(", "),
                    counted(data.len() as u64, "byte", "bytes")
                ),
            ));
        }
        let vertex_count = elements[vertex].count;
        if vertex_count > MAX_ELEMENTS as u64 {
            return Err(too_large(Some("PLY header".into()), vertex_count as usize));
        }

        let mut mesh = TriangleMesh {
            positions: Vec::with_capacity(vertex_count as usize),
            triangles: Vec::with_capacity(elements[face].count as usize),
        };
        let mut reader = Data {
            bytes: data,
            pos: 0,
            encoding: header.encoding,
            line: header.lines + 1,
            offset: header.data,
            element: "",
            instance: 0,
        };
        let mut polygon: Vec<u32> = Vec::new();
        for (e, element) in elements.iter().enumerate() {
            if element.properties.is_empty() {
                continue;
            }
            reader.element = &element.name;
            for instance in 0..element.count {
                reader.instance = instance;
                let mut point = [0.0; 3];
                polygon.clear();
                for (p, property) in element.properties.iter().enumerate() {
                    match property.kind {
                        Kind::Scalar(ty) => {
                            let value = reader.scalar(ty)?;
                            if e == vertex
                                && let Some(axis) = xyz.iter().position(|&a| a == p)
                            {
                                point[axis] = value;
                            }
                        }
                        Kind::List(count, item) => {
                            let n = reader.list_length(count, item)?;
                            let wanted = e == face && p == indices;
                            for _ in 0..n {
                                let value = reader.scalar(item)?;
                                if wanted {
                                    if !(value >= 0.0
                                        && value.fract() == 0.0
                                        && value < vertex_count as f64)
                                    {
                                        return Err(reader.error(
                                            MeshErrorKind::IndexOutOfRange,
                                            format!(
                                                "the face refers to vertex {value}, but there \
                                                 are {} (numbered from 0)",
                                                counted(vertex_count, "vertex", "vertices")
                                            ),
                                        ));
                                    }
                                    polygon.push(value as u32);
                                }
                            }
                        }
                    }
                }
                if e == vertex {
                    if !point.iter().all(|c| c.is_finite()) {
                        return Err(reader.error(
                            MeshErrorKind::NonFinite,
                            "the vertex has a coordinate that is not a finite number",
                        ));
                    }
                    mesh.positions.push(point);
                } else if e == face && polygon.len() >= 3 {
                    if mesh.triangles.len() + polygon.len() - 2 > MAX_ELEMENTS {
                        return Err(too_large(reader.here(), mesh.triangles.len()));
                    }
                    for k in 1..polygon.len() - 1 {
                        mesh.triangles
                            .push([polygon[0], polygon[k], polygon[k + 1]]);
                    }
                }
            }
        }
        Ok(mesh)
    }
}

/// glTF and GLB through the `gltf` crate's document model; the GLB container, the buffers and
/// the accessors' bytes are read here, with every offset checked.
mod gltf_file {
    use super::*;
    use gltf::Semantic;
    use gltf::accessor::{DataType, Dimensions};
    use gltf::mesh::Mode;

    /// A 4×4 matrix, column-major as in glTF.
    type Matrix = [[f64; 4]; 4];

    const IDENTITY: Matrix = [
        [1.0, 0.0, 0.0, 0.0],
        [0.0, 1.0, 0.0, 0.0],
        [0.0, 0.0, 1.0, 0.0],
        [0.0, 0.0, 0.0, 1.0],
    ];

    fn multiply(a: &Matrix, b: &Matrix) -> Matrix {
        let mut m = [[0.0; 4]; 4];
        for (c, column) in m.iter_mut().enumerate() {
            for (r, entry) in column.iter_mut().enumerate() {
                *entry = (0..4).map(|k| a[k][r] * b[c][k]).sum();
            }
        }
        m
    }

    fn determinant3(m: &Matrix) -> f64 {
        m[0][0] * (m[1][1] * m[2][2] - m[2][1] * m[1][2])
            - m[1][0] * (m[0][1] * m[2][2] - m[2][1] * m[0][2])
            + m[2][0] * (m[0][1] * m[1][2] - m[1][1] * m[0][2])
    }

    fn error(kind: MeshErrorKind, location: String, message: impl Into<String>) -> MeshError {
        MeshError::new(kind, Some(location), message)
    }

    /// Splits a GLB file into its JSON chunk and its BIN chunk (if any).
    fn split_glb(bytes: &[u8]) -> Result<(&[u8], Option<&[u8]>), MeshError> {
        let word = |at: usize| {
            bytes
                .get(at..at + 4)
                .map(|b| u32::from_le_bytes([b[0], b[1], b[2], b[3]]) as usize)
        };
        let here = |at: usize| format!("GLB byte {at}");
        let truncated = |at: usize| {
            error(
                MeshErrorKind::Truncated,
                here(at),
                "the file ends inside a chunk header",
            )
        };
        let version = word(4).ok_or_else(|| truncated(4))?;
        if version != 2 {
            return Err(error(
                MeshErrorKind::Unsupported,
                here(4),
                format!("GLB version {version} (only 2 is supported)"),
            ));
        }
        let length = word(8).ok_or_else(|| truncated(8))?;
        if length > bytes.len() {
            return Err(error(
                MeshErrorKind::Truncated,
                here(8),
                format!(
                    "the header gives a length of {length} bytes, but the file has {}",
                    bytes.len()
                ),
            ));
        }
        let bytes = &bytes[..length.max(12).min(bytes.len())];
        let (mut json, mut bin) = (None, None);
        let mut at = 12;
        while at < bytes.len() {
            let size = word(at).ok_or_else(|| truncated(at))?;
            let kind = bytes.get(at + 4..at + 8).ok_or_else(|| truncated(at + 4))?;
            let body = bytes.get(at + 8..at + 8 + size).ok_or_else(|| {
                error(
                    MeshErrorKind::Truncated,
                    here(at),
                    format!("a chunk of {size} bytes reaches past the end of the file"),
                )
            })?;
            match kind {
                b"JSON" if json.is_none() => json = Some(body),
                b"BIN\0" if bin.is_none() && json.is_some() => bin = Some(body),
                // Chunks of unknown types are skipped, as the specification asks.
                _ => {}
            }
            at += 8 + size;
            at += (4 - at % 4) % 4;
        }
        let json = json.ok_or_else(|| {
            error(
                MeshErrorKind::Syntax,
                here(12),
                "the file has no JSON chunk",
            )
        })?;
        Ok((json, bin))
    }

    /// The gltf crate's error, shortened to the first few validation problems.
    fn describe(e: gltf::Error) -> MeshError {
        let message = match e {
            gltf::Error::Validation(problems) => {
                let shown: Vec<String> = problems
                    .iter()
                    .take(3)
                    .map(|(path, problem)| format!("{path}: {problem}"))
                    .collect();
                let more = problems.len().saturating_sub(3);
                let mut text = format!("invalid glTF: {}", shown.join("; "));
                if more > 0 {
                    text.push_str(&format!(" (and {more} more)"));
                }
                text
            }
            other => format!("invalid glTF: {other}"),
        };
        MeshError::new(MeshErrorKind::Syntax, Some("glTF".into()), message)
    }

    /// The buffers, loaded when first used.
    struct Buffers<'a> {
        bin: Option<&'a [u8]>,
        base: Option<&'a Path>,
        loaded: Vec<Option<Vec<u8>>>,
        /// Bytes of input so far (the file and the external buffers read), which bounds the
        /// size of the mesh.
        input: usize,
    }

    impl Buffers<'_> {
        fn get(&mut self, buffer: &gltf::Buffer<'_>) -> Result<&[u8], MeshError> {
            let i = buffer.index();
            let here = || format!("glTF buffer {i}");
            let uri = match buffer.source() {
                gltf::buffer::Source::Bin => {
                    return self.bin.ok_or_else(|| {
                        error(
                            MeshErrorKind::Syntax,
                            here(),
                            "the buffer has no URI and there is no GLB binary chunk",
                        )
                    });
                }
                gltf::buffer::Source::Uri(uri) => uri,
            };
            if self.loaded.len() <= i {
                self.loaded.resize(i + 1, None);
            }
            if self.loaded[i].is_none() {
                let data = if let Some(data) = uri.strip_prefix("data:") {
                    let (kind, payload) = data.split_once(',').unwrap_or((data, ""));
                    if !kind.ends_with(";base64") {
                        return Err(error(
                            MeshErrorKind::Unsupported,
                            here(),
                            "only base64 data URIs are supported",
                        ));
                    }
                    base64(payload.as_bytes()).ok_or_else(|| {
                        error(
                            MeshErrorKind::Syntax,
                            here(),
                            "the data URI is not valid base64",
                        )
                    })?
                } else if uri.contains("://") {
                    return Err(error(
                        MeshErrorKind::Unsupported,
                        here(),
                        format!(
                            "remote buffer {} (only local files are read)",
                            excerpt(uri.as_bytes())
                        ),
                    ));
                } else {
                    let Some(base) = self.base else {
                        return Err(error(
                            MeshErrorKind::Unsupported,
                            here(),
                            format!(
                                "the buffer is the external file {}, but no directory to find \
                                 it in was given",
                                excerpt(uri.as_bytes())
                            ),
                        ));
                    };
                    let path = base.join(percent_decode(uri));
                    let data = std::fs::read(&path).map_err(|e| {
                        error(
                            MeshErrorKind::Io,
                            here(),
                            format!("cannot read {}: {e}", path.display()),
                        )
                    })?;
                    self.input += data.len();
                    data
                };
                self.loaded[i] = Some(data);
            }
            Ok(self.loaded[i].as_deref().unwrap_or_default())
        }
    }

    /// Standard base64 (padding optional); `None` on any other character.
    fn base64(text: &[u8]) -> Option<Vec<u8>> {
        let text = text
            .strip_suffix(b"==")
            .or_else(|| text.strip_suffix(b"="))
            .unwrap_or(text);
        let mut out = Vec::with_capacity(text.len() / 4 * 3 + 3);
        let (mut acc, mut bits) = (0u32, 0);
        for &c in text {
            let v = match c {
                b'A'..=b'Z' => c - b'A',
                b'a'..=b'z' => c - b'a' + 26,
                b'0'..=b'9' => c - b'0' + 52,
                b'+' => 62,
                b'/' => 63,
                _ => return None,
            };
            acc = (acc << 6) | v as u32;
            bits += 6;
            if bits >= 8 {
                bits -= 8;
                out.push((acc >> bits) as u8);
                acc &= (1 << bits) - 1;
            }
        }
        Some(out)
    }

    /// A relative URI reference as a path: `%XX` escapes decoded.
    fn percent_decode(uri: &str) -> PathBuf {
        let bytes = uri.as_bytes();
        let mut out = Vec::with_capacity(bytes.len());
        let mut i = 0;
        while i < bytes.len() {
            let hex = bytes
                .get(i + 1..i + 3)
                .and_then(|h| std::str::from_utf8(h).ok())
                .and_then(|h| u8::from_str_radix(h, 16).ok());
            match (bytes[i], hex) {
                (b'%', Some(b)) => {
                    out.push(b);
                    i += 3;
                }
                (b, _) => {
                    out.push(b);
                    i += 1;
                }
            }
        }
        PathBuf::from(String::from_utf8_lossy(&out).into_owned())
    }

    /// The bytes of each element of an accessor, with every offset checked: (data, start,
    /// stride, count).
    fn elements<'b>(
        accessor: &gltf::Accessor<'_>,
        buffers: &'b mut Buffers<'_>,
    ) -> Result<(&'b [u8], usize, usize, usize), MeshError> {
        let here = || format!("glTF accessor {}", accessor.index());
        if accessor.sparse().is_some() {
            return Err(error(
                MeshErrorKind::Unsupported,
                here(),
                "sparse accessors are not supported",
            ));
        }
        let view = accessor.view().ok_or_else(|| {
            error(
                MeshErrorKind::Unsupported,
                here(),
                "the accessor has no buffer view (compressed meshes are not supported)",
            )
        })?;
        let size = accessor.size();
        let stride = view.stride().unwrap_or(size);
        if stride < size {
            return Err(error(
                MeshErrorKind::Syntax,
                here(),
                format!("the byte stride {stride} is less than the element size {size}"),
            ));
        }
        let count = accessor.count();
        let data = buffers.get(&view.buffer())?;
        let view_end = view.offset().checked_add(view.length());
        let start = view.offset().checked_add(accessor.offset());
        let end = match (start, count) {
            (Some(s), 0) => Some(s),
            (Some(s), n) => (n - 1)
                .checked_mul(stride)
                .and_then(|x| x.checked_add(size))
                .and_then(|x| x.checked_add(s)),
            (None, _) => None,
        };
        match (start, end, view_end) {
            (Some(start), Some(end), Some(view_end))
                if end <= view_end && view_end <= data.len() =>
            {
                Ok((data, start, stride, count))
            }
            _ => Err(error(
                MeshErrorKind::Truncated,
                here(),
                format!(
                    "{} reach past the end of buffer view {} or of buffer {} ({})",
                    counted(count as u64, "element", "elements"),
                    view.index(),
                    view.buffer().index(),
                    counted(data.len() as u64, "byte", "bytes")
                ),
            )),
        }
    }

    /// One component at `at`, as a float (normalised integers mapped as glTF says).
    fn component(data: &[u8], at: usize, ty: DataType, normalized: bool) -> f64 {
        let b = |k: usize| data.get(at + k).copied().unwrap_or(0);
        let (value, scale) = match ty {
            DataType::I8 => (b(0) as i8 as f64, 127.0),
            DataType::U8 => (b(0) as f64, 255.0),
            DataType::I16 => (i16::from_le_bytes([b(0), b(1)]) as f64, 32767.0),
            DataType::U16 => (u16::from_le_bytes([b(0), b(1)]) as f64, 65535.0),
            DataType::U32 => (
                u32::from_le_bytes([b(0), b(1), b(2), b(3)]) as f64,
                4294967295.0,
            ),
            DataType::F32 => (f32::from_le_bytes([b(0), b(1), b(2), b(3)]) as f64, 1.0),
        };
        if normalized && ty != DataType::F32 {
            (value / scale).max(-1.0)
        } else {
            value
        }
    }

    fn component_size(ty: DataType) -> usize {
        match ty {
            DataType::I8 | DataType::U8 => 1,
            DataType::I16 | DataType::U16 => 2,
            DataType::U32 | DataType::F32 => 4,
        }
    }

    fn positions(
        accessor: &gltf::Accessor<'_>,
        buffers: &mut Buffers<'_>,
    ) -> Result<Vec<[f64; 3]>, MeshError> {
        if accessor.dimensions() != Dimensions::Vec3 {
            return Err(error(
                MeshErrorKind::Syntax,
                format!("glTF accessor {}", accessor.index()),
                "positions must be 3-vectors",
            ));
        }
        let (ty, normalized) = (accessor.data_type(), accessor.normalized());
        let c = component_size(ty);
        let (data, start, stride, count) = elements(accessor, buffers)?;
        Ok((0..count)
            .map(|i| {
                let at = start + i * stride;
                [0, 1, 2].map(|k| component(data, at + k * c, ty, normalized))
            })
            .collect())
    }

    fn indices(
        accessor: &gltf::Accessor<'_>,
        buffers: &mut Buffers<'_>,
    ) -> Result<Vec<u32>, MeshError> {
        let ty = accessor.data_type();
        if accessor.dimensions() != Dimensions::Scalar
            || !matches!(ty, DataType::U8 | DataType::U16 | DataType::U32)
        {
            return Err(error(
                MeshErrorKind::Syntax,
                format!("glTF accessor {}", accessor.index()),
                "indices must be unsigned integer scalars",
            ));
        }
        let (data, start, stride, count) = elements(accessor, buffers)?;
        Ok((0..count)
            .map(|i| component(data, start + i * stride, ty, false) as u32)
            .collect())
    }

    /// Adds a primitive's triangles, transformed by `world`.
    fn add_primitive(
        mesh: &mut TriangleMesh,
        primitive: &gltf::Primitive<'_>,
        world: &Matrix,
        buffers: &mut Buffers<'_>,
        where_: &str,
    ) -> Result<(), MeshError> {
        if !matches!(
            primitive.mode(),
            Mode::Triangles | Mode::TriangleStrip | Mode::TriangleFan
        ) {
            return Ok(());
        }
        let Some(accessor) = primitive.get(&Semantic::Positions) else {
            return Ok(());
        };
        let limit = MAX_ELEMENTS.min(buffers.input.saturating_mul(64).saturating_add(1 << 16));
        if mesh.positions.len() + accessor.count() > limit {
            return Err(too_large(
                Some(where_.into()),
                mesh.positions.len() + accessor.count(),
            ));
        }
        let points = positions(&accessor, buffers)?;
        let n = points.len();
        let order: Vec<u32> = match primitive.indices() {
            Some(accessor) => indices(&accessor, buffers)?,
            None => (0..n as u32).collect(),
        };
        if let Some(&bad) = order.iter().find(|&&i| i as usize >= n) {
            return Err(error(
                MeshErrorKind::IndexOutOfRange,
                where_.into(),
                format!(
                    "an index refers to vertex {bad}, but the primitive has {}",
                    counted(n as u64, "vertex", "vertices")
                ),
            ));
        }
        let triangles: Vec<[u32; 3]> = match primitive.mode() {
            Mode::TriangleStrip => (0..order.len().saturating_sub(2))
                .map(|i| {
                    if i % 2 == 0 {
                        [order[i], order[i + 1], order[i + 2]]
                    } else {
                        [order[i + 1], order[i], order[i + 2]]
                    }
                })
                .filter(|t| t[0] != t[1] && t[1] != t[2] && t[2] != t[0])
                .collect(),
            Mode::TriangleFan => (1..order.len().saturating_sub(1))
                .map(|i| [order[i], order[i + 1], order[0]])
                .collect(),
            _ => order.chunks_exact(3).map(|t| [t[0], t[1], t[2]]).collect(),
        };
        if mesh.triangles.len() + triangles.len() > limit {
            return Err(too_large(
                Some(where_.into()),
                mesh.triangles.len() + triangles.len(),
            ));
        }
        let base = mesh.positions.len() as u32;
        mesh.positions.extend(points.iter().map(|p| {
            [0, 1, 2]
                .map(|r| world[0][r] * p[0] + world[1][r] * p[1] + world[2][r] * p[2] + world[3][r])
        }));
        if let Some(i) = mesh.positions[base as usize..]
            .iter()
            .position(|p| !p.iter().all(|c| c.is_finite()))
        {
            return Err(error(
                MeshErrorKind::NonFinite,
                where_.into(),
                format!("vertex {i} has a coordinate that is not a finite number"),
            ));
        }
        let flip = determinant3(world) < 0.0;
        mesh.triangles
            .extend(triangles.into_iter().map(|[a, b, c]| {
                if flip {
                    [a + base, c + base, b + base]
                } else {
                    [a + base, b + base, c + base]
                }
            }));
        Ok(())
    }

    fn add_mesh(
        mesh: &mut TriangleMesh,
        source: &gltf::Mesh<'_>,
        world: &Matrix,
        buffers: &mut Buffers<'_>,
    ) -> Result<(), MeshError> {
        for primitive in source.primitives() {
            let where_ = format!(
                "glTF mesh {} primitive {}",
                source.index(),
                primitive.index()
            );
            add_primitive(mesh, &primitive, world, buffers, &where_)?;
        }
        Ok(())
    }

    pub(super) fn parse(bytes: &[u8], base: Option<&Path>) -> Result<TriangleMesh, MeshError> {
        let (json, bin) = if bytes.starts_with(b"glTF") {
            split_glb(bytes)?
        } else {
            (bytes, None)
        };
        if json.starts_with(b"glTF") {
            return Err(error(
                MeshErrorKind::Syntax,
                "glTF".into(),
                "the JSON chunk is not JSON",
            ));
        }
        let root = gltf::Gltf::from_slice_without_validation(json)
            .map_err(describe)?
            .document
            .into_json();
        // gltf-json's validation indexes the accessors with a primitive's POSITION attribute
        // unchecked (and panics when it is out of range), so check those references first.
        for (m, mesh) in root.meshes.iter().enumerate() {
            for (p, primitive) in mesh.primitives.iter().enumerate() {
                if let Some(index) = primitive
                    .attributes
                    .values()
                    .find(|index| index.value() >= root.accessors.len())
                {
                    return Err(error(
                        MeshErrorKind::Syntax,
                        format!("glTF mesh {m} primitive {p}"),
                        format!(
                            "an attribute refers to accessor {}, but there are {}",
                            index.value(),
                            counted(root.accessors.len() as u64, "accessor", "accessors")
                        ),
                    ));
                }
            }
        }
        let document = gltf::Document::from_json(root).map_err(describe)?;
        let mut buffers = Buffers {
            bin,
            base,
            loaded: Vec::new(),
            input: bytes.len(),
        };
        let mut mesh = TriangleMesh::default();
        let scene = document
            .default_scene()
            .or_else(|| document.scenes().next());
        let Some(scene) = scene else {
            for source in document.meshes() {
                add_mesh(&mut mesh, &source, &IDENTITY, &mut buffers)?;
            }
            return Ok(mesh);
        };
        // Depth first with an explicit stack; a node reached twice would make the hierarchy a
        // graph (or a cycle) rather than the tree glTF requires.
        let mut seen = vec![false; document.nodes().len()];
        let mut stack: Vec<(gltf::Node<'_>, Matrix)> =
            scene.nodes().map(|node| (node, IDENTITY)).collect();
        stack.reverse();
        while let Some((node, parent)) = stack.pop() {
            let i = node.index();
            if std::mem::replace(&mut seen[i], true) {
                return Err(error(
                    MeshErrorKind::Syntax,
                    format!("glTF node {i}"),
                    "the node is reached twice: the node hierarchy is not a tree",
                ));
            }
            let local = node.transform().matrix().map(|c| c.map(f64::from));
            let world = multiply(&parent, &local);
            if let Some(source) = node.mesh() {
                add_mesh(&mut mesh, &source, &world, &mut buffers)?;
            }
            let children: Vec<_> = node.children().collect();
            stack.extend(children.into_iter().rev().map(|child| (child, world)));
        }
        Ok(mesh)
    }
}
