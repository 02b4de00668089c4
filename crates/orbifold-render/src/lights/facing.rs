//! Which triangles of a sphere light can face a lit point, and how light sampling weighs them.
//!
//! Half of a sphere light's triangles face away from any point being lit, and could only ever
//! give zero; light sampling skips them. In the tangent space at the light mesh's origin (object
//! coordinates), a triangle whose centroid is `a` and outward normal `n` is kept for the point
//! `b` when n·(b − a) > −m (d + r), with d the distance of `b` from the sphere's centre, r the
//! sphere's radius and m = 0.05 + r²: a margin for the triangles' extent and for the curvature
//! over the light, so that no triangle that faces `b` is left out (on the sphere the margin
//! grows towards the light's antipode: [`Facing::margin`]). Points within 1.05 r of the centre
//! keep every triangle.
//!
//! Among the kept triangles, light sampling draws each by about the solid angle it fills seen
//! from the point ([`ShadingPoint::weight`]), not by its area, so that a light sample's estimate
//! hardly varies over the sphere.
//!
//! The weights are worked out at every light sample for every triangle, so they are laid out one
//! array per quantity ([`TriangleLanes`]) and computed in single precision, eight triangles to an
//! AVX register, with no branches; sampling then steps over whole blocks of eight by their sums
//! ([`Facing::pick`]). Sampling and its density read the same bits, so they agree exactly.

use std::f64::consts::PI;

use glam::DVec3;
use orbifold::space::Space;
use orbifold_trace::accel::Instance;
use orbifold_trace::with_avx512;

use super::frame::TangentFrame;

/// How many times the sphere's estimated spread of arrival angles the facing margin allows:
/// twice, for headroom over the estimate (`tests/lights.rs` checks that every point of the light
/// that a ray meets first can still be sampled).
const CURVATURE_MARGIN: f64 = 2.0;

/// On the sphere, points this close to the antipode of a sphere light keep all its triangles.
const ANTIPODE_TOLERANCE: f64 = 1e-3;

/// Triangles per block of [`Facing::kept_blocks`].
const BLOCK_SIZE: usize = 8;

/// Most blocks (a sphere light has 352 triangles: 44).
pub(super) const MAX_BLOCKS: usize = 64;

/// What lets light sampling skip the triangles of a sphere light that face away from the point
/// being lit, worked out in the tangent space at the light mesh's origin (object coordinates).
///
/// A triangle is kept for a point when the point lies in front of the triangle's plane or
/// behind it by less than a margin, which covers the triangles' extent and the curvature over
/// the light, so that no triangle that faces the point is left out. Kept triangles are drawn by
/// about the solid angle they fill seen from the point, not by their area, so that a light
/// sample's estimate hardly varies over the sphere.
#[derive(Clone, Debug)]
pub struct Facing {
    /// The curvature of the plane.
    kappa: f64,
    /// The frame at the mesh's origin in whose local coordinates the planes are written.
    frame: TangentFrame,
    /// The mean of the triangles' centroids (local coordinates).
    centre: DVec3,
    /// The farthest centroid's distance from `centre`.
    pub(super) radius: f64,
    /// Per triangle (n_x, n_y, n_z, n·a): its outward normal and offset.
    pub(super) planes: Vec<[f64; 4]>,
    /// The same planes and the triangles' areas, one array per quantity, for the pass over all
    /// of them at every light sample (SIMD, no branches).
    lanes: TriangleLanes,
}

/// The triangles' planes, centroids and areas, one array per quantity, padded to whole blocks
/// of [`BLOCK_SIZE`] (padding: area 0).
#[derive(Clone, Debug)]
struct TriangleLanes {
    nx: Vec<f32>,
    ny: Vec<f32>,
    nz: Vec<f32>,
    offset: Vec<f32>,
    /// The triangles' centroids.
    cx: Vec<f32>,
    cy: Vec<f32>,
    cz: Vec<f32>,
    area: Vec<f32>,
}

