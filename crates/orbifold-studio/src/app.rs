//! The studio's window: menus and shortcuts, the design and layout panel on the left, the room
//! on the right, and in the middle the 3D preview, the tiling of the cover and the renderer.

use std::path::PathBuf;

use egui::{Color32, Key, KeyboardShortcut, Modifiers, Ui};
use orbifold_scene::Scene;

use crate::dialogs::{FileDialogs, Request, relative_to};
use crate::document::{self, Document};
use crate::examples_browser::{Example, ExamplesBrowser};
use crate::listen_panel::ListenPanel;
use crate::render_job::{RenderJob, default_output};
use crate::room_panel::{Pick, Target};
use crate::view3d::View3d;
use crate::{design, drop, layout_view, room_panel};

/// What the middle of the window shows.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Tab {
    /// The real-time preview.
    View,
    /// The tiling of the universal cover.
    Tiling,
    /// The photo-realistic renderer.
    Render,
    /// The room's echoes: a clap at the camera, heard.
    Listen,
}

/// The studio's own file dialog, where a path is typed in: used when no [`FileDialogs`] are
/// given (tests that drive the typed dialog; the desktop and the web give theirs).
#[derive(Clone, Debug, PartialEq, Eq)]
enum Dialog {
    Open(String),
    SaveAs(String),
    SavePicture(String),
    PickMesh(String),
    PickTexture(Target, String),
}

/// The studio application.
pub struct Studio {
    /// The open document.
    pub document: Document,
    /// The 3D view.
    pub view: View3d,
    /// The tab shown in the middle.
    pub tab: Tab,
    /// The last message for the status line.
    pub status: String,
    dialog: Option<Dialog>,
    data: Option<PathBuf>,
    recent: Vec<PathBuf>,
    /// Unsaved work found from a session that crashed, offered to restore.
    pub recovered: Option<Scene>,
    recovery_written: u64,
    render: Option<RenderJob>,
    render_texture: Option<egui::TextureHandle>,
    render_size: (u32, u32),
    /// Whether the render takes the 3D view's shape (its height follows from the width).
    render_as_view: bool,
    render_samples: u32,
    tiling: Option<(u64, egui::TextureHandle)>,
    /// Set by the binary's `--screenshot`: frames left before the screenshot is taken.
    pub screenshot: Option<(PathBuf, u32)>,
    /// The listen tab (its audio output can be replaced, for tests).
    pub listen: ListenPanel,
    /// The file dialogs: the system's in the desktop binary, scripted ones in tests; `None`
    /// uses the studio's own window where a path is typed.
    pub dialogs: Option<Box<dyn FileDialogs>>,
    /// A dialog asked for in this frame, shown after it (with the surface an image is for).
    pending: Option<(Request, Option<Target>)>,
    /// The last dialog that gave no answer at once, which may answer later ([`Studio::answer`]).
    awaiting: Option<(Request, Option<Target>)>,
    /// The examples browser.
    pub examples: ExamplesBrowser,
}

impl Studio {
    /// The size (width, height) in pixels that the next render will have: with "frame as the
    /// 3D view" on, its height follows from its width and the 3D view's shape.
    pub fn render_size(&self) -> (u32, u32) {
        self.render_size
    }

    /// Sets the width in pixels of the next render (its height too when it is not framed as
    /// the 3D view). The web studio starts smaller: its renders run on one thread.
    pub fn set_render_size(&mut self, size: (u32, u32)) {
        self.render_size = size;
    }

    /// The last picture rendered so far (width, height, RGBA8 as shown), if a render has
    /// shown one.
    pub fn rendered_picture(&self) -> Option<(u32, u32, Vec<u8>)> {
        self.render.as_ref()?.picture()
    }

    /// A studio on a document. `data` is the studio's own folder (recent files, recovery);
    /// `None` keeps nothing (tests).
    pub fn new(document: Document, data: Option<PathBuf>) -> Studio {
        let recent = data
            .as_deref()
            .map(document::recent_files)
            .unwrap_or_default();
        let view = View3d::new(document.scene());
        Studio {
            document,
            view,
            tab: Tab::View,
            status: String::new(),
            dialog: None,
            data,
            recent,
            recovered: None,
            recovery_written: 0,
            render: None,
            render_texture: None,
            render_size: (480, 360),
            render_as_view: true,
            render_samples: 32,
            tiling: None,
            screenshot: None,
            listen: ListenPanel::default(),
            dialogs: None,
            pending: None,
            awaiting: None,
            examples: ExamplesBrowser::default(),
        }
    }

