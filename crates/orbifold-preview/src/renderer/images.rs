//! The scene's image textures on the GPU ([`crate::textures`]): one 2D array texture, a layer
//! per image file, bound beside the part table with a sampler of nearest texels that repeats.
//! A part whose image could not be read keeps its representative colour.

use std::path::{Path, PathBuf};

use super::Preview;
use crate::mesh::{IMAGE, PLAIN, PartStyle};
use crate::textures::{Images, TextureTable};

/// The images on the GPU: which files, read against which folder, and which of their layers
/// hold an image.
#[derive(Default)]
pub(super) struct UploadedImages {
    pub(super) table: TextureTable,
    pub(super) base: Option<PathBuf>,
    pub(super) readable: Vec<bool>,
    pub(super) unread: Vec<String>,
}

impl Preview {
    /// Puts the images of `table` (paths relative to `base`) on the GPU, unless they are there
    /// already, and turns the parts whose image could not be read to their plain colour.
    pub(super) fn upload_images(
        &mut self,
        table: &TextureTable,
        base: Option<&Path>,
        styles: &mut [PartStyle],
    ) {
        if self.images.table != *table || self.images.base.as_deref() != base {
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

/// Nearest texels, as the renderer looks a single point up; repeating, as images tile.
pub(super) fn sampler(device: &wgpu::Device) -> wgpu::Sampler {
    device.create_sampler(&wgpu::SamplerDescriptor {
        label: Some("preview images"),
        address_mode_u: wgpu::AddressMode::Repeat,
        address_mode_v: wgpu::AddressMode::Repeat,
        mag_filter: wgpu::FilterMode::Nearest,
        min_filter: wgpu::FilterMode::Nearest,
        ..Default::default()
    })
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
    let size = wgpu::Extent3d {
        width,
        height,
        depth_or_array_layers: layers,
    };
    let texture = device.create_texture(&wgpu::TextureDescriptor {
        label: Some("preview images"),
        size,
        mip_level_count: 1,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format: wgpu::TextureFormat::Rgba8UnormSrgb,
        usage: wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::COPY_DST,
        view_formats: &[],
    });
    for (layer, texels) in images.layers.iter().enumerate() {
        let Some(texels) = texels else { continue };
        queue.write_texture(
            wgpu::TexelCopyTextureInfo {
                texture: &texture,
                mip_level: 0,
                origin: wgpu::Origin3d {
                    x: 0,
                    y: 0,
                    z: layer as u32,
                },
                aspect: wgpu::TextureAspect::All,
            },
            texels,
            wgpu::TexelCopyBufferLayout {
                offset: 0,
                bytes_per_row: Some(4 * width),
                rows_per_image: Some(height),
            },
            wgpu::Extent3d {
                width,
                height,
                depth_or_array_layers: 1,
            },
        );
    }
    texture.create_view(&wgpu::TextureViewDescriptor {
        dimension: Some(wgpu::TextureViewDimension::D2Array),
        ..Default::default()
    })
}
