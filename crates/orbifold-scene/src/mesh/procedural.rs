//! The built-in shapes: a sphere, a torus, a cube, a human figure and the letters p, q, b, d
//! and F (the seed's Fig. 3.4 uses p, q, b, d to tell reflections from rotations).
//!
//! Every mesh here is closed (each edge is shared by exactly two triangles, in opposite
//! directions), oriented outward and free of degenerate triangles; a mesh made of several parts
//! (the figure, a letter on its stand) is closed part by part. [`builtin`] returns the shapes at
//! about one unit in size, resting on the plane y = 0; the generators take their dimensions and
//! resolutions as parameters and are centred at the origin unless they say otherwise.
//!
//! ```
//! use orbifold_scene::mesh::procedural::builtin;
//! let p = builtin("letter-p").unwrap();
//! let q = builtin("letter-q").unwrap();
//! // q is p seen in a mirror x ↦ −x …
//! let mut mirrored = p.clone();
//! mirrored.transform([[-1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]], [0.0; 3]);
//! assert_eq!(mirrored, q);
//! assert!(p.signed_volume() > 0.0);
//! assert!(builtin("teapot").is_none());
//! ```
//!
//! An extruded letter on its own would not be chiral in space: turned half way round about the
//! vertical axis, an upright slab p *is* a q seen from the front. So each letter stands on a
//! plinth that reaches out behind it (towards −z), which fixes front and back: a p and a q
//! are then congruent only through a reflection, as in the plane.

use std::f64::consts::{FRAC_PI_2, PI, TAU};

use super::TriangleMesh;

/// The names [`builtin`] knows, in the order of `validate::SHAPES`.
pub const NAMES: [&str; 9] = [
    "sphere", "torus", "cube", "figure", "letter-p", "letter-q", "letter-b", "letter-d", "letter-f",
];

/// A built-in shape by name (see [`NAMES`]), about one unit in size, horizontally centred on
/// the y axis and resting on the plane y = 0 (its lowest point has y = 0); `None` for an
/// unknown name.
pub fn builtin(name: &str) -> Option<TriangleMesh> {
    let mut mesh = match name {
        "sphere" => uv_sphere(0.5, 32, 24),
        "torus" => torus(0.35, 0.15, 40, 20),
        "cube" => cube(1.0),
        "figure" => figure(),
        "letter-p" => letter('p')?,
        "letter-q" => letter('q')?,
        "letter-b" => letter('b')?,
        "letter-d" => letter('d')?,
        "letter-f" => letter('F')?,
        _ => return None,
    };
    if let Some((lo, _)) = mesh.bounds() {
        mesh.translate([0.0, -lo[1], 0.0]);
    }
    Some(mesh)
}

/// A sphere of `radius` about the origin, as a latitude–longitude grid of `segments` meridians
/// (at least 3) and `rings` bands (at least 2), with a single vertex at each pole:
/// 2·segments·(rings − 1) triangles.
pub fn uv_sphere(radius: f64, segments: usize, rings: usize) -> TriangleMesh {
    let rings = rings.max(2);
    let profile: Vec<[f64; 2]> = (0..=rings)
        .map(|k| {
            let theta = PI * k as f64 / rings as f64;
            [radius * theta.sin(), radius * theta.cos()]
        })
        .collect();
    lathe(&profile, segments, false)
}

/// An ellipsoid about the origin with semi-axes `radii` along x, y and z (a scaled
/// [`uv_sphere`]).
pub fn ellipsoid(radii: [f64; 3], segments: usize, rings: usize) -> TriangleMesh {
    let mut mesh = uv_sphere(1.0, segments, rings);
    mesh.transform(diagonal(radii), [0.0; 3]);
    mesh
}

/// A torus about the y axis (lying flat) through the origin: the circle of radius `major`
/// swept by a tube of radius `minor` (less than `major`), with `segments` steps around the
/// axis and `sides` around the tube (each at least 3): 2·segments·sides triangles.
pub fn torus(major: f64, minor: f64, segments: usize, sides: usize) -> TriangleMesh {
    let sides = sides.max(3);
    let profile: Vec<[f64; 2]> = (0..sides)
        .map(|k| {
            // Clockwise in the (ρ, y) half-plane: top, outside, bottom, inside.
            let v = FRAC_PI_2 - TAU * k as f64 / sides as f64;
            [major + minor * v.cos(), minor * v.sin()]
        })
        .collect();
    lathe(&profile, segments, true)
}

