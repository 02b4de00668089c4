//! A pixel's footprint carried along its camera ray through the mirrors, and what it does for
//! the tiny mirror images of sphere lights (ARCHITECTURE.md §8; docs/rendering.md).
//!
//! In a mirror room the camera sees a crowd of light images, most of them smaller than a pixel
//! (thousands of them in a hyperbolic room). A camera ray either hits such an image or misses it,
//! so a pixel that holds one gets a few rays of enormous radiance among many dark ones: the
//! worst noise of the image, and too sparse for a denoiser. Instead each camera ray carries its
//! pixel's footprint — a rectangle across the ray, one pixel wide — and a sphere light whose
//! image is at most a few footprints wide adds its radiance times the share of the footprint
//! that the sphere covers ([`sphere_coverage`]), whether the ray's centre line hits it or not.
//! Larger images are left to the ray hits, which already resolve them.
//!
//! **Centred on the pixel.** The rectangle is the pixel's own: each ray carries the turns that
//! lead from it to its pixel's centre ([`Footprint::centre`]), which grow along the ray as the
//! widths do and change sides at every mirror. So every sample of a pixel counts the same share
//! — the pixel's box filter, exactly what its ray hits average to — and the samples' variance
//! vanishes but for the rims that hits hide behind an image. (A rectangle centred on each
//! sample's ray keeps the image's total but blurs it over the neighbouring pixels too, and its
//! share still varies with where the sample lies in the pixel.) A capped footprint (below) is
//! narrower than its pixel and stays centred on the ray.
//!
//! **Widths.** Walls are totally geodesic and the vertical plane over a horizontal geodesic is
//! flat, so a ray's neighbours separate like Jacobi fields of the two factors: a turn ε across
//! the ray (horizontally) moves the point at arc length s by ε·|S_κ(s cos α)|/cos α, a turn ε
//! in the vertical plane by ε·s. Mirrors are isometries and keep both.
//!
//! **Where images are found.** A march keeps the ray in the room, folding it at every mirror,
//! and so meets only the light's images in the copies of the room that the ray crosses; and a
//! ray that ends on the floor or the ceiling before it passes the light cannot count it. So the
//! footprint is capped where it could reach past a wall, the floor or the ceiling: at twice
//! the light's clearance from them, less the light's diameter. The image's total does not depend
//! on the widths as long as they are at most the true spread of the pixel's rays (the covered
//! share integrates to the light's area over the footprint's); capped widths only leave more
//! variance.
//!
//! **Coverage.** Near the light the metric is that of flat space to within the light's size.
//! The sphere's outline across the ray is a disc of radius r; its area inside the footprint's
//! rectangle has a closed form ([`disc_in_rectangle`]), exact and smooth in the offset. (A
//! square of the same area, used before, is exact in the mean too, but draws an image a few
//! pixels wide as a square.)

use glam::DVec3;
use orbifold::space::Space;

use crate::fastmath::asinh_fast;
use crate::geodesic::Ray;

/// The angular size of a pixel seen from the camera: its width across (horizontally) and its
/// height (in the vertical plane of the ray), in radians.
///
/// ```
/// use orbifold::{Geometry, space::Space};
/// use orbifold_trace::footprint::Footprint;
/// let footprint = Footprint { across: 1e-3, up: 1e-3, centre: [0.0; 2] };
/// let e2 = Space::new(Geometry::Euclidean);
/// // In flat space both widths grow linearly with distance.
/// let (w, h) = footprint.widths(e2, 10.0, 0.8);
/// assert!((w - 1e-2).abs() < 1e-15 && (h - 1e-2).abs() < 1e-15);
/// // In H² the width across grows like sinh: neighbouring rays diverge.
/// let h2 = Space::new(Geometry::Hyperbolic);
/// assert!(footprint.widths(h2, 10.0, 1.0).0 > 10.0);
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Footprint {
    /// The pixel's width across the ray (radians).
    pub across: f64,
    /// The pixel's height in the ray's vertical plane (radians).
    pub up: f64,
    /// Where the pixel's centre is seen from the camera, relative to this ray: the turn across
    /// (to the left, horizontally: the bearing's change times the cosine of the elevation) and
    /// up (the elevation's change), in radians. Coverage is counted over the pixel itself, so
    /// that every sample of a pixel counts a small light image alike ([`sphere_coverage`]);
    /// zero for a footprint centred on the ray.
    pub centre: [f64; 2],
}