    /// Opens a scene file in place of the document.
    pub fn open(&mut self, path: &std::path::Path) {
        let recovery = self.recovery_path();
        match Document::open(path, recovery) {
            Ok(document) => {
                self.document.remove_recovery();
                self.document = document;
                self.view.reset(self.document.scene());
                self.status = format!("opened {}", path.display());
                self.remember(path);
            }
            Err(e) => self.status = format!("cannot open {}: {e}", path.display()),
        }
    }

    /// Saves to `path` and makes it the document's file.
    pub fn save_as(&mut self, path: &std::path::Path) {
        match self.document.save_as(path) {
            Ok(()) => {
                self.status = format!("saved {}", path.display());
                self.remember(path);
            }
            Err(e) => self.status = e,
        }
    }

    fn remember(&mut self, path: &std::path::Path) {
        if let Some(data) = &self.data {
            let _ = document::remember(data, path);
            self.recent = document::recent_files(data);
        }
    }

    fn recovery_path(&self) -> Option<PathBuf> {
        self.data.as_ref().map(|d| d.join("recovery.toml"))
    }

    /// The whole window.
    pub fn ui(&mut self, ui: &mut Ui) {
        // A drag (of a value, an object, the polygon) or typing in a field is one undo step.
        let dragging = ui.input(|i| i.pointer.any_down());
        let typing = ui.ctx().egui_wants_keyboard_input();
        self.document.set_gesture(dragging || typing);
        self.shortcuts(ui);
        egui::Panel::top("menu").show(ui, |ui| self.menu(ui));
        egui::Panel::bottom("status").show(ui, |ui| self.status_line(ui));
        egui::Panel::left("design")
            .default_size(300.0)
            .resizable(true)
            .show(ui, |ui| {
                egui::ScrollArea::vertical().show(ui, |ui| self.design(ui));
            });
        egui::Panel::right("room")
            .default_size(330.0)
            .resizable(true)
            .show(ui, |ui| {
                egui::ScrollArea::vertical().show(ui, |ui| {
                    if let Some(next) = room_panel::show(ui, self.document.scene()) {
                        self.document.replace(next);
                    }
                });
            });
        egui::CentralPanel::default().show(ui, |ui| self.middle(ui));
        match room_panel::take_pick(ui.ctx()) {
            Some(Pick::Mesh) => self.ask(Request::PickMesh, None),
            Some(Pick::Texture(target)) => self.ask(Request::PickTexture, Some(target)),
            None => {}
        }
        if let Some(example) = self.examples.show(ui.ctx()) {
            self.open_example(example);
        }
        self.dropped_files(ui);
        self.dialog(ui);
        self.recovery(ui);
        self.take_screenshot(ui);
        self.answer_pending();
    }

    /// Asks for a file: through [`Studio::dialogs`] after this frame, or in the studio's own
    /// window. `target` is the surface an image is for.
    fn ask(&mut self, request: Request, target: Option<Target>) {
        if self.dialogs.is_some() {
            self.pending = Some((request, target));
            return;
        }
        let suggested = self.suggested(request).display().to_string();
        self.dialog = Some(match request {
            Request::OpenScene => Dialog::Open(String::new()),
            Request::SaveScene => Dialog::SaveAs(suggested),
            Request::SavePicture => Dialog::SavePicture(suggested),
            Request::PickMesh => Dialog::PickMesh(String::new()),
            Request::PickTexture => Dialog::PickTexture(target.unwrap_or_default(), String::new()),
        });
    }

    /// The name a save dialog starts with: the document's file (or `room.toml`), or a picture
    /// next to it.
    fn suggested(&self, request: Request) -> PathBuf {
        match request {
            Request::SavePicture => default_output(self.document.path()),
            _ => self
                .document
                .path()
                .map_or_else(|| PathBuf::from("room.toml"), std::path::Path::to_path_buf),
        }
    }

