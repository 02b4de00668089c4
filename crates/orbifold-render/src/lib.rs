//! The offline, physically based curved-ray tracer: exact geodesics of S²×R, E²×R and H²×R,
//! analytic mirror rooms, a BVH for curved rays, and light transport. See `DESIGN.md` §8.
//!
//! Not yet written: the tracing-core and rendering issues build it.

pub use orbifold;
pub use orbifold_scene;