impl Footprint {
    /// The footprint's widths (across, up) at arc length `s` from the camera along a ray whose
    /// elevation has cosine `cos_elevation`.
    pub fn widths(&self, space: Space, s: f64, cos_elevation: f64) -> (f64, f64) {
        let ca = cos_elevation.abs();
        let sigma = s * ca;
        // S_κ(σ)/cos α → s as the ray turns vertical.
        let spread = if sigma < 1e-6 {
            s
        } else {
            space.sin(sigma).abs() / ca
        };
        (self.across * spread, self.up * s)
    }

    /// The footprint after a mirror: a reflection swaps left and right, so the pixel's centre
    /// is now on the other side of the ray.
    ///
    /// ```
    /// use orbifold_trace::footprint::Footprint;
    /// let footprint = Footprint { across: 1e-3, up: 1e-3, centre: [2e-4, -1e-4] };
    /// assert_eq!(footprint.reflected().centre, [-2e-4, -1e-4]);
    /// ```
    pub fn reflected(&self) -> Footprint {
        Footprint {
            centre: [-self.centre[0], self.centre[1]],
            ..*self
        }
    }
}

/// A sphere light as the footprint sees it.
///
/// ```
/// use glam::DVec3;
/// use orbifold::{Geometry, space::Space};
/// use orbifold_trace::footprint::Sphere;
/// let h2 = Space::new(Geometry::Hyperbolic);
/// let sphere = Sphere::new(h2, DVec3::Z, 0.5, 0.1, 0.4, 0.5);
/// assert_eq!((sphere.radius(), sphere.clearance()), (0.1, 0.4));
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Sphere {
    centre: DVec3,
    height: f64,
    radius: f64,
    clearance: f64,
    /// S_κ(clearance), or ∞ where no geodesic is that far across (S² beyond π/2): what a ray's
    /// sine of the centre's offset across it is measured against, with no inverse sine for
    /// the many stretches that pass far from the light.
    clearance_sine: f64,
    headroom: f64,
}

impl Sphere {
    /// The sphere light centred at the ambient point `centre` and `height`, of outline radius
    /// `radius`, `clearance` (horizontal distance) from the nearest wall and `headroom`
    /// (vertical) from the floor or the ceiling, whichever is nearer.
    pub fn new(
        space: Space,
        centre: DVec3,
        height: f64,
        radius: f64,
        clearance: f64,
        headroom: f64,
    ) -> Sphere {
        let clearance_sine = if space.kappa() > 0.0 && clearance >= std::f64::consts::FRAC_PI_2 {
            f64::INFINITY
        } else {
            space.sin(clearance)
        };
        Sphere {
            centre,
            height,
            radius,
            clearance,
            clearance_sine,
            headroom,
        }
    }

    /// Ambient horizontal position of the centre.
    pub fn centre(&self) -> DVec3 {
        self.centre
    }

    /// Height of the centre.
    pub fn height(&self) -> f64 {
        self.height
    }

    /// Radius of the outline.
    pub fn radius(&self) -> f64 {
        self.radius
    }

    /// Horizontal distance from the centre to the nearest wall.
    pub fn clearance(&self) -> f64 {
        self.clearance
    }

    /// Vertical distance from the centre to the floor or the ceiling, whichever is nearer.
    pub fn headroom(&self) -> f64 {
        self.headroom
    }
}

/// What a sphere light looks like to a camera ray along one straight stretch (between mirrors).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Glimpse {
    /// The light's image is more than [`GLIMPSE_WIDTHS`] footprints wide there (or not near
    /// this stretch): ray hits resolve it.
    Unresolved,
    /// The image is at most [`GLIMPSE_WIDTHS`] footprints wide: this share of the footprint is
    /// the light.
    Covered(f64),
}

/// Images up to this many footprint widths across are counted by their coverage; larger ones
/// are left to ray hits (their variance is only at their rims, a small share of their pixels).
pub const GLIMPSE_WIDTHS: f64 = 8.0;

