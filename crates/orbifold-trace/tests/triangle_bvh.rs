//! Intrinsically flat triangles, the BVH and instances (ARCHITECTURE.md §7, §8), in S²×ℝ, E²×ℝ
//! and H²×ℝ, checked against independent references:
//!
//! - a brute-force search along the ray (dense sampling in arc length of the height difference
//!   between the ray and the surface over the footprint, finer near the footprint, refined by
//!   bisection);
//! - Möller–Trumbore on the corresponding Euclidean triangle (κ = 0);
//! - closed meshes, hit from inside by every ray (watertightness), including exactly vertical faces;
//! - brute force over all triangles (the BVH, and instances placed by random isometries).
//!
//! **Tolerances.** The dense search samples at a step of `s_max / (20000 · 64)` near the
//! footprint; it can miss or invent a
//! crossing only where the ray passes within about a step of the triangle's boundary (a sign
//! change straddling the boundary) or touches the surface without crossing it. Those cases are
//! recognised (the ray's hit, or the reference's, is within four sampling steps, horizontally, of an edge's
//! line, or the height difference changes by less than `GRAZE_SLOPE` per unit arc
//! length there) and counted, not failed; there may be at most a few per cent of them.

use std::f64::consts::PI;
use std::sync::Arc;

use glam::{DMat3, DVec3};
use num_complex::Complex64;
use orbifold::Geometry;
use orbifold::embed::{Placement, embed, place};
use orbifold::space::Space;
use orbifold_trace::accel::Bvh;
use orbifold_trace::accel::{Instance, Instances};
use orbifold_trace::geodesic::Ray;
use orbifold_trace::triangle::Triangle;
use proptest::prelude::*;

const GEOMETRIES: [Geometry; 3] = [
    Geometry::Spherical,
    Geometry::Euclidean,
    Geometry::Hyperbolic,
];

/// Slope of the height difference under which a disagreement counts as grazing.
const GRAZE_SLOPE: f64 = 1e-2;

/// A small deterministic generator (xorshift*), seeded by proptest.
struct Rng(u64);

impl Rng {
    fn new(seed: u64) -> Rng {
        Rng(seed.wrapping_mul(0x9E37_79B9_7F4A_7C15) | 1)
    }
    fn next(&mut self) -> f64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        (self.0.wrapping_mul(0x2545_F491_4F6C_DD1D) >> 11) as f64 / (1u64 << 53) as f64
    }
    fn range(&mut self, a: f64, b: f64) -> f64 {
        a + (b - a) * self.next()
    }
    fn unit2(&mut self) -> DVec3 {
        let t = self.range(0.0, 2.0 * PI);
        DVec3::new(t.cos(), t.sin(), 0.0)
    }
}

/// The point at tangent vector (x, y) from the origin.
fn at(space: Space, x: f64, y: f64) -> DVec3 {
    space.exp(DVec3::Z, DVec3::new(x, y, 0.0))
}

/// A random triangle near the origin, of intrinsic size 0.01–1, not steep.
fn random_triangle(space: Space, rng: &mut Rng) -> Triangle {
    let size = 10f64.powf(rng.range(-2.0, 0.0));
    let centre = rng.unit2() * rng.range(0.0, 0.5);
    let points = [0, 1, 2].map(|_| {
        let v = centre + rng.unit2() * size * rng.range(0.3, 1.0);
        at(space, v.x, v.y)
    });
    let base = rng.range(0.0, 1.0);
    let heights = [0, 1, 2].map(|_| base + size * rng.range(-1.0, 1.0));
    Triangle::new(points, heights)
}

/// A random ray starting near the origin.
fn random_ray(space: Space, rng: &mut Rng) -> Ray {
    let v = rng.unit2() * rng.range(0.0, 0.8);
    let origin = at(space, v.x, v.y);
    let dir = DVec3::new(
        rng.range(-1.0, 1.0),
        rng.range(-1.0, 1.0),
        rng.range(-1.0, 1.0),
    );
    Ray::new(
        space,
        origin,
        dir,
        rng.range(-0.5, 1.5),
        rng.range(-1.4, 1.4),
    )
}

