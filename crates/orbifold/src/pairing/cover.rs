//! The tiles of any orbifold group: every image of the fundamental polygon exactly once, by word
//! length in the generators `neighbour(i)` (ARCHITECTURE.md §6, §11).
//!
//! Breadth first from the base tile: the tile across edge i of the tile g is g·neighbour(i).
//! Two words give the same tile exactly when they give the same image of the polygon's centre O:
//! O is interior, so distinct tiles put their images of O at least 2δ apart, δ the distance from
//! O to the polygon's boundary, and in ambient coordinates at least σ = 2·S_κ(δ) apart (the chord:
//! the Euclidean distance of ambient points is at least the Minkowski one on the hyperboloid).
//! Images are deduplicated in a grid of cells of size σ/2 — but only when a rigorous bound ε on
//! the error of each computed image is below σ/16, so that the same tile's images lie within
//! σ/8 and different tiles' beyond 7σ/8, more than a cell's diagonal. Otherwise the enumeration stops with
//! [`CoverError::Precision`] instead of guessing.
//!
//! The bound follows each tile's matrix in the spectral norm: ‖P̃Ñ − PN‖ ≤ ‖P̃ − P‖·‖N‖ +
//! ‖P‖·‖Ñ − N‖ + 3γ₃‖P‖‖N‖ (the last term the rounding of the product: Higham, *Accuracy and
//! Stability of Numerical Algorithms*, §3.5), and an image of O is off by at most that times ‖O‖
//! plus its own rounding; in E² the translation column is followed apart from the linear part
//! (`Search::propagate`). ‖Ñ − N‖ ≤ e_gen·‖N‖ with e_gen the generators' measured defect: how
//! far each pairing and its partner's are from inverse, and how far the vertex cycles' angle
//! sums are from Poincaré's values (which is how far the group's relations are from holding),
//! times 16. The bound is therefore certified relative to that measured defect of the polygon,
//! not to an independent exact polygon.
//!
//! Only the last two layers are kept for deduplication: a word of length d + 1 can only equal
//! one of length d − 1, d or d + 1 (the generators are closed under inverses).

use glam::{DMat3, DVec3};
use hashbrown::HashTable;
use hashbrown::hash_table::Entry;

use super::{EdgeKind, FundamentalPolygon};
use crate::conway::OrbifoldSymbol;
use crate::cover::{Bound, Cover, CoverError, MEMORY_BUDGET};
use crate::euler::Geometry;
use crate::layout::LayoutOptions;
use crate::space::Space;

/// One tile: the group element that carries the base polygon onto it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GroupTile {
    /// The isometry as a 3×3 matrix on ambient coordinates.
    pub matrix: DMat3,
    /// Word length in the generators `neighbour(i)`: the distance from the base tile.
    pub depth: u32,
    /// Whether the isometry reverses orientation.
    pub reflected: bool,
    /// The edge of this tile across which it was reached from its parent; `None` for the base.
    pub edge: Option<u32>,
}

/// The tiles of an orbifold group.
///
/// ```
/// use orbifold::cover::Bound;
/// use orbifold::pairing::cover::GroupCover;
/// // The rotation group of the icosahedron has 60 elements.
/// let cover = GroupCover::enumerate(&"532".parse().unwrap(), Bound::All, true).unwrap();
/// assert_eq!(cover.tiles.len(), 60);
/// ```
#[derive(Clone, Debug)]
pub struct GroupCover {
    /// The number of tiles at each word length, from 0.
    pub counts_by_depth: Vec<u64>,
    /// The tiles, by depth, when requested.
    pub tiles: Vec<GroupTile>,
    /// The largest intrinsic distance from the base tile's centre to a tile's centre reached.
    pub farthest: f64,
    /// The polygon the group acts on.
    pub polygon: FundamentalPolygon,
}

/// How far beyond `--radius` plus the polygon's reach the search keeps expanding when the polygon
/// has ideal vertices (a geodesic can cross a tile deep in its cusp).
const CUSP_MARGIN: f64 = 2.0;

/// The unit roundoff of f64.
const U: f64 = f64::EPSILON / 2.0;

/// γ₃ = 3u/(1 − 3u): the relative error bound of a three-term dot product.
const GAMMA3: f64 = 3.0 * U / (1.0 - 3.0 * U);

impl GroupCover {
    /// The tiles of `symbol`'s group (default shape) within `bound`. Kaleidoscopic symbols use
    /// the combinatorial [`Cover`]; the others the certified geometric enumeration.
    pub fn enumerate(
        symbol: &OrbifoldSymbol,
        bound: Bound,
        keep_tiles: bool,
    ) -> Result<GroupCover, CoverError> {
        if symbol.is_bad() {
            let why = symbol.reason().unwrap_or_else(|| "not an orbifold".into());
            return Err(CoverError::NotAnOrbifold(why));
        }
        let polygon = FundamentalPolygon::new(symbol, &LayoutOptions::default())
            .map_err(|e| CoverError::Layout(e.to_string()))?;
        if let Some(signature) = symbol.as_kaleidoscopic() {
            let cover = Cover::enumerate(&signature, bound, keep_tiles)?;
            return Ok(GroupCover::from_cover(cover, polygon));
        }
        GroupCover::enumerate_polygon(polygon, bound, keep_tiles)
    }

    fn from_cover(cover: Cover, polygon: FundamentalPolygon) -> GroupCover {
        GroupCover {
            counts_by_depth: cover.counts_by_depth,
            tiles: cover
                .tiles
                .iter()
                .map(|t| GroupTile {
                    matrix: t.matrix,
                    depth: t.depth,
                    reflected: t.reflected,
                    edge: t.wall,
                })
                .collect(),
            farthest: cover.farthest,
            polygon,
        }
    }

    /// The certified geometric enumeration for the group of a given polygon (any construction,
    /// kaleidoscopic ones included, any shape and placement).
    pub fn enumerate_polygon(
        polygon: FundamentalPolygon,
        bound: Bound,
        keep_tiles: bool,
    ) -> Result<GroupCover, CoverError> {
        if polygon.geometry != Geometry::Spherical && matches!(bound, Bound::All) {
            return Err(CoverError::Unbounded(polygon.geometry));
        }
        let mut search = Search::new(&polygon, bound, keep_tiles);
        search.run()?;
        Ok(GroupCover {
            counts_by_depth: search.counts,
            tiles: search.kept,
            farthest: search.farthest,
            polygon,
        })
    }
}

