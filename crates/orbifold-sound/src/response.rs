//! The room's response between a source and a listener: every echo found by image sources,
//! sorted by time.
//!
//! For each tile g of the cover ([`crate::image_source`]) and, on the sphere, each way round,
//! the horizontal geodesic to g·s is followed through the room ([`crate::path`]); then the
//! floor and ceiling images of the source are taken slab by slab outward from the room
//! ([`crate::arrival`]). **Paths are limited by amplitude, not by order:** an echo is kept when
//! its amplitude in some octave band is at least `min_amplitude` (`[sound] min_level` decibels
//! below the direct sound at one metre, −60 dB by default, the level by which reverberation time
//! is defined; Kuttruff §5.1), and when it arrives within the response's length. Before a path
//! is followed its amplitude is bounded by its length and the most its word length of wall
//! reflections can let through; slabs are taken outward while the bound with their floors and
//! ceilings stays above the limit (it only falls as the slabs go farther).

use orbifold::space::Space;
use orbifold_trace::room::{AnalyticRoom, RoomSurface};
use rayon::prelude::*;
use std::sync::atomic::{AtomicUsize, Ordering};

use crate::absorption::largest;
use crate::arrival::{Arrival, Bounce, Echo, amplitude, fold_height, slab_image, spread};
use crate::image_source::{Tile, tiles};
use crate::path::{HorizontalPath, mirrored};
use crate::settings::{Point, Settings};

/// At most this many echoes in one response (a bound on memory, about 600 MB, for rooms that
/// absorb nothing heard down to a very low `min_level` for long).
pub const MAX_ARRIVALS: usize = 10_000_000;

/// Every echo between a source and a listener, sorted by time.
#[derive(Clone, Debug)]
pub struct Response {
    /// The echoes, by time (ties by length, then path and slab: the order does not depend on
    /// the threads).
    pub arrivals: Vec<Arrival>,
    /// The horizontal paths the echoes take.
    pub paths: Vec<HorizontalPath>,
    /// The source and the listener.
    pub source: Point,
    /// The listener.
    pub listener: Point,
    /// The room's height.
    pub room_height: f64,
    /// Image paths that did not arrive at the source when followed through the room (grazing
    /// a corner, or lost in a cusp), left out.
    pub lost: usize,
    /// Whether the search for images stopped at [`crate::image_source::MAX_TILES`] before it
    /// reached as far as the response can hear, or the echoes at [`MAX_ARRIVALS`] (some echoes
    /// are then missing, and which depends on the threads' timing).
    pub truncated: bool,
}

/// The listener's frame of reference for one response: the room, the settings and the places.
#[derive(Clone, Debug)]
pub struct Listening<'a> {
    /// The room.
    pub room: &'a AnalyticRoom,
    /// The room's centre (ambient), from which tiles are told apart.
    pub centre: glam::DVec3,
    /// The settings.
    pub settings: &'a Settings,
}

