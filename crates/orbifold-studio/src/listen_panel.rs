//! The *listen* tab: a clap half a metre in front of the camera, heard at the camera's two ears
//! through the room's echoes (`orbifold_sound`, as `orbifold listen --stereo --convolve` hears
//! it), played on the speakers, with the echogram beside the button.
//!
//! The echoes are found in the background; the sound is played once they are, through an
//! [`AudioOut`] (the speakers, or a recorder in tests).

use std::path::Path;
use std::sync::mpsc::{Receiver, channel};

use num_complex::Complex64;
use orbifold_scene::Scene;
use orbifold_scene::sound::Place;
use orbifold_sound::{Hearing, clap, convolve, echogram};

use crate::audio::{AudioOut, Speakers};

/// How far in front of the ears the hands clap, metres.
pub const CLAP_DISTANCE: f64 = 0.5;

/// What the background work gives back.
pub struct Heard {
    /// Interleaved stereo samples of the clap through the room, at `rate`.
    pub samples: Vec<f32>,
    /// Frames per second.
    pub rate: u32,
    /// The echogram (left ear) as a PNG.
    pub echogram_png: Vec<u8>,
    /// How many echoes each ear hears.
    pub echoes: usize,
}

/// The scene to hear: the listener at `camera`, the source `CLAP_DISTANCE` in front of it: past
/// a portal, where it lands beyond one, brought back through it as a person walking there would
/// be; at the camera itself where it lands beyond a mirror wall.
pub fn clap_scene(scene: &Scene, camera: &orbifold_scene::Camera) -> Result<Scene, String> {
    let mut scene = scene.clone();
    scene.camera = camera.clone();
    let layout = scene.layout()?;
    let space = layout.space();
    let ear = Place {
        at: camera.at,
        height: camera.height,
    };
    let [forward, _, _] = camera.basis();
    let z = Complex64::new(camera.at[0], camera.at[1]);
    let tangent = space.model_tangent(z, Complex64::new(forward.x, forward.y));
    let norm = space.point_dot(tangent, tangent).max(0.0).sqrt();
    let step = CLAP_DISTANCE / scene.sound.metres_per_unit;
    let hands = if norm > 0.0 {
        let p = space.exp(space.to_ambient(z), tangent * (step / norm));
        let (p, _, _) = layout.carried_inside(p, tangent, 0.0);
        let w = space.to_model(p);
        let at = [w.re, w.im];
        let inside = layout
            .edges
            .iter()
            .all(|e| e.wall.dot(space.to_ambient(w)) > 0.0);
        inside.then_some(Place { at, ..ear })
    } else {
        None
    };
    scene.sound.listener = Some(ear);
    scene.sound.source = Some(hands.unwrap_or(ear));
    Ok(scene)
}

/// Hears a clap in `scene` (made by [`clap_scene`]; mesh and texture paths relative to `base`):
/// both ears' responses, convolved with the built-in clap, interleaved, and the echogram.
pub fn hear(scene: &Scene, base: Option<&Path>) -> Result<Heard, String> {
    let hearing = Hearing::from_scene(scene, base).map_err(|e| e.to_string())?;
    let [left, right] = hearing.stereo(&|_, _| {});
    let rate = hearing.settings.sample_rate;
    let dry = clap::clap(rate);
    let ears: Vec<Vec<f32>> = [&left, &right]
        .iter()
        .map(|r| convolve::convolve(&dry, &hearing.samples(r)))
        .collect::<Result<_, _>>()
        .map_err(|e| e.to_string())?;
    let peak = ears
        .iter()
        .flatten()
        .fold(0.0f32, |m, x| m.max(x.abs()))
        .max(f32::MIN_POSITIVE);
    let samples = ears[0]
        .iter()
        .zip(&ears[1])
        .flat_map(|(l, r)| [0.9 * l / peak, 0.9 * r / peak])
        .collect();
    let floor = 20.0 * (4.0 * std::f64::consts::PI * hearing.settings.min_amplitude).log10();
    let title = format!("{}: a clap at the camera", hearing.signature);
    let echogram_png = echogram::echogram_png(
        &left.arrivals,
        &title,
        hearing.settings.seconds,
        floor,
        (640, 300),
    )
    .map_err(|e| e.to_string())?;
    Ok(Heard {
        samples,
        rate,
        echogram_png,
        echoes: left.arrivals.len(),
    })
}