/// ‖M‖∞: the largest row sum of absolute values.
fn norm(m: &DMat3) -> f64 {
    let r = |i: usize| m.row(i).abs().element_sum();
    r(0).max(r(1)).max(r(2))
}

/// A bound on the spectral norm ‖M‖₂ of a (computed) isometry: on the sphere √‖MᵀM‖∞ (≈ 1);
/// on the hyperboloid C + √(C² − 1) = e^d with C = |M₃₃| = cosh d, d the distance M moves the
/// origin (a Lorentz matrix is a rotation, a boost by d and a rotation); in E² the norm of the
/// linear 2×2 part, from its Gram matrix's larger eigenvalue. A relative 10⁻¹² covers the
/// computed matrix's distance from an exact isometry.
fn spectral(space: Space, m: &DMat3) -> f64 {
    let k = space.kappa();
    let value = if k > 0.0 {
        norm(&(m.transpose() * *m)).sqrt()
    } else if k < 0.0 {
        let c = m.z_axis.z.abs().max(1.0);
        c + (c * c - 1.0).sqrt()
    } else {
        let (x, y) = (m.x_axis.truncate(), m.y_axis.truncate());
        let (a, b, c) = (x.length_squared(), x.dot(y), y.length_squared());
        ((a + c) / 2.0 + (((a - c) / 2.0).powi(2) + b * b).sqrt()).sqrt()
    };
    value * (1.0 + 1e-12)
}

/// A tile in the search: its matrix, the image of the centre, and a bound on ‖M̃ − M‖₂, the
/// distance of its computed matrix from the exact group element.
#[derive(Clone, Copy)]
struct Node {
    matrix: DMat3,
    point: DVec3,
    /// The error bound (see [`Bounds`]); in E² of the linear part alone.
    error: f64,
    /// In E²: the error bound of the translation column; 0 otherwise.
    shift: f64,
}

/// A tile of a layer: its node and the edge across which it was reached (`u32::MAX` for the
/// base).
#[derive(Clone, Copy)]
struct LayerTile {
    node: Node,
    facing: u32,
}

/// The tiles of one depth and, for each, the mask ([`edge_bit`]) of the edges whose neighbour
/// is already known: its parent's, and those across which a tile of the search has found it.
///
/// The masks are apart from the tiles, which the search then only reads: a tile is read in
/// place, not copied whole (a copy is stored in pieces and read back in others, which the
/// processor cannot forward from its store buffer).
struct Layer {
    tiles: Vec<LayerTile>,
    known: Vec<u64>,
}

struct Search {
    space: Space,
    generators: Vec<DMat3>,
    /// N·O for each generator N.
    images: Vec<DVec3>,
    /// For each generator: ‖N‖₂ (of its linear part in E²), and the edge of the child that
    /// faces the parent.
    generator_norms: Vec<f64>,
    facing: Vec<u32>,
    /// For each generator, the mask of the child's edges that face its parent: `facing` and
    /// that edge's twin.
    facing_mask: Vec<u64>,
    /// For each generator, the length of its translation column (E²).
    generator_shifts: Vec<f64>,
    /// For each edge, the other edge whose generator is the same group element: the partner
    /// of an edge paired by a half-turn (N = N⁻¹, e.g. the two halves of a folded side), itself
    /// otherwise. Only the lower of two such edges is expanded, and a child reached across one
    /// faces its parent across both.
    twin: Vec<u32>,
    /// `beside[f·n + i]`: whether edges f and i meet at a vertex with three tiles round it. The
    /// child across i of a tile entered across f is then a neighbour of the parent as well, so
    /// no deeper than the tile itself: not new.
    beside: Vec<bool>,
    /// `beside` as masks ([`edge_bit`]): for each edge f, the edges i beside it.
    beside_mask: Vec<u64>,
    /// The mask of the edges that are expanded at all: every edge but a half-turn's second.
    expanded: u64,
    centre: DVec3,
    /// ‖O‖₂.
    centre_length: f64,
    /// The length of O's first two coordinates (E²).
    centre_planar: f64,
    /// The minimum ambient distance between images of the centre, σ.
    separation: f64,
    /// The generators' error e_gen.
    defect: f64,
    bound: Bound,
    /// Tiles farther than this from the centre are not expanded (radius bounds).
    reach: f64,
    keep: bool,
    counts: Vec<u64>,
    kept: Vec<GroupTile>,
    farthest: f64,
}

impl Search {
    fn new(polygon: &FundamentalPolygon, bound: Bound, keep: bool) -> Self {
        let space = polygon.space();
        let generators: Vec<DMat3> = polygon.edges.iter().map(|e| e.neighbour).collect();
        let facing: Vec<u32> = polygon
            .edges
            .iter()
            .enumerate()
            .map(|(i, e)| match e.kind {
                EdgeKind::Mirror => i as u32,
                EdgeKind::Paired { partner } => partner as u32,
            })
            .collect();
        let defect = defect(polygon, &generators);
        let twin = twins(polygon, &generators, defect);
        let facing_mask = facing
            .iter()
            .map(|&f: &u32| edge_bit(f as usize) | edge_bit(twin[f as usize] as usize))
            .collect();
        let beside = beside_in_threes(polygon);
        let n = generators.len();
        let beside_mask = (0..n)
            .map(|f| {
                (0..n)
                    .filter(|&i| beside[f * n + i])
                    .map(edge_bit)
                    .fold(0, |m, b| m | b)
            })
            .collect();
        let expanded = (0..n)
            .filter(|&i| twin[i] >= i as u32)
            .map(edge_bit)
            .fold(0, |m, b| m | b);
        let centre = polygon.centre_ambient();
        let delta = polygon.clearance();
        let diameter = polygon
            .vertices
            .iter()
            .filter(|v| !v.ideal)
            .map(|v| space.ambient_distance(centre, v.ambient))
            .fold(0.0, f64::max);
        // The tiles that a geodesic from the centre to a tile within r crosses have their
        // centres within r + diameter: expanding those reaches every tile within r.
        let cusps = polygon.vertices.iter().any(|v| v.ideal);
        let reach = match bound {
            Bound::Radius(r) if cusps => r + 2.0 * diameter + CUSP_MARGIN,
            Bound::Radius(r) => r + diameter * (1.0 + 1e-9) + 1e-9,
            _ => f64::INFINITY,
        };
        Search {
            space,
            generator_norms: generators.iter().map(|n| spectral(space, n)).collect(),
            generator_shifts: generators
                .iter()
                .map(|n| n.z_axis.truncate().length())
                .collect(),
            images: generators.iter().map(|n| *n * centre).collect(),
            defect,
            generators,
            facing,
            facing_mask,
            twin,
            beside,
            beside_mask,
            expanded,
            centre,
            centre_length: centre.length(),
            centre_planar: centre.truncate().length(),
            separation: 2.0 * space.sin(delta),
            bound,
            reach,
            keep,
            counts: Vec::new(),
            kept: Vec::new(),
            farthest: 0.0,
        }
    }

