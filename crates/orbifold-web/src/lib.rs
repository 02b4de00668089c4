//! The studio in the browser: [`orbifold_studio::Studio`] compiled to WebAssembly and run by
//! eframe's web runner on a `<canvas>`, drawn with wgpu (WebGPU where the browser has it,
//! WebGL2 otherwise). `scripts/web.sh build` makes the static site; see `docs/web.md`.
//!
//! What the browser lacks is made up here, around the unchanged studio: the studio's file
//! dialogs are the browser's file picker (the page's file input) and downloads; scenes, meshes
//! and images are opened by picking or dropping them on the page (a mesh or an image is given
//! to [`orbifold_scene::files`] under its name, since a page has no disk to read it from);
//! unsaved work, with the given files it needs, is kept in the browser's `localStorage`
//! ([`files`] holds the parts that do not need a browser, and are tested natively). The preview draws on the page's own GPU device
//! ([`orbifold_studio::view3d::View3d::use_window_gpu`]) and the renderer takes its rounds
//! between frames ([`orbifold_studio::render_job::RenderJob::step`]).

pub mod files;

#[cfg(target_arch = "wasm32")]
mod cxx;
#[cfg(target_arch = "wasm32")]
mod web;
