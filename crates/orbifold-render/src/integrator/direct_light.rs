//! Direct light by next-event estimation: at a surface point, one light sample through the
//! mirrors, kept among a few candidates by resampled importance sampling (RIS; Talbot et al.
//! 2005), and weighed against BSDF sampling by multiple importance sampling with the power
//! heuristic.
//!
//! A candidate takes an entry of the light sampler (a light, an image of the room, a way round),
//! a point on that light, and the geodesic from the surface to the light's image. Only the kept
//! candidate's geodesic is followed through the real room, as a shadow segment
//! ([`Integrator::follow_mirrors`]), and it counts only if it arrives at the light through
//! mirrors alone. A path that hits an area light after a non-specular bounce is weighted against
//! the light sample that could have made it ([`Integrator::light_pdf`]); the image it came through
//! is found from the walls it met.

use arrayvec::ArrayVec;
use glam::DVec3;
use orbifold_scene::color::luminance;
use orbifold_trace::triangle::TriangleHit;

use super::light_sampler::{NEAR_MAX, Normal};
use super::mirror_segment::{MirrorSegment, SegmentEnd};
use super::surface::GeometricSides;
use super::{Integrator, RAY_EPSILON, mul, scale};
use crate::lights::{
    AimedLight, Connection, Emitter, LightPoint, Rgb, TangentFrame, aim_at, connect, spread,
    travel_direction,
};
use crate::materials::bsdf::Bsdf;
use crate::sampler::{Frame, Sampler, power_heuristic};

/// The candidates drawn for each light sample by default, of which one is kept and followed
/// through the mirrors ([`Settings::light_candidates`](super::Settings::light_candidates)).
/// Each candidate weighs a sphere light's triangles and finds its image's connection, which
/// costs more than its noise is worth beyond three (docs/benchmarks.md).
pub const DEFAULT_LIGHT_CANDIDATES: u32 = 3;

/// The candidates by default where light sampling has few choices of image ([`FEW_ENTRIES`]):
/// the candidates then mostly differ only in the point on the light, which a sphere light
/// already draws by solid angle, so that two leave as little noise as more would, in less time
/// (docs/benchmarks.md).
pub const FEW_CANDIDATES: u32 = 2;

/// At most this many (light, image, way) choices count as few ([`FEW_CANDIDATES`]).
pub const FEW_ENTRIES: usize = 256;

/// The most candidates for one light sample.
pub const MAX_LIGHT_CANDIDATES: u32 = 16;

const LIGHT_CANDIDATES: usize = MAX_LIGHT_CANDIDATES as usize;

/// Shifts that make the later candidates' uniforms from the first's: the golden ratio's
/// fraction, and the two-dimensional R₂ sequence's (Roberts 2018), whose multiples are spread
/// evenly.
const GOLDEN: f64 = 0.618_033_988_749_894_9;
const R2: (f64, f64) = (0.754_877_666_246_692_7, 0.569_840_290_998_053_2);

/// A surface point to be lit by a light sample, with what its BSDF needs.
struct LitPoint<'a> {
    x: DVec3,
    h: f64,
    frame: &'a TangentFrame,
    shading: &'a Frame,
    sides: &'a GeometricSides,
    bsdf: &'a Bsdf,
}

/// A candidate light sample, worked out up to its visibility.
#[derive(Clone, Copy, Debug)]
struct LightCandidate {
    /// The (light, image, way) entry and its probability.
    index: usize,
    pmf: f64,
    /// The point on the light (in its own copy) and the geodesic to its image.
    point: LightPoint,
    link: Connection,
    /// The direction to the light at the lit point (shading frame's ambient local), the BSDF
    /// there and the cosine.
    wi: DVec3,
    f: Rgb,
    cos_x: f64,
    /// The luminance of the contribution if nothing blocks it: the resampling weight.
    weight: f64,
}