    fn distance(&self, point: DVec3) -> f64 {
        self.space.ambient_distance(self.centre, point)
    }

    /// The chord ([`chord`]) of the distance `r`, rounded up: every point within `r` of
    /// the centre has a chord at most this (all of them, for r ≥ π on the sphere).
    fn chord_within(&self, r: f64) -> f64 {
        if !r.is_finite() || self.space.kappa() > 0.0 && r >= std::f64::consts::PI {
            return f64::INFINITY;
        }
        let half = self.space.sin(r / 2.0);
        4.0 * half * half * (1.0 + 1e-12)
    }

    fn run(&mut self) -> Result<(), CoverError> {
        let base = Node {
            matrix: DMat3::IDENTITY,
            point: self.centre,
            error: 0.0,
            shift: 0.0,
        };
        let cell = self.separation / 2.0;
        if !(cell > 0.0 && cell.is_finite()) {
            return Err(CoverError::Layout(
                "the polygon's centre is not inside it".into(),
            ));
        }
        let bytes_per_tile =
            (std::mem::size_of::<LayerTile>() + std::mem::size_of::<Image>() + 16) as u128;
        // One grid holds the last two layers and the one being built; the layer before those
        // is evicted before each expansion (a word of length d + 1 equals none shorter than d − 1).
        let mut grid = Grid::new(cell);
        let image = Image {
            point: base.point,
            depth: 0,
            index: 0,
            hash: 0,
        };
        grid.insert(image, 0.0);
        let mut layer = Layer {
            tiles: vec![LayerTile {
                node: base,
                facing: u32::MAX,
            }],
            known: vec![0],
        };
        let mut previous = 1;
        let mut depth = 0usize;
        let mut total = 0u128;
        loop {
            if let Bound::Tiles(limit) = self.bound
                && total + layer.tiles.len() as u128 > limit as u128
            {
                break;
            }
            total += layer.tiles.len() as u128;
            if total.saturating_mul(bytes_per_tile) > MEMORY_BUDGET && self.keep
                || (layer.tiles.len() as u128).saturating_mul(3 * bytes_per_tile) > MEMORY_BUDGET
            {
                return Err(CoverError::TooLarge {
                    tiles: total,
                    bytes: total.saturating_mul(bytes_per_tile),
                    budget: MEMORY_BUDGET,
                });
            }
            self.record(&layer.tiles, depth);
            if layer.tiles.is_empty() || matches!(self.bound, Bound::Depth(d) if depth >= d) {
                break;
            }
            grid.evict_before(depth.saturating_sub(1) as u32);
            // Under a tile bound, a layer that cannot fit whole is not finished.
            let room = match self.bound {
                Bound::Tiles(limit) => (limit as u128).saturating_sub(total),
                _ => u128::MAX,
            };
            // Room for the next layer at the last layers' rate of growth, so that the table
            // grows once per layer rather than doubling several times on the way; never more
            // than a layer the memory budget allows.
            let growth = layer.tiles.len() as f64 / previous.max(1) as f64;
            let expected = (layer.tiles.len() as f64 * growth.max(1.0) * 1.25) as u128;
            let most = MEMORY_BUDGET / (3 * bytes_per_tile);
            let capacity = expected.min(room).min(most) as usize;
            grid.reserve(capacity);
            previous = layer.tiles.len();
            let Some(next) = self.expand(&mut layer, &mut grid, depth + 1, room, capacity)? else {
                break;
            };
            layer = next;
            depth += 1;
        }
        while self.counts.last() == Some(&0) {
            self.counts.pop();
        }
        Ok(())
    }

    /// The error bounds of the child P·N (generator `i`) of `parent`, and of its image of O.
    ///
    /// In the spectral norm: ‖P̃Ñ − PN‖ ≤ ‖P̃ − P‖‖N‖ + ‖P‖‖Ñ − N‖ + 3γ₃‖P‖‖N‖ (first order in
    /// the errors; the last term bounds the rounding of the product, Higham, *Accuracy and
    /// Stability of Numerical Algorithms*, §3.5), with ‖Ñ − N‖ ≤ e_gen‖N‖. On the sphere every
    /// norm is 1, so the bound grows linearly with the depth; in H² it grows with the product of
    /// the generators' norms. In E² the translation column is followed apart from the linear
    /// part, whose norm is 1: both bounds then grow linearly.
    ///
    /// `p_norm` is ‖P‖ and `shift_p` the length of P's translation column (used in E² only).
    fn propagate(&self, parent: &Node, p_norm: f64, shift_p: f64, i: usize) -> (f64, f64, f64) {
        let n_norm = self.generator_norms[i];
        let safety = 1.0 + 1e-10;
        if self.space.kappa() != 0.0 {
            let error = (parent.error * n_norm
                + p_norm * self.defect * n_norm
                + 3.0 * GAMMA3 * p_norm * n_norm)
                * safety;
            let point_error = (error + 3.0 * GAMMA3 * p_norm * n_norm) * self.centre_length;
            return (error, 0.0, point_error);
        }
        // E²: M = [A t; 0 1]. (PN)'s linear part is A_P A_N, its translation A_P t_N + t_P.
        let shift_n = self.generator_shifts[i];
        let error = (parent.error * n_norm
            + p_norm * self.defect * n_norm
            + 2.0 * GAMMA3 * p_norm * n_norm)
            * safety;
        let shift = (parent.error * shift_n
            + parent.shift
            + p_norm * self.defect * (1.0 + shift_n)
            + 3.0 * GAMMA3 * (p_norm * shift_n + shift_p))
            * safety;
        let o = self.centre_planar;
        let point_error = error * o + shift + 3.0 * GAMMA3 * (p_norm * (o + shift_n) + shift_p);
        (error, shift, point_error)
    }

