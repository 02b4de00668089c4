//! The light sampler: which light a light sample aims at, through which of the room's mirror
//! images, and on the sphere which way round (pbrt's `LightSampler`, over the images of lights
//! as well as the lights).
//!
//! Light reaches a point of a mirror room from every mirror image of every light, along the
//! geodesic to the image, through the mirrors. The sampler chooses among **entries** ([`Entry`]),
//! each a (light, image, way) choice: on the sphere every geodesic comes back round, so a point is
//! lit along the short and the long way to each image and along both again after each time
//! round, as long as the mirrors on the way leave something of the light ([`MAX_WRAPS`],
//! [`WRAP_CUTOFF`]) and the walls do not block every way round (a room whose images across its
//! mirror walls fit in a hemisphere: [`crate::lights::ImageSet::fit_in_a_hemisphere`]);
//! elsewhere the way is always the short one.
//!
//! The choice mixes two distributions. One is fixed per scene: ∝ the light's power × the image's
//! bound on the mirrors' reflectance / J at the image's distance from the room's centre, J being
//! the geodesics' spread (the area a unit solid angle covers, [`crate::lights::spread`]). The
//! other is worked out afresh at every lit point over the **near images**, the first
//! [`NEAR_IMAGES`] images breadth first (the nearest tiles): the same power over J of the
//! connection from the point itself, times the cosine there ([`Integrator::near_weights`], in
//! SIMD registers several images at a time). A share [`NEAR_SHARE`] of the choices uses the
//! per-point weights. A path that hits a light after a BSDF sample asks the sampler for the
//! probability it had of choosing that light's image ([`Integrator::pmf_at`]), for multiple
//! importance sampling.

use glam::{DMat3, DVec3};
use orbifold_scene::color::luminance;
use orbifold_trace::fastmath::{asin_fast, ln_fast};
use orbifold_trace::geodesic::Ray;
use orbifold_trace::room::RoomSurface;

use super::{Integrator, mul};
use crate::lights::{TangentFrame, spread, turned};
use crate::sampler::Distribution1d;

/// One choice of the light sampler: a light, an image of the room, and (on the sphere) which
/// way round and how many times ([`crate::lights::turned`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct Entry {
    /// The light's index.
    pub(super) light: usize,
    /// The image's index in the integrator's image set.
    pub(super) image: usize,
    /// Half-turns round the sphere past the image: 0 the short way, 1 the long way, 2 the
    /// short way once more round, … (always 0 off the sphere).
    pub(super) turns: u32,
    /// What the extra times round cost at most: the mirrors' reflectance over one time round,
    /// to the power of the number of times (1 for the short and the long way).
    pub(super) attenuation: f64,
    /// The image of the light's centre (ambient) and its height.
    pub(super) position: DVec3,
    pub(super) height: f64,
}

/// The first images (breadth first: the nearest tiles) whose light-sampling weights are worked
/// out afresh at every surface point.
const NEAR_IMAGES: usize = 24;

/// The most (light, image, way) choices weighted per surface point.
pub(super) const NEAR_MAX: usize = 96;

/// The share of light samples that use the per-point weights.
const NEAR_SHARE: f64 = 0.5;

/// On the sphere, light sampling follows the geodesics to each image that go round the sphere
/// up to this many times more (fewer where the mirrors take the light out sooner:
/// [`WRAP_CUTOFF`]). A bounce that reaches a light further round still counts it, unweighted.
const MAX_WRAPS: u32 = 16;

/// The times round are kept while the mirrors' reflectance over them is at least this.
const WRAP_CUTOFF: f64 = 1e-3;

/// Per-point weights treat nothing as closer than this (intrinsic units).
const NEAR_CLAMP: f64 = 0.05;

/// Per-point weights use at least this cosine (a light has a size: part of it can be above the
/// surface's horizon while its centre is below).
const COSINE_FLOOR: f64 = 0.05;

/// A surface normal as the per-point light weights use it: its horizontal part (an ambient
/// tangent vector at the point, of length √(1 − up²)) and its vertical part.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub(super) struct Normal {
    across: DVec3,
    up: f64,
}

