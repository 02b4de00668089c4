//! The universal cover: every tile of the reflection group's tiling exactly once (ARCHITECTURE.md §6).
//!
//! Tiles are group elements g, reached breadth-first by word length; the neighbour of g across its
//! wall t is g·r_t. Deduplication is combinatorial, with no coordinates compared. For each tile
//! and each corner j (walls j−1, j, order k) we keep hⱼ, the length of the tile's part in the
//! corner's dihedral group ⟨r_{j−1}, r_j⟩ (its distance, in the cycle of 2k tiles around that
//! vertex, from the cycle's tile nearest the base), and which wall that part ends with. Wall s is
//! a descent (crossing it goes back towards the base) exactly when some corner of s has hⱼ = k or
//! ends with s. A tile has one descent, or two at a corner whose cycle it tops (hⱼ = k), or — only
//! in finite groups — three. It is generated only from the neighbour across its smallest descent,
//! so each tile is produced exactly once.
//!
//! Crossing wall t (an ascent) raises h by one at the two corners on t. At the corner beyond a
//! corner that becomes full, h becomes 1 (the tile has one more descent there); every other corner
//! starts again at 0, because a tile's descents generate a finite group, and two walls that do not
//! meet generate an infinite one.

use glam::{DMat3, DVec3};
use rayon::prelude::*;

use crate::euler::Geometry;
use crate::growth::growth_series;
use crate::layout::Layout;
use crate::signature::{Kind, Signature};
use crate::space::Space;

/// How far to enumerate.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Bound {
    /// Every tile of word length at most this.
    Depth(usize),
    /// At most this many tiles, whole depths first (a depth that would exceed it is left out).
    Tiles(usize),
    /// Every tile whose centre is within this intrinsic distance of the base tile's centre.
    Radius(f64),
    /// Everything: only for finite (spherical) groups.
    All,
}

/// One tile: the group element that carries the base polygon onto it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Tile {
    /// The isometry as a 3×3 matrix on ambient coordinates.
    pub matrix: DMat3,
    /// Word length: the distance from the base tile in the dual graph.
    pub depth: u32,
    /// Whether the isometry reverses orientation (odd word length).
    pub reflected: bool,
    /// The wall (of this tile) across which it was reached from its parent; `None` for the base.
    pub wall: Option<u32>,
}

/// Why a cover cannot be enumerated.
#[derive(Clone, Debug, PartialEq)]
pub enum CoverError {
    /// Not a good orbifold: no reflection group.
    NotAnOrbifold(String),
    /// An infinite cover requested without a bound.
    Unbounded(Geometry),
    /// The request would need more memory than allowed.
    TooLarge {
        /// Tiles it would produce (or hold at once).
        tiles: u128,
        /// Bytes that would take.
        bytes: u128,
        /// The budget in bytes.
        budget: u128,
    },
    /// The polygon cannot be laid out.
    Layout(String),
    /// Tiles so far from the base that double precision can no longer certify a triangle group's
    /// descent test.
    Precision {
        /// The first depth where a test could not be certified.
        depth: usize,
    },
}

impl std::fmt::Display for CoverError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            CoverError::NotAnOrbifold(why) => write!(f, "no universal cover: {why}"),
            CoverError::Unbounded(g) => write!(
                f,
                "the {g} cover is infinite; bound it with a depth, a radius or a tile budget"
            ),
            CoverError::TooLarge {
                tiles,
                bytes,
                budget,
            } => write!(
                f,
                "refused before starting: {tiles} tiles would need about {} MiB, over the budget of {} MiB",
                bytes >> 20,
                budget >> 20
            ),
            CoverError::Layout(why) => write!(f, "cannot lay out the polygon: {why}"),
            CoverError::Precision { depth } => write!(
                f,
                "tiles at depth {depth} lie too far from the base for double precision to certify them \
                 (which way their walls face, or which of them coincide); ask for a smaller depth or radius"
            ),
        }
    }
}

impl std::error::Error for CoverError {}

/// The combinatorial structure of the group: corners as pairs of walls with their orders.
#[derive(Clone, Debug)]
struct Corners {
    walls: usize,
    /// For corner j: (first wall, second wall, order k; u32::MAX for ∞).
    corners: Vec<(usize, usize, u32)>,
    /// For wall t: the corner before it (walls t−1, t) and after it (walls t, t+1).
    around: Vec<(usize, usize)>,
}

