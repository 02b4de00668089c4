//! The horizontal part of an echo's path: the geodesic of the plane from the listener to an
//! image g·s of the source, followed through the real room, where it reflects off the walls of
//! its word in order.
//!
//! A wall paired with another by the orbifold's group is not a surface but a portal: the room
//! goes on beyond it, so the path passes it whole and goes on from the partner wall, moved by
//! the pairing (as the tracer's rays do, `Ray::passed`), and it is no reflection.
//!
//! An echo's geodesic in S²×R, E²×R or H²×R runs a geodesic of the plane at constant speed
//! while its height changes linearly (ARCHITECTURE.md §8), so the walls it meets, and where
//! along them, depend only on its horizontal part; the height only decides, at a wall with
//! partial mirrors, whether it meets a mirror there, and which floor and ceiling reflections
//! come between ([`crate::arrival`]). The path is followed by the tracer's closed-form
//! room exits ([`AnalyticRoom::exit`]) and reflected at every wall, as the renderer follows a
//! light's image (`orbifold-render`'s mirror segments); it counts only if it ends at the
//! source. On the sphere the geodesic may also go the long way round, or round more than once
//! ([`turned`]).

use std::f64::consts::PI;

use glam::DVec3;
use orbifold::space::Space;
use orbifold_trace::geodesic::Ray;
use orbifold_trace::room::AnalyticRoom;

use crate::absorption::{Bands, times};
use crate::settings::Reflection;

/// How far (intrinsic) the end of a followed path may be from the source and still count.
pub const ARRIVAL_TOLERANCE: f64 = 1e-6;

/// The most wall reflections and portal crossings followed on one path (rays that run into an
/// ideal corner bounce ever faster).
pub const MAX_WALL_REFLECTIONS: usize = 4096;

/// Where a path meets a wall.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct WallCrossing {
    /// The wall (the layout's edge index).
    pub wall: usize,
    /// Horizontal distance from the listener, intrinsic.
    pub sigma: f64,
    /// Where along the wall (fraction of its length), for partial mirrors.
    pub along: f64,
}

/// Whether a wall is a mirror at some heights and not at others.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Cover {
    Full,
    Bare,
    Partial,
}

/// The horizontal geodesic from the listener to one image of the source, followed through the
/// room.
#[derive(Clone, Debug, PartialEq)]
pub struct HorizontalPath {
    /// Its horizontal length σ, intrinsic.
    pub sigma: f64,
    /// The walls it reflects off, in order (the portals it passes are not among them).
    pub crossings: Vec<WallCrossing>,
    /// How many portals it passes.
    pub portals: u32,
    /// The product of the reflection coefficients of the crossings whose wall is a mirror
    /// everywhere or nowhere along that point (independent of height), per band.
    pub fixed: Bands,
    /// The crossings whose reflection depends on the height (indices into `crossings`).
    pub partial: Vec<u32>,
    /// The largest reflection coefficient of any band that the height-dependent crossings can
    /// have, each (for bounds).
    pub partial_best: f64,
    /// The unit horizontal direction it leaves the listener in (ambient).
    pub direction: DVec3,
}

/// The horizontal length of the geodesic between two points at distance `d` ≤ π of the sphere
/// that makes `turns` half-turns past the first (0: the short way, σ = d; 1: the long way
/// round, 2π − d; 2: the short way and once round, 2π + d; …), and whether it leaves the other
/// way (−u for the direction u of the short way).
///
/// ```
/// use orbifold_sound::path::turned;
/// use std::f64::consts::PI;
/// assert_eq!(turned(1.0, 0), (1.0, false));
/// assert_eq!(turned(1.0, 1), (2.0 * PI - 1.0, true));
/// assert_eq!(turned(1.0, 2), (2.0 * PI + 1.0, false));
/// ```
pub fn turned(d: f64, turns: u32) -> (f64, bool) {
    let t = f64::from(turns);
    if turns.is_multiple_of(2) {
        (d + PI * t, false)
    } else {
        (PI * (t + 1.0) - d, true)
    }
}

