//! A radiance cache on the room's own surfaces, for the far crowd of mirror images.
//!
//! Every mirror image of the figure, the floor or the ceiling is the *same* surface of the
//! orbifold seen along another chain of mirrors, and a diffuse surface sends the same radiance
//! in every direction. So the light leaving a far image is the light leaving a point of the
//! room itself, and it can be looked up instead of traced again. At the horizon of a mirror
//! room a pixel covers many small images; its noise is mostly *which* image each camera sample
//! lands on (coverage), and each sample there is dear (a long chain of mirrors, then light
//! sampling back through another chain, then the indirect light). With the cache such a sample
//! costs only its camera chain, so the adaptive sampler can afford many more of them. The same
//! holds for the light that a diffuse bounce gathers: the surface it reaches reflects the light
//! that the cache holds for it, so a path that has bounced once off a diffuse surface reads its
//! next diffuse surface from the cache and ends there.
//!
//! The cache stores, per cell of a hashed grid over (ambient point, height, facing), the mean
//! of the paths' estimates of *reflected radiance per unit albedo* (E/π for a Lambertian
//! surface, which does not depend on the texture). There are [`LEVELS`] grids, each cell twice
//! the size of the one below, from [`FINEST_CELL`] up. A camera path's first diffuse surface
//! uses the cache only where its pixel's footprint is at least as wide as a cell — its width in
//! the mean, the geometric mean of its widths across and up — so the cache's blur stays about
//! what the pixel averages anyway (a prefiltered far field, as with the footprint's texture
//! filtering), and the lookup point is jittered within a cell so that the grid shows as fine
//! noise, not as blocks (Binder et al. 2018, "Fast path space filtering by jittered spatial
//! hashing"). The geometric mean matters in H², where a far footprint is many times wider
//! across the ray (∝ sinh s) than up it (∝ s): the narrower width would keep the first rings of
//! far images off the cache, while the mean blurs their lighting by at most √(across/up) pixel
//! heights up and down, less than a pixel across (measured in docs/benchmarks.md).
//!
//! A render fills the cache from its own paths: after each round (and after the first half of
//! the first, [`crate::render`]) the estimates of the paths
//! that traced their first diffuse surface in full are added in pixel order (so an image is
//! the same for a given seed whatever the number of threads). A cell is used once it holds
//! [`READY`] estimates; a fraction [`PROBE`] of the camera paths whose first surface could use
//! it trace that surface in full anyway to keep it growing, while their pixels take the cell's
//! value like the others (a full estimate there would only add its noise to the pixel's).
//!
//! A cell's mean is shared by every sample that reads it, so its noise is the same in all of
//! them: it does not show in the pixels' standard errors, only between renders with different
//! seeds (as the Table 8.1 measurements take it). So **a sample reads a cell only once the cell
//! holds at least as many estimates as the sample's pixel has samples** ([`RadianceCache::reader`]):
//! a pixel whose samples read a share f of its value from a cell of m estimates has a variance
//! of about f²σ²/m + (1 − f)σ²/n after n samples, at most σ²/n, its own samples' alone, when
//! m ≥ n; and as the reads are cheaper than tracing, the cache never makes a pixel noisier at
//! equal time. Where many pixels see the same cell (the crowd of mirror images at the horizon,
//! the light a diffuse bounce gathers) the cells hold far more estimates than a pixel has
//! samples and are read as before; where a cell is seen by a pixel or two (a room without
//! mirrors) the pixels that cannot read it trace in full and add to it, so it keeps up with them.
//! (Read from four estimates on, the cache made the floor of a spherical room with black walls
//! four times noisier at 128 samples a pixel than tracing it in full.)
//!
//! ```
//! use glam::DVec3;
//! use orbifold_render::radiance_cache::{Deposit, RadianceCache};
//!
//! let mut cache = RadianceCache::new();
//! let point = DVec3::new(0.1, 0.2, 1.0);
//! let deposit = Deposit { point, height: 0.0, facing: 4, total: [0.5, 0.4, 0.2] };
//! for _ in 0..64 {
//!     cache.add(&deposit);
//! }
//! // A footprint a unit wide reads the mean back; one finer than the finest cell does not.
//! let floor = [(DVec3::X, 0.0), (DVec3::Y, 0.0)];
//! let found = cache.lookup(deposit.point, 0.0, 4, 1.0, floor, [0.5; 2]).unwrap();
//! assert!((found[0] - 0.5).abs() < 1e-12 && (found[2] - 0.2).abs() < 1e-12);
//! assert!(cache.lookup(deposit.point, 0.0, 4, 1e-4, floor, [0.5; 2]).is_none());
//! ```