impl Corners {
    fn new(signature: &Signature) -> Self {
        let orders: Vec<u32> = signature
            .corners()
            .iter()
            .map(|k| {
                k.as_integer()
                    .map_or(u32::MAX, |k| u32::try_from(k).unwrap_or(u32::MAX))
            })
            .collect();
        let n = orders.len();
        if n == 0 {
            // `*`: one wall, and its reflection is an involution (a "corner" of order 1).
            return Corners {
                walls: 1,
                corners: vec![(0, 0, 1)],
                around: vec![(0, 0)],
            };
        }
        if n == 2 {
            // A lune: both corners are the same dihedral group ⟨r₀, r₁⟩.
            return Corners {
                walls: 2,
                corners: vec![(0, 1, orders[0])],
                around: vec![(0, 0), (0, 0)],
            };
        }
        // Corner j sits between wall j−1 and wall j.
        let corners = (0..n).map(|j| ((j + n - 1) % n, j, orders[j])).collect();
        let around = (0..n).map(|t| (t, (t + 1) % n)).collect();
        Corners {
            walls: n,
            corners,
            around,
        }
    }

    /// The descents of a tile as a bit mask over walls. A corner whose part has the full length k
    /// makes both its walls descents; a shorter non-empty part makes its last wall one.
    fn descent_mask(&self, state: &[u32]) -> u64 {
        let mut mask = 0u64;
        for (&word, &(first, second, k)) in state.iter().zip(&self.corners) {
            let h = word & !ENDS_SECOND;
            if h == k {
                mask |= (1 << first) | (1 << second);
            } else if h > 0 {
                mask |= 1
                    << if word & ENDS_SECOND != 0 {
                        second
                    } else {
                        first
                    };
            }
        }
        mask
    }

    /// The corner state of the child across ascent `t`, written to `child`; false when the
    /// child's smallest descent is not `t` (another parent generates it).
    fn child_state(&self, parent: &[u32], t: usize, child: &mut [u32]) -> bool {
        child.fill(0);
        let (before, after) = self.around[t];
        let mut full = [false; 2];
        for (side, j) in [before, after].into_iter().enumerate() {
            let (first, second, k) = self.corners[j];
            let h = ((parent[j] & !ENDS_SECOND) + 1).min(k);
            child[j] = h | if t == second { ENDS_SECOND } else { 0 };
            if h == k {
                // The child tops this corner's cycle: the corner's other wall is a descent too.
                let other = if t == first { second } else { first };
                if other < t {
                    return false;
                }
                full[side] = true;
            }
        }
        let n = self.walls;
        if n >= 3 {
            // Beyond a full corner (t, s), the next corner along s has a part of length 1 ending in s.
            for (side, (j, beyond)) in [(before, (before + n - 1) % n), (after, (after + 1) % n)]
                .into_iter()
                .enumerate()
            {
                if full[side] {
                    let (first, second, _) = self.corners[j];
                    let s = if t == first { second } else { first };
                    child[beyond] = 1 | if self.corners[beyond].1 == s {
                        ENDS_SECOND
                    } else {
                        0
                    };
                }
            }
        }
        true
    }
}

/// The universal cover of a good kaleidoscopic orbifold, enumerated breadth-first.
///
/// ```
/// use orbifold::cover::{Bound, Cover};
/// let cover = Cover::enumerate(&"*2222222".parse().unwrap(), Bound::Depth(3), true).unwrap();
/// assert_eq!(cover.counts_by_depth, vec![1, 7, 35, 168]);
/// ```
#[derive(Clone, Debug)]
pub struct Cover {
    /// The number of tiles at each word length, from 0.
    pub counts_by_depth: Vec<u64>,
    /// The tiles, by depth, when requested.
    pub tiles: Vec<Tile>,
    /// The largest intrinsic distance from the base tile's centre to a tile's centre reached.
    pub farthest: f64,
    /// The polygon the group acts on.
    pub layout: Layout,
}

/// How far beyond `--radius` the search keeps expanding, so that tiles inside are reached even
/// when the shortest gallery to them passes outside.
const RADIUS_MARGIN: f64 = 4.0;

/// The memory budget for one enumeration.
pub const MEMORY_BUDGET: u128 = 2 << 30;

