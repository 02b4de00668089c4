//! Where the things a scene file leaves unplaced go: the camera, the default object and light,
//! and any object or light without an `at`.
//!
//! [`Scene::default`] is the seed's `*22222` room, and its camera, figure and light are placed
//! for that room. Another signature's polygon may lie elsewhere in the model (a Euclidean
//! polygon has a corner at the origin, not its centre), so those defaults can fall outside it.
//! A position the user did not write is therefore placed for the room it is in, the way
//! `orbifold scene new SIG` places them: objects and lights at the polygon's centre, the camera
//! on the −x side of the centre, three quarters of the way to the wall, looking at the centre.
//! A height the user did not write that would be above the ceiling follows the room's height
//! (the camera's eye at half of it, a light at nine tenths: the defaults' values in the default
//! room, whose height is 1).
//!
//! Reading a file keeps every unwritten default that already lies inside the room, so a file
//! that loaded before means what it meant; only when one of them would be outside are all the
//! unwritten positions placed for the room together (so the camera looks at the object).
//! Positions the user wrote are never moved: one outside the room stays an error at its line.

use num_complex::Complex64;
use orbifold::layout::Layout;

use crate::document::Scene;

/// Where a new scene's camera stands in `layout`'s room: on the −x side of the centre, three
/// quarters of the way to the wall, so that it looks across the room at the object in the
/// middle (yaw 0) rather than from inside it. Rooms open to infinity stop at model distance 1.
///
/// ```
/// use orbifold_scene::{Scene, placement};
/// let mut scene = Scene::default();
/// scene.orbifold.signature = "*444".into();
/// let layout = scene.layout().unwrap();
/// let at = placement::camera_position(&layout);
/// assert!(placement::is_inside(&layout, at));
/// assert!(at[0] < layout.centre.re);
/// ```
pub fn camera_position(layout: &Layout) -> [f64; 2] {
    let inside = |t: f64| is_inside(layout, [layout.centre.re - t, layout.centre.im]);
    // The model distance to the wall by bisection; rooms open to infinity stop at 1.
    let (mut lo, mut hi) = (0.0, 1.0);
    if inside(hi) {
        lo = hi;
    } else {
        for _ in 0..60 {
            let mid = 0.5 * (lo + hi);
            if inside(mid) {
                lo = mid;
            } else {
                hi = mid;
            }
        }
    }
    // The bisection assumes the points inside along the ray form one segment; should they not,
    // come closer to the centre until the point is inside.
    let mut t = 0.75 * lo;
    for _ in 0..60 {
        if inside(t) {
            break;
        }
        t *= 0.5;
    }
    [layout.centre.re - t, layout.centre.im]
}

/// Whether the model point `at` lies strictly inside `layout`'s polygon (the test that scene
/// validation applies to every position).
///
/// ```
/// use orbifold_scene::{Scene, placement};
/// let layout = Scene::default().layout().unwrap();
/// assert!(placement::is_inside(&layout, [0.0, 0.0]));
/// assert!(!placement::is_inside(&layout, [0.99, 0.0]));
/// ```
pub fn is_inside(layout: &Layout, at: [f64; 2]) -> bool {
    let space = layout.space();
    let z = Complex64::new(at[0], at[1]);
    if space.kappa() < 0.0 && z.norm() >= 1.0 {
        return false;
    }
    let p = space.to_ambient(z);
    layout.edges.iter().all(|e| e.wall.dot(p) > 0.0)
}

/// Which of a scene's placements its file spells out.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Written {
    /// `camera.at`.
    pub camera_at: bool,
    /// `camera.height`.
    pub camera_height: bool,
    /// Per object, whether its `at` is written (empty when the file has no `[[objects]]`: the
    /// default object is not written).
    pub objects_at: Vec<bool>,
    /// Per light, whether its `at` is written (empty without `[[lights]]`).
    pub lights_at: Vec<bool>,
    /// Per light, whether its `height` is written.
    pub lights_height: Vec<bool>,
}

