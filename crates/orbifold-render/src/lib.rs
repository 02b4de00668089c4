//! Rendering of orbifold mirror rooms: the 2D pictures of the universal cover (`tiling`), and the
//! curved-ray tracing core — exact geodesics of S²×R, E²×R and H²×R (`geodesic`), the analytic
//! mirror room (`room`), intrinsically flat triangles (`triangle`), a BVH for curved rays (`bvh`),
//! instanced objects (`instance`), and the tracer that follows rays through mirrors (`tracer`).
//! See DESIGN.md §8.

pub mod camera;
pub mod film;
pub mod filter;
pub mod geodesic;
pub mod room;
pub mod sampler;
pub mod tiling;

pub mod aov;
pub mod bsdf;
pub mod bvh;
mod cpu;
pub mod denoise;
mod fastmath;
pub mod flat;
pub mod footprint;
pub mod instance;
pub mod integrator;
pub mod light;
pub mod radiance_cache;
pub mod render;
pub mod shading_normal;
mod texture;
pub mod tracer;
pub mod triangle;

pub use orbifold;
pub use orbifold_scene;