/// A random ray aimed at a random point of the triangle (so that about half of them hit).
fn aimed_ray(space: Space, tri: &Triangle, rng: &mut Rng) -> Ray {
    let mut w = [
        rng.range(-0.2, 1.0),
        rng.range(-0.2, 1.0),
        rng.range(-0.2, 1.0),
    ];
    let sum: f64 = w.iter().sum();
    w = w.map(|x| x / sum);
    let (target, target_h) = tri.point(space, w);
    let v = rng.unit2() * rng.range(0.05, 0.8);
    let origin = at(space, v.x, v.y);
    let log = space.log(origin, target);
    let d = space.point_dot(log, log).sqrt();
    if d < 1e-9 {
        return random_ray(space, rng);
    }
    let h = rng.range(-0.5, 1.5);
    let elevation = (target_h - h).atan2(d);
    Ray::new(space, origin, log, h, elevation)
}

/// Footprint barycentrics and height difference (ray minus surface) at arc length `s`, by the
/// inverse matrix of the vertices (independent of the implementation).
fn reference_sample(
    space: Space,
    tri: &Triangle,
    inverse: &DMat3,
    ray: &Ray,
    s: f64,
) -> ([f64; 3], f64) {
    let (x, h) = ray.point_at(space, s);
    let q = *inverse * x;
    let total = q.x + q.y + q.z;
    let w = [q.x / total, q.y / total, q.z / total];
    let surface = w[0] * tri.heights[0] + w[1] * tri.heights[1] + w[2] * tri.heights[2];
    (if total > 0.0 { w } else { [-9.0; 3] }, h - surface)
}

/// Coarse samples along the ray.
const STEPS: usize = 20_000;
/// Each coarse step near the footprint is resampled this many times finer.
const REFINE: usize = 64;

/// The first crossing found by dense sampling and bisection: (s, barycentrics, slope). The ray is
/// sampled at `STEPS` points over [0, s_max]; steps with an end near the footprint (within two
/// steps of the vertices' bounding disc) are resampled `REFINE` times finer; a sign change of the height difference between two
/// fine samples over the footprint is refined by bisection.
fn reference_hit(
    space: Space,
    tri: &Triangle,
    ray: &Ray,
    s_max: f64,
) -> Option<(f64, [f64; 3], f64)> {
    let m = DMat3::from_cols(tri.points[0], tri.points[1], tri.points[2]);
    let inverse = m.inverse();
    let sample = |s: f64| reference_sample(space, tri, &inverse, ray, s);
    let over = |w: &[f64; 3]| w.iter().all(|&w| w >= 0.0);
    let coarse = s_max / STEPS as f64;
    // Near the footprint: within two coarse steps of the vertices' bounding disc.
    let centre = space.normalize_point(tri.points.iter().sum());
    let radius = tri
        .points
        .iter()
        .map(|p| space.ambient_distance(centre, *p))
        .fold(0.0, f64::max);
    let near =
        |s: f64| space.ambient_distance(ray.point_at(space, s).0, centre) <= radius + 2.0 * coarse;
    let mut previous = sample(0.0);
    for i in 1..=STEPS {
        let current = sample(coarse * i as f64);
        if near(coarse * (i - 1) as f64) || near(coarse * i as f64) {
            let s0 = coarse * (i - 1) as f64;
            let fine = coarse / REFINE as f64;
            let mut before = previous;
            for j in 1..=REFINE {
                let s = s0 + fine * j as f64;
                let after = sample(s);
                if over(&before.0) && over(&after.0) && (before.1 > 0.0) != (after.1 > 0.0) {
                    let (mut a, mut b, fa) = (s - fine, s, before.1);
                    for _ in 0..200 {
                        let mid = 0.5 * (a + b);
                        if (sample(mid).1 > 0.0) == (fa > 0.0) {
                            a = mid;
                        } else {
                            b = mid;
                        }
                    }
                    let slope = (after.1 - before.1) / fine;
                    return Some((0.5 * (a + b), sample(a).0, slope));
                }
                before = after;
            }
        }
        previous = current;
    }
    None
}