impl Cover {
    /// Enumerates the tiles within `bound`; with `keep_tiles` false only the counts are kept
    /// (the frontier is all that is held in memory).
    pub fn enumerate(
        signature: &Signature,
        bound: Bound,
        keep_tiles: bool,
    ) -> Result<Cover, CoverError> {
        if signature.kind() != Kind::Orbifold {
            let why = signature
                .reason()
                .unwrap_or_else(|| "not an orbifold".into());
            return Err(CoverError::NotAnOrbifold(why));
        }
        let geometry = signature.geometry();
        if geometry != Geometry::Spherical && matches!(bound, Bound::All) {
            return Err(CoverError::Unbounded(geometry));
        }
        if let Bound::Depth(depth) = bound {
            check_budget(signature, depth, keep_tiles)?;
        }
        let layout = Layout::new(signature, &Default::default())
            .map_err(|e| CoverError::Layout(e.to_string()))?;
        Cover::enumerate_layout(layout, bound, keep_tiles)
    }

    /// Like [`Cover::enumerate`], for the group generated by the walls of a given polygon of an
    /// orbifold (any shape parameters and placement).
    pub fn enumerate_layout(
        layout: Layout,
        bound: Bound,
        keep_tiles: bool,
    ) -> Result<Cover, CoverError> {
        let Some(signature) = layout.signature() else {
            return Err(CoverError::Layout(format!(
                "{} has side pairings, not only mirrors; its cover is pairing::cover::GroupCover",
                layout.symbol
            )));
        };
        let signature = &signature;
        if signature.kind() != Kind::Orbifold {
            let why = signature
                .reason()
                .unwrap_or_else(|| "not an orbifold".into());
            return Err(CoverError::NotAnOrbifold(why));
        }
        let geometry = signature.geometry();
        if geometry != Geometry::Spherical && matches!(bound, Bound::All) {
            return Err(CoverError::Unbounded(geometry));
        }
        if let Bound::Depth(depth) = bound {
            check_budget(signature, depth, keep_tiles)?;
        }
        let space = Space::new(geometry);
        let walls: Vec<DVec3> = layout.edges.iter().map(|e| e.wall).collect();
        let corners = Corners::new(signature);
        let mut search = Search::new(&corners, walls, space, bound, keep_tiles);
        search.run();
        if let Some(depth) = search.uncertain_at {
            return Err(CoverError::Precision { depth });
        }
        Ok(Cover {
            counts_by_depth: search.counts,
            tiles: search.kept,
            farthest: search.farthest,
            layout,
        })
    }
}

fn check_budget(signature: &Signature, depth: usize, keep_tiles: bool) -> Result<(), CoverError> {
    let Some(counts) = growth_series(signature, depth) else {
        return Ok(());
    };
    let bytes_per_tile =
        std::mem::size_of::<Tile>() as u128 + 8 * signature.corner_count() as u128 + 8;
    let tiles: u128 = if keep_tiles {
        counts.iter().sum()
    } else {
        counts.windows(2).map(|w| w[0] + w[1]).max().unwrap_or(1)
    };
    let bytes = tiles.saturating_mul(bytes_per_tile);
    if bytes > MEMORY_BUDGET {
        return Err(CoverError::TooLarge {
            tiles,
            bytes,
            budget: MEMORY_BUDGET,
        });
    }
    Ok(())
}

/// The reflection in a wall: p ↦ p − 2(ν·p) n with n = (ν₁, ν₂, κν₃), so that ν·n = 1.
pub fn reflection(space: Space, nu: DVec3) -> DMat3 {
    let n = DVec3::new(nu.x, nu.y, space.kappa() * nu.z);
    DMat3::IDENTITY - 2.0 * DMat3::from_cols(n * nu.x, n * nu.y, n * nu.z)
}

/// A run of tiles of one layer, stored flat.
#[derive(Default)]
struct Part {
    matrices: Vec<DMat3>,
    /// Corner states, one word per corner per tile: the part's length hⱼ in the low bits, and
    /// [`ENDS_SECOND`] when the part ends with the corner's second wall.
    state: Vec<u32>,
    walls: Vec<u32>,
}

/// The flag of a corner state whose dihedral part ends with the corner's second wall.
const ENDS_SECOND: u32 = 1 << 31;

