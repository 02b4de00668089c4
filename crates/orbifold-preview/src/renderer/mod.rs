//! The preview renderer: a scene in, a frame out, with cheap updates (ARCHITECTURE.md §9).
//!
//! The room and the objects live in two vertex buffers (objects in their own frames); every copy
//! of the room under the group is one GPU instance that carries its group element (already
//! composed with the view on the CPU, in f64) and its brightness. Moving the camera rewrites the
//! instance buffer; moving an object rewrites one entry of the part table; a new layout rebuilds
//! the room's buffer and the copies; a new depth only the copies.
//!
//! This module holds [`Preview`] itself, its construction, its settings and camera, and
//! [`Preview::draw`]. The rest of its methods live with what they do:
//!
//! - `settings`: [`Settings`], [`Stats`] and the constants of the preview's frames.
//! - `resources`: what lives on the GPU: the uniform block, the instance record, meshes and
//!   render targets.
//! - `images`: the scene's image textures, one layer each of an array texture.
//! - `scene`: loading a scene and the cheap updates of room and objects.
//! - `instances`: which copies a frame draws (images, frustum culling, levels of detail).
//! - `pipeline`: the render pipelines and the recording of each pass.
//! - `readback`: reading colours, surface ids and projected vertices back to the CPU.

mod images;
mod instances;
mod pipeline;
mod readback;
mod resources;
mod scene;
mod settings;

pub use settings::{
    BACKGROUND, COLOR_FORMAT, DEFAULT_TURNS, GPU_SAMPLES, MAX_PARTS, Settings, Stats,
};

use orbifold_scene::{Camera as CameraSettings, Scene};

use crate::PreviewError;
use crate::copies::Copy;
use crate::gpu::Gpu;
use crate::mesh::PartStyle;
use crate::projection::View;
use pipeline::{Pass, pipeline};
use resources::{Globals, GpuMesh, RenderTargets};
use scene::SceneState;

/// The real-time preview of a mirror room.
///
/// ```no_run
/// use orbifold_preview::{Gpu, Preview};
/// use orbifold_scene::Scene;
/// let mut preview = Preview::new(Gpu::headless()?);
/// let scene = Scene::default();
/// preview.load(&scene, None)?;
/// let frame = preview.render(640, 480)?;
/// frame.save_png(std::path::Path::new("preview.png"))?;
/// # Ok::<(), orbifold_preview::PreviewError>(())
/// ```
pub struct Preview {
    gpu: Gpu,
    /// The pipelines of the four passes (see [`Pass`]).
    opaque: wgpu::RenderPipeline,
    mirror: wgpu::RenderPipeline,
    ids: wgpu::RenderPipeline,
    points: wgpu::RenderPipeline,
    /// Samples a pixel of the colour picture.
    samples: u32,
    globals: wgpu::Buffer,
    parts: wgpu::Buffer,
    /// The layout of `bind_group`: globals, part table, images, sampler.
    bindings: wgpu::BindGroupLayout,
    sampler: wgpu::Sampler,
    images: images::UploadedImages,
    bind_group: wgpu::BindGroup,
    instances: Option<wgpu::Buffer>,
    room: Option<GpuMesh>,
    objects: Option<GpuMesh>,
    target: Option<RenderTargets>,
    scene: Option<SceneState>,
    camera: CameraSettings,
    settings: Settings,
    stats: Stats,
    /// Whether the globals and the instance buffer must be rewritten (by `upload_view`) before
    /// the next frame: the camera, the settings, the copies or the image size changed.
    view_stale: bool,
    /// The instances of each level of detail (the instance buffer is sorted by level).
    instance_levels: Vec<std::ops::Range<u32>>,
}

