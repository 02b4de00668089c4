//! Image textures that repeat over the plane, looked up at a point or averaged over a box (a
//! camera ray's pixel footprint, [`orbifold_trace::footprint`]) through a summed-area table: the
//! exact mean of the piecewise-constant image over any box, wrapping around, in constant time.

use std::path::Path;
use std::sync::Arc;

use glam::DVec3;

use super::TextureEvalContext;
use crate::lights::Rgb;

/// An image repeated with period 1 in (u, v); v runs up the image (row 0 is v = 1).
#[derive(Clone, Debug)]
pub(crate) struct ImageTexture {
    pixels: Arc<Vec<Rgb>>,
    /// Summed-area table over (x, y) = (u, 1 − v): `sums[j·(w + 1) + i]` is the integral over
    /// [0, i/w] × [0, j/h], in texel units (one texel has area 1).
    sums: Arc<Vec<Rgb>>,
    width: usize,
    height: usize,
}

impl ImageTexture {
    /// The texture of `width`×`height` linear RGB pixels, row by row from the top.
    ///
    /// # Panics
    ///
    /// When the sizes do not match or are zero.
    pub(super) fn new(pixels: Vec<Rgb>, width: usize, height: usize) -> ImageTexture {
        assert!(width > 0 && height > 0 && pixels.len() == width * height);
        let stride = width + 1;
        let mut sums = vec![[0.0; 3]; stride * (height + 1)];
        for j in 0..height {
            let mut row = [0.0; 3];
            for i in 0..width {
                let p = pixels[j * width + i];
                for k in 0..3 {
                    row[k] += p[k];
                    sums[(j + 1) * stride + i + 1][k] = sums[j * stride + i + 1][k] + row[k];
                }
            }
        }
        ImageTexture {
            pixels: Arc::new(pixels),
            sums: Arc::new(sums),
            width,
            height,
        }
    }

    /// The image in `file` (PNG or JPEG, sRGB), in linear RGB, read and decoded by
    /// [`orbifold_scene::files::read_image`] (given bytes before the disk; its format its
    /// extension's).
    pub(super) fn read(file: &Path) -> Result<ImageTexture, String> {
        let image = orbifold_scene::files::read_image(file)?.to_rgb8();
        let (width, height) = (image.width() as usize, image.height() as usize);
        let pixels = image
            .pixels()
            .map(|p| p.0.map(orbifold_scene::color::linear_from_srgb8))
            .collect::<Vec<_>>();
        Ok(ImageTexture::new(pixels, width, height))
    }

    /// The albedo where `lookup` says, the image covering `scale` × `scale` of its texture
    /// coordinates (intrinsic or model): the texel at the point, or, with a pixel footprint,
    /// the image's mean over the box of the footprint's half-axes.
    pub(super) fn albedo(&self, scale: f64, intrinsic: bool, lookup: &TextureEvalContext) -> Rgb {
        let Some([centre, a, b]) = lookup.footprint else {
            let p = (lookup.coords)(intrinsic, DVec3::ZERO);
            return self.texel(p[0] / scale, p[1] / scale);
        };
        let (p, pa, pb) = (
            (lookup.coords)(intrinsic, centre),
            (lookup.coords)(intrinsic, centre + a),
            (lookup.coords)(intrinsic, centre + b),
        );
        let (u, v) = (p[0] / scale, p[1] / scale);
        let half = |i: usize| ((pa[i] - p[i]).powi(2) + (pb[i] - p[i]).powi(2)).sqrt() / scale;
        self.box_mean(u, v, half(0), half(1))
    }

    /// The texel at (u, v).
    pub(super) fn texel(&self, u: f64, v: f64) -> Rgb {
        let (u, v) = (u.rem_euclid(1.0), v.rem_euclid(1.0));
        let i = ((u * self.width as f64) as usize).min(self.width - 1);
        let j = (((1.0 - v) * self.height as f64) as usize).min(self.height - 1);
        self.pixels[j * self.width + i]
    }

    /// The mean over the box (u ± hu, v ± hv), wrapping around; the texel at (u, v) for a box
    /// that is not finite or smaller than a millionth of a texel (where the table's differences
    /// would be rounding).
    pub(super) fn box_mean(&self, u: f64, v: f64, hu: f64, hv: f64) -> Rgb {
        let (w, h) = (self.width as f64, self.height as f64);
        // Texel units: x = u·w, y = (1 − v)·h.
        let (x0, x1) = ((u - hu) * w, (u + hu) * w);
        let (y0, y1) = ((1.0 - v - hv) * h, (1.0 - v + hv) * h);
        let area = (x1 - x0) * (y1 - y0);
        if !(area.is_finite() && area > 1e-6) {
            return self.texel(u, v);
        }
        let c = |x, y| self.cumulative(x, y);
        let (a, b, d, e) = (c(x1, y1), c(x0, y1), c(x1, y0), c(x0, y0));
        std::array::from_fn(|k| ((a[k] - b[k] - d[k] + e[k]) / area).max(0.0))
    }

    /// ∫ over [0, x] × [0, y] (texel units, any sign) of the repeated image.
    fn cumulative(&self, x: f64, y: f64) -> Rgb {
        let (w, h) = (self.width as f64, self.height as f64);
        let (nx, ny) = ((x / w).floor(), (y / h).floor());
        let (fx, fy) = (x - nx * w, y - ny * h);
        let (all, column, row, part) = (
            self.table(w, h),
            self.table(w, fy),
            self.table(fx, h),
            self.table(fx, fy),
        );
        std::array::from_fn(|k| nx * ny * all[k] + nx * column[k] + ny * row[k] + part[k])
    }

