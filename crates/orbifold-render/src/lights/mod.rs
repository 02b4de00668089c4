//! Lights, their mirror images, and geodesic connections between two points (DESIGN.md §8).
//!
//! **Connections.** Two points (x, h₁) and (y, h₂) of S²×R, E²×R or H²×R are joined by the
//! geodesic whose horizontal part runs the geodesic of the plane from x to y (horizontal length
//! σ, direction `log(x, y)`) and whose height is linear in arc length: length ℓ = √(σ² + Δh²),
//! elevation α = atan2(Δh, σ). On the sphere there is also the geodesic that goes the other way
//! round (σ′ = 2π − σ). The light that leaves a point into a small solid angle dω covers the area
//! J·dω at distance ℓ, with J(ℓ, α) = ℓ·S_κ(ℓ cos α)/cos α = ℓ²·S_κ(σ)/σ (ℓ² for κ = 0) — the
//! area density of geodesic spheres — so the geometric term of a connection is
//! |cos θ₁||cos θ₂| / J. On the sphere J vanishes at the antipode, where light refocuses.
//!
//! **Images.** A light seen in a chain of mirrors is, unfolded, the light moved by the product of
//! the walls' reflections: the image g·y in the tile g·P of the room's universal cover. A
//! connection to an image, followed in the real room, bounces off those walls and arrives at the
//! light; it counts only if every wall it meets on the way is a mirror there, nothing blocks it,
//! and it really arrives (the tracer checks all three). Images are enumerated once per room,
//! breadth first across mirror walls, and kept while their largest possible contribution —
//! reflectance bound over J at their least possible distance — stays above a fraction of the
//! direct light's ([`ImageSet::new`]); so point lights light the room through mirrors, and area
//! lights converge without waiting for random hits.

use rustc_hash::FxHashMap;
use std::f64::consts::{PI, TAU};
use std::sync::Arc;

use arrayvec::ArrayVec;
use glam::{DMat3, DVec3};
use num_complex::Complex64;
use orbifold::embed::{Placement, embed};
use orbifold::space::Space;
use orbifold_scene::{LightKind, Scene};

use crate::sampler::Distribution1d;
use orbifold_trace::accel::Bvh;
use orbifold_trace::accel::Instance;
use orbifold_trace::geodesic::Ray;
use orbifold_trace::room::AnalyticRoom;
use orbifold_trace::with_avx512;

pub use orbifold_scene::color::Rgb;

/// An orthonormal frame of the tangent space of the product space at a point: two unit
/// horizontal ambient tangents and the vertical. Local coordinates are (e₁, e₂, up).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TangentFrame {
    /// First horizontal unit tangent (ambient).
    pub e1: DVec3,
    /// Second horizontal unit tangent, a quarter turn from `e1`.
    pub e2: DVec3,
}

impl TangentFrame {
    /// A frame at the ambient point `x` ([`Space::tangent_frame`]: shading needs any frame,
    /// textures in intrinsic coordinates this one).
    ///
    /// ```
    /// use orbifold::{Geometry, space::Space};
    /// use orbifold_render::lights::TangentFrame;
    /// use glam::DVec3;
    /// let h2 = Space::new(Geometry::Hyperbolic);
    /// let x = h2.exp(DVec3::Z, DVec3::new(0.3, -1.2, 0.0));
    /// let f = TangentFrame::at(h2, x);
    /// assert!((h2.point_dot(f.e1, f.e1) - 1.0).abs() < 1e-12 && h2.point_dot(f.e1, f.e2).abs() < 1e-12);
    /// ```
    pub fn at(space: Space, x: DVec3) -> TangentFrame {
        let [e1, e2] = space.tangent_frame(x);
        TangentFrame { e1, e2 }
    }

    /// Local coordinates of a tangent vector (horizontal ambient part, vertical part).
    #[inline]
    pub fn to_local(&self, space: Space, horizontal: DVec3, vertical: f64) -> DVec3 {
        DVec3::new(
            space.point_dot(horizontal, self.e1),
            space.point_dot(horizontal, self.e2),
            vertical,
        )
    }

    /// The tangent vector (horizontal ambient part, vertical part) of local coordinates.
    #[inline]
    pub fn to_ambient(&self, v: DVec3) -> (DVec3, f64) {
        (self.e1 * v.x + self.e2 * v.y, v.z)
    }

    /// The ray from (x, h) in the local direction `v` (unit).
    pub fn ray(&self, space: Space, x: DVec3, h: f64, v: DVec3) -> Ray {
        let horizontal = (v.x * v.x + v.y * v.y).sqrt();
        if horizontal < 1e-12 {
            // Straight up or down: any horizontal direction will do.
            return Ray::climbing(space, x, self.e1, h, 0.0, v.z.signum());
        }
        let u = (self.e1 * v.x + self.e2 * v.y) / horizontal;
        Ray::climbing(space, x, u, h, horizontal, v.z)
    }
}

/// The local direction of travel of a ray at arc length `s` (unit, in `frame` at that point).
pub fn travel_direction(space: Space, frame: &TangentFrame, ray: &Ray, s: f64) -> DVec3 {
    let u = ray.tangent_at(space, s * ray.cos_elevation);
    frame.to_local(space, u * ray.cos_elevation, ray.sin_elevation)
}

/// J(ℓ, α) = ℓ²·S_κ(σ)/σ for horizontal length σ = ℓ cos α: the area that a unit solid angle
/// covers at arc length ℓ (ℓ² in E²×R). Its absolute value (the sphere's S is negative past π).
///
/// ```
/// use orbifold::{Geometry, space::Space};
/// use orbifold_render::lights::spread;
/// let h2 = Space::new(Geometry::Hyperbolic);
/// // Vertical: like flat space; horizontal: the circumference density ℓ sinh ℓ.
/// assert!((spread(h2, 2.0, 0.0) - 4.0).abs() < 1e-12);
/// assert!((spread(h2, 2.0, 2.0) - 2.0 * 2f64.sinh()).abs() < 1e-12);
/// ```
pub fn spread(space: Space, length: f64, sigma: f64) -> f64 {
    let ratio = if sigma < 1e-8 {
        1.0 - space.kappa() * sigma * sigma / 6.0
    } else {
        space.sin(sigma) / sigma
    };
    length * length * ratio.abs()
}

/// A geodesic from one point to another.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Connection {
    /// The geodesic, starting at the first point.
    pub ray: Ray,
    /// Its arc length.
    pub length: f64,
    /// Its horizontal length σ.
    pub sigma: f64,
    /// J: see [`spread`].
    pub spread: f64,
}

/// The horizontal length of the geodesic from one point of the sphere to another at distance
/// `d` ≤ π that makes `turns` half-turns past it, and whether it leaves along the way back
/// (−u for the direction u of the short way). Half-turn 0 is the short way (σ = d), 1 the long
/// way round (2π − d), 2 the short way once more round the sphere (2π + d), and so on: σ lies
/// in [πt, π(t + 1)], so `turns` = ⌊σ/π⌋ of a geodesic's own horizontal length.
///
/// ```
/// use orbifold_render::lights::turned;
/// use std::f64::consts::PI;
/// assert_eq!(turned(1.0, 0), (1.0, false));
/// assert_eq!(turned(1.0, 1), (2.0 * PI - 1.0, true));
/// assert_eq!(turned(1.0, 2), (2.0 * PI + 1.0, false));
/// assert_eq!(turned(1.0, 3), (4.0 * PI - 1.0, true));
/// ```
pub fn turned(d: f64, turns: u32) -> (f64, bool) {
    let t = f64::from(turns);
    if turns.is_multiple_of(2) {
        (d + PI * t, false)
    } else {
        (PI * (t + 1.0) - d, true)
    }
}

