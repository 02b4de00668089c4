//! What the processor can do beyond the baseline the crate is built for.
//!
//! Release builds target baseline x86-64 (SSE2), so that a binary runs on any x86-64 machine.
//! The hottest loops, the BVH's node tests (eight lanes) and the light-image weights, run faster
//! with AVX2 and FMA, where eight f32 or four f64 lanes fit one register (docs/benchmarks.md has
//! the figures): they are compiled twice, and [`has_avx2_fma`] picks the copy at run time
//! ([`with_avx2`](crate::with_avx2)). The loops over many values — a sphere light's triangles,
//! the light images, a row of the denoiser — get a third copy for AVX-512
//! ([`with_avx512`](crate::with_avx512)), where sixteen f32 or eight f64 lanes fit a register. Every copy computes the same IEEE operations
//! in the same order, so renders are bit for bit the same on any path (tests compare them).

/// Whether this processor has AVX2 and FMA (x86-64 only; `false` elsewhere). The answer is
/// cached by the standard library after the first call.
#[inline]
pub fn has_avx2_fma() -> bool {
    #[cfg(target_arch = "x86_64")]
    {
        std::arch::is_x86_feature_detected!("avx2") && std::arch::is_x86_feature_detected!("fma")
    }
    #[cfg(not(target_arch = "x86_64"))]
    {
        false
    }
}

/// Whether this processor has AVX-512 (foundation and vector-length extensions) besides AVX2
/// and FMA (x86-64 only).
#[inline]
pub fn has_avx512() -> bool {
    #[cfg(target_arch = "x86_64")]
    {
        has_avx2_fma()
            && std::arch::is_x86_feature_detected!("avx512f")
            && std::arch::is_x86_feature_detected!("avx512vl")
    }
    #[cfg(not(target_arch = "x86_64"))]
    {
        false
    }
}

/// Calls `$self.$portable(…)` through a copy compiled with the target features `$features`
/// when `$has()` says the processor has them, and returns its result; falls through otherwise.
/// The method must be `#[inline(always)]`, so that it is compiled anew inside the copy.
#[doc(hidden)]
#[macro_export]
macro_rules! call_with_features {
    ($features:literal, $has:path, $Type:ty, $self:ident . $portable:ident ($($arg:ident : $ty:ty),*) -> $ret:ty) => {
        #[cfg(target_arch = "x86_64")]
        {
            #[target_feature(enable = $features)]
            fn copy(this: &$Type, $($arg: $ty),*) -> $ret {
                this.$portable($($arg),*)
            }
            if $has() {
                // SAFETY: the processor has every feature the `target_feature` function
                // requires, checked just above.
                #[allow(unsafe_code)]
                return unsafe { copy($self, $($arg),*) };
            }
        }
    };
}

/// Calls the method `$portable` of `$self` (of type `$Type`; the method must be
/// `#[inline(always)]`, so that it is compiled anew inside the copy) through a copy compiled for
/// AVX2 and FMA when the processor has them, and directly otherwise. Used as the whole body of
/// a dispatching method:
///
/// ```ignore
/// pub fn occluded(&self, space: Space, ray: &Ray, s_min: f64, s_max: f64) -> bool {
///     with_avx2!(Bvh, self.occluded_portable(space: Space, ray: &Ray, s_min: f64, s_max: f64) -> bool)
/// }
/// ```
#[macro_export]
macro_rules! with_avx2 {
    ($Type:ty, $self:ident . $portable:ident ($($arg:ident : $ty:ty),* $(,)?) -> $ret:ty) => {{
        $crate::call_with_features!("avx2,fma", $crate::cpu::has_avx2_fma, $Type,
            $self.$portable($($arg: $ty),*) -> $ret);
        $self.$portable($($arg),*)
    }};
}

/// [`with_avx2`](crate::with_avx2) with a third copy compiled for AVX-512, picked first where the processor has
/// it: for the loops over many values (a light's triangles, a row of pixels, the light
/// images), which fill sixteen f32 or eight f64 lanes a register. The same IEEE operations in
/// the same order as the other copies, so the results are the same bits.
#[macro_export]
macro_rules! with_avx512 {
    ($Type:ty, $self:ident . $portable:ident ($($arg:ident : $ty:ty),* $(,)?) -> $ret:ty) => {{
        $crate::call_with_features!("avx512f,avx512vl,avx2,fma", $crate::cpu::has_avx512,
            $Type, $self.$portable($($arg: $ty),*) -> $ret);
        $crate::with_avx2!($Type, $self.$portable($($arg: $ty),*) -> $ret)
    }};
}

/// Asks the processor to bring the cache lines of `value`'s first `lines` × 64 bytes into its
/// caches (a hint: nothing is read, and nothing happens on other architectures). The BVH
/// traversals ask for a node's children as soon as the node is read, so that the children's
/// cache misses overlap the node's bound tests rather than follow them.
#[inline(always)]
pub fn prefetch<T>(value: &T, lines: usize) {
    #[cfg(target_arch = "x86_64")]
    {
        use std::arch::x86_64::{_MM_HINT_T0, _mm_prefetch};
        let start = std::ptr::from_ref(value).cast::<i8>();
        for line in 0..lines {
            // SAFETY: `prefetch` needs SSE, which every x86-64 processor has (it is in the
            // target's baseline); a prefetch never reads memory for the program nor faults, even
            // past the end of `value`.
            #[allow(unsafe_code)]
            unsafe {
                _mm_prefetch::<_MM_HINT_T0>(start.wrapping_add(64 * line));
            }
        }
    }
    #[cfg(not(target_arch = "x86_64"))]
    {
        let _ = (value, lines);
    }
}
