//! The examples browser: every scene of `examples/scenes/` (built into the binary) with a
//! thumbnail, one click away. An example opens as a new untitled document, so that saving asks
//! where to keep the copy and never overwrites the example.
//!
//! Thumbnails are small, few-sample renders of each scene from its own camera (the renderer's
//! one pipeline, denoised, as the render tab finishes its picture). They are made one at a time
//! on a background thread from the moment the browser is first opened, so the window stays
//! responsive, and kept for the rest of the session.

use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};

use orbifold_render::integrator::{Integrator, Settings};
use orbifold_render::render::{RenderOptions, render_picture};
use orbifold_scene::Scene;
use orbifold_trace::camera::Camera;

include!(concat!(env!("OUT_DIR"), "/examples.rs"));

/// A thumbnail's width in pixels (its height follows the scene's picture shape).
pub const THUMBNAIL_WIDTH: u32 = 128;
/// Samples a pixel of a thumbnail: enough, denoised, to see the room.
pub const THUMBNAIL_SAMPLES: u32 = 4;

/// One example scene.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Example {
    /// Its file name without `.toml`, such as `fig-8.10-444`.
    pub name: &'static str,
    /// The scene file's text.
    pub text: &'static str,
}

impl Example {
    /// The scene, read as `orbifold` reads the file.
    pub fn scene(&self) -> Result<Scene, String> {
        Scene::from_toml(self.text, None).map_err(|errors| {
            errors
                .iter()
                .map(ToString::to_string)
                .collect::<Vec<_>>()
                .join("\n")
        })
    }

    /// What the example shows: its file's leading comment, joined into one line.
    pub fn description(&self) -> String {
        self.text
            .lines()
            .map_while(|l| l.strip_prefix('#'))
            .map(str::trim)
            .collect::<Vec<_>>()
            .join(" ")
    }
}

/// Every example scene, by file name.
///
/// ```
/// let examples = orbifold_studio::examples_browser::examples();
/// assert!(examples.iter().any(|e| e.name == "default"));
/// assert!(examples.iter().all(|e| e.scene().is_ok()));
/// ```
pub fn examples() -> Vec<Example> {
    EXAMPLES
        .iter()
        .map(|&(name, text)| Example { name, text })
        .collect()
}

/// A picture (width, height, RGBA8) of `scene` from its camera, `width` pixels wide and shaped
/// as the scene's render, at [`THUMBNAIL_SAMPLES`] samples a pixel. `cancel` stops it early.
pub fn thumbnail(
    scene: &Scene,
    width: u32,
    cancel: &AtomicBool,
) -> Result<(u32, u32, Vec<u8>), String> {
    let integrator = Integrator::from_scene(scene, None, Settings::of_scene(scene))?;
    let camera = Camera::new(integrator.space(), &scene.camera);
    let shape = f64::from(scene.render.height) / f64::from(scene.render.width.max(1));
    let height = ((f64::from(width) * shape).round() as u32).clamp(8, 4 * width);
    let options = RenderOptions {
        filter: scene.render.filter.into(),
        denoised: true,
        ..RenderOptions::new(width, height, THUMBNAIL_SAMPLES, 0)
    };
    let picture = render_picture(&integrator, &camera, &options, None, cancel, &|_, _| {});
    let (w, h) = picture.size();
    Ok((w, h, picture.rgba8()))
}

/// A thumbnail as made: the picture, or why there is none.
type Made = Result<(u32, u32, Vec<u8>), String>;

/// The browser's window and its thumbnails.
#[derive(Default)]
pub struct ExamplesBrowser {
    /// Whether the window is shown.
    pub open: bool,
    /// Per example: its thumbnail, or why it has none; `None` while it is being made.
    thumbnails: Vec<Option<Result<egui::TextureHandle, String>>>,
    maker: Option<Maker>,
}

/// Makes thumbnails in order, one at a time.
struct Maker {
    #[cfg(not(target_arch = "wasm32"))]
    receiver: std::sync::mpsc::Receiver<(usize, Made)>,
    /// Without threads: the next example to make.
    #[cfg(target_arch = "wasm32")]
    next: usize,
    cancel: Arc<AtomicBool>,
}