/// The area of the part of a disc of radius `r` centred at (`cx`, `cy`) that lies in the
/// rectangle [−w/2, w/2] × [−h/2, h/2]: exact, in closed form.
///
/// ```
/// use orbifold_trace::footprint::disc_in_rectangle;
/// use std::f64::consts::PI;
/// // A disc inside the rectangle, a rectangle inside the disc, half a disc.
/// assert!((disc_in_rectangle(0.1, -0.2, 0.5, 4.0, 4.0) - PI * 0.25).abs() < 1e-12);
/// assert!((disc_in_rectangle(0.0, 0.0, 2.0, 1.0, 0.5) - 0.5).abs() < 1e-12);
/// assert!((disc_in_rectangle(1.0, 0.0, 1.0, 2.0, 9.0) - PI / 2.0).abs() < 1e-12);
/// ```
pub fn disc_in_rectangle(cx: f64, cy: f64, r: f64, w: f64, h: f64) -> f64 {
    // In the disc's own coordinates: the rectangle [x1, x2] × [y1, y2].
    let (x1, x2) = ((-0.5 * w - cx).max(-r), (0.5 * w - cx).min(r));
    if !(x1 < x2 && r > 0.0) {
        return 0.0;
    }
    let (y1, y2) = (-0.5 * h - cy, 0.5 * h - cy);
    (below(x1, x2, y2, r) - below(x1, x2, y1, r)).max(0.0)
}

/// ∫₀ˣ √(r² − t²) dt for |x| ≤ r.
fn half_chord_integral(x: f64, r: f64) -> f64 {
    let t = (x / r).clamp(-1.0, 1.0);
    0.5 * (x * (r * r - x * x).max(0.0).sqrt() + r * r * t.asin())
}

/// The area of the disc of radius r about the origin over [a, b] (within [−r, r]) below the
/// line Y = y: ∫ (clamp(y, −s, s) + s) dX with s = √(r² − X²).
fn below(a: f64, b: f64, y: f64, r: f64) -> f64 {
    let half = half_chord_integral(b, r) - half_chord_integral(a, r);
    if y >= r {
        return 2.0 * half;
    }
    if y <= -r {
        return 0.0;
    }
    // Where |X| < q the chord reaches past y and the clamp is y; elsewhere it is ±s.
    let q = (r * r - y * y).sqrt();
    let (c, d) = (a.max(-q), b.min(q));
    let (inner_length, inner) = if c < d {
        (d - c, half_chord_integral(d, r) - half_chord_integral(c, r))
    } else {
        (0.0, 0.0)
    };
    let sign = if y < 0.0 { -1.0 } else { 1.0 };
    (1.0 + sign) * half + y * inner_length - sign * inner
}

