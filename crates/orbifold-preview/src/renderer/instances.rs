//! Which copies of the room a frame draws, and how finely: the instance buffer and the
//! per-frame uniforms.
//!
//! Every copy of the room under the group is one GPU instance that carries its group element
//! (already composed with the view on the CPU, in f64, so that far copies keep their precision)
//! and its brightness. Moving the camera rewrites the instance buffer. Three choices are made
//! per copy, each frame:
//!
//! - *Images*: on the sphere (S²×R) each copy is drawn once per way round (the short and the
//!   long way, for a few turns) and the depth test keeps the nearest (ARCHITECTURE.md §9).
//! - *Frustum culling*: a copy whose bounding sphere misses the view frustum is skipped, where
//!   the logarithm map at the eye cannot stretch distances (κ ≤ 0).
//! - *Levels of detail*: a far copy draws its objects with the coarsest level that still gives
//!   about one triangle per pixel; the instance buffer is sorted by level so that each level is
//!   one instanced draw.

use glam::DVec3;

use super::Preview;
use super::resources::{Globals, InstanceRaw};
use super::scene::SceneState;
use super::settings::{AMBIENT, NEAR, Settings, Stats};
use crate::projection::{Projection, View};

impl Preview {
    /// Writes the globals and the instance buffer for the current camera.
    pub(super) fn upload_view(&mut self, width: u32, height: u32) {
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
        self.view_stale = false;
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
    let reach = state.bounding_radius();
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
                && !ball_in_frustum(view, t, reach, aspect)
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

/// Whether a ball of radius `reach` about the tangent vector `t` (a copy's bounding sphere,
/// mapped to the eye's tangent space) meets the view frustum.
fn ball_in_frustum(view: &View, t: DVec3, reach: f64, aspect: f64) -> bool {
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