/// The geodesic from (x, hx) to (y, hy) that makes `turns` half-turns round the sphere
/// ([`turned`]; 0, the shortest, in every geometry — the others exist on the sphere only,
/// where every geodesic comes back round). `frame` is a frame at x (for a vertical
/// connection).
pub fn connect(
    space: Space,
    frame: &TangentFrame,
    (x, hx): (DVec3, f64),
    (y, hy): (DVec3, f64),
    turns: u32,
) -> Option<Connection> {
    let way = Way::new(space, frame, (x, hx), (y, hy), turns)?;
    Some(Connection {
        ray: Ray::climbing(space, x, way.u, hx, way.sigma, way.dh),
        length: way.length,
        sigma: way.sigma,
        spread: spread(space, way.length, way.sigma),
    })
}

/// The geodesic of [`connect`] before its ray is built: the unit horizontal direction `u` it
/// leaves x in (ambient), its horizontal length σ, its rise and its arc length.
struct Way {
    u: DVec3,
    sigma: f64,
    dh: f64,
    length: f64,
}

impl Way {
    fn new(
        space: Space,
        frame: &TangentFrame,
        (x, hx): (DVec3, f64),
        (y, hy): (DVec3, f64),
        turns: u32,
    ) -> Option<Way> {
        if turns > 0 && space.kappa() <= 0.0 {
            return None;
        }
        let d = space.ambient_distance(x, y);
        let (u, sigma) = if d < 1e-12 {
            // Every way round leads back to x (a focus): only the straight connection is one.
            if turns > 0 {
                return None;
            }
            (frame.e1, 0.0)
        } else {
            let (sigma, back) = turned(d, turns);
            // The unit tangent towards y, y − C(d)·x normalised, with C(d) = 1 − κV from the
            // chord (V = ½|y − x|²_κ): `Space::log` over d, without its second inverse function
            // for d and its C(d).
            let chord = y - x;
            let t = y - x * (1.0 - 0.5 * space.kappa() * space.point_dot(chord, chord));
            let n = space.point_dot(t, t).max(0.0).sqrt();
            let u = if n == 0.0 {
                DVec3::ZERO
            } else {
                t / if back { -n } else { n }
            };
            (u, sigma)
        };
        let dh = hy - hx;
        let length = (sigma * sigma + dh * dh).sqrt();
        (length > 1e-12 && length.is_finite()).then_some(Way {
            u,
            sigma,
            dh,
            length,
        })
    }
}

/// What [`connect`] and [`travel_direction`] give of the geodesic from (x, hx) to (y, hy) with
/// `turns` half-turns, without building its ray: the direction it leaves x in (unit, local to
/// `frame`) and its J ([`spread`]). `None` where [`connect`] has no geodesic.
///
/// ```
/// use glam::DVec3;
/// use orbifold::{Geometry, space::Space};
/// use orbifold_render::lights::{TangentFrame, aim_at, connect, travel_direction};
/// let h2 = Space::new(Geometry::Hyperbolic);
/// let x = h2.exp(DVec3::Z, DVec3::new(0.3, -0.2, 0.0));
/// let y = h2.exp(DVec3::Z, DVec3::new(-0.5, 0.4, 0.0));
/// let frame = TangentFrame::at(h2, x);
/// let (wi, j) = aim_at(h2, &frame, (x, 0.1), (y, 0.7), 0).unwrap();
/// let link = connect(h2, &frame, (x, 0.1), (y, 0.7), 0).unwrap();
/// assert!((wi - travel_direction(h2, &frame, &link.ray, 0.0)).length() < 1e-12);
/// assert!((j - link.spread).abs() < 1e-12 * j);
/// ```
pub fn aim_at(
    space: Space,
    frame: &TangentFrame,
    (x, hx): (DVec3, f64),
    (y, hy): (DVec3, f64),
    turns: u32,
) -> Option<(DVec3, f64)> {
    let way = Way::new(space, frame, (x, hx), (y, hy), turns)?;
    let (cos, sin) = (way.sigma / way.length, way.dh / way.length);
    let direction = frame.to_local(space, way.u * cos, sin);
    Some((direction.normalize(), spread(space, way.length, way.sigma)))
}

/// The reflection across a wall (normalised linear form ν) as an ambient matrix:
/// x ↦ x − 2(ν·x)Gν.
pub fn reflection_matrix(space: Space, nu: DVec3) -> DMat3 {
    let g_nu = DVec3::new(nu.x, nu.y, space.kappa() * nu.z);
    DMat3::from_cols(
        DVec3::X - g_nu * (2.0 * nu.x),
        DVec3::Y - g_nu * (2.0 * nu.y),
        DVec3::Z - g_nu * (2.0 * nu.z),
    )
}

/// One image of the room: a tile g·P of its universal cover reached across mirror walls.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Image {
    /// g, as an ambient matrix (the product of the wall reflections, first wall first).
    pub isometry: DMat3,
    /// g⁻¹.
    pub inverse: DMat3,
    /// g applied to the room's centre (identifies the tile).
    pub key: DVec3,
    /// The largest product of mirror reflectances a path into this tile can carry.
    pub reflectance: Rgb,
    /// Number of reflections.
    pub depth: usize,
}

/// The images of a room (the identity first), with a lookup from g.
#[derive(Clone, Debug)]
pub struct ImageSet {
    /// The images, the identity first, by depth.
    pub images: Vec<Image>,
    /// The images by the cell of their keys ([`ImageSet::cell`]; a small integer key, for
    /// which a multiplicative hash does).
    lookup: FxHashMap<[i64; 3], Vec<usize>>,
    centre: DVec3,
}

/// How many times the sphere's estimated spread of arrival angles the facing margin allows
/// (once is enough in `tests/lights.rs` over 20,000 random points; half is not).
const CURVATURE_MARGIN: f64 = 2.0;
/// On the sphere, points this close to the antipode of a sphere light keep all its triangles.
const ANTIPODE: f64 = 1e-3;

/// Images are kept while their contribution bound is at least this fraction of the direct light's.
pub const IMAGE_CUTOFF: f64 = 1e-4;
/// At most this many images.
pub const MAX_IMAGES: usize = 4096;

use orbifold_scene::color::luminance;

impl ImageSet {
    /// The images of a room whose centre is `centre` (ambient), breadth first across walls that
    /// carry a mirror, while reflectance bound × J(radius)/J(least distance) ≥ [`IMAGE_CUTOFF`]
    /// and at most [`MAX_IMAGES`].
    ///
    /// ```
    /// use orbifold::{Layout, LayoutOptions};
    /// use orbifold_render::{light::ImageSet, room::AnalyticRoom};
    /// let layout = Layout::new(&"*235".parse()?, &LayoutOptions::default())?;
    /// let room = AnalyticRoom::all_mirrors(&layout, 1.0, [0.9; 3])?;
    /// let images = ImageSet::new(&room, room.space.to_ambient(layout.centre));
    /// // The spherical group *235 has 120 elements: every tile is an image.
    /// assert_eq!(images.images.len(), 120);
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn new(room: &AnalyticRoom, centre: DVec3) -> ImageSet {
        let space = room.space;
        let radius = room
            .walls
            .iter()
            .map(|w| space.ambient_distance(centre, w.start))
            .fold(0.0, f64::max)
            .max(room.height)
            .max(1e-3);
        let reference = spread(space, radius, radius);
        let mirrors: Vec<(usize, DMat3, Rgb)> = room
            .walls
            .iter()
            .enumerate()
            // A wall drawn as a model circle (straight rays) is no isometry's mirror.
            .filter(|(_, w)| w.drawn_in.is_none())
            .filter_map(|(i, w)| {
                let best = w.mirrors.iter().fold([0.0f64; 3], |acc, m| {
                    [0, 1, 2].map(|c| acc[c].max(m.reflectance[c]))
                });
                (luminance(best) > 0.0).then(|| (i, reflection_matrix(space, w.form), best))
            })
            .collect();
        let mut set = ImageSet {
            images: vec![Image {
                isometry: DMat3::IDENTITY,
                inverse: DMat3::IDENTITY,
                key: centre,
                reflectance: [1.0; 3],
                depth: 0,
            }],
            lookup: FxHashMap::default(),
            centre,
        };
        set.insert_key(0);
        let mut next = 0;
        while next < set.images.len() && set.images.len() < MAX_IMAGES {
            let image = set.images[next];
            next += 1;
            for &(_, reflection, rho) in &mirrors {
                let isometry = image.isometry * reflection;
                let key = isometry * centre;
                if set.find(key).is_some() {
                    continue;
                }
                let reflectance = [0, 1, 2].map(|c| image.reflectance[c] * rho[c]);
                let far = (space.ambient_distance(centre, key) - 2.0 * radius).max(radius);
                let bound = luminance(reflectance) * reference / spread(space, far, far);
                if space.kappa() <= 0.0 && bound < IMAGE_CUTOFF {
                    continue;
                }
                set.images.push(Image {
                    isometry,
                    inverse: isometry.inverse(),
                    key,
                    reflectance,
                    depth: image.depth + 1,
                });
                set.insert_key(set.images.len() - 1);
                if set.images.len() >= MAX_IMAGES {
                    break;
                }
            }
        }
        set
    }