fn check_against_reference(g: Geometry, seed: u64) -> Result<(usize, usize), TestCaseError> {
    let space = Space::new(g);
    let mut rng = Rng::new(seed);
    let (mut hits, mut grazing) = (0, 0);
    for _ in 0..4 {
        let tri = random_triangle(space, &mut rng);
        for _ in 0..4 {
            let ray = aimed_ray(space, &tri, &mut rng);
            let s_max = 3.0;
            let found = tri.intersect(space, &ray, 0.0, s_max);
            if let Some(c) = found {
                // The hit is on the triangle and on the ray.
                prop_assert!(c.barycentric.iter().all(|&w| w >= -1e-9), "{g:?} {c:?}");
                prop_assert!((c.barycentric.iter().sum::<f64>() - 1.0).abs() < 1e-9);
                let (x, h) = tri.point(space, c.barycentric);
                let (y, k) = ray.point_at(space, c.s);
                prop_assert!(
                    (x - y).length() < 1e-9 && (h - k).abs() < 1e-9,
                    "{g:?} {c:?}"
                );
                prop_assert!(c.s >= 0.0 && c.s <= s_max);
            }
            let reference = reference_hit(space, &tri, &ray, s_max);
            match (found, reference) {
                (Some(c), Some((s, _, _))) if (c.s - s).abs() < 1e-9 => hits += 1,
                (None, None) => {}
                (found, reference) => {
                    // Grazing: the hit is within a few sampling steps (horizontally) of an edge,
                    // or the height difference barely changes there.
                    let step = s_max / (STEPS * REFINE) as f64;
                    let near_edge = |s: f64| {
                        let (x, _) = ray.point_at(space, s);
                        (0..3).any(|i| {
                            let n = tri.points[(i + 1) % 3].cross(tri.points[(i + 2) % 3]);
                            let wall = space.normalize_wall(n);
                            space.asin(wall.dot(x)).abs() < 4.0 * step
                        })
                    };
                    let graze = found.is_some_and(|c| near_edge(c.s))
                        || reference
                            .is_some_and(|(s, _, slope)| near_edge(s) || slope.abs() < GRAZE_SLOPE);
                    prop_assert!(
                        graze,
                        "{g:?}: {found:?} vs reference {reference:?} ({tri:?}, {ray:?})"
                    );
                    grazing += 1;
                }
            }
        }
    }
    Ok((hits, grazing))
}