/// A candidate of a resampled light sample ([`Integrator::direct`]).
#[derive(Clone, Copy, Debug)]
// A few live in an ArrayVec on the stack per light sample: boxing the large one would allocate.
#[allow(clippy::large_enum_variant)]
enum Candidate {
    /// Drawn in full: its point on the light is in its weight.
    Drawn(LightCandidate),
    /// A sphere light's, weighed from the light's centre ([`Integrator::sphere_weight`]): its
    /// point is drawn, with these uniforms, only if it is kept.
    Deferred {
        index: usize,
        pmf: f64,
        point_uniforms: (f64, (f64, f64)),
        weight: f64,
    },
}

impl Candidate {
    /// Its resampling weight.
    fn weight(&self) -> f64 {
        match self {
            Candidate::Drawn(c) => c.weight,
            Candidate::Deferred { weight, .. } => *weight,
        }
    }
}

impl Integrator {
    /// The candidates drawn for each light sample:
    /// [`Settings::light_candidates`](super::Settings::light_candidates), or by
    /// default [`FEW_CANDIDATES`] where light sampling has at most [`FEW_ENTRIES`] choices of
    /// (light, image, way), else [`DEFAULT_LIGHT_CANDIDATES`].
    ///
    /// ```
    /// use orbifold_render::integrator::{Integrator, Settings};
    /// use orbifold_scene::Scene;
    ///
    /// let mut scene = Scene::default();
    /// scene.orbifold.signature = "*222".into();
    /// let sphere = Integrator::from_scene(&scene, None, Settings::default()).unwrap();
    /// scene.orbifold.signature = "*2222".into();
    /// let flat = Integrator::from_scene(&scene, None, Settings::default()).unwrap();
    /// assert_eq!((sphere.light_candidates(), flat.light_candidates()), (2, 3));
    /// ```
    pub fn light_candidates(&self) -> u32 {
        let default = if self.entries.len() <= FEW_ENTRIES {
            FEW_CANDIDATES
        } else {
            DEFAULT_LIGHT_CANDIDATES
        };
        self.settings
            .light_candidates
            .unwrap_or(default)
            .clamp(1, MAX_LIGHT_CANDIDATES)
    }