impl Listening<'_> {
    /// Every echo from `source` to `listener` within the response's length and above its
    /// amplitude limit. `progress(done, total)` is called as tiles are done (from any thread).
    ///
    /// ```
    /// use orbifold::{Layout, LayoutOptions};
    /// use orbifold_sound::response::Listening;
    /// use orbifold_sound::settings::{Point, Settings};
    /// use orbifold_trace::room::AnalyticRoom;
    /// let layout = Layout::new(&"*2222".parse()?, &LayoutOptions::default())?;
    /// let room = AnalyticRoom::all_mirrors(&layout, 1.0, [1.0; 3])?;
    /// let mut sound = orbifold_scene::sound::Sound::default();
    /// sound.seconds = 0.1;
    /// let settings = Settings::from_sound(&sound);
    /// let space = room.space;
    /// let listening = Listening { room: &room, centre: space.to_ambient(layout.centre), settings: &settings };
    /// let (s, l) = (Point::from_model(space, [0.1, 0.0], 0.5), Point::from_model(space, [-0.1, 0.0], 0.5));
    /// let response = listening.response(s, l, &|_, _| {});
    /// // The direct sound first: 0.2 model units are 0.4 intrinsic, 1.6 m at 4 m a unit.
    /// assert!((response.arrivals[0].length - 1.6).abs() < 1e-12);
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn response(
        &self,
        source: Point,
        listener: Point,
        progress: &(dyn Fn(usize, usize) + Sync),
    ) -> Response {
        let reach = self.reach();
        let list = tiles(self.room, self.centre, listener.at, reach);
        let too_many_tiles = list.len() >= crate::image_source::MAX_TILES;
        let done = AtomicUsize::new(0);
        let found = AtomicUsize::new(0);
        let total = list.len();
        let per_tile: Vec<(Vec<HorizontalPath>, Vec<Arrival>, usize)> = list
            .par_iter()
            .map(|tile| {
                let echoes = self.tile_echoes(tile, (source, listener), reach, &found);
                let n = done.fetch_add(1, Ordering::Relaxed) + 1;
                if n.is_multiple_of(256) || n == total {
                    progress(n, total);
                }
                echoes
            })
            .collect();
        let mut paths = Vec::new();
        let mut arrivals = Vec::new();
        let mut lost = 0;
        for (tile_paths, mut tile_arrivals, tile_lost) in per_tile {
            let offset = paths.len() as u32;
            tile_arrivals.iter_mut().for_each(|a| a.path += offset);
            paths.extend(tile_paths);
            arrivals.extend(tile_arrivals);
            lost += tile_lost;
        }
        arrivals.sort_by(|a, b| {
            a.time
                .total_cmp(&b.time)
                .then(a.length.total_cmp(&b.length))
                .then(a.path.cmp(&b.path))
                .then(a.slab.cmp(&b.slab))
        });
        Response {
            arrivals,
            paths,
            source,
            listener,
            room_height: self.room.height,
            lost,
            truncated: too_many_tiles || found.load(Ordering::Relaxed) > MAX_ARRIVALS,
        }
    }

    /// The echoes through one tile: each way round, each slab.
    fn tile_echoes(
        &self,
        tile: &Tile,
        (source, listener): (Point, Point),
        reach: f64,
        found: &AtomicUsize,
    ) -> (Vec<HorizontalPath>, Vec<Arrival>, usize) {
        let space = self.room.space;
        let settings = self.settings;
        let image = tile.matrix * source.at;
        let d = space.ambient_distance(listener.at, image);
        let wall_best =
            largest(&settings.reflection.mirror).max(largest(&settings.reflection.wall));
        let mut paths = Vec::new();
        let mut arrivals = Vec::new();
        let mut lost = 0;
        let turns = if space.kappa() > 0.0 { u32::MAX } else { 1 };
        // On the sphere, the path of turn t + 2 is that of turn t and once more round: it meets
        // every wall that one meets and more, so once a turn is too quiet at its loudest (at a
        // focus), so are all later turns of its parity.
        let mut quiet = [false; 2];
        for turn in 0..turns {
            let (sigma, _) = crate::path::turned(d, turn);
            if sigma > reach || quiet.iter().all(|&q| q) {
                break;
            }
            if quiet[turn as usize % 2] {
                continue;
            }
            // No path into this tile reflects off fewer walls than its fewest (a portal passes
            // sound on whole).
            let bound = wall_best.powi(tile.reflections.min(i32::MAX as u32) as i32)
                * self.spreading_bound(space, sigma, sigma);
            if bound < settings.min_amplitude {
                continue;
            }
            let Some(path) = HorizontalPath::follow(
                self.room,
                &settings.reflection,
                listener.at,
                source.at,
                image,
                turn,
            ) else {
                lost += 1;
                continue;
            };
            if space.kappa() > 0.0 {
                let walls =
                    largest(&path.fixed) * path.partial_best.powi(path.partial.len() as i32);
                quiet[turn as usize % 2] = walls * self.focus_bound(sigma) < settings.min_amplitude;
            }
            let index = paths.len() as u32;
            self.slabs(&path, index, (source, listener), found, &mut arrivals);
            paths.push(path);
        }
        (paths, arrivals, lost)
    }

    /// The longest horizontal part σ of a path that can be heard: no longer than the response
    /// lasts, and, where spreading alone takes a path below the amplitude limit, no longer than
    /// that. A path of horizontal length σ is at least σ long, so its J = ℓ²·S_κ(σ)/σ is at
    /// least σ·S_κ(σ), which grows with σ in E² and H² (not on the sphere, where the turns are
    /// limited instead). Lengths as such are limited only by time: a path that climbs steeply
    /// spreads as in flat space.
    pub fn reach(&self) -> f64 {
        let space = self.room.space;
        let time = self.settings.reach();
        if space.kappa() > 0.0
            || self.spreading_bound(space, time, time) >= self.settings.min_amplitude
        {
            return time;
        }
        // J(ℓ, ℓ) grows with ℓ: bisect for the length where the bound meets the limit.
        let (mut lo, mut hi) = (0.0, time);
        for _ in 0..60 {
            let mid = 0.5 * (lo + hi);
            if self.spreading_bound(space, mid, mid) >= self.settings.min_amplitude {
                lo = mid;
            } else {
                hi = mid;
            }
        }
        hi
    }

    /// The most that spreading lets through on the sphere at horizontal length σ or more
    /// (J ≥ σ·sin(focus), its least value, at a focus).
    fn focus_bound(&self, sigma: f64) -> f64 {
        let r = self.settings.metres_per_unit;
        let focus = 0.5 * self.settings.listener_size / r;
        let j = (sigma * focus.sin()).max(1e-300) * r * r;
        1.0 / (4.0 * std::f64::consts::PI * j.sqrt())
    }

    /// The most that spreading lets through at length ℓ and horizontal length σ.
    fn spreading_bound(&self, space: Space, length: f64, sigma: f64) -> f64 {
        let r = self.settings.metres_per_unit;
        let focus = 0.5 * self.settings.listener_size / r;
        1.0 / (4.0 * std::f64::consts::PI * (spread(space, length, sigma, focus) * r * r).sqrt())
    }

    /// The echoes along one horizontal path: the slabs 0, 1, 2, … and −1, −2, …, each side while
    /// its bound stays above the limit and it arrives within the response's length.
    fn slabs(
        &self,
        path: &HorizontalPath,
        index: u32,
        (source, listener): (Point, Point),
        found: &AtomicUsize,
        out: &mut Vec<Arrival>,
    ) {
        let space = self.room.space;
        let settings = self.settings;
        // Lengths are limited by time alone (see [`Listening::reach`]).
        let reach = settings.reach();
        let walls_best = largest(&path.fixed) * path.partial_best.powi(path.partial.len() as i32);
        let (floor_best, ceiling_best) = (
            largest(&settings.reflection.floor),
            largest(&settings.reflection.ceiling),
        );
        for step in [1i32, -1] {
            let mut j = if step > 0 { 0 } else { -1 };
            loop {
                let (z, floors, ceilings) = slab_image(j, source.height, self.room.height);
                let rise = z - listener.height;
                let length = (path.sigma * path.sigma + rise * rise).sqrt();
                if length > reach {
                    break;
                }
                let bound = walls_best
                    * floor_best.powi(floors as i32)
                    * ceiling_best.powi(ceilings as i32)
                    * self.spreading_bound(space, length, path.sigma);
                if bound < settings.min_amplitude {
                    break;
                }
                let slope = if path.sigma > 0.0 {
                    rise / path.sigma
                } else {
                    0.0
                };
                let walls = path.walls_reflection(self.room, &settings.reflection, |s| {
                    fold_height(listener.height + s * slope, self.room.height)
                });
                let echo = Echo {
                    length,
                    sigma: path.sigma,
                    walls,
                    floors,
                    ceilings,
                };
                let (bands, broadband) = amplitude(space, settings, &echo);
                if largest(&bands) >= settings.min_amplitude {
                    // Counted across the threads; past the limit nothing more is kept.
                    if found.fetch_add(1, Ordering::Relaxed) >= MAX_ARRIVALS {
                        return;
                    }
                    let metres = length * settings.metres_per_unit;
                    out.push(Arrival {
                        time: metres / settings.speed,
                        length: metres,
                        amplitude: broadband,
                        bands: bands.map(|b| b as f32),
                        reflections: path.crossings.len() as u32 + floors + ceilings,
                        path: index,
                        slab: j,
                    });
                }
                j += step;
            }
        }
    }
}