    fn record(&mut self, layer: &[LayerTile], depth: usize) {
        let mut count = 0;
        // Distances from O grow with the chord: compare chords, and take one distance per layer
        // for the farthest tile.
        let (space, centre) = (self.space, self.centre);
        let chord = |p: DVec3| chord(space, centre, p);
        let limit = match self.bound {
            Bound::Radius(r) => self.chord_within(r),
            _ => f64::INFINITY,
        };
        let mut widest = 0.0f64;
        let mut farthest = None;
        for LayerTile {
            node, facing: edge, ..
        } in layer
        {
            let c = chord(node.point);
            if c > widest || farthest.is_none() {
                widest = c;
                farthest = Some(node.point);
            }
            if c > limit {
                continue;
            }
            count += 1;
            if self.keep {
                self.kept.push(GroupTile {
                    matrix: node.matrix,
                    depth: depth as u32,
                    reflected: node.matrix.determinant() < 0.0,
                    edge: (*edge != u32::MAX).then_some(*edge),
                });
            }
        }
        if let Some(p) = farthest {
            self.farthest = self.farthest.max(self.distance(p));
        }
        self.counts.push(count);
    }

    /// The next layer: every neighbour of the layer's tiles that is in none of the last two
    /// layers (in `grid`) nor already in the new one, which it adds to `grid`; `None` as soon as
    /// it would hold more than `room` tiles.
    ///
    /// One pass in the layer's order: each child is looked up and, when new, stored at once.
    /// (Looking the children up on all cores first and storing them in order afterwards, with
    /// the grid sharded among the cores or not, was slower on two cores: docs/cover.md.)
    ///
    /// A lookup that finds a tile of this layer or the next marks on that tile the edge that
    /// faces the parent ([`Layer::known`]), so that the same pair of tiles is not looked up
    /// again from the other side: each edge between tiles of the search is looked up once.
    fn expand(
        &self,
        layer: &mut Layer,
        grid: &mut Grid,
        depth: usize,
        room: u128,
        capacity: usize,
    ) -> Result<Option<Layer>, CoverError> {
        let Layer { tiles, known } = layer;
        let mut next = Layer {
            tiles: Vec::with_capacity(capacity),
            known: Vec::with_capacity(capacity),
        };
        let stamp = depth as u32;
        // Below σ/16 per image: one tile's images lie within σ/8, distinct tiles' images at
        // least 7σ/8 apart, more than a cell's diagonal (√3·σ/2 ≈ 0.87σ).
        let limit = self.separation / 16.0;
        let reach = self.chord_within(self.reach);
        let n = self.generators.len();
        for (index, tile) in tiles.iter().enumerate() {
            let (parent, facing) = (&tile.node, tile.facing);
            if chord(self.space, self.centre, parent.point) > reach {
                continue;
            }
            let p_norm = self.parent_norm(parent);
            let shift_p = parent.matrix.z_axis.truncate().length();
            // The edges to look across, as a mask rather than a test per edge, whose outcome
            // varies from tile to tile: not a known neighbour (the parent among them), not a
            // half-turn's second edge (it gives the first one's children again), not beside
            // the parent round a vertex of three (that tile is no deeper than this one).
            let beside = self.beside_mask.get(facing as usize).copied().unwrap_or(0);
            let mut todo = self.expanded & !known[index] & !beside;
            let mut wide = 64..n;
            loop {
                let i = if todo != 0 {
                    let i = todo.trailing_zeros() as usize;
                    todo &= todo - 1;
                    i
                } else if let Some(i) = wide.next() {
                    let besides = facing != u32::MAX && self.beside[facing as usize * n + i];
                    if self.twin[i] < i as u32 || besides {
                        continue;
                    }
                    i
                } else {
                    break;
                };
                // The image of O first (N·O is precomputed); the matrix only for a new tile.
                let point = parent.matrix * self.images[i];
                let (error, shift, point_error) = self.propagate(parent, p_norm, shift_p, i);
                if point_error.is_nan() || point_error >= limit || !point.is_finite() {
                    return Err(CoverError::Precision { depth });
                }
                let faces_parent = self.facing_mask[i];
                let image = Image {
                    point,
                    depth: stamp,
                    index: next.tiles.len() as u32,
                    hash: 0,
                };
                match grid.insert(image, point_error) {
                    None => {
                        let node = Node {
                            matrix: parent.matrix * self.generators[i],
                            point,
                            error,
                            shift,
                        };
                        next.tiles.push(LayerTile {
                            node,
                            facing: self.facing[i],
                        });
                        next.known.push(faces_parent);
                        if next.tiles.len() as u128 > room {
                            return Ok(None);
                        }
                    }
                    Some(found) if found.depth == stamp => {
                        next.known[found.index as usize] |= faces_parent;
                    }
                    Some(found) if found.depth + 1 == stamp => {
                        known[found.index as usize] |= faces_parent;
                    }
                    Some(_) => {}
                }
            }
        }
        Ok(Some(next))
    }

    /// A bound on ‖P‖₂ for the computed matrix of a tile: on the sphere and in E² (its linear
    /// part) 1 plus its error bound, as the exact matrix is orthogonal; on the hyperboloid from
    /// the matrix itself ([`spectral`]).
    fn parent_norm(&self, parent: &Node) -> f64 {
        if self.space.kappa() < 0.0 {
            spectral(self.space, &parent.matrix)
        } else {
            (1.0 + parent.error) * (1.0 + 1e-12)
        }
    }
}

/// The chord ⟨p − O, p − O⟩ of an ambient point p: 4·S_κ(d/2)², d its distance from the centre
/// O, which grows with d (up to π on the sphere). Comparing chords saves an acosh or acos per
/// tile.
fn chord(space: Space, centre: DVec3, p: DVec3) -> f64 {
    let d = p - centre;
    space.point_dot(d, d)
}

