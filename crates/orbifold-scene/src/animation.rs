//! Animation paths: where the camera (or a walking object) is in each frame.
//!
//! Built-in paths follow the room's geometry, computed with the room's own geodesics:
//!
//! - [`Path::Walls`]: a walk round the room along its walls (the seed's Fig. 8.7), on the
//!   geodesic polygon whose corners lie on the segments from the room's centre to its corners,
//!   at [`WALK_INSET`] of the way there (at most [`WALK_REACH`] from the centre, so ideal
//!   corners are visited at a finite distance), at constant speed, facing the way it goes.
//! - [`Path::Orbit`]: a geodesic circle round the room's centre through the camera's position,
//!   facing the centre.
//! - [`Path::Turn`]: one full turn on the spot (a turning panorama with a panorama camera).
//! - [`Path::Keyframes`]: poses read from a file, joined by geodesics.
//!
//! Frame `i` of `n` is at parameter i / n for closed paths (frame n would repeat frame 0), and
//! i / (n − 1) for keyframes (the last frame is the last key).

use std::f64::consts::TAU;

use glam::DVec3;
use num_complex::Complex64;
use orbifold::Layout;
use orbifold::space::Space;

/// How far along each centre–corner segment the walk along the walls goes.
pub const WALK_INSET: f64 = 0.75;
/// The farthest the walk goes from the centre (intrinsic units).
pub const WALK_REACH: f64 = 1.5;

/// One pose of the walker: model position, height, bearing (degrees from the model's +x,
/// counter-clockwise) and pitch (degrees).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Pose {
    /// Model position.
    pub at: [f64; 2],
    /// Height above the floor.
    pub height: f64,
    /// Bearing, degrees.
    pub yaw: f64,
    /// Elevation, degrees.
    pub pitch: f64,
}

/// A path through the room.
#[derive(Clone, Debug, PartialEq)]
pub enum Path {
    /// Round the room along its walls.
    Walls,
    /// Round the room's centre, facing it.
    Orbit,
    /// A full turn on the spot.
    Turn,
    /// Poses joined by geodesics.
    Keyframes(Vec<Pose>),
}

impl Path {
    /// Reads keyframes: one pose per line, `x y height yaw [pitch]` separated by spaces or
    /// commas; `#` starts a comment. Errors name the line.
    ///
    /// ```
    /// use orbifold_scene::animation::Path;
    ///
    /// let path = Path::parse_keyframes("# x y h yaw pitch\n0 0 0.5 0\n0.1, 0, 0.5, 90, -10\n").unwrap();
    /// let Path::Keyframes(keys) = path else { unreachable!() };
    /// assert_eq!(keys[1].yaw, 90.0);
    /// assert!(Path::parse_keyframes("0 0 zero 0").unwrap_err().contains("line 1"));
    /// ```
    pub fn parse_keyframes(text: &str) -> Result<Path, String> {
        let mut keys = Vec::new();
        for (number, line) in text.lines().enumerate() {
            let line = line.split('#').next().unwrap_or("").trim();
            if line.is_empty() {
                continue;
            }
            let fields: Vec<&str> = line
                .split(|c: char| c == ',' || c.is_whitespace())
                .filter(|f| !f.is_empty())
                .collect();
            let values = fields
                .iter()
                .map(|f| f.parse::<f64>().ok().filter(|v| v.is_finite()))
                .collect::<Option<Vec<f64>>>()
                .filter(|v| v.len() == 4 || v.len() == 5)
                .ok_or_else(|| {
                    format!(
                        "line {}: expected `x y height yaw [pitch]` (finite numbers), found `{line}`",
                        number + 1
                    )
                })?;
            keys.push(Pose {
                at: [values[0], values[1]],
                height: values[2],
                yaw: values[3],
                pitch: values.get(4).copied().unwrap_or(0.0),
            });
        }
        if keys.is_empty() {
            return Err("no keyframes: expected lines `x y height yaw [pitch]`".into());
        }
        Ok(Path::Keyframes(keys))
    }

    /// The pose of frame `index` of `count`, starting from `start` (the scene's camera, or the
    /// walking object's pose) in the room `layout`.
    ///
    /// ```
    /// use orbifold_scene::Scene;
    /// use orbifold_scene::animation::{Path, Pose};
    ///
    /// let scene = Scene::default();
    /// let layout = scene.layout().unwrap();
    /// let start = Pose { at: scene.camera.at, height: 0.5, yaw: 0.0, pitch: -20.0 };
    /// let first = Path::Turn.pose(&layout, start, 0, 4);
    /// let second = Path::Turn.pose(&layout, start, 1, 4);
    /// assert_eq!(first, start);
    /// assert!((second.yaw - 90.0).abs() < 1e-12);
    /// ```
    pub fn pose(&self, layout: &Layout, start: Pose, index: usize, count: usize) -> Pose {
        let t = index as f64 / count.max(1) as f64;
        match self {
            Path::Turn => Pose {
                yaw: start.yaw + 360.0 * t,
                ..start
            },
            Path::Orbit => orbit(layout, start, t),
            Path::Walls => walls(layout, start, t),
            Path::Keyframes(keys) => {
                let t = if count > 1 {
                    index as f64 / (count - 1) as f64
                } else {
                    0.0
                };
                keyframes(layout.space(), keys, t)
            }
        }
    }
}

