//! The Stanford PLY reader: the header, and data in ASCII or in binary of either byte order.
//!
//! The format is Greg Turk's "The PLY Polygon File Format" (mirrored at
//! <https://paulbourke.net/dataformats/ply/>): a text header declares elements, each with a
//! count and typed properties, and the data follows in that order. The shape is the `vertex`
//! element's scalar properties `x`, `y` and `z` and the `face` element's list property
//! `vertex_indices` (or `vertex_index`); other elements and properties are read past.
//!
//! A header may announce any count, so before the reader allocates anything it checks that the
//! data can hold what the header announces, and before each list that the rest of the file can
//! hold its items: arbitrary bytes neither panic nor exhaust memory. Each error names the header
//! line, or the data line (ASCII) or byte (binary) and the element being read.

use super::{MAX_ELEMENTS, MeshError, MeshErrorKind, counted, excerpt, too_large};
use crate::mesh::TriangleMesh;

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

/// What a property holds: one value, or a list of values preceded by its length.
#[derive(Clone, Copy, Debug)]
enum PropertyKind {
    Scalar(Scalar),
    List {
        /// The type of the list's length.
        length: Scalar,
        /// The type of its items.
        item: Scalar,
    },
}

#[derive(Debug)]
struct Property {
    name: String,
    kind: PropertyKind,
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
                PropertyKind::Scalar(s) | PropertyKind::List { length: s, .. } => s.size() as u128,
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
                        kind: PropertyKind::List {
                            length: scalar(count)?,
                            item: scalar(item)?,
                        },
                    },
                    [ty, name] if *ty != "list" => Property {
                        name: name.to_string(),
                        kind: PropertyKind::Scalar(scalar(ty)?),
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
struct DataReader<'a> {
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

impl DataReader<'_> {
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
    fn list_length(&mut self, length: Scalar, item: Scalar) -> Result<usize, MeshError> {
        let n = self.scalar(length)?;
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
            .position(|p| p.name == name && matches!(p.kind, PropertyKind::Scalar(_)))
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
            matches!(p.kind, PropertyKind::List { .. })
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
    let mut reader = DataReader {
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
                    PropertyKind::Scalar(ty) => {
                        let value = reader.scalar(ty)?;
                        if e == vertex
                            && let Some(axis) = xyz.iter().position(|&a| a == p)
                        {
                            point[axis] = value;
                        }
                    }
                    PropertyKind::List { length, item } => {
                        let n = reader.list_length(length, item)?;
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
