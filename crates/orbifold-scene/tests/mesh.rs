//! Meshes: the built-in shapes are closed, outward and well formed, the letters are chiral, and
//! the OBJ, PLY and glTF/GLB readers read back what was written and fail cleanly on bad input.

use std::collections::HashMap;
use std::path::Path;
use std::time::Instant;

use num_complex::Complex64;
use orbifold_scene::mesh::TriangleMesh;
use orbifold_scene::mesh::import::{MeshError, MeshErrorKind, MeshFormat, load_mesh, parse_mesh};
use orbifold_scene::mesh::procedural::{
    NAMES, builtin, capsule, cube, extrude, letter, torus, uv_sphere,
};
use orbifold_scene::validate::SHAPES;
use proptest::prelude::*;

// ---------------------------------------------------------------------------------------------
// Properties of meshes.

/// Every directed edge appears once and its reverse once: closed, 2-manifold along edges, and
/// consistently oriented.
fn assert_closed(name: &str, mesh: &TriangleMesh) {
    let mut edges: HashMap<(u32, u32), usize> = HashMap::new();
    for t in &mesh.triangles {
        for k in 0..3 {
            *edges.entry((t[k], t[(k + 1) % 3])).or_default() += 1;
        }
    }
    for (&(a, b), &n) in &edges {
        assert_eq!(
            n, 1,
            "{name}: edge {a}→{b} is used {n} times in one direction"
        );
        assert_eq!(
            edges.get(&(b, a)),
            Some(&1),
            "{name}: edge {a}→{b} has no partner in the opposite direction"
        );
    }
}