    /// The lookup cell of a key: its coordinates in steps of 1e-4, rounded half away from zero
    /// by casts (`f64::round` is a library call on baseline x86-64, and a lookup rounds nine
    /// times). Any monotone rounding would do: [`ImageSet::find`] relies on that alone.
    fn cell(key: DVec3) -> [i64; 3] {
        [key.x, key.y, key.z].map(|v| {
            let steps = ((v * 1e4).abs() + 0.5) as i64;
            if v < 0.0 { -steps } else { steps }
        })
    }

    fn insert_key(&mut self, index: usize) {
        let cell = Self::cell(self.images[index].key);
        self.lookup.entry(cell).or_default().push(index);
    }

    /// The image whose tile has centre `key` (within 1e-7 (1 + |key|)), if enumerated.
    pub fn find(&self, key: DVec3) -> Option<usize> {
        // Long chains of reflections in H² reach points far out on the hyperboloid, whose cells
        // saturate: no image is there.
        if !key.is_finite() {
            return None;
        }
        let tolerance = 1e-7 * (1.0 + key.length());
        // Only the cells within the tolerance of the key (nearly always its own alone; a key
        // within the tolerance of a cell's edge also looks across it), at most one cell away.
        let centre = Self::cell(key);
        let low = Self::cell(key - DVec3::splat(tolerance));
        let high = Self::cell(key + DVec3::splat(tolerance));
        let span = |axis: usize| {
            low[axis].max(centre[axis].saturating_sub(1))
                ..=high[axis].min(centre[axis].saturating_add(1))
        };
        for a in span(0) {
            for b in span(1) {
                for c in span(2) {
                    let Some(list) = self.lookup.get(&[a, b, c]) else {
                        continue;
                    };
                    for &i in list {
                        if (self.images[i].key - key).length() < tolerance {
                            return Some(i);
                        }
                    }
                }
            }
        }
        None
    }

    /// The image reached by a path that met the walls with these reflection matrices, in order.
    pub fn find_chain(&self, reflections: &DMat3) -> Option<usize> {
        self.find(*reflections * self.centre)
    }
}

/// Triangles per block of [`Facing::kept_blocks`].
const BLOCK: usize = 8;
/// Most blocks (a sphere light has 352 triangles: 44).
const MAX_BLOCKS: usize = 64;

/// What lets light sampling skip the triangles of a sphere light that face away from the point
/// being lit (half of them, which could only ever give zero), in the tangent space at the light
/// mesh's origin (object coordinates).
///
/// A triangle whose centroid is `a` and outward normal `n` (local coordinates) is kept for the
/// point `b` when n·(b − a) > −m (d + r), with d the distance of `b` from the sphere's centre, r
/// the sphere's radius and m = 0.05 + r²: a margin for the triangles' extent and for the
/// curvature over the light, so that no triangle that faces `b` is left out. Points within 1.05 r
/// of the centre keep every triangle.
///
/// Among the kept triangles, light sampling draws each by about the solid angle it fills seen
/// from the point (`Aim::weight`), not by its area, so that a light sample's estimate hardly
/// varies over the sphere.
#[derive(Clone, Debug)]
pub struct Facing {
    /// The curvature of the plane.
    kappa: f64,
    frame: TangentFrame,
    centre: DVec3,
    radius: f64,
    /// Per triangle (n_x, n_y, n_z, n·a): its outward normal and offset.
    planes: Vec<[f64; 4]>,
    /// The same planes and the triangles' areas, one array per quantity, for the pass over all
    /// of them at every light sample (SIMD, no branches).
    lanes: PlaneLanes,
}

/// The triangles' planes and areas, one array per quantity, padded to whole blocks of `BLOCK`
/// (padding: area 0).
#[derive(Clone, Debug)]
struct PlaneLanes {
    nx: Vec<f32>,
    ny: Vec<f32>,
    nz: Vec<f32>,
    offset: Vec<f32>,
    /// The triangles' centroids.
    cx: Vec<f32>,
    cy: Vec<f32>,
    cz: Vec<f32>,
    area: Vec<f32>,
}

/// A lit point in the local coordinates of a sphere light's [`Facing`], with what weighing its
/// triangles for it takes.
///
/// Weights are worked out in single precision, eight triangles to an AVX register: they only
/// shape a distribution, and sampling and its density read the same bits.
#[derive(Clone, Copy, Debug)]
struct Aim {
    /// The point.
    b: [f32; 3],
    /// The facing margin ([`Facing::margin`]).
    margin: f32,
    /// A floor under squared distances, (0.05 r)² for the sphere's radius r (points are kept
    /// only beyond 1.05 r from its centre).
    floor: f32,
}

impl Aim {
    /// The weight of a kept triangle of area `area` whose plane is `value` in front of the
    /// point and whose centroid is ℓ away (`squared` = ℓ²): about the solid angle it fills seen
    /// from the point, area · value / ℓ³ (area times the cosine at the triangle over ℓ²).
    /// The margin is added to `value` (kept triangles have `value` > −margin) so that those kept
    /// only by the margin, seen past the silhouette through the curvature, can still be drawn. These weights make a light
    /// sample's estimate nearly constant over the sphere, where area weights leave each
    /// triangle's cosine over ℓ² in it: a relative variance of about 1/3 seen from far away,
    /// and far more from near.
    #[inline(always)]
    fn weight(&self, area: f32, value: f32, squared: f32) -> f32 {
        let squared = squared.max(self.floor);
        area * (value + self.margin) / (squared * squared.sqrt())
    }
}

impl PlaneLanes {
    fn new(planes: &[[f64; 4]], centroids: &[DVec3], areas: &[f64]) -> PlaneLanes {
        let padded = planes.len().div_ceil(BLOCK) * BLOCK;
        // Padding: area 0, and a centroid far from any point (no distance 0 to divide by).
        let lane = |f: &dyn Fn(usize) -> f64, padding: f32| -> Vec<f32> {
            (0..padded)
                .map(|i| {
                    if i < planes.len() {
                        f(i) as f32
                    } else {
                        padding
                    }
                })
                .collect()
        };
        PlaneLanes {
            nx: lane(&|i| planes[i][0], 0.0),
            ny: lane(&|i| planes[i][1], 0.0),
            nz: lane(&|i| planes[i][2], 0.0),
            offset: lane(&|i| planes[i][3], 0.0),
            cx: lane(&|i| centroids[i].x, 1e3),
            cy: lane(&|i| centroids[i].y, 1e3),
            cz: lane(&|i| centroids[i].z, 1e3),
            area: lane(&|i| areas[i], 0.0),
        }
    }

