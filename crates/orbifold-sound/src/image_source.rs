//! The image sources of a room: the tiles g·P of its universal cover (ARCHITECTURE.md §6), in
//! which the source's mirror images g·s lie.
//!
//! Sound reflects off every wall — mirror or not, only the absorption differs — so every group
//! element gives an image, as in the image-source method of a rectangular room (Allen &
//! Berkley, "Image method for efficiently simulating small-room acoustics", JASA 65, 1979) and of
//! any room bounded by planes (Borish, JASA 75, 1984). Here the planes are the walls' geodesics,
//! the images are taken by the reflection group of the orbifold, and the floor and ceiling, the
//! flat R factor, unfold separately ([`crate::arrival`]).
//!
//! Tiles are found breadth first across walls, each child being its parent's element times the
//! reflection in one wall (`orbifold::cover::reflection`), and recognised by where they take the
//! room's centre. The search keeps every tile whose centre is within `reach + radius` of the
//! listener: every tile that a geodesic of length `reach` from the listener crosses or ends in
//! has a point within `reach` of the listener, so its centre is within `reach + radius`, and
//! those tiles connect the listener's own (the base tile) to the one it ends in.

use glam::{DMat3, DVec3};
use orbifold::cover::reflection;
use orbifold_trace::room::AnalyticRoom;
use rustc_hash::FxHashMap;

/// One tile of the cover: a group element and its word length.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Tile {
    /// The element g, as an ambient matrix.
    pub matrix: DMat3,
    /// Its word length: the fewest walls a path into the tile crosses.
    pub depth: u32,
}

/// At most this many tiles (a bound on memory, about 300 MB, for rooms whose cover grows
/// fast: H² with a very low `min_level`).
pub const MAX_TILES: usize = 2_000_000;

/// The tiles whose centres are within `reach + radius` of `listener` (ambient, in the room),
/// where `radius` is the room's (the farthest of its corners, or cusp cuts, from `centre`),
/// breadth first: the identity first, then by word length; at most [`MAX_TILES`] (then the
/// farthest are missing: see [`crate::response::Response::truncated`]).
///
/// ```
/// use orbifold::{Layout, LayoutOptions};
/// use orbifold_sound::image_source::tiles;
/// use orbifold_trace::room::AnalyticRoom;
/// let layout = Layout::new(&"*235".parse()?, &LayoutOptions::default())?;
/// let room = AnalyticRoom::all_mirrors(&layout, 1.0, [1.0; 3])?;
/// let centre = room.space.to_ambient(layout.centre);
/// // The spherical group *235 has 120 elements.
/// assert_eq!(tiles(&room, centre, centre, 10.0).len(), 120);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn tiles(room: &AnalyticRoom, centre: DVec3, listener: DVec3, reach: f64) -> Vec<Tile> {
    let space = room.space;
    let radius = room_radius(room, centre);
    let limit = reach + radius;
    let reflections: Vec<DMat3> = room
        .walls
        .iter()
        .map(|w| reflection(space, w.form))
        .collect();
    let mut found = Found::default();
    let mut list = vec![Tile {
        matrix: DMat3::IDENTITY,
        depth: 0,
    }];
    found.insert(centre, 0);
    let mut next = 0;
    while next < list.len() && list.len() < MAX_TILES {
        let tile = list[next];
        next += 1;
        for r in &reflections {
            let matrix = tile.matrix * *r;
            let key = matrix * centre;
            // Far out on the hyperboloid long products lose their last digits: no tile there.
            if !key.is_finite() || space.ambient_distance(listener, key) > limit {
                continue;
            }
            if found.contains(key) {
                continue;
            }
            found.insert(key, list.len());
            list.push(Tile {
                matrix,
                depth: tile.depth + 1,
            });
        }
    }
    list
}

/// The farthest a point of the room is from `centre`: its farthest corner (or cusp cut).
pub fn room_radius(room: &AnalyticRoom, centre: DVec3) -> f64 {
    room.walls
        .iter()
        .map(|w| room.space.ambient_distance(centre, w.start))
        .fold(0.0, f64::max)
        .max(1e-3)
}