/// The bit of edge `i` in a tile's mask of known neighbours; none beyond 64 edges, whose
/// neighbours are then always looked up.
fn edge_bit(i: usize) -> u64 {
    if i < 64 { 1 << i } else { 0 }
}

/// For each edge, the edge whose generator is the same group element ([`Search::twin`]).
///
/// A pairing N with N = N⁻¹ is an involution: its partner's generator N⁻¹ is N itself. The test
/// ‖N·N − I‖ within the generators' measured defect cannot mistake another pairing for one: an
/// orientation-preserving isometry other than a half-turn or the identity moves the polygon's
/// centre, or turns about it, by a fixed amount far above that bound.
fn twins(polygon: &FundamentalPolygon, generators: &[DMat3], defect: f64) -> Vec<u32> {
    polygon
        .edges
        .iter()
        .enumerate()
        .map(|(i, e)| match e.kind {
            EdgeKind::Paired { partner } if partner != i => {
                let n = generators[i];
                let square = n * n;
                let tolerance = defect * norm(&n) * norm(&n);
                if norm(&(square - DMat3::IDENTITY)) <= tolerance {
                    partner as u32
                } else {
                    i as u32
                }
            }
            _ => i as u32,
        })
        .collect()
}

/// For each pair of edges (f, i), whether they meet at a vertex whose cycle has three tiles round
/// it in the tiling ([`Search::beside`]): k tiles per corner of a closed cycle of order k, 2k per
/// corner of a cycle on a mirror.
fn beside_in_threes(polygon: &FundamentalPolygon) -> Vec<bool> {
    let n = polygon.edges.len();
    let mut beside = vec![false; n * n];
    for cycle in &polygon.cycles {
        let Some(k) = cycle.order.as_integer() else {
            continue;
        };
        let per_corner = if cycle.closed { k } else { 2 * k };
        if cycle.kind == super::CycleKind::Ideal || per_corner * cycle.vertices.len() as u64 != 3 {
            continue;
        }
        for &v in &cycle.vertices {
            let at_v = |&j: &usize| {
                let e = &polygon.edges[j];
                e.from == Some(v) || e.to == Some(v)
            };
            let edges: Vec<usize> = (0..n).filter(at_v).collect();
            for &f in &edges {
                for &i in edges.iter().filter(|&&i| i != f) {
                    beside[f * n + i] = true;
                }
            }
        }
    }
    beside
}

/// The generators' measured defect: pairings against their partners' inverses, mirrors against
/// involutions, and the vertex cycles' angle sums against Poincaré's values (an angle error θ
/// makes a cycle's relation miss the identity by a rotation of θ per turn, k turns for order k).
fn defect(polygon: &FundamentalPolygon, generators: &[DMat3]) -> f64 {
    let mut worst: f64 = 0.0;
    for (i, e) in polygon.edges.iter().enumerate() {
        let partner = match e.kind {
            EdgeKind::Mirror => i,
            EdgeKind::Paired { partner } => partner,
        };
        let product = generators[i] * generators[partner];
        let off = norm(&(product - DMat3::IDENTITY));
        let scale = norm(&generators[i]) * norm(&generators[partner]);
        worst = worst.max(off / scale.max(1.0));
    }
    for c in &polygon.cycles {
        let k = c.order.to_f64();
        let turns = if k.is_finite() { k } else { 1.0 };
        worst = worst.max((c.angle_sum - c.expected_angle_sum()).abs() * turns);
    }
    16.0 * worst.max(64.0 * U)
}

/// The integer nearest to v (ties to even), as an integer and as a float: the grid's cell of a
/// coordinate, so that the cells are [k − ½, k + ½]. Rounding to nearest, rather than down,
/// needs no comparison afterwards: a branch on the rounding's direction goes either way at
/// random, and the processor's mispredictions of it were a sixth of the search's time.
///
/// Adding 1.5·2⁵² rounds v to the nearest integer (the processor's rounding mode), whose two's
/// complement then sits in the sum's low mantissa bits (exact for |v| < 2⁵¹; larger values, far
/// beyond any certified image, take ⌊v + ½⌋ with a saturating conversion as `as` does).
fn nearest(v: f64) -> (i64, f64) {
    const MAGIC: f64 = 6_755_399_441_055_744.0;
    if v.abs() < (1u64 << 50) as f64 {
        let sum = v + MAGIC;
        let n = sum.to_bits() as i64 - MAGIC.to_bits() as i64;
        return (n, sum - MAGIC);
    }
    let w = v + 0.5;
    let t = w as i64;
    let t = if (t as f64) > w {
        t.saturating_sub(1)
    } else {
        t
    };
    (t, t as f64)
}

/// A cell of the grid: its integer coordinates.
#[derive(Clone, Copy, PartialEq, Eq)]
struct Cell(i64, i64, i64);

impl Cell {
    /// The table's hash of the cell: the three coordinates mixed into one word, its low bits
    /// (which pick the bucket) as well mixed as its high ones (the tag). The grid's cells are
    /// consecutive integers, often with one coordinate constant (E²).
    fn hash(self) -> u64 {
        let h = (self.0 as u64).wrapping_mul(0x9E37_79B9_7F4A_7C15)
            ^ (self.1 as u64).wrapping_mul(0xC2B2_AE3D_27D4_EB4F)
            ^ (self.2 as u64).wrapping_mul(0x1656_67B1_9E37_79F9);
        let h = (h ^ (h >> 29)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        h ^ (h >> 32)
    }
}

/// An image of the centre stored in the grid, with its tile's depth, its index in its layer,
/// and its cell's hash (so that growing the table does not locate every image again).
#[derive(Clone, Copy)]
struct Image {
    point: DVec3,
    depth: u32,
    index: u32,
    hash: u64,
}

/// Images of the centre in cells of a grid in ambient ℝ³. Cells are σ/2 wide, so their
/// diagonal (√3·σ/2) is shorter than the separation σ of distinct images: a cell holds at most
/// one image.
///
/// The table holds the images under their cells' hashes, without the cells: an image found
/// under a cell's hash is the same tile's exactly when it lies within σ/2 (images of one tile
/// lie within σ/8, of distinct tiles beyond 7σ/8), whichever cell it lies in.
struct Grid {
    /// 1 / cell: the cells are found by multiplying, not dividing.
    inverse: f64,
    /// (σ/2)²: images closer than this are the same tile's.
    same: f64,
    cells: HashTable<Image>,
    /// The hashes of the stored images, by depth and, within a depth, in the order stored (the
    /// images' `index`): how the images of a layer are found again to forget them.
    hashes: Vec<Vec<u64>>,
    /// The largest error bound of a stored image.
    error: f64,
}

impl Grid {
    fn new(cell: f64) -> Self {
        Grid {
            inverse: 1.0 / cell,
            same: cell * cell,
            cells: HashTable::new(),
            hashes: Vec::new(),
            error: 0.0,
        }
    }

