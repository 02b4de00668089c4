//! The integrator's side of the radiance cache ([`crate::radiance_cache`]): reading the cache's
//! estimate of the light that a diffuse surface reflects where tracing it would be wasted (a far
//! mirror image, whose pixel footprint is wider than a cell of the cache, or a surface reached by
//! a diffuse bounce), and handing the cache the estimates of the camera paths' first diffuse
//! surfaces that were traced in full ([`PendingDeposit`]). The path loop decides which surfaces
//! read and which deposit.

use glam::DVec3;

use super::Integrator;
use crate::lights::{Rgb, TangentFrame};
use crate::radiance_cache::{self, Deposit, Reader, facing};
use crate::sampler::{Frame, Sampler};

/// The camera path's first diffuse surface, while its estimate there is being traced.
pub(super) struct PendingDeposit {
    pub(super) point: DVec3,
    pub(super) height: f64,
    /// Which way the surface faces ([`facing`]).
    pub(super) facing: u8,
    /// The path's radiance before the surface's reflected light.
    pub(super) before: Rgb,
    /// The throughput times the albedo there.
    pub(super) weight: Rgb,
    /// What the radiance cache holds for the surface, times `weight`, when the path probes a
    /// ready cell: the pixel takes it like any other read, and the path's own estimate only
    /// feeds the cache.
    pub(super) read: Option<Rgb>,
}

impl PendingDeposit {
    /// The estimate, once the path's radiance is `after`.
    pub(super) fn deposit(&self, after: Rgb) -> Deposit {
        let per_albedo = |c: usize, value: f64| value / self.weight[c];
        Deposit {
            point: self.point,
            height: self.height,
            facing: self.facing,
            total: [0, 1, 2].map(|c| per_albedo(c, after[c] - self.before[c])),
        }
    }
}

impl Integrator {
    /// Whether renders read far and indirect light from a radiance cache: when the settings ask
    /// for it, with light sampling and the pixel footprint (brute-force path tracing, the
    /// reference, and straight rays trace every path in full).
    pub fn uses_radiance_cache(&self) -> bool {
        let s = &self.settings;
        s.radiance_cache && s.nee && s.pixel_footprint && !s.straight_rays
    }

    /// Which way a surface at (x, h) with normal `geometric` (local to `frame`) faces, and the
    /// cache's estimate of the light it reflects per unit albedo, spread over `width`
    /// ([`Reader::lookup`], jittered along the surface).
    #[allow(clippy::too_many_arguments)]
    pub(super) fn cached(
        &self,
        cache: &Reader,
        x: DVec3,
        h: f64,
        frame: &TangentFrame,
        geometric: DVec3,
        width: f64,
        sampler: &mut Sampler,
    ) -> (u8, Option<Rgb>) {
        let ambient = |t: DVec3| (frame.e1 * t.x + frame.e2 * t.y, t.z);
        let normal = ambient(geometric);
        let facing = facing(normal.0, normal.1);
        if width < radiance_cache::FINEST_CELL {
            return (facing, None);
        }
        let along = Frame::from_normal(geometric);
        let tangents = [ambient(along.tangent()), ambient(along.bitangent())];
        let jitter = [
            sampler.next_independent_f64(),
            sampler.next_independent_f64(),
        ];
        (facing, cache.lookup(x, h, facing, width, tangents, jitter))
    }
}