use std::collections::HashMap;
use std::hash::{BuildHasherDefault, Hasher};

use glam::{DVec3, DVec4};
use rayon::prelude::*;

use crate::lights::Rgb;

/// Side of the finest cells, in ambient units (about intrinsic units near the room's centre).
pub const FINEST_CELL: f64 = 1.0 / 128.0;
/// Number of grid levels; the coarsest cells are `FINEST_CELL · 2^(LEVELS − 1)` wide.
pub const LEVELS: u32 = 9;
/// Estimates a cell needs before it is used.
pub const READY: u32 = 4;
/// After a diffuse bounce, the width over which the light arriving at the next surface is
/// spread, per unit of distance travelled (a cone of about ±6°: the narrowest part of a
/// Lambertian lobe that still carries much of its light).
pub const DIFFUSE_SPREAD: f64 = 0.2;
/// The share of the camera paths whose first surface could read the cache that trace it in
/// full anyway, to add to it (their pixels read the cache all the same).
pub const PROBE: f64 = 0.1;
/// The fewest scatterings a path must still be allowed (the maximum depth less its depth) to
/// read the cache after a bounce. The cache holds the light of paths with the whole maximum
/// depth still ahead of them, so a read deeper along a path counts light of a few bounces more
/// than the path may take; with this many still allowed, that light is negligible.
pub const DEPTH_LEFT_FOR_READS: u32 = 16;

/// One path's estimate of the radiance a diffuse surface point reflects, per unit albedo.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Deposit {
    /// Ambient position of the point.
    pub point: DVec3,
    /// Its height.
    pub height: f64,
    /// Which way its surface faces ([`facing`]).
    pub facing: u8,
    /// Reflected radiance over albedo, per channel.
    pub total: Rgb,
}

/// What a cell holds: the sum of its estimates and their number.
#[derive(Clone, Copy, Debug, Default)]
struct Cell {
    total: Rgb,
    count: u32,
}

/// The keys are already well mixed: hash them as they are.
#[derive(Default)]
struct KeyHasher(u64);

impl Hasher for KeyHasher {
    fn finish(&self) -> u64 {
        self.0
    }
    fn write(&mut self, bytes: &[u8]) {
        for &b in bytes {
            self.0 = (self.0 << 8) | u64::from(b);
        }
    }
    fn write_u64(&mut self, key: u64) {
        self.0 = key;
    }
}

type Cells = HashMap<u64, Cell, BuildHasherDefault<KeyHasher>>;

/// Cells by hashed key, one map per level.
#[derive(Clone, Debug)]
pub struct RadianceCache {
    levels: Vec<Cells>,
}

impl Default for RadianceCache {
    fn default() -> Self {
        RadianceCache {
            levels: vec![Cells::default(); LEVELS as usize],
        }
    }
}

/// Which of eight directions a surface faces most: ± each ambient axis of its horizontal part,
/// or up or down. `horizontal` is the ambient horizontal part of the normal, `up` its vertical
/// component.
///
/// ```
/// use glam::DVec3;
/// use orbifold_render::radiance_cache::facing;
///
/// assert_ne!(facing(DVec3::ZERO, 1.0), facing(DVec3::ZERO, -1.0));
/// assert_eq!(facing(DVec3::new(0.9, 0.1, 0.0), 0.2), facing(DVec3::new(0.8, -0.2, 0.0), 0.1));
/// ```
pub fn facing(horizontal: DVec3, up: f64) -> u8 {
    let v = DVec4::new(horizontal.x, horizontal.y, horizontal.z, up);
    let a = v.abs();
    let axis = if a.w >= a.x.max(a.y).max(a.z) {
        3
    } else if a.x >= a.y.max(a.z) {
        0
    } else if a.y >= a.z {
        1
    } else {
        2
    };
    2 * axis + u8::from(v[axis as usize] < 0.0)
}

/// splitmix64's finaliser: a bijection that spreads every input bit over the output.
fn mix(mut z: u64) -> u64 {
    z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
    z ^ (z >> 31)
}

/// The indices of the finest cell that holds (point, height), along each ambient axis and up.
/// A coarser level's cell is these shifted right by the level: the cells are nested, each
/// twice the size of the one below, and dividing by a power of two is exact in floating point,
/// so ⌊⌊c/s⌋/2ˡ⌋ = ⌊c/(2ˡs)⌋ holds to the last bit.
fn finest_cell(point: DVec3, height: f64) -> [i64; 4] {
    // Saturating casts: far points share an edge cell, harmlessly.
    [point.x, point.y, point.z, height].map(|c| (c / FINEST_CELL).floor() as i64)
}