    /// Shows the dialog asked for in the frame just drawn (between frames, so a dialog that
    /// blocks never interrupts a panel) and does what the chosen file is for.
    fn answer_pending(&mut self) {
        let Some((request, target)) = self.pending.take() else {
            return;
        };
        let suggested = self.suggested(request);
        let Some(dialogs) = &mut self.dialogs else {
            return;
        };
        match dialogs.ask(request, &suggested) {
            Some(path) => self.chosen(request, target, &path),
            None => self.awaiting = Some((request, target)),
        }
    }

    /// A file chosen for the last dialog that did not answer at once (the browser's file
    /// picker hands its file over later): does what `request` asked it for, with the surface an
    /// image was asked for. Returns `false`, doing nothing, when that dialog asked for
    /// something else or nothing is awaited.
    ///
    /// ```
    /// use std::path::{Path, PathBuf};
    /// use orbifold_studio::Studio;
    /// use orbifold_studio::dialogs::Request;
    /// use orbifold_studio::document::Document;
    /// let mut studio = Studio::new(Document::new(None), None);
    /// // No dialog asked: nothing happens.
    /// assert!(!studio.answer(Request::PickMesh, Path::new("bunny.obj")));
    /// assert_eq!(studio.document.scene().objects.len(), 1);
    /// ```
    pub fn answer(&mut self, request: Request, path: &std::path::Path) -> bool {
        match self.awaiting {
            Some((asked, target)) if asked == request => {
                self.awaiting = None;
                self.chosen(request, target, path);
                true
            }
            _ => false,
        }
    }

    /// Does what a chosen file is for.
    fn chosen(&mut self, request: Request, target: Option<Target>, path: &std::path::Path) {
        match request {
            Request::OpenScene => self.open(path),
            Request::SaveScene => self.save_as(path),
            Request::SavePicture => self.save_picture(path),
            Request::PickMesh => self.add_mesh(path),
            Request::PickTexture => self.put_texture(target.unwrap_or_default(), path),
        }
    }

    /// Writes the render tab's picture: PNG or JPEG as shown, EXR for the HDR image.
    pub fn save_picture(&mut self, path: &std::path::Path) {
        self.status = match &self.render {
            Some(job) => match job.save(path) {
                Ok(()) => format!("wrote {}", path.display()),
                Err(e) => format!("cannot write {}: {e}", path.display()),
            },
            None => "nothing rendered yet: render in the render tab first".into(),
        };
    }

    /// Adds an object made from the mesh file at `path`, at the room's centre.
    pub fn add_mesh(&mut self, path: &std::path::Path) {
        let name = relative_to(path, self.document.base());
        self.document.edit(|scene| {
            let object = room_panel::mesh_object(scene, name.clone());
            scene.objects.push(object);
        });
        self.status = format!("added {} as an object", path.display());
    }

    /// Puts the image at `path` on `target` (the floor, the ceiling, the walls or an object).
    pub fn put_texture(&mut self, target: Target, path: &std::path::Path) {
        let name = relative_to(path, self.document.base());
        let mut found = false;
        self.document
            .edit(|scene| found = room_panel::apply_texture(scene, target, name.clone()));
        self.status = if found {
            format!("the {} shows {}", target.name(), path.display())
        } else {
            format!("there is no {} to put {} on", target.name(), path.display())
        };
    }

    /// Opens an example as a new untitled document: saving asks where, so the example stays.
    pub fn open_example(&mut self, example: Example) {
        match example.scene() {
            Ok(scene) => {
                self.document.remove_recovery();
                self.document = Document::with_scene(scene, None, self.recovery_path());
                self.view.reset(self.document.scene());
                self.status = format!(
                    "opened the example {} as a new scene: Save asks where to keep it",
                    example.name
                );
            }
            Err(e) => self.status = format!("cannot open the example {}: {e}", example.name),
        }
    }

