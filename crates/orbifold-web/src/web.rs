//! The page: starts the studio on the canvas `#studio`, and connects it to the browser's file
//! input (`#open-scene`), downloads, dropped files and `localStorage`.
//!
//! The studio's File menu, its shortcuts and the room panel's "pick" buttons ask through
//! [`WebDialogs`], the browser's side of [`FileDialogs`]: a question for a file opens the
//! browser's file picker, whose answer comes later, through the inbox, to
//! [`Studio::answer`]; a save is a download, made after the frame.

use std::cell::{Cell, RefCell};
use std::collections::BTreeSet;
use std::path::{Path, PathBuf};
use std::rc::Rc;
use std::sync::Arc;

use eframe::egui_wgpu::{WgpuConfiguration, WgpuSetup, WgpuSetupCreateNew};
use eframe::wgpu;
use egui::Ui;
use orbifold_studio::Studio;
use orbifold_studio::dialogs::{FileDialogs, Request};
use orbifold_studio::document::Document;
use orbifold_studio::room_panel;
use wasm_bindgen::JsCast;
use wasm_bindgen::prelude::*;

use crate::files::{self, FILE_KEY_PREFIX, Kind, RECOVERY_KEY};

/// A file the page was given (picked or dropped): its name, its bytes, and what the studio's
/// dialog had asked for when the picker that chose it was opened by one.
struct Given {
    name: String,
    bytes: Vec<u8>,
    asked: Option<Request>,
}

/// Files the page has read and the next frame takes.
type Inbox = Rc<RefCell<Vec<Given>>>;

/// What the file picker was last opened for by the studio's dialogs (`None`: the bar's button).
type Asking = Rc<Cell<Option<Request>>>;

/// A save the studio's dialogs asked for, handed to the browser as a download after the frame.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Download {
    Scene,
    Picture,
}

type Downloads = Rc<RefCell<Vec<Download>>>;

/// The studio's file dialogs in the browser: questions for a file open the browser's file
/// picker (for the kinds asked for) and answer later; saves become downloads.
struct WebDialogs {
    asking: Asking,
    downloads: Downloads,
}

impl FileDialogs for WebDialogs {
    fn open_scene(&mut self) -> Option<PathBuf> {
        pick_file(&self.asking, Some(Request::OpenScene));
        None
    }

    fn save_scene(&mut self, _suggested: &Path) -> Option<PathBuf> {
        self.downloads.borrow_mut().push(Download::Scene);
        None
    }

    fn save_picture(&mut self, _suggested: &Path) -> Option<PathBuf> {
        self.downloads.borrow_mut().push(Download::Picture);
        None
    }

    fn pick_mesh(&mut self) -> Option<PathBuf> {
        pick_file(&self.asking, Some(Request::PickMesh));
        None
    }

    fn pick_texture(&mut self) -> Option<PathBuf> {
        pick_file(&self.asking, Some(Request::PickTexture));
        None
    }

    fn hands_files_over(&self) -> bool {
        true
    }
}

/// Starts the studio when the module is loaded.
#[wasm_bindgen(start)]
pub fn start() {
    wasm_bindgen_futures::spawn_local(async {
        if let Err(e) = run().await {
            let message = format!("the studio could not start: {e:?}");
            web_sys::console::error_1(&message.clone().into());
            show_failure(&message);
        }
    });
}

async fn run() -> Result<(), JsValue> {
    // A page has no system fonts: the text of the pictures rendered from SVG (the echogram's
    // axes and legend) is drawn with egui's own sans-serif font.
    orbifold_picture::svg::add_font(epaint_default_fonts::UBUNTU_LIGHT.to_vec());
    let document = web_sys::window()
        .and_then(|w| w.document())
        .ok_or("no document")?;
    let canvas: web_sys::HtmlCanvasElement = document
        .get_element_by_id("studio")
        .ok_or("no canvas #studio")?
        .dyn_into()?;
    let options = eframe::WebOptions {
        wgpu_options: WgpuConfiguration {
            wgpu_setup: WgpuSetup::CreateNew(WgpuSetupCreateNew {
                // Everything the adapter can, as the desktop preview asks for: the preview's
                // table of parts is a 24 KiB uniform buffer, over WebGL2's guaranteed 16 KiB
                // that eframe asks for by default (browsers give 64 KiB).
                device_descriptor: Arc::new(|adapter| wgpu::DeviceDescriptor {
                    label: Some("orbifold web studio"),
                    required_limits: adapter.limits(),
                    ..Default::default()
                }),
                ..WgpuSetupCreateNew::without_display_handle()
            }),
            ..Default::default()
        },
        ..Default::default()
    };
    eframe::WebRunner::new()
        .start(
            canvas,
            options,
            Box::new(|cc| Ok(Box::new(WebStudio::new(cc)))),
        )
        .await
}