proptest! {
    // Dense sampling is slow unoptimised: fewer cases in debug builds (CI), all in release.
    #![proptest_config(ProptestConfig::with_cases(if cfg!(debug_assertions) { 16 } else { 48 }))]

    #[test]
    fn hits_agree_with_dense_sampling(seed in any::<u64>()) {
        for g in GEOMETRIES {
            let (_, grazing) = check_against_reference(g, seed)?;
            // Every disagreement is checked to be grazing above; a few of 16 rays aimed at a
            // triangle's area do graze (3 for the seed in the regressions file).
            prop_assert!(grazing <= 4, "{g:?}: {grazing} grazing disagreements of 16");
        }
    }

    #[test]
    fn euclidean_hits_are_moller_trumbore(seed in any::<u64>()) {
        let space = Space::new(Geometry::Euclidean);
        let mut rng = Rng::new(seed);
        for _ in 0..16 {
            let tri = random_triangle(space, &mut rng);
            let ray = aimed_ray(space, &tri, &mut rng);
            let v = tri.points.map(|p| DVec3::new(p.x, p.y, 0.0));
            let v = [0, 1, 2].map(|i| DVec3::new(v[i].x, v[i].y, tri.heights[i]));
            let o = DVec3::new(ray.origin.x, ray.origin.y, ray.height);
            let d = DVec3::new(
                ray.cos_elevation * ray.direction.x,
                ray.cos_elevation * ray.direction.y,
                ray.sin_elevation,
            );
            let mt = moller_trumbore(o, d, v).filter(|&(t, _, _)| (0.0..=5.0).contains(&t));
            let ours = tri.intersect(space, &ray, 0.0, 5.0);
            match (ours, mt) {
                (Some(c), Some((t, b1, b2))) => {
                    // Both solutions err by about ε/|cos θ| (θ between the ray and the normal):
                    // a glancing ray's crossing is ill-conditioned whoever computes it.
                    let n = (v[1] - v[0]).cross(v[2] - v[0]);
                    let cos = (n.dot(d) / (n.length() * d.length())).abs();
                    let tolerance = 1e-12 * (1.0 + t) / cos.max(1e-3);
                    prop_assert!((c.s - t).abs() < tolerance, "{} vs {t} (cos θ {cos})", c.s);
                    prop_assert!((c.barycentric[1] - b1).abs() < 1e-9 && (c.barycentric[2] - b2).abs() < 1e-9);
                }
                (None, None) => {}
                (Some(c), None) => prop_assert!(c.barycentric.iter().any(|w| w.abs() < 1e-9), "{c:?}"),
                (None, Some((_, b1, b2))) => {
                    prop_assert!(b1.abs() < 1e-9 || b2.abs() < 1e-9 || (1.0 - b1 - b2).abs() < 1e-9)
                }
            }
        }
    }

    #[test]
    fn normals_are_unit_orthogonal_and_right_handed(seed in any::<u64>()) {
        for g in GEOMETRIES {
            let space = Space::new(g);
            let mut rng = Rng::new(seed);
            let tri = random_triangle(space, &mut rng);
            let w = {
                let w = [rng.range(0.01, 1.0), rng.range(0.01, 1.0), rng.range(0.01, 1.0)];
                let s: f64 = w.iter().sum();
                w.map(|x| x / s)
            };
            let (n, up) = tri.normal(space, w).unwrap();
            let (x, _) = tri.point(space, w);
            // Tangent at x, unit in the product metric.
            let along = if g == Geometry::Euclidean { n.z } else { space.point_dot(n, x) };
            prop_assert!(along.abs() < 1e-12);
            prop_assert!((space.point_dot(n, n) + up * up - 1.0).abs() < 1e-12);
            // Orthogonal to both edge directions (central differences of the surface map).
            let t = 1e-6;
            for (i, j) in [(0, 1), (0, 2)] {
                let mut plus = w;
                let mut minus = w;
                plus[j] += t; plus[i] -= t; minus[j] -= t; minus[i] += t;
                let (xp, hp) = tri.point(space, plus);
                let (xm, hm) = tri.point(space, minus);
                let (dx, dh) = ((xp - xm) / (2.0 * t), (hp - hm) / (2.0 * t));
                let norm = (space.point_dot(dx, dx) + dh * dh).sqrt();
                let dot = space.point_dot(n, dx) + up * dh;
                prop_assert!(dot.abs() < 1e-6 * norm, "{g:?}: {dot}");
            }
        }
        // κ = 0: the right-handed cross product of the Euclidean triangle.
        let space = Space::new(Geometry::Euclidean);
        let mut rng = Rng::new(seed);
        let tri = random_triangle(space, &mut rng);
        let v = [0, 1, 2].map(|i| DVec3::new(tri.points[i].x, tri.points[i].y, tri.heights[i]));
        let expected = (v[1] - v[0]).cross(v[2] - v[0]).normalize();
        let (n, up) = tri.normal(space, [0.3, 0.3, 0.4]).unwrap();
        prop_assert!((DVec3::new(n.x, n.y, up) - expected).length() < 1e-9);
    }
}

/// Möller–Trumbore: (t, b₁, b₂) with o + t d = (1 − b₁ − b₂) v₀ + b₁ v₁ + b₂ v₂.
fn moller_trumbore(o: DVec3, d: DVec3, v: [DVec3; 3]) -> Option<(f64, f64, f64)> {
    let (e1, e2) = (v[1] - v[0], v[2] - v[0]);
    let pv = d.cross(e2);
    let det = e1.dot(pv);
    if det.abs() < 1e-14 {
        return None;
    }
    let tv = o - v[0];
    let b1 = tv.dot(pv) / det;
    let qv = tv.cross(e1);
    let b2 = d.dot(qv) / det;
    let t = e2.dot(qv) / det;
    (b1 >= 0.0 && b2 >= 0.0 && b1 + b2 <= 1.0).then_some((t, b1, b2))
}

// ---------------------------------------------------------------------------------------------
// Closed meshes.