    /// Room for `additional` more images.
    fn reserve(&mut self, additional: usize) {
        self.cells.reserve(additional, |image| image.hash);
    }

    /// The cell of `p` and `p`'s position in it, each coordinate in [0, 1] up to rounding.
    fn locate(&self, p: DVec3) -> (Cell, DVec3) {
        let q = p * self.inverse;
        let ((x, fx), (y, fy), (z, fz)) = (nearest(q.x), nearest(q.y), nearest(q.z));
        (Cell(x, y, z), q - DVec3::new(fx, fy, fz) + 0.5)
    }

    /// Forgets the images of tiles shallower than `depth`, each found again under its stored
    /// hash: a probe per forgotten image, rather than a sweep over every image in the table
    /// (three layers' worth, with a branch the processor cannot predict per image).
    fn evict_before(&mut self, depth: u32) {
        for d in 0..(depth as usize).min(self.hashes.len()) {
            for (index, hash) in std::mem::take(&mut self.hashes[d]).into_iter().enumerate() {
                let stamp = (d as u32, index as u32);
                let this = |image: &Image| (image.depth, image.index) == stamp;
                if let Ok(entry) = self.cells.find_entry(hash, this) {
                    entry.remove();
                }
            }
        }
    }

    /// Stores `image` (its error at most `error`) unless an image of the same tile is stored;
    /// `None` when it was new, the stored image otherwise.
    ///
    /// Two computed images in one cell are less than a cell's diagonal, √3·σ/2 < 7σ/8, apart:
    /// they are the same tile's. The neighbouring cells are searched only when the point lies
    /// within the two error bounds of its own cell's faces, and there an image must be within
    /// σ/2.
    ///
    /// Inlined: passed to a call, the image is stored in pieces and loaded whole, which the
    /// processor cannot forward from its store buffer.
    #[inline(always)]
    fn insert(&mut self, image: Image, error: f64) -> Option<Image> {
        let (key, local) = self.locate(image.point);
        // Each coordinate's cell is certain when it lies farther than the two images' error
        // bounds (in cells) from the cell's faces: the stored image of the same tile is then in
        // this very cell. Otherwise the neighbours are searched first, and the cell itself is
        // then probed once, to find it empty and fill it.
        let s = 2.0 * (error + self.error) * self.inverse;
        if (local.min_element() < s || local.max_element() > 1.0 - s)
            && let Some(found) = self.in_neighbour(image.point, key, local, s)
        {
            return Some(found);
        }
        let (p, same, hash) = (image.point, self.same, key.hash());
        let is_same = |stored: &Image| stored.point.distance_squared(p) < same;
        match self.cells.entry(hash, is_same, |stored| stored.hash) {
            Entry::Occupied(cell) => Some(*cell.get()),
            Entry::Vacant(cell) => {
                cell.insert(Image { hash, ..image });
                let depth = image.depth as usize;
                if self.hashes.len() <= depth {
                    self.hashes.resize_with(depth + 1, Vec::new);
                }
                self.hashes[depth].push(hash);
                self.error = self.error.max(error);
                None
            }
        }
    }