/// Replaces the loading text with why the studio did not start.
fn show_failure(message: &str) {
    if let Some(status) = web_sys::window()
        .and_then(|w| w.document())
        .and_then(|d| d.get_element_by_id("loading"))
    {
        status.set_text_content(Some(message));
    }
}

/// The studio with the page's files, downloads and storage around it.
struct WebStudio {
    studio: Studio,
    inbox: Inbox,
    asking: Asking,
    downloads: Downloads,
    storage: Option<web_sys::Storage>,
    /// The document revision last kept in `localStorage`.
    kept: u64,
    /// Given files kept in `localStorage` with the unsaved work.
    kept_files: BTreeSet<PathBuf>,
    /// Given files that `localStorage` refused (too large): not tried again.
    unkept_files: BTreeSet<PathBuf>,
    /// Whether a file was given since the unsaved work was last kept.
    files_changed: bool,
    /// The page's title as last set.
    title: String,
}

impl WebStudio {
    fn new(cc: &eframe::CreationContext<'_>) -> WebStudio {
        let mut studio = Studio::new(Document::new(None), None);
        // Half the desktop's width: a round of samples (a sample for every pixel) is taken
        // between two frames on the page's one thread, and a quarter of the pixels keeps the
        // page answering (docs/web.md).
        studio.set_render_size((240, 180));
        if let Some(state) = &cc.wgpu_render_state {
            studio.view.use_window_gpu(state);
        }
        let storage = web_sys::window().and_then(|w| w.local_storage().ok().flatten());
        // The files kept with the unsaved work first: the recovered scene names them.
        let kept_files = storage.as_ref().map(restore_files).unwrap_or_default();
        let recovered = storage
            .as_ref()
            .and_then(|s| s.get_item(RECOVERY_KEY).ok().flatten());
        if let Some(text) = recovered {
            match files::recovered(&text) {
                Ok((scene, missing)) => {
                    if !missing.is_empty() {
                        studio.status = format!(
                            "the unsaved work names files the browser could not keep: {}; \
                             restore it, then drop them on the page again",
                            files::listed(&missing)
                        );
                    }
                    studio.recovered = Some(scene);
                }
                Err(e) => studio.status = format!("cannot read the unsaved work: {e}"),
            }
        }
        let (inbox, asking, downloads) =
            (Inbox::default(), Asking::default(), Downloads::default());
        if let Err(e) = listen_to_file_input(&inbox, &asking, &cc.egui_ctx) {
            studio.status = format!("no file input: {e:?}");
        }
        studio.dialogs = Some(Box::new(WebDialogs {
            asking: asking.clone(),
            downloads: downloads.clone(),
        }));
        hide_loading();
        WebStudio {
            kept: studio.document.revision(),
            studio,
            inbox,
            asking,
            downloads,
            storage,
            kept_files,
            unkept_files: BTreeSet::new(),
            files_changed: false,
            title: String::new(),
        }
    }

