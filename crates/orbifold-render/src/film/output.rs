//! The film written out: OpenEXR (linear, 32-bit float), PNG and JPEG (tone-mapped 8-bit
//! sRGB), written atomically so that a file never holds a partial image.

use std::fs::{self, File, OpenOptions};
use std::io::{Cursor, Write};
use std::path::Path;
use std::sync::atomic::{AtomicU64, Ordering};

use image::ImageEncoder;
use image::codecs::png::PngEncoder;

use super::Film;
use super::tone::tone_map;

impl Film {
    /// The film as an OpenEXR file in memory: one layer with the channels R, G, B as 32-bit
    /// floats of linear radiance (the pixel means), ZIP-compressed scan lines, top line first.
    ///
    /// ```
    /// use orbifold_render::film::Film;
    ///
    /// let mut film = Film::new(2, 2);
    /// film.add(0, 0, [1.5, 0.25, 4.0]);
    /// let bytes = film.to_exr_bytes().unwrap();
    /// assert_eq!(&bytes[..4], &[0x76, 0x2f, 0x31, 0x01]); // the OpenEXR magic number
    /// ```
    pub fn to_exr_bytes(&self) -> Result<Vec<u8>, String> {
        use exr::prelude::{Encoding, Image, SpecificChannels, Vec2, WritableImage};

        let size = (self.width as usize, self.height as usize);
        let channels = SpecificChannels::rgb(|p: Vec2<usize>| {
            let c = self.mean_at(p.y() * size.0 + p.x());
            (c[0] as f32, c[1] as f32, c[2] as f32)
        });
        let image = Image::from_encoded_channels(size, Encoding::SMALL_LOSSLESS, channels);
        let mut out = Cursor::new(Vec::new());
        image
            .write()
            .to_buffered(&mut out)
            .map_err(|e| format!("cannot encode the OpenEXR image: {e}"))?;
        Ok(out.into_inner())
    }

    /// The film as an 8-bit sRGB PNG in memory, each pixel mean tone-mapped with
    /// [`tone_map`] at `exposure` stops.
    ///
    /// ```
    /// use orbifold_render::film::Film;
    ///
    /// let mut film = Film::new(3, 2);
    /// film.add(2, 1, [1.0; 3]);
    /// let bytes = film.to_png_bytes(0.0).unwrap();
    /// assert_eq!(&bytes[..8], b"\x89PNG\r\n\x1a\n");
    /// ```
    pub fn to_png_bytes(&self, exposure: f64) -> Result<Vec<u8>, String> {
        let data: Vec<u8> = (0..self.count.len())
            .flat_map(|i| tone_map(self.mean_at(i), exposure))
            .collect();
        let mut out = Vec::new();
        PngEncoder::new(&mut out)
            .write_image(
                &data,
                self.width,
                self.height,
                image::ExtendedColorType::Rgb8,
            )
            .map_err(|e| format!("cannot encode the PNG image: {e}"))?;
        Ok(out)
    }

    /// The film as a tone-mapped 8-bit sRGB JPEG of the given quality (1 to 100) in memory:
    /// small files for galleries and web pages.
    ///
    /// ```
    /// use orbifold_render::film::Film;
    ///
    /// let mut film = Film::new(3, 2);
    /// film.add(2, 1, [1.0; 3]);
    /// let bytes = film.to_jpeg_bytes(0.0, 90).unwrap();
    /// assert_eq!(&bytes[..2], b"\xff\xd8");
    /// ```
    pub fn to_jpeg_bytes(&self, exposure: f64, quality: u8) -> Result<Vec<u8>, String> {
        let data: Vec<u8> = (0..self.count.len())
            .flat_map(|i| tone_map(self.mean_at(i), exposure))
            .collect();
        let mut out = Vec::new();
        image::codecs::jpeg::JpegEncoder::new_with_quality(&mut out, quality.clamp(1, 100))
            .write_image(
                &data,
                self.width,
                self.height,
                image::ExtendedColorType::Rgb8,
            )
            .map_err(|e| format!("cannot encode the JPEG image: {e}"))?;
        Ok(out)
    }

    /// Writes the film to `path`: OpenEXR ([`Film::to_exr_bytes`]) for the extension `.exr`,
    /// PNG ([`Film::to_png_bytes`] at `exposure` stops) for `.png`, JPEG of quality 90
    /// ([`Film::to_jpeg_bytes`]) for `.jpg` or `.jpeg` (in any letter case).
    /// Any other extension, or none, is an error that names it. The file is written
    /// atomically: the bytes go to a new temporary file in the same directory, which is synced
    /// and then renamed over `path`, so `path` never holds a partial image; the temporary file
    /// is removed if anything fails.
    ///
    /// ```
    /// use orbifold_render::film::Film;
    ///
    /// let tmp = tempfile::Builder::new().prefix("orbifold-film-doc-").tempdir().unwrap();
    /// let dir = tmp.path();
    /// let mut film = Film::new(4, 4);
    /// film.add(1, 1, [0.5, 0.6, 0.7]);
    /// film.write(&dir.join("image.png"), 0.0).unwrap();
    /// film.write(&dir.join("image.exr"), 0.0).unwrap();
    /// let error = film.write(&dir.join("image.tiff"), 0.0).unwrap_err();
    /// assert!(error.contains("tiff"));
    /// ```
    pub fn write(&self, path: &Path, exposure: f64) -> Result<(), String> {
        let extension = path.extension().map(|e| e.to_string_lossy().into_owned());
        let bytes = match extension.as_deref().map(str::to_ascii_lowercase).as_deref() {
            Some("exr") => self.to_exr_bytes()?,
            Some("png") => self.to_png_bytes(exposure)?,
            Some("jpg" | "jpeg") => self.to_jpeg_bytes(exposure, 90)?,
            Some(_) => {
                return Err(format!(
                    "unsupported image extension \".{}\" (use .exr, .png or .jpg)",
                    extension.unwrap_or_default()
                ));
            }
            None => {
                return Err(format!(
                    "{} has no extension (use .exr, .png or .jpg)",
                    path.display()
                ));
            }
        };
        write_atomically(path, &bytes)
    }
}

/// Distinguishes the temporary files of concurrent writes within one process.
static TEMP_COUNTER: AtomicU64 = AtomicU64::new(0);

/// Writes `bytes` to a fresh temporary file beside `path`, syncs it and renames it to `path`.
fn write_atomically(path: &Path, bytes: &[u8]) -> Result<(), String> {
    let name = path
        .file_name()
        .ok_or_else(|| format!("{} is not a file name", path.display()))?;
    let dir = match path.parent() {
        Some(p) if !p.as_os_str().is_empty() => p,
        _ => Path::new("."),
    };
    let temp = dir.join(format!(
        ".{}.{}-{}.tmp",
        name.to_string_lossy(),
        std::process::id(),
        TEMP_COUNTER.fetch_add(1, Ordering::Relaxed)
    ));
    let mut file: File = OpenOptions::new()
        .write(true)
        .create_new(true)
        .open(&temp)
        .map_err(|e| format!("cannot create {}: {e}", temp.display()))?;
    let written = file
        .write_all(bytes)
        .and_then(|()| file.sync_all())
        .map_err(|e| format!("cannot write {}: {e}", temp.display()));
    drop(file);
    let result = written.and_then(|()| {
        fs::rename(&temp, path).map_err(|e| {
            format!(
                "cannot rename {} to {}: {e}",
                temp.display(),
                path.display()
            )
        })
    });
    if result.is_err() {
        let _ = fs::remove_file(&temp);
    }
    result
}