/// A lit point in the local coordinates of a sphere light's [`Facing`], with what weighing its
/// triangles for it takes.
///
/// Weights are worked out in single precision, eight triangles to an AVX register: they only
/// shape a distribution, and sampling and its density read the same bits.
#[derive(Clone, Copy, Debug)]
pub(super) struct ShadingPoint {
    /// The point, in the light's local coordinates.
    local: [f32; 3],
    /// The facing margin ([`Facing::margin`]).
    margin: f32,
    /// A floor under squared distances, (0.05 r)² for the sphere's radius r (points are kept
    /// only beyond 1.05 r from its centre).
    min_squared_distance: f32,
}

impl ShadingPoint {
    /// The weight of a kept triangle of area `area` whose plane is `value` in front of the
    /// point and whose centroid is ℓ away (`squared` = ℓ²): about the solid angle it fills seen
    /// from the point, area · value / ℓ³ (area times the cosine at the triangle over ℓ²).
    /// The margin is added to `value` (kept triangles have `value` > −margin) so that those kept
    /// only by the margin, seen past the silhouette through the curvature, can still be drawn.
    /// These weights make a light sample's estimate nearly constant over the sphere, where area
    /// weights leave each triangle's cosine over ℓ² in it: a relative variance of about 1/3 seen
    /// from far away, and far more from near.
    #[inline(always)]
    fn weight(&self, area: f32, value: f32, squared: f32) -> f32 {
        let squared = squared.max(self.min_squared_distance);
        area * (value + self.margin) / (squared * squared.sqrt())
    }
}

impl TriangleLanes {
    fn new(planes: &[[f64; 4]], centroids: &[DVec3], areas: &[f64]) -> TriangleLanes {
        let padded = planes.len().div_ceil(BLOCK_SIZE) * BLOCK_SIZE;
        // Padding: area 0, and a centroid far from any point (no distance 0 to divide by).
        let lane = |f: &dyn Fn(usize) -> f64, padding: f32| -> Vec<f32> {
            (0..padded)
                .map(|i| {
                    if i < planes.len() {
                        f(i) as f32
                    } else {
                        padding
                    }
                })
                .collect()
        };
        TriangleLanes {
            nx: lane(&|i| planes[i][0], 0.0),
            ny: lane(&|i| planes[i][1], 0.0),
            nz: lane(&|i| planes[i][2], 0.0),
            offset: lane(&|i| planes[i][3], 0.0),
            cx: lane(&|i| centroids[i].x, 1e3),
            cy: lane(&|i| centroids[i].y, 1e3),
            cz: lane(&|i| centroids[i].z, 1e3),
            area: lane(&|i| areas[i], 0.0),
        }
    }

    /// How many blocks.
    fn blocks(&self) -> usize {
        self.area.len() / BLOCK_SIZE
    }

    /// The weights for `shading` of the triangles from `start` on, as many as `out` holds:
    /// [`ShadingPoint::weight`] where the triangle is kept, else 0. One plain loop over the
    /// arrays, which the compiler turns into SIMD; lane by lane the same operations whatever the
    /// stretch, so a block's weights are the same bits whether worked out alone or with all the
    /// others.
    #[inline(always)]
    fn weights_into(&self, shading: &ShadingPoint, start: usize, out: &mut [f32]) {
        let n = out.len();
        let range = start..start + n;
        let (nx, ny, nz) = (
            &self.nx[range.clone()],
            &self.ny[range.clone()],
            &self.nz[range.clone()],
        );
        let (cx, cy, cz) = (
            &self.cx[range.clone()],
            &self.cy[range.clone()],
            &self.cz[range.clone()],
        );
        let (offset, area) = (&self.offset[range.clone()], &self.area[range]);
        let [x, y, z] = shading.local;
        for i in 0..n {
            let value = nx[i] * x + ny[i] * y + nz[i] * z - offset[i];
            let (dx, dy, dz) = (x - cx[i], y - cy[i], z - cz[i]);
            let weight = shading.weight(area[i], value, dx * dx + dy * dy + dz * dz);
            // The weight masked by the comparison (what SIMD compare-and-mask does).
            let mask = if value > -shading.margin { u32::MAX } else { 0 };
            out[i] = f32::from_bits(weight.to_bits() & mask);
        }
    }

