//! [`DenoiseOptions`]: how strongly each guide stops the filter, and how far the filter reaches.

/// How strongly each guide stops the filter.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DenoiseOptions {
    /// Number of à-trous passes (the footprint is 4·2^passes − 3 pixels wide).
    pub passes: u32,
    /// Exponent of the normal weight max(0, n·n′)^σ for the first surface's light sample (and
    /// for the light seen directly).
    pub sigma_normal: f64,
    /// Exponent of the normal weight for the rest of the reflected light (the light of longer
    /// paths). Lower than [`DenoiseOptions::sigma_normal`]: light that arrives after a bounce
    /// comes from all round and changes slowly with the normal, while a light sample follows
    /// the normal's cosine to the light. On a bumpy mesh, whose normals turn by tens of degrees
    /// from pixel to pixel, the light sample's exponent would let nothing be averaged there (the
    /// trade of noise for bias is measured in `docs/benchmarks.md`).
    pub sigma_normal_rest: f64,
    /// Relative depth difference that lowers the weight e-fold in the first pass (the scale
    /// grows with each pass's step).
    pub sigma_depth: f64,
    /// Albedo difference scale; infinite (the default) for no albedo guide. The lighting is
    /// filtered divided by the albedo, so a texture's edge is no lighting edge; and where a
    /// checkerboard's checks shrink towards a pixel, each pixel's footprint-averaged albedo
    /// differs from its neighbours' (a moiré), so an albedo guide would stop the filter just where
    /// the far floor's noise is worst.
    pub sigma_albedo: f64,
    /// Lighting difference, in standard errors, that the weight tolerates.
    pub sigma_lighting: f64,
}

impl Default for DenoiseOptions {
    fn default() -> Self {
        DenoiseOptions {
            passes: 5,
            sigma_normal: 64.0,
            sigma_normal_rest: 8.0,
            sigma_depth: 0.05,
            sigma_albedo: f64::INFINITY,
            sigma_lighting: 4.0,
        }
    }
}
