//! Reading frames back to the CPU: the colours, the surface ids and the projected vertices.
//!
//! wgpu copies a texture to a buffer only in rows padded to
//! [`wgpu::COPY_BYTES_PER_ROW_ALIGNMENT`] bytes; [`read_texture`] copies, waits for the GPU,
//! and packs the rows again. Each read waits until the GPU has drawn the frame;
//! [`Preview::draw`] alone leaves the picture on the GPU, for an application to show.

use super::Preview;
use super::pipeline::Pass;
use crate::PreviewError;
use crate::frame::Frame;
use crate::gpu::Gpu;

impl Preview {
    /// Where the vertices of the room itself (floor, ceiling, walls and mirrors, not the
    /// objects or the copies) land: the vertex index (into the room's vertex list, as
    /// [`mesh::room`](crate::mesh::room) makes it) and pixel of each vertex drawn, one vertex per pixel (the last
    /// drawn where several share one). The shader's projection, read back.
    pub fn vertex_pixels(
        &mut self,
        width: u32,
        height: u32,
    ) -> Result<Vec<(u32, u32, u32)>, PreviewError> {
        self.draw(width, height)?;
        self.submit(Pass::Points);
        let target = self.target.as_ref().expect("drawn above");
        let ids = read_texture(&self.gpu, &target.id, width, height)?;
        let ids: &[i32] = bytemuck::cast_slice(&ids);
        Ok(ids
            .iter()
            .enumerate()
            .filter(|&(_, &id)| id >= 0)
            .map(|(k, &id)| (id as u32, k as u32 % width, k as u32 / width))
            .collect())
    }

    /// Draws a frame and reads back its colours only (RGBA, 8 bits a channel, rows top to
    /// bottom): what a window showing the preview needs each frame. It skips the surface-id
    /// pass of [`Preview::render`], which draws every triangle a second time.
    ///
    /// ```no_run
    /// # use orbifold_preview::{Gpu, Preview};
    /// let mut preview = Preview::new(Gpu::headless()?);
    /// preview.load(&orbifold_scene::Scene::default(), None)?;
    /// let rgba = preview.render_colors(320, 240)?;
    /// assert_eq!(rgba.len(), 320 * 240 * 4);
    /// # Ok::<(), orbifold_preview::PreviewError>(())
    /// ```
    pub fn render_colors(&mut self, width: u32, height: u32) -> Result<Vec<u8>, PreviewError> {
        self.draw(width, height)?;
        let target = self.target.as_ref().expect("drawn above");
        read_texture(&self.gpu, &target.color, width, height)
    }

    /// Draws a frame and reads it back: colours and surface ids.
    pub fn render(&mut self, width: u32, height: u32) -> Result<Frame, PreviewError> {
        self.draw(width, height)?;
        self.submit(Pass::Ids);
        let target = self.target.as_ref().expect("drawn above");
        let color = read_texture(&self.gpu, &target.color, width, height)?;
        let ids = read_texture(&self.gpu, &target.id, width, height)?;
        Ok(Frame {
            width,
            height,
            rgba: color,
            ids: bytemuck::cast_slice::<u8, i32>(&ids).to_vec(),
        })
    }
}

/// Copies a texture to the CPU, rows packed.
fn read_texture(
    gpu: &Gpu,
    texture: &wgpu::Texture,
    width: u32,
    height: u32,
) -> Result<Vec<u8>, PreviewError> {
    let bytes_per_pixel = 4u32;
    let row = width * bytes_per_pixel;
    let padded =
        row.div_ceil(wgpu::COPY_BYTES_PER_ROW_ALIGNMENT) * wgpu::COPY_BYTES_PER_ROW_ALIGNMENT;
    let buffer = gpu.device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("preview readback"),
        size: u64::from(padded) * u64::from(height),
        usage: wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::MAP_READ,
        mapped_at_creation: false,
    });
    let mut encoder = gpu
        .device
        .create_command_encoder(&wgpu::CommandEncoderDescriptor {
            label: Some("preview readback"),
        });
    encoder.copy_texture_to_buffer(
        texture.as_image_copy(),
        wgpu::TexelCopyBufferInfo {
            buffer: &buffer,
            layout: wgpu::TexelCopyBufferLayout {
                offset: 0,
                bytes_per_row: Some(padded),
                rows_per_image: Some(height),
            },
        },
        wgpu::Extent3d {
            width,
            height,
            depth_or_array_layers: 1,
        },
    );
    gpu.queue.submit([encoder.finish()]);
    let slice = buffer.slice(..);
    let (sender, receiver) = std::sync::mpsc::channel();
    slice.map_async(wgpu::MapMode::Read, move |r| {
        let _ = sender.send(r);
    });
    gpu.device
        .poll(wgpu::PollType::wait_indefinitely())
        .map_err(|e| PreviewError::Gpu(e.to_string()))?;
    receiver
        .recv()
        .map_err(|e| PreviewError::Gpu(e.to_string()))?
        .map_err(|e| PreviewError::Gpu(e.to_string()))?;
    let data = slice
        .get_mapped_range()
        .map_err(|e| PreviewError::Gpu(e.to_string()))?;
    let mut out = Vec::with_capacity((row * height) as usize);
    for r in 0..height as usize {
        let start = r * padded as usize;
        out.extend_from_slice(&data[start..start + row as usize]);
    }
    Ok(out)
}
