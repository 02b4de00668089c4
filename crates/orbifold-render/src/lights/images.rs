//! The mirror images of a light, through which it lights the room.
//!
//! A light seen in a chain of mirrors is, unfolded, the light moved by the product of the walls'
//! reflections: the image g·y in the tile g·P of the room's universal cover. Through a portal the
//! same holds with the portal's pairing in place of a reflection (ARCHITECTURE.md §11), so images
//! are enumerated across mirrors and portals alike. A connection to an
//! image, followed in the real room, bounces off those walls and arrives at the light; it counts
//! only if every wall it meets on the way is a mirror there, nothing blocks it, and it really
//! arrives (the tracer checks all three). Images are enumerated once per room, breadth first
//! across mirror walls, and kept while their largest possible contribution — reflectance bound
//! over J at their least possible distance — stays above a fraction of the direct light's
//! ([`ImageSet::new`]); so point lights light the room through mirrors, and area lights converge
//! without waiting for random hits.

use glam::{DMat3, DVec3};
use orbifold::space::Space;
use orbifold_scene::color::{Rgb, luminance};
use orbifold_trace::room::AnalyticRoom;
use rustc_hash::FxHashMap;

use super::connection::spread;

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
    /// The room's centre (ambient), which an image's g takes to its key.
    centre: DVec3,
}

/// Images are kept while their contribution bound is at least this fraction of the direct light's.
pub const IMAGE_CUTOFF: f64 = 1e-4;

/// At most this many images.
pub const MAX_IMAGES: usize = 4096;

impl ImageSet {
    /// The images of a room whose centre is `centre` (ambient), breadth first across walls that
    /// carry a mirror, while reflectance bound × J(radius)/J(least distance) ≥ [`IMAGE_CUTOFF`]
    /// and at most [`MAX_IMAGES`].
    ///
    /// ```
    /// use orbifold::{Layout, LayoutOptions};
    /// use orbifold_render::lights::ImageSet;
    /// use orbifold_trace::room::AnalyticRoom;
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
        // Each wall a path can cross: a mirror wall's reflection and the most any of its mirrors
        // reflects, per channel; a portal's pairing g (the tile across it is g(P)) and its
        // transmittance. A wall with mirrors on part of a portal is both.
        let mirrors: Vec<(DMat3, Rgb)> = room
            .walls
            .iter()
            // A wall drawn as a model circle (straight rays) is no isometry's mirror.
            .filter(|w| w.drawn_in.is_none())
            .flat_map(|w| {
                let best = w.mirrors.iter().fold([0.0f64; 3], |acc, m| {
                    [0, 1, 2].map(|c| acc[c].max(m.reflectance[c]))
                });
                let mirror =
                    (luminance(best) > 0.0).then(|| (reflection_matrix(space, w.form), best));
                let portal = w
                    .portal
                    .filter(|p| luminance(p.transmittance) > 0.0)
                    .map(|p| (p.across, p.transmittance));
                mirror.into_iter().chain(portal)
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
            for &(reflection, wall_reflectance) in &mirrors {
                let isometry = image.isometry * reflection;
                let key = isometry * centre;
                if set.find(key).is_some() {
                    continue;
                }
                let reflectance = [0, 1, 2].map(|c| image.reflectance[c] * wall_reflectance[c]);
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

    /// Whether, on the sphere, the tiles of these images — the room and its images across mirror
    /// walls — all lie in one closed hemisphere. A geodesic that carries light from a light image
    /// crosses only mirror walls, so it stays in these tiles; and no geodesic longer than π fits
    /// in a closed hemisphere. So when they fit, the walls block every way round the sphere (the
    /// long way to a light image is at least π long), and light sampling leaves those ways out.
    /// Conservative: a tile is convex, so it lies in the hemisphere when its corners and the
    /// middles of its walls do (the middles matter for a lune, whose corners are antipodal), and
    /// the hemisphere tried is the one centred on their mean with the tiles' centres (which
    /// matter for the hemisphere of `*`, whose one wall's start and middle are antipodal);
    /// `false` off the sphere.
    ///
    /// ```
    /// use orbifold::{Layout, LayoutOptions};
    /// use orbifold_render::lights::ImageSet;
    /// use orbifold_trace::room::AnalyticRoom;
    /// let layout = Layout::new(&"*222".parse()?, &LayoutOptions::default())?;
    /// let centre = |room: &AnalyticRoom| room.space.to_ambient(layout.centre);
    /// // Walls without mirrors: the room alone, an eighth of the sphere.
    /// let plain = AnalyticRoom::all_mirrors(&layout, 1.0, [0.0; 3])?;
    /// assert!(ImageSet::new(&plain, centre(&plain)).fit_in_a_hemisphere(&plain));
    /// // Every wall a mirror: the images cover the sphere.
    /// let mirrors = AnalyticRoom::all_mirrors(&layout, 1.0, [0.9; 3])?;
    /// assert!(!ImageSet::new(&mirrors, centre(&mirrors)).fit_in_a_hemisphere(&mirrors));
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn fit_in_a_hemisphere(&self, room: &AnalyticRoom) -> bool {
        let space = room.space;
        if space.kappa() <= 0.0 || room.walls.iter().any(|w| w.drawn_in.is_some()) {
            return false;
        }
        let outline: Vec<DVec3> = room
            .walls
            .iter()
            .flat_map(|w| [w.start, space.exp(w.start, w.tangent * (0.5 * w.length))])
            .chain([self.centre])
            .collect();
        let points: Vec<DVec3> = self
            .images
            .iter()
            .flat_map(|image| outline.iter().map(move |&p| image.isometry * p))
            .collect();
        let sum: DVec3 = points.iter().sum();
        if !sum.is_finite() || sum.length() <= 1e-9 {
            return false;
        }
        let pole = sum.normalize();
        points.iter().all(|p| pole.dot(*p) >= -1e-9)
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

#[cfg(test)]
mod tests {
    use super::*;

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
}
