//! The render pipelines and the passes that use them.
//!
//! One shader (`preview.wgsl`) serves four pipelines, one per [`Pass`]: the opaque surfaces,
//! antialiased with a depth test; the mirrors, alpha-blended over them in the same render pass
//! without writing depth, so that what lies behind a mirror shows through; the surface ids,
//! single-sampled, mirrors seen through; and the room's own vertices as points, for testing
//! the shader's projection against the CPU twin. All four read the same vertex layout (the
//! mesh's vertices, then one [`InstanceRaw`] per copy) and the same bind group (the frame's
//! [`Globals`](super::resources::Globals) and the part table).

use super::Preview;
use super::resources::{DEPTH_FORMAT, ID_FORMAT, InstanceRaw};
use super::settings::{BACKGROUND, COLOR_FORMAT};
use crate::mesh::Vertex;

impl Preview {
    /// Records one pass and sends it to the GPU.
    pub(super) fn submit(&self, pass: Pass) {
        let mut encoder = self
            .gpu
            .device
            .create_command_encoder(&wgpu::CommandEncoderDescriptor {
                label: Some("preview pass"),
            });
        self.encode(&mut encoder, pass);
        self.gpu.queue.submit([encoder.finish()]);
    }

    /// Records a pass: the antialiased picture, the surface ids, or the room's own vertices
    /// as points.
    fn encode(&self, encoder: &mut wgpu::CommandEncoder, pass: Pass) {
        let target = self.target.as_ref().expect("made by draw");
        let view = |t: &wgpu::Texture| t.create_view(&Default::default());
        let (attachment, resolve, depth, clear) = match pass {
            Pass::Opaque | Pass::Mirror => {
                let [r, g, b] = BACKGROUND;
                let clear = wgpu::Color { r, g, b, a: 1.0 };
                let (attachment, resolve) = match &target.color_samples {
                    Some(samples) => (view(samples), Some(view(&target.color))),
                    None => (view(&target.color), None),
                };
                (attachment, resolve, view(&target.depth_samples), clear)
            }
            Pass::Ids | Pass::Points => {
                let clear = wgpu::Color {
                    r: -1.0,
                    ..wgpu::Color::TRANSPARENT
                };
                (view(&target.id), None, view(&target.id_depth), clear)
            }
        };
        let mut render = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("preview"),
            color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                view: &attachment,
                depth_slice: None,
                resolve_target: resolve.as_ref(),
                ops: wgpu::Operations {
                    load: wgpu::LoadOp::Clear(clear),
                    // Samples are needed only until they are resolved.
                    store: if resolve.is_some() {
                        wgpu::StoreOp::Discard
                    } else {
                        wgpu::StoreOp::Store
                    },
                },
            })],
            depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                view: &depth,
                depth_ops: Some(wgpu::Operations {
                    load: wgpu::LoadOp::Clear(1.0),
                    store: wgpu::StoreOp::Discard,
                }),
                stencil_ops: None,
            }),
            timestamp_writes: None,
            occlusion_query_set: None,
            multiview_mask: None,
        });
        let Some(instances) = &self.instances else {
            return;
        };
        let count = self.stats.instances as u32;
        if count == 0 {
            return;
        }
        render.set_bind_group(0, &self.bind_group, &[]);
        render.set_vertex_buffer(1, instances.slice(..));
        if pass == Pass::Points {
            if let Some(room) = &self.room {
                render.set_pipeline(&self.points);
                render.set_vertex_buffer(0, room.vertices.slice(..));
                let vertices = (room.vertices.size() / std::mem::size_of::<Vertex>() as u64) as u32;
                render.draw(0..vertices, 0..1);
            }
            return;
        }
        let meshes = [&self.room, &self.objects];
        render.set_pipeline(if pass == Pass::Ids {
            &self.ids
        } else {
            &self.opaque
        });
        if let Some(room) = &self.room {
            render.set_vertex_buffer(0, room.vertices.slice(..));
            render.set_index_buffer(room.indices.slice(..), wgpu::IndexFormat::Uint32);
            render.draw_indexed(room.opaque.clone(), 0, 0..count);
        }
        if let (Some(objects), Some(state)) = (&self.objects, &self.scene) {
            render.set_vertex_buffer(0, objects.vertices.slice(..));
            render.set_index_buffer(objects.indices.slice(..), wgpu::IndexFormat::Uint32);
            // Each level of detail with the copies that use it.
            for (triangles, copies) in state.object_levels.iter().zip(&self.instance_levels) {
                if !copies.is_empty() {
                    render.draw_indexed(triangles.clone(), 0, copies.clone());
                }
            }
        }
        if pass == Pass::Ids {
            // Mirrors are seen through: the id is what lies behind them.
            return;
        }
        render.set_pipeline(&self.mirror);
        for mesh in meshes.iter().copied().flatten() {
            if mesh.mirrors.is_empty() {
                continue;
            }
            render.set_vertex_buffer(0, mesh.vertices.slice(..));
            render.set_index_buffer(mesh.indices.slice(..), wgpu::IndexFormat::Uint32);
            render.draw_indexed(mesh.mirrors.clone(), 0, 0..count);
        }
    }
}