fn sub(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

fn norm(a: [f64; 3]) -> f64 {
    (a[0] * a[0] + a[1] * a[1] + a[2] * a[2]).sqrt()
}

fn assert_no_degenerate_triangles(name: &str, mesh: &TriangleMesh) {
    for (i, t) in mesh.triangles.iter().enumerate() {
        assert!(
            t[0] != t[1] && t[1] != t[2] && t[2] != t[0],
            "{name}: triangle {i} repeats a vertex"
        );
        let [a, b, c] = t.map(|k| mesh.positions[k as usize]);
        let area = 0.5 * norm(cross(sub(b, a), sub(c, a)));
        assert!(area > 1e-7, "{name}: triangle {i} has area {area}");
    }
}

/// The signed volume of each connected part (parts joined through shared vertices).
fn part_volumes(mesh: &TriangleMesh) -> Vec<f64> {
    let mut parent: Vec<usize> = (0..mesh.positions.len()).collect();
    fn root(parent: &mut [usize], mut i: usize) -> usize {
        while parent[i] != i {
            parent[i] = parent[parent[i]];
            i = parent[i];
        }
        i
    }
    for t in &mesh.triangles {
        for k in 1..3 {
            let (a, b) = (
                root(&mut parent, t[0] as usize),
                root(&mut parent, t[k] as usize),
            );
            parent[a] = b;
        }
    }
    let mut parts: HashMap<usize, TriangleMesh> = HashMap::new();
    for t in &mesh.triangles {
        let part = parts.entry(root(&mut parent, t[0] as usize)).or_default();
        part.positions = mesh.positions.clone();
        part.triangles.push(*t);
    }
    parts.values().map(TriangleMesh::signed_volume).collect()
}

/// ∫ f dV over the solid, f a polynomial of degree ≤ 3 in the offset from the centre of mass:
/// the cubic five-point rule on the tetrahedra from the centre of mass to each triangle.
fn integrate<const N: usize>(mesh: &TriangleMesh, f: impl Fn([f64; 3]) -> [f64; N]) -> [f64; N] {
    let c = mesh.centre_of_mass().expect("a positive volume");
    let mut total = [0.0; N];
    for t in &mesh.triangles {
        let [a, b, d] = t.map(|k| sub(mesh.positions[k as usize], c));
        let volume = (a[0] * (b[1] * d[2] - b[2] * d[1]) - a[1] * (b[0] * d[2] - b[2] * d[0])
            + a[2] * (b[0] * d[1] - b[1] * d[0]))
            / 6.0;
        let corners = [[0.0; 3], a, b, d];
        let centroid = [0, 1, 2].map(|k| corners.iter().map(|v| v[k]).sum::<f64>() / 4.0);
        let mut add = |p: [f64; 3], weight: f64| {
            for (sum, value) in total.iter_mut().zip(f(p)) {
                *sum += volume * weight * value;
            }
        };
        add(centroid, -0.8);
        for v in corners {
            add(
                [0, 1, 2].map(|k| v[k] / 3.0 + 2.0 * centroid[k] / 3.0),
                0.45,
            );
        }
    }
    total
}

/// Pseudo-scalars of the solid that turns about the vertical (y) axis and translations leave
/// alone and that a reflection x ↦ −x negates. With w = x + iz horizontal and moments about
/// the centre of mass, I = ∫ w², J₁ = ∫ y w, J₂ = ∫ y² w (made dimensionless by the volume and
/// the radius of gyration): Im(J₁² Ī), Im(J̄₁ J₂), Im(J₂² Ī). A solid for which one of them is
/// not zero is not congruent to its mirror image by any turn about a vertical axis.
fn chirality(mesh: &TriangleMesh) -> [f64; 3] {
    let [v, r2, i_re, i_im, j1_re, j1_im, j2_re, j2_im] = integrate(mesh, |[x, y, z]| {
        [
            1.0,
            x * x + y * y + z * z,
            x * x - z * z,
            2.0 * x * z,
            y * x,
            y * z,
            y * y * x,
            y * y * z,
        ]
    });
    let l = (r2 / v).sqrt();
    let i = Complex64::new(i_re, i_im) / (v * l * l);
    let j1 = Complex64::new(j1_re, j1_im) / (v * l * l);
    let j2 = Complex64::new(j2_re, j2_im) / (v * l * l * l);
    [
        (j1 * j1 * i.conj()).im,
        (j1.conj() * j2).im,
        (j2 * j2 * i.conj()).im,
    ]
}

const MIRROR_X: [[f64; 3]; 3] = [[-1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];

fn turn_about_y(angle: f64) -> [[f64; 3]; 3] {
    let (s, c) = angle.sin_cos();
    [[c, 0.0, s], [0.0, 1.0, 0.0], [-s, 0.0, c]]
}

fn transformed(mesh: &TriangleMesh, linear: [[f64; 3]; 3], offset: [f64; 3]) -> TriangleMesh {
    let mut m = mesh.clone();
    m.transform(linear, offset);
    m
}

/// The vertex positions, sorted, rounded to 1e-9.
fn vertex_set(mesh: &TriangleMesh) -> Vec<[i64; 3]> {
    let mut v: Vec<[i64; 3]> = mesh
        .positions
        .iter()
        .map(|p| p.map(|c| (c * 1e9).round() as i64))
        .collect();
    v.sort_unstable();
    v
}

// ---------------------------------------------------------------------------------------------
// The built-in shapes.

#[test]
fn the_builtin_names_are_the_scene_shapes() {
    assert_eq!(NAMES, SHAPES);
    for name in SHAPES {
        assert!(builtin(name).is_some(), "{name}");
    }
    assert!(builtin("teapot").is_none());
    assert!(letter('x').is_none());
}

#[test]
fn every_builtin_is_closed_outward_well_formed_and_unit_sized() {
    for name in SHAPES {
        let mesh = builtin(name).unwrap();
        assert!(!mesh.triangles.is_empty(), "{name}");
        assert!(
            mesh.triangles.len() <= 8000,
            "{name}: {} triangles",
            mesh.triangles.len()
        );
        assert!(
            mesh.triangles
                .iter()
                .flatten()
                .all(|&i| (i as usize) < mesh.positions.len())
        );
        assert_closed(name, &mesh);
        assert_no_degenerate_triangles(name, &mesh);
        assert!(mesh.signed_volume() > 0.0, "{name}");
        for v in part_volumes(&mesh) {
            assert!(v > 0.0, "{name}: a part has volume {v}");
        }
        let (lo, hi) = mesh.bounds().unwrap();
        assert!(lo[1].abs() < 1e-12, "{name} rests on y = 0, not {}", lo[1]);
        let extent = (0..3).map(|k| hi[k] - lo[k]).fold(0.0, f64::max);
        assert!((0.8..=2.0).contains(&extent), "{name}: extent {extent}");
        for k in [0, 2] {
            assert!(
                (hi[k] + lo[k]).abs() < 0.5,
                "{name} is horizontally centred: {lo:?} {hi:?}"
            );
        }
    }
}

#[test]
fn generators_with_parameters() {
    let sphere = uv_sphere(0.5, 32, 24);
    assert_eq!(sphere.triangles.len(), 2 * 32 * 23);
    let volume = 4.0 / 3.0 * std::f64::consts::PI * 0.125;
    assert!((sphere.signed_volume() / volume - 1.0).abs() < 0.02);
    assert!(
        sphere
            .positions
            .iter()
            .all(|p| (norm(*p) - 0.5).abs() < 1e-12)
    );
    let t = torus(0.35, 0.15, 40, 20);
    assert_eq!(t.triangles.len(), 2 * 40 * 20);
    let volume = 2.0 * std::f64::consts::PI.powi(2) * 0.35 * 0.15 * 0.15;
    assert!((t.signed_volume() / volume - 1.0).abs() < 0.03);
    let c = cube(2.0);
    assert_eq!((c.positions.len(), c.triangles.len()), (8, 12));
    assert!((c.signed_volume() - 8.0).abs() < 1e-12);
    let cap = capsule(0.1, 0.5, 12, 3);
    for (name, mesh) in [
        ("sphere", &sphere),
        ("torus", &t),
        ("cube", &c),
        ("capsule", &cap),
    ] {
        assert_closed(name, mesh);
        assert_no_degenerate_triangles(name, mesh);
        assert!(mesh.signed_volume() > 0.0);
    }
    // Small resolutions are raised to the least that makes a closed mesh.
    for mesh in [uv_sphere(1.0, 0, 0), torus(1.0, 0.2, 1, 1)] {
        assert_closed("coarse", &mesh);
        assert!(mesh.signed_volume() > 0.0);
    }
    // A square ring, either way round.
    let outer = [[0.0, 0.0], [0.0, 3.0], [3.0, 3.0], [3.0, 0.0]];
    let hole = vec![[1.0, 1.0], [2.0, 1.0], [2.0, 2.0], [1.0, 2.0]];
    let ring = extrude(&outer, &[hole], 0.0, 1.0);
    assert_closed("ring", &ring);
    assert_no_degenerate_triangles("ring", &ring);
    assert!((ring.signed_volume() - 8.0).abs() < 1e-12);
    // Two holes, one of them a triangle, the other clockwise already.
    let holes = vec![
        vec![[0.5, 0.5], [1.5, 0.5], [1.0, 2.5]],
        vec![[2.0, 0.5], [2.0, 2.5], [2.5, 2.5], [2.5, 0.5]],
    ];
    let two = extrude(&outer, &holes, -0.5, 0.5);
    assert_closed("two holes", &two);
    assert_no_degenerate_triangles("two holes", &two);
    assert!((two.signed_volume() - (9.0 - 1.0 - 1.0)).abs() < 1e-12);
    // Nonsense input gives some mesh, and no panic.
    let _ = extrude(&[[0.0, 0.0]], &[hole_of_nothing()], 0.0, 1.0);
    let _ = extrude(&[], &[], 0.0, 1.0);
}

fn hole_of_nothing() -> Vec<[f64; 2]> {
    vec![[5.0, 5.0], [6.0, 5.0], [5.0, 6.0]]
}

#[test]
fn the_figure_stands_on_its_feet_and_faces_forward() {
    let figure = builtin("figure").unwrap();
    let (lo, hi) = figure.bounds().unwrap();
    assert!(lo[1].abs() < 1e-12);
    assert!((1.6..=1.95).contains(&hi[1]), "height {}", hi[1]);
    // The nose and toes point to +z.
    assert!(hi[2] > -lo[2]);
    // Its raised right hand (−x) makes it chiral.
    let chi = chirality(&figure);
    assert!(chi.iter().any(|c| c.abs() > 1e-3), "{chi:?}");
    let mirrored = chirality(&transformed(&figure, MIRROR_X, [0.0; 3]));
    for k in 0..3 {
        assert!((mirrored[k] + chi[k]).abs() < 1e-9);
    }
}

#[test]
fn q_and_d_are_p_and_b_in_a_mirror() {
    for (a, b) in [("letter-p", "letter-q"), ("letter-b", "letter-d")] {
        let (a, b) = (builtin(a).unwrap(), builtin(b).unwrap());
        let mirrored = transformed(&a, MIRROR_X, [0.0; 3]);
        assert_eq!(vertex_set(&mirrored), vertex_set(&b));
        assert_eq!(mirrored, b);
    }
}

#[test]
fn the_letters_are_chiral_under_turns_about_the_vertical() {
    for name in ["letter-p", "letter-q", "letter-b", "letter-d", "letter-f"] {
        let mesh = builtin(name).unwrap();
        let chi = chirality(&mesh);
        assert!(chi.iter().any(|c| c.abs() > 1e-3), "{name}: χ = {chi:?}");
        for angle in [0.3, 1.0, std::f64::consts::PI, 4.0] {
            let turned = chirality(&transformed(&mesh, turn_about_y(angle), [0.7, -0.2, 1.3]));
            for k in 0..3 {
                assert!(
                    (turned[k] - chi[k]).abs() < 1e-9,
                    "{name}: χ is invariant under turns"
                );
            }
        }
        let mirrored = chirality(&transformed(&mesh, MIRROR_X, [0.0; 3]));
        for k in 0..3 {
            assert!((mirrored[k] + chi[k]).abs() < 1e-9);
        }
    }
    // A bare extruded glyph is not chiral in space: it is its own mirror image in z ↦ −z, so
    // a half turn about y makes the mirrored outline. Hence the plinths.
    let outline = [
        [0.0, 0.0],
        [0.2, 0.0],
        [0.2, 0.5],
        [0.5, 0.5],
        [0.5, 0.7],
        [0.0, 0.7],
    ];
    let slab = extrude(&outline, &[], -0.1, 0.1);
    assert!(chirality(&slab).iter().all(|c| c.abs() < 1e-12));
    // So p and q (b and d) are not congruent by a turn about a vertical axis, while the flat
    // outline of a p turned half way round is that of a q.
    let (p, q) = (builtin("letter-p").unwrap(), builtin("letter-q").unwrap());
    let turned = transformed(&p, turn_about_y(std::f64::consts::PI), [0.0; 3]);
    assert_ne!(vertex_set(&turned), vertex_set(&q));
    let front = |m: &TriangleMesh| -> Vec<[i64; 2]> {
        let mut v: Vec<[i64; 2]> = m
            .positions
            .iter()
            .filter(|p| p[1] > 0.06 && p[2].abs() < 0.1 + 1e-9)
            .map(|p| [(p[0] * 1e9).round() as i64, (p[1] * 1e9).round() as i64])
            .collect();
        v.sort_unstable();
        v.dedup();
        v
    };
    assert_eq!(front(&turned), front(&q));
}

#[test]
fn the_letters_read_from_the_front() {
    // Seen from +z with y up, +x is to the right.
    let side = |name: &str, low: bool| {
        let mesh = builtin(name).unwrap();
        let (lo, hi) = mesh.bounds().unwrap();
        let cut = lo[1] + 0.3 * (hi[1] - lo[1]);
        // Mean x of the glyph's vertices (not the plinth's) in its lowest or highest part.
        let xs: Vec<f64> = mesh
            .positions
            .iter()
            .filter(|p| p[2].abs() < 0.1 + 1e-9)
            .filter(|p| if low { p[1] < cut } else { p[1] > hi[1] - 0.3 })
            .map(|p| p[0])
            .collect();
        xs.iter().sum::<f64>() / xs.len() as f64
    };
    // p and q: only the stem reaches down; b and d: only the stem reaches up.
    assert!(side("letter-p", true) < -0.1);
    assert!(side("letter-q", true) > 0.1);
    assert!(side("letter-b", false) < -0.1);
    assert!(side("letter-d", false) > 0.1);
    // F: its stem on the left, its arms to the right.
    assert!(side("letter-f", true) < -0.1);
    // The plinth reaches out behind.
    let (lo, hi) = builtin("letter-p").unwrap().bounds().unwrap();
    assert!(-lo[2] > 2.0 * hi[2]);
}

// ---------------------------------------------------------------------------------------------
// Writing small files.

/// A tetrahedron with coordinates that f32 cannot hold exactly, oriented outward.
fn tetrahedron() -> TriangleMesh {
    let mut mesh = TriangleMesh {
        positions: vec![
            [0.1, 0.2, 0.3],
            [1.1, 0.25, 0.35],
            [0.15, 1.3, 0.2],
            [0.2, 0.3, 1.7],
        ],
        triangles: vec![[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]],
    };
    if mesh.signed_volume() < 0.0 {
        mesh.flip();
    }
    mesh
}

fn obj_text(mesh: &TriangleMesh) -> String {
    let mut s = String::from("# a test\nmtllib missing.mtl\no thing\n");
    for p in &mesh.positions {
        s += &format!("v {} {} {}\n", p[0], p[1], p[2]);
    }
    s += "vn 0 0 1\nvt 0.5 0.5\nusemtl stone\n";
    for t in &mesh.triangles {
        s += &format!("f {}/1/1 {}/1/1 {}/1/1\n", t[0] + 1, t[1] + 1, t[2] + 1);
    }
    s
}

fn ply_header(mesh: &TriangleMesh, format: &str, coordinate: &str) -> String {
    format!(
        "ply\nformat {format} 1.0\ncomment made by a test\nelement vertex {}\n\
         property {coordinate} x\nproperty {coordinate} y\nproperty {coordinate} z\n\
         property uchar red\nelement face {}\nproperty list uchar int vertex_indices\n\
         property list ushort float texcoord\nelement edge 1\nproperty int vertex1\n\
         property int vertex2\nend_header\n",
        mesh.positions.len(),
        mesh.triangles.len()
    )
}

fn ply_ascii(mesh: &TriangleMesh) -> Vec<u8> {
    let mut s = ply_header(mesh, "ascii", "double");
    for p in &mesh.positions {
        s += &format!("{} {} {} 255\n", p[0], p[1], p[2]);
    }
    for t in &mesh.triangles {
        s += &format!("3 {} {} {} 2 0.5 0.25\n", t[0], t[1], t[2]);
    }
    s += "0 1\n";
    s.into_bytes()
}

fn ply_binary(mesh: &TriangleMesh, big_endian: bool, double: bool) -> Vec<u8> {
    let format = if big_endian {
        "binary_big_endian"
    } else {
        "binary_little_endian"
    };
    let mut out = ply_header(mesh, format, if double { "double" } else { "float" }).into_bytes();
    let mut put = |bytes: &[u8]| {
        let mut b = bytes.to_vec();
        if big_endian {
            b.reverse();
        }
        out.extend_from_slice(&b);
    };
    for p in &mesh.positions {
        for c in p {
            if double {
                put(&c.to_le_bytes());
            } else {
                put(&(*c as f32).to_le_bytes());
            }
        }
        put(&[255]);
    }
    for t in &mesh.triangles {
        put(&[3]);
        for i in t {
            put(&(*i as i32).to_le_bytes());
        }
        put(&1u16.to_le_bytes());
        put(&0.5f32.to_le_bytes());
    }
    put(&0i32.to_le_bytes());
    put(&1i32.to_le_bytes());
    out
}

/// The BIN data (f32 positions, then u16 indices) and the glTF JSON for one mesh in one
/// node with `node` extra properties (such as a transform); `buffer` is the buffer object's
/// extra members (such as a URI).
fn gltf_parts(mesh: &TriangleMesh, node: &str, buffer: &str) -> (String, Vec<u8>) {
    let mut bin = Vec::new();
    for p in &mesh.positions {
        for c in p {
            bin.extend_from_slice(&(*c as f32).to_le_bytes());
        }
    }
    let positions = bin.len();
    for t in &mesh.triangles {
        for i in t {
            bin.extend_from_slice(&(*i as u16).to_le_bytes());
        }
    }
    let indices = bin.len() - positions;
    let (lo, hi) = mesh.bounds().unwrap();
    let f = |v: [f64; 3]| format!("[{},{},{}]", v[0] as f32, v[1] as f32, v[2] as f32);
    let json = format!(
        r#"{{"asset":{{"version":"2.0"}},"scene":0,"scenes":[{{"nodes":[0]}}],
        "nodes":[{{"children":[1]}},{{"mesh":0{node}}}],
        "meshes":[{{"primitives":[{{"attributes":{{"POSITION":0}},"indices":1}}]}}],
        "buffers":[{{"byteLength":{}{buffer}}}],
        "bufferViews":[{{"buffer":0,"byteLength":{positions}}},
                       {{"buffer":0,"byteOffset":{positions},"byteLength":{indices}}}],
        "accessors":[{{"bufferView":0,"componentType":5126,"count":{},"type":"VEC3",
                       "min":{},"max":{}}},
                     {{"bufferView":1,"componentType":5123,"count":{},"type":"SCALAR"}}]}}"#,
        bin.len(),
        mesh.positions.len(),
        f(lo),
        f(hi),
        3 * mesh.triangles.len()
    );
    (json, bin)
}