/// How much of the footprint of a camera ray covers a sphere light along the ray's stretch of
/// arc length `[0, end]`, the ray having come `travelled` from the camera before it. The sphere
/// counts only where its centre's closest approach lies on the stretch (to within `slack`: a
/// stretch that ends on the sphere itself ends about a radius short of the centre).
///
/// ```
/// use glam::DVec3;
/// use orbifold::{Geometry, space::Space};
/// use orbifold_trace::footprint::{Footprint, Glimpse, Sphere, sphere_coverage};
/// use orbifold_trace::geodesic::Ray;
/// let e2 = Space::new(Geometry::Euclidean);
/// let ray = Ray::new(e2, DVec3::new(0.0, 0.0, 1.0), DVec3::X, 0.5, 0.0);
/// let footprint = Footprint { across: 0.01, up: 0.01, centre: [0.0; 2] };
/// // A sphere of radius 0.01 ten units ahead, where the footprint is 0.1 wide: its disc
/// // covers π·0.01²/0.1² of it.
/// let centre = DVec3::new(10.0, 0.0, 1.0);
/// let far = f64::INFINITY;
/// let sphere = Sphere::new(e2, centre, 0.5, 0.01, far, far);
/// let Glimpse::Covered(c) = sphere_coverage(e2, &ray, 0.0, &footprint, &sphere, 20.0, 0.0) else {
///     panic!()
/// };
/// assert!((c - std::f64::consts::PI * 1e-2).abs() < 1e-9);
/// ```
pub fn sphere_coverage(
    space: Space,
    ray: &Ray,
    travelled: f64,
    footprint: &Footprint,
    sphere: &Sphere,
    end: f64,
    slack: f64,
) -> Glimpse {
    // The capped footprint reaches at most `clearance` across from the ray's centre line.
    let Some(Approach {
        s,
        across: lateral,
        up: vertical,
    }) = closest_approach(
        space,
        ray,
        sphere.centre,
        sphere.height,
        sphere.clearance_sine,
        (0.0, end + slack),
    )
    else {
        return Glimpse::Unresolved;
    };
    let diameter = 2.0 * sphere.radius;
    let (across, up) = footprint.widths(space, travelled + s, ray.cos_elevation);
    let caps = (
        2.0 * sphere.clearance - diameter,
        2.0 * sphere.headroom - diameter,
    );
    // Over the pixel itself, where it is all within the caps: the pixel's centre, seen along
    // this ray, is where the turns `centre` take the ray at this distance (they scale as the
    // widths do). A capped footprint is centred on the ray, as a smaller box filter.
    let whole = across <= caps.0 && up <= caps.1;
    let (centre_across, centre_up) = if whole {
        let [turn_across, turn_up] = footprint.centre;
        (
            turn_across * across / footprint.across,
            turn_up * up / footprint.up,
        )
    } else {
        (0.0, 0.0)
    };
    // (`f64::min` would turn a NaN width into the cap.)
    let (across, up) = if across.is_nan() || up.is_nan() {
        (0.0, 0.0)
    } else {
        (across.min(caps.0), up.min(caps.1))
    };
    // A footprint with no width (a panorama's pole; a cap at a light touching a wall) or NaN
    // widths leaves the light to ray hits too.
    let positive = across > 0.0 && up > 0.0;
    if !positive || diameter > GLIMPSE_WIDTHS * across.max(up) {
        return Glimpse::Unresolved;
    }
    let (cx, cy) = (lateral - centre_across, vertical - centre_up);
    let (cx, cy) = if cx.is_finite() && cy.is_finite() {
        (cx, cy)
    } else {
        (lateral, vertical)
    };
    let share = disc_in_rectangle(cx, cy, sphere.radius, across, up) / (across * up);
    Glimpse::Covered(if share.is_finite() { share } else { 0.0 })
}

/// Where a ray passes closest to a point, to first order in the offsets.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Approach {
    /// The ray's arc length there.
    pub(crate) s: f64,
    /// The point's signed offset across the ray (horizontal, to the left).
    pub(crate) across: f64,
    /// Its signed offset in the ray's vertical plane, perpendicular to the ray (upwards).
    pub(crate) up: f64,
}

