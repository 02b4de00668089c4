//! Rendering a camera's view of a scene: from an [`Integrator`] and a [`Camera`] to a finished
//! picture.
//!
//! - [`options`](RenderOptions): what to render (size, samples, seed, when to stop, adaptive
//!   sampling, the pixel filter).
//! - [`Progressive`]: the render loop, progressive rounds of one sample per pixel, in
//!   parallel, into an HDR [`Film`](crate::film::Film); [`render`] runs it to the end, a time
//!   limit, a noise target or cancellation.
//! - the adaptive sampler (`adaptive.rs`): how many samples each pixel gets, stage by stage,
//!   and how each stage's samples are weighted so that the image stays unbiased.
//! - [`Picture`]: **the one render pipeline** that `orbifold render`, `orbifold animate` and
//!   the studio call: progressive rounds, then the guided denoiser when the picture is to be
//!   denoised, tone mapping for display, and the HDR image kept for EXR
//!   ([`render_picture`], [`Progressive::picture`]).
//!
//! Every sample's random numbers depend only on (seed, pixel, the pixel's sample index), and
//! each round (each half of the first) is added to the film and the cache in pixel order, so an
//! image is the same for a given seed whatever the number of threads.

mod adaptive;
mod options;
mod pipeline;
mod progressive;

pub use adaptive::LONGEST_STAGE;
pub use options::{MOST_SAMPLES_PER_ROUND, RenderOptions, WARMUP_ROUNDS};
pub use pipeline::{Picture, render_picture};
pub use progressive::{Progressive, Rendered, render, render_scene};

#[cfg(doc)]
use crate::integrator::Integrator;
#[cfg(doc)]
use orbifold_trace::camera::Camera;