/// Tiles already found, by the cell of where they take the room's centre.
///
/// Keys far out on the hyperboloid are large and carry proportionally large rounding errors, so
/// the tolerance within which two keys are the same tile grows with the key (1e-7·(1 + |key|)),
/// and so do the cells: keys of size in [2ᵇ − 1, 2ᵇ⁺¹ − 1) are gridded in cells 2ᵇ·10⁻⁴ wide. A
/// lookup then looks in at most two cells a side, in the one or two size bands the tolerance
/// reaches.
#[derive(Default)]
struct Found {
    /// The last key put in each cell; `next` chains the others (no allocation per cell).
    cells: FxHashMap<[i64; 4], u32>,
    next: Vec<u32>,
    keys: Vec<DVec3>,
}

/// The end of a cell's chain.
const NONE: u32 = u32::MAX;

impl Found {
    fn band(size: f64) -> i32 {
        (1.0 + size).log2().floor() as i32
    }

    fn cell(band: i32, key: DVec3) -> [i64; 3] {
        let width = 1e-4 * 2f64.powi(band);
        [key.x, key.y, key.z].map(|v| (v / width).floor() as i64)
    }

    fn insert(&mut self, key: DVec3, index: usize) {
        debug_assert_eq!(index, self.keys.len());
        self.keys.push(key);
        let band = Self::band(key.length());
        let [a, b, c] = Self::cell(band, key);
        let last = self.cells.insert([i64::from(band), a, b, c], index as u32);
        self.next.push(last.unwrap_or(NONE));
    }

    /// Whether a tile takes the centre within 1e-7·(1 + |key|) of `key`.
    fn contains(&self, key: DVec3) -> bool {
        let size = key.length();
        let tolerance = 1e-7 * (1.0 + size);
        // |key| changes by at most the distance between two keys.
        let bands = Self::band((size - tolerance).max(0.0))..=Self::band(size + tolerance);
        for band in bands {
            let low = Self::cell(band, key - DVec3::splat(tolerance));
            let high = Self::cell(band, key + DVec3::splat(tolerance));
            for a in low[0]..=high[0] {
                for b in low[1]..=high[1] {
                    for c in low[2]..=high[2] {
                        let mut i = self
                            .cells
                            .get(&[i64::from(band), a, b, c])
                            .copied()
                            .unwrap_or(NONE);
                        while i != NONE {
                            if (self.keys[i as usize] - key).length() < tolerance {
                                return true;
                            }
                            i = self.next[i as usize];
                        }
                    }
                }
            }
        }
        false
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use orbifold::{Layout, LayoutOptions};

    fn room(signature: &str) -> (AnalyticRoom, DVec3) {
        let layout = Layout::new(&signature.parse().unwrap(), &LayoutOptions::default()).unwrap();
        let room = AnalyticRoom::all_mirrors(&layout, 1.0, [1.0; 3]).unwrap();
        let centre = room.space.to_ambient(layout.centre);
        (room, centre)
    }

    #[test]
    fn tiles_are_distinct_and_counted_by_the_growth_series_near_the_base() {
        // Every tile up to a word length is found once: the counts by depth agree with the
        // Coxeter group's growth series (computed independently in `orbifold::growth`).
        // Reaches that take in every tile of depth 3 (the rectangle's are 3.25 by 2.33).
        for (signature, reach) in [
            ("*2222", 12.0),
            ("*444", 6.0),
            ("*2333", 6.0),
            ("*235", 6.0),
        ] {
            let (room, centre) = room(signature);
            let list = tiles(&room, centre, centre, reach);
            let series = orbifold::growth::growth_series(&signature.parse().unwrap(), 3).unwrap();
            for (depth, expected) in series.iter().enumerate() {
                let count = list.iter().filter(|t| t.depth as usize == depth).count();
                assert_eq!(count as u128, *expected, "{signature} depth {depth}");
            }
        }
    }
}
