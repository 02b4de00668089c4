//! The data the preview keeps on the GPU: the uniform block of per-frame values, the
//! per-instance record of one copy of the room, the vertex and index buffers of a mesh, and the
//! offscreen render targets.
//!
//! [`Globals`] and [`InstanceRaw`] are `#[repr(C)]` twins of the `Globals` and `InstanceIn`
//! structs of `preview.wgsl`: their layouts must match the shader's byte for byte, which the
//! tests below hold them to.

use bytemuck::{Pod, Zeroable};
use wgpu::util::DeviceExt;

use super::settings::COLOR_FORMAT;
use crate::mesh::MeshData;

/// The format of the surface-id image: the part index under each pixel, −1 for none.
pub(super) const ID_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::R32Sint;
/// The format of both depth buffers.
pub(super) const DEPTH_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Depth32Float;

/// The uniform block of one frame (the shader's `Globals`): the camera and the projection.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable)]
pub(super) struct Globals {
    /// The camera's right axis in the eye's frame; w: the curvature κ.
    pub(super) right: [f32; 4],
    /// The camera's up axis; w: the eye's height.
    pub(super) up: [f32; 4],
    /// The camera's forward axis; w: 1 for the straight projection, 0 for the curved one.
    pub(super) forward: [f32; 4],
    /// The perspective projection: 1/(tan(fov/2)·aspect), 1/tan(fov/2), near, far.
    pub(super) lens: [f32; 4],
    /// xy: the eye's flat position (2x, 2y) for the straight projection; z: the ambient term;
    /// w: unused.
    pub(super) eye: [f32; 4],
}

/// One instance: a copy of the room (the shader's `InstanceIn`), in the instance vertex buffer.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable)]
pub(super) struct InstanceRaw {
    /// The copy's group element composed with the view, as three columns of a 3×3 matrix; the
    /// w of the first column carries the copy's word length (reflections deep).
    pub(super) columns: [[f32; 4]; 3],
    /// rgb: the copy's brightness; a: which image of each point (S²×R: 0 the short way, 1 the
    /// long way, ...).
    pub(super) tint: [f32; 4],
}

/// A mesh on the GPU: its vertex and index buffers, the index range of the opaque triangles,
/// and that of the mirrors (drawn blended after everything opaque).
pub(super) struct GpuMesh {
    pub(super) vertices: wgpu::Buffer,
    pub(super) indices: wgpu::Buffer,
    pub(super) opaque: std::ops::Range<u32>,
    pub(super) mirrors: std::ops::Range<u32>,
}

impl GpuMesh {
    /// The mesh uploaded; `None` for a mesh without triangles, which has nothing to draw.
    pub(super) fn new(device: &wgpu::Device, data: &MeshData, label: &str) -> Option<GpuMesh> {
        if data.indices.is_empty() {
            return None;
        }
        Some(GpuMesh {
            vertices: device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some(label),
                contents: bytemuck::cast_slice(&data.vertices),
                usage: wgpu::BufferUsages::VERTEX,
            }),
            indices: device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some(label),
                contents: bytemuck::cast_slice(&data.indices),
                usage: wgpu::BufferUsages::INDEX,
            }),
            opaque: data.opaque.clone(),
            mirrors: data.mirrors.clone(),
        })
    }
}

/// Offscreen render targets of one size: the multisampled colour and depth of the picture, its
/// resolved colour, and the single-sampled surface ids with their own depth.
pub(super) struct RenderTargets {
    pub(super) width: u32,
    pub(super) height: u32,
    /// With multisampling: the samples, resolved into `color`.
    pub(super) color_samples: Option<wgpu::Texture>,
    pub(super) depth_samples: wgpu::Texture,
    pub(super) color: wgpu::Texture,
    pub(super) id: wgpu::Texture,
    pub(super) id_depth: wgpu::Texture,
}

impl RenderTargets {
    pub(super) fn new(
        device: &wgpu::Device,
        width: u32,
        height: u32,
        samples: u32,
    ) -> RenderTargets {
        let texture = |format, samples, label| {
            let readable = if samples == 1 {
                wgpu::TextureUsages::COPY_SRC | wgpu::TextureUsages::TEXTURE_BINDING
            } else {
                wgpu::TextureUsages::empty()
            };
            device.create_texture(&wgpu::TextureDescriptor {
                label: Some(label),
                size: wgpu::Extent3d {
                    width,
                    height,
                    depth_or_array_layers: 1,
                },
                mip_level_count: 1,
                sample_count: samples,
                dimension: wgpu::TextureDimension::D2,
                format,
                usage: wgpu::TextureUsages::RENDER_ATTACHMENT | readable,
                view_formats: &[],
            })
        };
        RenderTargets {
            width,
            height,
            color_samples: (samples > 1)
                .then(|| texture(COLOR_FORMAT, samples, "preview colour samples")),
            depth_samples: texture(DEPTH_FORMAT, samples, "preview depth samples"),
            color: texture(COLOR_FORMAT, 1, "preview colour"),
            id: texture(ID_FORMAT, 1, "preview surface ids"),
            id_depth: texture(DEPTH_FORMAT, 1, "preview id depth"),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::{PartStyle, Vertex};

    #[test]
    fn instance_and_style_layouts_match_the_shader() {
        assert_eq!(std::mem::size_of::<InstanceRaw>(), 64);
        assert_eq!(std::mem::size_of::<PartStyle>(), 112);
        assert_eq!(std::mem::size_of::<Globals>(), 80);
        assert_eq!(std::mem::size_of::<Vertex>(), 32);
    }
}