    /// Direct light at a surface point through next-event estimation: one light sample, chosen
    /// by resampling among [`LIGHT_CANDIDATES`] candidates (resampled importance sampling,
    /// Talbot et al. 2005).
    ///
    /// Each candidate is drawn as a plain light sample would be (a (light, image, way) choice
    /// from [`Integrator::pick_entry_with`]'s distribution and a point on that light), and its
    /// contribution is worked out in full except for what it costs most: the shadow segment
    /// through the mirrors that finds whether it is blocked. One candidate is then kept with
    /// probability ∝ that unblocked contribution's luminance, and only its shadow segment is
    /// traced. The estimate is the kept
    /// candidate's contribution (with the mirrors' actual reflectances and its visibility) times
    /// the candidates' mean luminance over its own: unbiased whatever the candidates' weights,
    /// since each candidate alone is distributed as a plain light sample. Where the per-point
    /// weights misjudge an image (the scene-wide half of the distribution, the cosine at the
    /// light, the point on a sphere light's side) the candidates' mean averages it out, and the
    /// noise left is mostly which candidate is blocked. A sphere light's candidate is weighed
    /// from the light's centre, and its point is drawn only if it is kept
    /// ([`Integrator::sphere_weight`]).
    ///
    /// The multiple-importance weight against BSDF sampling uses the plain light sample's
    /// density on both sides (as [`Integrator::light_pdf`] does), so that the two weights of any
    /// path still add up to one.
    #[allow(clippy::too_many_arguments)]
    pub(super) fn direct(
        &self,
        sampler: &mut Sampler,
        x: DVec3,
        h: f64,
        frame: &TangentFrame,
        shading: &Frame,
        sides: &GeometricSides,
        bsdf: &Bsdf,
        candidates: u32,
    ) -> Rgb {
        let normal = Normal::new(frame, shading.normal());
        let mut weights = [0.0; NEAR_MAX];
        let total = self.near_weights(x, h, normal, &mut weights);
        let at = LitPoint {
            x,
            h,
            frame,
            shading,
            sides,
            bsdf,
        };
        // The first candidate takes the bounce's stratified dimensions; the others are shifted
        // copies of them (each uniform on its own: that is all resampling needs).
        let u = sampler.next_f64();
        let u_point = sampler.next_f64();
        let v = sampler.next_2d();
        let uniforms = |j: u32| {
            let shifted = |a: f64, b: f64| (a + f64::from(j) * b).fract();
            (
                shifted(u, 1.0 / f64::from(candidates)),
                shifted(u_point, GOLDEN),
                (shifted(v.0, R2.0), shifted(v.1, R2.1)),
            )
        };
        let mut aimed = ArrayVec::new();
        if candidates <= 1 {
            return self
                .light_candidate(&at, (&weights, total), &mut aimed, uniforms(0))
                .map_or([0.0; 3], |c| self.light_contribution(&at, &c));
        }
        // Only the candidates that can light the point, in order (no slots to initialise).
        let mut drawn = ArrayVec::<Candidate, LIGHT_CANDIDATES>::new();
        let mut sum = 0.0;
        for j in 0..candidates {
            let (u, u_point, v) = uniforms(j);
            let candidate = self
                .pick_entry_with(&weights, total, u)
                .and_then(|(index, pmf)| {
                    if let Some(weight) = self.sphere_weight(&at, index, pmf) {
                        return Some(Candidate::Deferred {
                            index,
                            pmf,
                            point_uniforms: (u_point, v),
                            weight,
                        });
                    }
                    let mut c = self.candidate_at(&at, index, pmf, &mut aimed, (u_point, v))?;
                    c.weight = self.candidate_weight(&at, &c)?;
                    Some(Candidate::Drawn(c))
                });
            if let Some(candidate) = candidate {
                sum += candidate.weight();
                drawn.push(candidate);
            }
        }
        if !(sum > 0.0 && sum.is_finite()) {
            return [0.0; 3];
        }
        let mut target = sampler.next_independent_f64() * sum;
        let mut chosen = None;
        for candidate in &drawn {
            chosen = Some(candidate);
            if target < candidate.weight() {
                break;
            }
            target -= candidate.weight();
        }
        let Some(chosen) = chosen else {
            return [0.0; 3];
        };
        let value = match *chosen {
            Candidate::Drawn(ref c) => self.light_contribution(&at, c),
            // Its point is drawn only now: it did not enter the weight.
            Candidate::Deferred {
                index,
                pmf,
                point_uniforms,
                ..
            } => self
                .candidate_at(&at, index, pmf, &mut aimed, point_uniforms)
                .map_or([0.0; 3], |c| self.light_contribution(&at, &c)),
        };
        scale(value, sum / (f64::from(candidates) * chosen.weight()))
    }

    /// The resampling weight of a sphere light's candidate worked out from the light's centre
    /// alone, before any point on it is drawn: the luminance of the contribution of a small
    /// sphere of the light's radiance and radius seen from the centre's direction, with the
    /// image's bound on the mirrors' reflectance, over the light sample's density for it (the
    /// entry's probability over the solid angle πr²/J the sphere fills). `None` for other
    /// lights, and where the centre cannot light the point (part of the sphere still may: such
    /// a candidate is drawn and weighed in full instead, so that every point that can be lit
    /// keeps a positive weight).
    ///
    /// Resampling stays unbiased with this weight: the candidate's target density is this
    /// weight times the entry's probability times the density of the point drawn on the light,
    /// so the point does not change the weight and need only be drawn once the candidate is
    /// kept. That saves the candidates that are not kept the light's per-point work (weighing
    /// the sphere's hundreds of triangles for the point, drawing one and its normal).
    fn sphere_weight(&self, at: &LitPoint, index: usize, pmf: f64) -> Option<f64> {
        let space = self.space();
        let entry = self.entries[index];
        let light = &self.lights[entry.light];
        let (radius, radiance) = light.sphere()?;
        let image = &self.images.images[entry.image];
        let (wi, j) = aim_at(
            space,
            at.frame,
            (at.x, at.h),
            (entry.position, entry.height),
            entry.turns,
        )?;
        if !at.sides.agree(at.shading.normal(), wi) {
            return None;
        }
        let wo = at.shading.to_local(at.sides.wo);
        let wi_local = at.shading.to_local(wi);
        let f = at.bsdf.eval(wo, wi_local);
        let cos_x = wi.dot(at.shading.normal()).abs();
        let pdf_light = pmf * j / (std::f64::consts::PI * radius * radius);
        let weight = power_heuristic(1.0, pdf_light, 1.0, at.bsdf.pdf(wo, wi_local));
        let unblocked = scale(mul(f, image.reflectance), entry.attenuation);
        let value = luminance(mul(unblocked, radiance)) * cos_x * weight / pdf_light;
        (value > 0.0 && value.is_finite()).then_some(value)
    }