impl Part {
    fn len(&self) -> usize {
        self.matrices.len()
    }

    fn with_capacity(tiles: usize, corners: usize) -> Self {
        Part {
            matrices: Vec::with_capacity(tiles),
            state: Vec::with_capacity(tiles * corners),
            walls: Vec::with_capacity(tiles),
        }
    }
}

/// One layer of the breadth-first search: runs of tiles, as the parallel workers produced them
/// (never concatenated, which would copy every tile once more).
#[derive(Default)]
struct Layer {
    parts: Vec<Part>,
}

impl Layer {
    fn len(&self) -> usize {
        self.parts.iter().map(Part::len).sum()
    }

    fn matrices(&self) -> impl Iterator<Item = &DMat3> {
        self.parts.iter().flat_map(|p| p.matrices.iter())
    }
}

struct Search<'a> {
    corners: &'a Corners,
    reflections: Vec<DMat3>,
    /// The base walls as linear forms, for the geometric descent test of triangle groups.
    walls: Vec<DVec3>,
    /// Set when a geometric descent test could not be certified.
    uncertain_at: Option<usize>,
    farthest: f64,
    space: Space,
    bound: Bound,
    keep: bool,
    counts: Vec<u64>,
    kept: Vec<Tile>,
}

impl<'a> Search<'a> {
    fn new(
        corners: &'a Corners,
        walls: Vec<DVec3>,
        space: Space,
        bound: Bound,
        keep: bool,
    ) -> Self {
        let reflections = walls.iter().map(|&w| reflection(space, w)).collect();
        Search {
            corners,
            reflections,
            walls,
            uncertain_at: None,
            farthest: 0.0,
            space,
            bound,
            keep,
            counts: Vec::new(),
            kept: Vec::new(),
        }
    }

    /// Triangle groups use the geometric descent test: in a triangle, the corner opposite a
    /// crossed wall can sit anywhere in its cycle, which the corner counters cannot follow.
    fn geometric(&self) -> bool {
        self.corners.walls == 3
    }

    /// Wall s of the tile with matrix `m` is a descent iff the base centre lies on its far side:
    /// with q = m⁻¹(O), the sign of ν_s·q. Every wall of the tiling is at least the inradius from
    /// the base centre, so |ν_s·q| ≥ S_κ(r); the test is trusted only when that value is far above
    /// the rounding error of q (which grows with the tile's distance), else `None`.
    fn geometric_descents(&self, m: &DMat3, depth: usize) -> Option<[bool; 3]> {
        let k = self.space.kappa();
        let q = if k == 0.0 {
            m.inverse().z_axis
        } else {
            let row = m.row(2);
            DVec3::new(k * row.x, k * row.y, row.z)
        };
        let mut out = [false; 3];
        for (s, nu) in self.walls.iter().enumerate() {
            let value = nu.dot(q);
            let error = 64.0
                * f64::EPSILON
                * (depth as f64 + 1.0)
                * nu.abs().max_element()
                * q.abs().max_element()
                * 3.0;
            if value.abs() <= error {
                return None;
            }
            out[s] = value < 0.0;
        }
        Some(out)
    }

    fn next_layer_geometric(&mut self, layer: &Layer, depth: usize) -> Layer {
        let mut next = Part::default();
        for &m in layer.matrices() {
            if let Bound::Radius(r) = self.bound
                && !self.within_radius_margin(&m, r)
            {
                continue;
            }
            let Some(descents) = self.geometric_descents(&m, depth) else {
                self.uncertain_at.get_or_insert(depth);
                continue;
            };
            for (t, &is_descent) in descents.iter().enumerate() {
                if is_descent {
                    continue;
                }
                let child = m * self.reflections[t];
                let Some(child_descents) = self.geometric_descents(&child, depth + 1) else {
                    self.uncertain_at.get_or_insert(depth + 1);
                    continue;
                };
                // Generated only from the neighbour across the child's smallest descent.
                if child_descents.iter().position(|&d| d) != Some(t) {
                    continue;
                }
                next.matrices.push(child);
                next.walls.push(t as u32);
            }
        }
        Layer { parts: vec![next] }
    }