/// An icosphere of radius `r` (Euclidean, outward counter-clockwise), subdivided `levels` times.
fn icosphere(r: f64, levels: usize) -> (Vec<[f64; 3]>, Vec<[u32; 3]>) {
    let t = (1.0 + 5f64.sqrt()) / 2.0;
    let mut v: Vec<DVec3> = [
        (-1.0, t, 0.0),
        (1.0, t, 0.0),
        (-1.0, -t, 0.0),
        (1.0, -t, 0.0),
        (0.0, -1.0, t),
        (0.0, 1.0, t),
        (0.0, -1.0, -t),
        (0.0, 1.0, -t),
        (t, 0.0, -1.0),
        (t, 0.0, 1.0),
        (-t, 0.0, -1.0),
        (-t, 0.0, 1.0),
    ]
    .iter()
    .map(|&(x, y, z)| DVec3::new(x, y, z).normalize())
    .collect();
    let mut f: Vec<[u32; 3]> = vec![
        [0, 11, 5],
        [0, 5, 1],
        [0, 1, 7],
        [0, 7, 10],
        [0, 10, 11],
        [1, 5, 9],
        [5, 11, 4],
        [11, 10, 2],
        [10, 7, 6],
        [7, 1, 8],
        [3, 9, 4],
        [3, 4, 2],
        [3, 2, 6],
        [3, 6, 8],
        [3, 8, 9],
        [4, 9, 5],
        [2, 4, 11],
        [6, 2, 10],
        [8, 6, 7],
        [9, 8, 1],
    ];
    for _ in 0..levels {
        let mut cache = std::collections::HashMap::new();
        let mut mid = |a: u32, b: u32, v: &mut Vec<DVec3>| {
            *cache.entry((a.min(b), a.max(b))).or_insert_with(|| {
                v.push(((v[a as usize] + v[b as usize]) * 0.5).normalize());
                (v.len() - 1) as u32
            })
        };
        let mut next = Vec::new();
        for [a, b, c] in f {
            let (ab, bc, ca) = (mid(a, b, &mut v), mid(b, c, &mut v), mid(c, a, &mut v));
            next.extend([[a, ab, ca], [b, bc, ab], [c, ca, bc], [ab, bc, ca]]);
        }
        f = next;
    }
    (v.iter().map(|p| (*p * r).to_array()).collect(), f)
}

/// A cube of half-side `r` centred at 0 (Euclidean), each face an n × n grid of squares cut in two.
fn cube(r: f64, n: usize) -> (Vec<[f64; 3]>, Vec<[u32; 3]>) {
    let mut v = Vec::new();
    let mut f = Vec::new();
    for axis in 0..3 {
        for sign in [-1.0, 1.0] {
            let normal = DVec3::AXES[axis] * sign;
            let a = DVec3::AXES[(axis + 1) % 3];
            let b = normal.cross(a);
            let base = v.len() as u32;
            for i in 0..=n {
                for j in 0..=n {
                    let (x, y) = (
                        2.0 * i as f64 / n as f64 - 1.0,
                        2.0 * j as f64 / n as f64 - 1.0,
                    );
                    v.push(((normal + a * x + b * y) * r).to_array());
                }
            }
            let id = |i: usize, j: usize| base + (i * (n + 1) + j) as u32;
            for i in 0..n {
                for j in 0..n {
                    f.push([id(i, j), id(i + 1, j), id(i + 1, j + 1)]);
                    f.push([id(i, j), id(i + 1, j + 1), id(i, j + 1)]);
                }
            }
        }
    }
    (v, f)
}

fn watertight(g: Geometry, mesh: &(Vec<[f64; 3]>, Vec<[u32; 3]>), rays: usize, seed: u64) {
    let space = Space::new(g);
    let (positions, triangles) = mesh;
    let e = embed(space, positions, DVec3::ZERO, 1.0);
    let lowest = positions.iter().map(|p| p[1]).fold(f64::INFINITY, f64::min);
    let bvh = Bvh::build(space, &e.points, &e.heights, triangles);
    assert_eq!(bvh.triangle_count(), triangles.len());
    let mut rng = Rng::new(seed);
    let mut missed = Vec::new();
    for _ in 0..rays {
        // From the centre (height −lowest after embedding), in a direction uniform on the sphere,
        // and, for a quarter of the rays, from a random point inside.
        let elevation = rng.range(-1.0, 1.0).asin();
        let offset = if rng.next() < 0.25 {
            rng.unit2() * rng.range(0.0, 0.1)
        } else {
            DVec3::ZERO
        };
        let origin = at(space, offset.x, offset.y);
        let ray = Ray::new(
            space,
            origin,
            rng.unit2(),
            -lowest + rng.range(-0.05, 0.05) * offset.length() * 10.0,
            elevation,
        );
        if bvh.intersect(space, &ray, 0.0, 10.0).is_none() {
            missed.push(ray);
        }
        assert!(bvh.occluded(space, &ray, 0.0, 10.0) || missed.last() == Some(&ray));
    }
    assert!(
        missed.is_empty(),
        "{g:?}: {} of {rays} rays slipped out, e.g. {:?}",
        missed.len(),
        missed[0]
    );
}