    /// How many blocks.
    fn blocks(&self) -> usize {
        self.area.len() / BLOCK
    }

    /// The weights for the aim of the triangles from `start` on, as many as `out` holds:
    /// [`Aim::weight`] where the triangle is kept, else 0. One plain loop over the arrays, which
    /// the compiler turns into SIMD; lane by lane the same operations whatever the stretch, so
    /// a block's weights are the same bits whether worked out alone or with all the others.
    #[inline(always)]
    fn weights_into(&self, aim: &Aim, start: usize, out: &mut [f32]) {
        let n = out.len();
        let range = start..start + n;
        let (nx, ny, nz) = (
            &self.nx[range.clone()],
            &self.ny[range.clone()],
            &self.nz[range.clone()],
        );
        let (cx, cy, cz) = (
            &self.cx[range.clone()],
            &self.cy[range.clone()],
            &self.cz[range.clone()],
        );
        let (offset, area) = (&self.offset[range.clone()], &self.area[range]);
        let [x, y, z] = aim.b;
        for i in 0..n {
            let value = nx[i] * x + ny[i] * y + nz[i] * z - offset[i];
            let (dx, dy, dz) = (x - cx[i], y - cy[i], z - cz[i]);
            let weight = aim.weight(area[i], value, dx * dx + dy * dy + dz * dz);
            // The weight masked by the comparison (what SIMD compare-and-mask does).
            let mask = if value > -aim.margin { u32::MAX } else { 0 };
            out[i] = f32::from_bits(weight.to_bits() & mask);
        }
    }

    /// Block `k`'s weights for the aim.
    #[inline(always)]
    fn block(&self, aim: &Aim, k: usize) -> [f32; BLOCK] {
        let mut weights = [0.0; BLOCK];
        self.weights_into(aim, k * BLOCK, &mut weights);
        weights
    }
}

/// A block's weights summed: halves, then quarters, then pairs (the order in which a register
/// is folded; a running sum would wait on every addition).
#[inline(always)]
fn block_sum(weights: &[f32]) -> f64 {
    let h: [f64; 4] = std::array::from_fn(|j| f64::from(weights[j]) + f64::from(weights[j + 4]));
    (h[0] + h[2]) + (h[1] + h[3])
}

impl Facing {
    fn new(space: Space, instance: &Instance, areas: &[f64]) -> Option<Facing> {
        let origin = DVec3::Z;
        let frame = TangentFrame::at(space, origin);
        let (points, heights, triangles) = instance.bvh.mesh();
        let local = |i: u32| {
            let i = i as usize;
            frame.to_local(space, space.log(origin, points[i]), heights[i])
        };
        let centroids: Vec<DVec3> = triangles
            .iter()
            .map(|t| (local(t[0]) + local(t[1]) + local(t[2])) / 3.0)
            .collect();
        let centre = centroids.iter().copied().sum::<DVec3>() / centroids.len().max(1) as f64;
        // The triangles' own (flat) normals, outwards: within a triangle n·(b − p) is the same
        // for every point p, up to the curvature over the light.
        let normals: Vec<DVec3> = triangles
            .iter()
            .zip(&centroids)
            .map(|(t, a)| {
                let n = (local(t[1]) - local(t[0]))
                    .cross(local(t[2]) - local(t[0]))
                    .normalize_or_zero();
                if n.dot(*a - centre) < 0.0 { -n } else { n }
            })
            .collect();
        let radius = centroids
            .iter()
            .map(|a| (*a - centre).length())
            .fold(0.0, f64::max);
        let planes: Vec<[f64; 4]> = normals
            .iter()
            .zip(&centroids)
            .map(|(n, a)| [n.x, n.y, n.z, n.dot(*a)])
            .collect();
        let lanes = PlaneLanes::new(&planes, &centroids, areas);
        (radius > 0.0 && radius.is_finite()).then_some(Facing {
            kappa: space.kappa(),
            frame,
            centre,
            radius,
            planes,
            lanes,
        })
    }

    /// The point (object coordinates) in the local coordinates of the triangles, or `None` when
    /// every triangle is kept.
    fn local(&self, space: Space, (x, h): (DVec3, f64)) -> Option<DVec3> {
        let b = self.frame.to_local(space, space.log(DVec3::Z, x), h);
        let d = (b - self.centre).length();
        // At the light's antipode on the sphere, geodesics from the point reach it from every
        // side (`margin` grows without bound towards it).
        let antipodal = space.kappa() > 0.0 && (b.x * b.x + b.y * b.y).sqrt() > PI - ANTIPODE;
        (b.is_finite() && d > 1.05 * self.radius && !antipodal).then_some(b)
    }

    /// The margin for the local point `b`.
    ///
    /// On the sphere geodesics from a point D away refocus towards its antipode, so they reach
    /// the light's side at angles that differ from straight lines' by about r(1/D − cot D) (the
    /// Jacobi fields of the sphere against those of the plane): negligible near the light, a
    /// radian for r = 0.1 at D = 3 and unbounded at the antipode. The margin grows with it.
    fn margin(&self, b: DVec3) -> f64 {
        let mut angle = 0.05 + self.radius * self.radius;
        // (Local coordinates near the light: no overflow for `hypot`, which is slow, to guard.)
        let d = (b.x * b.x + b.y * b.y).sqrt();
        if self.kappa > 0.0 && d > 1e-6 {
            angle += CURVATURE_MARGIN * self.radius * (1.0 / d - 1.0 / d.tan()).max(0.0);
        }
        angle * ((b - self.centre).length() + self.radius)
    }

    /// What sampling needs to weigh the triangles for the local point `b`.
    fn aim(&self, b: DVec3) -> Aim {
        let margin = self.margin(b);
        Aim {
            b: [b.x as f32, b.y as f32, b.z as f32],
            margin: margin as f32,
            floor: (0.05 * self.radius).powi(2) as f32,
        }
    }

    /// Triangle `i`'s weight for the aim `aim` (0 when it is not kept), computed as the blocks
    /// compute it, to the bit.
    #[inline]
    fn weight_of(&self, i: usize, aim: &Aim) -> f64 {
        f64::from(self.lanes.block(aim, i / BLOCK)[i % BLOCK])
    }

    /// The kept weight block by block (`BLOCK` triangles each) into `blocks`, and the total;
    /// `None` when the light has more than `BLOCK`·`MAX_BLOCKS` triangles.
    fn kept_blocks(&self, aim: &Aim, blocks: &mut [f64; MAX_BLOCKS]) -> Option<f64> {
        with_avx512!(
            Facing,
            self.kept_blocks_portable(aim: &Aim, blocks: &mut [f64; MAX_BLOCKS]) -> Option<f64>
        )
    }

    #[inline(always)]
    fn kept_blocks_portable(&self, aim: &Aim, blocks: &mut [f64; MAX_BLOCKS]) -> Option<f64> {
        let count = self.lanes.blocks();
        if count > MAX_BLOCKS {
            return None;
        }
        let mut weights = [0.0; BLOCK * MAX_BLOCKS];
        let weights = &mut weights[..count * BLOCK];
        self.lanes.weights_into(aim, 0, weights);
        let mut total = 0.0;
        for (block, sum) in weights.chunks_exact(BLOCK).zip(blocks.iter_mut()) {
            *sum = block_sum(block);
            total += *sum;
        }
        Some(total)
    }