impl Written {
    /// What the TOML table of a scene file writes.
    ///
    /// ```
    /// use orbifold_scene::placement::Written;
    /// let table: toml::Table = "[camera]\nat = [0.1, 0.0]\n[[lights]]\nheight = 0.5\n"
    ///     .parse()
    ///     .unwrap();
    /// let written = Written::of(&table);
    /// assert!(written.camera_at && !written.camera_height);
    /// assert_eq!((written.lights_at, written.lights_height), (vec![false], vec![true]));
    /// ```
    pub fn of(table: &toml::Table) -> Written {
        let has = |section: Option<&toml::Value>, key: &str| {
            section
                .and_then(toml::Value::as_table)
                .is_some_and(|t| t.contains_key(key))
        };
        let each = |name: &str, key: &str| -> Vec<bool> {
            table
                .get(name)
                .and_then(toml::Value::as_array)
                .map(|items| items.iter().map(|item| has(Some(item), key)).collect())
                .unwrap_or_default()
        };
        Written {
            camera_at: has(table.get("camera"), "at"),
            camera_height: has(table.get("camera"), "height"),
            objects_at: each("objects", "at"),
            lights_at: each("lights", "at"),
            lights_height: each("lights", "height"),
        }
    }
}

impl Scene {
    /// The default scene for `signature`, as `orbifold scene new SIG` writes it: the default
    /// room's figure and light at the centre of this signature's polygon and the camera placed
    /// for it ([`camera_position`]). An error says why the signature has no room.
    ///
    /// ```
    /// use orbifold_scene::Scene;
    /// let scene = Scene::for_signature("*2∞3").unwrap();
    /// assert!(scene.check(None).is_ok());
    /// assert!(Scene::for_signature("*23").is_err()); // a bad orbifold: no room
    /// ```
    pub fn for_signature(signature: &str) -> Result<Scene, String> {
        let mut scene = Scene {
            orbifold: crate::OrbifoldSection {
                signature: signature.to_string(),
                ..Default::default()
            },
            ..Scene::default()
        };
        let layout = scene.layout()?;
        scene.place(&layout, &Written::default());
        Ok(scene)
    }

    /// Places the positions and heights that `written` says the file left out for the room
    /// they are in (see the module documentation); a scene whose signature has no polygon is
    /// left as it is, for validation to report.
    pub fn place_unwritten(&mut self, written: &Written) {
        // Heights as positions: a default that fits under the ceiling stays.
        let height = self.room.height;
        if height.is_finite() && height > 0.0 {
            if !written.camera_height && self.camera.height > height {
                self.camera.height = 0.5 * height;
            }
            for (i, light) in self.lights.iter_mut().enumerate() {
                if !written.lights_height.get(i).copied().unwrap_or(false) && light.height > height
                {
                    light.height = 0.9 * height;
                }
            }
        }
        let Ok(layout) = self.layout() else {
            return;
        };
        let object_written = |i: usize| written.objects_at.get(i).copied().unwrap_or(false);
        let light_written = |i: usize| written.lights_at.get(i).copied().unwrap_or(false);
        let fits = (written.camera_at || is_inside(&layout, self.camera.at))
            && self
                .objects
                .iter()
                .enumerate()
                .all(|(i, o)| object_written(i) || is_inside(&layout, o.at))
            && self
                .lights
                .iter()
                .enumerate()
                .all(|(i, l)| light_written(i) || is_inside(&layout, l.at));
        if !fits {
            self.place(&layout, written);
        }
    }

    /// Puts every position `written` leaves out where `orbifold scene new` puts it.
    fn place(&mut self, layout: &Layout, written: &Written) {
        let centre = [layout.centre.re, layout.centre.im];
        for (i, object) in self.objects.iter_mut().enumerate() {
            if !written.objects_at.get(i).copied().unwrap_or(false) {
                object.at = centre;
            }
        }
        for (i, light) in self.lights.iter_mut().enumerate() {
            if !written.lights_at.get(i).copied().unwrap_or(false) {
                light.at = centre;
            }
        }
        if !written.camera_at {
            self.camera.at = camera_position(layout);
        }
    }
}
