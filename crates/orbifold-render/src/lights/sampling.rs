//! Sampling points on a light for a lit point, and the density of a point so sampled.
//!
//! A point light is its own sample. An area light picks a triangle and then a point uniform in
//! its area: a rectangle light picks its triangles by area, a sphere light only among those that
//! face the lit point, by about the solid angle each fills (`facing.rs`). [`Light::pdf_area`]
//! gives the density of a point so drawn, for weighing light samples against the bounces that
//! hit the light.

use arrayvec::ArrayVec;
use glam::DVec3;
use orbifold::space::Space;

use super::area::area_jacobian;
use super::emitter::{Emitter, Light};
use super::facing::{Facing, MAX_BLOCKS, ShadingPoint};

/// A point sampled on a light, with its emission towards a direction still to be given.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LightPoint {
    /// Ambient horizontal position.
    pub x: DVec3,
    /// Height.
    pub h: f64,
    /// Probability density per unit area (0 for point lights).
    pub pdf_area: f64,
    /// The triangle of the light's mesh and the barycentrics (area lights).
    pub triangle: Option<(u32, [f64; 3])>,
}

/// The facing triangles of a sphere light for one lit point, by blocks ([`Facing::kept_blocks`]).
#[derive(Clone, Copy, Debug)]
struct KeptBlocks {
    /// The lit point, as the light's facing test sees it.
    shading: ShadingPoint,
    /// The kept weight of each block.
    sums: [f64; MAX_BLOCKS],
    /// Their total.
    total: f64,
}

/// A light made ready to sample points for one lit point ([`Light::aimed_at`]).
#[derive(Clone, Copy, Debug)]
pub struct AimedLight<'a> {
    /// The light.
    light: &'a Light,
    /// The lit point, as for [`Light::sample_point`].
    from: Option<(DVec3, f64)>,
    /// For a sphere light, its triangles that face `from`.
    kept: Option<KeptBlocks>,
}

impl AimedLight<'_> {
    /// Works out which of a sphere light's triangles face `from`, in place.
    fn cull_back_faces(&mut self, space: Space) {
        let light = self.light;
        let Emitter::Area {
            facing: Some(facing),
            ..
        } = &light.emitter
        else {
            return;
        };
        let Some((_, b)) = light.facing_from(space, self.from) else {
            return;
        };
        let shading = facing.shading_point(b);
        let kept = self.kept.insert(KeptBlocks {
            shading,
            sums: [0.0; MAX_BLOCKS],
            total: 0.0,
        });
        match facing.kept_blocks(&shading, &mut kept.sums) {
            Some(total) => kept.total = total,
            None => self.kept = None,
        }
    }

    /// A point on the light for uniforms `u`, `v`, as [`Light::sample_point`] draws it.
    pub fn sample(&self, space: Space, u: f64, v: (f64, f64)) -> Option<LightPoint> {
        let light = self.light;
        let Emitter::Area {
            areas,
            total_area,
            triangle_distribution,
            facing,
            ..
        } = &light.emitter
        else {
            return Some(LightPoint {
                x: light.position,
                h: light.height,
                pdf_area: 0.0,
                triangle: None,
            });
        };
        if let (Some(kept), Some(facing)) = (&self.kept, facing)
            && kept.total > 0.0
        {
            // The kept triangles' set changes with the point: block sums, then one block.
            let i = facing.pick(&kept.shading, &kept.sums, u * kept.total)?;
            let weight = facing.weight_of(i, &kept.shading);
            let probability = weight / kept.total;
            return light.point_on(space, i, probability, v);
        }
        let (index, probability) = match (light.facing_weight(space, self.from), facing) {
            (Some((shading, kept)), Some(facing)) => {
                // A linear scan over the kept triangles (their set changes with the point).
                let mut target = u * kept;
                let mut chosen = None;
                for i in 0..areas.len() {
                    let weight = facing.weight_of(i, &shading);
                    if weight > 0.0 {
                        chosen = Some((i, weight));
                        if target < weight {
                            break;
                        }
                        target -= weight;
                    }
                }
                let (i, weight) = chosen?;
                (i, weight / kept)
            }
            // Pick a triangle ∝ area (a binary search over the cumulative areas).
            _ => {
                let (i, _) = triangle_distribution.sample(u);
                (i, areas[i] / total_area)
            }
        };
        light.point_on(space, index, probability, v)
    }
}

impl Light {
    /// For a sphere light and a lit point `from` (world coordinates, in the light's own copy of
    /// the room: the image's inverse applied), its [`Facing`] and the point in its local
    /// coordinates; `None` for other lights, without `from`, or when every triangle is a
    /// candidate (the point is too close).
    fn facing_from(&self, space: Space, from: Option<(DVec3, f64)>) -> Option<(&Facing, DVec3)> {
        let (
            Emitter::Area {
                instance,
                facing: Some(facing),
                ..
            },
            Some((x, h)),
        ) = (&self.emitter, from)
        else {
            return None;
        };
        let b = facing.local_point(space, (instance.to_object * x, h - instance.height))?;
        Some((facing, b))
    }

    /// For a sphere light and a lit point `from` (as for [`Light::facing_from`]), the point as
    /// the facing test sees it and the total weight of the triangles kept for it; `None` when
    /// every triangle is a candidate.
    fn facing_weight(
        &self,
        space: Space,
        from: Option<(DVec3, f64)>,
    ) -> Option<(ShadingPoint, f64)> {
        let (facing, b) = self.facing_from(space, from)?;
        let shading = facing.shading_point(b);
        let total = facing.kept_weight(&shading);
        (total > 0.0).then_some((shading, total))
    }

