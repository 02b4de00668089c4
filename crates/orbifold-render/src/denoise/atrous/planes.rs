//! The memory of the à-trous passes, laid out for SIMD: each part of the light as *planes*, one
//! array over the whole image per quantity (structure of arrays), so that at one tap of the
//! kernel a row of pixels and their neighbours are two contiguous runs of each plane; and each
//! worker's sums for the row it filters. All of it is allocated once for all passes.

use super::{PARTS, Part};
use orbifold_scene::color::luminance;

/// One part during the passes, one plane per quantity.
pub(super) struct Planes {
    /// The lighting's red, green and blue, 0 where not finite.
    pub(super) lighting: [Vec<f64>; 3],
    /// The lighting's luminance (not finite where the lighting is not).
    pub(super) luminance: Vec<f64>,
    /// The variance of the luminance (infinite where unknown).
    pub(super) variance: Vec<f64>,
    /// The variance where it is finite, 0 elsewhere (where the pixel is no neighbour's), so
    /// that weights of 0 can be added without a branch or a masked load.
    pub(super) finite_variance: Vec<f64>,
}

impl Planes {
    /// The planes of `part`.
    pub(super) fn new(part: &Part) -> Planes {
        Planes::from_planes(
            [0, 1, 2].map(|c| part.lighting.iter().map(|l| l[c]).collect()),
            part.variance.clone(),
        )
    }

    /// Planes of `lighting` and `variance`. A pixel whose lighting is not finite is no
    /// neighbour's (its luminance is not finite, and neither is its weight) and counts as 0 for
    /// itself, so that sums of weights of 0 need no branch.
    fn from_planes(mut lighting: [Vec<f64>; 3], variance: Vec<f64>) -> Planes {
        let luminance = (0..variance.len())
            .map(|i| luminance([lighting[0][i], lighting[1][i], lighting[2][i]]))
            .collect();
        for plane in &mut lighting {
            for l in plane.iter_mut().filter(|l| !l.is_finite()) {
                *l = 0.0;
            }
        }
        let finite_variance = variance
            .iter()
            .map(|&v| if v.is_finite() { v } else { 0.0 })
            .collect();
        Planes {
            lighting,
            luminance,
            variance,
            finite_variance,
        }
    }

    /// Planes of `n` pixels, all 0 (to be written by a pass).
    pub(super) fn zeroed(n: usize) -> Planes {
        Planes {
            lighting: [0, 1, 2].map(|_| vec![0.0; n]),
            luminance: vec![0.0; n],
            variance: vec![0.0; n],
            finite_variance: vec![0.0; n],
        }
    }

    /// The planes' rows of `width` pixels, each writable on its own.
    pub(super) fn rows_mut(&mut self, width: usize) -> impl Iterator<Item = PlanesRow<'_>> {
        let [r, g, b] = &mut self.lighting;
        (r.chunks_mut(width))
            .zip(g.chunks_mut(width))
            .zip(b.chunks_mut(width))
            .zip(self.luminance.chunks_mut(width))
            .zip(self.variance.chunks_mut(width))
            .zip(self.finite_variance.chunks_mut(width))
            .map(
                |(((((r, g), b), luminance), variance), finite_variance)| PlanesRow {
                    lighting: [r, g, b],
                    luminance,
                    variance,
                    finite_variance,
                },
            )
    }

    /// The part that the planes hold.
    pub(super) fn part(&self) -> Part {
        let [r, g, b] = &self.lighting;
        Part {
            lighting: (0..r.len()).map(|i| [r[i], g[i], b[i]]).collect(),
            variance: self.variance.clone(),
        }
    }
}

/// What a row's pass adds up for one part at each pixel: Σw·lighting, Σw and Σw²·variance.
pub(super) struct RowSums {
    pub(super) lighting: [Vec<f64>; 3],
    pub(super) weights: Vec<f64>,
    pub(super) variance: Vec<f64>,
}

impl RowSums {
    /// A worker's memory for the rows of `width` pixels it filters: every part's sums, and one
    /// tap's runs.
    pub(super) fn zeroed(width: usize) -> ([RowSums; PARTS], TapRuns) {
        let sums = std::array::from_fn(|_| RowSums {
            lighting: [0, 1, 2].map(|_| vec![0.0; width]),
            weights: vec![0.0; width],
            variance: vec![0.0; width],
        });
        let runs = TapRuns {
            normal_log: vec![0.0; width],
            depth_albedo_log: vec![0.0; width],
            weights: vec![0.0; width],
        };
        (sums, runs)
    }

    /// Zero sums, for the next row.
    pub(super) fn clear(&mut self) {
        for plane in self
            .lighting
            .iter_mut()
            .chain([&mut self.weights, &mut self.variance])
        {
            plane.fill(0.0);
        }
    }
}

/// One tap's runs over a row. At one tap of the kernel (one neighbour offset), a *run* is the
/// stretch of the row's pixels whose neighbour at that offset is inside the image: the pixels
/// and their neighbours are then contiguous in every plane, and are weighed side by side.
pub(super) struct TapRuns {
    /// The log of the normals' weight, which each part raises to its own exponent.
    pub(super) normal_log: Vec<f64>,
    /// The log of the depth and albedo falloffs' weight.
    pub(super) depth_albedo_log: Vec<f64>,
    /// One part's weights.
    pub(super) weights: Vec<f64>,
}

/// One row of a part's [`Planes`], being written by a pass.
pub(super) struct PlanesRow<'a> {
    lighting: [&'a mut [f64]; 3],
    luminance: &'a mut [f64],
    variance: &'a mut [f64],
    finite_variance: &'a mut [f64],
}

impl PlanesRow<'_> {
    /// The row's filtered values from its sums (a pixel with no weight keeps its value in
    /// `old`, the planes the pass read; its first pixel is `start` there), with the luminance
    /// and the finite values that [`Planes::from_planes`] derives.
    pub(super) fn finish(&mut self, sums: &RowSums, old: &Planes, start: usize) {
        for x in 0..self.luminance.len() {
            let (i, weights) = (start + x, sums.weights[x]);
            let lighting = [0, 1, 2].map(|c| {
                if weights > 0.0 {
                    sums.lighting[c][x] / weights
                } else {
                    old.lighting[c][i]
                }
            });
            let variance = if weights > 0.0 {
                sums.variance[x] / (weights * weights)
            } else {
                old.variance[i]
            };
            self.luminance[x] = luminance(lighting);
            for (plane, l) in self.lighting.iter_mut().zip(lighting) {
                plane[x] = if l.is_finite() { l } else { 0.0 };
            }
            self.variance[x] = variance;
            self.finite_variance[x] = if variance.is_finite() { variance } else { 0.0 };
        }
    }
}
