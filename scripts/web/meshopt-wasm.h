/* Forced into meshoptimizer's C++ sources when they are compiled for wasm32-unknown-unknown
 * (scripts/web.sh sets CXXFLAGS_wasm32_unknown_unknown). The meshopt crate (0.7) compiles them
 * there against its own stripped-down headers, which lack floorf, ceilf, log2f, frexpf,
 * ldexpf and cosf that opacitymap.cpp, quantization.cpp and tangentspace.cpp call. floorf and ceilf are WebAssembly
 * instructions. The others have none and there is no libm to link, so they are computed here
 * from the float's bits: frexpf and ldexpf exactly for normal numbers and zero, log2f from the
 * exponent and a polynomial for the mantissa (error under 1e-4), cosf by a Taylor series
 * after reduction to [-π, π] (error under 1e-6). The orbifold preview calls
 * only meshopt's vertex-cache and fetch optimisers, which use none of them. */
#define floorf __builtin_floorf
#define ceilf __builtin_ceilf
typedef union { float f; unsigned int u; } orbifold_wasm_bits;
static inline float orbifold_wasm_frexpf(float x, int* exponent) {
    orbifold_wasm_bits bits = { x };
    int e = (int)((bits.u >> 23) & 255u);
    if (e == 0 || e == 255) { /* zero (and, roughly, subnormals), infinities and NaN */
        *exponent = 0;
        return x;
    }
    *exponent = e - 126;
    bits.u = (bits.u & 0x807fffffu) | (126u << 23); /* the mantissa in [0.5, 1) */
    return bits.f;
}
static inline float orbifold_wasm_ldexpf(float x, int exponent) {
    /* Scaled in steps that stay within the normal range of float. */
    while (exponent > 100) { x *= 1.2676506e30f; exponent -= 100; }
    while (exponent < -100) { x *= 7.888609e-31f; exponent += 100; }
    orbifold_wasm_bits scale = { 0.0f };
    scale.u = (unsigned int)(exponent + 127) << 23;
    return x * scale.f;
}
#define frexpf orbifold_wasm_frexpf
#define ldexpf orbifold_wasm_ldexpf
static inline float orbifold_wasm_log2f(float x) {
    orbifold_wasm_bits bits = { x };
    int exponent = (int)((bits.u >> 23) & 255u) - 127;
    bits.u = (bits.u & 0x007fffffu) | 0x3f800000u; /* the mantissa m, in [1, 2) */
    float m = bits.f - 1.0f;
    /* log2(1 + m) on [0, 1): a minimax-like cubic through the end points. */
    float p = m * (1.4425449f + m * (-0.7181452f + m * 0.2755995f));
    return (float)exponent + p;
}
#define log2f orbifold_wasm_log2f
static inline float orbifold_wasm_cosf(float x) {
    const float two_pi = 6.28318531f;
    x -= two_pi * __builtin_floorf(x / two_pi + 0.5f);
    float x2 = x * x, term = 1.0f, sum = 1.0f;
    for (int n = 1; n <= 10; ++n) {
        term *= -x2 / (float)((2 * n - 1) * (2 * n));
        sum += term;
    }
    return sum;
}
#define cosf orbifold_wasm_cosf