/// The ways the preview draws: one pipeline each.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Pass {
    /// Surfaces, antialiased, with depth.
    Opaque,
    /// Mirrors over them: blended, no depth write (in the same pass as `Opaque`).
    Mirror,
    /// The surface under each pixel, mirrors seen through.
    Ids,
    /// The room's vertices as points writing their index, over everything.
    Points,
}

/// The render pipeline of one pass; `color_samples` is the multisample count of the colour
/// picture (the id and point passes are single-sampled).
pub(super) fn pipeline(
    device: &wgpu::Device,
    layout: &wgpu::PipelineLayout,
    module: &wgpu::ShaderModule,
    pass: Pass,
    color_samples: u32,
) -> wgpu::RenderPipeline {
    const VERTEX: [wgpu::VertexAttribute; 4] =
        wgpu::vertex_attr_array![0 => Float32x3, 1 => Float32, 2 => Float32x3, 3 => Uint32];
    const INSTANCE: [wgpu::VertexAttribute; 4] = wgpu::vertex_attr_array![
        4 => Float32x4, 5 => Float32x4, 6 => Float32x4, 7 => Float32x4
    ];
    let buffers = [
        Some(wgpu::VertexBufferLayout {
            array_stride: std::mem::size_of::<Vertex>() as u64,
            step_mode: wgpu::VertexStepMode::Vertex,
            attributes: &VERTEX,
        }),
        Some(wgpu::VertexBufferLayout {
            array_stride: std::mem::size_of::<InstanceRaw>() as u64,
            step_mode: wgpu::VertexStepMode::Instance,
            attributes: &INSTANCE,
        }),
    ];
    let (format, blend, samples, entry) = match pass {
        Pass::Opaque => (COLOR_FORMAT, None, color_samples, "fs_opaque"),
        Pass::Mirror => (
            COLOR_FORMAT,
            Some(wgpu::BlendState::ALPHA_BLENDING),
            color_samples,
            "fs_mirror",
        ),
        Pass::Ids => (ID_FORMAT, None, 1, "fs_id"),
        Pass::Points => (ID_FORMAT, None, 1, "fs_point"),
    };
    let targets = [Some(wgpu::ColorTargetState {
        format,
        blend,
        write_mask: wgpu::ColorWrites::ALL,
    })];
    device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
        label: Some(entry),
        layout: Some(layout),
        vertex: wgpu::VertexState {
            module,
            entry_point: Some("vs_main"),
            compilation_options: Default::default(),
            buffers: &buffers,
        },
        primitive: wgpu::PrimitiveState {
            topology: if pass == Pass::Points {
                wgpu::PrimitiveTopology::PointList
            } else {
                wgpu::PrimitiveTopology::TriangleList
            },
            cull_mode: None,
            ..Default::default()
        },
        depth_stencil: Some(wgpu::DepthStencilState {
            format: DEPTH_FORMAT,
            depth_write_enabled: Some(matches!(pass, Pass::Opaque | Pass::Ids)),
            depth_compare: Some(if pass == Pass::Points {
                wgpu::CompareFunction::Always
            } else {
                wgpu::CompareFunction::Less
            }),
            stencil: Default::default(),
            bias: Default::default(),
        }),
        multisample: wgpu::MultisampleState {
            count: samples,
            ..Default::default()
        },
        fragment: Some(wgpu::FragmentState {
            module,
            entry_point: Some(entry),
            compilation_options: Default::default(),
            targets: &targets,
        }),
        multiview_mask: None,
        cache: None,
    })
}