    /// The image within σ/2 of `p` in a neighbouring cell of `key` that `p` may belong to, given
    /// the error bounds: `s` in cells on either side of each face.
    #[cold]
    fn in_neighbour(&self, p: DVec3, Cell(x, y, z): Cell, local: DVec3, s: f64) -> Option<Image> {
        let range = |f: f64| {
            let lo = if f < s { -1 } else { 0 };
            let hi = if f > 1.0 - s { 1 } else { 0 };
            lo..=hi
        };
        let is_same = |stored: &&Image| stored.point.distance_squared(p) < self.same;
        for dx in range(local.x) {
            for dy in range(local.y) {
                for dz in range(local.z) {
                    if (dx, dy, dz) == (0, 0, 0) {
                        continue;
                    }
                    let hash = Cell(x + dx, y + dy, z + dz).hash();
                    if let Some(q) = self.cells.find(hash, |q| is_same(&q)) {
                        return Some(*q);
                    }
                }
            }
        }
        None
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::layout::Shape;

    fn polygon(s: &str) -> FundamentalPolygon {
        FundamentalPolygon::new(&s.parse().unwrap(), &LayoutOptions::default()).unwrap()
    }

    fn geometric(s: &str, bound: Bound) -> GroupCover {
        GroupCover::enumerate_polygon(polygon(s), bound, true)
            .unwrap_or_else(|e| panic!("{s}: {e}"))
    }

    /// The grid's rounding is an integer within ½ of v (the nearest, ties to even, as the C
    /// library's `rint` rounds), as a float too; beyond the range of i64 it saturates, as `as`
    /// does.
    fn assert_nearest(v: f64) {
        let (n, f) = nearest(v);
        if v.abs() < 2f64.powi(50) {
            let rounded = v.round();
            let tie = (v - v.floor()) == 0.5;
            let expected = if tie && rounded % 2.0 != 0.0 {
                rounded - v.signum()
            } else {
                rounded
            };
            assert_eq!(f, expected, "{v}");
        } else {
            assert_eq!(
                f,
                (v + 0.5).floor().clamp(i64::MIN as f64, i64::MAX as f64),
                "{v}"
            );
        }
        assert_eq!(f, n as f64, "{v}");
        if v.abs() < 1e15 {
            assert!((v - f).abs() <= 0.5, "{v}: {f}");
        }
    }

    /// At integers, halves and their neighbours in the last bit, and far beyond the rounding
    /// trick's range.
    #[test]
    fn nearest_rounds_integers_and_halves_as_the_library_does() {
        for v in [
            0.0,
            -0.0,
            1e300,
            -1e300,
            2f64.powi(50),
            -(2f64.powi(51)),
            2f64.powi(53),
        ] {
            assert_nearest(v);
        }
        for k in -1000..1000 {
            for v in [k as f64, k as f64 + 0.5] {
                for w in [v, v.next_up(), v.next_down()] {
                    assert_nearest(w);
                }
            }
        }
    }

    proptest::proptest! {
        /// And at random values of every scale and both signs.
        #[test]
        fn nearest_rounds_as_the_library_does(m in -1.0f64..1.0, e in -3i32..18) {
            assert_nearest(m * 10f64.powi(e));
        }
    }

    /// The edges paired by involutions (here half-turns), and only those, share their
    /// generator: the folds of
    /// `2223`'s three cones of order 2 and of p2's two folded sides; not `632`'s rotations nor
    /// p2's translation nor `22×`'s glide.
    #[test]
    fn half_turns_are_their_own_partners_generators() {
        for (s, pairs) in [("2223", 3), ("2222", 2), ("632", 0), ("22×", 2), ("oo", 0)] {
            let p = polygon(s);
            let generators: Vec<DMat3> = p.edges.iter().map(|e| e.neighbour).collect();
            let twin = twins(&p, &generators, defect(&p, &generators));
            let shared = (0..twin.len()).filter(|&i| twin[i] as usize > i).count();
            assert_eq!(shared, pairs, "{s}: {twin:?}");
            for (i, &t) in twin.iter().enumerate() {
                assert_eq!(twin[t as usize] as usize, i, "{s}: twins pair up");
                let square = generators[i] * generators[i];
                assert_eq!(
                    t as usize != i,
                    matches!(p.edges[i].kind, EdgeKind::Paired { partner } if partner != i)
                        && square.abs_diff_eq(DMat3::IDENTITY, 1e-9),
                    "{s}: edge {i}"
                );
            }
        }
    }

    /// Only the two edges at a vertex with three tiles round it are beside each other: `632`'s
    /// and `2223`'s cones of order 3 (vertices 2 and 7), and no vertex of `oo` (eight tiles round
    /// its one vertex) nor of `*236` (six round each corner of order 3).
    #[test]
    fn edges_beside_each_other_round_three_tiles() {
        for (s, pairs) in [
            ("632", vec![(1, 2)]),
            ("2223", vec![(6, 7)]),
            ("oo", vec![]),
            ("*236", vec![]),
        ] {
            let p = polygon(s);
            let n = p.edges.len();
            let beside = beside_in_threes(&p);
            let marked: Vec<(usize, usize)> = (0..n * n)
                .filter(|&k| beside[k])
                .map(|k| (k / n, k % n))
                .filter(|(f, i)| f < i)
                .collect();
            assert_eq!(marked, pairs, "{s}");
            for (f, i) in pairs {
                assert!(beside[i * n + f], "{s}: both ways");
            }
        }
    }

    #[test]
    fn spherical_groups_have_order_two_over_chi() {
        let mut symbols: Vec<String> = ["532", "432", "332", "3*2", "×", "*532", "*432", "*"]
            .map(String::from)
            .to_vec();
        for n in 2..=7 {
            symbols.extend([
                format!("22({n})"),
                format!("({n})({n})"),
                format!("2*({n})"),
                format!("({n})*"),
                format!("({n})×"),
                format!("*22({n})"),
            ]);
        }
        for s in symbols {
            let symbol: OrbifoldSymbol = s.parse().unwrap();
            let order = symbol.group_order().unwrap() as usize;
            let cover = geometric(&s, Bound::All);
            assert_eq!(cover.tiles.len(), order, "{s}");
            let via = GroupCover::enumerate(&symbol, Bound::All, false).unwrap();
            assert_eq!(
                via.counts_by_depth.iter().sum::<u64>() as usize,
                order,
                "{s}"
            );
        }
    }

    #[test]
    fn the_geometric_search_agrees_with_the_combinatorial_cover() {
        for (s, depth) in [
            ("*2222222", 5),
            ("*237", 18),
            ("*2323", 7),
            ("*442", 12),
            ("*∞∞∞", 7),
        ] {
            let ours = geometric(s, Bound::Depth(depth));
            let theirs = Cover::enumerate(&s.parse().unwrap(), Bound::Depth(depth), false).unwrap();
            assert_eq!(ours.counts_by_depth, theirs.counts_by_depth, "{s}");
        }
    }

    /// Every point of a disc lies in exactly one tile (in at least one closed tile, in at most
    /// one open one), and no two tiles are the same.
    fn check_covers_disc(p: FundamentalPolygon, disc: f64) {
        let space = p.space();
        let name = p.symbol.to_string();
        let reach = p
            .vertices
            .iter()
            .map(|v| space.ambient_distance(p.centre_ambient(), v.ambient))
            .fold(0.0, f64::max);
        let offset = space.ambient_distance(p.centre_ambient(), DVec3::Z);
        let cover =
            GroupCover::enumerate_polygon(p.clone(), Bound::Radius(disc + reach + offset), true)
                .unwrap_or_else(|e| panic!("{name}: {e}"));
        let inverses: Vec<DMat3> = cover
            .tiles
            .iter()
            .map(|t| {
                crate::isometry::Isometry::from_matrix(space, t.matrix)
                    .inverse()
                    .matrix()
            })
            .collect();
        let o = p.centre_ambient();
        for (i, a) in cover.tiles.iter().enumerate() {
            for b in &cover.tiles[..i] {
                let d = space.ambient_distance(a.matrix * o, b.matrix * o);
                assert!(d > p.clearance(), "{name}: two tiles at distance {d}");
            }
        }
        let mut seed = 0x9e3779b97f4a7c15u64;
        let mut random = || {
            seed ^= seed << 13;
            seed ^= seed >> 7;
            seed ^= seed << 17;
            (seed >> 11) as f64 / (1u64 << 53) as f64
        };
        for _ in 0..300 {
            let (r, t) = (disc * random().sqrt(), std::f64::consts::TAU * random());
            let x = crate::isometry::Isometry::translation_by(
                space,
                r,
                num_complex::Complex64::from_polar(1.0, t),
            )
            .apply_ambient(DVec3::Z);
            let closed = inverses
                .iter()
                .filter(|m| p.contains_ambient(**m * x, 1e-9))
                .count();
            let open = inverses
                .iter()
                .filter(|m| p.contains_ambient(**m * x, -1e-9))
                .count();
            assert!(
                closed >= 1 && open <= 1,
                "{name}: {closed} closed, {open} open"
            );
        }
    }

    #[test]
    fn random_points_lie_in_exactly_one_tile() {
        for s in [
            "632", "2222", "22×", "××", "o", "*×", "2*22", "4*2", "22*", "**",
        ] {
            check_covers_disc(polygon(s), 3.0);
        }
        for s in ["532", "22(5)", "3*2", "(5)×", "2*(4)"] {
            check_covers_disc(polygon(s), 3.1);
        }
        for s in [
            "2223", "237", "4*3", "oo", "××", "*2×", "3333", "2*34", "***", "3*33", "o*2", "*2*3",
            "2*2222", "23*2", "2*2×",
        ] {
            let p = polygon(s);
            if p.geometry == Geometry::Hyperbolic {
                check_covers_disc(p, 2.0);
            }
        }
        // An ideal corner on a boundary with corners (the balanced star): a smaller disc, as the
        // cusp's tiles soon lie too far out for a certified enumeration.
        check_covers_disc(polygon("∞*∞"), 1.0);
    }

    #[test]
    fn shapes_and_placements_cover_too() {
        let p = FundamentalPolygon::new(
            &"22×".parse().unwrap(),
            &LayoutOptions {
                shape: Shape::Parameters(vec![1.3]),
                at: num_complex::Complex64::new(0.2, 0.1),
                angle: 0.4,
            },
        )
        .unwrap();
        check_covers_disc(p, 3.0);
    }

    /// The rotation group `pqr` in the doubled shape of `*pqr`: each of its tiles is the union
    /// of two tiles of the reflection group, g(T) and g·r₀(T).
    #[test]
    fn rotation_subgroup_tiles_are_pairs_of_reflection_tiles() {
        for (s, radius) in [("237", 3.5), ("333", 5.0), ("245", 3.5), ("532", 4.0)] {
            let rotations = geometric(s, Bound::Radius(radius));
            let kal = polygon(&format!("*{s}"));
            let reflections = GroupCover::enumerate(
                &format!("*{s}").parse().unwrap(),
                Bound::Radius(radius + 4.0),
                true,
            )
            .unwrap();
            let r0 = kal.edges[0].neighbour;
            let found = |m: DMat3| {
                let scale = norm(&m);
                reflections
                    .tiles
                    .iter()
                    .any(|t| t.matrix.abs_diff_eq(m, 1e-9 * scale))
            };
            for t in &rotations.tiles {
                assert!(!t.reflected, "{s}");
                assert!(
                    found(t.matrix) && found(t.matrix * r0),
                    "{s}: a tile is not two reflection tiles"
                );
            }
            let within = |c: &GroupCover, r: f64| {
                let o = c.polygon.centre_ambient();
                let space = c.polygon.space();
                c.tiles
                    .iter()
                    .filter(|t| space.ambient_distance(o, t.matrix * o) <= r)
                    .count()
            };
            if s != "532" {
                // Reflection tiles: the same elements g and g·r₀; counting within a radius by the
                // triangle's centre gives about twice as many.
                let (a, b) = (
                    within(&rotations, radius - 1.0),
                    within(&reflections, radius - 1.0),
                );
                assert!(
                    b as f64 > 1.6 * a as f64 && (b as f64) < 2.4 * a as f64,
                    "{s}: {a} vs {b}"
                );
            } else {
                assert_eq!(rotations.tiles.len() * 2, reflections.tiles.len(), "{s}");
            }
        }
    }

    #[test]
    fn imprecise_generators_are_refused_rather_than_guessed() {
        // A pairing perturbed by 10⁻⁴ no longer inverts its partner's: the measured defect makes
        // the error bound exceed the separation of tiles within a few layers.
        let mut p = polygon("2223");
        p.edges[0].neighbour *= 1.0 + 1e-4;
        match GroupCover::enumerate_polygon(p, Bound::Depth(60), false) {
            Err(CoverError::Precision { depth }) => assert!(depth < 60),
            other => panic!("{:?}", other.map(|c| c.counts_by_depth)),
        }
        assert!(matches!(
            GroupCover::enumerate(&"2223".parse().unwrap(), Bound::All, false),
            Err(CoverError::Unbounded(_))
        ));
    }

    #[test]
    fn first_layer_is_the_distinct_generators() {
        for s in ["632", "22×", "oo", "2*22"] {
            let c = geometric(s, Bound::Depth(1));
            let p = polygon(s);
            let mut distinct: Vec<DMat3> = Vec::new();
            for e in &p.edges {
                if !distinct.iter().any(|m| m.abs_diff_eq(e.neighbour, 1e-9)) {
                    distinct.push(e.neighbour);
                }
            }
            assert_eq!(c.counts_by_depth, vec![1, distinct.len() as u64], "{s}");
            assert!(
                c.tiles[1..]
                    .iter()
                    .all(|t| t.depth == 1 && t.edge.is_some())
            );
        }
    }

    /// The genus-two surface group ⟨a, b, c, d | [a, b][c, d]⟩ (the star of `oo`: a
    /// commutator of pairings per handle) has one relator, of length 8, and it is a small
    /// cancellation group, so two reduced words of length at most 4 are equal only when
    /// together they spell the relator: below length 4 all 8·7ⁿ⁻¹ reduced words are distinct,
    /// and at length 4 the relator's 16 cyclic words (its 8 rotations and theirs inverted) make 8
    /// pairs of equal words, leaving 8·7³ − 8 = 2736. The search, which knows nothing of words,
    /// finds these counts from the images of the centre alone.
    #[test]
    fn the_genus_two_group_grows_as_its_one_relator_says() {
        let c = geometric("oo", Bound::Depth(4));
        let reduced = |n: u32| 8 * 7u64.pow(n - 1);
        let expected = vec![1, reduced(1), reduced(2), reduced(3), reduced(4) - 8];
        assert_eq!(c.counts_by_depth, expected);
        assert_eq!(expected[4], 2736);
    }
}