    /// Files dropped on the window: scenes open, meshes become objects, images go on the
    /// surface the room panel names. While files hover over the window, says what they do.
    fn dropped_files(&mut self, ui: &Ui) {
        let hovering = ui.input(|i| !i.raw.hovered_files.is_empty());
        if hovering {
            let target = room_panel::texture_target(ui.ctx());
            let screen = ui.ctx().content_rect();
            let painter = ui.ctx().layer_painter(egui::LayerId::new(
                egui::Order::Foreground,
                egui::Id::unique("drop"),
            ));
            painter.rect_filled(screen, 0.0, Color32::from_black_alpha(160));
            painter.text(
                screen.center(),
                egui::Align2::CENTER_CENTER,
                format!(
                    "drop a scene to open it, a mesh to add it, an image to put it on the {}",
                    target.name()
                ),
                egui::FontId::proportional(20.0),
                Color32::WHITE,
            );
        }
        for dropped in drop::dropped(ui.ctx()) {
            match dropped {
                drop::Dropped::Scene(path) => self.open(&path),
                drop::Dropped::Mesh(path) => self.add_mesh(&path),
                drop::Dropped::Texture(path) => {
                    self.put_texture(room_panel::texture_target(ui.ctx()), &path);
                }
                drop::Dropped::Refused(message) => self.status = message,
            }
        }
    }

    fn shortcuts(&mut self, ui: &Ui) {
        let command = |key| KeyboardShortcut::new(Modifiers::COMMAND, key);
        let shift = |key| KeyboardShortcut::new(Modifiers::COMMAND | Modifiers::SHIFT, key);
        let (redo, redo_y, undo, save, open, new) = ui.input_mut(|i| {
            (
                i.consume_shortcut(&shift(Key::Z)),
                i.consume_shortcut(&command(Key::Y)),
                i.consume_shortcut(&command(Key::Z)),
                i.consume_shortcut(&command(Key::S)),
                i.consume_shortcut(&command(Key::O)),
                i.consume_shortcut(&command(Key::N)),
            )
        });
        if redo || redo_y {
            self.document.redo();
        } else if undo {
            self.document.undo();
        }
        if save {
            self.save();
        }
        if open {
            self.ask(Request::OpenScene, None);
        }
        if new {
            self.new_document();
        }
    }

    fn new_document(&mut self) {
        self.document.remove_recovery();
        self.document = Document::new(self.recovery_path());
        self.view.reset(self.document.scene());
        self.status = "new document: the seed's *22222 room".into();
    }

    fn save(&mut self) {
        let handed_over = self.dialogs.as_ref().is_some_and(|d| d.hands_files_over());
        match self.document.path().map(std::path::Path::to_path_buf) {
            Some(path) if !handed_over => self.save_as(&path),
            _ => self.ask(Request::SaveScene, None),
        }
    }

    fn menu(&mut self, ui: &mut Ui) {
        ui.horizontal(|ui| {
            ui.menu_button("File", |ui| {
                if ui.button("New").clicked() {
                    self.new_document();
                }
                if ui.button("Open…").clicked() {
                    self.ask(Request::OpenScene, None);
                }
                if ui.button("Examples…").clicked() {
                    self.examples.open = true;
                }
                if ui.button("Save").clicked() {
                    self.save();
                }
                if ui.button("Save As…").clicked() {
                    self.ask(Request::SaveScene, None);
                }
                ui.separator();
                ui.label("Recent");
                for path in self.recent.clone() {
                    if ui.button(path.display().to_string()).clicked() {
                        self.open(&path);
                    }
                }
            });
            ui.menu_button("Edit", |ui| self.undo_redo(ui, ["Undo", "Redo"]));
            self.undo_redo(ui, ["undo", "redo"]);
            ui.separator();
            ui.label(self.document.title());
        });
    }

    /// Undo and redo buttons with these names, enabled when there is something to undo or redo.
    fn undo_redo(&mut self, ui: &mut Ui, names: [&str; 2]) {
        if ui
            .add_enabled(self.document.can_undo(), egui::Button::new(names[0]))
            .clicked()
        {
            self.document.undo();
        }
        if ui
            .add_enabled(self.document.can_redo(), egui::Button::new(names[1]))
            .clicked()
        {
            self.document.redo();
        }
    }