/// A cube of edge `size` centred at the origin, with its faces perpendicular to the axes:
/// 8 vertices and 12 triangles.
pub fn cube(size: f64) -> TriangleMesh {
    let h = 0.5 * size;
    cuboid([-h; 3], [h; 3])
}

/// The axis-aligned box from corner `min` to corner `max` (each coordinate of `min` less than
/// that of `max`): 8 vertices and 12 triangles.
pub fn cuboid(min: [f64; 3], max: [f64; 3]) -> TriangleMesh {
    // Vertex i has coordinate k at max when bit k of i is set.
    let positions = (0..8)
        .map(|i| [0, 1, 2].map(|k| if i >> k & 1 == 1 { max[k] } else { min[k] }))
        .collect();
    let mut triangles = Vec::with_capacity(12);
    for k in 0..3 {
        let (u, v) = (1 << ((k + 1) % 3), 1 << ((k + 2) % 3));
        for side in [0, 1 << k] {
            // (c00, c10, c11, c01) is counter-clockwise seen from +axis k.
            let [a, b, c, d] = [side, side | u, side | u | v, side | v];
            if side == 0 {
                triangles.extend([[a, d, c], [a, c, b]]);
            } else {
                triangles.extend([[a, b, c], [a, c, d]]);
            }
        }
    }
    TriangleMesh {
        positions,
        triangles,
    }
}

/// A capsule along the y axis centred at the origin: a cylinder of `radius` and `length`
/// (between the centres of its two caps) closed by hemispheres, with `segments` steps around
/// the axis and `cap_rings` bands in each hemisphere.
pub fn capsule(radius: f64, length: f64, segments: usize, cap_rings: usize) -> TriangleMesh {
    let n = cap_rings.max(1);
    let half = 0.5 * length;
    let mut profile = Vec::with_capacity(2 * n + 2);
    for k in 0..=n {
        let theta = FRAC_PI_2 * k as f64 / n as f64;
        profile.push([radius * theta.sin(), half + radius * theta.cos()]);
    }
    for k in 0..=n {
        let theta = FRAC_PI_2 * (1.0 + k as f64 / n as f64);
        profile.push([radius * theta.sin(), -half + radius * theta.cos()]);
    }
    lathe(&profile, segments, false)
}

/// A capsule of `radius` whose cap centres are the points `a` and `b` (which must differ).
pub fn capsule_between(a: [f64; 3], b: [f64; 3], radius: f64) -> TriangleMesh {
    let d = [b[0] - a[0], b[1] - a[1], b[2] - a[2]];
    let length = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
    let mut mesh = capsule(radius, length, 16, 4);
    let y = d.map(|c| c / length);
    // A unit vector perpendicular to y, then z = x × y completes a right-handed frame.
    let helper = if y[0].abs() < 0.9 {
        [1.0, 0.0, 0.0]
    } else {
        [0.0, 0.0, 1.0]
    };
    let x = normalized(cross(helper, y));
    let z = cross(x, y);
    let rows = [0, 1, 2].map(|r| [x[r], y[r], z[r]]);
    let mid = [0, 1, 2].map(|k| 0.5 * (a[k] + b[k]));
    mesh.transform(rows, mid);
    mesh
}

