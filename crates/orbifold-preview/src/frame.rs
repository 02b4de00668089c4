//! A frame read back from the GPU: colours and the surface under each pixel.

use std::path::Path;

use crate::PreviewError;

/// One preview image.
#[derive(Clone, Debug, PartialEq)]
pub struct Frame {
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// sRGB colours, four bytes a pixel, rows from the top.
    pub rgba: Vec<u8>,
    /// The surface each pixel shows, coded as the tracer's surface-id AOV (0 floor, 1 ceiling,
    /// 2 + i wall i, 1000 + i object i; −1 nothing). Mirrors are seen through.
    pub ids: Vec<i32>,
}

impl Frame {
    /// The surface code at pixel (x, y).
    pub fn id(&self, x: u32, y: u32) -> i32 {
        self.ids[(y * self.width + x) as usize]
    }

    /// The colours as an image.
    pub fn to_image(&self) -> image::RgbaImage {
        image::RgbaImage::from_raw(self.width, self.height, self.rgba.clone())
            .expect("a frame holds width × height pixels")
    }

    /// Writes the colours as a PNG (or JPEG, by the extension) through a temporary file in the
    /// same folder, renamed into place: never a half-written picture.
    pub fn save_png(&self, path: &Path) -> Result<(), PreviewError> {
        let format = image::ImageFormat::from_path(path)
            .ok()
            .filter(|f| matches!(f, image::ImageFormat::Png | image::ImageFormat::Jpeg))
            .ok_or_else(|| {
                PreviewError::Output(format!(
                    "{}: the preview writes .png or .jpg pictures",
                    path.display()
                ))
            })?;
        let image = image::DynamicImage::ImageRgba8(self.to_image());
        let image = if format == image::ImageFormat::Jpeg {
            image::DynamicImage::ImageRgb8(image.to_rgb8())
        } else {
            image
        };
        let name = path
            .file_name()
            .map_or_else(|| "preview".into(), |n| n.to_string_lossy().into_owned());
        let temporary = path.with_file_name(format!(".{name}.{}.tmp", std::process::id()));
        let written = image
            .save_with_format(&temporary, format)
            .map_err(|e| e.to_string())
            .and_then(|()| std::fs::rename(&temporary, path).map_err(|e| e.to_string()));
        written.map_err(|e| {
            let _ = std::fs::remove_file(&temporary);
            PreviewError::Output(format!("cannot write {}: {e}", path.display()))
        })
    }
}
