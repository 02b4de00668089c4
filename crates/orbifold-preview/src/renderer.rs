//! The preview renderer: a scene in, a frame out, with cheap updates.
//!
//! The room and the objects live in two vertex buffers (objects in their own frames); every copy
//! of the room under the group is one GPU instance that carries its group element (already
//! composed with the view on the CPU, in f64) and its brightness. Moving the camera rewrites the
//! instance buffer; moving an object rewrites one entry of the part table; a new layout rebuilds
//! the room's buffer and the copies; a new depth only the copies.

use std::path::Path;

use bytemuck::{Pod, Zeroable};
use glam::DVec3;
use orbifold::Layout;
use orbifold::embed::Placement;
use orbifold_scene::{Attenuation, Camera as CameraSettings, Scene};
use wgpu::util::DeviceExt;

use crate::PreviewError;
use crate::copies::{Copy, copies};
use crate::frame::Frame;
use crate::gpu::Gpu;
use crate::mesh::{self, MeshData, PartStyle, Vertex};
use crate::projection::{Projection, View};

/// The largest number of parts (objects, floor, ceiling, walls and mirrors) a scene may have.
pub const MAX_PARTS: usize = 256;

/// The colour format of the preview's image.
pub const COLOR_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba8UnormSrgb;
const ID_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::R32Sint;
const DEPTH_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Depth32Float;
/// Samples a pixel of the colour picture on a GPU (multisample antialiasing); software
/// adapters take one, as four cost them two to four times the time.
pub const GPU_SAMPLES: u32 = 4;
/// How close to the eye a surface may come before it is cut away (intrinsic units).
const NEAR: f64 = 0.005;
/// The background colour (linear RGB): what lies beyond the copies drawn.
pub const BACKGROUND: [f64; 3] = [0.012, 0.014, 0.02];
/// The share of light every surface gets whatever its angle to the eye.
const AMBIENT: f32 = 0.3;

/// What the preview shows, apart from the scene and the camera.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Settings {
    /// How many reflections deep the copies go (the whole group in S²×R).
    pub depth: u32,
    /// How copies fade (seed Fig. 8.6).
    pub attenuation: Attenuation,
    /// Curved or straight projection.
    pub projection: Projection,
    /// Whether copies that cannot be in view are skipped.
    pub cull: bool,
    /// In S²×R, how many times round the sphere the images go (see [`View::with_turns`]).
    pub turns: u32,
    /// Whether far copies draw their objects with fewer triangles (levels of detail).
    pub lod: bool,
}

impl Settings {
    /// The settings a scene's `[preview]` section gives.
    pub fn of_scene(scene: &Scene) -> Settings {
        Settings {
            depth: scene.preview.depth,
            attenuation: scene.preview.attenuation,
            projection: Projection::Curved,
            cull: true,
            turns: DEFAULT_TURNS,
            lod: true,
        }
    }
}

/// Turns round the sphere drawn by default: every floor and ceiling seen more than about 2°
/// from level in a room of height 1.
pub const DEFAULT_TURNS: u32 = 3;

/// What the last frame drew.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Stats {
    /// Copies of the room up to the depth (the room itself included).
    pub copies: usize,
    /// Instances drawn: copies in view, times the images of each point (two in S²×R).
    pub instances: usize,
    /// Triangles of one copy of the room with its objects.
    pub triangles_per_copy: usize,
    /// Triangles drawn: instances times triangles per copy.
    pub triangles: usize,
}

#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable)]
struct Globals {
    right: [f32; 4],
    up: [f32; 4],
    forward: [f32; 4],
    lens: [f32; 4],
    eye: [f32; 4],
}

#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable)]
struct InstanceRaw {
    columns: [[f32; 4]; 3],
    tint: [f32; 4],
}

/// A mesh on the GPU.
struct GpuMesh {
    vertices: wgpu::Buffer,
    indices: wgpu::Buffer,
    opaque: std::ops::Range<u32>,
    mirrors: std::ops::Range<u32>,
}