    /// The kept triangle that `target` (in [0, kept weight)) falls on when the kept triangles'
    /// weights are laid end to end (the last kept one if rounding runs past): whole blocks are
    /// stepped over by their sums, and only the block it falls in is scanned.
    fn pick(&self, aim: &Aim, blocks: &[f64; MAX_BLOCKS], mut target: f64) -> Option<usize> {
        let count = self.lanes.blocks();
        let range = |k: usize| k * BLOCK..((k + 1) * BLOCK).min(self.planes.len());
        let mut last = None;
        for (k, &sum) in blocks[..count].iter().enumerate() {
            if sum <= 0.0 {
                continue;
            }
            last = Some(k);
            if target >= sum {
                target -= sum;
                continue;
            }
            let weights = self.lanes.block(aim, k);
            for i in range(k) {
                let weight = f64::from(weights[i % BLOCK]);
                if weight > 0.0 {
                    if target < weight {
                        return Some(i);
                    }
                    target -= weight;
                }
            }
        }
        // Rounding ran past the end: the last kept triangle.
        let last = last?;
        let weights = self.lanes.block(aim, last);
        range(last).rev().find(|&i| weights[i % BLOCK] > 0.0)
    }

    /// The total weight of the triangles kept for the aim (one branch-free pass; summed as
    /// [`Facing::kept_blocks`] sums it, so that sampling and its density agree to the last bit).
    fn kept_weight(&self, aim: &Aim) -> f64 {
        let mut blocks = [0.0; MAX_BLOCKS];
        if let Some(total) = self.kept_blocks(aim, &mut blocks) {
            return total;
        }
        (0..self.planes.len()).map(|i| self.weight_of(i, aim)).sum()
    }
}

impl Emitter {
    /// The emitter with [`Facing`] for a sphere light's mesh.
    fn with_facing(self, space: Space) -> Emitter {
        match self {
            Emitter::Area {
                radiance,
                instance,
                areas,
                pick,
                total_area,
                two_sided,
                ..
            } => Emitter::Area {
                facing: Facing::new(space, &instance, &areas),
                radiance,
                instance,
                areas,
                pick,
                total_area,
                two_sided,
            },
            other => other,
        }
    }
}

/// How a light emits.
#[derive(Clone, Debug)]
// A scene has a handful of lights: their size does not matter, one indirection per sample does.
#[allow(clippy::large_enum_variant)]
pub enum Emitter {
    /// A point emitting `intensity` (W/sr per channel) in every direction.
    Point {
        /// Radiant intensity.
        intensity: Rgb,
    },
    /// A point emitting `intensity` inside a cone around `axis` (local frame at the light).
    Spot {
        /// Radiant intensity inside the cone.
        intensity: Rgb,
        /// Unit axis in the light's local frame.
        axis: DVec3,
        /// cos of the cone's half-angle.
        cos_cone: f64,
    },
    /// A mesh of intrinsically flat triangles emitting `radiance` (Lambertian).
    Area {
        /// Emitted radiance.
        radiance: Rgb,
        /// The placed mesh (also hit by rays).
        instance: Instance,
        /// Triangle areas (intrinsic).
        areas: Vec<f64>,
        /// Picks a triangle ∝ its area.
        pick: Distribution1d,
        /// For a sphere light: which triangles can face a point.
        facing: Option<Facing>,
        /// Their total.
        total_area: f64,
        /// Emits from both sides (spheres) or only the front (rectangles).
        two_sided: bool,
    },
}

/// A light of the scene.
#[derive(Clone, Debug)]
pub struct Light {
    /// Ambient horizontal position of its centre.
    pub position: DVec3,
    /// Height of its centre.
    pub height: f64,
    /// A tangent frame at its centre.
    pub frame: TangentFrame,
    /// Power (W, per channel: colour × power).
    pub power: Rgb,
    /// How it emits.
    pub emitter: Emitter,
}

/// A point sampled on a light, with its emission towards a direction still to be given.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LightPoint {
    /// Ambient horizontal position.
    pub x: DVec3,
    /// Height.
    pub h: f64,
    /// Probability density per unit area (0 for point lights).
    pub pdf_area: f64,
    /// The triangle of the light's mesh and the barycentrics (area lights).
    pub triangle: Option<(u32, [f64; 3])>,
}

/// The facing triangles of a sphere light for one lit point, by blocks ([`Facing::kept_blocks`]).
#[derive(Clone, Copy, Debug)]
struct KeptBlocks {
    aim: Aim,
    blocks: [f64; MAX_BLOCKS],
    kept: f64,
}

/// A light made ready to sample points for one lit point ([`Light::aimed_at`]).
#[derive(Clone, Copy, Debug)]
pub struct AimedLight<'a> {
    light: &'a Light,
    from: Option<(DVec3, f64)>,
    blocked: Option<KeptBlocks>,
}

impl AimedLight<'_> {
    /// Works out which of a sphere light's triangles face `from`, in place.
    fn aim(&mut self, space: Space) {
        let light = self.light;
        let Emitter::Area {
            facing: Some(facing),
            ..
        } = &light.emitter
        else {
            return;
        };
        let Some((_, b)) = light.facing_from(space, self.from) else {
            return;
        };
        let aim = facing.aim(b);
        let kept = self.blocked.insert(KeptBlocks {
            aim,
            blocks: [0.0; MAX_BLOCKS],
            kept: 0.0,
        });
        match facing.kept_blocks(&aim, &mut kept.blocks) {
            Some(total) => kept.kept = total,
            None => self.blocked = None,
        }
    }

    /// A point on the light for uniforms `u`, `v`, as [`Light::sample_point`] draws it.
    pub fn sample(&self, space: Space, u: f64, v: (f64, f64)) -> Option<LightPoint> {
        let light = self.light;
        let Emitter::Area {
            areas,
            total_area,
            pick,
            facing,
            ..
        } = &light.emitter
        else {
            return Some(LightPoint {
                x: light.position,
                h: light.height,
                pdf_area: 0.0,
                triangle: None,
            });
        };
        if let (Some(kept), Some(facing)) = (&self.blocked, facing)
            && kept.kept > 0.0
        {
            // The kept triangles' set changes with the point: block sums, then one block.
            let i = facing.pick(&kept.aim, &kept.blocks, u * kept.kept)?;
            let weight = facing.weight_of(i, &kept.aim);
            let probability = weight / kept.kept;
            return light.point_on(space, i, probability, v);
        }
        let (index, probability) = match (light.kept(space, self.from), facing) {
            (Some((aim, kept)), Some(facing)) => {
                // A linear scan over the kept triangles (their set changes with the point).
                let mut target = u * kept;
                let mut chosen = None;
                for i in 0..areas.len() {
                    let weight = facing.weight_of(i, &aim);
                    if weight > 0.0 {
                        chosen = Some((i, weight));
                        if target < weight {
                            break;
                        }
                        target -= weight;
                    }
                }
                let (i, weight) = chosen?;
                (i, weight / kept)
            }
            // Pick a triangle ∝ area (binary search: a sphere light has thousands).
            _ => {
                let (i, _) = pick.sample(u);
                (i, areas[i] / total_area)
            }
        };
        light.point_on(space, index, probability, v)
    }
}

