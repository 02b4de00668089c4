//! The Wavefront OBJ reader: [`tobj`] does the parsing, behind a line filter that keeps only
//! what the shape needs.
//!
//! The format is Wavefront's "Object Files (.obj)", appendix B1 of the Advanced Visualizer
//! manual (mirrored at <https://paulbourke.net/dataformats/obj/>). Only `v` (positions) and `f`
//! (polygonal faces) matter here. The filter sits in front of `tobj` because `tobj` reports
//! neither lines nor which index is out of range, and would keep attributes the shape does not
//! use: the filter counts lines and vertices, so that each error names its line; makes relative
//! (negative) indices absolute and checks every index against the vertices defined so far;
//! drops per-vertex colours; and blanks normals, texture coordinates, groups, materials and
//! polylines, so that `tobj` sees a single object of positions and faces.

use std::io::{self, BufRead, Read};

use super::{MAX_ELEMENTS, MeshError, MeshErrorKind, counted, excerpt, too_large};
use crate::mesh::TriangleMesh;

/// Feeds `tobj` one line at a time, counting lines (for messages) and vertices (to resolve
/// relative indices and check every index against the vertices defined so far). Face
/// corners are cut down to their position index, made absolute; lines that only concern
/// attributes, groups, materials or polylines are blanked; so `tobj` sees one object of
/// positions and faces.
struct LineFilter<'a> {
    rest: &'a [u8],
    /// Lines handed out so far (the 1-based number of the current line).
    line: usize,
    /// `v` lines so far.
    vertices: usize,
    /// The largest position index a face has used, and the line it is on.
    largest_index: usize,
    largest_index_line: usize,
    /// The current line as `tobj` gets it, and how much of it it has taken.
    buf: Vec<u8>,
    pos: usize,
    /// The first problem the filter found; it stops the reading.
    error: Option<MeshError>,
}

impl LineFilter<'_> {
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
                                        counted(self.vertices as u64, "vertex is", "vertices are")
                                    ),
                                ));
                            }
                            self.vertices as u64 + 1 - back
                        }
                    };
                    if absolute > self.largest_index as u64 {
                        self.largest_index = absolute as usize;
                        self.largest_index_line = self.line;
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

impl Read for LineFilter<'_> {
    fn read(&mut self, out: &mut [u8]) -> io::Result<usize> {
        let available = self.fill_buf()?;
        let n = available.len().min(out.len());
        out[..n].copy_from_slice(&available[..n]);
        self.consume(n);
        Ok(n)
    }
}

impl BufRead for LineFilter<'_> {
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
    let mut lines = LineFilter {
        rest: bytes,
        line: 0,
        vertices: 0,
        largest_index: 0,
        largest_index_line: 0,
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
    let (largest, line) = (lines.largest_index, lines.largest_index_line);
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
