//! The 3D view: the real-time preview (`orbifold-preview`) of the room and its mirror copies,
//! with the depth, attenuation and straight-rays controls, and walking inside the room.
//!
//! Keys: W/S or ↑/↓ walk forward and back along the geodesic, A/D or ←/→ turn, Q/E look up and
//! down; dragging in the view turns and tilts. Walking moves the view's own camera; "Use this
//! view" makes it the scene's camera (one undoable edit). While the camera moves the view draws
//! two reflections fewer, and the full depth again as soon as it stops.

use egui::{Color32, Ui};
use num_complex::Complex64;
use orbifold::Layout;
use orbifold::space::Space;
use orbifold_preview::{Gpu, Preview, Projection};
use orbifold_scene::{Attenuation, Camera, Scene};

/// How far one key press walks (intrinsic units per second).
const WALK_SPEED: f64 = 0.5;
/// How fast keys turn (degrees per second).
const TURN_SPEED: f64 = 60.0;

/// The window's GPU, when the preview draws on it: its frame is then shown as a wgpu texture
/// registered with egui's renderer, with no copy back to the CPU. The web studio needs this
/// (the browser cannot wait for a GPU copy inside a frame, nor open a second device), the
/// desktop studio draws on a device of its own and copies the frame back.
struct WindowGpu {
    state: eframe::egui_wgpu::RenderState,
    /// The preview's colour image as egui knows it.
    texture: Option<egui::TextureId>,
}

/// The 3D view's state.
pub struct View3d {
    preview: Option<Result<Preview, String>>,
    texture: Option<egui::TextureHandle>,
    window: Option<WindowGpu>,
    /// The camera the view shows (walking moves it).
    pub camera: Camera,
    /// Reflections deep.
    pub depth: u32,
    /// How copies fade.
    pub attenuation: Attenuation,
    /// Straight rays (the model picture as flat space).
    pub straight: bool,
    /// The document revision and settings last drawn.
    drawn: Option<(u64, Camera, u32, Attenuation, bool, [usize; 2])>,
    /// What the preview drew: copies and triangles, for the status line.
    pub stats: Option<orbifold_preview::Stats>,
    /// The last error, for the status line.
    pub error: Option<String>,
    /// What the picture leaves out (an image texture that cannot be read), shown over it.
    pub warning: Option<String>,
    /// The revision and scene the preview holds.
    loaded: Option<(u64, Scene)>,
    /// Whether the camera is moving (keys held or a drag under way).
    moving: bool,
}

impl View3d {
    /// The size in pixels of the picture last drawn (width, height), if one was: the render
    /// tab frames its picture to the same shape.
    pub fn drawn_size(&self) -> Option<[usize; 2]> {
        self.drawn.as_ref().map(|drawn| drawn.5)
    }

    /// A view of a scene's camera and preview settings.
    pub fn new(scene: &Scene) -> View3d {
        View3d {
            preview: None,
            texture: None,
            window: None,
            camera: scene.camera.clone(),
            depth: scene.preview.depth,
            attenuation: scene.preview.attenuation,
            straight: false,
            drawn: None,
            stats: None,
            error: None,
            warning: None,
            loaded: None,
            moving: false,
        }
    }

    /// Starts again from a scene (after opening a document).
    pub fn reset(&mut self, scene: &Scene) {
        let preview = self.preview.take();
        let window = self.window.take();
        *self = View3d::new(scene);
        self.preview = preview;
        self.window = window;
    }

    /// Loads the scene's files again for the next frame, though the scene has not changed: a
    /// file it names has been given since (a mesh dropped on the web studio's page after the
    /// scene that names it was opened).
    ///
    /// ```
    /// use orbifold_scene::Scene;
    /// use orbifold_studio::view3d::View3d;
    /// let mut view = View3d::new(&Scene::default());
    /// view.reload();
    /// assert_eq!(view.drawn_size(), None);
    /// ```
    pub fn reload(&mut self) {
        self.drawn = None;
        self.loaded = None;
    }

    /// Draws the preview on the window's GPU (eframe's wgpu device) and shows its frames
    /// without copying them back to the CPU, in place of a device of its own: what the web
    /// studio does.
    pub fn use_window_gpu(&mut self, state: &eframe::egui_wgpu::RenderState) {
        self.window = Some(WindowGpu {
            state: state.clone(),
            texture: None,
        });
        self.preview = None;
        self.drawn = None;
        self.loaded = None;
    }