impl Normal {
    /// The normal `local` (unit, in `frame`'s local coordinates).
    pub(super) fn new(frame: &TangentFrame, local: DVec3) -> Normal {
        let (across, up) = frame.to_ambient(local);
        Normal { across, up }
    }
}

/// The near light images as the per-point weights use them, one array per quantity so that the
/// loop over them runs several images at a time in SIMD registers (it runs at every path
/// vertex, over up to `NEAR_MAX` images).
#[derive(Clone, Debug, Default)]
pub(super) struct NearImages {
    /// Ambient position of the image of the light's centre.
    x: Vec<f64>,
    y: Vec<f64>,
    z: Vec<f64>,
    height: Vec<f64>,
    /// 1 for the long way round the sphere (σ → 2π − σ), else 0.
    long_way: Vec<f64>,
    /// Luminance of the light's power × the image's reflectance.
    power: Vec<f64>,
}

impl NearImages {
    fn new(images: impl Iterator<Item = (DVec3, f64, bool, f64)>) -> NearImages {
        let mut near = NearImages::default();
        for (position, height, long_way, power) in images {
            near.x.push(position.x);
            near.y.push(position.y);
            near.z.push(position.z);
            near.height.push(height);
            near.long_way.push(if long_way { 1.0 } else { 0.0 });
            near.power.push(power);
        }
        near
    }

    /// The weights at `(x, h)` with normal `(across, up)` and `floor` in a geometry of
    /// curvature `k` whose sign is `K` (see [`Integrator::near_weights`]), and their sum.
    /// Straight-line code: the inverse functions are `fastmath`'s, the branches selects.
    #[inline(always)]
    fn weights<const K: i32>(
        &self,
        k: f64,
        (x, h, normal, floor): (DVec3, f64, Normal, f64),
        weights: &mut [f64; NEAR_MAX],
    ) -> f64 {
        let Normal { across, up } = normal;
        let n = self.x.len().min(NEAR_MAX);
        let (px, py, pz) = (&self.x[..n], &self.y[..n], &self.z[..n]);
        let (height, long_way, power) = (&self.height[..n], &self.long_way[..n], &self.power[..n]);
        for i in 0..n {
            // σ and S(σ) from the chord c = 2 S(σ/2): S(σ) = c √(1 − κc²/4), with one inverse
            // function.
            let (dx, dy, dz) = (x.x - px[i], x.y - py[i], x.z - pz[i]);
            let c = (dx * dx + dy * dy + k * dz * dz).max(0.0).sqrt();
            let half = 0.5 * c;
            let sigma = match K {
                1 => 2.0 * asin_fast(half.min(1.0)),
                -1 => 2.0 * ln_fast(half + (half * half + 1.0).sqrt()),
                _ => c,
            };
            let sine = if K == 0 {
                c
            } else {
                c * (1.0 - k * half * half).max(0.0).sqrt()
            };
            // The normal's horizontal part along the initial direction u of the geodesic to the
            // image, times σ: ⟨n, y − x⟩ = S(σ)⟨n, u⟩ (σ⟨n, u⟩ in E²); the long way round
            // leaves x along −u and is 2π − σ long.
            let toward = -(across.x * dx + across.y * dy + k * across.z * dz);
            let horizontal = toward * (sigma - long_way[i] * std::f64::consts::TAU)
                / sine.max(f64::MIN_POSITIVE);
            let sigma = sigma + long_way[i] * (std::f64::consts::TAU - 2.0 * sigma);
            let dh = height[i] - h;
            let length2 = sigma * sigma + dh * dh;
            let ratio = if sigma > 1e-9 { sine / sigma } else { 1.0 };
            let cosine = ((horizontal + up * dh) / length2.sqrt()).clamp(COSINE_FLOOR, 1.0);
            weights[i] = power[i] * cosine / (length2 * ratio).max(floor);
        }
        weights[..n].iter().sum()
    }
}