    /// Block `k`'s weights for `shading`.
    #[inline(always)]
    fn block_weights(&self, shading: &ShadingPoint, k: usize) -> [f32; BLOCK_SIZE] {
        let mut weights = [0.0; BLOCK_SIZE];
        self.weights_into(shading, k * BLOCK_SIZE, &mut weights);
        weights
    }
}

/// A block's weights summed: halves, then quarters, then pairs (the order in which a register
/// is folded; a running sum would wait on every addition).
#[inline(always)]
fn block_sum(weights: &[f32]) -> f64 {
    let h: [f64; 4] = std::array::from_fn(|j| f64::from(weights[j]) + f64::from(weights[j + 4]));
    (h[0] + h[2]) + (h[1] + h[3])
}

impl Facing {
    /// The facing test for the mesh of `instance` (a sphere light's, its triangles' areas
    /// `areas`); `None` when the mesh has no extent.
    pub(super) fn new(space: Space, instance: &Instance, areas: &[f64]) -> Option<Facing> {
        let origin = DVec3::Z;
        let frame = TangentFrame::at(space, origin);
        let (points, heights, triangles) = instance.bvh.mesh();
        let local = |i: u32| {
            let i = i as usize;
            frame.to_local(space, space.log(origin, points[i]), heights[i])
        };
        let centroids: Vec<DVec3> = triangles
            .iter()
            .map(|t| (local(t[0]) + local(t[1]) + local(t[2])) / 3.0)
            .collect();
        let centre = centroids.iter().copied().sum::<DVec3>() / centroids.len().max(1) as f64;
        // The triangles' own (flat) normals, outwards: within a triangle n·(b − p) is the same
        // for every point p, up to the curvature over the light.
        let normals: Vec<DVec3> = triangles
            .iter()
            .zip(&centroids)
            .map(|(t, a)| {
                let n = (local(t[1]) - local(t[0]))
                    .cross(local(t[2]) - local(t[0]))
                    .normalize_or_zero();
                if n.dot(*a - centre) < 0.0 { -n } else { n }
            })
            .collect();
        let radius = centroids
            .iter()
            .map(|a| (*a - centre).length())
            .fold(0.0, f64::max);
        let planes: Vec<[f64; 4]> = normals
            .iter()
            .zip(&centroids)
            .map(|(n, a)| [n.x, n.y, n.z, n.dot(*a)])
            .collect();
        let lanes = TriangleLanes::new(&planes, &centroids, areas);
        (radius > 0.0 && radius.is_finite()).then_some(Facing {
            kappa: space.kappa(),
            frame,
            centre,
            radius,
            planes,
            lanes,
        })
    }

    /// The point (object coordinates) in the local coordinates of the triangles, or `None` when
    /// every triangle is kept.
    pub(super) fn local_point(&self, space: Space, (x, h): (DVec3, f64)) -> Option<DVec3> {
        let b = self.frame.to_local(space, space.log(DVec3::Z, x), h);
        let d = (b - self.centre).length();
        // At the light's antipode on the sphere, geodesics from the point reach it from every
        // side (`margin` grows without bound towards it).
        let antipodal =
            space.kappa() > 0.0 && (b.x * b.x + b.y * b.y).sqrt() > PI - ANTIPODE_TOLERANCE;
        (b.is_finite() && d > 1.05 * self.radius && !antipodal).then_some(b)
    }