/// The key of the cell of `level` that holds the finest cell `finest` facing `facing`.
fn key(level: u32, finest: [i64; 4], facing: u8) -> u64 {
    let mut k = mix(u64::from(level) << 8 | u64::from(facing));
    for i in finest {
        k = mix(k ^ (i >> level) as u64);
    }
    k
}

impl RadianceCache {
    /// An empty cache.
    pub fn new() -> RadianceCache {
        RadianceCache::default()
    }

    /// Number of cells (of all levels) that hold an estimate.
    pub fn cells(&self) -> usize {
        self.levels.iter().map(HashMap::len).sum()
    }

    /// Adds one estimate to its cell at every level.
    pub fn add(&mut self, deposit: &Deposit) {
        self.add_all(std::slice::from_ref(deposit));
    }

    /// Adds estimates in order, the levels in parallel (each level's sums in the same order
    /// whatever the threads, so the cache is too). Non-finite or negative estimates are left out.
    pub fn add_all(&mut self, deposits: &[Deposit]) {
        let valid = |d: &&Deposit| {
            let ok = |v: &f64| v.is_finite() && *v >= -1e-9;
            d.total.iter().all(ok)
        };
        let deposits: Vec<(&Deposit, [i64; 4])> = deposits
            .iter()
            .filter(valid)
            .map(|d| (d, finest_cell(d.point, d.height)))
            .collect();
        self.levels
            .par_iter_mut()
            .enumerate()
            .for_each(|(level, cells)| {
                for (deposit, finest) in &deposits {
                    let k = key(level as u32, *finest, deposit.facing);
                    let cell = cells.entry(k).or_default();
                    for c in 0..3 {
                        cell.total[c] += deposit.total[c].max(0.0);
                    }
                    cell.count += 1;
                }
            });
    }

    /// The cache as a sample of a pixel that already has `pixel_samples` samples reads it: a
    /// cell only once it holds at least that many estimates, and [`READY`] (see the module
    /// documentation).
    ///
    /// ```
    /// use glam::DVec3;
    /// use orbifold_render::radiance_cache::{Deposit, RadianceCache};
    ///
    /// let mut cache = RadianceCache::new();
    /// let point = DVec3::new(0.1, 0.2, 1.0);
    /// for _ in 0..8 {
    ///     cache.add(&Deposit { point, height: 0.0, facing: 4, total: [0.5; 3] });
    /// }
    /// let floor = [(DVec3::X, 0.0), (DVec3::Y, 0.0)];
    /// let read = |samples| cache.reader(samples).lookup(point, 0.0, 4, 1.0, floor, [0.5; 2]);
    /// assert!(read(8).is_some() && read(9).is_none());
    /// ```
    pub fn reader(&self, pixel_samples: u32) -> Reader<'_> {
        Reader {
            cache: self,
            least: pixel_samples.max(READY),
        }
    }

    /// The mean reflected radiance per unit albedo near (point, height) facing `facing`, from
    /// the coarsest level whose cells are at most `width` wide, if its cell there is ready
    /// (holds [`READY`] estimates; [`RadianceCache::reader`] asks for more).
    /// The lookup point moves by `jitter` (uniform in [0, 1)²) up to half a cell along each of
    /// the surface's two unit `tangents`, each given as (ambient horizontal part, vertical
    /// part): along the surface, so that it stays among the estimates of the same surface.
    pub fn lookup(
        &self,
        point: DVec3,
        height: f64,
        facing: u8,
        width: f64,
        tangents: [(DVec3, f64); 2],
        jitter: [f64; 2],
    ) -> Option<Rgb> {
        self.reader(0)
            .lookup(point, height, facing, width, tangents, jitter)
    }
}

/// The radiance cache as one sample reads it ([`RadianceCache::reader`]).
#[derive(Clone, Copy, Debug)]
pub struct Reader<'a> {
    cache: &'a RadianceCache,
    /// The fewest estimates a cell must hold to be read.
    least: u32,
}