/// A GLB file: header, JSON chunk, BIN chunk.
fn glb(json: &str, bin: &[u8]) -> Vec<u8> {
    let mut json = json.as_bytes().to_vec();
    while !json.len().is_multiple_of(4) {
        json.push(b' ');
    }
    let mut bin = bin.to_vec();
    while !bin.len().is_multiple_of(4) {
        bin.push(0);
    }
    let total = 12 + 8 + json.len() + 8 + bin.len();
    let mut out = b"glTF".to_vec();
    out.extend_from_slice(&2u32.to_le_bytes());
    out.extend_from_slice(&(total as u32).to_le_bytes());
    out.extend_from_slice(&(json.len() as u32).to_le_bytes());
    out.extend_from_slice(b"JSON");
    out.extend_from_slice(&json);
    out.extend_from_slice(&(bin.len() as u32).to_le_bytes());
    out.extend_from_slice(b"BIN\0");
    out.extend_from_slice(&bin);
    out
}

fn base64(bytes: &[u8]) -> String {
    const ALPHABET: &[u8] = b"ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    let mut out = String::new();
    for chunk in bytes.chunks(3) {
        let b = [0, 1, 2].map(|k| chunk.get(k).copied().unwrap_or(0) as u32);
        let n = b[0] << 16 | b[1] << 8 | b[2];
        for k in 0..4 {
            if k <= chunk.len() {
                out.push(ALPHABET[(n >> (18 - 6 * k) & 63) as usize] as char);
            } else {
                out.push('=');
            }
        }
    }
    out
}