    /// Takes a file the page was given: a scene opens; a mesh or an image is given to the
    /// scene's files and becomes an object, or goes onto a surface (the one whose button
    /// asked for it, or the one the room panel names for dropped images), or, when the scene
    /// already names it, is what the scene finds there from now on; a glTF buffer is kept
    /// for the glTF files that name it.
    fn take(&mut self, given: Given, ctx: &egui::Context) {
        let Given { name, bytes, asked } = given;
        let kind = files::kind(&name);
        let request = match kind {
            Kind::Scene => return self.open(&name, &bytes),
            Kind::Other => {
                self.studio.status = files::refusal(&name).unwrap_or_default();
                return;
            }
            Kind::Mesh => Some(Request::PickMesh),
            Kind::Texture => Some(Request::PickTexture),
            Kind::Buffer => None,
        };
        let path = PathBuf::from(&name);
        orbifold_scene::files::provide(&path, bytes);
        self.unkept_files.remove(&path);
        self.files_changed = true;
        let base = self.studio.document.base().map(Path::to_path_buf);
        let named = self.studio.document.scene().named_files().iter().any(|n| {
            base.as_ref()
                .map_or_else(|| PathBuf::from(n), |b| b.join(n))
                == path
        });
        if let Some(request) = request.filter(|r| asked == Some(*r))
            && self.studio.answer(request, &path)
        {
            return;
        }
        if named || kind == Kind::Buffer {
            // The scene (or a glTF file in it) names this file: it is there now.
            self.studio.view.reload();
            self.studio.status = format!("{name} is here: the scene uses it");
        } else if kind == Kind::Mesh {
            self.studio.add_mesh(&path);
        } else {
            self.studio
                .put_texture(room_panel::texture_target(ctx), &path);
        }
    }

    /// Opens a scene file the page was given, or says why it cannot.
    fn open(&mut self, name: &str, bytes: &[u8]) {
        match files::scene(name, bytes) {
            Ok((scene, missing)) => {
                self.studio.document = Document::with_scene(scene, Some(PathBuf::from(name)), None);
                self.studio.view.reset(self.studio.document.scene());
                self.studio.status = if missing.is_empty() {
                    format!("opened {name}")
                } else {
                    format!(
                        "opened {name}; it names files this page has not been given: {} \
                         (drop them on the page)",
                        files::listed(&missing)
                    )
                };
                self.kept = self.studio.document.revision();
                self.forget_recovery();
            }
            Err(e) => self.studio.status = format!("cannot open {e}"),
        }
    }

    fn save(&mut self) {
        let name = self
            .studio
            .document
            .path()
            .and_then(|p| p.file_name())
            .map_or_else(|| "room.toml".into(), |n| n.to_string_lossy().into_owned());
        let text = self.studio.document.scene().to_toml();
        match download(&name, text.as_bytes(), "application/toml") {
            Ok(()) => {
                self.studio.document.mark_saved(PathBuf::from(&name));
                self.kept = self.studio.document.revision();
                self.forget_recovery();
                self.studio.status = format!("saved {name} (a download)");
            }
            Err(e) => self.studio.status = format!("cannot save {name}: {e:?}"),
        }
    }

    fn save_picture(&mut self) {
        let Some((width, height, rgba)) = self.studio.rendered_picture() else {
            self.studio.status = "nothing rendered yet: render in the render tab first".into();
            return;
        };
        let saved = files::png(width, height, rgba).and_then(|png| {
            download("render.png", &png, "image/png").map_err(|e| format!("{e:?}"))
        });
        self.studio.status = match saved {
            Ok(()) => "saved render.png (a download)".into(),
            Err(e) => format!("cannot save render.png: {e}"),
        };
    }

    /// The bar above the studio's menu: what the browser does in place of the File menu's
    /// paths.
    fn bar(&mut self, ui: &mut Ui) {
        ui.horizontal(|ui| {
            ui.label("web studio:");
            if ui.button("Open scene…").clicked() {
                pick_file(&self.asking, None);
            }
            if ui.button("Save scene").clicked() {
                self.save();
            }
            if ui.button("Save picture").clicked() {
                self.save_picture();
            }
            ui.label("(or drop a scene, a mesh or an image on the page)");
        });
    }