impl Integrator {
    /// The light sampler's choices and weights: power × image reflectance / J(distance of the
    /// image from the room's centre, at least the room's size).
    pub(super) fn build_light_distribution(&mut self, height: f64) {
        let space = self.tracer.space();
        let size = self
            .tracer
            .room
            .walls
            .iter()
            .map(|w| space.ambient_distance(self.centre, w.start))
            .fold(height, f64::max);
        let floor = spread(space, size, size);
        // Every geodesic of the sphere comes back round: a point is lit along the short and the
        // long way to each image and along both again after each time round, as long as the
        // mirrors on the way leave something of the light.
        let once_round = self.reflectance_once_round(height);
        let wraps = if space.kappa() > 0.0 && once_round > 0.0 {
            let cut = (WRAP_CUTOFF.ln() / once_round.ln()).ceil();
            if cut.is_finite() {
                (cut as u32).min(MAX_WRAPS)
            } else {
                MAX_WRAPS
            }
        } else {
            0
        };
        // Where the room and its images across mirror walls fit in a hemisphere, the walls
        // block every way round ([`crate::lights::ImageSet::fit_in_a_hemisphere`]): only the
        // short ways are worth a light sample.
        let round_the_sphere =
            space.kappa() > 0.0 && !self.images.fit_in_a_hemisphere(&self.tracer.room);
        let turns = if round_the_sphere { 2 * (wraps + 1) } else { 1 };
        let mut weights = Vec::new();
        for (l, light) in self.lights.iter().enumerate() {
            for (k, image) in self.images.images.iter().enumerate() {
                let y = image.isometry * light.position;
                let d = space.ambient_distance(self.centre, y);
                for t in 0..turns {
                    let sigma = turned(d, t).0;
                    let attenuation = once_round.powi((t / 2) as i32);
                    // J at least the room's size's, and for the times round at least what
                    // it is that far round from a point as far from the image as the room is
                    // wide: the image's distance from the centre can put it at a focus (J → 0)
                    // that hardly any lit point is near.
                    let j = spread(space, sigma, sigma).max(floor * (sigma / size).max(1.0));
                    let w = luminance(mul(light.power, image.reflectance)) * attenuation / j;
                    if w > 0.0 && w.is_finite() {
                        if k < NEAR_IMAGES && t < 2 && self.near.len() < NEAR_MAX {
                            self.near.push(self.entries.len());
                        }
                        self.entries.push(Entry {
                            light: l,
                            image: k,
                            turns: t,
                            attenuation,
                            position: y,
                            height: light.height,
                        });
                        weights.push(w);
                    }
                }
            }
        }
        self.distribution = Distribution1d::new(&weights);
        self.near_images = NearImages::new(self.near.iter().map(|&e| {
            let entry = &self.entries[e];
            let image = &self.images.images[entry.image];
            let power = luminance(mul(self.lights[entry.light].power, image.reflectance));
            (entry.position, entry.height, entry.turns == 1, power)
        }));
    }

    /// The luminance of the mirrors' reflectance over one time round the sphere, on average
    /// over horizontal great circles from the room's centre at `height` (walls only: the
    /// objects may let the light through elsewhere); 0 off the sphere.
    fn reflectance_once_round(&self, height: f64) -> f64 {
        const DIRECTIONS: usize = 16;
        let space = self.space();
        if space.kappa() <= 0.0 {
            return 0.0;
        }
        let room = &self.tracer.room;
        let h = 0.5 * height;
        let mut sum = 0.0;
        for i in 0..DIRECTIONS {
            let angle = std::f64::consts::TAU * (i as f64 + 0.5) / DIRECTIONS as f64;
            let u = self.centre_frame.e1 * angle.cos() + self.centre_frame.e2 * angle.sin();
            let mut ray = Ray::new(space, self.centre, u, h, 0.0);
            let (mut travelled, mut carried) = (0.0, 1.0);
            while carried > 0.0 {
                let Some(exit) = room.exit(&ray) else {
                    carried = 0.0;
                    break;
                };
                // The crossings of one time round only.
                if travelled + exit.s >= std::f64::consts::TAU {
                    break;
                }
                let RoomSurface::Wall(w) = exit.surface else {
                    carried = 0.0;
                    break;
                };
                let Some(passage) = room.passage(w, exit.point, exit.height) else {
                    carried = 0.0;
                    break;
                };
                carried *= luminance(passage.throughput);
                travelled += exit.s;
                ray = (ray.continued(space, exit.s, exit.point, exit.tangent))
                    .passed(space, &passage);
            }
            sum += carried;
        }
        sum / DIRECTIONS as f64
    }

