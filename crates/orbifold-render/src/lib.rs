//! Rendering: today the 2D pictures of the universal cover (`tiling`); the offline, physically
//! based curved-ray tracer (exact geodesics of S²×R, E²×R and H²×R, analytic mirror rooms, a BVH
//! for curved rays, light transport; DESIGN.md §8) comes with the tracing-core issues.

pub mod tiling;

pub use orbifold;
pub use orbifold_scene;