impl Reader<'_> {
    /// [`RadianceCache::lookup`], from cells that hold enough estimates for this sample.
    pub fn lookup(
        &self,
        point: DVec3,
        height: f64,
        facing: u8,
        width: f64,
        tangents: [(DVec3, f64); 2],
        jitter: [f64; 2],
    ) -> Option<Rgb> {
        // (NaN widths fail the test too.)
        if width.is_nan() || width < FINEST_CELL {
            return None;
        }
        let level = ((width / FINEST_CELL).log2().floor() as u32).min(LEVELS - 1);
        let size = FINEST_CELL * f64::from(1u32 << level);
        let (a, b) = ((jitter[0] - 0.5) * size, (jitter[1] - 0.5) * size);
        let point = point + tangents[0].0 * a + tangents[1].0 * b;
        let height = height + tangents[0].1 * a + tangents[1].1 * b;
        let k = key(level, finest_cell(point, height), facing);
        let cell = self.cache.levels[level as usize].get(&k)?;
        let n = f64::from(cell.count);
        (cell.count >= self.least).then(|| cell.total.map(|s| s / n))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    /// The floor's tangents: along the two horizontal ambient axes of E².
    const FLOOR: [(DVec3, f64); 2] = [(DVec3::X, 0.0), (DVec3::Y, 0.0)];
    const NO_JITTER: ([(DVec3, f64); 2], [f64; 2]) = (FLOOR, [0.5; 2]);

    proptest! {
        #[test]
        fn a_lookup_returns_the_mean_of_its_cell(
            x in -3.0f64..3.0, y in -3.0f64..3.0, h in -1.0f64..1.0,
            values in proptest::collection::vec(0.0f64..10.0, 32..64),
            width in 0.01f64..4.0,
        ) {
            let mut cache = RadianceCache::new();
            let point = DVec3::new(x, y, 1.0);
            for &v in &values {
                cache.add(&Deposit { point, height: h, facing: 5, total: [v, 2.0 * v, 0.0] });
            }
            let mean = values.iter().sum::<f64>() / values.len() as f64;
            // Without jitter the lookup point is the deposits' own: the same cell.
            let found = cache.lookup(point, h, 5, width, NO_JITTER.0, NO_JITTER.1).unwrap();
            prop_assert!((found[0] - mean).abs() < 1e-9 * (1.0 + mean));
            prop_assert!((found[1] - 2.0 * mean).abs() < 1e-9 * (1.0 + mean));
            prop_assert_eq!(found[2], 0.0);
            // Another facing is another cell.
            prop_assert!(cache.lookup(point, h, 4, width, NO_JITTER.0, NO_JITTER.1).is_none());
        }

        #[test]
        fn a_coarse_cell_is_the_finest_cells_index_shifted(
            c in -1e6f64..1e6, level in 0..LEVELS,
        ) {
            // The cell of a level, found directly, is the finest cell's shifted by the level,
            // on the cells' edges and just below them too.
            let size = FINEST_CELL * f64::from(1u32 << level);
            let edge = (c / size).round() * size;
            for c in [c, edge, edge.next_down(), edge.next_up()] {
                let direct = (c / size).floor() as i64;
                prop_assert_eq!(finest_cell(DVec3::new(c, 0.0, 0.0), 0.0)[0] >> level, direct);
            }
        }

        #[test]
        fn jitter_never_reaches_past_a_neighbouring_cell(
            x in -3.0f64..3.0, y in -3.0f64..3.0, far in 2.5f64..10.0,
            width in 0.01f64..1.0, u in proptest::array::uniform2(0.0f64..1.0),
        ) {
            // Estimates more than a cell and a half away along x are never read.
            let mut cache = RadianceCache::new();
            let point = DVec3::new(x, y, 1.0);
            let level = ((width / FINEST_CELL).log2().floor() as u32).min(LEVELS - 1);
            let size = FINEST_CELL * f64::from(1u32 << level);
            let other = point + DVec3::new(far * size, 0.0, 0.0);
            for _ in 0..READY {
                cache.add(&Deposit { point: other, height: 0.0, facing: 0, total: [1.0; 3] });
            }
            prop_assert!(cache.lookup(point, 0.0, 0, width, FLOOR, [u[0], u[1]]).is_none());
        }
    }

    #[test]
    fn a_cell_is_not_used_before_it_is_ready() {
        let mut cache = RadianceCache::new();
        let deposit = Deposit {
            point: DVec3::new(0.3, 0.0, 1.0),
            height: 0.2,
            facing: 1,
            total: [1.0; 3],
        };
        for _ in 1..READY {
            cache.add(&deposit);
        }
        assert!(
            cache
                .lookup(deposit.point, 0.2, 1, 0.5, NO_JITTER.0, NO_JITTER.1)
                .is_none()
        );
        cache.add(&deposit);
        assert!(
            cache
                .lookup(deposit.point, 0.2, 1, 0.5, NO_JITTER.0, NO_JITTER.1)
                .is_some()
        );
        // Non-finite or negative estimates are left out.
        cache.add(&Deposit {
            total: [f64::NAN, 1.0, 1.0],
            ..deposit
        });
        cache.add(&Deposit {
            total: [-1.0, 1.0, 1.0],
            ..deposit
        });
        assert_eq!(
            cache.lookup(deposit.point, 0.2, 1, 0.5, NO_JITTER.0, NO_JITTER.1),
            Some([1.0; 3])
        );
    }
}
