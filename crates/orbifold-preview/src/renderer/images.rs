//! The scene's image textures on the GPU ([`crate::textures`]): one 2D array texture with mip
//! levels, a layer per image file, bound beside the part table with a sampler that repeats (the
//! nearest texel close up, mip levels blended far away). A part whose image could not be read
//! keeps its representative colour.

use std::path::{Path, PathBuf};

use super::Preview;
use crate::mesh::{IMAGE, PLAIN, PartStyle};
use crate::textures::{Images, TextureTable, Version};

/// The images on the GPU: which files, read against which folder, and which of their layers
/// hold an image.
#[derive(Default)]
pub(super) struct UploadedImages {
    pub(super) table: TextureTable,
    pub(super) base: Option<PathBuf>,
    pub(super) versions: Vec<Version>,
    pub(super) readable: Vec<bool>,
    pub(super) unread: Vec<String>,
}

impl Preview {
    /// Puts the images of `table` (paths relative to `base`) on the GPU, unless the same
    /// versions of them are there already, and turns the parts whose image could not be read to
    /// their plain colour.
    pub(super) fn upload_images(
        &mut self,
        table: &TextureTable,
        base: Option<&Path>,
        styles: &mut [PartStyle],
    ) {
        let versions = table.versions(base);
        if self.images.table != *table
            || self.images.base.as_deref() != base
            || self.images.versions != versions
        {
            let mut images = table.read(base);
            let most = self.gpu.device.limits().max_texture_array_layers as usize;
            for (layer, texels) in images.layers.iter_mut().enumerate().skip(most) {
                if texels.take().is_some() {
                    images.unread.push(format!(
                        "texture {} is one more than the GPU's {most} layers",
                        table.paths()[layer]
                    ));
                }
            }
            let view = array_view(&self.gpu.device, &self.gpu.queue, &images);
            self.bind_group = bind_group(
                &self.gpu.device,
                &self.bindings,
                [&self.globals, &self.parts],
                &view,
                &self.sampler,
            );
            self.images = UploadedImages {
                table: table.clone(),
                base: base.map(Path::to_path_buf),
                versions,
                readable: images.layers.iter().map(Option::is_some).collect(),
                unread: images.unread,
            };
        }
        for style in styles.iter_mut().filter(|s| s.pattern == IMAGE) {
            if !self
                .images
                .readable
                .get(style.layer as usize)
                .copied()
                .unwrap_or(false)
            {
                style.pattern = PLAIN;
            }
        }
    }
}

/// The bind group of the globals and the part table (`buffers`), `images` and the sampler.
pub(super) fn bind_group(
    device: &wgpu::Device,
    layout: &wgpu::BindGroupLayout,
    buffers: [&wgpu::Buffer; 2],
    images: &wgpu::TextureView,
    sampler: &wgpu::Sampler,
) -> wgpu::BindGroup {
    device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: Some("preview bindings"),
        layout,
        entries: &[
            wgpu::BindGroupEntry {
                binding: 0,
                resource: buffers[0].as_entire_binding(),
            },
            wgpu::BindGroupEntry {
                binding: 1,
                resource: buffers[1].as_entire_binding(),
            },
            wgpu::BindGroupEntry {
                binding: 2,
                resource: wgpu::BindingResource::TextureView(images),
            },
            wgpu::BindGroupEntry {
                binding: 3,
                resource: wgpu::BindingResource::Sampler(sampler),
            },
        ],
    })
}

/// The bind group layout entries of the images and their sampler (bindings 2 and 3).
pub(super) fn layout_entries() -> [wgpu::BindGroupLayoutEntry; 2] {
    [
        wgpu::BindGroupLayoutEntry {
            binding: 2,
            visibility: wgpu::ShaderStages::FRAGMENT,
            ty: wgpu::BindingType::Texture {
                sample_type: wgpu::TextureSampleType::Float { filterable: true },
                view_dimension: wgpu::TextureViewDimension::D2Array,
                multisampled: false,
            },
            count: None,
        },
        wgpu::BindGroupLayoutEntry {
            binding: 3,
            visibility: wgpu::ShaderStages::FRAGMENT,
            ty: wgpu::BindingType::Sampler(wgpu::SamplerBindingType::Filtering),
            count: None,
        },
    ]
}