    /// The intrinsic distance from the base centre (the origin) to the centre of the tile `m`.
    fn centre_distance(&self, m: &DMat3) -> f64 {
        let centre = m.z_axis;
        match self.space.kappa() {
            k if k < 0.0 => centre.z.max(1.0).acosh(),
            k if k > 0.0 => centre.z.clamp(-1.0, 1.0).acos(),
            _ => centre.x.hypot(centre.y),
        }
    }

    fn within_radius(&self, m: &DMat3) -> bool {
        match self.bound {
            Bound::Radius(r) => self.centre_distance(m) <= r,
            _ => true,
        }
    }

    fn run(&mut self) {
        let c = self.corners.corners.len();
        let base = Part {
            matrices: vec![DMat3::IDENTITY],
            state: vec![0; c],
            walls: vec![u32::MAX],
        };
        let mut layer = Layer { parts: vec![base] };
        let mut depth = 0usize;
        loop {
            if let Bound::Tiles(limit) = self.bound
                && self.total() + layer.len() as u64 > limit as u64
            {
                break;
            }
            self.record(&layer, depth);
            if layer.len() == 0 || matches!(self.bound, Bound::Depth(d) if depth >= d) {
                break;
            }
            layer = if self.geometric() {
                self.next_layer_geometric(&layer, depth)
            } else {
                self.next_layer(&layer)
            };
            depth += 1;
            if layer.len() == 0 {
                break;
            }
        }
        while self.counts.last() == Some(&0) {
            self.counts.pop();
        }
    }

    fn total(&self) -> u64 {
        self.counts.iter().sum()
    }

    fn record(&mut self, layer: &Layer, depth: usize) {
        // The farthest tile is in the last layer or near it; measuring the last two layers
        // is enough, but every layer is cheap next to building it.
        let farthest = layer
            .matrices()
            .map(|m| self.centre_distance(m))
            .fold(0.0, f64::max);
        self.farthest = self.farthest.max(farthest);
        let radius = matches!(self.bound, Bound::Radius(_));
        if !radius && !self.keep {
            self.counts.push(layer.len() as u64);
            return;
        }
        let before = self.kept.len();
        let mut count = 0u64;
        for part in &layer.parts {
            for i in 0..part.len() {
                if radius && !self.within_radius(&part.matrices[i]) {
                    continue;
                }
                count += 1;
                if self.keep {
                    self.kept.push(Tile {
                        matrix: part.matrices[i],
                        depth: depth as u32,
                        reflected: depth % 2 == 1,
                        wall: (part.walls[i] != u32::MAX).then_some(part.walls[i]),
                    });
                }
            }
        }
        debug_assert!(!self.keep || self.kept.len() - before == count as usize);
        self.counts.push(count);
    }

    /// The next layer by the corner counters, in parallel over runs of the current layer.
    fn next_layer(&self, layer: &Layer) -> Layer {
        const RUN: usize = 4096;
        let runs: Vec<(&Part, std::ops::Range<usize>)> = layer
            .parts
            .iter()
            .flat_map(|part| {
                (0..part.len().div_ceil(RUN))
                    .map(move |r| (part, r * RUN..((r + 1) * RUN).min(part.len())))
            })
            .collect();
        let parts = runs
            .into_par_iter()
            .map(|(part, range)| self.expand(part, range))
            .collect();
        Layer { parts }
    }

    /// The children of the tiles `range` of `part`.
    fn expand(&self, part: &Part, range: std::ops::Range<usize>) -> Part {
        let c = self.corners.corners.len();
        let mut next = Part::with_capacity(range.len() * (self.corners.walls - 1).max(1), c);
        let mut child = vec![0u32; c];
        for i in range {
            let m = part.matrices[i];
            if let Bound::Radius(r) = self.bound
                && !self.within_radius_margin(&m, r)
            {
                continue;
            }
            let parent = &part.state[i * c..(i + 1) * c];
            let descents = self.corners.descent_mask(parent);
            for t in 0..self.corners.walls {
                if descents & (1 << t) != 0 || !self.corners.child_state(parent, t, &mut child) {
                    continue;
                }
                next.matrices.push(m * self.reflections[t]);
                next.state.extend_from_slice(&child);
                next.walls.push(t as u32);
            }
        }
        next
    }

    fn within_radius_margin(&self, m: &DMat3, r: f64) -> bool {
        self.centre_distance(m) <= r + RADIUS_MARGIN
    }
}