    /// Keeps the unsaved work in `localStorage` when the document changed or a file was given:
    /// the scene, and the given files it needs.
    fn keep_recovery(&mut self, offered: bool) {
        // "Discard" in the studio's recovery window changes nothing in the document.
        let discarded =
            offered && self.studio.recovered.is_none() && !self.studio.document.is_dirty();
        if discarded {
            self.forget_recovery();
        }
        let revision = self.studio.document.revision();
        if revision == self.kept && !self.files_changed {
            return;
        }
        self.kept = revision;
        self.files_changed = false;
        if !self.studio.document.is_dirty() {
            self.forget_recovery();
            return;
        }
        let Some(storage) = self.storage.clone() else {
            return;
        };
        let document = &self.studio.document;
        if let Err(e) = storage.set_item(RECOVERY_KEY, &document.scene().to_toml()) {
            self.studio.status = format!("cannot keep a recovery copy: {e:?}");
            return;
        }
        let needed = files::needed(document.scene(), document.base());
        let mut refused = Vec::new();
        for path in &needed {
            if self.kept_files.contains(path) || self.unkept_files.contains(path) {
                continue;
            }
            let Some(bytes) = orbifold_scene::files::provided(path) else {
                continue;
            };
            let key = format!("{FILE_KEY_PREFIX}{}", path.display());
            match storage.set_item(&key, &files::base64(&bytes)) {
                Ok(()) => {
                    self.kept_files.insert(path.clone());
                }
                Err(_) => {
                    // The browser's storage is full (a few MiB an origin).
                    let _ = storage.remove_item(&key);
                    self.unkept_files.insert(path.clone());
                    refused.push(path.clone());
                }
            }
        }
        for path in self.kept_files.clone() {
            if !needed.contains(&path) {
                let _ = storage.remove_item(&format!("{FILE_KEY_PREFIX}{}", path.display()));
                self.kept_files.remove(&path);
            }
        }
        if !refused.is_empty() {
            self.studio.status = format!(
                "the browser's storage cannot keep {} with the unsaved work (too large): after \
                 a reload, drop it on the page again",
                files::listed(&refused)
            );
        }
    }

    /// Names the document in the browser's tab (and for the end-to-end tests, which cannot
    /// read the canvas): "room.toml • — orbifold studio" while it has unsaved changes.
    fn show_title(&mut self) {
        let title = format!("{} — orbifold studio", self.studio.document.title());
        if title != self.title {
            if let Some(document) = web_sys::window().and_then(|w| w.document()) {
                document.set_title(&title);
            }
            self.title = title;
        }
    }

    /// Removes the unsaved work and the files kept with it from `localStorage`.
    fn forget_recovery(&mut self) {
        if let Some(storage) = &self.storage {
            let _ = storage.remove_item(RECOVERY_KEY);
            for key in file_keys(storage) {
                let _ = storage.remove_item(&key);
            }
        }
        self.kept_files.clear();
        self.unkept_files.clear();
    }
}

impl eframe::App for WebStudio {
    fn ui(&mut self, ui: &mut Ui, _frame: &mut eframe::Frame) {
        let given: Vec<_> = self.inbox.borrow_mut().drain(..).collect();
        for file in given {
            self.take(file, ui.ctx());
        }
        // The browser reads dropped files asynchronously: they join the file input's inbox.
        let dropped = ui.input(|i| i.raw.dropped_files.clone());
        for file in dropped {
            let (inbox, ctx) = (self.inbox.clone(), ui.ctx().clone());
            wasm_bindgen_futures::spawn_local(async move {
                let name = file.path().display().to_string();
                match file.bytes_async().await {
                    Ok(bytes) => inbox.borrow_mut().push(Given {
                        name,
                        bytes,
                        asked: None,
                    }),
                    Err(e) => web_sys::console::error_1(&format!("cannot read {name}: {e}").into()),
                }
                ctx.request_repaint();
            });
        }
        egui::Panel::top("web").show(ui, |ui| self.bar(ui));
        let offered = self.studio.recovered.is_some();
        // The studio's File menu and shortcuts ask its dialogs (`WebDialogs`): the picker
        // opens from there, and saves come back here as downloads.
        self.studio.ui(ui);
        let downloads: Vec<_> = self.downloads.borrow_mut().drain(..).collect();
        for download in downloads {
            match download {
                Download::Scene => self.save(),
                Download::Picture => self.save_picture(),
            }
        }
        self.keep_recovery(offered);
        self.show_title();
    }
}

/// Opens the browser's file picker (the page's hidden `<input type=file id=open-scene>`) for
/// the files `request` asks for (any file the studio takes for `None`, the bar's button),
/// remembering in `asking` what the chosen files answer.
fn pick_file(asking: &Asking, request: Option<Request>) {
    let accept = match request {
        Some(Request::OpenScene) => ".toml",
        Some(Request::PickMesh) => ".obj,.ply,.gltf,.glb,.bin",
        Some(Request::PickTexture) => ".png,.jpg,.jpeg",
        _ => ".toml,.obj,.ply,.gltf,.glb,.bin,.png,.jpg,.jpeg",
    };
    if let Some(input) = file_input() {
        input.set_accept(accept);
        asking.set(request);
        input.click();
    }
}

