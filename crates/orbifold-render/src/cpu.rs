//! What the processor can do beyond the baseline the crate is built for.
//!
//! Release builds target baseline x86-64 (SSE2), so that a binary runs on any x86-64 machine.
//! The hottest loops, the BVH's four-lane bound tests, gain a fifth or more from AVX2 and FMA,
//! where four f64 lanes fit one register: they are compiled twice, and [`has_avx2_fma`] picks
//! the copy at run time. Both copies compute the same IEEE operations in the same order, so
//! renders are bit for bit the same on either path.

/// Whether this processor has AVX2 and FMA (x86-64 only; `false` elsewhere). The answer is
/// cached by the standard library after the first call.
#[inline]
pub(crate) fn has_avx2_fma() -> bool {
    #[cfg(target_arch = "x86_64")]
    {
        std::arch::is_x86_feature_detected!("avx2") && std::arch::is_x86_feature_detected!("fma")
    }
    #[cfg(not(target_arch = "x86_64"))]
    {
        false
    }
}