    /// The adapter the preview draws on, once it has drawn.
    pub fn adapter(&self) -> Option<String> {
        match &self.preview {
            Some(Ok(p)) => Some(p.gpu().describe()),
            _ => None,
        }
    }

    /// The controls and the picture. `revision` tells when the scene changed.
    pub fn show(
        &mut self,
        ui: &mut Ui,
        scene: &Scene,
        base: Option<&std::path::Path>,
        revision: u64,
    ) {
        ui.horizontal(|ui| {
            crate::design::labelled_value(ui, "depth", &mut self.depth, 0..=14, 0.05);
            let label = ui.label("attenuation");
            egui::ComboBox::from_id_salt("attenuation")
                .selected_text(attenuation_name(self.attenuation))
                .show_ui(ui, |ui| {
                    for a in [
                        Attenuation::Reflectance,
                        Attenuation::Orbifold,
                        Attenuation::Translations,
                        Attenuation::Universal,
                    ] {
                        ui.selectable_value(&mut self.attenuation, a, attenuation_name(a));
                    }
                })
                .response
                .labelled_by(label.id);
            ui.checkbox(&mut self.straight, "straight rays");
        });
        let size = ui.available_size();
        let (w, h) = (size.x.max(64.0) as usize, (size.y - 4.0).max(48.0) as usize);
        let (rect, response) = ui.allocate_exact_size(
            egui::vec2(w as f32, h as f32),
            egui::Sense::click_and_drag(),
        );
        self.walk(ui, &response, scene);
        self.redraw(ui, scene, base, revision, [w, h]);
        let shown = match &self.window {
            Some(window) => window.texture,
            None => self.texture.as_ref().map(egui::TextureHandle::id),
        };
        match shown.filter(|_| self.error.is_none()) {
            Some(texture) => {
                ui.painter().image(
                    texture,
                    rect,
                    egui::Rect::from_min_max(egui::pos2(0.0, 0.0), egui::pos2(1.0, 1.0)),
                    Color32::WHITE,
                );
                if let Some(warning) = &self.warning {
                    ui.painter().text(
                        rect.left_bottom() + egui::vec2(6.0, -6.0),
                        egui::Align2::LEFT_BOTTOM,
                        format!("{warning} (drawn in its plain colour)"),
                        egui::FontId::proportional(13.0),
                        Color32::YELLOW,
                    );
                }
            }
            None => {
                ui.painter().rect_filled(rect, 0.0, Color32::from_gray(20));
                let text = self.error.clone().unwrap_or_else(|| "no preview".into());
                ui.painter().text(
                    rect.center(),
                    egui::Align2::CENTER_CENTER,
                    text,
                    egui::FontId::proportional(14.0),
                    Color32::LIGHT_RED,
                );
            }
        }
    }

    /// Keys and drags move the view's camera.
    fn walk(&mut self, ui: &Ui, response: &egui::Response, scene: &Scene) {
        self.moving = response.dragged();
        if response.dragged() {
            let d = response.drag_delta();
            self.camera.yaw -= f64::from(d.x) * 0.3;
            self.camera.pitch = (self.camera.pitch - f64::from(d.y) * 0.3).clamp(-89.0, 89.0);
        }
        if !(response.hovered() || response.has_focus()) {
            return;
        }
        let dt = f64::from(ui.input(|i| i.stable_dt)).min(0.1);
        let (forward, turn, tilt) = ui.input(|i| {
            let key = |a: egui::Key, b: egui::Key| i.key_down(a) || i.key_down(b);
            let axis = |plus: bool, minus: bool| f64::from(i8::from(plus) - i8::from(minus));
            (
                axis(
                    key(egui::Key::W, egui::Key::ArrowUp),
                    key(egui::Key::S, egui::Key::ArrowDown),
                ),
                axis(
                    key(egui::Key::A, egui::Key::ArrowLeft),
                    key(egui::Key::D, egui::Key::ArrowRight),
                ),
                axis(i.key_down(egui::Key::Q), i.key_down(egui::Key::E)),
            )
        });
        self.camera.yaw += turn * TURN_SPEED * dt;
        self.camera.pitch = (self.camera.pitch + tilt * TURN_SPEED * dt).clamp(-89.0, 89.0);
        if forward != 0.0
            && let Ok(layout) = scene.layout()
        {
            walk_through_portals(&layout, &mut self.camera, forward * WALK_SPEED * dt);
        }
        if forward != 0.0 || turn != 0.0 || tilt != 0.0 {
            self.moving = true;
            ui.ctx().request_repaint();
        }
    }