/// The listen tab's state.
pub struct ListenPanel {
    output: Box<dyn AudioOut>,
    job: Option<Receiver<Result<Heard, String>>>,
    /// In the browser, which has no threads: the work, run by [`ListenPanel::collect`] once a
    /// frame with the spinner has been shown, so that the page says what it is doing while it
    /// holds.
    #[cfg(target_arch = "wasm32")]
    deferred: Option<(Box<dyn FnOnce()>, Option<u64>)>,
    echogram: Option<egui::TextureHandle>,
    /// The last message: what was heard, or what went wrong.
    pub message: String,
}

impl Default for ListenPanel {
    fn default() -> Self {
        ListenPanel::with_output(Box::new(Speakers::default()))
    }
}

impl ListenPanel {
    /// A panel that plays through `output`.
    pub fn with_output(output: Box<dyn AudioOut>) -> ListenPanel {
        ListenPanel {
            output,
            job: None,
            #[cfg(target_arch = "wasm32")]
            deferred: None,
            echogram: None,
            message: String::new(),
        }
    }

    /// Whether echoes are being found.
    pub fn busy(&self) -> bool {
        self.job.is_some()
    }

    /// The tab: the button, what was heard, and the echogram. `base` is the folder of the
    /// scene's file.
    pub fn show(
        &mut self,
        ui: &mut egui::Ui,
        scene: &Scene,
        base: Option<&Path>,
        camera: &orbifold_scene::Camera,
    ) {
        self.collect(ui.ctx());
        // The button and what it heard on the left, the echogram beside them.
        ui.horizontal_top(|ui| {
            ui.vertical(|ui| {
                ui.set_width(220.0);
                let button = ui.add_enabled(!self.busy(), egui::Button::new("Listen"));
                if button.clicked() {
                    self.start(scene, base, camera);
                }
                if self.busy() {
                    ui.horizontal(|ui| {
                        ui.spinner();
                        ui.label("finding the echoes…");
                    });
                    ui.ctx()
                        .request_repaint_after(std::time::Duration::from_millis(100));
                } else {
                    ui.label(&self.message);
                }
                ui.label("A clap half a metre in front of the 3D view's camera, heard at its two ears through every echo off the walls, mirrors, floor and ceiling and through the portals, along the true geodesics ([sound] in the scene sets the units and absorption).");
            });
            if let Some(texture) = &self.echogram {
                let size = texture.size_vec2();
                let scale = (ui.available_width() / size.x).min(1.5);
                ui.image((texture.id(), size * scale));
            }
        });
    }

    fn start(&mut self, scene: &Scene, base: Option<&Path>, camera: &orbifold_scene::Camera) {
        let scene = match clap_scene(scene, camera) {
            Ok(scene) => scene,
            Err(e) => {
                self.message = e;
                return;
            }
        };
        let (send, receive) = channel();
        let base = base.map(Path::to_path_buf);
        let work = move || {
            let _ = send.send(hear(&scene, base.as_deref()));
        };
        #[cfg(not(target_arch = "wasm32"))]
        std::thread::spawn(work);
        // The browser has no threads: the echoes are found on the page's own, holding it a
        // moment, after the spinner has been drawn.
        #[cfg(target_arch = "wasm32")]
        {
            self.deferred = Some((Box::new(work), None));
        }
        self.job = Some(receive);
    }

    /// Takes the background work's result when it is there: plays it and shows its echogram
    /// (called every frame, whichever tab is shown, so the sound plays as soon as it is heard).
    pub fn collect(&mut self, ctx: &egui::Context) {
        #[cfg(target_arch = "wasm32")]
        if let Some((_, seen)) = &mut self.deferred {
            let frame = ctx.cumulative_frame_nr();
            match *seen {
                None => *seen = Some(frame),
                Some(first) if frame > first + 1 => {
                    if let Some((work, _)) = self.deferred.take() {
                        work();
                    }
                }
                Some(_) => {}
            }
        }
        let Some(job) = &self.job else { return };
        let Ok(result) = job.try_recv() else { return };
        self.job = None;
        match result {
            Ok(heard) => {
                self.message = format!("{} echoes at each ear", heard.echoes);
                if let Err(e) = self.output.play(&heard.samples, 2, heard.rate) {
                    self.message = format!("{}; cannot play it: {e}", self.message);
                }
                match image::load_from_memory(&heard.echogram_png) {
                    Ok(picture) => {
                        let rgba = picture.to_rgba8();
                        let image = egui::ColorImage::from_rgba_unmultiplied(
                            [rgba.width() as usize, rgba.height() as usize],
                            &rgba,
                        );
                        self.echogram =
                            Some(ctx.load_texture("echogram", image, egui::TextureOptions::LINEAR));
                    }
                    Err(e) => self.message = format!("{}; no echogram: {e}", self.message),
                }
            }
            Err(e) => self.message = e,
        }
    }
}