impl Light {
    /// The lights of a scene in the room's space.
    pub fn from_scene(space: Space, scene: &Scene) -> Result<Vec<Light>, String> {
        scene
            .lights
            .iter()
            .enumerate()
            .map(|(i, l)| {
                let z = Complex64::new(l.at[0], l.at[1]);
                let position = space.to_ambient(z);
                let frame = TangentFrame::at(space, position);
                let power = l.color.map(|c| c * l.power);
                let (yaw, pitch) = (l.yaw.to_radians(), l.pitch.to_radians());
                // The light's direction in (model +x, model +y, up) at its position, then in
                // the light's own frame.
                let model = [
                    space.model_tangent(z, Complex64::new(1.0, 0.0)),
                    space.model_tangent(z, Complex64::new(0.0, 1.0)),
                ];
                let h = model[0] * (pitch.cos() * yaw.cos()) + model[1] * (pitch.cos() * yaw.sin());
                let axis = frame.to_local(space, h, pitch.sin()).normalize();
                let emitter = match l.kind {
                    LightKind::Point => Emitter::Point {
                        intensity: power.map(|p| p / (4.0 * PI)),
                    },
                    LightKind::Spot => {
                        let cos_cone = l.cone.to_radians().cos();
                        Emitter::Spot {
                            intensity: power.map(|p| p / (TAU * (1.0 - cos_cone))),
                            axis,
                            cos_cone,
                        }
                    }
                    LightKind::Sphere => {
                        // Coarser than the built-in object sphere: light sampling scans the
                        // triangles that face the lit point, 352 here (2 × 16 × 11).
                        let mesh = orbifold_scene::mesh::procedural::uv_sphere(0.5, 16, 12);
                        let centre =
                            orbifold::embed::centre_of_mass(&mesh.positions, &mesh.triangles);
                        let (lo, hi) = mesh.bounds().ok_or("empty sphere")?;
                        let scale = 2.0 * l.radius / (hi[1] - lo[1]);
                        area_emitter(
                            space,
                            &mesh.positions,
                            &mesh.triangles,
                            centre,
                            scale,
                            z,
                            l.height - l.radius,
                            power,
                            true,
                        )
                        .map(|e| e.with_facing(space))
                        .map_err(|e| format!("lights[{i}]: {e}"))?
                    }
                    LightKind::Rectangle => {
                        let (positions, triangles, lowest) = rectangle(axis, l.size);
                        area_emitter(
                            space,
                            &positions,
                            &triangles,
                            DVec3::ZERO,
                            1.0,
                            z,
                            l.height + lowest,
                            power,
                            false,
                        )
                        .map_err(|e| format!("lights[{i}]: {e}"))?
                    }
                };
                Ok(Light {
                    position,
                    height: l.height,
                    frame,
                    power,
                    emitter,
                })
            })
            .collect()
    }

    /// For a sphere light: the radius of its mesh's outline and its radiance (what
    /// [`orbifold_trace::footprint`] needs); `None` for other lights.
    pub fn sphere(&self) -> Option<(f64, Rgb)> {
        match &self.emitter {
            Emitter::Area {
                radiance,
                facing: Some(facing),
                ..
            } => Some((facing.radius, *radiance)),
            _ => None,
        }
    }

    /// Whether the light is a point (delta) light.
    pub fn is_point(&self) -> bool {
        !matches!(self.emitter, Emitter::Area { .. })
    }

    /// For a sphere light and a lit point `from` (world coordinates, in the light's own copy of
    /// the room: the image's inverse applied), its [`Facing`] and the point in its local
    /// coordinates; `None` for other lights, without `from`, or when every triangle is a
    /// candidate (the point is too close).
    fn facing_from(&self, space: Space, from: Option<(DVec3, f64)>) -> Option<(&Facing, DVec3)> {
        let (
            Emitter::Area {
                instance,
                facing: Some(facing),
                ..
            },
            Some((x, h)),
        ) = (&self.emitter, from)
        else {
            return None;
        };
        let b = facing.local(space, (instance.to_object * x, h - instance.height))?;
        Some((facing, b))
    }

    /// For a sphere light and a lit point `from` (as for [`Light::facing_from`]), the point's
    /// [`Aim`] and the total weight of the triangles kept for it; `None` when every triangle is
    /// a candidate.
    fn kept(&self, space: Space, from: Option<(DVec3, f64)>) -> Option<(Aim, f64)> {
        let (facing, b) = self.facing_from(space, from)?;
        let aim = facing.aim(b);
        let total = facing.kept_weight(&aim);
        (total > 0.0).then_some((aim, total))
    }

    /// Samples a point on the light (the centre for point lights) with uniforms `u`, `v`. With
    /// `from`, the point to be lit (world coordinates in the light's own copy of the room), a
    /// sphere light picks only among its triangles that can face it.
    pub fn sample_point(
        &self,
        space: Space,
        u: f64,
        v: (f64, f64),
        from: Option<(DVec3, f64)>,
    ) -> Option<LightPoint> {
        self.aimed_at(space, from).sample(space, u, v)
    }

    /// What [`Light::sample_point`] works out for the point `from` before it draws: which of a
    /// sphere light's triangles face it. Worked out once, it serves several draws for the same
    /// point (the candidates of a resampled light sample that chose the same image).
    ///
    /// ```
    /// use num_complex::Complex64;
    /// use orbifold_render::lights::Light;
    /// use orbifold_scene::{LightKind, Scene};
    ///
    /// let mut scene = Scene::default();
    /// scene.orbifold.signature = "*333".into();
    /// let layout = scene.layout().unwrap();
    /// scene.lights[0].kind = LightKind::Sphere;
    /// scene.lights[0].at = [layout.centre.re, layout.centre.im];
    /// let space = layout.space();
    /// let lights = Light::from_scene(space, &scene).unwrap();
    /// let x = space.to_ambient(layout.centre + Complex64::new(0.3, 0.1));
    /// let from = Some((x, 0.2));
    /// let aimed = lights[0].aimed_at(space, from);
    /// let once = aimed.sample(space, 0.4, (0.3, 0.6)).unwrap();
    /// let again = lights[0].sample_point(space, 0.4, (0.3, 0.6), from).unwrap();
    /// assert_eq!(once.x, again.x);
    /// assert_eq!(once.pdf_area, again.pdf_area);
    /// ```
    pub fn aimed_at(&self, space: Space, from: Option<(DVec3, f64)>) -> AimedLight<'_> {
        let mut aimed = AimedLight {
            light: self,
            from,
            blocked: None,
        };
        aimed.aim(space);
        aimed
    }

    /// [`Light::aimed_at`] pushed onto `list` with the tag `key`, its triangles' weights
    /// worked out where they are kept (they fill several cache lines: a light sample copied
    /// them twice, 1 % of a render's time in `memmove`).
    pub(crate) fn push_aimed<'a, 'b, const N: usize>(
        &'a self,
        space: Space,
        from: Option<(DVec3, f64)>,
        key: usize,
        list: &'b mut ArrayVec<(usize, AimedLight<'a>), N>,
    ) -> &'b AimedLight<'a> {
        list.push((
            key,
            AimedLight {
                light: self,
                from,
                blocked: None,
            },
        ));
        let (_, aimed) = list.last_mut().expect("just pushed");
        aimed.aim(space);
        aimed
    }

    /// A point of the area light's triangle `index`, picked with `probability`, uniform in its
    /// area for uniforms `v`.
    fn point_on(
        &self,
        space: Space,
        index: usize,
        probability: f64,
        v: (f64, f64),
    ) -> Option<LightPoint> {
        let Emitter::Area { instance, .. } = &self.emitter else {
            return None;
        };
        let root = v.0.sqrt();
        let w = [1.0 - root, root * (1.0 - v.1), root * v.1];
        let triangle = instance.bvh.triangle(index as u32);
        let (x, h) = triangle.point(space, w);
        let jacobian = area_jacobian(space, &triangle.points, &triangle.heights, w);
        if jacobian <= 0.0 {
            return None;
        }
        Some(LightPoint {
            x: instance.to_world * x,
            h: h + instance.height,
            pdf_area: probability * 2.0 / jacobian,
            triangle: Some((index as u32, w)),
        })
    }

    /// Whether a geodesic from `from` (world coordinates in the light's own copy of the room, as
    /// for [`Light::sample_point`]) to a point of triangle `triangle` cannot meet the light
    /// itself before it: for a sphere light's triangle that faces `from` clearly (a geodesic
    /// enters a convex ball once, through the side that faces it; triangles near the silhouette,
    /// where the curvature could decide, are left out). Shadow rays to such a point need not
    /// test the light's own mesh. False for other lights and triangles.
    pub fn reaches_unobstructed(
        &self,
        space: Space,
        triangle: u32,
        from: Option<(DVec3, f64)>,
    ) -> bool {
        let i = triangle as usize;
        // Facing by more than the margin that covers the curvature over the light (the test is
        // made in the tangent space at the light's centre).
        self.facing_from(space, from).is_some_and(|(facing, b)| {
            i < facing.planes.len() && {
                let [x, y, z, offset] = facing.planes[i];
                DVec3::new(x, y, z).dot(b) - offset > facing.margin(b)
            }
        })
    }

    /// The density per unit area with which [`Light::sample_point`] picks the point of triangle
    /// `triangle` at barycentrics `w` (area lights) for the lit point `from`.
    pub fn pdf_area(
        &self,
        space: Space,
        triangle: u32,
        w: [f64; 3],
        from: Option<(DVec3, f64)>,
    ) -> f64 {
        let Emitter::Area {
            instance,
            areas,
            total_area,
            facing,
            ..
        } = &self.emitter
        else {
            return 0.0;
        };
        let probability = match (self.kept(space, from), facing) {
            (Some((aim, kept)), Some(facing)) => facing.weight_of(triangle as usize, &aim) / kept,
            _ => areas[triangle as usize] / total_area,
        };
        let t = instance.bvh.triangle(triangle);
        let jacobian = area_jacobian(space, &t.points, &t.heights, w);
        if jacobian <= 0.0 {
            return 0.0;
        }
        probability * 2.0 / jacobian
    }

    /// Radiant intensity (point lights) or radiance (area lights) leaving towards the local
    /// direction `out` (unit, in the light's frame for point lights; for area lights `cos_out` is
    /// the cosine with the surface normal, negative behind).
    pub fn emission(&self, out: DVec3, cos_out: f64) -> Rgb {
        match &self.emitter {
            Emitter::Point { intensity } => *intensity,
            Emitter::Spot {
                intensity,
                axis,
                cos_cone,
            } => {
                if out.dot(*axis) >= *cos_cone {
                    *intensity
                } else {
                    [0.0; 3]
                }
            }
            Emitter::Area {
                radiance,
                two_sided,
                ..
            } => {
                if cos_out > 0.0 || (*two_sided && cos_out < 0.0) {
                    *radiance
                } else {
                    [0.0; 3]
                }
            }
        }
    }
}