    /// The margin for the local point `b`.
    ///
    /// On the sphere geodesics from a point D away refocus towards its antipode, so they reach
    /// the light's side at angles that differ from straight lines' by about r(1/D − cot D) (the
    /// Jacobi fields of the sphere against those of the plane): negligible near the light, a
    /// radian for r = 0.1 at D = 3 and unbounded at the antipode. The margin grows with it.
    pub(super) fn margin(&self, b: DVec3) -> f64 {
        let mut angle = 0.05 + self.radius * self.radius;
        // (Local coordinates near the light: no overflow for `hypot`, which is slow, to guard.)
        let d = (b.x * b.x + b.y * b.y).sqrt();
        if self.kappa > 0.0 && d > 1e-6 {
            angle += CURVATURE_MARGIN * self.radius * (1.0 / d - 1.0 / d.tan()).max(0.0);
        }
        angle * ((b - self.centre).length() + self.radius)
    }

    /// What sampling needs to weigh the triangles for the local point `b`.
    pub(super) fn shading_point(&self, b: DVec3) -> ShadingPoint {
        let margin = self.margin(b);
        ShadingPoint {
            local: [b.x as f32, b.y as f32, b.z as f32],
            margin: margin as f32,
            min_squared_distance: (0.05 * self.radius).powi(2) as f32,
        }
    }

    /// Triangle `i`'s weight for `shading` (0 when it is not kept), computed as the blocks
    /// compute it, to the bit.
    #[inline]
    pub(super) fn weight_of(&self, i: usize, shading: &ShadingPoint) -> f64 {
        f64::from(self.lanes.block_weights(shading, i / BLOCK_SIZE)[i % BLOCK_SIZE])
    }

    /// The kept weight block by block (`BLOCK_SIZE` triangles each) into `blocks`, and the total;
    /// `None` when the light has more than `BLOCK_SIZE`·`MAX_BLOCKS` triangles.
    pub(super) fn kept_blocks(
        &self,
        shading: &ShadingPoint,
        blocks: &mut [f64; MAX_BLOCKS],
    ) -> Option<f64> {
        with_avx512!(
            Facing,
            self.kept_blocks_portable(shading: &ShadingPoint, blocks: &mut [f64; MAX_BLOCKS]) -> Option<f64>
        )
    }

    #[inline(always)]
    fn kept_blocks_portable(
        &self,
        shading: &ShadingPoint,
        blocks: &mut [f64; MAX_BLOCKS],
    ) -> Option<f64> {
        let count = self.lanes.blocks();
        if count > MAX_BLOCKS {
            return None;
        }
        let mut weights = [0.0; BLOCK_SIZE * MAX_BLOCKS];
        let weights = &mut weights[..count * BLOCK_SIZE];
        self.lanes.weights_into(shading, 0, weights);
        let mut total = 0.0;
        for (block, sum) in weights.chunks_exact(BLOCK_SIZE).zip(blocks.iter_mut()) {
            *sum = block_sum(block);
            total += *sum;
        }
        Some(total)
    }

    /// The kept triangle that `target` (in [0, kept weight)) falls on when the kept triangles'
    /// weights are laid end to end (the last kept one if rounding runs past): whole blocks are
    /// stepped over by their sums, and only the block it falls in is scanned.
    pub(super) fn pick(
        &self,
        shading: &ShadingPoint,
        blocks: &[f64; MAX_BLOCKS],
        mut target: f64,
    ) -> Option<usize> {
        let count = self.lanes.blocks();
        let range = |k: usize| k * BLOCK_SIZE..((k + 1) * BLOCK_SIZE).min(self.planes.len());
        let mut last = None;
        for (k, &sum) in blocks[..count].iter().enumerate() {
            if sum <= 0.0 {
                continue;
            }
            last = Some(k);
            if target >= sum {
                target -= sum;
                continue;
            }
            let weights = self.lanes.block_weights(shading, k);
            for i in range(k) {
                let weight = f64::from(weights[i % BLOCK_SIZE]);
                if weight > 0.0 {
                    if target < weight {
                        return Some(i);
                    }
                    target -= weight;
                }
            }
        }
        // Rounding ran past the end: the last kept triangle.
        let last = last?;
        let weights = self.lanes.block_weights(shading, last);
        range(last).rev().find(|&i| weights[i % BLOCK_SIZE] > 0.0)
    }