    /// The depth drawn: while the camera moves, two reflections less (at least 2), so that
    /// walking stays fluid on a slow adapter; the full depth as soon as it stops.
    fn drawn_depth(&self) -> u32 {
        if self.moving {
            self.depth.min(self.depth.saturating_sub(2).max(2))
        } else {
            self.depth
        }
    }

    /// Draws a new frame when the scene, the camera, the settings or the size changed.
    fn redraw(
        &mut self,
        ui: &Ui,
        scene: &Scene,
        base: Option<&std::path::Path>,
        revision: u64,
        size: [usize; 2],
    ) {
        let depth = self.drawn_depth();
        let key = (
            revision,
            self.camera.clone(),
            depth,
            self.attenuation,
            self.straight,
            size,
        );
        if self.drawn.as_ref() == Some(&key) {
            return;
        }
        self.drawn = Some(key);
        let window = &mut self.window;
        let preview = self.preview.get_or_insert_with(|| match window.as_ref() {
            Some(w) => Ok(Preview::new(Gpu::from_parts(
                w.state.device.clone(),
                w.state.queue.clone(),
                w.state.adapter.get_info(),
            ))),
            None => Gpu::headless().map(Preview::new).map_err(|e| e.to_string()),
        });
        let preview = match preview {
            Ok(p) => p,
            Err(e) => {
                self.error = Some(e.clone());
                return;
            }
        };
        let result = (|| -> Result<Option<Vec<u8>>, orbifold_preview::PreviewError> {
            if self.loaded.as_ref().is_none_or(|(r, _)| *r != revision) {
                let before = self.loaded.take().map(|(_, s)| s);
                update(preview, before.as_ref(), scene, base)?;
                self.loaded = Some((revision, scene.clone()));
            }
            preview.set_camera(&self.camera);
            let mut settings = preview.settings();
            settings.depth = depth;
            settings.attenuation = self.attenuation;
            settings.projection = if self.straight {
                Projection::Straight
            } else {
                Projection::Curved
            };
            preview.set_settings(settings)?;
            let (width, height) = (size[0] as u32, size[1] as u32);
            match window {
                Some(window) => {
                    let texture = preview.draw(width, height)?;
                    let view = texture.create_view(&Default::default());
                    let mut renderer = window.state.renderer.write();
                    let device = &window.state.device;
                    let filter = eframe::wgpu::FilterMode::Linear;
                    match window.texture {
                        Some(id) => {
                            renderer
                                .update_egui_texture_from_wgpu_texture(device, &view, filter, id);
                        }
                        None => {
                            window.texture =
                                Some(renderer.register_native_texture(device, &view, filter));
                        }
                    }
                    Ok(None)
                }
                // Colours only: the surface ids would draw every triangle a second time.
                None => preview.render_colors(width, height).map(Some),
            }
        })();
        match result {
            Ok(None) => {
                self.stats = Some(preview.stats());
                self.error = None;
                self.warning = preview.unread_textures().first().cloned();
            }
            Ok(Some(rgba)) => {
                let image = egui::ColorImage::from_rgba_unmultiplied(size, &rgba);
                match &mut self.texture {
                    Some(t) => t.set(image, egui::TextureOptions::LINEAR),
                    None => {
                        self.texture = Some(ui.ctx().load_texture(
                            "preview",
                            image,
                            egui::TextureOptions::LINEAR,
                        ));
                    }
                }
                self.stats = Some(preview.stats());
                self.error = None;
                self.warning = preview.unread_textures().first().cloned();
            }
            Err(e) => {
                self.error = Some(e.to_string());
                self.loaded = None;
            }
        }
    }
}