fn assert_same(read: &TriangleMesh, written: &TriangleMesh, tolerance: f64, what: &str) {
    assert_eq!(read.triangles, written.triangles, "{what}");
    assert_eq!(read.positions.len(), written.positions.len(), "{what}");
    for (a, b) in read.positions.iter().zip(&written.positions) {
        for k in 0..3 {
            assert!((a[k] - b[k]).abs() <= tolerance, "{what}: {a:?} vs {b:?}");
        }
    }
}

/// Each triangle's corners (which do not depend on how the vertices are numbered).
fn corners(mesh: &TriangleMesh) -> Vec<[[f64; 3]; 3]> {
    mesh.triangles
        .iter()
        .map(|t| t.map(|i| mesh.positions[i as usize]))
        .collect()
}

/// A fresh scratch directory, removed when the test ends (also when it fails).
fn scratch(name: &str) -> tempfile::TempDir {
    tempfile::Builder::new()
        .prefix(&format!("orbifold-mesh-test-{name}-"))
        .tempdir()
        .unwrap()
}

fn kind(result: Result<TriangleMesh, MeshError>) -> MeshErrorKind {
    let error = result.expect_err("an error");
    assert!(!error.to_string().is_empty());
    error.kind
}

// ---------------------------------------------------------------------------------------------
// Round trips.