    /// Samples a point on the light (the centre for point lights) with uniforms `u`, `v`. With
    /// `from`, the point to be lit (world coordinates in the light's own copy of the room), a
    /// sphere light picks only among its triangles that can face it.
    pub fn sample_point(
        &self,
        space: Space,
        u: f64,
        v: (f64, f64),
        from: Option<(DVec3, f64)>,
    ) -> Option<LightPoint> {
        self.aimed_at(space, from).sample(space, u, v)
    }

    /// What [`Light::sample_point`] works out for the point `from` before it draws: which of a
    /// sphere light's triangles face it. Worked out once, it serves several draws for the same
    /// point (the candidates of a resampled light sample that chose the same image).
    ///
    /// ```
    /// use num_complex::Complex64;
    /// use orbifold_render::lights::Light;
    /// use orbifold_scene::{LightKind, Scene};
    ///
    /// let mut scene = Scene::default();
    /// scene.orbifold.signature = "*333".into();
    /// let layout = scene.layout().unwrap();
    /// scene.lights[0].kind = LightKind::Sphere;
    /// scene.lights[0].at = [layout.centre.re, layout.centre.im];
    /// let space = layout.space();
    /// let lights = Light::from_scene(space, &scene).unwrap();
    /// let x = space.to_ambient(layout.centre + Complex64::new(0.3, 0.1));
    /// let from = Some((x, 0.2));
    /// let aimed = lights[0].aimed_at(space, from);
    /// let once = aimed.sample(space, 0.4, (0.3, 0.6)).unwrap();
    /// let again = lights[0].sample_point(space, 0.4, (0.3, 0.6), from).unwrap();
    /// assert_eq!(once.x, again.x);
    /// assert_eq!(once.pdf_area, again.pdf_area);
    /// ```
    pub fn aimed_at(&self, space: Space, from: Option<(DVec3, f64)>) -> AimedLight<'_> {
        let mut aimed = AimedLight {
            light: self,
            from,
            kept: None,
        };
        aimed.cull_back_faces(space);
        aimed
    }

    /// [`Light::aimed_at`] pushed onto `list` with the tag `key`, its triangles' weights worked
    /// out in place in the list: they fill several cache lines, which working them out elsewhere
    /// would copy in.
    pub(crate) fn push_aimed<'a, 'b, const N: usize>(
        &'a self,
        space: Space,
        from: Option<(DVec3, f64)>,
        key: usize,
        list: &'b mut ArrayVec<(usize, AimedLight<'a>), N>,
    ) -> &'b AimedLight<'a> {
        list.push((
            key,
            AimedLight {
                light: self,
                from,
                kept: None,
            },
        ));
        let (_, aimed) = list.last_mut().expect("just pushed");
        aimed.cull_back_faces(space);
        aimed
    }

    /// A point of the area light's triangle `index`, picked with `probability`, uniform in its
    /// area for uniforms `v`.
    fn point_on(
        &self,
        space: Space,
        index: usize,
        probability: f64,
        v: (f64, f64),
    ) -> Option<LightPoint> {
        let Emitter::Area { instance, .. } = &self.emitter else {
            return None;
        };
        let root = v.0.sqrt();
        let w = [1.0 - root, root * (1.0 - v.1), root * v.1];
        let triangle = instance.bvh.triangle(index as u32);
        let (x, h) = triangle.point(space, w);
        let jacobian = area_jacobian(space, &triangle.points, &triangle.heights, w);
        if jacobian <= 0.0 {
            return None;
        }
        Some(LightPoint {
            x: instance.to_world * x,
            h: h + instance.height,
            pdf_area: probability * 2.0 / jacobian,
            triangle: Some((index as u32, w)),
        })
    }

    /// Whether a geodesic from `from` (world coordinates in the light's own copy of the room, as
    /// for [`Light::sample_point`]) to a point of triangle `triangle` cannot meet the light
    /// itself before it: for a sphere light's triangle that faces `from` clearly (a geodesic
    /// enters a convex ball once, through the side that faces it; triangles near the silhouette,
    /// where the curvature could decide, are left out). Shadow rays to such a point need not
    /// test the light's own mesh. False for other lights and triangles.
    pub fn reaches_unobstructed(
        &self,
        space: Space,
        triangle: u32,
        from: Option<(DVec3, f64)>,
    ) -> bool {
        let i = triangle as usize;
        // Facing by more than the margin that covers the curvature over the light (the test is
        // made in the tangent space at the light's centre).
        self.facing_from(space, from).is_some_and(|(facing, b)| {
            i < facing.planes.len() && {
                let [x, y, z, offset] = facing.planes[i];
                DVec3::new(x, y, z).dot(b) - offset > facing.margin(b)
            }
        })
    }

    /// The density per unit area with which [`Light::sample_point`] picks the point of triangle
    /// `triangle` at barycentrics `w` (area lights) for the lit point `from`.
    pub fn pdf_area(
        &self,
        space: Space,
        triangle: u32,
        w: [f64; 3],
        from: Option<(DVec3, f64)>,
    ) -> f64 {
        let Emitter::Area {
            instance,
            areas,
            total_area,
            facing,
            ..
        } = &self.emitter
        else {
            return 0.0;
        };
        let probability = match (self.facing_weight(space, from), facing) {
            (Some((shading, kept)), Some(facing)) => {
                facing.weight_of(triangle as usize, &shading) / kept
            }
            _ => areas[triangle as usize] / total_area,
        };
        let t = instance.bvh.triangle(triangle);
        let jacobian = area_jacobian(space, &t.points, &t.heights, w);
        if jacobian <= 0.0 {
            return 0.0;
        }
        probability * 2.0 / jacobian
    }
}