/// Bearing (degrees) at `z` of the geodesic towards `w`.
fn bearing(space: Space, z: Complex64, w: Complex64) -> f64 {
    space.direction(z, w).arg().to_degrees()
}

/// The model point at intrinsic distance `d` from `z` along the bearing `direction` (model).
fn walk(space: Space, z: Complex64, direction: Complex64, d: f64) -> Complex64 {
    let p = space.to_ambient(z);
    let v = space.model_tangent(z, direction);
    space.to_model(space.exp(p, v * d))
}

fn orbit(layout: &Layout, start: Pose, t: f64) -> Pose {
    let space = layout.space();
    let centre = layout.centre;
    let z = Complex64::new(start.at[0], start.at[1]);
    let radius = space.distance(centre, z);
    if radius < 1e-9 {
        return Pose {
            yaw: start.yaw + 360.0 * t,
            ..start
        };
    }
    // Round the centre from the start's bearing (seen from the centre), counter-clockwise.
    let from = space.direction(centre, z);
    let direction = from * Complex64::from_polar(1.0, TAU * t);
    let at = walk(space, centre, direction, radius);
    Pose {
        at: [at.re, at.im],
        yaw: bearing(space, at, centre),
        ..start
    }
}

/// The corners of the walk round the walls.
fn walk_corners(layout: &Layout) -> Vec<Complex64> {
    let space = layout.space();
    let centre = layout.centre;
    layout
        .vertices
        .iter()
        .map(|v| {
            let reach = if v.ideal {
                WALK_REACH
            } else {
                (WALK_INSET * space.distance(centre, v.position)).min(WALK_REACH)
            };
            walk(space, centre, space.direction(centre, v.position), reach)
        })
        .collect()
}

/// The point at arc length `s` (wrapped) along the closed geodesic polygon `corners`.
fn along(space: Space, corners: &[Complex64], lengths: &[f64], mut s: f64) -> Complex64 {
    let total: f64 = lengths.iter().sum();
    s = s.rem_euclid(total);
    for (i, &length) in lengths.iter().enumerate() {
        if s <= length || i + 1 == lengths.len() {
            let (p, q) = (corners[i], corners[(i + 1) % corners.len()]);
            let u = if length > 0.0 {
                (s / length).min(1.0)
            } else {
                0.0
            };
            let x = space.interpolate(space.to_ambient(p), space.to_ambient(q), u);
            return space.to_model(x);
        }
        s -= length;
    }
    corners[0]
}

fn walls(layout: &Layout, start: Pose, t: f64) -> Pose {
    let space = layout.space();
    let corners = walk_corners(layout);
    if corners.len() < 2 {
        return orbit(layout, start, t);
    }
    let lengths: Vec<f64> = (0..corners.len())
        .map(|i| space.distance(corners[i], corners[(i + 1) % corners.len()]))
        .collect();
    let total: f64 = lengths.iter().sum();
    // Start halfway along the first side; look a little ahead so corners are turned smoothly.
    let s = lengths[0] / 2.0 + t * total;
    let at = along(space, &corners, &lengths, s);
    let ahead = along(space, &corners, &lengths, s + 0.05 * total);
    Pose {
        at: [at.re, at.im],
        yaw: bearing(space, at, ahead),
        ..start
    }
}

fn keyframes(space: Space, keys: &[Pose], t: f64) -> Pose {
    if keys.len() == 1 {
        return keys[0];
    }
    let x = t.clamp(0.0, 1.0) * (keys.len() - 1) as f64;
    let k = (x.floor() as usize).min(keys.len() - 2);
    let u = x - k as f64;
    let (a, b) = (keys[k], keys[k + 1]);
    let p: DVec3 = space.to_ambient(Complex64::new(a.at[0], a.at[1]));
    let q: DVec3 = space.to_ambient(Complex64::new(b.at[0], b.at[1]));
    let at = space.to_model(space.interpolate(p, q, u));
    // The shorter way round between the two bearings.
    let turn = (b.yaw - a.yaw + 180.0).rem_euclid(360.0) - 180.0;
    Pose {
        at: [at.re, at.im],
        height: a.height + u * (b.height - a.height),
        yaw: a.yaw + u * turn,
        pitch: a.pitch + u * (b.pitch - a.pitch),
    }
}