/// The area element of the intrinsically flat triangle at barycentrics `w`, per unit of
/// (w₁, w₂): |∂X/∂w₁ ∧ ∂X/∂w₂| in the product metric, X(w) = (normalise(Σ wᵢpᵢ), Σ wᵢhᵢ).
pub fn area_jacobian(space: Space, points: &[DVec3; 3], heights: &[f64; 3], w: [f64; 3]) -> f64 {
    let q = points[0] * w[0] + points[1] * w[1] + points[2] * w[2];
    // normalise(q) = q/|q|_κ, and for κ = 0 q/q_z (the plane z = 1).
    let norm = if space.kappa() == 0.0 {
        q.z
    } else {
        space.point_dot(q, q).abs().sqrt()
    };
    if norm == 0.0 {
        return 0.0;
    }
    let n = q / norm;
    let k = space.kappa();
    // d normalise(q) = (v − κ⟨n, v⟩n)/|q| (E²: z is fixed at 1 and v has z = 0).
    let project = |v: DVec3| (v - n * (k * space.point_dot(n, v))) / norm;
    let a = (project(points[1] - points[0]), heights[1] - heights[0]);
    let b = (project(points[2] - points[0]), heights[2] - heights[0]);
    let dot = |x: (DVec3, f64), y: (DVec3, f64)| space.point_dot(x.0, y.0) + x.1 * y.1;
    (dot(a, a) * dot(b, b) - dot(a, b).powi(2)).max(0.0).sqrt()
}

/// A rectangle facing `axis` (local frame), `size` = [width, height], in object coordinates
/// (Y up) as [`embed`] takes them, centred at the origin; and its lowest local height.
fn rectangle(axis: DVec3, size: [f64; 2]) -> (Vec<[f64; 3]>, Vec<[u32; 3]>, f64) {
    let right = if axis.truncate().length() < 1e-9 {
        DVec3::X
    } else {
        axis.cross(DVec3::Z).normalize()
    };
    // (right, up, axis) right-handed, so that right × up = axis: the front faces the axis.
    let up = axis.cross(right);
    let corners = [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)]
        .map(|(a, b)| right * (0.5 * size[0] * a) + up * (0.5 * size[1] * b));
    // Wound counter-clockwise seen from the front.
    let lowest = corners.iter().map(|c| c.z).fold(f64::INFINITY, f64::min);
    let positions = corners.iter().map(|c| [c.x, c.z, -c.y]).collect();
    (positions, vec![[0, 1, 2], [0, 2, 3]], lowest)
}

#[allow(clippy::too_many_arguments)]
fn area_emitter(
    space: Space,
    positions: &[[f64; 3]],
    triangles: &[[u32; 3]],
    centre: DVec3,
    scale: f64,
    at: Complex64,
    height: f64,
    power: Rgb,
    two_sided: bool,
) -> Result<Emitter, String> {
    let embedded = embed(space, positions, centre, scale);
    let bvh = Bvh::build(space, &embedded.points, &embedded.heights, triangles);
    let placement = Placement {
        at,
        height,
        yaw: 0.0,
    };
    mesh_emitter(
        space,
        Instance::from_placement(space, Arc::new(bvh), &placement),
        power,
        two_sided,
    )
}