impl Maker {
    fn start(examples: Vec<Example>) -> Maker {
        let cancel = Arc::new(AtomicBool::new(false));
        #[cfg(not(target_arch = "wasm32"))]
        {
            let (sender, receiver) = std::sync::mpsc::channel();
            let stop = cancel.clone();
            std::thread::spawn(move || {
                for (i, example) in examples.iter().enumerate() {
                    if stop.load(Ordering::Relaxed) {
                        return;
                    }
                    let made = example
                        .scene()
                        .and_then(|scene| thumbnail(&scene, THUMBNAIL_WIDTH, &stop));
                    // The browser is gone: nobody wants the rest.
                    if sender.send((i, made)).is_err() {
                        return;
                    }
                }
            });
            Maker { receiver, cancel }
        }
        #[cfg(target_arch = "wasm32")]
        {
            let _ = examples;
            Maker { next: 0, cancel }
        }
    }

    /// The thumbnails made since the last call.
    fn made(&mut self, examples: &[Example]) -> Vec<(usize, Made)> {
        #[cfg(not(target_arch = "wasm32"))]
        {
            let _ = examples;
            self.receiver.try_iter().collect()
        }
        // Without threads, one thumbnail a frame on the UI thread.
        #[cfg(target_arch = "wasm32")]
        {
            let Some(example) = examples.get(self.next) else {
                return Vec::new();
            };
            let made = example
                .scene()
                .and_then(|scene| thumbnail(&scene, THUMBNAIL_WIDTH, &self.cancel));
            self.next += 1;
            vec![(self.next - 1, made)]
        }
    }
}

impl Drop for Maker {
    fn drop(&mut self) {
        self.cancel.store(true, Ordering::Relaxed);
    }
}

impl ExamplesBrowser {
    /// How many thumbnails are ready (made, or failed with a reason).
    pub fn thumbnails_done(&self) -> usize {
        self.thumbnails.iter().filter(|t| t.is_some()).count()
    }

    /// Whether example `i`'s thumbnail is a picture (not missing or failed).
    pub fn has_thumbnail(&self, i: usize) -> bool {
        matches!(self.thumbnails.get(i), Some(Some(Ok(_))))
    }

    /// Shows the window when it is open; returns the example the user chose.
    pub fn show(&mut self, ctx: &egui::Context) -> Option<Example> {
        if !self.open {
            return None;
        }
        let examples = examples();
        if self.maker.is_none() {
            self.thumbnails = vec![None; examples.len()];
            self.maker = Some(Maker::start(examples.clone()));
        }
        if let Some(maker) = &mut self.maker {
            for (i, made) in maker.made(&examples) {
                let texture = made.map(|(w, h, rgba)| {
                    let image =
                        egui::ColorImage::from_rgba_unmultiplied([w as usize, h as usize], &rgba);
                    ctx.load_texture(
                        format!("example {}", examples[i].name),
                        image,
                        egui::TextureOptions::LINEAR,
                    )
                });
                if let Some(slot) = self.thumbnails.get_mut(i) {
                    *slot = Some(texture);
                }
            }
        }
        if self.thumbnails_done() < examples.len() {
            ctx.request_repaint_after(std::time::Duration::from_millis(100));
        }
        let mut chosen = None;
        let mut open = self.open;
        egui::Window::new("Examples")
            .open(&mut open)
            .default_size([720.0, 560.0])
            .vscroll(true)
            .show(ctx, |ui| {
                ui.label("Click an example to open it as a new, untitled scene.");
                ui.horizontal_wrapped(|ui| {
                    for (i, example) in examples.iter().enumerate() {
                        ui.vertical(|ui| {
                            ui.set_width(THUMBNAIL_WIDTH as f32 + 8.0);
                            let size = egui::vec2(THUMBNAIL_WIDTH as f32, 0.75 * 128.0);
                            match self.thumbnails.get(i) {
                                Some(Some(Ok(texture))) => {
                                    let [w, h] = texture.size();
                                    let height = THUMBNAIL_WIDTH as f32 * h as f32 / w as f32;
                                    let image = egui::Image::new((
                                        texture.id(),
                                        egui::vec2(size.x, height),
                                    ))
                                    .sense(egui::Sense::click());
                                    if ui.add(image).clicked() {
                                        chosen = Some(*example);
                                    }
                                }
                                Some(Some(Err(e))) => {
                                    ui.allocate_ui(size, |ui| {
                                        ui.colored_label(egui::Color32::LIGHT_RED, "no picture")
                                            .on_hover_text(e);
                                    });
                                }
                                _ => {
                                    ui.allocate_ui(size, |ui| {
                                        ui.spinner();
                                    });
                                }
                            }
                            let button =
                                ui.button(example.name).on_hover_text(example.description());
                            if button.clicked() {
                                chosen = Some(*example);
                            }
                        });
                    }
                });
            });
        self.open = open && chosen.is_none();
        chosen
    }
}