impl HorizontalPath {
    /// The geodesic from `listener` to `image` (ambient, an image of `source`) with `turns`
    /// half-turns ([`turned`]; 0 but on the sphere), followed through the room; `None` when it
    /// does not end at `source` (it grazes a corner, or runs into a cusp).
    ///
    /// ```
    /// use orbifold::{Layout, LayoutOptions};
    /// use orbifold_sound::path::HorizontalPath;
    /// use orbifold_sound::settings::Settings;
    /// use orbifold_trace::room::AnalyticRoom;
    /// use num_complex::Complex64;
    /// let layout = Layout::new(&"*2222".parse()?, &LayoutOptions::default())?;
    /// let room = AnalyticRoom::all_mirrors(&layout, 1.0, [1.0; 3])?;
    /// let space = room.space;
    /// let (x, s) = (space.to_ambient(Complex64::new(0.1, 0.0)), space.to_ambient(Complex64::new(-0.1, 0.05)));
    /// // The image across wall 0.
    /// let image = space.reflect(room.walls[0].form, s);
    /// let reflection = Settings::from_sound(&Default::default()).reflection;
    /// let path = HorizontalPath::follow(&room, &reflection, x, s, image, 0).unwrap();
    /// assert_eq!(path.crossings.len(), 1);
    /// assert_eq!(path.crossings[0].wall, 0);
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn follow(
        room: &AnalyticRoom,
        reflection: &Reflection,
        listener: DVec3,
        source: DVec3,
        image: DVec3,
        turns: u32,
    ) -> Option<HorizontalPath> {
        let space = room.space;
        if turns > 0 && space.kappa() <= 0.0 {
            return None;
        }
        let d = space.ambient_distance(listener, image);
        let (sigma, back) = turned(d, turns);
        let log = space.log(listener, image);
        let norm = space.point_dot(log, log).max(0.0).sqrt();
        if norm < 1e-12 {
            // At the image itself (a source straight above or below the listener, or its
            // image): the vertical path alone. Every great circle through the point comes
            // back to it on the sphere, a whole family of paths with no one direction; they
            // are left out (an exact alignment: a source a hair's breadth aside has them).
            return (turns == 0).then(|| HorizontalPath::vertical(space, listener));
        }
        let direction = if back { -log / norm } else { log / norm };
        let mut ray = Ray::new(space, listener, direction, 0.0, 0.0);
        let mut travelled = 0.0;
        let mut crossings = Vec::new();
        let mut portals = 0u32;
        let mut fixed = [1.0; crate::absorption::BANDS];
        let mut partial = Vec::new();
        let mut partial_best: f64 = 0.0;
        loop {
            let left = sigma - travelled;
            let hit = room.exit(&ray).filter(|h| h.s < left);
            let Some(hit) = hit else {
                let (end, _) = ray.point_at(space, left);
                return (space.ambient_distance(end, source) < ARRIVAL_TOLERANCE).then_some(
                    HorizontalPath {
                        sigma,
                        crossings,
                        portals,
                        fixed,
                        partial,
                        partial_best,
                        direction,
                    },
                );
            };
            let orbifold_trace::room::RoomSurface::Wall(wall) = hit.surface else {
                // A horizontal ray meets no floor or ceiling.
                return None;
            };
            if crossings.len() + portals as usize >= MAX_WALL_REFLECTIONS {
                return None;
            }
            travelled += hit.s;
            let continued = ray.continued(space, hit.s, hit.point, hit.tangent);
            if let Some(portal) = room.walls[wall]
                .portal
                .filter(|_| room.walls[wall].mirrors.is_empty())
            {
                portals += 1;
                ray = continued.transformed(&portal.back, 0.0).renormalized(space);
                continue;
            }
            let along = room.along(wall, hit.point).clamp(0.0, 1.0);
            match cover(room, wall, along) {
                Cover::Full => fixed = times(&fixed, &reflection.mirror),
                Cover::Bare => fixed = times(&fixed, &reflection.wall),
                Cover::Partial => {
                    partial.push(crossings.len() as u32);
                    let best = reflection
                        .mirror
                        .iter()
                        .chain(&reflection.wall)
                        .copied()
                        .fold(0.0, f64::max);
                    partial_best = partial_best.max(best);
                }
            }
            crossings.push(WallCrossing {
                wall,
                sigma: travelled,
                along,
            });
            ray = continued.reflected(space, room.walls[wall].form);
        }
    }

    fn vertical(space: Space, at: DVec3) -> HorizontalPath {
        HorizontalPath {
            sigma: 0.0,
            crossings: Vec::new(),
            portals: 0,
            fixed: [1.0; crate::absorption::BANDS],
            partial: Vec::new(),
            partial_best: 0.0,
            direction: space.tangent_frame(at)[0],
        }
    }

    /// The product of the walls' reflection coefficients per band for a path whose height is
    /// `height(σ)` at horizontal distance σ.
    pub fn walls_reflection(
        &self,
        room: &AnalyticRoom,
        reflection: &Reflection,
        height: impl Fn(f64) -> f64,
    ) -> Bands {
        let mut product = self.fixed;
        for &i in &self.partial {
            let c = self.crossings[i as usize];
            let r = if mirrored(room, c.wall, c.along, height(c.sigma)) {
                &reflection.mirror
            } else {
                &reflection.wall
            };
            product = times(&product, r);
        }
        product
    }
}

/// Whether wall `wall` has a mirror at the point `along` its length at every height, none at
/// any height, or one at some heights only.
fn cover(room: &AnalyticRoom, wall: usize, along: f64) -> Cover {
    let height = room.height;
    let mut any = false;
    for m in &room.walls[wall].mirrors {
        if !(m.from <= along && along <= m.to) {
            continue;
        }
        any = true;
        if m.bottom <= 0.0 && m.top >= height {
            return Cover::Full;
        }
    }
    if any { Cover::Partial } else { Cover::Bare }
}

/// Whether the wall point `along` its length at `height` is on a mirror.
pub fn mirrored(room: &AnalyticRoom, wall: usize, along: f64, height: f64) -> bool {
    room.walls[wall]
        .mirrors
        .iter()
        .any(|m| m.covers(along.clamp(0.0, 1.0), height))
}
