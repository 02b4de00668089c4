//! Uploading a scene: what the preview keeps of it on the CPU ([`SceneState`]), and the
//! [`Preview`] methods that load it and apply cheap updates.
//!
//! The room and the objects live in two vertex buffers (objects in their own frames) and the
//! part table holds every part's style and placement. Each update rewrites only what it
//! changes: moving an object rewrites one entry of the part table; a new layout rebuilds the
//! room's buffer and the copies; a new depth only the copies (through
//! [`Preview::set_settings`]).

use std::path::{Path, PathBuf};

use glam::DVec3;
use orbifold::Layout;
use orbifold::embed::Placement;
use orbifold_scene::Scene;

use super::Preview;
use super::resources::GpuMesh;
use super::settings::{MAX_PARTS, Settings};
use crate::PreviewError;
use crate::copies::{Copy, copies};
use crate::mesh::{self, PartStyle};
use crate::textures::TextureTable;

/// The scene as the preview holds it on the CPU.
pub(super) struct SceneState {
    pub(super) layout: Layout,
    pub(super) height: f64,
    /// Each wall's reflectance, for the copies' brightness (see [`wall_reflectance`]).
    pub(super) reflectances: Vec<[f64; 3]>,
    /// Part styles: objects first, then the room's parts.
    pub(super) styles: Vec<PartStyle>,
    pub(super) objects: usize,
    /// The image files of the objects' materials (the room's follow them in the layers).
    pub(super) object_textures: TextureTable,
    /// The folder that mesh and image file names are relative to.
    pub(super) base: Option<PathBuf>,
    /// The largest intrinsic distance of an object's point from the object's centre.
    pub(super) object_radius: f64,
    /// The highest point of an object above its base.
    pub(super) object_top: f64,
    pub(super) object_triangles: usize,
    /// The index ranges of the objects' levels of detail, finest first.
    pub(super) object_levels: Vec<std::ops::Range<u32>>,
    /// The largest intrinsic distance from the room's centre to its boundary.
    pub(super) room_radius: f64,
    pub(super) room_triangles: usize,
    pub(super) copies: Vec<Copy>,
}

impl SceneState {
    /// The radius of a bounding sphere of one copy: how far from the room's centre (in the
    /// product space, from mid-height) anything of one copy can be.
    pub(super) fn bounding_radius(&self) -> f64 {
        let top = self.height.max(self.object_top);
        (self.room_radius + self.object_radius).hypot(0.5 * top)
    }

    pub(super) fn triangles(&self) -> usize {
        self.room_triangles + self.object_triangles
    }
}

impl Preview {
    /// Loads a whole scene: room, objects, copies, camera and the scene's preview settings.
    /// `base` resolves mesh and image file names.
    pub fn load(&mut self, scene: &Scene, base: Option<&Path>) -> Result<(), PreviewError> {
        let layout = scene.layout().map_err(PreviewError::Scene)?;
        let mut object_textures = TextureTable::default();
        let objects = mesh::objects(scene, &layout, base, &mut object_textures)
            .map_err(PreviewError::Scene)?;
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
            object_textures,
            base: base.map(Path::to_path_buf),
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
        let mut textures = state.object_textures.clone();
        let (room, styles) =
            mesh::room(scene, &layout, &mesher, state.objects as u32, &mut textures);
        if state.objects + styles.len() > MAX_PARTS {
            return Err(PreviewError::Scene(format!(
                "the scene has {} parts (objects, floor, ceiling, walls and mirrors); the preview \
                 draws at most {MAX_PARTS}",
                state.objects + styles.len()
            )));
        }
        state.styles.truncate(state.objects);
        state.styles.extend(styles);
        state.reflectances = (layout.edges.iter().enumerate())
            .map(|(w, edge)| wall_reflectance(scene, w, edge.partner().is_some()))
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
        let mut styles = std::mem::take(&mut state.styles);
        let base = state.base.clone();
        self.upload_images(&textures, base.as_deref(), &mut styles);
        self.room = GpuMesh::new(&self.gpu.device, &room, "preview room");
        self.gpu
            .queue
            .write_buffer(&self.parts, 0, bytemuck::cast_slice(&styles));
        if let Some(state) = self.scene.as_mut() {
            state.styles = styles;
        }
        self.rebuild_copies()
    }

    /// Moves object `index` (of the scene's objects): one entry of the part table to the GPU,
    /// nothing rebuilt.
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

    /// Recomputes the copies of the room up to the depth, for a new layout, depth or
    /// attenuation.
    pub(super) fn rebuild_copies(&mut self) -> Result<(), PreviewError> {
        let state = self.scene.as_mut().ok_or(PreviewError::NoScene)?;
        state.copies = copies(
            &state.layout,
            self.settings.depth,
            &state.reflectances,
            self.settings.attenuation,
        )
        .map_err(|e| PreviewError::Scene(format!("copies of the room: {e}")))?;
        self.view_stale = true;
        Ok(())
    }
}

/// What a wall's mirrors reflect, weighted by their areas (1 for a wall without a mirror): the
/// the reflectance [`copies`] tints a copy by for each reflection in that wall.
fn wall_reflectance(scene: &Scene, wall: usize, portal: bool) -> [f64; 3] {
    let height = scene.room.height;
    let mut total = [0.0; 3];
    let mut area = 0.0;
    for m in scene.mirrors_of_wall(wall, portal) {
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