fn file_input() -> Option<web_sys::HtmlInputElement> {
    web_sys::window()?
        .document()?
        .get_element_by_id("open-scene")?
        .dyn_into()
        .ok()
}

/// Reads the files chosen in the page's file input into `inbox`, with what the picker was
/// opened for (`asking`), and wakes the studio.
fn listen_to_file_input(
    inbox: &Inbox,
    asking: &Asking,
    ctx: &egui::Context,
) -> Result<(), JsValue> {
    let input = file_input().ok_or("no <input id=open-scene>")?;
    let (inbox, asking, ctx, target) = (inbox.clone(), asking.clone(), ctx.clone(), input.clone());
    let changed = Closure::<dyn FnMut(web_sys::Event)>::new(move |_| {
        let Some(list) = target.files() else { return };
        let asked = asking.take();
        for i in 0..list.length() {
            let Some(file) = list.get(i) else { continue };
            let (inbox, ctx) = (inbox.clone(), ctx.clone());
            wasm_bindgen_futures::spawn_local(async move {
                let name = file.name();
                match wasm_bindgen_futures::JsFuture::from(file.array_buffer()).await {
                    Ok(buffer) => {
                        let bytes = js_sys::Uint8Array::new(&buffer).to_vec();
                        inbox.borrow_mut().push(Given { name, bytes, asked });
                    }
                    Err(e) => web_sys::console::error_2(&"cannot read".into(), &e),
                }
                ctx.request_repaint();
            });
        }
        // The same file chosen again is a change too.
        target.set_value("");
    });
    input.add_event_listener_with_callback("change", changed.as_ref().unchecked_ref())?;
    // The listener lives as long as the page.
    changed.forget();
    Ok(())
}

/// Hands `bytes` to the browser as a download called `name`.
fn download(name: &str, bytes: &[u8], mime: &str) -> Result<(), JsValue> {
    let document = web_sys::window()
        .and_then(|w| w.document())
        .ok_or("no document")?;
    let parts = js_sys::Array::of1(&js_sys::Uint8Array::from(bytes));
    let options = web_sys::BlobPropertyBag::new();
    options.set_type(mime);
    let blob = web_sys::Blob::new_with_u8_array_sequence_and_options(&parts, &options)?;
    let url = web_sys::Url::create_object_url_with_blob(&blob)?;
    let link: web_sys::HtmlAnchorElement = document.create_element("a")?.dyn_into()?;
    link.set_href(&url);
    link.set_download(name);
    link.click();
    web_sys::Url::revoke_object_url(&url)?;
    Ok(())
}

/// Removes the page's "loading" text once the studio runs.
fn hide_loading() {
    if let Some(loading) = web_sys::window()
        .and_then(|w| w.document())
        .and_then(|d| d.get_element_by_id("loading"))
    {
        loading.remove();
    }
}

/// The `localStorage` keys of files kept with the unsaved work.
fn file_keys(storage: &web_sys::Storage) -> Vec<String> {
    let count = storage.length().unwrap_or(0);
    (0..count)
        .filter_map(|i| storage.key(i).ok().flatten())
        .filter(|key| key.starts_with(FILE_KEY_PREFIX))
        .collect()
}

/// Gives the scene's files the files kept with the unsaved work; returns their paths.
fn restore_files(storage: &web_sys::Storage) -> BTreeSet<PathBuf> {
    let mut restored = BTreeSet::new();
    for key in file_keys(storage) {
        let text = storage.get_item(&key).ok().flatten().unwrap_or_default();
        let path = PathBuf::from(&key[FILE_KEY_PREFIX.len()..]);
        match files::from_base64(&text) {
            Some(bytes) => {
                orbifold_scene::files::provide(&path, bytes);
                restored.insert(path);
            }
            None => {
                let _ = storage.remove_item(&key);
            }
        }
    }
    restored
}