/// The closest approach of a ray to the point (`centre`, `height`): the foot of the horizontal
/// perpendicular (S(d⊥) = ⟨c − p, v⟩ across the horizontal geodesic, C(d⊥)·S(σ) = ⟨c − p, u⟩
/// along it), then the nearest point in the flat vertical plane over the geodesic. `None` when
/// the point is as far across as the distance whose S_κ is `within_sine` or farther (tested
/// before the costlier part), or when the closest approach's arc length is outside `s_range`
/// (tested before the offset across is worked out: a ray's stretch between two mirrors passes
/// a light at most once, and most stretches near it pass it before or after their ends).
pub(crate) fn closest_approach(
    space: Space,
    ray: &Ray,
    centre: DVec3,
    height: f64,
    within_sine: f64,
    s_range: (f64, f64),
) -> Option<Approach> {
    let k = space.kappa();
    let (ca, sa) = (ray.cos_elevation, ray.sin_elevation);
    let p = ray.origin;
    let u = ray.direction;
    let v = space.quarter_turn(p, u);
    // S(d⊥) = ⟨c − p, v⟩ across the horizontal geodesic, C(d⊥)·S(σ_c) = ⟨c − p, u⟩ along it.
    let d = centre - p;
    let gamma = space.point_dot(d, v);
    let along = space.point_dot(d, u);
    // A camera ray meets the light in a few of its stretches: those that pass far from it
    // are told by the sine (S_κ is increasing), and the rest take the fast logarithm.
    if gamma.abs() >= within_sine || gamma.is_nan() {
        return None;
    }
    let m = (1.0 - k * gamma * gamma).max(0.0).sqrt();
    let sigma = if k > 0.0 {
        along.atan2(space.point_dot(centre, p) / k)
    } else if k == 0.0 {
        along
    } else {
        asinh_fast(along / m)
    };
    let rise = height - ray.height;
    let s = sigma * ca + rise * sa;
    if !(s >= s_range.0 && s <= s_range.1) {
        return None;
    }
    let lateral = if k < 0.0 {
        asinh_fast(gamma)
    } else {
        space.asin(gamma)
    };
    Some(Approach {
        s,
        across: lateral,
        up: rise * ca - sigma * sa,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use orbifold::Geometry;
    use proptest::prelude::*;

    const GEOMETRIES: [Geometry; 3] = [
        Geometry::Spherical,
        Geometry::Euclidean,
        Geometry::Hyperbolic,
    ];

    proptest! {
        /// The covered share, integrated over the ray's offsets across the footprint, is the
        /// sphere's outline's area divided by the footprint's: the mean of a pixel is kept, for
        /// images smaller than the footprint and for those up to `GLIMPSE_WIDTHS` wide. The
        /// offsets are those of parallel rays: translating the ray sideways (across, in E²)
        /// and up.
        #[test]
        fn coverage_integrates_to_the_sphere_s_share(
            r in 0.001f64..0.05, distance in 1.0f64..20.0, pixel in 0.001f64..0.02,
        ) {
            let e2 = Space::new(Geometry::Euclidean);
            let footprint = Footprint { across: pixel, up: pixel, centre: [0.0; 2] };
            let width = pixel * distance;
            prop_assume!(2.0 * r <= GLIMPSE_WIDTHS * width);
            let n = 96;
            // Offsets over every position where the footprint meets the sphere.
            let reach = 0.5 * width + r;
            let mut total = 0.0;
            for i in 0..n {
                for j in 0..n {
                    let dy = ((f64::from(i) + 0.5) / f64::from(n) * 2.0 - 1.0) * reach;
                    let dz = ((f64::from(j) + 0.5) / f64::from(n) * 2.0 - 1.0) * reach;
                    let ray = Ray::new(e2, DVec3::new(0.0, dy, 1.0), DVec3::X, 0.5 + dz, 0.0);
                    let centre = DVec3::new(distance, 0.0, 1.0);
                    let sphere = Sphere::new(e2, centre, 0.5, r, f64::INFINITY, f64::INFINITY);
                    match sphere_coverage(e2, &ray, 0.0, &footprint, &sphere, 100.0, 0.0) {
                        Glimpse::Covered(c) => total += c,
                        Glimpse::Unresolved => prop_assert!(false, "resolved by the footprint"),
                    }
                }
            }
            let cell = (2.0 * reach / f64::from(n)).powi(2);
            let expected = std::f64::consts::PI * r * r;
            prop_assert!((total * cell - expected).abs() < 0.02 * expected, "{} vs {}", total * cell, expected);
        }

        /// The disc's area in the rectangle is what counting a fine grid of the rectangle's
        /// points in the disc gives, wherever the two lie.
        #[test]
        fn the_disc_s_area_in_a_rectangle_is_counted_right(
            cx in -2.0f64..2.0, cy in -2.0f64..2.0, r in 0.01f64..2.0, w in 0.01f64..3.0, h in 0.01f64..3.0,
        ) {
            let area = disc_in_rectangle(cx, cy, r, w, h);
            let n = 600;
            let mut inside = 0u32;
            for i in 0..n {
                for j in 0..n {
                    let x = ((f64::from(i) + 0.5) / f64::from(n) - 0.5) * w;
                    let y = ((f64::from(j) + 0.5) / f64::from(n) - 0.5) * h;
                    if (x - cx).powi(2) + (y - cy).powi(2) <= r * r {
                        inside += 1;
                    }
                }
            }
            let counted = f64::from(inside) * w * h / f64::from(n * n);
            // The grid's error: its cells along the disc's rim, and along the rectangle's.
            let cell = w.max(h) / f64::from(n);
            let tolerance = 2.0 * cell * (std::f64::consts::TAU * r) + 1e-9;
            prop_assert!((area - counted).abs() <= tolerance, "{} vs {} counted", area, counted);
            prop_assert!(area >= 0.0 && area <= (std::f64::consts::PI * r * r).min(w * h) + 1e-12);
        }

        /// A sample's footprint, centred on its pixel, counts a light image as the pixel's
        /// centre ray does: the turns from the sample's ray to the pixel's centre, carried along
        /// the ray as the widths are, land on the centre ray (to first order in the pixel's
        /// size), in every geometry and at every elevation.
        #[test]
        fn a_footprint_counts_what_its_pixel_s_centre_ray_counts(
            g in 0usize..3, yaw in 0.0f64..std::f64::consts::TAU, pitch in -0.5f64..0.5,
            pixel in 1e-4f64..2e-3, distance in 0.3f64..1.5, off in (-1.5f64..1.5, -1.5f64..1.5),
            dx in -0.5f64..0.5, dy in -0.5f64..0.5, radius in 0.2f64..3.0,
        ) {
            use num_complex::Complex64;
            let space = Space::new(GEOMETRIES[g]);
            let z = Complex64::new(0.1, -0.05);
            let centre_ray = Ray::from_model(space, z, 0.5, yaw, pitch);
            // The sample's ray, turned dx pixels to the left and dy up.
            let turn = dx * pixel / pitch.cos();
            let ray = Ray::from_model(space, z, 0.5, yaw + turn, pitch + dy * pixel);
            let centred = Footprint { across: pixel, up: pixel, centre: [0.0; 2] };
            let footprint = Footprint {
                centre: [-turn * (pitch + dy * pixel).cos(), -dy * pixel],
                ..centred
            };
            // A sphere `radius` pixels wide, `off` pixels beside the centre ray.
            let width = pixel * distance;
            let (q, h) = centre_ray.point_at(space, distance);
            let left = space.quarter_turn(q, centre_ray.tangent_at(space, distance * centre_ray.cos_elevation));
            let sphere = Sphere::new(
                space,
                space.exp(q, left * (off.0 * width)),
                h + off.1 * width,
                radius * width,
                f64::INFINITY,
                f64::INFINITY,
            );
            let share = |ray: &Ray, footprint: &Footprint| {
                match sphere_coverage(space, ray, 0.0, footprint, &sphere, 10.0, 0.0) {
                    Glimpse::Covered(c) => c,
                    Glimpse::Unresolved => f64::NAN,
                }
            };
            let (a, b) = (share(&centre_ray, &centred), share(&ray, &footprint));
            prop_assert!((a - b).abs() < 0.02, "centre ray {}, sample {}", a, b);
        }

        /// The closest approach found in every geometry is the true one: at the arc length
        /// where a numerical search finds the ray nearest the point, with the offsets it was
        /// placed at.
        #[test]
        fn closest_approach_is_where_the_centre_is_nearest(
            g in 0usize..3, x in -0.4f64..0.4, y in -0.4f64..0.4, yaw in 0.0f64..std::f64::consts::TAU,
            pitch in -0.6f64..0.6, ahead in 0.2f64..1.0, off in -0.02f64..0.02, lift in -0.02f64..0.02,
        ) {
            use num_complex::Complex64;
            let space = Space::new(GEOMETRIES[g]);
            let ray = Ray::from_model(space, Complex64::new(x, y) * 0.5, 0.5, yaw, pitch);
            // A centre near the ray's point at arc length `ahead`, nudged across and up.
            let (q, h) = ray.point_at(space, ahead);
            let across = space.quarter_turn(q, ray.tangent_at(space, ahead * ray.cos_elevation));
            let centre = space.exp(q, across * off);
            let height = h + lift;
            // Refused exactly when the centre is `within` or farther across (it is |off| across).
            let within = 0.04 * (yaw * 7.0).fract();
            if (off.abs() - within).abs() > 1e-9 {
                let seen = closest_approach(space, &ray, centre, height, space.sin(within), (f64::NEG_INFINITY, f64::INFINITY));
                prop_assert_eq!(seen.is_some(), off.abs() < within);
            }
            let approach = closest_approach(space, &ray, centre, height, space.sin(1.0), (f64::NEG_INFINITY, f64::INFINITY)).unwrap();
            // The arc-length range is a filter on that same s: in it, the same approach.
            let near = (approach.s - 1e-3, approach.s + 1e-3);
            let within_range = closest_approach(space, &ray, centre, height, space.sin(1.0), near);
            prop_assert_eq!(within_range, Some(approach));
            let after = (approach.s + 1e-3, f64::INFINITY);
            prop_assert!(closest_approach(space, &ray, centre, height, space.sin(1.0), after).is_none());
            let before = (f64::NEG_INFINITY, approach.s - 1e-3);
            prop_assert!(closest_approach(space, &ray, centre, height, space.sin(1.0), before).is_none());
            let distance = |s: f64| {
                let (p, hp) = ray.point_at(space, s);
                space.ambient_distance(p, centre).hypot(hp - height)
            };
            // Arc length of the closest approach, by golden-section search.
            let (mut lo, mut hi) = (0.0, 2.0);
            for _ in 0..200 {
                let a = lo + 0.382 * (hi - lo);
                let b = lo + 0.618 * (hi - lo);
                if distance(a) < distance(b) { hi = b } else { lo = a }
            }
            let nearest = 0.5 * (lo + hi);
            let size = off.hypot(lift);
            prop_assert!((approach.s - nearest).abs() < 1e-3 + 0.05 * size, "{:?} at {}", approach, nearest);
            // Placed `off` to the left (J u) and `lift` up, seen across the tilted ray.
            prop_assert!((approach.across - off).abs() < 0.05 * size + 1e-9, "{:?}", approach);
            let up = lift * ray.cos_elevation;
            prop_assert!((approach.up - up).abs() < 0.05 * size + 1e-9, "{:?} vs {}", approach, up);
        }
    }

    /// A level ray along +x from the origin of E² at height 0.5, and a sphere of `radius` at
    /// (x, 0) on its line, with no walls, floor or ceiling near.
    fn level(x: f64, radius: f64) -> (Space, Ray, Sphere) {
        let e2 = Space::new(Geometry::Euclidean);
        let ray = Ray::new(e2, DVec3::new(0.0, 0.0, 1.0), DVec3::X, 0.5, 0.0);
        let sphere = Sphere::new(
            e2,
            DVec3::new(x, 0.0, 1.0),
            0.5,
            radius,
            f64::INFINITY,
            f64::INFINITY,
        );
        (e2, ray, sphere)
    }

    fn square(width: f64) -> Footprint {
        Footprint {
            across: width,
            up: width,
            centre: [0.0; 2],
        }
    }

    #[test]
    fn a_large_image_is_left_to_ray_hits() {
        let (e2, ray, sphere) = level(2.0, 0.05);
        let glimpse = sphere_coverage(e2, &ray, 0.0, &square(1e-3), &sphere, 10.0, 0.0);
        assert_eq!(glimpse, Glimpse::Unresolved);
        // Up to `GLIMPSE_WIDTHS` footprints wide, the footprint counts it; the ray's centre
        // line runs through the disc, so the whole footprint is light.
        let at_most = 0.1 / (GLIMPSE_WIDTHS * 2.0);
        let glimpse = sphere_coverage(e2, &ray, 0.0, &square(1.01 * at_most), &sphere, 10.0, 0.0);
        assert!(
            matches!(glimpse, Glimpse::Covered(c) if (c - 1.0).abs() < 1e-9),
            "{glimpse:?}"
        );
        let glimpse = sphere_coverage(e2, &ray, 0.0, &square(0.99 * at_most), &sphere, 10.0, 0.0);
        assert_eq!(glimpse, Glimpse::Unresolved);
    }

    #[test]
    fn a_footprint_without_width_leaves_the_light_to_ray_hits() {
        let (e2, ray, sphere) = level(10.0, 0.01);
        for across in [0.0, f64::NAN] {
            let footprint = Footprint {
                across,
                up: 0.1,
                centre: [0.0; 2],
            };
            let glimpse = sphere_coverage(e2, &ray, 0.0, &footprint, &sphere, 20.0, 0.0);
            assert_eq!(glimpse, Glimpse::Unresolved, "{footprint:?}");
        }
        // A light touching a wall: the capped width is negative.
        let touching = Sphere::new(
            e2,
            sphere.centre,
            sphere.height,
            sphere.radius,
            0.005,
            sphere.headroom,
        );
        let glimpse = sphere_coverage(e2, &ray, 0.0, &square(0.1), &touching, 20.0, 0.0);
        assert_eq!(glimpse, Glimpse::Unresolved);
    }

    #[test]
    fn a_light_behind_or_past_the_stretch_is_not_seen() {
        for x in [-2.0, 5.0] {
            let (e2, ray, sphere) = level(x, 0.01);
            let glimpse = sphere_coverage(e2, &ray, 0.0, &square(0.1), &sphere, 3.0, 0.0);
            assert_eq!(glimpse, Glimpse::Unresolved);
        }
    }
}
