//! The scene's image textures on the GPU: one layer of a 2D array texture per image file, so
//! that the part table can name an image by its layer (`PartStyle::layer`).
//!
//! The shader looks an image up as the renderer does (docs/scene-format.md, "Where a pattern
//! lies"): the texel at u = p₀/scale along its rows and v = p₁/scale upwards, repeating, 8-bit
//! sRGB decoded to linear (the texture's format does the decoding); the nearest texel where a
//! pixel covers less than a texel, mip levels (means in linear light) where it covers more, as
//! the renderer averages an image over a pixel's footprint. The
//! layers of an array share one size, so each image is resampled to the largest width and
//! height among them (at most [`MAX_SIDE`]); which texel a point falls in is a matter of
//! fractions of the image, so the pattern stays where it is.

use std::path::{Path, PathBuf};

/// The longest side of a layer: larger images are resampled down to it.
pub const MAX_SIDE: u32 = 1024;

/// The image files a scene's parts use, each once, in the order first met.
///
/// ```
/// use orbifold_preview::textures::TextureTable;
/// let mut table = TextureTable::default();
/// assert_eq!(table.layer("wood.png"), 0);
/// assert_eq!(table.layer("tiles.jpg"), 1);
/// assert_eq!(table.layer("wood.png"), 0);
/// assert_eq!(table.paths(), ["wood.png", "tiles.jpg"]);
/// ```
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct TextureTable {
    paths: Vec<String>,
}

impl TextureTable {
    /// The layer of the image at `path` (as the scene writes it), adding it when new.
    pub fn layer(&mut self, path: &str) -> u32 {
        let index = match self.paths.iter().position(|p| p == path) {
            Some(i) => i,
            None => {
                self.paths.push(path.to_owned());
                self.paths.len() - 1
            }
        };
        index as u32
    }

    /// The image files, by layer.
    pub fn paths(&self) -> &[String] {
        &self.paths
    }

    /// What each file is now, so that an image replaced under the same name is read again: the
    /// bytes given for it ([`orbifold_scene::files::provide`], as a page is given a dropped
    /// file), or the file's time of modification on disk.
    pub fn versions(&self, base: Option<&Path>) -> Vec<Version> {
        self.paths
            .iter()
            .map(|path| {
                let file: PathBuf = base.map_or_else(|| path.into(), |b| b.join(path));
                match orbifold_scene::files::provided(&file) {
                    Some(bytes) => Version::Given(bytes),
                    None => {
                        Version::Modified(std::fs::metadata(&file).and_then(|m| m.modified()).ok())
                    }
                }
            })
            .collect()
    }

    /// Reads and decodes every image (`base` resolves relative paths, as the renderer resolves
    /// them; the bytes come through [`orbifold_scene::files::read`], so given bytes come before
    /// the disk), resampled to one size. An image that cannot be read leaves its layer empty
    /// and is named in [`Images::unread`]: its parts keep their representative colour.
    pub fn read(&self, base: Option<&Path>) -> Images {
        let decoded: Vec<Result<image::RgbaImage, String>> = self
            .paths
            .iter()
            .map(|path| {
                let file: PathBuf = base.map_or_else(|| path.into(), |b| b.join(path));
                orbifold_scene::files::read_image(&file).map(|image| image.to_rgba8())
            })
            .collect();
        let side = |f: fn(&image::RgbaImage) -> u32| {
            decoded
                .iter()
                .flatten()
                .map(f)
                .max()
                .unwrap_or(1)
                .clamp(1, MAX_SIDE)
        };
        let (width, height) = (
            side(image::RgbaImage::width),
            side(image::RgbaImage::height),
        );
        let mut unread = Vec::new();
        let layers = decoded
            .into_iter()
            .map(|d| match d {
                Ok(img) if (img.width(), img.height()) == (width, height) => Some(img.into_raw()),
                Ok(img) => Some(
                    image::imageops::resize(
                        &img,
                        width,
                        height,
                        image::imageops::FilterType::Triangle,
                    )
                    .into_raw(),
                ),
                Err(why) => {
                    unread.push(why);
                    None
                }
            })
            .collect();
        Images {
            width,
            height,
            layers,
            unread,
        }
    }
}

/// Which version of an image file a layer holds ([`TextureTable::versions`]).
#[derive(Clone, Debug)]
pub enum Version {
    /// Bytes given for the file's name: the same bytes, not equal ones.
    Given(std::sync::Arc<[u8]>),
    /// The file on disk, by its time of modification (`None`: there is no such file).
    Modified(Option<std::time::SystemTime>),
}

impl PartialEq for Version {
    fn eq(&self, other: &Version) -> bool {
        match (self, other) {
            (Version::Given(a), Version::Given(b)) => std::sync::Arc::ptr_eq(a, b),
            (Version::Modified(a), Version::Modified(b)) => a == b,
            _ => false,
        }
    }
}

/// The decoded images of a [`TextureTable`], all of one size.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Images {
    /// The layers' width in texels.
    pub width: u32,
    /// The layers' height in texels.
    pub height: u32,
    /// Each layer's texels (sRGB, RGBA, rows from the top), `None` where the file could not be
    /// read.
    pub layers: Vec<Option<Vec<u8>>>,
    /// Why each unread file could not be read.
    pub unread: Vec<String>,
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Images of different sizes come out at the largest width and height, and an unreadable
    /// file leaves its layer empty with a reason.
    #[test]
    fn images_share_one_size_and_unread_ones_are_named() {
        let dir = std::env::temp_dir().join(format!("orbifold-textures-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        image::RgbImage::from_pixel(4, 2, image::Rgb([255, 0, 0]))
            .save(dir.join("a.png"))
            .unwrap();
        image::RgbImage::from_pixel(2, 8, image::Rgb([0, 0, 255]))
            .save(dir.join("b.png"))
            .unwrap();
        let mut table = TextureTable::default();
        for name in ["a.png", "missing.png", "b.png"] {
            table.layer(name);
        }
        let images = table.read(Some(&dir));
        assert_eq!((images.width, images.height), (4, 8));
        assert_eq!(images.layers.len(), 3);
        assert!(images.layers[1].is_none());
        assert_eq!(images.unread.len(), 1);
        assert!(
            images.unread[0].contains("missing.png"),
            "{:?}",
            images.unread
        );
        let a = images.layers[0].as_ref().unwrap();
        assert_eq!(a.len(), 4 * 8 * 4);
        assert_eq!(&a[..4], &[255, 0, 0, 255]);
        let b = images.layers[2].as_ref().unwrap();
        assert_eq!(&b[b.len() - 4..], &[0, 0, 255, 255]);
        // Bytes given under a name are a new version each time they are given.
        let versions = table.versions(Some(&dir));
        assert_eq!(versions, table.versions(Some(&dir)));
        orbifold_scene::files::provide(dir.join("a.png"), vec![1, 2, 3]);
        let given = table.versions(Some(&dir));
        assert_ne!(given, versions);
        orbifold_scene::files::provide(dir.join("a.png"), vec![1, 2, 3]);
        assert_ne!(table.versions(Some(&dir)), given);
        orbifold_scene::files::forget(&dir.join("a.png"));
        std::fs::remove_dir_all(&dir).ok();
    }
}