impl Preview {
    /// A preview that draws on `gpu`. Load a scene before rendering.
    pub fn new(gpu: Gpu) -> Preview {
        let device = &gpu.device;
        let source = include_str!("../preview.wgsl").replace("MAX_PARTS", &MAX_PARTS.to_string());
        let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some("preview shader"),
            source: wgpu::ShaderSource::Wgsl(source.into()),
        });
        let uniform = |binding| wgpu::BindGroupLayoutEntry {
            binding,
            visibility: wgpu::ShaderStages::VERTEX_FRAGMENT,
            ty: wgpu::BindingType::Buffer {
                ty: wgpu::BufferBindingType::Uniform,
                has_dynamic_offset: false,
                min_binding_size: None,
            },
            count: None,
        };
        let [image_entry, sampler_entry] = images::layout_entries();
        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("preview bindings"),
            entries: &[uniform(0), uniform(1), image_entry, sampler_entry],
        });
        let globals = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("preview globals"),
            size: std::mem::size_of::<Globals>() as u64,
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let parts = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("preview parts"),
            size: (MAX_PARTS * std::mem::size_of::<PartStyle>()) as u64,
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let sampler = images::sampler(device);
        let no_images = images::array_view(device, &gpu.queue, &Default::default());
        let pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("preview"),
            bind_group_layouts: &[Some(&layout)],
            immediate_size: 0,
        });
        let samples = if gpu.info.device_type == wgpu::DeviceType::Cpu {
            1
        } else {
            GPU_SAMPLES
        };
        let make = |pass| pipeline(device, &pipeline_layout, &module, pass, samples);
        let (opaque, mirror) = (make(Pass::Opaque), make(Pass::Mirror));
        let (ids, points) = (make(Pass::Ids), make(Pass::Points));
        let bind_group =
            images::bind_group(device, &layout, [&globals, &parts], &no_images, &sampler);
        Preview {
            gpu,
            opaque,
            mirror,
            ids,
            points,
            samples,
            globals,
            parts,
            bindings: layout,
            sampler,
            images: Default::default(),
            bind_group,
            instances: None,
            room: None,
            objects: None,
            target: None,
            scene: None,
            camera: CameraSettings::default(),
            settings: Settings::of_scene(&Scene::default()),
            stats: Stats::default(),
            view_stale: true,
            instance_levels: Vec::new(),
        }
    }

    /// Samples a pixel of the colour picture: [`GPU_SAMPLES`] on a GPU, 1 on a software
    /// adapter.
    pub fn samples(&self) -> u32 {
        self.samples
    }

    /// The GPU it draws on.
    pub fn gpu(&self) -> &Gpu {
        &self.gpu
    }

    /// Sets the depth, the attenuation, the projection and culling.
    pub fn set_settings(&mut self, settings: Settings) -> Result<(), PreviewError> {
        let old = std::mem::replace(&mut self.settings, settings);
        if old.depth != settings.depth || old.attenuation != settings.attenuation {
            self.rebuild_copies()?;
        }
        self.view_stale = true;
        Ok(())
    }

    /// The current settings.
    pub fn settings(&self) -> Settings {
        self.settings
    }

    /// Moves the camera.
    pub fn set_camera(&mut self, camera: &CameraSettings) {
        self.camera = camera.clone();
        self.view_stale = true;
    }

    /// The copies of the room up to the depth.
    pub fn copies(&self) -> &[Copy] {
        self.scene.as_ref().map_or(&[], |s| &s.copies)
    }

    /// Why each image texture the scene names could not be read (its parts are drawn in their
    /// representative colour); empty when every image is on the GPU.
    pub fn unread_textures(&self) -> &[String] {
        &self.images.unread
    }

    /// What the last frame drew.
    pub fn stats(&self) -> Stats {
        self.stats
    }

    /// The view of the current camera and projection.
    pub fn view(&self) -> Option<View> {
        let state = self.scene.as_ref()?;
        Some(
            View::new(state.layout.space(), &self.camera, self.settings.projection)
                .with_turns(self.settings.turns),
        )
    }

    /// Draws a frame into the preview's own offscreen images and returns the colour texture
    /// (for an application to show).
    pub fn draw(&mut self, width: u32, height: u32) -> Result<&wgpu::Texture, PreviewError> {
        if width == 0 || height == 0 {
            return Err(PreviewError::Size(width, height));
        }
        let limit = self.gpu.device.limits().max_texture_dimension_2d;
        if width > limit || height > limit {
            return Err(PreviewError::Size(width, height));
        }
        if self.scene.is_none() {
            return Err(PreviewError::NoScene);
        }
        if self
            .target
            .as_ref()
            .is_none_or(|t| (t.width, t.height) != (width, height))
        {
            self.target = Some(RenderTargets::new(
                &self.gpu.device,
                width,
                height,
                self.samples,
            ));
            self.view_stale = true;
        }
        if self.view_stale {
            self.upload_view(width, height);
        }
        self.submit(Pass::Opaque);
        Ok(&self.target.as_ref().expect("target made above").color)
    }

    /// Waits until the GPU has finished every frame drawn so far (for timing).
    pub fn finish(&self) -> Result<(), PreviewError> {
        self.gpu
            .device
            .poll(wgpu::PollType::wait_indefinitely())
            .map(|_| ())
            .map_err(|e| PreviewError::Gpu(e.to_string()))
    }
}
