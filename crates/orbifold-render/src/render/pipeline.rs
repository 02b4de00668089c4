//! The render pipeline: from a camera's view of a scene to a finished picture — progressive
//! rounds ([`render`]), the guided denoiser when the picture is to be denoised
//! ([`RenderOptions::denoised`]), an exposure, and tone mapping for display — with the HDR
//! image kept for EXR. `orbifold render`, `orbifold animate` and the studio all make their
//! pictures here, so that a scene and a camera give the same picture everywhere.

use std::path::Path;
use std::sync::atomic::AtomicBool;
use std::time::Duration;

use orbifold_trace::camera::Camera;

use super::options::RenderOptions;
use super::progressive::{Progressive, Rendered, render};
use crate::denoise::{DenoiseOptions, denoise};
use crate::film::{Film, tone_map};
use crate::integrator::Integrator;

/// A finished picture: the render's HDR image, denoised when it was asked for, and the
/// exposure its display form is tone-mapped with.
///
/// ```
/// use std::sync::atomic::AtomicBool;
/// use orbifold_render::integrator::{Integrator, Settings};
/// use orbifold_render::render::{RenderOptions, render_picture};
/// use orbifold_trace::camera::Camera;
///
/// let scene = orbifold_scene::Scene::default();
/// let integrator = Integrator::from_scene(&scene, None, Settings::default())?;
/// let camera = Camera::new(integrator.space(), &scene.camera);
/// let options = RenderOptions { denoised: true, ..RenderOptions::new(8, 6, 2, 1) };
/// let picture = render_picture(&integrator, &camera, &options, None, &AtomicBool::new(false), &|_, _| {});
/// assert!(picture.denoised);
/// assert_eq!(picture.rgba8().len(), 8 * 6 * 4);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
#[derive(Clone, Debug)]
pub struct Picture {
    /// The denoised film, when the picture was denoised (else the rendered film is the image).
    denoised_image: Option<Film>,
    /// Whether the image ([`Picture::image`]) was denoised.
    pub denoised: bool,
    /// The exposure (stops) that the display form is tone-mapped with: the caller's, or the
    /// raw film's log-average ([`Film::auto_exposure`]).
    pub exposure: f64,
    /// The render as the sampler left it: the raw film, the denoiser's guides, samples, paths,
    /// rays, time.
    pub rendered: Rendered,
}

impl Picture {
    /// Finishes a render: denoises it when `denoised`, and fixes the exposure (`None`: the raw
    /// film's log-average).
    pub fn finish(rendered: Rendered, denoised: bool, exposure: Option<f64>) -> Picture {
        let exposure = exposure.unwrap_or_else(|| rendered.film.auto_exposure());
        let denoised_image =
            denoised.then(|| denoise(&rendered.film, &rendered.guides, &DenoiseOptions::default()));
        Picture {
            denoised_image,
            denoised,
            exposure,
            rendered,
        }
    }

    /// The finished HDR image: the denoised film, or the rendered film itself.
    pub fn image(&self) -> &Film {
        self.denoised_image.as_ref().unwrap_or(&self.rendered.film)
    }

    /// The picture's width and height in pixels.
    pub fn size(&self) -> (u32, u32) {
        (self.image().width(), self.image().height())
    }

    /// The display form: tone-mapped 8-bit sRGB, four bytes a pixel (opaque), rows from the top.
    pub fn rgba8(&self) -> Vec<u8> {
        let (width, height) = self.size();
        let image = self.image();
        let mut rgba = Vec::with_capacity(width as usize * height as usize * 4);
        for y in 0..height {
            for x in 0..width {
                let [r, g, b] = tone_map(image.pixel(x, y), self.exposure);
                rgba.extend_from_slice(&[r, g, b, 255]);
            }
        }
        rgba
    }

    /// Writes the picture by `path`'s extension: the HDR image as OpenEXR, or its display form
    /// as PNG or JPEG; atomically, so `path` never holds a partial image ([`Film::write`]).
    pub fn write(&self, path: &Path) -> Result<(), String> {
        self.image().write(path, self.exposure)
    }
}

/// Renders the camera's view to a finished picture: [`render`] (progressive rounds until the
/// samples, the time limit or the noise target of `options`, or `cancel`), then
/// [`Picture::finish`], denoised when `options.denoised`. `progress(done, wanted)` is called
/// after every round.
pub fn render_picture(
    integrator: &Integrator,
    camera: &Camera,
    options: &RenderOptions,
    exposure: Option<f64>,
    cancel: &AtomicBool,
    progress: &(dyn Fn(u32, u32) + Sync),
) -> Picture {
    let rendered = render(integrator, camera, options, cancel, progress);
    Picture::finish(rendered, options.denoised, exposure)
}

impl Progressive<'_> {
    /// The picture so far, finished as [`render_picture`] finishes the whole render (denoised
    /// when the options ask for it), after `elapsed` of rendering: for a caller that shows the
    /// picture while it refines.
    pub fn picture(&self, elapsed: Duration, exposure: Option<f64>) -> Picture {
        Picture::finish(self.snapshot(elapsed), self.options().denoised, exposure)
    }
}