/// A Lambertian emitter of total power `power` over the mesh of `instance`.
pub(crate) fn mesh_emitter(
    space: Space,
    instance: Instance,
    power: Rgb,
    two_sided: bool,
) -> Result<Emitter, String> {
    let (points, heights, triangles) = instance.bvh.mesh();
    let areas: Vec<f64> = triangles
        .iter()
        .map(|t| {
            let p = t.map(|i| points[i as usize]);
            let h = t.map(|i| heights[i as usize]);
            0.5 * area_jacobian(space, &p, &h, [1.0 / 3.0; 3])
        })
        .collect();
    let total_area: f64 = areas.iter().sum();
    let pick = Distribution1d::new(&areas).ok_or("the light has no area")?;
    Ok(Emitter::Area {
        // A Lambertian emitter of area A and radiance L sends out πAL.
        radiance: power.map(|p| p / (PI * total_area)),
        instance,
        areas,
        pick,
        facing: None,
        total_area,
        two_sided,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use orbifold_scene::{LightKind, Scene};

    /// An image set of the identity at each of `keys`, looked up as [`ImageSet::new`] does.
    fn set_of(keys: &[DVec3]) -> ImageSet {
        let image = |key| Image {
            isometry: DMat3::IDENTITY,
            inverse: DMat3::IDENTITY,
            key,
            reflectance: [1.0; 3],
            depth: 0,
        };
        let mut set = ImageSet {
            images: keys.iter().copied().map(image).collect(),
            lookup: FxHashMap::default(),
            centre: keys[0],
        };
        (0..keys.len()).for_each(|i| set.insert_key(i));
        set
    }

    proptest::proptest! {
        #[test]
        fn find_sees_a_key_from_across_cell_edges_and_no_further(
            corner in proptest::array::uniform3(-30_000i64..30_000),
            offset in proptest::array::uniform3(-1.0f64..1.0),
            delta in proptest::array::uniform3(-1.0f64..1.0),
        ) {
            // A key within a tolerance of a corner of the lookup cells (1e-4 wide), looked up
            // from points on every side of it within the tolerance (often in another cell).
            let corner = DVec3::from(corner.map(|c| (c as f64 + 0.5) * 1e-4));
            let tolerance = 1e-7 * (1.0 + corner.length());
            let key = corner + DVec3::from(offset) * tolerance / 3.0_f64.sqrt();
            let set = set_of(&[key]);
            let delta = DVec3::from(delta);
            let step = delta.normalize_or(DVec3::X) * delta.length().min(1.0);
            proptest::prop_assert_eq!(set.find(key + step * 0.99 * tolerance), Some(0));
            proptest::prop_assert_eq!(set.find(key + step.normalize_or(DVec3::X) * 3.0 * tolerance), None);
        }
    }

    #[test]
    fn every_image_is_found_by_its_key() {
        for signature in ["*235", "*2222", "*444", "*2223"] {
            let layout = orbifold::Layout::new(
                &signature.parse().unwrap(),
                &orbifold::LayoutOptions::default(),
            )
            .unwrap();
            let room =
                orbifold_trace::room::AnalyticRoom::all_mirrors(&layout, 1.0, [0.9; 3]).unwrap();
            let set = ImageSet::new(&room, room.space.to_ambient(layout.centre));
            assert!(set.images.len() > 40, "{signature}");
            for (i, image) in set.images.iter().enumerate() {
                assert_eq!(set.find(image.key), Some(i), "{signature} image {i}");
            }
        }
    }

    /// The sphere light of radius 0.1 over the centre of `signature`'s default room, and the
    /// room's space.
    fn sphere_light(signature: &str) -> (Space, Light) {
        let mut scene = Scene::default();
        scene.orbifold.signature = signature.into();
        let layout = scene.layout().unwrap();
        scene.lights[0].kind = LightKind::Sphere;
        scene.lights[0].at = [layout.centre.re, layout.centre.im];
        scene.lights[0].radius = 0.1;
        let mut lights = Light::from_scene(layout.space(), &scene).unwrap();
        (layout.space(), lights.swap_remove(0))
    }

    /// The sphere light of [`sphere_light`]: its facing and its triangles' areas.
    fn facing(signature: &str) -> (Facing, Vec<f64>) {
        let (_, light) = sphere_light(signature);
        let Emitter::Area {
            facing: Some(facing),
            areas,
            ..
        } = &light.emitter
        else {
            panic!("a sphere light with its facing");
        };
        (facing.clone(), areas.clone())
    }

    /// Triangle `i`'s plane value n·b − n·a for the local point `b` (in double precision).
    fn plane_value(facing: &Facing, i: usize, b: DVec3) -> f64 {
        let [x, y, z, offset] = facing.planes[i];
        DVec3::new(x, y, z).dot(b) - offset
    }

    /// Points all around the light, near (1.1 r) and far (21 r).
    fn points_around(facing: &Facing) -> impl Iterator<Item = DVec3> + '_ {
        (0..400).map(|k| {
            let t = f64::from(k);
            let direction =
                DVec3::new((t * 0.7).cos(), (t * 0.7).sin(), (t * 0.31).sin()).normalize();
            facing.centre + direction * facing.radius * (1.1 + 0.05 * t)
        })
    }

    #[test]
    fn block_sums_pick_the_triangles_a_scan_would_keep() {
        // For points all around the light, near and far: the triangles with a weight are those
        // that face the point within the margin, the block sums add up to their weights, and
        // `pick` lays the kept triangles end to end in index order, each over a stretch as long
        // as its weight (so a triangle is picked ∝ its weight).
        for signature in ["*235", "*2222", "*2223"] {
            let (facing, areas) = facing(signature);
            for b in points_around(&facing) {
                let aim = facing.aim(b);
                let margin = facing.margin(b);
                let weights: Vec<f64> = (0..areas.len())
                    .map(|i| facing.weight_of(i, &aim))
                    .collect();
                for (i, &w) in weights.iter().enumerate() {
                    // Single precision may decide otherwise only right at the margin.
                    let value = plane_value(&facing, i, b);
                    if (value + margin).abs() > 1e-5 * margin {
                        assert_eq!(w > 0.0, value > -margin, "triangle {i} at {b}");
                    }
                }
                let kept: Vec<usize> = (0..areas.len()).filter(|&i| weights[i] > 0.0).collect();
                assert!(!kept.is_empty() && kept.len() < areas.len());
                let scan: f64 = weights.iter().sum();
                let mut blocks = [0.0; MAX_BLOCKS];
                let total = facing.kept_blocks(&aim, &mut blocks).unwrap();
                assert!((total - scan).abs() <= 1e-12 * scan, "{total} vs {scan}");
                // What the processor's SIMD copy (AVX-512 or AVX2, where it has them) computes
                // is what the portable body computes, to the bit.
                let mut portable = [0.0; MAX_BLOCKS];
                let portable_total = facing.kept_blocks_portable(&aim, &mut portable).unwrap();
                assert_eq!(total.to_bits(), portable_total.to_bits());
                assert_eq!(blocks.map(f64::to_bits), portable.map(f64::to_bits));
                assert_eq!(facing.kept_weight(&aim), total);
                let mut start = 0.0;
                for &i in &kept {
                    // Stretches too short to tell from the rounding of the running sums are
                    // left out.
                    if weights[i] > 1e-4 * total {
                        let middle = start + 0.5 * weights[i];
                        assert_eq!(facing.pick(&aim, &blocks, middle), Some(i));
                    }
                    start += weights[i];
                }
                // Past the end (rounding): the last kept triangle.
                let last = facing.pick(&aim, &blocks, total * (1.0 + 1e-6));
                assert_eq!(last, kept.last().copied());
            }
        }
    }

    #[test]
    fn triangles_are_drawn_by_the_solid_angle_they_fill() {
        // In a flat room, for points from 1.5 r to 21 r away: each clearly facing triangle's
        // share of the weight, against its share of the solid angle the sphere fills (the exact
        // solid angle of a flat triangle, Van Oosterom and Strackee). Drawing by area instead
        // leaves out the cosine over the squared distance.
        let (facing, areas) = facing("*2222");
        let (space, light) = sphere_light("*2222");
        let Emitter::Area { instance, .. } = &light.emitter else {
            unreachable!()
        };
        let (points, heights, triangles) = instance.bvh.mesh();
        let local = |i: u32| {
            let i = i as usize;
            facing
                .frame
                .to_local(space, space.log(DVec3::Z, points[i]), heights[i])
        };
        let mut worst: f64 = 1.0;
        let mut worst_by_area: f64 = 1.0;
        for b in points_around(&facing) {
            // Nearer, the triangles are not small against their distance.
            if (b - facing.centre).length() < 1.5 * facing.radius {
                continue;
            }
            let aim = facing.aim(b);
            let total = facing.kept_weight(&aim);
            let kept_area: f64 = (0..areas.len())
                .filter(|&i| facing.weight_of(i, &aim) > 0.0)
                .map(|i| areas[i])
                .sum();
            let solid: Vec<f64> = triangles
                .iter()
                .map(|t| {
                    let [p, q, r] = [local(t[0]) - b, local(t[1]) - b, local(t[2]) - b];
                    let (lp, lq, lr) = (p.length(), q.length(), r.length());
                    let numerator = p.dot(q.cross(r));
                    let denominator = lp * lq * lr + p.dot(q) * lr + q.dot(r) * lp + r.dot(p) * lq;
                    (2.0 * numerator.atan2(denominator)).abs()
                })
                .collect();
            let seen: f64 = (0..areas.len())
                .filter(|&i| plane_value(&facing, i, b) > 0.0)
                .map(|i| solid[i])
                .sum();
            for i in 0..areas.len() {
                let value = plane_value(&facing, i, b);
                let distance = (b - facing.centre).length();
                // Clearly facing: at least a third of the way from the silhouette to the front.
                if value > (distance - facing.radius) / 3.0 {
                    let share = facing.weight_of(i, &aim) / total;
                    let ratio = share / (solid[i] / seen);
                    worst = worst.max(ratio).max(1.0 / ratio);
                    let by_area = areas[i] / kept_area / (solid[i] / seen);
                    worst_by_area = worst_by_area.max(by_area).max(1.0 / by_area);
                }
            }
        }
        // Measured: 1.27 by weight, 5.8 by area.
        assert!(worst < 1.35, "weights off the solid angle by up to {worst}");
        assert!(
            worst_by_area > 4.0,
            "the points do not tell weights from areas"
        );
    }
}