    /// The total weight of the triangles kept for `shading` (one branch-free pass; summed as
    /// [`Facing::kept_blocks`] sums it, so that sampling and its density agree to the last bit).
    pub(super) fn kept_weight(&self, shading: &ShadingPoint) -> f64 {
        let mut blocks = [0.0; MAX_BLOCKS];
        if let Some(total) = self.kept_blocks(shading, &mut blocks) {
            return total;
        }
        (0..self.planes.len())
            .map(|i| self.weight_of(i, shading))
            .sum()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::lights::{Emitter, Light};
    use orbifold_scene::{LightKind, Scene};

    /// The sphere light of radius 0.1 over the centre of `signature`'s default room, and the
    /// room's space.
    fn sphere_light(signature: &str) -> (Space, Light) {
        let mut scene = Scene::default();
        scene.orbifold.signature = signature.into();
        let layout = scene.layout().unwrap();
        scene.lights[0].kind = LightKind::Sphere;
        scene.lights[0].at = [layout.centre.re, layout.centre.im];
        scene.lights[0].radius = 0.1;
        let mut lights = Light::from_scene(layout.space(), &scene).unwrap();
        (layout.space(), lights.swap_remove(0))
    }

    /// The sphere light of [`sphere_light`]: its facing and its triangles' areas.
    fn facing(signature: &str) -> (Facing, Vec<f64>) {
        let (_, light) = sphere_light(signature);
        let Emitter::Area {
            facing: Some(facing),
            areas,
            ..
        } = &light.emitter
        else {
            panic!("a sphere light with its facing");
        };
        (facing.clone(), areas.clone())
    }

    /// Triangle `i`'s plane value n·b − n·a for the local point `b` (in double precision).
    fn plane_value(facing: &Facing, i: usize, b: DVec3) -> f64 {
        let [x, y, z, offset] = facing.planes[i];
        DVec3::new(x, y, z).dot(b) - offset
    }

    /// Points all around the light, near (1.1 r) and far (21 r).
    fn points_around(facing: &Facing) -> impl Iterator<Item = DVec3> + '_ {
        (0..400).map(|k| {
            let t = f64::from(k);
            let direction =
                DVec3::new((t * 0.7).cos(), (t * 0.7).sin(), (t * 0.31).sin()).normalize();
            facing.centre + direction * facing.radius * (1.1 + 0.05 * t)
        })
    }

    #[test]
    fn block_sums_pick_the_triangles_a_scan_would_keep() {
        // For points all around the light, near and far: the triangles with a weight are those
        // that face the point within the margin, the block sums add up to their weights, and
        // `pick` lays the kept triangles end to end in index order, each over a stretch as long
        // as its weight (so a triangle is picked ∝ its weight).
        for signature in ["*235", "*2222", "*2223"] {
            let (facing, areas) = facing(signature);
            for b in points_around(&facing) {
                let shading = facing.shading_point(b);
                let margin = facing.margin(b);
                let weights: Vec<f64> = (0..areas.len())
                    .map(|i| facing.weight_of(i, &shading))
                    .collect();
                for (i, &w) in weights.iter().enumerate() {
                    // Single precision may decide otherwise only right at the margin.
                    let value = plane_value(&facing, i, b);
                    if (value + margin).abs() > 1e-5 * margin {
                        assert_eq!(w > 0.0, value > -margin, "triangle {i} at {b}");
                    }
                }
                let kept: Vec<usize> = (0..areas.len()).filter(|&i| weights[i] > 0.0).collect();
                assert!(!kept.is_empty() && kept.len() < areas.len());
                let scan: f64 = weights.iter().sum();
                let mut blocks = [0.0; MAX_BLOCKS];
                let total = facing.kept_blocks(&shading, &mut blocks).unwrap();
                assert!((total - scan).abs() <= 1e-12 * scan, "{total} vs {scan}");
                // What the processor's SIMD copy (AVX-512 or AVX2, where it has them) computes
                // is what the portable body computes, to the bit.
                let mut portable = [0.0; MAX_BLOCKS];
                let portable_total = facing
                    .kept_blocks_portable(&shading, &mut portable)
                    .unwrap();
                assert_eq!(total.to_bits(), portable_total.to_bits());
                assert_eq!(blocks.map(f64::to_bits), portable.map(f64::to_bits));
                assert_eq!(facing.kept_weight(&shading), total);
                let mut start = 0.0;
                for &i in &kept {
                    // Stretches too short to tell from the rounding of the running sums are
                    // left out.
                    if weights[i] > 1e-4 * total {
                        let middle = start + 0.5 * weights[i];
                        assert_eq!(facing.pick(&shading, &blocks, middle), Some(i));
                    }
                    start += weights[i];
                }
                // Past the end (rounding): the last kept triangle.
                let last = facing.pick(&shading, &blocks, total * (1.0 + 1e-6));
                assert_eq!(last, kept.last().copied());
            }
        }
    }