    fn design(&mut self, ui: &mut Ui) {
        let signature = self.document.scene().orbifold.signature.clone();
        if let Some(next) = design::show(ui, &signature) {
            self.document.edit(|scene| {
                scene.orbifold.signature = next;
                // New walls: the old free parameters and per-wall settings no longer fit.
                scene.orbifold.parameters.clear();
                scene.walls.clear();
                // The incircle shape is a polygon of mirrors' only.
                let kaleidoscopic = scene
                    .orbifold
                    .signature
                    .parse::<orbifold::OrbifoldSymbol>()
                    .is_ok_and(|s| s.as_kaleidoscopic().is_some());
                if !kaleidoscopic {
                    scene.orbifold.shape = orbifold_scene::ShapeName::Default;
                }
                if let Ok(layout) = scene.layout() {
                    let c = layout.centre;
                    scene.objects.iter_mut().for_each(|o| o.at = [c.re, c.im]);
                    scene.lights.iter_mut().for_each(|l| l.at = [c.re, c.im]);
                }
            });
            self.view.camera = camera_for(self.document.scene());
        }
        ui.separator();
        if let Some(next) = layout_view::show(ui, self.document.scene()) {
            self.document.replace(next);
        }
    }

    fn middle(&mut self, ui: &mut Ui) {
        self.listen.collect(ui.ctx());
        // In the browser the render takes its rounds here, between frames, whichever tab is
        // shown (on the desktop it has its own thread and this does nothing).
        if let Some(job) = &mut self.render
            && !job.is_done()
        {
            job.step();
            if cfg!(target_arch = "wasm32") {
                ui.ctx().request_repaint();
            }
        }
        ui.horizontal(|ui| {
            ui.selectable_value(&mut self.tab, Tab::View, "3D view");
            ui.selectable_value(&mut self.tab, Tab::Tiling, "tiling");
            ui.selectable_value(&mut self.tab, Tab::Render, "render");
            ui.selectable_value(&mut self.tab, Tab::Listen, "listen");
            if self.tab == Tab::View && ui.button("Use this view").clicked() {
                let camera = self.view.camera.clone();
                self.document.edit(|scene| scene.camera = camera);
            }
        });
        match self.tab {
            Tab::View => {
                let base = self.document.base().map(std::path::Path::to_path_buf);
                let revision = self.document.revision();
                self.view
                    .show(ui, self.document.scene(), base.as_deref(), revision);
            }
            Tab::Tiling => self.tiling(ui),
            Tab::Render => self.render(ui),
            Tab::Listen => self.listen.show(
                ui,
                self.document.scene(),
                self.document.base(),
                &self.view.camera,
            ),
        }
    }

    fn tiling(&mut self, ui: &mut Ui) {
        let revision = self.document.revision();
        if self.tiling.as_ref().is_none_or(|(r, _)| *r != revision) {
            match self.document.scene().layout() {
                Ok(layout) => {
                    let size = 512;
                    let view = orbifold_picture::tiling::View {
                        coloring: orbifold_picture::tiling::Coloring::Wall,
                        ..orbifold_picture::tiling::View::new(layout.space().geometry(), size)
                    };
                    match orbifold_picture::tiling::render(&layout, &view, None) {
                        Ok(picture) => {
                            let image = egui::ColorImage::from_rgba_unmultiplied(
                                [picture.size as usize; 2],
                                &picture.rgba,
                            );
                            let texture = ui.ctx().load_texture(
                                "tiling",
                                image,
                                egui::TextureOptions::LINEAR,
                            );
                            self.tiling = Some((revision, texture));
                        }
                        Err(e) => self.status = e,
                    }
                }
                Err(e) => self.status = e,
            }
        }
        if let Some((_, texture)) = &self.tiling {
            let side = ui.available_width().min(ui.available_height());
            ui.image((texture.id(), egui::vec2(side, side)));
        }
    }