#[test]
fn formats_from_paths() {
    for (name, format) in [
        ("a.obj", Some(MeshFormat::Obj)),
        ("dir/b.OBJ", Some(MeshFormat::Obj)),
        ("c.Ply", Some(MeshFormat::Ply)),
        ("d.gltf", Some(MeshFormat::Gltf)),
        ("e.GLB", Some(MeshFormat::Glb)),
        ("f.stl", None),
        ("obj", None),
    ] {
        assert_eq!(MeshFormat::from_path(Path::new(name)), format, "{name}");
    }
}

#[test]
fn obj_round_trip() {
    let mesh = tetrahedron();
    let read = parse_mesh(obj_text(&mesh).as_bytes(), MeshFormat::Obj, None).unwrap();
    // Vertices come back numbered in order of first use.
    assert_eq!(corners(&read), corners(&mesh));
    assert_eq!(read.positions.len(), mesh.positions.len());
}

#[test]
fn obj_polygons_groups_and_relative_indices() {
    // A cube of quads in two groups, with normals, indices partly relative, one vertex with a
    // colour and one with a weight (1 1 1 2 is (0.5, 0.5, 0.5)).
    let text = "v 0 0 0\nv 1 0 0 1 0 0\nv 0 1 0\nv 1 1 0\nv 0 0 1\nv 1 0 1\nv 0 1 1\nv 1 1 1 2\n\
                vn 1 0 0\ng a\nf 1//1 3//1 4//1 2//1\nf 5 6 8 7\nf -8 -7 -3 -4\ng b\n\
                f 3 7 8 4\nf 1 5 7 3\nf 2 4 8 6\r\n";
    let mesh = parse_mesh(text.as_bytes(), MeshFormat::Obj, None).unwrap();
    assert_eq!((mesh.positions.len(), mesh.triangles.len()), (8, 12));
    assert_closed("OBJ cube", &mesh);
    assert!(mesh.positions.contains(&[0.5, 0.5, 0.5]));
    assert!(mesh.signed_volume() > 0.0);
}

#[test]
fn ply_round_trips() {
    let mesh = tetrahedron();
    let read = parse_mesh(&ply_ascii(&mesh), MeshFormat::Ply, None).unwrap();
    assert_same(&read, &mesh, 0.0, "ASCII PLY");
    for big_endian in [false, true] {
        for double in [false, true] {
            let bytes = ply_binary(&mesh, big_endian, double);
            let read = parse_mesh(&bytes, MeshFormat::Ply, None).unwrap();
            let tolerance = if double { 0.0 } else { 1e-7 };
            assert_same(
                &read,
                &mesh,
                tolerance,
                &format!("PLY {big_endian} {double}"),
            );
        }
    }
}

#[test]
fn ply_polygons_are_fans() {
    let text = "ply\r\nformat ascii 1.0\r\nelement vertex 4\r\nproperty float x\r\n\
                property float y\r\nproperty float z\r\nelement face 2\r\n\
                property list uint8 uint32 vertex_index\r\nend_header\r\n\
                0 0 0\r\n1 0 0\r\n1 1 0\r\n0 1 0\r\n4 0 1 2 3\r\n2 0 1\r\n";
    let mesh = parse_mesh(text.as_bytes(), MeshFormat::Ply, None).unwrap();
    assert_eq!(mesh.triangles, vec![[0, 1, 2], [0, 2, 3]]);
}