impl Response {
    /// The surfaces an echo reflects off, in order.
    ///
    /// ```
    /// # use orbifold::{Layout, LayoutOptions};
    /// # use orbifold_sound::response::Listening;
    /// # use orbifold_sound::settings::{Point, Settings};
    /// # use orbifold_trace::room::AnalyticRoom;
    /// # let layout = Layout::new(&"*2222".parse()?, &LayoutOptions::default())?;
    /// # let room = AnalyticRoom::all_mirrors(&layout, 1.0, [1.0; 3])?;
    /// # let mut sound = orbifold_scene::sound::Sound::default();
    /// # sound.seconds = 0.05;
    /// # let settings = Settings::from_sound(&sound);
    /// # let space = room.space;
    /// # let listening = Listening { room: &room, centre: space.to_ambient(layout.centre), settings: &settings };
    /// # let (s, l) = (Point::from_model(space, [0.1, 0.0], 0.5), Point::from_model(space, [-0.1, 0.0], 0.5));
    /// let response = listening.response(s, l, &|_, _| {});
    /// for a in &response.arrivals {
    ///     assert_eq!(response.bounces(&room, a).len() as u32, a.reflections);
    /// }
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn bounces(&self, room: &AnalyticRoom, arrival: &Arrival) -> Vec<Bounce> {
        let path = &self.paths[arrival.path as usize];
        let h = self.room_height;
        let (z, _, _) = slab_image(arrival.slab, self.source.height, h);
        let rise = z - self.listener.height;
        // Every surface by the fraction τ of the path at which it is met.
        let mut met: Vec<(f64, Bounce)> = Vec::new();
        let slope = if path.sigma > 0.0 {
            rise / path.sigma
        } else {
            0.0
        };
        for c in &path.crossings {
            let height = fold_height(self.listener.height + c.sigma * slope, h);
            met.push((
                c.sigma / path.sigma,
                Bounce {
                    surface: RoomSurface::Wall(c.wall),
                    mirror: mirrored(room, c.wall, c.along, height),
                },
            ));
        }
        let planes: Vec<i32> = if arrival.slab >= 0 {
            (1..=arrival.slab).collect()
        } else {
            (arrival.slab + 1..=0).rev().collect()
        };
        for k in planes {
            let tau = (f64::from(k) * h - self.listener.height) / rise;
            let surface = if k % 2 == 0 {
                RoomSurface::Floor
            } else {
                RoomSurface::Ceiling
            };
            met.push((
                tau,
                Bounce {
                    surface,
                    mirror: false,
                },
            ));
        }
        met.sort_by(|a, b| a.0.total_cmp(&b.0));
        met.into_iter().map(|(_, b)| b).collect()
    }
}
