//! The page: starts the studio on the canvas `#studio`, and connects it to the browser's file
//! input (`#open-scene`), downloads, dropped files and `localStorage`.

use std::cell::RefCell;
use std::path::PathBuf;
use std::rc::Rc;
use std::sync::Arc;

use eframe::egui_wgpu::{WgpuConfiguration, WgpuSetup, WgpuSetupCreateNew};
use eframe::wgpu;
use egui::{Key, KeyboardShortcut, Modifiers, Ui};
use orbifold_studio::Studio;
use orbifold_studio::document::Document;
use wasm_bindgen::JsCast;
use wasm_bindgen::prelude::*;

use crate::files::{self, RECOVERY_KEY};

/// Files the page's file input has read and the next frame opens: names and bytes.
type Inbox = Rc<RefCell<Vec<(String, Vec<u8>)>>>;

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
    storage: Option<web_sys::Storage>,
    /// The document revision last kept in `localStorage`.
    kept: u64,
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
        studio.recovered = storage
            .as_ref()
            .and_then(|s| s.get_item(RECOVERY_KEY).ok().flatten())
            .and_then(|text| files::scene(RECOVERY_KEY, text.as_bytes()).ok());
        let inbox = Inbox::default();
        if let Err(e) = listen_to_file_input(&inbox, &cc.egui_ctx) {
            studio.status = format!("no file input: {e:?}");
        }
        hide_loading();
        WebStudio {
            kept: studio.document.revision(),
            studio,
            inbox,
            storage,
            title: String::new(),
        }
    }

    /// Opens a file the page was given, or says why it cannot.
    fn open(&mut self, name: &str, bytes: &[u8]) {
        if let Some(reason) = files::refusal(name) {
            self.studio.status = reason;
            return;
        }
        match files::scene(name, bytes) {
            Ok(scene) => {
                self.studio.document = Document::with_scene(scene, Some(PathBuf::from(name)), None);
                self.studio.view.reset(self.studio.document.scene());
                self.studio.status = format!("opened {name}");
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
                pick_file();
            }
            if ui.button("Save scene").clicked() {
                self.save();
            }
            if ui.button("Save picture").clicked() {
                self.save_picture();
            }
            ui.label("(or drop a scene file on the page)");
        });
    }

    /// Keeps the unsaved work in `localStorage` when the document changed.
    fn keep_recovery(&mut self, offered: bool) {
        let document = &self.studio.document;
        // "Discard" in the studio's recovery window changes nothing in the document.
        let discarded = offered && self.studio.recovered.is_none() && !document.is_dirty();
        if discarded {
            self.forget_recovery();
        }
        if document.revision() == self.kept {
            return;
        }
        self.kept = document.revision();
        let Some(storage) = &self.storage else { return };
        if document.is_dirty() {
            if let Err(e) = storage.set_item(RECOVERY_KEY, &document.scene().to_toml()) {
                self.studio.status = format!("cannot keep a recovery copy: {e:?}");
            }
        } else {
            let _ = storage.remove_item(RECOVERY_KEY);
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

    fn forget_recovery(&self) {
        if let Some(storage) = &self.storage {
            let _ = storage.remove_item(RECOVERY_KEY);
        }
    }
}

impl eframe::App for WebStudio {
    fn ui(&mut self, ui: &mut Ui, _frame: &mut eframe::Frame) {
        let picked: Vec<_> = self.inbox.borrow_mut().drain(..).collect();
        for (name, bytes) in picked {
            self.open(&name, &bytes);
        }
        // The browser reads dropped files asynchronously: they join the file input's inbox.
        let dropped = ui.input(|i| i.raw.dropped_files.clone());
        for file in dropped {
            let (inbox, ctx) = (self.inbox.clone(), ui.ctx().clone());
            wasm_bindgen_futures::spawn_local(async move {
                let name = file.path().display().to_string();
                match file.bytes_async().await {
                    Ok(bytes) => inbox.borrow_mut().push((name, bytes)),
                    Err(e) => web_sys::console::error_1(&format!("cannot read {name}: {e}").into()),
                }
                ctx.request_repaint();
            });
        }
        // Ctrl+O and Ctrl+S go to the page's file input and downloads, before the studio
        // would take them for its dialogs of typed paths.
        let (open, save) = ui.input_mut(|i| {
            (
                i.consume_shortcut(&KeyboardShortcut::new(Modifiers::COMMAND, Key::O)),
                i.consume_shortcut(&KeyboardShortcut::new(Modifiers::COMMAND, Key::S)),
            )
        });
        if open {
            pick_file();
        }
        if save {
            self.save();
        }
        egui::Panel::top("web").show(ui, |ui| self.bar(ui));
        let offered = self.studio.recovered.is_some();
        self.studio.ui(ui);
        self.keep_recovery(offered);
        self.show_title();
    }
}

/// Opens the browser's file picker (the page's hidden `<input type=file id=open-scene>`).
fn pick_file() {
    if let Some(input) = file_input() {
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

/// Reads the files chosen in the page's file input into `inbox`, and wakes the studio.
fn listen_to_file_input(inbox: &Inbox, ctx: &egui::Context) -> Result<(), JsValue> {
    let input = file_input().ok_or("no <input id=open-scene>")?;
    let (inbox, ctx, target) = (inbox.clone(), ctx.clone(), input.clone());
    let changed = Closure::<dyn FnMut(web_sys::Event)>::new(move |_| {
        let Some(list) = target.files() else { return };
        for i in 0..list.length() {
            let Some(file) = list.get(i) else { continue };
            let (inbox, ctx) = (inbox.clone(), ctx.clone());
            wasm_bindgen_futures::spawn_local(async move {
                let name = file.name();
                match wasm_bindgen_futures::JsFuture::from(file.array_buffer()).await {
                    Ok(buffer) => {
                        let bytes = js_sys::Uint8Array::new(&buffer).to_vec();
                        inbox.borrow_mut().push((name, bytes));
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