    #[test]
    fn triangles_are_drawn_by_the_solid_angle_they_fill() {
        // In a flat room, for points from 1.5 r to 21 r away: each clearly facing triangle's
        // share of the weight, against its share of the solid angle the sphere fills (the exact
        // solid angle of a flat triangle, Van Oosterom and Strackee). Drawing by area instead
        // leaves out the cosine over the squared distance.
        let (facing, areas) = facing("*2222");
        let (space, light) = sphere_light("*2222");
        let Emitter::Area { instance, .. } = &light.emitter else {
            unreachable!()
        };
        let (points, heights, triangles) = instance.bvh.mesh();
        let local = |i: u32| {
            let i = i as usize;
            facing
                .frame
                .to_local(space, space.log(DVec3::Z, points[i]), heights[i])
        };
        let mut worst: f64 = 1.0;
        let mut worst_by_area: f64 = 1.0;
        for b in points_around(&facing) {
            // Nearer, the triangles are not small against their distance.
            if (b - facing.centre).length() < 1.5 * facing.radius {
                continue;
            }
            let shading = facing.shading_point(b);
            let total = facing.kept_weight(&shading);
            let kept_area: f64 = (0..areas.len())
                .filter(|&i| facing.weight_of(i, &shading) > 0.0)
                .map(|i| areas[i])
                .sum();
            let solid: Vec<f64> = triangles
                .iter()
                .map(|t| {
                    let [p, q, r] = [local(t[0]) - b, local(t[1]) - b, local(t[2]) - b];
                    let (lp, lq, lr) = (p.length(), q.length(), r.length());
                    let numerator = p.dot(q.cross(r));
                    let denominator = lp * lq * lr + p.dot(q) * lr + q.dot(r) * lp + r.dot(p) * lq;
                    (2.0 * numerator.atan2(denominator)).abs()
                })
                .collect();
            let seen: f64 = (0..areas.len())
                .filter(|&i| plane_value(&facing, i, b) > 0.0)
                .map(|i| solid[i])
                .sum();
            for i in 0..areas.len() {
                let value = plane_value(&facing, i, b);
                let distance = (b - facing.centre).length();
                // Clearly facing: at least a third of the way from the silhouette to the front.
                if value > (distance - facing.radius) / 3.0 {
                    let share = facing.weight_of(i, &shading) / total;
                    let ratio = share / (solid[i] / seen);
                    worst = worst.max(ratio).max(1.0 / ratio);
                    let by_area = areas[i] / kept_area / (solid[i] / seen);
                    worst_by_area = worst_by_area.max(by_area).max(1.0 / by_area);
                }
            }
        }
        // Weights follow the solid angle closely; areas leave it several times over.
        assert!(worst < 1.35, "weights off the solid angle by up to {worst}");
        assert!(
            worst_by_area > 4.0,
            "the points do not tell weights from areas"
        );
    }
}
