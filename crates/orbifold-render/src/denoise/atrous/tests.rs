//! The check of the row-wise, SIMD-friendly filter against a reference that filters one pixel
//! at a time, straight from the weights' definition.

use super::*;
use orbifold_scene::color::luminance;

/// The filter written one pixel at a time with libm's `exp` and `ln`, straight from the
/// weights' definition: the reference that the row-wise, SIMD-friendly [`AtrousFilter::smooth`]
/// must agree with.
fn smooth_one_pixel_at_a_time(
    filter: &AtrousFilter<'_>,
    mut parts: [Part; PARTS],
    rules: [PartRule; PARTS],
) -> [Part; PARTS] {
    let (w, h, o) = (filter.width, filter.height, filter.options);
    let normal = |i: usize| {
        DVec3::new(
            filter.normal[0][i],
            filter.normal[1][i],
            filter.normal[2][i],
        )
    };
    for pass in 0..o.passes {
        let step = 1usize << pass;
        let around: Vec<[f64; PARTS]> = (0..w * h)
            .map(|i| std::array::from_fn(|k| filter.blurred_variance(i, &parts[k].variance)))
            .collect();
        let filtered: Vec<[(Rgb, f64); PARTS]> = (0..w * h)
            .map(|i| {
                let (x, y) = ((i % w) as isize, (i / w) as isize);
                let trust = filter.coherence[i];
                let mut sums = [([0.0; 3], 0.0, 0.0); PARTS];
                for (dy, ky) in KERNEL.iter().enumerate() {
                    for (dx, kx) in KERNEL.iter().enumerate() {
                        let (xx, yy) = (
                            x + (dx as isize - 2) * step as isize,
                            y + (dy as isize - 2) * step as isize,
                        );
                        if xx < 0 || yy < 0 || xx >= w as isize || yy >= h as isize {
                            continue;
                        }
                        let j = yy as usize * w + xx as usize;
                        let cos = normal(i).dot(normal(j));
                        let guides = if j == i || trust <= 0.0 {
                            Some((0.0, 0.0))
                        } else if cos > 0.0 {
                            Some((trust * cos.ln(), 0.0))
                        } else {
                            None
                        };
                        let Some((normal_log, _)) = guides else {
                            continue;
                        };
                        let (zi, zj) = (filter.depth[i], filter.depth[j]);
                        let depth = if j == i {
                            0.0
                        } else {
                            -(zi - zj).abs() / (o.sigma_depth * zi.max(zj) * step as f64 + 1e-9)
                                * trust
                        };
                        for k in 0..PARTS {
                            let part = &parts[k];
                            let sharpness = match rules[k] {
                                PartRule::Rest => o.sigma_normal_rest,
                                _ => o.sigma_normal,
                            };
                            let tolerance = o.sigma_lighting * around[i][k].sqrt() + 1e-6;
                            let open = match rules[k] {
                                PartRule::SeenDirectly => filter.openness[i] * filter.openness[j],
                                _ => 1.0,
                            };
                            let weight = if j == i {
                                kx * ky
                            } else {
                                let light = -(luminance(part.lighting[i])
                                    - luminance(part.lighting[j]))
                                .abs()
                                    / tolerance;
                                open * kx * ky * (sharpness * normal_log + depth + light).exp()
                            };
                            if !(weight > 0.0 && (j == i || part.variance[j].is_finite())) {
                                continue;
                            }
                            let (sum, weights, variance) = &mut sums[k];
                            for (s, l) in sum.iter_mut().zip(part.lighting[j]) {
                                *s += weight * l;
                            }
                            *weights += weight;
                            *variance += weight * weight * part.variance[j];
                        }
                    }
                }
                std::array::from_fn(|k| {
                    let (sum, weights, variance) = sums[k];
                    (sum.map(|s| s / weights), variance / (weights * weights))
                })
            })
            .collect();
        parts = std::array::from_fn(|k| Part {
            lighting: filtered.iter().map(|f| f[k].0).collect(),
            variance: filtered.iter().map(|f| f[k].1).collect(),
        });
    }
    parts
}

#[test]
fn the_rows_in_simd_lanes_filter_as_one_pixel_at_a_time() {
    // Random guides and parts on an image of odd size (so that every tap's run is clipped
    // somewhere), with the cases the weights branch on: normals facing apart and missing
    // (nothing seen), coherences of 0, 1 and above the light's openness threshold,
    // unsampled pixels (infinite variance) and lighting far outside the tolerance.
    let (w, h) = (141usize, 23usize);
    let n = w * h;
    let mut sampler = crate::sampler::Sampler::new(99, 0, 0);
    let mut next = move || sampler.next_f64();
    let normal: Vec<DVec3> = (0..n)
        .map(|_| match (next() * 10.0) as u32 {
            0 => DVec3::ZERO,
            1 => -DVec3::Z,
            _ => DVec3::new(next() - 0.5, next() - 0.5, 2.0).normalize(),
        })
        .collect();
    let depth: Vec<f64> = (0..n).map(|_| 1.0 + 5.0 * next()).collect();
    let coherence: Vec<f64> = (0..n)
        .map(|_| match (next() * 5.0) as u32 {
            0 => 0.0,
            1 => 1.0,
            _ => next(),
        })
        .collect();
    let albedo = vec![[0.5; 3]; n];
    let part = |next: &mut dyn FnMut() -> f64| Part {
        lighting: (0..n)
            .map(|_| {
                let scale = if next() < 0.1 { 50.0 } else { 1.0 };
                [next() * scale, next() * scale, next() * scale]
            })
            .collect(),
        variance: (0..n)
            .map(|_| {
                if next() < 0.05 {
                    f64::INFINITY
                } else {
                    0.01 * next()
                }
            })
            .collect(),
    };
    for passes in [1, 3, 5] {
        let options = DenoiseOptions {
            passes,
            ..DenoiseOptions::default()
        };
        let filter = AtrousFilter::new((w, h), &albedo, &normal, &depth, &coherence, &options);
        let rules = [
            PartRule::LightSample,
            PartRule::Rest,
            PartRule::SeenDirectly,
        ];
        let parts = [part(&mut next), part(&mut next), part(&mut next)];
        let copy = |parts: &[Part; PARTS]| {
            parts.each_ref().map(|p| Part {
                lighting: p.lighting.clone(),
                variance: p.variance.clone(),
            })
        };
        let fast = filter.smooth(copy(&parts), rules);
        let slow = smooth_one_pixel_at_a_time(&filter, parts, rules);
        for k in 0..PARTS {
            for i in 0..n {
                let close = |a: f64, b: f64| {
                    a == b || (a - b).abs() <= 1e-9 * a.abs().max(b.abs()).max(1e-12)
                };
                for c in 0..3 {
                    let (a, b) = (fast[k].lighting[i][c], slow[k].lighting[i][c]);
                    assert!(
                        close(a, b),
                        "{passes} passes, part {k}, pixel {i}: {a} against {b}"
                    );
                }
                let (a, b) = (fast[k].variance[i], slow[k].variance[i]);
                assert!(
                    close(a, b),
                    "{passes} passes, part {k}, pixel {i}'s variance: {a} against {b}"
                );
            }
        }
    }
}