    /// One candidate of a light sample at `at` with `uniforms` (the choice of (light, image,
    /// way), of the light's triangle, and the point in it): its unblocked contribution, with the
    /// image's bound on the mirrors' reflectance. `None` when it cannot light the point.
    fn light_candidate<'a>(
        &'a self,
        at: &LitPoint,
        (weights, total): (&[f64; NEAR_MAX], f64),
        aimed: &mut ArrayVec<(usize, AimedLight<'a>), LIGHT_CANDIDATES>,
        (u, u_point, v): (f64, f64, (f64, f64)),
    ) -> Option<LightCandidate> {
        let (index, pmf) = self.pick_entry_with(weights, total, u)?;
        self.candidate_at(at, index, pmf, aimed, (u_point, v))
    }

    /// The candidate of entry `index` (picked with probability `pmf`) with the point on the
    /// light that uniforms `u_point`, `v` draw, as [`Integrator::light_candidate`] gives it.
    fn candidate_at<'a>(
        &'a self,
        at: &LitPoint,
        index: usize,
        pmf: f64,
        aimed: &mut ArrayVec<(usize, AimedLight<'a>), LIGHT_CANDIDATES>,
        (u_point, v): (f64, (f64, f64)),
    ) -> Option<LightCandidate> {
        let space = self.space();
        let entry = self.entries[index];
        let light = &self.lights[entry.light];
        let image = &self.images.images[entry.image];
        // The point to light, seen from the light's own copy of the room (the long way round
        // arrives from the other side: every triangle is a candidate then).
        // Candidates that chose the same entry share what the light works out for the point.
        let aimed = match aimed.iter().find(|(i, _)| *i == index) {
            Some((_, aimed)) => aimed,
            None => {
                let from = (entry.turns == 0).then(|| (image.inverse * at.x, at.h));
                light.push_aimed(space, from, index, aimed)
            }
        };
        let point = aimed.sample(space, u_point, v)?;
        let target = image.isometry * point.x;
        let link = connect(
            space,
            at.frame,
            (at.x, at.h),
            (target, point.h),
            entry.turns,
        )?;
        let wi = travel_direction(space, at.frame, &link.ray, 0.0);
        if !at.sides.agree(at.shading.normal(), wi) {
            return None;
        }
        let f = at
            .bsdf
            .eval(at.shading.to_local(at.sides.wo), at.shading.to_local(wi));
        let cos_x = wi.dot(at.shading.normal()).abs();
        if luminance(f) <= 0.0 || cos_x == 0.0 {
            return None;
        }
        Some(LightCandidate {
            index,
            pmf,
            point,
            link,
            wi,
            f,
            cos_x,
            weight: 1.0,
        })
    }