/// Brings the preview from the scene `before` to `after` the cheapest way: objects moved are
/// placed anew (nothing rebuilt), a changed room without changed objects rebuilds the room only,
/// and anything else loads the whole scene.
fn update(
    preview: &mut Preview,
    before: Option<&Scene>,
    after: &Scene,
    base: Option<&std::path::Path>,
) -> Result<(), orbifold_preview::PreviewError> {
    let Some(before) = before else {
        return preview.load(after, base);
    };
    let unplaced = |s: &Scene| {
        let mut s = s.clone();
        s.objects.iter_mut().for_each(|o| {
            o.at = [0.0; 2];
            o.height = 0.0;
            o.yaw = 0.0;
        });
        // What the preview does not draw.
        s.lights.clear();
        s.camera = Camera::default();
        s.render = Default::default();
        s.preview = Default::default();
        s
    };
    let (a, b) = (unplaced(before), unplaced(after));
    if a == b {
        for i in 0..after.objects.len() {
            if before.objects[i] != after.objects[i] {
                preview.set_object_placement(i, &after.object_placement(i))?;
            }
        }
        return Ok(());
    }
    // Objects are embedded in their plane: a new geometry needs them embedded again.
    let geometry = |s: &Scene| s.layout().map(|l| l.space().kappa()).ok();
    let room_only = before.objects == after.objects && geometry(before) == geometry(after);
    if room_only {
        preview.set_room(after)
    } else {
        preview.load(after, base)
    }
}

/// Moves a camera `distance` along the geodesic it looks along (horizontally), keeping its
/// bearing relative to the geodesic (parallel transport).
///
/// ```
/// use orbifold::{Geometry, space::Space};
/// use orbifold_scene::Camera;
/// let mut camera = Camera { at: [0.0, 0.0], yaw: 0.0, ..Camera::default() };
/// orbifold_studio::view3d::walk(Space::new(Geometry::Hyperbolic), &mut camera, 0.5);
/// // Half a unit along the real axis of the Poincaré disk: tanh(0.25).
/// assert!((camera.at[0] - 0.25f64.tanh()).abs() < 1e-9 && camera.at[1].abs() < 1e-12);
/// assert!(camera.yaw.abs() < 1e-6);
/// ```
pub fn walk(space: Space, camera: &mut Camera, distance: f64) {
    let z = Complex64::new(camera.at[0], camera.at[1]);
    let p = space.to_ambient(z);
    let v = space.model_tangent(z, Complex64::from_polar(1.0, camera.yaw.to_radians()));
    let q = space.exp(p, v * distance);
    let ahead = space.exp(p, v * (distance + 1e-6));
    let z2 = space.to_model(q);
    let direction = space.direction(z2, space.to_model(ahead));
    camera.at = [z2.re, z2.im];
    camera.yaw = direction.arg().to_degrees();
}

/// [`walk`], and through a portal when the step crosses one: a camera that leaves the room
/// across a wall the orbifold's group pairs with another comes back in through the partner wall,
/// its heading moved by the pairing ([`Layout::carried_inside`]); through a glide it comes out
/// mirrored (left and right swapped), so that the view goes on without a jump.
///
/// ```
/// use orbifold::{Layout, LayoutOptions};
/// use orbifold_scene::Camera;
/// let layout = Layout::of_symbol(&"632".parse()?, &LayoutOptions::default())?;
/// let mut camera = Camera { at: [0.0, 0.0], yaw: 10.0, ..Camera::default() };
/// for _ in 0..100 {
///     orbifold_studio::view3d::walk_through_portals(&layout, &mut camera, 0.05);
/// }
/// // Five units walked, and still in the room.
/// let p = layout.space().to_ambient(num_complex::Complex64::new(camera.at[0], camera.at[1]));
/// assert!(layout.edges.iter().all(|e| e.wall.dot(p) > -1e-9));
/// // 632 has no glides: the view is never mirrored.
/// assert!(!camera.mirrored);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn walk_through_portals(layout: &Layout, camera: &mut Camera, distance: f64) {
    let space = layout.space();
    walk(space, camera, distance);
    let z = Complex64::new(camera.at[0], camera.at[1]);
    let p = space.to_ambient(z);
    let v = space.model_tangent(z, Complex64::from_polar(1.0, camera.yaw.to_radians()));
    let (q, u, glided) = layout.carried_inside(p, v, 1e-12);
    if q == p {
        return;
    }
    camera.mirrored ^= glided;
    let z2 = space.to_model(q);
    let ahead = space.to_model(space.exp(q, u * 1e-6));
    camera.at = [z2.re, z2.im];
    camera.yaw = space.direction(z2, ahead).arg().to_degrees();
}

/// The attenuation's name in the menu.
pub fn attenuation_name(a: Attenuation) -> &'static str {
    match a {
        Attenuation::Reflectance => "reflectance",
        Attenuation::Orbifold => "orbifold",
        Attenuation::Translations => "translations",
        Attenuation::Universal => "universal cover",
    }
}