    fn render(&mut self, ui: &mut Ui) {
        ui.horizontal(|ui| {
            design::labelled_value(ui, "render width", &mut self.render_size.0, 16..=4096, 1.0);
            // The same framing as the 3D view: both cameras' field of view is vertical, so the
            // picture shows what the view shows when it has the view's shape.
            ui.checkbox(&mut self.render_as_view, "frame as the 3D view");
            match self.view.drawn_size().filter(|_| self.render_as_view) {
                Some([w, h]) => {
                    let height = f64::from(self.render_size.0) * h as f64 / w.max(1) as f64;
                    self.render_size.1 = (height.round() as u32).clamp(16, 4096);
                    ui.label(format!("render height {}", self.render_size.1));
                }
                None => {
                    design::labelled_value(
                        ui,
                        "render height",
                        &mut self.render_size.1,
                        16..=4096,
                        1.0,
                    );
                }
            }
            design::labelled_value(
                ui,
                "render samples",
                &mut self.render_samples,
                1..=4096,
                1.0,
            );
            let running = self.render.as_ref().is_some_and(|r| !r.is_done());
            if !running && ui.button("Render").clicked() {
                // What the 3D view shows: with its straight rays on, the render's rays too.
                let mut scene = self.document.scene().clone();
                scene.render.straight_rays |= self.view.straight;
                self.render = Some(RenderJob::start(
                    &scene,
                    self.document.base(),
                    &self.view.camera,
                    self.render_size,
                    self.render_samples,
                ));
                self.render_texture = None;
            }
            if running
                && ui.button("Cancel").clicked()
                && let Some(job) = &self.render
            {
                job.cancel();
            }
            if self.render.is_some() && ui.button("Save picture…").clicked() {
                self.ask(Request::SavePicture, None);
            }
        });
        let Some(job) = &self.render else {
            ui.label("Renders the 3D view's camera along the true geodesics, with light through the mirrors (straight rays when the 3D view or the scene's render settings ask for them).");
            return;
        };
        if let Some(e) = job.error() {
            ui.colored_label(Color32::LIGHT_RED, e);
        }
        let passes = job.passes();
        ui.add(
            egui::ProgressBar::new(passes as f32 / job.samples as f32)
                .text(format!("{passes} / {} samples a pixel", job.samples)),
        );
        if !job.is_done() {
            ui.ctx()
                .request_repaint_after(std::time::Duration::from_millis(200));
        }
        if let Some((w, h, rgba)) = job.picture() {
            let image = egui::ColorImage::from_rgba_unmultiplied([w as usize, h as usize], &rgba);
            match &mut self.render_texture {
                Some(t) => t.set(image, egui::TextureOptions::LINEAR),
                None => {
                    self.render_texture = Some(ui.ctx().load_texture(
                        "render",
                        image,
                        egui::TextureOptions::LINEAR,
                    ));
                }
            }
        }
        if let Some(texture) = &self.render_texture {
            let available = ui.available_size();
            let (w, h) = (job.size.0 as f32, job.size.1 as f32);
            let scale = (available.x / w).min(available.y / h).min(2.0);
            ui.image((texture.id(), egui::vec2(w * scale, h * scale)));
        }
    }

    fn status_line(&mut self, ui: &mut Ui) {
        ui.horizontal(|ui| {
            if let Some(stats) = self.view.stats {
                ui.label(format!(
                    "{} copies, {} drawn, {:.1} M triangles",
                    stats.copies,
                    stats.instances,
                    stats.triangles as f64 / 1e6
                ));
                ui.separator();
            }
            if let Some(e) = &self.view.error {
                ui.colored_label(Color32::LIGHT_RED, e);
                ui.separator();
            }
            ui.label(&self.status);
        });
        if self.document.revision() != self.recovery_written {
            self.recovery_written = self.document.revision();
            if let Err(e) = self.document.write_recovery() {
                self.status = format!("cannot keep a recovery copy: {e}");
            }
        }
    }

