//! The settings of the light transport: how deep paths go, whether light is sampled through
//! mirror images, the pixel and bounce footprints, the radiance cache and the light sample's
//! candidates. A scene's `[render]` table sets some of them ([`Settings::of_scene`]).

use orbifold_scene::Scene;

use crate::lights::Rgb;

/// Settings of the light transport.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Settings {
    /// The most non-mirror bounces of a path.
    pub max_depth: u32,
    /// Next-event estimation (light sampling through mirror images) with MIS; without it, light
    /// is found only by paths that hit it (brute force, the reference for tests).
    pub nee: bool,
    /// Radiance that every opaque surface other than a mirror or a light emits, uniformly in every
    /// direction (0 by default). A closed room whose surfaces all glow and reflect with albedo
    /// ρ reaches the radiance glow / (1 − ρ) everywhere (the furnace test); a small glow also
    /// shows the room's shape without any lights.
    pub glow: Rgb,
    /// Light as if space were flat: the room's model picture rendered with straight rays (see
    /// [`crate::straight_rays`]; the seed's Fig. 8.1a), for teaching and comparison.
    pub straight_rays: bool,
    /// Carry each camera ray's pixel footprint ([`orbifold_trace::footprint`]; on by default): the
    /// light's mirror images up to a few pixels wide count by the share of the pixel they
    /// cover, not by ray hits, and checkerboards and images are averaged over the footprint. It
    /// needs the room's mirrors to be isometries, so straight rays never carry it.
    pub pixel_footprint: bool,
    /// With the pixel footprint and light sampling, rays that leave a diffuse bounce carry a
    /// footprint too (`BOUNCE_FOOTPRINT`; on by default), with which the far mirror images of
    /// sphere lights that light sampling cannot draw (beyond the image set's cutoff: thousands
    /// in a hyperbolic room) count by the share of it they cover instead of by rare hits of
    /// enormous radiance. Off, those images are found by ray hits alone.
    pub bounce_footprint: bool,
    /// Read the light that far mirror images of diffuse surfaces reflect, and the light that
    /// diffuse surfaces reached by a diffuse bounce reflect, from a cache filled by the render's
    /// own paths ([`crate::radiance_cache`]; on by default, used by [`crate::render`]). It needs
    /// light sampling and the pixel footprint.
    pub radiance_cache: bool,
    /// Candidates drawn for each light sample, of which one is kept by resampling and tested
    /// for visibility (1 for the plain light sample; at most
    /// [`MAX_LIGHT_CANDIDATES`](super::MAX_LIGHT_CANDIDATES)). More candidates cost something
    /// each and lower the noise of direct light wherever the per-image choice misjudges a
    /// point's light. `None` (the default): [`FEW_CANDIDATES`](super::FEW_CANDIDATES) where
    /// light sampling draws at most [`FEW_ENTRIES`](super::FEW_ENTRIES) (light, image, way)
    /// choices (the spherical rooms), else
    /// [`DEFAULT_LIGHT_CANDIDATES`](super::DEFAULT_LIGHT_CANDIDATES).
    pub light_candidates: Option<u32>,
}

impl Default for Settings {
    fn default() -> Self {
        Settings {
            max_depth: 8,
            nee: true,
            glow: [0.0; 3],
            straight_rays: false,
            pixel_footprint: true,
            bounce_footprint: true,
            radiance_cache: true,
            light_candidates: None,
        }
    }
}

impl Settings {
    /// The settings a scene's `[render]` table asks for: its most bounces and whether light
    /// runs in straight lines; the rest as by default.
    ///
    /// ```
    /// use orbifold_render::integrator::Settings;
    /// use orbifold_scene::Scene;
    ///
    /// let mut scene = Scene::default();
    /// scene.render.max_depth = 3;
    /// scene.render.straight_rays = true;
    /// let settings = Settings::of_scene(&scene);
    /// assert_eq!((settings.max_depth, settings.straight_rays), (3, true));
    /// assert!(settings.nee);
    /// ```
    pub fn of_scene(scene: &Scene) -> Settings {
        Settings {
            max_depth: scene.render.max_depth,
            straight_rays: scene.render.straight_rays,
            ..Settings::default()
        }
    }
}