impl GpuMesh {
    fn new(device: &wgpu::Device, data: &MeshData, label: &str) -> Option<GpuMesh> {
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

/// Offscreen images of one size: the multisampled colour and depth of the picture, its
/// resolved colour, and the single-sampled surface ids with their own depth.
struct Target {
    width: u32,
    height: u32,
    /// With multisampling: the samples, resolved into `color`.
    color_samples: Option<wgpu::Texture>,
    depth_samples: wgpu::Texture,
    color: wgpu::Texture,
    id: wgpu::Texture,
    id_depth: wgpu::Texture,
}

impl Target {
    fn new(device: &wgpu::Device, width: u32, height: u32, samples: u32) -> Target {
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
        Target {
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

/// The scene as the preview holds it on the CPU.
struct SceneState {
    layout: Layout,
    height: f64,
    reflectances: Vec<[f64; 3]>,
    /// Part styles: objects first, then the room's parts.
    styles: Vec<PartStyle>,
    objects: usize,
    /// The largest intrinsic distance of an object's point from the object's centre.
    object_radius: f64,
    /// The highest point of an object above its base.
    object_top: f64,
    object_triangles: usize,
    /// The index ranges of the objects' levels of detail, finest first.
    object_levels: Vec<std::ops::Range<u32>>,
    /// The largest intrinsic distance from the room's centre to its boundary.
    room_radius: f64,
    room_triangles: usize,
    copies: Vec<Copy>,
}

impl SceneState {
    /// How far from the room's centre (in the product space, from mid-height) anything of one
    /// copy can be.
    fn reach(&self) -> f64 {
        let top = self.height.max(self.object_top);
        (self.room_radius + self.object_radius).hypot(0.5 * top)
    }

    fn triangles(&self) -> usize {
        self.room_triangles + self.object_triangles
    }
}

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
    opaque: wgpu::RenderPipeline,
    mirror: wgpu::RenderPipeline,
    ids: wgpu::RenderPipeline,
    points: wgpu::RenderPipeline,
    /// Samples a pixel of the colour picture.
    samples: u32,
    globals: wgpu::Buffer,
    parts: wgpu::Buffer,
    bind_group: wgpu::BindGroup,
    instances: Option<wgpu::Buffer>,
    room: Option<GpuMesh>,
    objects: Option<GpuMesh>,
    target: Option<Target>,
    scene: Option<SceneState>,
    camera: CameraSettings,
    settings: Settings,
    stats: Stats,
    /// Whether the instance buffer must be rebuilt before the next frame.
    stale: bool,
    /// The instances of each level of detail (the instance buffer is sorted by level).
    instance_levels: Vec<std::ops::Range<u32>>,
}

impl Preview {
    /// A preview that draws on `gpu`. Load a scene before rendering.
    pub fn new(gpu: Gpu) -> Preview {
        let device = &gpu.device;
        let source = include_str!("preview.wgsl").replace("MAX_PARTS", &MAX_PARTS.to_string());
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
        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("preview bindings"),
            entries: &[uniform(0), uniform(1)],
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
        let bind_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("preview bindings"),
            layout: &layout,
            entries: &[
                wgpu::BindGroupEntry {
                    binding: 0,
                    resource: globals.as_entire_binding(),
                },
                wgpu::BindGroupEntry {
                    binding: 1,
                    resource: parts.as_entire_binding(),
                },
            ],
        });
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
        Preview {
            gpu,
            opaque,
            mirror,
            ids,
            points,
            samples,
            globals,
            parts,
            bind_group,
            instances: None,
            room: None,
            objects: None,
            target: None,
            scene: None,
            camera: CameraSettings::default(),
            settings: Settings::of_scene(&Scene::default()),
            stats: Stats::default(),
            stale: true,
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

    /// Loads a whole scene: room, objects, copies, camera and the scene's preview settings.
    /// `base` resolves mesh file names.
    pub fn load(&mut self, scene: &Scene, base: Option<&Path>) -> Result<(), PreviewError> {
        let layout = scene.layout().map_err(PreviewError::Scene)?;
        let objects = mesh::objects(scene, &layout, base).map_err(PreviewError::Scene)?;
        self.objects = GpuMesh::new(&self.gpu.device, &objects.mesh, "preview objects");
        let object_radius = objects.extents.iter().map(|e| e.0).fold(0.0, f64::max);
        // The highest point: an object's top above the height it stands at.
        let object_top = objects
            .extents
            .iter()
            .zip(&scene.objects)
            .map(|(e, o)| e.1 + o.height)
            .fold(0.0, f64::max);
        self.scene = Some(SceneState {
            layout: layout.clone(),
            height: scene.room.height,
            reflectances: Vec::new(),
            objects: objects.styles.len(),
            styles: objects.styles,
            object_radius,
            object_top,
            // Full detail: the first level (the coarser ones follow it in the index list).
            object_triangles: objects.levels.first().map_or(0, |l| l.len() / 3),
            object_levels: objects.levels.clone(),
            room_radius: 0.0,
            room_triangles: 0,
            copies: Vec::new(),
        });
        self.settings = Settings {
            depth: scene.preview.depth,
            attenuation: scene.preview.attenuation,
            ..self.settings
        };
        self.camera = scene.camera.clone();
        self.set_room(scene).inspect_err(|_| {
            // Half a scene is worse than none: drawing says so until a scene loads.
            self.scene = None;
            self.room = None;
            self.objects = None;
        })
    }

    /// Rebuilds the room (its layout, height, mirrors and materials changed) and its copies,
    /// keeping the objects.
    pub fn set_room(&mut self, scene: &Scene) -> Result<(), PreviewError> {
        let Some(state) = self.scene.as_mut() else {
            return self.load(scene, None);
        };
        let layout = scene.layout().map_err(PreviewError::Scene)?;
        let mesher = scene.room_mesher(&layout).map_err(PreviewError::Scene)?;
        let (room, styles) = mesh::room(scene, &layout, &mesher, state.objects as u32);
        if state.objects + styles.len() > MAX_PARTS {
            return Err(PreviewError::Scene(format!(
                "the scene has {} parts (objects, floor, ceiling, walls and mirrors); the preview \
                 draws at most {MAX_PARTS}",
                state.objects + styles.len()
            )));
        }
        state.styles.truncate(state.objects);
        state.styles.extend(styles);
        state.reflectances = (0..layout.edges.len())
            .map(|w| wall_reflectance(scene, w))
            .collect();
        let centre = layout.space().to_ambient(layout.centre);
        state.room_radius = room
            .vertices
            .iter()
            .map(|v| {
                let p = DVec3::new(
                    v.position[0].into(),
                    v.position[1].into(),
                    v.position[2].into(),
                );
                layout.space().ambient_distance(centre, p)
            })
            .fold(0.0, f64::max);
        state.height = scene.room.height;
        state.room_triangles = room.triangles();
        state.layout = layout;
        self.room = GpuMesh::new(&self.gpu.device, &room, "preview room");
        self.gpu
            .queue
            .write_buffer(&self.parts, 0, bytemuck::cast_slice(&state.styles));
        self.rebuild_copies()
    }

    /// Sets the depth, the attenuation, the projection and culling.
    pub fn set_settings(&mut self, settings: Settings) -> Result<(), PreviewError> {
        let old = std::mem::replace(&mut self.settings, settings);
        if old.depth != settings.depth || old.attenuation != settings.attenuation {
            self.rebuild_copies()?;
        }
        self.stale = true;
        Ok(())
    }

    /// The current settings.
    pub fn settings(&self) -> Settings {
        self.settings
    }

    /// Moves the camera.
    pub fn set_camera(&mut self, camera: &CameraSettings) {
        self.camera = camera.clone();
        self.stale = true;
    }

    /// Moves object `index` (of the scene's objects): 64 bytes to the GPU, nothing rebuilt.
    pub fn set_object_placement(
        &mut self,
        index: usize,
        placement: &Placement,
    ) -> Result<(), PreviewError> {
        let state = self.scene.as_mut().ok_or(PreviewError::NoScene)?;
        if index >= state.objects {
            return Err(PreviewError::Scene(format!(
                "object {index} does not exist (the scene has {})",
                state.objects
            )));
        }
        let style = &mut state.styles[index];
        style.place(state.layout.space(), Some(placement));
        let offset = (index * std::mem::size_of::<PartStyle>()) as u64;
        self.gpu
            .queue
            .write_buffer(&self.parts, offset, bytemuck::bytes_of(style));
        Ok(())
    }

    /// The copies of the room up to the depth.
    pub fn copies(&self) -> &[Copy] {
        self.scene.as_ref().map_or(&[], |s| &s.copies)
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

    fn rebuild_copies(&mut self) -> Result<(), PreviewError> {
        let state = self.scene.as_mut().ok_or(PreviewError::NoScene)?;
        state.copies = copies(
            &state.layout,
            self.settings.depth,
            &state.reflectances,
            self.settings.attenuation,
        )
        .map_err(|e| PreviewError::Scene(format!("copies of the room: {e}")))?;
        self.stale = true;
        Ok(())
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
            self.target = Some(Target::new(&self.gpu.device, width, height, self.samples));
            self.stale = true;
        }
        if self.stale {
            self.upload_view(width, height);
        }
        self.submit(Pass::Opaque);
        Ok(&self.target.as_ref().expect("target made above").color)
    }

    /// Where the vertices of the room itself (floor, ceiling, walls and mirrors, not the
    /// objects or the copies) land: the vertex index (into the room's vertex list, as
    /// [`mesh::room`] makes it) and pixel of each vertex drawn, one vertex per pixel (the last
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

    /// Waits until the GPU has finished every frame drawn so far (for timing).
    pub fn finish(&self) -> Result<(), PreviewError> {
        self.gpu
            .device
            .poll(wgpu::PollType::wait_indefinitely())
            .map(|_| ())
            .map_err(|e| PreviewError::Gpu(e.to_string()))
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

    /// Writes the globals and the instance buffer for the current camera.
    fn upload_view(&mut self, width: u32, height: u32) {
        let state = self.scene.as_ref().expect("checked by the caller");
        let space = state.layout.space();
        let view = View::new(space, &self.camera, self.settings.projection)
            .with_turns(self.settings.turns);
        let aspect = f64::from(width) / f64::from(height);
        let (instances, levels, far) =
            instances(&view, state, &self.settings, aspect, f64::from(height));
        let [forward, right, up] = view.basis();
        let v4 = |v: DVec3, w: f64| [v.x as f32, v.y as f32, v.z as f32, w as f32];
        let mode = f64::from(u8::from(self.settings.projection == Projection::Straight));
        let eye = view.eye_model();
        let globals = Globals {
            right: v4(right, space.kappa()),
            up: v4(up, view.eye_height()),
            forward: v4(forward, mode),
            lens: [
                (1.0 / (view.tan_half_fov() * aspect)) as f32,
                (1.0 / view.tan_half_fov()) as f32,
                NEAR as f32,
                far as f32,
            ],
            eye: [2.0 * eye.re as f32, 2.0 * eye.im as f32, AMBIENT, 0.0],
        };
        self.gpu
            .queue
            .write_buffer(&self.globals, 0, bytemuck::bytes_of(&globals));
        let bytes: &[u8] = bytemuck::cast_slice(&instances);
        let fits = self
            .instances
            .as_ref()
            .is_some_and(|b| b.size() >= bytes.len() as u64);
        if !fits && !bytes.is_empty() {
            self.instances = Some(self.gpu.device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("preview copies"),
                size: (bytes.len() as u64).next_power_of_two(),
                usage: wgpu::BufferUsages::VERTEX | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            }));
        }
        if let Some(buffer) = &self.instances
            && !bytes.is_empty()
        {
            self.gpu.queue.write_buffer(buffer, 0, bytes);
        }
        let drawn: usize = levels
            .iter()
            .zip(&state.object_levels)
            .map(|(copies, l)| copies.len() * (state.room_triangles + l.len() / 3))
            .sum();
        self.stats = Stats {
            copies: state.copies.len(),
            instances: instances.len(),
            triangles_per_copy: state.triangles(),
            triangles: drawn,
        };
        self.instance_levels = levels;
        self.stale = false;
    }

    /// Records one pass and sends it to the GPU.
    fn submit(&self, pass: Pass) {
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

/// What a wall's mirrors reflect, weighted by their areas (1 for a wall without a mirror).
fn wall_reflectance(scene: &Scene, wall: usize) -> [f64; 3] {
    let height = scene.room.height;
    let mut total = [0.0; 3];
    let mut area = 0.0;
    for m in scene.wall_mirrors(wall) {
        let a = (m.to - m.from) * (m.top.unwrap_or(height).min(height) - m.bottom);
        if a > 0.0 {
            area += a;
            (0..3).for_each(|k| total[k] += a * m.reflectance[k]);
        }
    }
    if area > 0.0 {
        total.map(|t| t / area)
    } else {
        [1.0; 3]
    }
}

/// The instances of the copies in view, sorted by the level of detail of their objects, the
/// instance range of each level, and the far distance that holds them all.
fn instances(
    view: &View,
    state: &SceneState,
    settings: &Settings,
    aspect: f64,
    height_px: f64,
) -> (Vec<InstanceRaw>, Vec<std::ops::Range<u32>>, f64) {
    let space = view.space();
    let centre = space.to_ambient(state.layout.centre);
    let reach = state.reach();
    let mut far: f64 = 1.0;
    let levels = state.object_levels.len().max(1);
    let mut by_level: Vec<Vec<InstanceRaw>> = vec![Vec::new(); levels];
    // Pixels per unit of size at unit distance.
    let focal = 0.5 * height_px / view.tan_half_fov();
    for image in 0..view.images() {
        for copy in &state.copies {
            let c = copy.matrix * centre;
            let t = view.log(c, 0.5 * state.height.max(state.object_top), image);
            // The log map at the eye never stretches distances where κ ≤ 0, so the copy lies
            // within `reach` of its centre's image; on the sphere it may stretch, so no culling.
            if settings.cull
                && space.kappa() <= 0.0
                && view.projection() == Projection::Curved
                && !in_view(view, t, reach, aspect)
            {
                continue;
            }
            far = far.max(t.length() + reach);
            let level = if settings.lod {
                // The log map scales sizes across the line of sight by d/S_κ(d) at horizontal
                // distance d (magnifying near the sphere's antipode, shrinking in H²), and
                // heights not at all: an image far round the sphere is wide and flat.
                let d = t.x.hypot(t.y);
                let stretch = match view.projection() {
                    Projection::Curved if d > 1e-9 => d / space.sin(d).abs().max(1e-9),
                    _ => 1.0,
                };
                let width = 2.0 * state.object_radius;
                let height = width.max(state.object_top);
                let pixels = focal / (t.length() - reach).max(1e-3);
                detail_level(
                    &state.object_levels,
                    (width * stretch * pixels) * (height * pixels),
                )
            } else {
                0
            };
            let m = view.instance_matrix(&copy.matrix);
            let mut columns =
                [m.x_axis, m.y_axis, m.z_axis].map(|c| [c.x as f32, c.y as f32, c.z as f32, 0.0]);
            columns[0][3] = copy.depth as f32;
            by_level[level].push(InstanceRaw {
                columns,
                tint: [
                    copy.tint[0] as f32,
                    copy.tint[1] as f32,
                    copy.tint[2] as f32,
                    image as f32,
                ],
            });
        }
    }
    if space.kappa() > 0.0 && view.projection() == Projection::Curved {
        // Image k reaches (k + 1)π round the sphere.
        far = far.max(std::f64::consts::PI * f64::from(view.images()) + reach);
    }
    let mut ranges = Vec::with_capacity(levels);
    let mut out = Vec::with_capacity(by_level.iter().map(Vec::len).sum());
    for list in by_level {
        let start = out.len() as u32;
        out.extend(list);
        ranges.push(start..out.len() as u32);
    }
    (out, ranges, far * 1.01)
}

/// The coarsest level of detail that still gives an object about one triangle per pixel of the
/// rectangle it covers on screen (`area` pixels, its width times its height): the first level
/// with at most that many triangles.
fn detail_level(levels: &[std::ops::Range<u32>], area: f64) -> usize {
    levels
        .iter()
        .position(|l| (l.len() / 3) as f64 <= area)
        .unwrap_or(levels.len().saturating_sub(1))
}

/// Whether a ball of radius `reach` about the tangent vector `t` meets the view frustum.
fn in_view(view: &View, t: DVec3, reach: f64, aspect: f64) -> bool {
    let [forward, right, up] = view.basis();
    let (x, y, z) = (t.dot(right), t.dot(up), t.dot(forward));
    if z + reach < NEAR {
        return false;
    }
    let tan_y = view.tan_half_fov();
    let tan_x = tan_y * aspect;
    // Distance to each side plane through the eye, whose normal is (±1, 0, −tan)/√(1 + tan²).
    let side = |u: f64, tan: f64| (u.abs() - tan * z) / (1.0 + tan * tan).sqrt();
    side(x, tan_x) <= reach && side(y, tan_y) <= reach
}

/// The ways the preview draws.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Pass {
    /// Surfaces, antialiased, with depth.
    Opaque,
    /// Mirrors over them: blended, no depth write (in the same pass as `Opaque`).
    Mirror,
    /// The surface under each pixel, mirrors seen through.
    Ids,
    /// The room's vertices as points writing their index, over everything.
    Points,
}

fn pipeline(
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn instance_and_style_layouts_match_the_shader() {
        assert_eq!(std::mem::size_of::<InstanceRaw>(), 64);
        assert_eq!(std::mem::size_of::<PartStyle>(), 112);
        assert_eq!(std::mem::size_of::<Globals>(), 80);
        assert_eq!(std::mem::size_of::<Vertex>(), 32);
    }
}