/// Repeating, as images tile. Magnified, the nearest texel, as the renderer looks a point up
/// when a pixel's footprint is smaller than a texel; minified, the mip levels' texels blended,
/// as the renderer averages an image over a larger footprint (far copies do not alias).
pub(super) fn sampler(device: &wgpu::Device) -> wgpu::Sampler {
    device.create_sampler(&wgpu::SamplerDescriptor {
        label: Some("preview images"),
        address_mode_u: wgpu::AddressMode::Repeat,
        address_mode_v: wgpu::AddressMode::Repeat,
        mag_filter: wgpu::FilterMode::Nearest,
        min_filter: wgpu::FilterMode::Linear,
        mipmap_filter: wgpu::MipmapFilterMode::Linear,
        ..Default::default()
    })
}

/// The next mip level of `texels` (RGBA, sRGB, `width`×`height`), half the size rounded down:
/// each texel the mean of the 2×2 below it, in linear light (a side of one texel halves the
/// other side only).
fn half_size(texels: &[u8], width: u32, height: u32) -> (Vec<u8>, u32, u32) {
    let (w, h) = ((width / 2).max(1), (height / 2).max(1));
    let linear = orbifold_scene::color::linear_from_srgb8;
    let mut out = Vec::with_capacity((4 * w * h) as usize);
    for y in 0..h {
        for x in 0..w {
            let mut sum = [0.0f64; 4];
            let mut count = 0.0;
            for (dx, dy) in [(0, 0), (1, 0), (0, 1), (1, 1)] {
                let (sx, sy) = (2 * x + dx, 2 * y + dy);
                if sx < width && sy < height {
                    let k = (4 * (sy * width + sx)) as usize;
                    for c in 0..3 {
                        sum[c] += linear(texels[k + c]);
                    }
                    sum[3] += f64::from(texels[k + 3]);
                    count += 1.0;
                }
            }
            let [r, g, b, a] = sum.map(|s| s / count);
            out.extend([r, g, b].map(orbifold_scene::color::srgb8_from_linear));
            out.push(a.round() as u8);
        }
    }
    (out, w, h)
}

/// The images as layers of one sRGB texture (at least one layer: an array cannot be empty, and
/// an unread image's layer stays black, unused).
pub(super) fn array_view(
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    images: &Images,
) -> wgpu::TextureView {
    let (width, height) = (images.width.max(1), images.height.max(1));
    let layers = images.layers.len().max(1) as u32;
    let levels = 32 - width.max(height).leading_zeros();
    let size = wgpu::Extent3d {
        width,
        height,
        depth_or_array_layers: layers,
    };
    let texture = device.create_texture(&wgpu::TextureDescriptor {
        label: Some("preview images"),
        size,
        mip_level_count: levels,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format: wgpu::TextureFormat::Rgba8UnormSrgb,
        usage: wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::COPY_DST,
        view_formats: &[],
    });
    for (layer, texels) in images.layers.iter().enumerate() {
        let Some(texels) = texels else { continue };
        let (mut level, mut w, mut h) = (texels.clone(), width, height);
        for mip_level in 0..levels {
            if mip_level > 0 {
                (level, w, h) = half_size(&level, w, h);
            }
            queue.write_texture(
                wgpu::TexelCopyTextureInfo {
                    texture: &texture,
                    mip_level,
                    origin: wgpu::Origin3d {
                        x: 0,
                        y: 0,
                        z: layer as u32,
                    },
                    aspect: wgpu::TextureAspect::All,
                },
                &level,
                wgpu::TexelCopyBufferLayout {
                    offset: 0,
                    bytes_per_row: Some(4 * w),
                    rows_per_image: Some(h),
                },
                wgpu::Extent3d {
                    width: w,
                    height: h,
                    depth_or_array_layers: 1,
                },
            );
        }
    }
    texture.create_view(&wgpu::TextureViewDescriptor {
        dimension: Some(wgpu::TextureViewDimension::D2Array),
        ..Default::default()
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A mip level's texel is the mean in linear light of the four below it: black and white
    /// make sRGB 188, not 128; a row of one texel halves along its length only.
    #[test]
    fn mip_levels_average_in_linear_light() {
        let (w, b) = ([255, 255, 255, 255], [0, 0, 0, 255]);
        let texels: Vec<u8> = [w, b, b, w].concat();
        let (level, width, height) = half_size(&texels, 2, 2);
        assert_eq!((width, height), (1, 1));
        assert_eq!(level, vec![188, 188, 188, 255]);
        let row: Vec<u8> = [w, b, w, w].concat();
        let (level, width, height) = half_size(&row, 4, 1);
        assert_eq!((width, height), (2, 1));
        assert_eq!(level, [[188, 188, 188, 255], w].concat());
    }
}