    /// The per-point weights of the `near` choices at (x, h) (power × reflectance bound / J of
    /// the connection to the image's centre × the cosine there) into `weights`; returns their
    /// sum. `normal` is the unit normal at x.
    ///
    /// The cosine at x of the geodesic to an image at horizontal distance σ and height
    /// difference Δh is (⟨n_h, u⟩ σ + up·Δh)/ℓ for the unit horizontal direction u of the
    /// geodesic, where ⟨n_h, u⟩ = ⟨n_h, y − x⟩/S(σ) for the image's position y: one dot
    /// product. Images behind the surface then weigh next to nothing (the cosine's floor), and
    /// on the floor and the ceiling far images weigh as 1/ℓ³ rather than 1/ℓ².
    pub(super) fn near_weights(
        &self,
        x: DVec3,
        h: f64,
        normal: Normal,
        weights: &mut [f64; NEAR_MAX],
    ) -> f64 {
        orbifold_trace::with_avx512!(
            Integrator,
            self.near_weights_portable(
                x: DVec3,
                h: f64,
                normal: Normal,
                weights: &mut [f64; NEAR_MAX],
            ) -> f64
        )
    }

    #[inline(always)]
    fn near_weights_portable(
        &self,
        x: DVec3,
        h: f64,
        normal: Normal,
        weights: &mut [f64; NEAR_MAX],
    ) -> f64 {
        let space = self.space();
        let floor = spread(space, NEAR_CLAMP, NEAR_CLAMP);
        let at = (x, h, normal, floor);
        let k = space.kappa();
        if k > 0.0 {
            self.near_images.weights::<1>(k, at, weights)
        } else if k < 0.0 {
            self.near_images.weights::<-1>(k, at, weights)
        } else {
            self.near_images.weights::<0>(k, at, weights)
        }
    }

    /// Picks a light-sampling choice with the per-point weights of the near images (and their
    /// sum `total`, from [`Integrator::near_weights`]): with probability `NEAR_SHARE` among
    /// the near images by those weights, else from the scene-wide distribution. Returns the
    /// entry and its probability.
    pub(super) fn pick_entry_with(
        &self,
        weights: &[f64; NEAR_MAX],
        total: f64,
        u: f64,
    ) -> Option<(usize, f64)> {
        let distribution = self.distribution.as_ref()?;
        let share = if total > 0.0 && total.is_finite() {
            NEAR_SHARE
        } else {
            0.0
        };
        let index = if u < share {
            let mut target = u / share * total;
            let mut chosen = self.near[self.near.len() - 1];
            for (w, &e) in weights.iter().zip(&self.near) {
                if target < *w {
                    chosen = e;
                    break;
                }
                target -= w;
            }
            chosen
        } else {
            distribution.sample((u - share) / (1.0 - share)).0
        };
        Some((index, self.entry_pmf(index, weights, total, share)))
    }

    /// The probability of [`Integrator::pick_entry_with`] choosing `index`, given the per-point
    /// weights.
    fn entry_pmf(&self, index: usize, weights: &[f64; NEAR_MAX], total: f64, share: f64) -> f64 {
        let global = self.distribution.as_ref().map_or(0.0, |d| d.pmf(index));
        // `near` lists its entries in increasing order (they are pushed as they are made).
        let near = match self.near.binary_search(&index) {
            Ok(i) if share > 0.0 => weights[i] / total,
            _ => 0.0,
        };
        share * near + (1.0 - share) * global
    }

    /// The probability of [`Integrator::pick_entry_with`] at (x, h) with unit normal `normal`
    /// choosing `index`.
    pub(super) fn pmf_at(&self, x: DVec3, h: f64, normal: Normal, index: usize) -> f64 {
        let mut weights = [0.0; NEAR_MAX];
        let total = self.near_weights(x, h, normal, &mut weights);
        let share = if total > 0.0 && total.is_finite() {
            NEAR_SHARE
        } else {
            0.0
        };
        self.entry_pmf(index, &weights, total, share)
    }