    fn dialog(&mut self, ui: &mut Ui) {
        let Some(dialog) = self.dialog.clone() else {
            return;
        };
        let (title, action, mut text) = match &dialog {
            Dialog::Open(t) => ("Open a scene", "Open", t.clone()),
            Dialog::SaveAs(t) => ("Save the scene as", "Save", t.clone()),
            Dialog::SavePicture(t) => ("Save the picture as", "Save picture", t.clone()),
            Dialog::PickMesh(t) => ("Add a mesh", "Add mesh", t.clone()),
            Dialog::PickTexture(_, t) => ("Pick an image", "Use image", t.clone()),
        };
        let mut close = false;
        let mut confirm = false;
        egui::Window::new(title)
            .collapsible(false)
            .show(ui.ctx(), |ui| {
                let label = ui.label("file");
                let edit = ui
                    .add(egui::TextEdit::singleline(&mut text).desired_width(360.0))
                    .labelled_by(label.id);
                if edit.lost_focus() && ui.input(|i| i.key_pressed(Key::Enter)) {
                    confirm = true;
                }
                ui.horizontal(|ui| {
                    confirm |= ui.button(action).clicked();
                    close |= ui.button("Cancel").clicked();
                });
            });
        self.dialog = Some(match &dialog {
            Dialog::Open(_) => Dialog::Open(text.clone()),
            Dialog::SaveAs(_) => Dialog::SaveAs(text.clone()),
            Dialog::SavePicture(_) => Dialog::SavePicture(text.clone()),
            Dialog::PickMesh(_) => Dialog::PickMesh(text.clone()),
            Dialog::PickTexture(target, _) => Dialog::PickTexture(*target, text.clone()),
        });
        if confirm {
            let path = PathBuf::from(text.trim());
            let (request, target) = match dialog {
                Dialog::Open(_) => (Request::OpenScene, None),
                Dialog::SaveAs(_) => (Request::SaveScene, None),
                Dialog::SavePicture(_) => (Request::SavePicture, None),
                Dialog::PickMesh(_) => (Request::PickMesh, None),
                Dialog::PickTexture(target, _) => (Request::PickTexture, Some(target)),
            };
            self.chosen(request, target, &path);
            close = true;
        }
        if close {
            self.dialog = None;
        }
    }

    fn recovery(&mut self, ui: &mut Ui) {
        let Some(scene) = self.recovered.clone() else {
            return;
        };
        egui::Window::new("Unsaved work")
            .collapsible(false)
            .show(ui.ctx(), |ui| {
                ui.label("The studio did not close cleanly last time. Restore the unsaved work?");
                ui.horizontal(|ui| {
                    if ui.button("Restore").clicked() {
                        self.document.replace(scene);
                        self.view.reset(self.document.scene());
                        self.recovered = None;
                        self.status = "restored the unsaved work".into();
                    }
                    if ui.button("Discard").clicked() {
                        self.document.remove_recovery();
                        self.recovered = None;
                    }
                });
            });
    }

    /// Counts frames down, then asks for a screenshot; the callback writes it and closes the
    /// window.
    fn take_screenshot(&mut self, ui: &Ui) {
        let Some((path, frames)) = self.screenshot.take() else {
            return;
        };
        ui.ctx().request_repaint();
        if frames > 0 {
            self.screenshot = Some((path, frames - 1));
            return;
        }
        let ctx = ui.ctx().clone();
        ui.ctx().request_screenshot(move |image| {
            let [w, h] = image.size;
            let bytes: Vec<u8> = image.pixels.iter().flat_map(|c| c.to_array()).collect();
            let saved = image::RgbaImage::from_raw(w as u32, h as u32, bytes)
                .ok_or_else(|| "the screenshot has the wrong size".to_string())
                .and_then(|img| img.save(&path).map_err(|e| e.to_string()));
            match saved {
                Ok(()) => eprintln!("wrote {}", path.display()),
                Err(e) => eprintln!("error: cannot write {}: {e}", path.display()),
            }
            ctx.send_viewport_cmd(egui::ViewportCommand::Close);
            ctx.request_repaint();
        });
    }
}

impl eframe::App for Studio {
    fn ui(&mut self, ui: &mut Ui, _frame: &mut eframe::Frame) {
        Studio::ui(self, ui);
    }

    fn on_exit(&mut self) {
        // A clean exit: unsaved work is the user's choice, not a crash to recover from.
        self.document.remove_recovery();
    }
}

/// A camera for a scene's room: part of the way from the centre towards the first corner,
/// looking back at the centre a little from above.
pub fn camera_for(scene: &Scene) -> orbifold_scene::Camera {
    let mut camera = scene.camera.clone();
    if let Ok(layout) = scene.layout() {
        let c = layout.centre;
        let corner = layout.vertices.first().map_or(c + 0.3, |v| {
            if v.ideal {
                c + (v.position - c) * 0.5
            } else {
                v.position
            }
        });
        let eye = c + (corner - c) * 0.6;
        camera.at = [eye.re, eye.im];
        camera.yaw = layout.space().direction(eye, c).arg().to_degrees();
        camera.pitch = -15.0;
        camera.height = 0.5 * scene.room.height;
    }
    camera
}