#[test]
fn closed_meshes_are_watertight() {
    for g in GEOMETRIES {
        watertight(g, &icosphere(0.4, 3), 12_000, 1);
        // Exactly vertical faces, edges and vertices along axes (degenerate for footprints).
        watertight(g, &cube(0.3, 4), 12_000, 2);
    }
}

#[test]
fn rays_along_shared_edges_and_through_vertices_hit() {
    // Rays from the centre of an embedded cube aimed exactly at its vertices and edge midpoints.
    for g in GEOMETRIES {
        let space = Space::new(g);
        let (positions, triangles) = cube(0.3, 2);
        let e = embed(space, &positions, DVec3::ZERO, 1.0);
        let bvh = Bvh::build(space, &e.points, &e.heights, &triangles);
        for (p, &h) in e.points.iter().zip(&e.heights) {
            let log = space.log(DVec3::Z, *p);
            let d = space.point_dot(log, log).sqrt();
            let dir = if d > 0.0 { log } else { DVec3::X };
            let ray = Ray::new(space, DVec3::Z, dir, 0.3, (h - 0.3).atan2(d));
            let hit = bvh.intersect(space, &ray, 0.0, 10.0);
            assert!(hit.is_some(), "{g:?}: ray to vertex {p:?} {h} slipped out");
        }
    }
}

// ---------------------------------------------------------------------------------------------
// BVH and instances against brute force.

/// A soup of random triangles near the origin.
fn soup(space: Space, count: usize, rng: &mut Rng) -> (Vec<DVec3>, Vec<f64>, Vec<[u32; 3]>) {
    let mut points = Vec::new();
    let mut heights = Vec::new();
    let mut triangles = Vec::new();
    for t in 0..count {
        let centre = rng.unit2() * rng.range(0.0, 1.0).sqrt();
        let size = rng.range(0.01, 0.1);
        let base = rng.range(0.0, 1.0);
        let steep = t % 5 == 0;
        for _ in 0..3 {
            let v = centre + rng.unit2() * size * rng.range(0.2, 1.0);
            points.push(at(space, v.x, v.y));
            heights.push(base + if steep { 3.0 } else { 0.5 } * size * rng.range(-1.0, 1.0));
        }
        let i = 3 * t as u32;
        triangles.push([i, i + 1, i + 2]);
    }
    (points, heights, triangles)
}

fn brute_force(
    space: Space,
    points: &[DVec3],
    heights: &[f64],
    triangles: &[[u32; 3]],
    ray: &Ray,
    s_max: f64,
) -> Option<(u32, f64)> {
    let mut best: Option<(u32, f64)> = None;
    for (t, tri) in triangles.iter().enumerate() {
        let tri = Triangle::new(
            tri.map(|i| points[i as usize]),
            tri.map(|i| heights[i as usize]),
        );
        if let Some(c) = tri.intersect(space, ray, 0.0, s_max)
            && best.is_none_or(|(_, s)| c.s < s)
        {
            best = Some((t as u32, c.s));
        }
    }
    best
}