    /// The entry of (`light`, `image`, `turns`), if light sampling draws it.
    pub(super) fn entry_index(&self, light: usize, image: usize, turns: u32) -> Option<usize> {
        // Entries are in (light, image, turns) order with some left out: binary search.
        let key = (light, image, turns);
        self.entries
            .binary_search_by(|e| (e.light, e.image, e.turns).cmp(&key))
            .ok()
    }

    /// Whether light sampling can draw the image of light `light` that a path sees after
    /// meeting the walls of `chain` (not round the sphere: the bounce footprint is off there).
    pub(super) fn samples_image(&self, light: usize, chain: &DMat3) -> bool {
        self.images
            .find_chain(chain)
            .is_some_and(|image| self.entry_index(light, image, 0).is_some())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::integrator::Settings;
    use proptest::prelude::*;

    /// The ways round the sphere among the light sampler's choices of a spherical room of
    /// `signature` whose walls listed in `mirrors` carry a mirror.
    fn ways_round(signature: &str, mirrors: &[usize]) -> usize {
        let mut scene = orbifold_scene::Scene::default();
        scene.orbifold.signature = signature.into();
        scene.room.mirrors = orbifold_scene::MirrorDefault::None;
        scene.walls = mirrors
            .iter()
            .map(|&index| orbifold_scene::Wall {
                index,
                material: None,
                mirrors: vec![orbifold_scene::Mirror {
                    from: 0.0,
                    to: 1.0,
                    bottom: 0.0,
                    top: None,
                    reflectance: [0.9; 3],
                }],
            })
            .collect();
        let integrator = Integrator::from_scene(&scene, None, Settings::default()).unwrap();
        integrator.entries.iter().filter(|e| e.turns > 0).count()
    }

    #[test]
    fn light_samples_go_round_the_sphere_only_where_the_walls_let_them() {
        // No mirror, or mirrors that all meet at one corner: the room's images fit in a
        // hemisphere (the octant and its images round a right-angled corner), so every way
        // round is blocked. Three mirrors: the images cover the sphere.
        assert_eq!(ways_round("*222", &[]), 0);
        assert_eq!(ways_round("*222", &[0]), 0);
        assert_eq!(ways_round("*222", &[0, 1]), 0);
        assert_eq!(ways_round("*235", &[1, 2]), 0);
        assert!(ways_round("*222", &[0, 1, 2]) > 0);
        assert!(ways_round("*235", &[0, 1, 2]) > 0);
        // The hemisphere of `*` with its one wall a mirror: the whole sphere.
        assert_eq!(ways_round("*", &[]), 0);
        assert!(ways_round("*", &[0]) > 0);
    }

    proptest! {
        /// The per-point weights' cosine is the true one: on a face whose normal is level, at
        /// the light's height, turning the face round divides each image's weight by the cosine
        /// towards it and multiplies it by the cosine away from it (each at least the floor).
        /// The cosine comes from the geodesic's initial direction, `Space::log`, here.
        #[test]
        fn light_weights_face_the_images_in_front(
            g in 0usize..3, a in -0.3f64..0.3, b in -0.3f64..0.3, turn in 0.0f64..std::f64::consts::TAU,
        ) {
            let signature = ["*235", "*2222", "*2223"][g];
            let mut scene = orbifold_scene::Scene::default();
            scene.orbifold.signature = signature.into();
            scene.lights[0].kind = orbifold_scene::LightKind::Sphere;
            let integrator = Integrator::from_scene(&scene, None, Settings::default()).unwrap();
            let space = integrator.space();
            let x = space.exp(
                integrator.centre,
                space.transport(DVec3::Z, integrator.centre, DVec3::new(a, b, 0.0)),
            );
            let frame = TangentFrame::at(space, x);
            let local = DVec3::new(turn.cos(), turn.sin(), 0.0);
            let h = integrator.near_images.height[0];
            let (mut front, mut back) = ([0.0; NEAR_MAX], [0.0; NEAR_MAX]);
            integrator.near_weights_portable(x, h, Normal::new(&frame, local), &mut front);
            integrator.near_weights_portable(x, h, Normal::new(&frame, -local), &mut back);
            let images = &integrator.near_images;
            let (n_h, _) = frame.to_ambient(local);
            for i in 0..images.x.len().min(NEAR_MAX) {
                let y = DVec3::new(images.x[i], images.y[i], images.z[i]);
                let v = space.log(x, y);
                let sigma = space.point_dot(v, v).max(0.0).sqrt();
                prop_assume!(sigma > 1e-6 && (images.height[i] - h).abs() < 1e-12);
                let mut cosine = space.point_dot(n_h, v) / sigma;
                if images.long_way[i] == 1.0 {
                    cosine = -cosine;
                }
                let clamp = |c: f64| c.clamp(COSINE_FLOOR, 1.0);
                let expected = clamp(cosine) / clamp(-cosine);
                let ratio = front[i] / back[i];
                prop_assert!(
                    (ratio / expected - 1.0).abs() < 1e-6,
                    "{signature}, image {i}: {ratio} against {expected}"
                );
            }
        }
    }

    #[test]
    fn the_avx2_light_image_weights_are_the_portable_ones_bit_for_bit() {
        // What `near_weights` runs on a processor with AVX2 against the portable body, at random
        // points of a spherical, a Euclidean and a hyperbolic room of mirrors.
        for signature in ["*235", "*2222", "*2223"] {
            let mut scene = orbifold_scene::Scene::default();
            scene.orbifold.signature = signature.into();
            scene.lights[0].kind = orbifold_scene::LightKind::Sphere;
            let integrator = Integrator::from_scene(&scene, None, Settings::default()).unwrap();
            let space = integrator.space();
            let mut seed = 11u64;
            let mut u = move || {
                seed = seed
                    .wrapping_mul(6364136223846793005)
                    .wrapping_add(1442695040888963407);
                (seed >> 11) as f64 / (1u64 << 53) as f64
            };
            for _ in 0..500 {
                let v = DVec3::new(u() - 0.5, u() - 0.5, 0.0) * 0.4;
                let x = space.exp(
                    integrator.centre,
                    space.transport(DVec3::Z, integrator.centre, v),
                );
                let h = u();
                let local = DVec3::new(u() - 0.5, u() - 0.5, u() - 0.5).normalize();
                let normal = Normal::new(&TangentFrame::at(space, x), local);
                let (mut a, mut b) = ([0.0; NEAR_MAX], [0.0; NEAR_MAX]);
                let total_a = integrator.near_weights(x, h, normal, &mut a);
                let total_b = integrator.near_weights_portable(x, h, normal, &mut b);
                assert_eq!(total_a.to_bits(), total_b.to_bits(), "{signature}");
                assert_eq!(a.map(f64::to_bits), b.map(f64::to_bits), "{signature}");
                assert!(total_a > 0.0, "{signature}");
            }
        }
    }

    #[test]
    fn a_time_round_the_sphere_crosses_every_mirror_line_twice() {
        // A great circle meets each great circle of the tiling's mirror lines twice: once round
        // a room of mirrors of reflectance 0.9 with 1, 2 and 3 such lines carries 0.9² , 0.9⁴
        // and 0.9⁶ (whatever the direction, as long as it misses the corners).
        for (signature, lines) in [("*", 1), ("*22", 2), ("*222", 3)] {
            let mut scene = orbifold_scene::Scene::default();
            scene.orbifold.signature = signature.into();
            scene.room.reflectance = [0.9; 3];
            let integrator = Integrator::from_scene(&scene, None, Settings::default()).unwrap();
            let once = integrator.reflectance_once_round(scene.room.height);
            let expected = 0.9f64.powi(2 * lines);
            assert!(
                (once - expected).abs() < 1e-9,
                "{signature}: {once} against {expected}"
            );
        }
        let mut flat = orbifold_scene::Scene::default();
        flat.orbifold.signature = "*2222".into();
        let integrator = Integrator::from_scene(&flat, None, Settings::default()).unwrap();
        assert_eq!(integrator.reflectance_once_round(flat.room.height), 0.0);
    }
}