    /// The resampling weight of a candidate: the luminance of its contribution if nothing
    /// blocks it, with the image's bound on the mirrors' reflectance (`None` if zero).
    fn candidate_weight(&self, at: &LitPoint, candidate: &LightCandidate) -> Option<f64> {
        let space = self.space();
        let entry = self.entries[candidate.index];
        let light = &self.lights[entry.light];
        let image = &self.images.images[entry.image];
        let (point, link) = (&candidate.point, &candidate.link);
        // The direction of arrival at the light, carried back from the image to the light's
        // own copy (the isometry is linear on ambient vectors, so it maps tangents too).
        let u_end = image.inverse * link.ray.tangent_at(space, link.sigma);
        let (cos_a, sin_a) = (link.ray.cos_elevation, link.ray.sin_elevation);
        let unblocked = scale(mul(candidate.f, image.reflectance), entry.attenuation);
        let value = match (point.triangle, &light.emitter) {
            (Some((triangle, w)), Emitter::Area { instance, .. }) => {
                // The cosine at the light, in ambient terms (no frame needed there).
                let hit = TriangleHit {
                    s: 0.0,
                    triangle,
                    barycentric: w,
                };
                let (n_across, n_up) = instance.normal(space, &hit)?;
                let norm = (space.point_dot(n_across, n_across) + n_up * n_up).sqrt();
                let cos_out = -(space.point_dot(u_end, n_across) * cos_a + n_up * sin_a) / norm;
                let emitted = light.emission(DVec3::ZERO, cos_out);
                if cos_out == 0.0 || cos_out.is_nan() || luminance(emitted) <= 0.0 {
                    return None;
                }
                let pdf_light = candidate.pmf * point.pdf_area * link.spread / cos_out.abs();
                let wo = at.shading.to_local(at.sides.wo);
                let pdf_bsdf = at.bsdf.pdf(wo, at.shading.to_local(candidate.wi));
                let weight = power_heuristic(1.0, pdf_light, 1.0, pdf_bsdf);
                scale(
                    mul(unblocked, emitted),
                    candidate.cos_x * weight / pdf_light,
                )
            }
            _ => {
                let arrival = light.frame.to_local(space, u_end * cos_a, sin_a);
                let emitted = light.emission(-arrival, 1.0);
                scale(
                    mul(unblocked, emitted),
                    candidate.cos_x / (link.spread * candidate.pmf),
                )
            }
        };
        let weight = luminance(value);
        (weight > 0.0 && weight.is_finite()).then_some(weight)
    }

    /// The contribution of a light candidate once its connection is followed through the real
    /// room: zero when something other than a mirror is in the way, else with the mirrors'
    /// actual reflectances.
    fn light_contribution(&self, at: &LitPoint, candidate: &LightCandidate) -> Rgb {
        let space = self.space();
        let entry = self.entries[candidate.index];
        let light = &self.lights[entry.light];
        let image = &self.images.images[entry.image];
        let (point, link) = (&candidate.point, &candidate.link);
        let from = (entry.turns == 0).then(|| (image.inverse * at.x, at.h));
        let start = link.ray.advanced(space, RAY_EPSILON);
        // A point on the side of a sphere light that faces x is reached without meeting the
        // light first: its own mesh (hundreds of triangles) need not be tested.
        let skip = point
            .triangle
            .is_some_and(|(t, _)| light.reaches_unobstructed(space, t, from))
            .then_some(entry.light);
        let segment = self.follow_mirrors(
            &start,
            link.length - 2.0 * RAY_EPSILON,
            skip,
            None,
            None,
            true,
        );
        if segment.end != SegmentEnd::Reached {
            return [0.0; 3];
        }
        // It must arrive at the light itself (the chain of walls it met is the image's).
        let (end, end_h) = segment.ray.point_at(space, segment.rest + RAY_EPSILON);
        let tolerance = 1e-6 * (1.0 + link.length);
        if space.ambient_distance(end, point.x) > tolerance || (end_h - point.h).abs() > tolerance {
            return [0.0; 3];
        }
        let light_frame = TangentFrame::at(space, point.x);
        let arrival = travel_direction(
            space,
            &light_frame,
            &segment.ray,
            segment.rest + RAY_EPSILON,
        );
        let unoccluded = mul(candidate.f, segment.throughput);
        let (cos_x, pmf) = (candidate.cos_x, candidate.pmf);
        match point.triangle {
            None => {
                // A point light: its own frame is the one at its position.
                let out = -travel_direction(
                    space,
                    &light.frame,
                    &segment.ray,
                    segment.rest + RAY_EPSILON,
                );
                let emitted = light.emission(out, 1.0);
                scale(mul(unoccluded, emitted), cos_x / (link.spread * pmf))
            }
            Some((triangle, w)) => {
                let Some(n) = self.light_normal(entry.light, triangle, w, &light_frame) else {
                    return [0.0; 3];
                };
                let cos_out = -arrival.dot(n);
                let emitted = light.emission(-arrival, cos_out);
                if cos_out == 0.0 || luminance(emitted) <= 0.0 {
                    return [0.0; 3];
                }
                let pdf_light = pmf * point.pdf_area * link.spread / cos_out.abs();
                let wo = at.shading.to_local(at.sides.wo);
                let pdf_bsdf = at.bsdf.pdf(wo, at.shading.to_local(candidate.wi));
                let weight = power_heuristic(1.0, pdf_light, 1.0, pdf_bsdf);
                scale(mul(unoccluded, emitted), cos_x * weight / pdf_light)
            }
        }
    }

