//! The glTF 2.0 reader, for both the JSON form (`.gltf`) and the binary container (`.glb`).
//!
//! The format is the Khronos glTF 2.0 specification
//! (<https://registry.khronos.org/glTF/specs/2.0/glTF-2.0.html>). The `gltf` crate parses and
//! validates the JSON into its document model; the GLB container, the buffers (GLB binary
//! chunk, base64 data URIs, files beside the glTF file) and the accessors' bytes are read here,
//! with every offset and length checked against the bytes there are, so that a file that lies
//! about its sizes is an error rather than a panic. The mesh is the default scene's (or else
//! the first scene's) node tree, each node's mesh placed by the product of the transforms above
//! it; without scenes, every mesh as it is. Primitives that are not triangles, triangle strips
//! or fans are skipped; sparse and compressed accessors are not supported.

use std::path::{Path, PathBuf};

use gltf::Semantic;
use gltf::accessor::{DataType, Dimensions};
use gltf::mesh::Mode;

use super::{MAX_ELEMENTS, MeshError, MeshErrorKind, counted, excerpt, too_large};
use crate::mesh::TriangleMesh;

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
                crate::base64::decode(payload.as_bytes()).ok_or_else(|| {
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
                let data = crate::files::read(&path).map_err(|e| {
                    error(
                        MeshErrorKind::Io,
                        here(),
                        format!("cannot read {}: {e}", path.display()),
                    )
                })?;
                self.input += data.len();
                data.into_vec()
            };
            self.loaded[i] = Some(data);
        }
        Ok(self.loaded[i].as_deref().unwrap_or_default())
    }
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

/// Where an accessor's elements lie in their buffer, every offset checked: element `i` begins
/// at `data[start + i * stride]`.
struct AccessorElements<'b> {
    /// The whole buffer.
    data: &'b [u8],
    start: usize,
    stride: usize,
    count: usize,
}

/// The bytes of each element of an accessor, with every offset checked.
fn elements<'b>(
    accessor: &gltf::Accessor<'_>,
    buffers: &'b mut Buffers<'_>,
) -> Result<AccessorElements<'b>, MeshError> {
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
        (Some(start), Some(end), Some(view_end)) if end <= view_end && view_end <= data.len() => {
            Ok(AccessorElements {
                data,
                start,
                stride,
                count,
            })
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
    let AccessorElements {
        data,
        start,
        stride,
        count,
    } = elements(accessor, buffers)?;
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
    let AccessorElements {
        data,
        start,
        stride,
        count,
    } = elements(accessor, buffers)?;
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
    location: &str,
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
            Some(location.into()),
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
            location.into(),
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
            Some(location.into()),
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
            location.into(),
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
        let location = format!(
            "glTF mesh {} primitive {}",
            source.index(),
            primitive.index()
        );
        add_primitive(mesh, &primitive, world, buffers, &location)?;
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