#[test]
fn bvh_agrees_with_brute_force() {
    for g in GEOMETRIES {
        let space = Space::new(g);
        let mut rng = Rng::new(7);
        let (points, heights, triangles) = soup(space, 3000, &mut rng);
        let bvh = Bvh::build(space, &points, &heights, &triangles);
        // Leaves of at most 4 triangles, nodes of at most 8 children: at least 750 leaves under
        // at least 107 nodes, 4 levels deep.
        assert!(
            bvh.depth() >= 4 && bvh.depth() <= 64,
            "{g:?}: depth {}",
            bvh.depth()
        );
        assert!(bvh.node_count() >= triangles.len() / 28);
        let (mut hits, mut rays) = (0, 0);
        // Brute force over the soup is slow unoptimised: fewer rays in debug builds (CI).
        let total = if cfg!(debug_assertions) { 1000 } else { 3000 };
        while rays < total {
            let ray = random_ray(space, &mut rng);
            // Every fourth ray level or nearly so: the heights' slab of the BVH's f32 lanes
            // grows without bound as the climb goes to 0 (and leaves f32's range at 1e-31,
            // where the discs are tested instead).
            let ray = if rays % 4 == 0 {
                let elevation = [0.0, 1e-31, -1e-12, 1e-6, -1e-3][(rays / 4) % 5];
                Ray::new(space, ray.origin, ray.direction, ray.height, elevation)
            } else {
                ray
            };
            let s_max = 3.0;
            let expected = brute_force(space, &points, &heights, &triangles, &ray, s_max);
            let got = bvh.intersect(space, &ray, 0.0, s_max);
            match (got, expected) {
                (Some(hit), Some((t, s))) => {
                    assert_eq!(hit.triangle, t, "{g:?}: {ray:?}");
                    assert!((hit.s - s).abs() < 1e-12, "{g:?}: {} vs {s}", hit.s);
                    hits += 1;
                }
                (None, None) => {}
                (got, expected) => panic!("{g:?}: BVH {got:?}, brute force {expected:?}, {ray:?}"),
            }
            assert_eq!(bvh.occluded(space, &ray, 0.0, s_max), expected.is_some());
            rays += 1;
        }
        assert!(hits > total / 10, "{g:?}: only {hits} hits of {total}");
    }
}

#[test]
fn instances_agree_with_moved_triangles() {
    for g in GEOMETRIES {
        let space = Space::new(g);
        let mut rng = Rng::new(11);
        let (positions, triangles) = icosphere(0.2, 2);
        let object = embed(space, &positions, DVec3::ZERO, 1.0);
        let bvh = Arc::new(Bvh::build(
            space,
            &object.points,
            &object.heights,
            &triangles,
        ));
        let mut hits = 0;
        for _ in 0..40 {
            let placement = Placement {
                at: Complex64::from_polar(rng.range(0.0, 0.4), rng.range(0.0, 2.0 * PI)),
                height: rng.range(0.0, 1.0),
                yaw: rng.range(0.0, 2.0 * PI),
            };
            let moved = place(space, &object, &placement);
            let instance = Instance::from_placement(space, bvh.clone(), &placement);
            let decoy = Instance::from_placement(
                space,
                bvh.clone(),
                &Placement {
                    height: 5.0,
                    ..placement
                },
            );
            let objects = Instances::new(vec![decoy, instance.clone()]);
            for _ in 0..50 {
                let ray = random_ray(space, &mut rng);
                let expected =
                    brute_force(space, &moved.points, &moved.heights, &triangles, &ray, 3.0);
                let got = instance.intersect(space, &ray, 0.0, 3.0);
                let both = objects.intersect(space, &ray, 0.0, 3.0);
                match (got, expected) {
                    (Some(hit), Some((t, s))) => {
                        assert!((hit.s - s).abs() < 1e-9, "{g:?}: {} vs {s}", hit.s);
                        if hit.triangle != t {
                            // Only on a shared edge: the same point.
                            let (x, h) = instance.point(space, &hit);
                            let (y, k) = ray.point_at(space, s);
                            assert!((x - y).length() < 1e-8 && (h - k).abs() < 1e-8);
                        }
                        let (x, h) = instance.point(space, &hit);
                        let (y, k) = ray.point_at(space, hit.s);
                        assert!((x - y).length() < 1e-9 && (h - k).abs() < 1e-9);
                        let (n, up) = instance.normal(space, &hit).unwrap();
                        assert!((space.point_dot(n, n) + up * up - 1.0).abs() < 1e-9);
                        let (index, other) = both.unwrap();
                        assert_eq!(index, 1);
                        assert_eq!(other.s, hit.s);
                        hits += 1;
                    }
                    (None, None) => assert!(both.is_none()),
                    (got, expected) => panic!("{g:?}: instance {got:?}, brute force {expected:?}"),
                }
                assert_eq!(objects.occluded(space, &ray, 0.0, 3.0), expected.is_some());
            }
        }
        assert!(hits > 50, "{g:?}: only {hits} hits");
    }
}