    /// The probability density (solid angle at the previous vertex) with which light sampling
    /// would have produced a path that hit area light `light` at (`triangle`, `w`) after meeting
    /// the walls of `segment.chain`.
    pub(super) fn light_pdf(
        &self,
        (x, h, normal): (DVec3, f64, Normal),
        light: usize,
        triangle: u32,
        w: [f64; 3],
        segment: &MirrorSegment,
        cos_out: f64,
    ) -> f64 {
        let space = self.space();
        let Some(image) = self.images.find_chain(&segment.chain) else {
            return 0.0;
        };
        let sigma = segment.length * segment.ray.cos_elevation.abs();
        // The half-turns round the sphere that the path made ([`turned`]).
        let turns = if space.kappa() > 0.0 {
            (sigma / std::f64::consts::PI)
                .floor()
                .min(f64::from(u32::MAX)) as u32
        } else {
            0
        };
        let Some(index) = self.entry_index(light, image, turns) else {
            return 0.0;
        };
        let from = (turns == 0).then(|| (self.images.images[image].inverse * x, h));
        let pdf_area = self.lights[light].pdf_area(space, triangle, w, from);
        let j = spread(space, segment.length, sigma);
        self.pmf_at(x, h, normal, index) * pdf_area * j / cos_out.abs().max(1e-12)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::integrator::Settings;
    use crate::integrator::mirror_segment::HitKind;

    #[test]
    fn a_bounce_that_reaches_a_light_round_the_sphere_could_have_been_a_light_sample() {
        // In a spherical room of mirrors, the geodesics from a point of the floor to the
        // sphere light that go round the sphere once and more reach it through the mirrors.
        // Light sampling must draw them too (a positive density at the point where such a
        // bounce meets the light), or MIS counts those bounces unweighted: the noisiest light
        // of the spherical rooms of the seed's Table 8.1.
        for signature in ["*", "*22", "*222"] {
            let mut scene = orbifold_scene::Scene::default();
            scene.orbifold.signature = signature.into();
            scene.objects.clear();
            scene.room.reflectance = [0.9; 3];
            scene.lights[0].kind = orbifold_scene::LightKind::Sphere;
            scene.lights[0].at = [
                scene.layout().unwrap().centre.re,
                scene.layout().unwrap().centre.im,
            ];
            let integrator = Integrator::from_scene(&scene, None, Settings::default()).unwrap();
            let space = integrator.space();
            let light = &integrator.lights[0];
            let offset = integrator.centre_frame.e1 * 0.2 + integrator.centre_frame.e2 * 0.1;
            let x = space.exp(integrator.centre, offset);
            let h = 1e-6;
            let frame = TangentFrame::at(space, x);
            let up = Normal::new(&frame, DVec3::Z);
            let mut reached = 0;
            for turns in 0..8 {
                let link =
                    connect(space, &frame, (x, h), (light.position, light.height), turns).unwrap();
                let start = link.ray.advanced(space, RAY_EPSILON);
                let segment =
                    integrator.follow_mirrors(&start, f64::INFINITY, None, None, None, false);
                let SegmentEnd::Hit(hit) = segment.end else {
                    continue;
                };
                let HitKind::Light {
                    light: l,
                    triangle,
                    barycentric: w,
                } = hit.kind
                else {
                    continue;
                };
                let sigma = segment.length * segment.ray.cos_elevation;
                assert_eq!(
                    (sigma / std::f64::consts::PI).floor() as u32,
                    turns,
                    "{signature}"
                );
                let light_frame = TangentFrame::at(space, hit.point);
                let n = integrator
                    .light_normal(l, triangle, w, &light_frame)
                    .unwrap();
                let travel = travel_direction(space, &light_frame, &segment.ray, segment.rest);
                let pdf =
                    integrator.light_pdf((x, h, up), l, triangle, w, &segment, -travel.dot(n));
                assert!(pdf > 0.0, "{signature}: {turns} half-turns, density {pdf}");
                reached += 1;
            }
            assert!(
                reached >= 6,
                "{signature}: the light reached {reached} ways of 8"
            );
        }
    }

    #[test]
    fn a_sphere_light_whose_centre_is_behind_the_surface_still_lights_it_through_resampling() {
        // A sphere light's resampling candidates are weighed from its centre. Where the centre
        // lies a little behind the surface while part of the sphere is in front, the candidate
        // is drawn and weighed in full instead: the resampled estimate must keep that light.
        // Without mirrors the light has one image, so losing it would lose all the light.
        for (signature, tilt) in [("*2222", 0.05f64), ("*2223", 0.1), ("*444", 0.2)] {
            let mut scene = orbifold_scene::Scene::default();
            scene.orbifold.signature = signature.into();
            scene.room.mirrors = orbifold_scene::MirrorDefault::None;
            scene.lights[0].kind = orbifold_scene::LightKind::Sphere;
            scene.lights[0].radius = 0.2;
            let integrator = Integrator::from_scene(&scene, None, Settings::default()).unwrap();
            let space = integrator.space();
            let light = &integrator.lights[0];
            // A point 0.6 from the light's centre at its height, tilted so that the centre is
            // `tilt` radians below its horizon (the sphere's angular radius is about 0.34).
            let away = space.transport(DVec3::Z, light.position, DVec3::new(0.6, 0.0, 0.0));
            let x = space.exp(light.position, away);
            let frame = TangentFrame::at(space, x);
            let link = connect(
                space,
                &frame,
                (x, light.height),
                (light.position, light.height),
                0,
            )
            .unwrap();
            let towards = travel_direction(space, &frame, &link.ray, 0.0);
            let normal = (DVec3::Z * tilt.cos() - towards * tilt.sin()).normalize();
            assert!(normal.dot(towards) < 0.0);
            let shading = Frame::from_normal(normal);
            let sides = GeometricSides {
                geometric: normal,
                wo: normal,
            };
            let bsdf = Bsdf::Diffuse { albedo: [0.8; 3] };
            let estimate = |candidates: u32| {
                let n = 4000;
                let (mut sum, mut squares) = (0.0, 0.0);
                for i in 0..n {
                    let mut sampler = Sampler::new(7, 0, i);
                    sampler.start_bounce(0);
                    let value = luminance(integrator.direct(
                        &mut sampler,
                        x,
                        light.height,
                        &frame,
                        &shading,
                        &sides,
                        &bsdf,
                        candidates,
                    ));
                    sum += value;
                    squares += value * value;
                }
                let mean = sum / n as f64;
                (mean, ((squares / n as f64 - mean * mean) / n as f64).sqrt())
            };
            let (plain, plain_error) = estimate(1);
            let (resampled, resampled_error) = estimate(4);
            assert!(plain > 0.0, "{signature}: the sphere lights the point");
            let tolerance = 4.0 * (plain_error.powi(2) + resampled_error.powi(2)).sqrt();
            assert!(
                (plain - resampled).abs() < tolerance,
                "{signature}: plain {plain} ± {plain_error}, resampled {resampled} ± {resampled_error}"
            );
        }
    }
}