/// A standing human figure, feet on y = 0, 1.72 units to the top of its head, facing +z and
/// waving with its right hand (on the −x side, raised to 1.87), so that it is chiral: its mirror
/// image waves with the left hand. It is
/// made of closed parts (feet, legs, pelvis, torso, neck, head, nose, arms and hands) that
/// overlap where they join.
pub fn figure() -> TriangleMesh {
    let mut mesh = TriangleMesh::default();
    for side in [-1.0, 1.0] {
        let x = 0.1 * side;
        mesh.append(&cuboid([x - 0.055, 0.0, -0.06], [x + 0.055, 0.07, 0.2]));
        mesh.append(&capsule_between([x, 0.12, 0.0], [x, 0.86, 0.0], 0.065));
    }
    let mut pelvis = ellipsoid([0.18, 0.11, 0.11], 20, 10);
    pelvis.translate([0.0, 0.93, 0.0]);
    mesh.append(&pelvis);
    let mut torso = capsule(0.16, 0.3, 24, 6);
    torso.transform(diagonal([1.15, 1.0, 0.7]), [0.0, 1.17, 0.0]);
    mesh.append(&torso);
    mesh.append(&capsule_between([0.0, 1.42, 0.0], [0.0, 1.5, 0.0], 0.045));
    let mut head = ellipsoid([0.095, 0.115, 0.105], 24, 14);
    head.translate([0.0, 1.6, 0.0]);
    mesh.append(&head);
    let mut nose = ellipsoid([0.02, 0.03, 0.03], 10, 6);
    nose.translate([0.0, 1.585, 0.1]);
    mesh.append(&nose);
    // Left arm (+x) hanging, right arm (−x) raised in a wave.
    let arms = [
        ([0.2, 1.4, 0.0], [0.25, 1.12, 0.0], [0.27, 0.88, 0.04]),
        ([-0.2, 1.4, 0.0], [-0.42, 1.5, 0.0], [-0.47, 1.76, 0.03]),
    ];
    for (shoulder, elbow, wrist) in arms {
        mesh.append(&capsule_between(shoulder, elbow, 0.047));
        mesh.append(&capsule_between(elbow, wrist, 0.04));
        // The hand continues the forearm.
        let dir = normalized([0, 1, 2].map(|k| wrist[k] - elbow[k]));
        let mut hand = ellipsoid([0.035, 0.055, 0.045], 12, 8);
        let centre = [0, 1, 2].map(|k| wrist[k] + 0.06 * dir[k]);
        hand.translate(centre);
        mesh.append(&hand);
    }
    mesh
}

/// Stroke width, thickness, plinth and arc resolution of the letters (height 1).
const STROKE: f64 = 0.16;
const THICKNESS: f64 = 0.2;
const ARC_STEPS: usize = 16;
const PLINTH_HEIGHT: f64 = 0.06;
const PLINTH_SINK: f64 = 0.02;