#[test]
fn glb_round_trip_with_node_transforms() {
    let mesh = tetrahedron();
    let (json, bin) = gltf_parts(&mesh, "", "");
    let read = parse_mesh(&glb(&json, &bin), MeshFormat::Glb, None).unwrap();
    assert_same(&read, &mesh, 1e-7, "GLB");
    // A translation and a mirroring scale: moved, and still outward.
    let (json, bin) = gltf_parts(&mesh, r#","translation":[1,2,3],"scale":[-1,1,1]"#, "");
    let read = parse_mesh(&glb(&json, &bin), MeshFormat::Glb, None).unwrap();
    assert!(read.signed_volume() > 0.0);
    assert!((read.signed_volume() - mesh.signed_volume()).abs() < 1e-6);
    for (a, b) in read.positions.iter().zip(&mesh.positions) {
        let expected = [1.0 - b[0], 2.0 + b[1], 3.0 + b[2]];
        assert!((0..3).all(|k| (a[k] - expected[k]).abs() < 1e-6));
    }
    // Read as .gltf all the same.
    assert!(parse_mesh(&glb(&json, &bin), MeshFormat::Gltf, None).is_ok());
}

#[test]
fn gltf_with_a_data_uri_and_with_an_external_buffer() {
    let mesh = tetrahedron();
    let (_, bin) = gltf_parts(&mesh, "", "");
    let uri = format!(
        r#","uri":"data:application/octet-stream;base64,{}""#,
        base64(&bin)
    );
    let (json, _) = gltf_parts(&mesh, "", &uri);
    let read = parse_mesh(json.as_bytes(), MeshFormat::Gltf, None).unwrap();
    assert_same(&read, &mesh, 1e-7, "glTF data URI");

    let tmp = scratch("gltf");
    let dir = tmp.path();
    let (json, bin) = gltf_parts(&mesh, "", r#","uri":"tetra%20data.bin""#);
    std::fs::write(dir.join("tetra data.bin"), &bin).unwrap();
    std::fs::write(dir.join("tetra.gltf"), &json).unwrap();
    let read = load_mesh(&dir.join("tetra.gltf")).unwrap();
    assert_same(&read, &mesh, 1e-7, "glTF external buffer");
    // Without a directory to look in, the external buffer cannot be found.
    let e = parse_mesh(json.as_bytes(), MeshFormat::Gltf, None).unwrap_err();
    assert_eq!(e.kind, MeshErrorKind::Unsupported);
    assert!(e.to_string().contains("buffer 0"), "{e}");
    // A missing buffer file is an I/O error that names it.
    std::fs::remove_file(dir.join("tetra data.bin")).unwrap();
    let e = load_mesh(&dir.join("tetra.gltf")).unwrap_err();
    assert_eq!(e.kind, MeshErrorKind::Io);
    assert!(e.to_string().contains("tetra data.bin"), "{e}");
    assert!(e.to_string().contains("tetra.gltf"), "{e}");

    // The other formats through files too.
    std::fs::write(dir.join("t.OBJ"), obj_text(&mesh)).unwrap();
    std::fs::write(dir.join("t.ply"), ply_binary(&mesh, true, true)).unwrap();
    std::fs::write(dir.join("t.glb"), glb(&gltf_parts(&mesh, "", "").0, &bin)).unwrap();
    for name in ["t.ply", "t.glb"] {
        let read = load_mesh(&dir.join(name)).unwrap();
        assert_same(&read, &mesh, 1e-7, name);
    }
    let read = load_mesh(&dir.join("t.OBJ")).unwrap();
    assert_eq!(corners(&read), corners(&mesh));
}

#[test]
fn gltf_without_a_scene_reads_every_mesh() {
    let mesh = tetrahedron();
    let (json, bin) = gltf_parts(&mesh, r#","translation":[5,5,5]"#, "");
    let json = json.replace(r#""scene":0,"scenes":[{"nodes":[0]}],"#, "");
    let read = parse_mesh(&glb(&json, &bin), MeshFormat::Glb, None).unwrap();
    // No scene: the mesh as it is, without the node's transform.
    assert_same(&read, &mesh, 1e-7, "no scene");
}

#[test]
fn builtins_survive_a_round_trip() {
    for name in SHAPES {
        let mesh = builtin(name).unwrap();
        let read = parse_mesh(&ply_binary(&mesh, false, true), MeshFormat::Ply, None).unwrap();
        assert_same(&read, &mesh, 0.0, name);
    }
}

// ---------------------------------------------------------------------------------------------
// Errors.

#[test]
fn garbage_is_an_error_in_every_format() {
    let garbage: &[u8] = b"\x00\x01\xffgarbage\nnot a mesh\n\x7f";
    for format in [
        MeshFormat::Obj,
        MeshFormat::Ply,
        MeshFormat::Gltf,
        MeshFormat::Glb,
    ] {
        let e = parse_mesh(garbage, format, None).unwrap_err();
        assert!(!e.message.is_empty(), "{format}");
        let e = parse_mesh(b"", format, None).unwrap_err();
        assert!(!e.message.is_empty(), "{format}");
    }
    assert_eq!(
        kind(parse_mesh(
            b"glTF\x02\0\0\0\x08\0\0\0",
            MeshFormat::Glb,
            None
        )),
        MeshErrorKind::Syntax
    );
    assert_eq!(
        kind(parse_mesh(b"glTF\x01\0\0\0", MeshFormat::Glb, None)),
        MeshErrorKind::Unsupported
    );
}

#[test]
fn empty_files_have_no_triangles() {
    for text in [
        "",
        "# nothing\n",
        "v 0 0 0\nv 1 0 0\nv 0 1 0\n",
        "v 0 0 0\nv 1 0 0\nf 1 2\n",
    ] {
        let e = parse_mesh(text.as_bytes(), MeshFormat::Obj, None).unwrap_err();
        assert_eq!(e.kind, MeshErrorKind::Empty, "{text:?}: {e}");
    }
    let e = parse_mesh(
        b"ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\n\
          property float z\nend_header\n0 0 0\n",
        MeshFormat::Ply,
        None,
    )
    .unwrap_err();
    assert_eq!(e.kind, MeshErrorKind::Empty);
}

#[test]
fn indices_out_of_range_say_where() {
    let e = parse_mesh(
        b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 4\n",
        MeshFormat::Obj,
        None,
    )
    .unwrap_err();
    assert_eq!(e.kind, MeshErrorKind::IndexOutOfRange);
    assert_eq!(e.location.as_deref(), Some("OBJ line 4"));
    let e = parse_mesh(b"v 0 0 0\nv 1 0 0\nf 1 2 -3\n", MeshFormat::Obj, None).unwrap_err();
    assert_eq!(e.kind, MeshErrorKind::IndexOutOfRange);
    assert_eq!(e.location.as_deref(), Some("OBJ line 3"));
    let e = parse_mesh(b"v 0 0 0\nf 0 1 1\n", MeshFormat::Obj, None).unwrap_err();
    assert_eq!(e.kind, MeshErrorKind::IndexOutOfRange);

    let mut bad = tetrahedron();
    bad.triangles[3][2] = 4;
    let e = parse_mesh(&ply_ascii(&bad), MeshFormat::Ply, None).unwrap_err();
    assert_eq!(e.kind, MeshErrorKind::IndexOutOfRange, "{e}");
    assert_eq!(e.location.as_deref(), Some("PLY line 23 (face 3)"), "{e}");
    for big_endian in [false, true] {
        let e =
            parse_mesh(&ply_binary(&bad, big_endian, false), MeshFormat::Ply, None).unwrap_err();
        assert_eq!(e.kind, MeshErrorKind::IndexOutOfRange, "{e}");
    }

    bad.triangles[2][1] = 9;
    let (json, bin) = gltf_parts(&bad, "", "");
    let e = parse_mesh(&glb(&json, &bin), MeshFormat::Glb, None).unwrap_err();
    assert_eq!(e.kind, MeshErrorKind::IndexOutOfRange, "{e}");
    assert!(e.to_string().contains("mesh 0 primitive 0"), "{e}");
}

#[test]
fn non_finite_coordinates_are_rejected() {
    let e = parse_mesh(
        b"v 0 0 0\nv nan 0 0\nv 0 1 0\nf 1 2 3\n",
        MeshFormat::Obj,
        None,
    )
    .unwrap_err();
    assert_eq!(e.kind, MeshErrorKind::NonFinite);
    assert_eq!(e.location.as_deref(), Some("OBJ line 2"));
    let e = parse_mesh(
        b"v 0 0 0\nv 1 0 0\nv 0 1 inf\nf 1 2 3\n",
        MeshFormat::Obj,
        None,
    )
    .unwrap_err();
    assert_eq!(e.kind, MeshErrorKind::NonFinite);

    let mut mesh = tetrahedron();
    mesh.positions[1][2] = f64::NAN;
    let text = String::from_utf8(ply_ascii(&mesh)).unwrap();
    let e = parse_mesh(text.as_bytes(), MeshFormat::Ply, None).unwrap_err();
    assert_eq!(e.kind, MeshErrorKind::NonFinite, "{e}");
    assert!(e.to_string().contains("vertex 1"), "{e}");
    for big_endian in [false, true] {
        let e =
            parse_mesh(&ply_binary(&mesh, big_endian, false), MeshFormat::Ply, None).unwrap_err();
        assert_eq!(e.kind, MeshErrorKind::NonFinite);
    }
    let (json, bin) = gltf_parts(&tetrahedron(), "", "");
    let mut bin = bin;
    bin[20..24].copy_from_slice(&f32::INFINITY.to_le_bytes());
    let e = parse_mesh(&glb(&json, &bin), MeshFormat::Glb, None).unwrap_err();
    assert_eq!(e.kind, MeshErrorKind::NonFinite, "{e}");
}

#[test]
fn truncated_files_are_errors() {
    let mesh = tetrahedron();
    for big_endian in [false, true] {
        let bytes = ply_binary(&mesh, big_endian, false);
        for cut in [1, 5, 17, 40] {
            let e = parse_mesh(&bytes[..bytes.len() - cut], MeshFormat::Ply, None).unwrap_err();
            assert_eq!(e.kind, MeshErrorKind::Truncated, "cut {cut}: {e}");
        }
    }
    let text = ply_ascii(&mesh);
    let e = parse_mesh(&text[..text.len() - 10], MeshFormat::Ply, None).unwrap_err();
    assert_eq!(e.kind, MeshErrorKind::Truncated, "{e}");
    let header = ply_header(&mesh, "ascii", "float");
    let e = parse_mesh(&header.as_bytes()[..40], MeshFormat::Ply, None).unwrap_err();
    assert_eq!(e.kind, MeshErrorKind::Truncated, "{e}");

    let (json, bin) = gltf_parts(&mesh, "", "");
    let file = glb(&json, &bin);
    for cut in [1, 8, 30, file.len() - 20] {
        let e = parse_mesh(&file[..file.len() - cut], MeshFormat::Glb, None).unwrap_err();
        assert!(!e.message.is_empty());
    }
    // A BIN chunk too short for the accessors.
    let e = parse_mesh(&glb(&json, &bin[..30]), MeshFormat::Glb, None).unwrap_err();
    assert_eq!(e.kind, MeshErrorKind::Truncated, "{e}");
}

#[test]
fn a_header_that_claims_a_trillion_vertices_fails_fast() {
    let start = Instant::now();
    for format in ["ascii", "binary_little_endian"] {
        let text = format!(
            "ply\nformat {format} 1.0\nelement vertex 1000000000000\nproperty float x\n\
             property float y\nproperty float z\nelement face 1000000000000\n\
             property list uchar int vertex_indices\nend_header\n0 0 0 1 1 1"
        );
        let e = parse_mesh(text.as_bytes(), MeshFormat::Ply, None).unwrap_err();
        assert_eq!(e.kind, MeshErrorKind::Truncated, "{e}");
        assert!(e.to_string().contains("1000000000000 vertex"), "{e}");
    }
    // A list length that cannot fit either.
    let text = "ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\n\
                property float y\nproperty float z\nelement face 1\n\
                property list uint int vertex_indices\nend_header\n";
    let mut bytes = text.as_bytes().to_vec();
    bytes.extend_from_slice(&[0; 36]);
    bytes.extend_from_slice(&u32::MAX.to_le_bytes());
    bytes.extend_from_slice(&[0; 12]);
    let e = parse_mesh(&bytes, MeshFormat::Ply, None).unwrap_err();
    assert_eq!(e.kind, MeshErrorKind::Truncated, "{e}");
    // An element with no properties and a huge count takes no time.
    let text = "ply\nformat ascii 1.0\nelement nothing 18446744073709551615\n\
                element vertex 3\nproperty float x\nproperty float y\nproperty float z\n\
                element face 1\nproperty list uchar int vertex_indices\nend_header\n\
                0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n";
    assert!(parse_mesh(text.as_bytes(), MeshFormat::Ply, None).is_ok());
    // A GLB accessor that claims a huge count.
    let mesh = tetrahedron();
    let (json, bin) = gltf_parts(&mesh, "", "");
    let json = json.replace(r#""count":4,"#, r#""count":4000000000,"#);
    let e = parse_mesh(&glb(&json, &bin), MeshFormat::Glb, None).unwrap_err();
    assert!(
        matches!(e.kind, MeshErrorKind::Truncated | MeshErrorKind::TooLarge),
        "{e}"
    );
    assert!(start.elapsed().as_secs_f64() < 2.0);
}

#[test]
fn ply_header_errors_have_lines() {
    let e = parse_mesh(
        b"ply\nformat ascii 1.0\nelement vertex 1\nproperty float33 x\nend_header\n",
        MeshFormat::Ply,
        None,
    )
    .unwrap_err();
    assert_eq!(e.location.as_deref(), Some("PLY header line 4"));
    assert!(e.message.contains("float33"));
    let e = parse_mesh(
        b"ply\nformat ascii 1.0\nelement vertex 1\n",
        MeshFormat::Ply,
        None,
    )
    .unwrap_err();
    assert_eq!(e.kind, MeshErrorKind::Truncated);
    let e = parse_mesh(
        b"ply\nformat binary_middle_endian 1.0\nend_header\n",
        MeshFormat::Ply,
        None,
    )
    .unwrap_err();
    assert_eq!(e.kind, MeshErrorKind::Unsupported);
    let e = parse_mesh(b"solid cube\n", MeshFormat::Ply, None).unwrap_err();
    assert!(e.message.contains("not a PLY file"), "{e}");
    let e = parse_mesh(
        b"ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\n\
          property float z\nelement face 0\nproperty list uchar int vertex_indices\n\
          end_header\n0 zero 0\n",
        MeshFormat::Ply,
        None,
    )
    .unwrap_err();
    assert_eq!(e.kind, MeshErrorKind::Syntax);
    assert_eq!(e.location.as_deref(), Some("PLY line 10 (vertex 0)"));
}

#[test]
fn obj_syntax_errors_have_lines() {
    let e = parse_mesh(b"v 0 0 0\nv 1 0\nv 0 1 0\nf 1 2 3\n", MeshFormat::Obj, None).unwrap_err();
    assert_eq!(e.kind, MeshErrorKind::Syntax);
    assert_eq!(e.location.as_deref(), Some("OBJ line 2"));
    let e = parse_mesh(
        b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 x 3\n",
        MeshFormat::Obj,
        None,
    )
    .unwrap_err();
    assert_eq!(e.location.as_deref(), Some("OBJ line 4"));
    assert!(e.message.contains("\"x\""), "{e}");
    let e = parse_mesh(b"v 0 0 0\n\xff\xfe\n", MeshFormat::Obj, None).unwrap_err();
    assert_eq!(e.location.as_deref(), Some("OBJ line 2"));
}

#[test]
fn gltf_structure_errors() {
    let mesh = tetrahedron();
    // A cycle in the node hierarchy.
    let (json, bin) = gltf_parts(&mesh, r#","children":[0]"#, "");
    let e = parse_mesh(&glb(&json, &bin), MeshFormat::Glb, None).unwrap_err();
    assert_eq!(
        e.to_string(),
        "glTF node 0: the node is reached twice: the node hierarchy is not a tree"
    );
    // A POSITION attribute naming an accessor that does not exist (gltf-json's own validation
    // would panic on it).
    let (json, bin) = gltf_parts(&mesh, "", "");
    let json = json.replace(r#""POSITION":0"#, r#""POSITION":5"#);
    let e = parse_mesh(&glb(&json, &bin), MeshFormat::Glb, None).unwrap_err();
    assert_eq!(e.kind, MeshErrorKind::Syntax);
    assert!(e.to_string().contains("accessor 5"), "{e}");
    // A reference to an accessor that does not exist.
    let (json, bin) = gltf_parts(&mesh, "", "");
    let json = json.replace(r#""indices":1"#, r#""indices":7"#);
    let e = parse_mesh(&glb(&json, &bin), MeshFormat::Glb, None).unwrap_err();
    assert_eq!(e.kind, MeshErrorKind::Syntax);
    assert!(e.message.contains("indices"), "{e}");
    // Remote buffers are not fetched.
    let (json, _) = gltf_parts(&mesh, "", r#","uri":"https://example.com/a.bin""#);
    let e = parse_mesh(json.as_bytes(), MeshFormat::Gltf, None).unwrap_err();
    assert_eq!(e.kind, MeshErrorKind::Unsupported);
}

#[test]
fn load_mesh_names_the_file() {
    let e = load_mesh(Path::new("/nonexistent/dir/model.ply")).unwrap_err();
    assert_eq!(e.kind, MeshErrorKind::Io);
    assert!(
        e.to_string().starts_with("/nonexistent/dir/model.ply: "),
        "{e}"
    );
    let e = load_mesh(Path::new("model.stl")).unwrap_err();
    assert_eq!(e.kind, MeshErrorKind::UnknownFormat);
    let tmp = scratch("names");
    let dir = tmp.path();
    let path = dir.join("broken.obj");
    std::fs::write(&path, "v 0 0 0\nf 1 1 2\n").unwrap();
    let e = load_mesh(&path).unwrap_err();
    assert_eq!(
        e.to_string(),
        format!(
            "{}: OBJ line 2: the face refers to vertex 2, but only 1 vertex is defined",
            path.display()
        )
    );
}

// ---------------------------------------------------------------------------------------------
// No input makes a reader panic.

const FORMATS: [MeshFormat; 4] = [
    MeshFormat::Obj,
    MeshFormat::Ply,
    MeshFormat::Gltf,
    MeshFormat::Glb,
];

fn samples() -> Vec<(MeshFormat, Vec<u8>)> {
    let mesh = tetrahedron();
    let (json, bin) = gltf_parts(&mesh, r#","rotation":[0,0.6,0,0.8]"#, "");
    let uri = format!(
        r#","uri":"data:application/gltf-buffer;base64,{}""#,
        base64(&bin)
    );
    vec![
        (MeshFormat::Obj, obj_text(&mesh).into_bytes()),
        (MeshFormat::Ply, ply_ascii(&mesh)),
        (MeshFormat::Ply, ply_binary(&mesh, false, false)),
        (MeshFormat::Ply, ply_binary(&mesh, true, true)),
        (MeshFormat::Glb, glb(&json, &bin)),
        (MeshFormat::Gltf, gltf_parts(&mesh, "", &uri).0.into_bytes()),
    ]
}

#[test]
fn the_samples_are_valid() {
    for (format, bytes) in samples() {
        let mesh = parse_mesh(&bytes, format, None).unwrap();
        assert_eq!(mesh.triangles.len(), 4);
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(512))]

    #[test]
    fn random_bytes_never_panic(bytes in prop::collection::vec(any::<u8>(), 0..600)) {
        for format in FORMATS {
            let _ = parse_mesh(&bytes, format, None);
        }
    }

    #[test]
    fn random_data_after_a_ply_header_never_panics(
        binary in any::<bool>(),
        data in prop::collection::vec(any::<u8>(), 0..300),
    ) {
        let format = if binary { "binary_big_endian" } else { "ascii" };
        let mut bytes = format!(
            "ply\nformat {format} 1.0\nelement vertex 4\nproperty short x\nproperty double y\n\
             property int8 z\nelement face 3\nproperty list int16 uint16 vertex_indices\n\
             end_header\n"
        )
        .into_bytes();
        bytes.extend_from_slice(&data);
        let _ = parse_mesh(&bytes, MeshFormat::Ply, None);
    }

    #[test]
    fn damaged_files_never_panic(
        which in any::<prop::sample::Index>(),
        edits in prop::collection::vec((any::<prop::sample::Index>(), any::<u8>()), 0..6),
        cut in any::<prop::sample::Index>(),
        truncate in any::<bool>(),
    ) {
        let samples = samples();
        let (format, mut bytes) = samples[which.index(samples.len())].clone();
        for (at, byte) in edits {
            let i = at.index(bytes.len());
            bytes[i] = byte;
        }
        if truncate {
            bytes.truncate(cut.index(bytes.len() + 1));
        }
        for f in FORMATS {
            if let Ok(mesh) = parse_mesh(&bytes, f, None) {
                prop_assert!(!mesh.triangles.is_empty());
                prop_assert!(mesh.positions.iter().flatten().all(|c| c.is_finite()));
                prop_assert!(mesh.triangles.iter().flatten().all(|&i| (i as usize) < mesh.positions.len()));
            }
        }
        let _ = format;
    }
}