    /// The summed-area table at (x, y) ∈ [0, w] × [0, h], bilinear between its entries: exact
    /// for a piecewise-constant image.
    fn table(&self, x: f64, y: f64) -> Rgb {
        let stride = self.width + 1;
        let x = x.clamp(0.0, self.width as f64);
        let y = y.clamp(0.0, self.height as f64);
        let (i, j) = (
            (x as usize).min(self.width - 1),
            (y as usize).min(self.height - 1),
        );
        let (tx, ty) = (x - i as f64, y - j as f64);
        let at = |i: usize, j: usize| self.sums[j * stride + i];
        let (s00, s10, s01, s11) = (at(i, j), at(i + 1, j), at(i, j + 1), at(i + 1, j + 1));
        std::array::from_fn(|k| {
            let bottom = s00[k] + (s10[k] - s00[k]) * tx;
            let top = s01[k] + (s11[k] - s01[k]) * tx;
            bottom + (top - bottom) * ty
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    fn texture() -> ImageTexture {
        // 7×5 texels of distinct colours.
        let pixels = (0..35)
            .map(|i| {
                let t = f64::from(i);
                [t / 35.0, (t * 0.37).sin().abs(), ((t * 1.3) % 1.0)]
            })
            .collect();
        ImageTexture::new(pixels, 7, 5)
    }

    proptest! {
        /// The box mean is the mean of texel lookups over the box (midpoint rule, wrapping).
        #[test]
        fn box_means_are_means_of_the_texels(
            u in -3.0f64..3.0, v in -3.0f64..3.0, hu in 0.01f64..1.5, hv in 0.01f64..1.5,
        ) {
            let t = texture();
            let n = 300;
            let mut sum = [0.0; 3];
            for a in 0..n {
                for b in 0..n {
                    let uu = u - hu + 2.0 * hu * (f64::from(a) + 0.5) / f64::from(n);
                    let vv = v - hv + 2.0 * hv * (f64::from(b) + 0.5) / f64::from(n);
                    let p = t.texel(uu, vv);
                    for k in 0..3 {
                        sum[k] += p[k] / f64::from(n * n);
                    }
                }
            }
            let mean = t.box_mean(u, v, hu, hv);
            for k in 0..3 {
                // The midpoint rule's error: a texel edge crossing a cell, 1/n of the box.
                prop_assert!((mean[k] - sum[k]).abs() < 0.02, "{:?} vs {:?}", mean, sum);
            }
        }
    }

    /// A PNG of one row: red, then blue.
    fn red_blue_png() -> Vec<u8> {
        let image = image::RgbImage::from_fn(2, 1, |x, _| {
            image::Rgb(if x == 0 { [255, 0, 0] } else { [0, 0, 255] })
        });
        let mut bytes = Vec::new();
        image
            .write_to(
                &mut std::io::Cursor::new(&mut bytes),
                image::ImageFormat::Png,
            )
            .unwrap();
        bytes
    }

    #[test]
    fn a_texture_given_by_bytes_is_read_as_a_file_would_be() {
        orbifold_scene::files::provide("render-unit/given.png", red_blue_png());
        let t = ImageTexture::read(Path::new("render-unit/given.png")).unwrap();
        assert_eq!((t.width, t.height), (2, 1));
        assert_eq!(t.texel(0.25, 0.5), [1.0, 0.0, 0.0]);
        assert_eq!(t.texel(0.75, 0.5), [0.0, 0.0, 1.0]);
        // A scene that names it, with the folder it is given in: the renderer takes it.
        let mut scene = orbifold_scene::Scene::default();
        scene.room.floor = orbifold_scene::Material::Texture {
            path: "given.png".into(),
            scale: 0.5,
            coordinates: Default::default(),
        };
        let settings = crate::integrator::Settings::default();
        let base = Some(Path::new("render-unit"));
        assert!(crate::integrator::Integrator::from_scene(&scene, base, settings).is_ok());
        // Not given, and not on the disk: the error names the file, as it always did.
        let error = ImageTexture::read(Path::new("render-unit/missing.png")).unwrap_err();
        assert!(
            error.starts_with("cannot read texture render-unit/missing.png: "),
            "{error}"
        );
        scene.room.floor = orbifold_scene::Material::Texture {
            path: "missing.png".into(),
            scale: 0.5,
            coordinates: Default::default(),
        };
        let error = match crate::integrator::Integrator::from_scene(&scene, base, settings) {
            Ok(_) => panic!("the texture is missing, but the scene was taken"),
            Err(error) => error,
        };
        assert!(error.contains("render-unit/missing.png"), "{error}");
    }

    #[test]
    fn a_box_without_area_or_within_a_texel_is_the_texel() {
        let t = texture();
        // (Points off the texels' edges: a tiny box on an edge averages its two sides.)
        for (u, v) in [(0.13, 0.27), (0.93, 0.01), (-0.4, 2.7)] {
            assert_eq!(t.box_mean(u, v, 0.0, 0.0), t.texel(u, v));
            let tiny = t.box_mean(u, v, 1e-4, 1e-4);
            let texel = t.texel(u, v);
            assert!(
                (0..3).all(|k| (tiny[k] - texel[k]).abs() < 1e-8),
                "{tiny:?} {texel:?}"
            );
        }
    }

    #[test]
    fn a_whole_period_is_the_image_mean() {
        let t = texture();
        let mean: Vec<f64> = (0..3)
            .map(|k| t.pixels.iter().map(|p| p[k]).sum::<f64>() / 35.0)
            .collect();
        let m = t.box_mean(0.3, -1.7, 0.5, 1.5);
        assert!(
            (0..3).all(|k| (m[k] - mean[k]).abs() < 1e-12),
            "{m:?} {mean:?}"
        );
    }
}