/// A letter `p`, `q`, `b`, `d` or `F` (`f` gives F too): the glyph, 1 unit tall and 0.2
/// thick, standing upright in the x–y plane and readable from +z, extruded between
/// z = −0.1 and z = 0.1 and horizontally centred on x = 0, set into a low plinth that reaches
/// out behind it to z = −0.45 (see the module documentation for why). The glyph is one closed
/// extruded outline (with the hole of the bowl triangulated), the plinth a box; `q` and `d`
/// are exactly `p` and `b` mirrored in x ↦ −x. `None` for other characters.
pub fn letter(ch: char) -> Option<TriangleMesh> {
    let mirror = [[-1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
    let (outer, holes) = match ch {
        'p' => bowl_letter(false),
        'b' => bowl_letter(true),
        'q' | 'd' => {
            let mut mesh = letter(if ch == 'q' { 'p' } else { 'b' })?;
            mesh.transform(mirror, [0.0; 3]);
            return Some(mesh);
        }
        'F' | 'f' => (letter_f(), Vec::new()),
        _ => return None,
    };
    let (lo, hi) = outer
        .iter()
        .fold(([f64::MAX; 2], [f64::MIN; 2]), |(lo, hi), p| {
            (
                [lo[0].min(p[0]), lo[1].min(p[1])],
                [hi[0].max(p[0]), hi[1].max(p[1])],
            )
        });
    let shift = [-0.5 * (lo[0] + hi[0]), PLINTH_HEIGHT - PLINTH_SINK - lo[1]];
    let moved = |ring: &[[f64; 2]]| -> Vec<[f64; 2]> {
        ring.iter()
            .map(|p| [p[0] + shift[0], p[1] + shift[1]])
            .collect()
    };
    let holes: Vec<Vec<[f64; 2]>> = holes.iter().map(|h| moved(h)).collect();
    let mut mesh = extrude(&moved(&outer), &holes, -0.5 * THICKNESS, 0.5 * THICKNESS);
    let half_width = 0.5 * (hi[0] - lo[0]) + 0.06;
    mesh.append(&cuboid(
        [-half_width, 0.0, -0.45],
        [half_width, PLINTH_HEIGHT, 0.5 * THICKNESS + 0.03],
    ));
    Some(mesh)
}

/// The outline of `p` (stem from 0 to 1 with the bowl at the top right), or of `b` (its
/// reflection top to bottom): the outer ring and the hole of the bowl.
fn bowl_letter(bowl_at_bottom: bool) -> (Vec<[f64; 2]>, Vec<Vec<[f64; 2]>>) {
    let w = STROKE;
    let (bottom, top) = (0.4, 1.0);
    let r = 0.5 * (top - bottom);
    let (xc, ym) = (0.3, 0.5 * (top + bottom));
    let arc = |radius: f64| {
        (0..=ARC_STEPS).map(move |k| {
            let a = -FRAC_PI_2 + PI * k as f64 / ARC_STEPS as f64;
            [xc + radius * a.cos(), ym + radius * a.sin()]
        })
    };
    let mut outer = vec![[0.0, 0.0], [w, 0.0], [w, bottom]];
    outer.extend(arc(r));
    outer.push([0.0, top]);
    let mut hole = vec![[w, bottom + w]];
    hole.extend(arc(r - w));
    hole.push([w, top - w]);
    if bowl_at_bottom {
        for ring in [&mut outer, &mut hole] {
            for p in ring.iter_mut() {
                p[1] = 1.0 - p[1];
            }
            ring.reverse();
        }
    }
    (outer, vec![hole])
}

/// The outline of a capital F, 1 tall and 0.6 wide.
fn letter_f() -> Vec<[f64; 2]> {
    let w = STROKE;
    vec![
        [0.0, 0.0],
        [w, 0.0],
        [w, 0.44],
        [0.46, 0.44],
        [0.46, 0.44 + w],
        [w, 0.44 + w],
        [w, 1.0 - w],
        [0.6, 1.0 - w],
        [0.6, 1.0],
        [0.0, 1.0],
    ]
}

/// The prism over a plane polygon with holes: the region inside `outer` and outside each of
/// `holes`, in the x–y plane, extruded from z = `z0` to z = `z1` (z0 < z1). The rings may run
/// either way round, must be simple, must not touch each other, and the holes must lie inside
/// the outer ring. The result is one closed outward-oriented mesh whose caps are triangulated
/// by ear clipping (other input gives some mesh that need not be closed, without panicking).
pub fn extrude(outer: &[[f64; 2]], holes: &[Vec<[f64; 2]>], z0: f64, z1: f64) -> TriangleMesh {
    // All ring points in one list; rings as index lists, outer counter-clockwise and holes
    // clockwise, so the region is always on the left.
    let mut points: Vec<[f64; 2]> = Vec::new();
    let mut rings: Vec<Vec<usize>> = Vec::new();
    for (k, ring) in std::iter::once(outer)
        .chain(holes.iter().map(Vec::as_slice))
        .enumerate()
    {
        let start = points.len();
        points.extend_from_slice(ring);
        let mut indices: Vec<usize> = (start..points.len()).collect();
        let ccw = ring_area(&points, &indices) > 0.0;
        if ccw != (k == 0) {
            indices.reverse();
        }
        rings.push(indices);
    }
    let caps = triangulate(&points, &rings);
    let n = points.len();
    let mut positions: Vec<[f64; 3]> = points.iter().map(|p| [p[0], p[1], z1]).collect();
    positions.extend(points.iter().map(|p| [p[0], p[1], z0]));
    let mut triangles = Vec::with_capacity(2 * caps.len() + 2 * n);
    for &[a, b, c] in &caps {
        triangles.push([a, b, c]);
        triangles.push([n + a, n + c, n + b]);
    }
    for ring in &rings {
        for (i, &a) in ring.iter().enumerate() {
            let b = ring[(i + 1) % ring.len()];
            triangles.push([a, n + a, n + b]);
            triangles.push([a, n + b, b]);
        }
    }
    TriangleMesh {
        positions,
        triangles: triangles.into_iter().map(|t| t.map(|i| i as u32)).collect(),
    }
}

/// A surface of revolution about the y axis with `segments` (at least 3) steps around the
/// axis. The profile is a list of (ρ, y) with ρ ≥ 0, running clockwise in the (ρ, y)
/// half-plane (downwards on the outside); when `closed` it is a loop of points with ρ > 0
/// (a torus), otherwise its first and last points are the poles (their ρ is ignored) and the
/// others have ρ > 0.
fn lathe(profile: &[[f64; 2]], segments: usize, closed: bool) -> TriangleMesh {
    let segments = segments.max(3);
    let rings: &[[f64; 2]] = if closed {
        profile
    } else {
        &profile[1..profile.len() - 1]
    };
    let mut mesh = TriangleMesh::default();
    for &[rho, y] in rings {
        for j in 0..segments {
            let phi = TAU * j as f64 / segments as f64;
            mesh.positions.push([rho * phi.cos(), y, rho * phi.sin()]);
        }
    }
    let at = |ring: usize, j: usize| (ring * segments + j % segments) as u32;
    let bands = if closed { rings.len() } else { rings.len() - 1 };
    for k in 0..bands {
        let next = (k + 1) % rings.len();
        for j in 0..segments {
            let (u0, u1, l0, l1) = (at(k, j), at(k, j + 1), at(next, j), at(next, j + 1));
            mesh.triangles.push([u0, u1, l1]);
            mesh.triangles.push([u0, l1, l0]);
        }
    }
    if !closed {
        let north = mesh.positions.len() as u32;
        mesh.positions.push([0.0, profile[0][1], 0.0]);
        let south = north + 1;
        mesh.positions
            .push([0.0, profile[profile.len() - 1][1], 0.0]);
        let last = rings.len() - 1;
        for j in 0..segments {
            mesh.triangles.push([north, at(0, j + 1), at(0, j)]);
            mesh.triangles.push([south, at(last, j), at(last, j + 1)]);
        }
    }
    mesh
}

/// The diagonal matrix with entries `d`, as rows.
fn diagonal(d: [f64; 3]) -> [[f64; 3]; 3] {
    [[d[0], 0.0, 0.0], [0.0, d[1], 0.0], [0.0, 0.0, d[2]]]
}

fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

fn normalized(a: [f64; 3]) -> [f64; 3] {
    let n = (a[0] * a[0] + a[1] * a[1] + a[2] * a[2]).sqrt();
    a.map(|c| c / n)
}

/// Twice the signed area of the triangle (a, b, c): positive when counter-clockwise.
fn orient(a: [f64; 2], b: [f64; 2], c: [f64; 2]) -> f64 {
    (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0])
}

/// The signed area of a ring: positive when counter-clockwise.
fn ring_area(points: &[[f64; 2]], ring: &[usize]) -> f64 {
    (0..ring.len())
        .map(|i| {
            let (a, b) = (points[ring[i]], points[ring[(i + 1) % ring.len()]]);
            a[0] * b[1] - a[1] * b[0]
        })
        .sum::<f64>()
        * 0.5
}

/// Whether the open segments p–q and r–s cross at a point inside both.
fn segments_cross(p: [f64; 2], q: [f64; 2], r: [f64; 2], s: [f64; 2]) -> bool {
    let (d1, d2) = (orient(p, q, r), orient(p, q, s));
    let (d3, d4) = (orient(r, s, p), orient(r, s, q));
    d1 * d2 < 0.0 && d3 * d4 < 0.0
}

/// Whether `m` lies strictly inside the angle of the ring at position `i` (on the region's
/// side of both edges there), the ring running with the region on its left.
fn locally_inside(points: &[[f64; 2]], ring: &[usize], i: usize, m: [f64; 2]) -> bool {
    let n = ring.len();
    let a = points[ring[(i + n - 1) % n]];
    let p = points[ring[i]];
    let b = points[ring[(i + 1) % n]];
    if orient(a, p, b) >= 0.0 {
        orient(p, b, m) > 0.0 && orient(a, p, m) > 0.0
    } else {
        orient(p, b, m) > 0.0 || orient(a, p, m) > 0.0
    }
}

/// Triangulates the region inside `rings[0]` (counter-clockwise) and outside the others
/// (clockwise): each hole is joined to the outer ring by a bridge to the nearest vertex that
/// sees it, then ears are clipped. Triangles are counter-clockwise index triples.
fn triangulate(points: &[[f64; 2]], rings: &[Vec<usize>]) -> Vec<[usize; 3]> {
    let mut ring = rings[0].clone();
    if ring.len() < 3 {
        return Vec::new();
    }
    let mut holes: Vec<&Vec<usize>> = rings[1..].iter().collect();
    let max_x = |h: &Vec<usize>| h.iter().map(|&i| points[i][0]).fold(f64::MIN, f64::max);
    holes.sort_by(|a, b| max_x(b).total_cmp(&max_x(a)));
    for (h, hole) in holes.iter().enumerate() {
        let start = (0..hole.len())
            .max_by(|&a, &b| points[hole[a]][0].total_cmp(&points[hole[b]][0]))
            .unwrap_or(0);
        let m = points[hole[start]];
        let blocks = |p: [f64; 2]| {
            let edges = |r: &[usize]| {
                (0..r.len())
                    .map(|i| (points[r[i]], points[r[(i + 1) % r.len()]]))
                    .collect::<Vec<_>>()
            };
            let mut all = edges(&ring);
            for other in &holes[h..] {
                all.extend(edges(other));
            }
            all.iter().any(|&(r, s)| segments_cross(m, p, r, s))
        };
        let distance = |i: usize| {
            let p = points[ring[i]];
            (p[0] - m[0]).powi(2) + (p[1] - m[1]).powi(2)
        };
        let nearest = |candidates: &mut dyn Iterator<Item = usize>| {
            candidates.min_by(|&a, &b| distance(a).total_cmp(&distance(b)))
        };
        // Only for rings that break the rules can no vertex see the hole; then take the
        // nearest, to give some (wrong) answer rather than none.
        let best = nearest(
            &mut (0..ring.len())
                .filter(|&i| locally_inside(points, &ring, i, m) && !blocks(points[ring[i]])),
        )
        .or_else(|| nearest(&mut (0..ring.len())))
        .unwrap_or(0);
        let mut merged = ring[..=best].to_vec();
        merged.extend((0..=hole.len()).map(|k| hole[(start + k) % hole.len()]));
        merged.extend_from_slice(&ring[best..]);
        ring = merged;
    }
    clip_ears(points, ring)
}

/// Ear clipping of a counter-clockwise ring (which may visit a point twice along a bridge).
fn clip_ears(points: &[[f64; 2]], mut ring: Vec<usize>) -> Vec<[usize; 3]> {
    let mut triangles = Vec::with_capacity(ring.len().saturating_sub(2));
    while ring.len() > 3 {
        let n = ring.len();
        let ear = (0..n).find(|&i| {
            let (a, b, c) = (ring[(i + n - 1) % n], ring[i], ring[(i + 1) % n]);
            let (pa, pb, pc) = (points[a], points[b], points[c]);
            if orient(pa, pb, pc) <= 1e-12 {
                return false;
            }
            !ring.iter().any(|&k| {
                let q = points[k];
                q != pa
                    && q != pb
                    && q != pc
                    && orient(pa, pb, q) >= 0.0
                    && orient(pb, pc, q) >= 0.0
                    && orient(pc, pa, q) >= 0.0
            })
        });
        // Only a degenerate ring has no ear; dropping a vertex then keeps the loop finite.
        let i = ear.unwrap_or(0);
        let (a, b, c) = (ring[(i + n - 1) % n], ring[i], ring[(i + 1) % n]);
        if ear.is_some() {
            triangles.push([a, b, c]);
        }
        ring.remove(i);
    }
    if let [a, b, c] = ring[..]
        && orient(points[a], points[b], points[c]) > 1e-12
    {
        triangles.push([a, b, c]);
    }
    triangles
}
