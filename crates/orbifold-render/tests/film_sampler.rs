//! Tests of the random sampler, the sampling helpers and the HDR film.

use std::f64::consts::PI;
use std::io::Cursor;
use std::path::Path;

use glam::DVec3;
use orbifold_render::film::PixelFilter;
use orbifold_render::film::{Film, tone_map};
use orbifold_render::orbifold_scene::color::luminance;
use orbifold_render::sampler::{
    Distribution1d, Frame, Sampler, cosine_hemisphere, cosine_hemisphere_pdf, frame_from_normal,
    power_heuristic, to_local, to_world, uniform_cone, uniform_cone_pdf, uniform_disk_concentric,
    uniform_sphere, uniform_sphere_pdf,
};
use proptest::prelude::*;

const DRAWS: usize = 100_000;

/// Pearson's χ² of observed counts against expected counts.
fn chi_square(observed: &[u64], expected: &[f64]) -> f64 {
    observed
        .iter()
        .zip(expected)
        .map(|(&o, &e)| (o as f64 - e).powi(2) / e)
        .sum()
}

/// χ² of values that should be uniform in [0, 1), over `bins` bins.
fn uniform_chi_square(values: impl Iterator<Item = f64>, bins: usize) -> f64 {
    let mut counts = vec![0u64; bins];
    let mut n = 0usize;
    for v in values {
        assert!((0.0..=1.0).contains(&v), "{v} outside [0, 1]");
        counts[((v * bins as f64) as usize).min(bins - 1)] += 1;
        n += 1;
    }
    chi_square(&counts, &vec![n as f64 / bins as f64; bins])
}

// With 31 degrees of freedom the 99.9 % quantile of χ² is about 61.1.
const CHI2_31: f64 = 61.1;

fn uniforms(seed: u64) -> impl Iterator<Item = (f64, f64)> {
    let mut s = Sampler::new(seed, 12345, 0);
    std::iter::repeat_with(move || s.next_2d()).take(DRAWS)
}

fn close(a: f64, b: f64, rel: f64) -> bool {
    (a - b).abs() <= rel * b.abs()
}

// ---------------------------------------------------------------- sampler

#[test]
fn sampler_is_deterministic() {
    let mut a = Sampler::new(42, 17, 3);
    let mut b = Sampler::new(42, 17, 3);
    for _ in 0..1000 {
        assert_eq!(a.next_u64(), b.next_u64());
    }
    let mut a = Sampler::new(42, 17, 3);
    let mut b = Sampler::new(42, 17, 3);
    assert_eq!(a.next_2d(), b.next_2d());
    assert_eq!(a.next_u32_below(10), b.next_u32_below(10));
    assert_eq!(a.next_f64(), b.next_f64());
}

#[test]
fn different_seeds_pixels_and_samples_give_different_streams() {
    let first = |seed, pixel, sample| -> Vec<u64> {
        let mut s = Sampler::new(seed, pixel, sample);
        (0..4).map(|_| s.next_u64()).collect()
    };
    let base = first(1, 2, 3);
    assert_ne!(base, first(0, 2, 3));
    assert_ne!(base, first(1, 3, 3));
    assert_ne!(base, first(1, 2, 4));
    // Swapping the roles of pixel and sample gives another stream.
    assert_ne!(first(1, 2, 3), first(1, 3, 2));
    // All first values over a grid of (pixel, sample) are distinct.
    let mut seen = std::collections::HashSet::new();
    for pixel in 0..100 {
        for sample in 0..100 {
            assert!(seen.insert(Sampler::new(9, pixel, sample).next_u64()));
        }
    }
}

#[test]
fn neighbouring_streams_are_uncorrelated() {
    // Pearson correlation of the first uniform of pixel p and of pixel p + 1 (and of sample
    // s and s + 1): about N(0, 1/√n).
    let n = 20_000;
    for (dp, ds) in [(1, 0), (0, 1)] {
        let pairs: Vec<(f64, f64)> = (0..n)
            .map(|p| {
                (
                    Sampler::new(5, p, 0).next_f64(),
                    Sampler::new(5, p + dp, ds).next_f64(),
                )
            })
            .collect();
        let (ma, mb) = pairs.iter().fold((0.0, 0.0), |(a, b), (x, y)| {
            (a + x / n as f64, b + y / n as f64)
        });
        let cov: f64 = pairs.iter().map(|(x, y)| (x - ma) * (y - mb)).sum::<f64>();
        let va: f64 = pairs.iter().map(|(x, _)| (x - ma).powi(2)).sum::<f64>();
        let vb: f64 = pairs.iter().map(|(_, y)| (y - mb).powi(2)).sum::<f64>();
        let r = cov / (va * vb).sqrt();
        assert!(r.abs() < 0.03, "correlation {r}");
    }
}

#[test]
fn next_f64_is_uniform() {
    let mut s = Sampler::new(3, 0, 0);
    let chi2 = uniform_chi_square(std::iter::repeat_with(|| s.next_f64()).take(DRAWS), 32);
    assert!(chi2 < CHI2_31, "χ² = {chi2}");
    // Across pixels too: the first draw of each pixel's stream.
    let chi2 = uniform_chi_square(
        (0..DRAWS as u64).map(|p| Sampler::new(3, p, 0).next_f64()),
        32,
    );
    assert!(chi2 < CHI2_31, "χ² over pixels = {chi2}");
    let mut s = Sampler::new(3, 0, 0);
    for _ in 0..DRAWS {
        let (a, b) = s.next_2d();
        assert!((0.0..1.0).contains(&a) && (0.0..1.0).contains(&b));
    }
}

#[test]
fn next_u32_below_stays_in_bounds_and_is_uniform() {
    let mut s = Sampler::new(11, 1, 1);
    for n in [1, 2, 3, 7, 1000, 1 << 31, u32::MAX] {
        for _ in 0..2000 {
            assert!(s.next_u32_below(n) < n);
        }
    }
    assert!((0..100).all(|_| s.next_u32_below(1) == 0));
    let mut counts = [0u64; 6];
    for _ in 0..60_000 {
        counts[s.next_u32_below(6) as usize] += 1;
    }
    // 5 degrees of freedom: the 99.9 % quantile is about 20.5.
    let chi2 = chi_square(&counts, &[10_000.0; 6]);
    assert!(chi2 < 20.5, "χ² = {chi2} for {counts:?}");
    // A large n that is not a power of two: the top half must not be favoured.
    let n = 3 * (1u32 << 30);
    let high = (0..40_000).filter(|_| s.next_u32_below(n) >= n / 2).count();
    assert!((high as f64 / 40_000.0 - 0.5).abs() < 0.015, "{high}");
}

#[test]
#[should_panic]
fn next_u32_below_zero_panics() {
    Sampler::new(0, 0, 0).next_u32_below(0);
}

// ---------------------------------------------------------------- warping functions

#[test]
fn cosine_hemisphere_has_density_cos_over_pi() {
    let dirs: Vec<DVec3> = uniforms(1).map(cosine_hemisphere).collect();
    for w in &dirs {
        assert!((w.length() - 1.0).abs() < 1e-12 && w.z >= 0.0, "{w}");
    }
    // ∫ √z dω over the hemisphere = 4π/3, estimated as E[√z / pdf].
    let estimate = dirs
        .iter()
        .filter(|w| w.z > 0.0)
        .map(|w| w.z.sqrt() / cosine_hemisphere_pdf(w.z))
        .sum::<f64>()
        / dirs.len() as f64;
    assert!(close(estimate, 4.0 * PI / 3.0, 0.02), "{estimate}");
    // Under cos θ/π, z² is uniform and so is the azimuth.
    assert!(uniform_chi_square(dirs.iter().map(|w| w.z * w.z), 32) < CHI2_31);
    let azimuth = |w: &DVec3| (w.y.atan2(w.x) / (2.0 * PI)).rem_euclid(1.0);
    assert!(uniform_chi_square(dirs.iter().map(azimuth), 32) < CHI2_31);
    assert_eq!(cosine_hemisphere_pdf(-0.1), 0.0);
}

#[test]
fn uniform_sphere_has_density_one_over_four_pi() {
    let dirs: Vec<DVec3> = uniforms(2).map(uniform_sphere).collect();
    for w in &dirs {
        assert!((w.length() - 1.0).abs() < 1e-12, "{w}");
    }
    // E[1/pdf] is the measure 4π; ∫ (x + y + z)² dω = 4π too but tests all three axes.
    let measure = dirs.iter().map(|_| 1.0 / uniform_sphere_pdf()).sum::<f64>() / DRAWS as f64;
    assert!(close(measure, 4.0 * PI, 1e-9));
    let estimate = dirs
        .iter()
        .map(|w| (w.x + w.y + w.z).powi(2) / uniform_sphere_pdf())
        .sum::<f64>()
        / DRAWS as f64;
    assert!(close(estimate, 4.0 * PI, 0.02), "{estimate}");
    // Archimedes: z is uniform in [−1, 1].
    assert!(uniform_chi_square(dirs.iter().map(|w| (w.z + 1.0) / 2.0), 32) < CHI2_31);
    let azimuth = |w: &DVec3| (w.y.atan2(w.x) / (2.0 * PI)).rem_euclid(1.0);
    assert!(uniform_chi_square(dirs.iter().map(azimuth), 32) < CHI2_31);
}

#[test]
fn uniform_cone_has_density_one_over_its_solid_angle() {
    for cos_max in [0.95, 0.5, 0.0, -0.7] {
        let dirs: Vec<DVec3> = uniforms(3).map(|u| uniform_cone(u, cos_max)).collect();
        for w in &dirs {
            assert!((w.length() - 1.0).abs() < 1e-12, "{w}");
            assert!(
                w.z >= cos_max - 1e-12 && w.z <= 1.0,
                "{w} outside the cone {cos_max}"
            );
        }
        let pdf = uniform_cone_pdf(cos_max);
        // ∫ z dω over the cone = π(1 − cos_max²).
        let estimate = dirs.iter().map(|w| w.z / pdf).sum::<f64>() / DRAWS as f64;
        let exact = PI * (1.0 - cos_max * cos_max);
        assert!(
            (estimate - exact).abs() < 0.02 * exact.max(0.3),
            "{cos_max}: {estimate}"
        );
        // z is uniform in [cos_max, 1].
        let z = dirs.iter().map(|w| (w.z - cos_max) / (1.0 - cos_max));
        assert!(uniform_chi_square(z.map(|v| v.clamp(0.0, 1.0)), 32) < CHI2_31);
    }
    assert!(close(uniform_cone_pdf(-1.0), uniform_sphere_pdf(), 1e-15));
}

#[test]
fn concentric_disk_is_uniform_in_area() {
    let points: Vec<(f64, f64)> = uniforms(4).map(uniform_disk_concentric).collect();
    for &(x, y) in &points {
        assert!(x * x + y * y <= 1.0 + 1e-12);
    }
    // ∫ (1 + x)² dA over the unit disk = π + π/4, with the density 1/π.
    let estimate = points
        .iter()
        .map(|(x, _)| (1.0 + x).powi(2) * PI)
        .sum::<f64>()
        / DRAWS as f64;
    assert!(close(estimate, 1.25 * PI, 0.02), "{estimate}");
    assert!(uniform_chi_square(points.iter().map(|(x, y)| x * x + y * y), 32) < CHI2_31);
    let angle = |&(x, y): &(f64, f64)| (y.atan2(x) / (2.0 * PI)).rem_euclid(1.0);
    assert!(uniform_chi_square(points.iter().map(angle), 32) < CHI2_31);
    assert_eq!(uniform_disk_concentric((0.5, 0.5)), (0.0, 0.0));
}

#[test]
fn power_heuristic_is_a_partition_of_unity_and_robust() {
    for (f, g) in [(1.0, 2.0), (0.3, 0.3), (1e-300, 1e300), (5.0, 1e-9)] {
        let sum = power_heuristic(1.0, f, 1.0, g) + power_heuristic(1.0, g, 1.0, f);
        assert!((sum - 1.0).abs() < 1e-12, "{f} {g}");
    }
    assert_eq!(power_heuristic(1.0, 1.0, 1.0, 3.0), 0.1);
    assert_eq!(power_heuristic(2.0, 1.0, 1.0, 2.0), 0.5);
    assert_eq!(power_heuristic(1.0, 2.0, 1.0, 0.0), 1.0);
    assert_eq!(power_heuristic(1.0, 0.0, 1.0, 2.0), 0.0);
    assert_eq!(power_heuristic(1.0, 0.0, 1.0, 0.0), 0.0);
    assert_eq!(power_heuristic(1.0, f64::INFINITY, 1.0, 2.0), 1.0);
    assert_eq!(power_heuristic(1.0, 2.0, 1.0, f64::INFINITY), 0.0);
    assert_eq!(power_heuristic(1.0, f64::INFINITY, 1.0, f64::INFINITY), 0.5);
    assert_eq!(power_heuristic(1.0, f64::NAN, 1.0, 1.0), 0.0);
    assert_eq!(power_heuristic(1.0, 1e200, 1.0, 1e200), 0.5);
}

// ---------------------------------------------------------------- Distribution1d

#[test]
fn distribution_frequencies_follow_the_weights() {
    let weights = [1.0, 0.0, 2.0, 3.0, 0.0, 4.0, 0.0];
    let d = Distribution1d::new(&weights).unwrap();
    assert_eq!(d.len(), 7);
    assert!(!d.is_empty());
    assert_eq!(d.total(), 10.0);
    assert!(((0..d.len()).map(|i| d.pmf(i)).sum::<f64>() - 1.0).abs() < 1e-12);
    assert_eq!(d.pmf(100), 0.0);
    let mut counts = [0u64; 7];
    let mut s = Sampler::new(8, 0, 0);
    for _ in 0..DRAWS {
        let (i, p) = d.sample(s.next_f64());
        assert_eq!(p, d.pmf(i));
        counts[i] += 1;
    }
    for (i, w) in weights.iter().enumerate() {
        if *w == 0.0 {
            assert_eq!(counts[i], 0, "item {i} of zero weight was chosen");
        }
    }
    let observed: Vec<u64> = [0, 2, 3, 5].iter().map(|&i| counts[i]).collect();
    let expected: Vec<f64> = [0, 2, 3, 5]
        .iter()
        .map(|&i| DRAWS as f64 * weights[i] / 10.0)
        .collect();
    // 3 degrees of freedom: the 99.9 % quantile is about 16.3.
    let chi2 = chi_square(&observed, &expected);
    assert!(chi2 < 16.3, "χ² = {chi2} for {counts:?}");
}

#[test]
fn distribution_edges() {
    let d = Distribution1d::new(&[0.0, 0.0, 1.0, 1.0, 0.0]).unwrap();
    assert_eq!(d.sample(0.0), (2, 0.5));
    assert_eq!(d.sample(0.5), (3, 0.5));
    assert_eq!(d.sample(1.0 - f64::EPSILON / 2.0), (3, 0.5));
    assert_eq!(d.sample(1.0), (3, 0.5));
    assert_eq!(d.sample(7.0), (3, 0.5));
    assert_eq!(d.sample(-1.0), (2, 0.5));
    assert_eq!(d.sample(f64::NAN), (2, 0.5));
    // Weights with very different scales.
    let d = Distribution1d::new(&[1e-300, 1.0, 1e300]).unwrap();
    assert_eq!(d.sample(0.5).0, 2);
    // Rejected inputs.
    assert!(Distribution1d::new(&[]).is_none());
    assert!(Distribution1d::new(&[0.0; 4]).is_none());
    assert!(Distribution1d::new(&[1.0, -0.5]).is_none());
    assert!(Distribution1d::new(&[1.0, f64::INFINITY]).is_none());
    assert!(Distribution1d::new(&[1.0, f64::NAN]).is_none());
    assert!(Distribution1d::new(&[f64::MAX, f64::MAX]).is_none());
    // A single item.
    let d = Distribution1d::new(&[0.25]).unwrap();
    assert_eq!((d.sample(0.9), d.len(), d.total()), ((0, 1.0), 1, 0.25));
}

/// The item whose interval of the cumulative sums (summed as `Distribution1d::new` sums them)
/// holds `u`: cdf_i ≤ u < cdf_(i+1), by a plain binary search over all of them.
fn item_by_bisection(weights: &[f64], u: f64) -> usize {
    let total: f64 = weights.iter().sum();
    let mut running = 0.0;
    let mut cdf = vec![0.0];
    for w in weights {
        running += w;
        cdf.push(running / total);
    }
    let last = weights.iter().rposition(|w| *w > 0.0).unwrap();
    for c in &mut cdf[last + 1..] {
        *c = 1.0;
    }
    cdf.partition_point(|c| *c <= u).saturating_sub(1).min(last)
}

proptest! {
    /// The guide table only narrows the search: every uniform gets the item that a binary
    /// search over the whole cdf gives, at random uniforms, at the table's own interval ends
    /// j/M and the numbers either side of them, and at the cdf's values themselves.
    #[test]
    fn distribution_guide_table_finds_the_bisection_item(
        weights in prop::collection::vec(
            prop_oneof![Just(0.0), 0.0..1.0f64, 1e-9..1e-6f64, 1.0..1e6f64], 1..300),
        uniforms in prop::collection::vec(0.0..1.0f64, 64),
    ) {
        prop_assume!(weights.iter().any(|w| *w > 0.0));
        let d = Distribution1d::new(&weights).unwrap();
        let intervals = weights.len().next_power_of_two() as f64;
        let mut probes = uniforms.clone();
        for j in 0..=(intervals as usize) {
            let x = j as f64 / intervals;
            probes.extend([x, x.next_down(), x.next_up()]);
        }
        let mut running = 0.0;
        let total: f64 = weights.iter().sum();
        for w in &weights {
            running += w;
            probes.extend([running / total, (running / total).next_down()]);
        }
        for u in probes.into_iter().filter(|u| (0.0..=1.0).contains(u)) {
            let (i, p) = d.sample(u);
            prop_assert_eq!(i, item_by_bisection(&weights, u), "u = {}", u);
            prop_assert!(p > 0.0);
        }
    }
}

// ---------------------------------------------------------------- frames

fn check_frame(n: DVec3) {
    let (t, b) = frame_from_normal(n);
    for (v, name) in [(t, "tangent"), (b, "bitangent")] {
        assert!(
            (v.length() - 1.0).abs() < 1e-12,
            "{name} of {n} has length {}",
            v.length()
        );
        assert!(v.dot(n).abs() < 1e-12, "{name} of {n} not orthogonal to it");
    }
    assert!(t.dot(b).abs() < 1e-12);
    assert!((t.cross(b) - n).length() < 1e-12, "not right-handed at {n}");
    let v = DVec3::new(0.3, -1.2, 0.7);
    assert!((to_world(n, t, b, to_local(n, t, b, v)) - v).length() < 1e-12);
    let f = Frame::from_normal(n);
    assert_eq!((f.tangent(), f.bitangent(), f.normal()), (t, b, n));
    assert!((f.to_local(n) - DVec3::Z).length() < 1e-12);
    assert!((f.to_world(f.to_local(v)) - v).length() < 1e-12);
    assert!((f.to_local(f.to_world(v)) - v).length() < 1e-12);
}

#[test]
fn frames_at_special_normals() {
    for n in [
        DVec3::X,
        DVec3::Y,
        DVec3::Z,
        DVec3::NEG_X,
        DVec3::NEG_Y,
        DVec3::NEG_Z,
        DVec3::new(0.0, 0.0, -0.0),
        DVec3::new(1.0, 0.0, -0.0),
        DVec3::new(1e-9, 0.0, -1.0).normalize(),
        DVec3::new(0.0, 1e-9, 1.0).normalize(),
    ] {
        if n.length() > 0.5 {
            check_frame(n);
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(256))]

    #[test]
    fn frames_are_orthonormal_and_right_handed(
        x in -1.0f64..1.0,
        y in -1.0f64..1.0,
        z in -1.0f64..1.0,
    ) {
        let v = DVec3::new(x, y, z);
        prop_assume!(v.length() > 1e-3);
        check_frame(v.normalize());
    }

    #[test]
    fn frames_of_sphere_samples(u0 in 0.0f64..1.0, u1 in 0.0f64..1.0) {
        check_frame(uniform_sphere((u0, u1)));
    }
}

// ---------------------------------------------------------------- film

fn random_film(width: u32, height: u32, samples: u64, seed: u64) -> (Film, Vec<[f64; 3]>) {
    let mut film = Film::new(width, height);
    let mut all = Vec::new();
    for y in 0..height {
        for x in 0..width {
            let pixel = u64::from(y * width + x);
            for k in 0..samples {
                let mut s = Sampler::new(seed, pixel, k);
                let c = [s.next_f64() * 3.0, s.next_f64(), s.next_f64() * 0.5];
                film.add(x, y, c);
                all.push(c);
            }
        }
    }
    (film, all)
}

#[test]
fn film_pixels_are_the_mean_of_their_samples() {
    let mut film = Film::new(3, 2);
    let samples = [[1.0, 2.0, 3.0], [0.5, 0.0, 1.0], [4.5, 1.0, 2.0]];
    for s in samples {
        film.add(2, 1, s);
    }
    assert_eq!(film.pixel(2, 1), [2.0, 1.0, 2.0]);
    assert_eq!(film.samples(2, 1), 3);
    assert_eq!(film.pixel(0, 0), [0.0; 3]);
    assert_eq!(film.samples(0, 0), 0);
    assert_eq!(film.dropped(), 0);
    // Standard error of the luminance mean, by the textbook formula.
    let l: Vec<f64> = samples.iter().map(|&s| luminance(s)).collect();
    let mean = l.iter().sum::<f64>() / 3.0;
    let var = l.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / 2.0;
    assert!((film.standard_error(2, 1) - (var / 3.0).sqrt()).abs() < 1e-12);
    assert_eq!(film.standard_error(0, 0), f64::INFINITY);
    // A constant pixel has no error at all.
    let mut flat = Film::new(1, 1);
    for _ in 0..10 {
        flat.add(0, 0, [0.1, 0.7, 0.3]);
    }
    assert_eq!(flat.standard_error(0, 0), 0.0);
    assert_eq!(flat.relative_noise(), 0.0);
}

#[test]
fn relative_noise_follows_its_definition() {
    let (film, _) = random_film(4, 3, 5, 21);
    let mut expected = 0.0;
    for y in 0..3 {
        for x in 0..4 {
            let l = luminance(film.pixel(x, y));
            expected += film.standard_error(x, y) / (l + 1e-2) / 12.0;
        }
    }
    assert!((film.relative_noise() - expected).abs() < 1e-12);
    assert!(expected > 0.0);
    // More samples, less noise.
    let (more, _) = random_film(4, 3, 80, 21);
    assert!(more.relative_noise() < 0.5 * film.relative_noise());
    // Unknown noise below two samples per pixel; none for an empty film.
    assert_eq!(random_film(2, 2, 1, 0).0.relative_noise(), f64::INFINITY);
    assert_eq!(Film::new(0, 0).relative_noise(), 0.0);
}

#[test]
fn merging_equals_adding_everything() {
    let (w, h) = (5, 4);
    let mut all = Film::new(w, h);
    let mut parts = [Film::new(w, h), Film::new(w, h), Film::new(w, h)];
    let mut s = Sampler::new(77, 0, 0);
    for k in 0..300 {
        let (x, y) = (s.next_u32_below(w), s.next_u32_below(h));
        let c = if k % 50 == 0 {
            [f64::NAN, 0.0, 0.0]
        } else {
            [s.next_f64() * 10.0, s.next_f64(), s.next_f64()]
        };
        all.add(x, y, c);
        parts[s.next_u32_below(3) as usize].add(x, y, c);
    }
    let mut merged = Film::new(w, h);
    for part in &parts {
        merged.merge(part);
    }
    assert_eq!(merged.dropped(), all.dropped());
    assert_eq!(all.dropped(), 6);
    for y in 0..h {
        for x in 0..w {
            assert_eq!(merged.samples(x, y), all.samples(x, y));
            for (a, b) in merged.pixel(x, y).iter().zip(all.pixel(x, y)) {
                assert!((a - b).abs() < 1e-12);
            }
            let (ea, eb) = (merged.standard_error(x, y), all.standard_error(x, y));
            assert!(ea == eb || (ea - eb).abs() < 1e-12, "{ea} vs {eb}");
        }
    }
    assert!((merged.relative_noise() - all.relative_noise()).abs() < 1e-9);
}

/// One sample: its pixel and its radiance.
type Splat = (u32, u32, [f64; 3]);

/// A random image (a noisy value per pixel around a smooth ramp) splatted with `filter`, each
/// pixel with its own number of samples, from 1 up to `most` (as adaptive sampling leaves them).
fn splatted_film(
    (w, h): (u32, u32),
    most: u64,
    seed: u64,
    filter: PixelFilter,
) -> (Film, Vec<Splat>) {
    let mut film = Film::new(w, h);
    let mut all = Vec::new();
    for y in 0..h {
        for x in 0..w {
            let pixel = u64::from(y * w + x);
            let samples = 1 + Sampler::new(seed, pixel, u64::MAX).next_u64() % most;
            for k in 0..samples {
                let mut s = Sampler::stratified(seed, pixel, k);
                let v = 0.2 + 0.01 * f64::from(x) + s.next_f64();
                let c = [v, 0.5 * v, 2.0 * v];
                film.splat(x, y, c, filter);
                all.push((x, y, c));
            }
        }
    }
    (film, all)
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(32))]
    /// A pixel's value under a filter is the filter's weighted mean of its neighbours' own
    /// means, Σ Kⱼ mⱼ / Σ Kⱼ, however many samples each neighbour has — the mean of its samples
    /// weighted Kⱼ/nⱼ — and its standard error is that of a weighted mean of independent means,
    /// √(Σ Kⱼ² sⱼ²/nⱼ)/Σ Kⱼ with sⱼ² each neighbour's own sample variance; where a neighbour has
    /// a single sample, the textbook one of the weighted mean of all the samples,
    /// √(s²·Σw²)/Σw with s² = Σw(L − mean)²/(Σw − Σw²/Σw).
    #[test]
    fn a_filtered_pixel_is_the_weighted_mean_of_its_neighbours_means(
        seed in 0u64..1000,
        most in 1u64..12,
        gaussian in any::<bool>(),
    ) {
        let filter = if gaussian { PixelFilter::GAUSSIAN } else { PixelFilter::Box };
        let weights = filter.pixel_weights();
        let k = |d: i64| weights.iter().find(|w| i64::from(w.0) == d).map_or(0.0, |w| w.1);
        let (w, h) = (5, 4);
        let (film, all) = splatted_film((w, h), most, seed, filter);
        for y in 0..h {
            for x in 0..w {
                let reach: Vec<(f64, [f64; 3])> = all
                    .iter()
                    .filter_map(|&(i, j, c)| {
                        let kernel = k(i64::from(i) - i64::from(x)) * k(i64::from(j) - i64::from(y));
                        let n = film.samples(i, j) as f64;
                        (kernel > 0.0).then(|| (kernel / n, c))
                    })
                    .collect();
                let sw: f64 = reach.iter().map(|r| r.0).sum();
                let sw2: f64 = reach.iter().map(|r| r.0 * r.0).sum();
                let mean: [f64; 3] =
                    [0, 1, 2].map(|k| reach.iter().map(|r| r.0 * r.1[k]).sum::<f64>() / sw);
                for (a, b) in film.pixel(x, y).iter().zip(mean) {
                    prop_assert!((a - b).abs() < 1e-12 * (1.0 + b.abs()));
                }
                let l = luminance(mean);
                let m2: f64 = reach.iter().map(|r| r.0 * (luminance(r.1) - l).powi(2)).sum();
                let se = film.standard_error(x, y);
                // Each neighbour's own luminances, with its pixel weight.
                let neighbours: Vec<(f64, Vec<f64>)> = (0..h)
                    .flat_map(|j| (0..w).map(move |i| (i, j)))
                    .filter_map(|(i, j)| {
                        let kernel = k(i64::from(i) - i64::from(x)) * k(i64::from(j) - i64::from(y));
                        let own: Vec<f64> = all
                            .iter()
                            .filter(|s| (s.0, s.1) == (i, j))
                            .map(|s| luminance(s.2))
                            .collect();
                        (kernel > 0.0 && !own.is_empty()).then_some((kernel, own))
                    })
                    .collect();
                if gaussian && neighbours.iter().all(|(_, own)| own.len() >= 2) {
                    let (mut sk, mut var) = (0.0, 0.0);
                    for (kernel, own) in &neighbours {
                        let n = own.len() as f64;
                        let m = own.iter().sum::<f64>() / n;
                        let s2 = own.iter().map(|v| (v - m).powi(2)).sum::<f64>() / (n - 1.0);
                        sk += kernel;
                        var += kernel * kernel * s2 / n;
                    }
                    let expected = var.sqrt() / sk;
                    prop_assert!((se - expected).abs() < 1e-9 * (1.0 + expected), "{se} {expected}");
                } else if sw * sw > sw2 * (1.0 + 1e-6) {
                    let expected = (m2 / (sw - sw2 / sw) * sw2).sqrt() / sw;
                    prop_assert!((se - expected).abs() < 1e-9 * (1.0 + expected), "{se} {expected}");
                } else {
                    prop_assert_eq!(se, f64::INFINITY);
                }
            }
        }
    }
}

/// A sharp edge is not noise: pixels whose samples agree report no error under the filter,
/// however different their neighbours are; with noise on both sides, the error a pixel at the
/// edge reports is what it varies by from render to render (pooling the neighbours' samples
/// into one variance reported the edge's contrast instead, here over ten times the truth).
#[test]
fn an_edge_is_not_noise() {
    let (w, h, n) = (6u32, 4u32, 8u64);
    let value = |x: u32| if x < 3 { 10.0 } else { 0.1 };
    let render = |seed: u64, noise: f64| {
        let mut film = Film::new(w, h);
        let mut splats = Vec::new();
        for y in 0..h {
            for x in 0..w {
                for k in 0..n {
                    let u = Sampler::new(seed, u64::from(y * w + x), k).next_f64();
                    let v = value(x) + noise * (u - 0.5);
                    splats.push(orbifold_render::film::Splat {
                        x,
                        y,
                        radiance: [v; 3],
                    });
                }
            }
        }
        film.splat_all(&splats, PixelFilter::GAUSSIAN);
        film
    };
    let clean = render(1, 0.0);
    for y in 0..h {
        for x in 0..w {
            assert_eq!(clean.standard_error(x, y), 0.0, "({x}, {y})");
        }
    }
    // Pixel (3, 1), the dark side of the edge, over many renders.
    let renders: Vec<Film> = (0..400).map(|seed| render(seed, 1.0)).collect();
    let values: Vec<f64> = renders.iter().map(|f| luminance(f.pixel(3, 1))).collect();
    let mean = values.iter().sum::<f64>() / values.len() as f64;
    let spread = values.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / (values.len() - 1) as f64;
    let reported = renders
        .iter()
        .map(|f| f.standard_error(3, 1).powi(2))
        .sum::<f64>()
        / renders.len() as f64;
    assert!(
        (reported / spread - 1.0).abs() < 0.25,
        "{reported} vs {spread}"
    );
}

/// The bias that pbrt's splatting has under adaptive sampling, and this film has not: a sharp
/// edge between a bright and a dark half, the bright pixels sampled 50 times as often. The
/// dark pixel next to the edge must come out as with equal samples.
#[test]
fn a_neighbour_with_more_samples_weighs_no_more() {
    let (w, h) = (6, 3);
    let value = |x: u32| if x < 3 { 10.0 } else { 0.1 };
    let film_with = |bright: u64| {
        let mut film = Film::new(w, h);
        for y in 0..h {
            for x in 0..w {
                let n = if x < 3 { bright } else { 1 };
                for _ in 0..n {
                    film.splat(x, y, [value(x); 3], PixelFilter::GAUSSIAN);
                }
            }
        }
        film
    };
    let (even, skewed) = (film_with(1), film_with(50));
    for y in 0..h {
        for x in 0..w {
            let (a, b) = (even.pixel(x, y)[0], skewed.pixel(x, y)[0]);
            assert!((a - b).abs() < 1e-12 * a, "({x}, {y}): {a} vs {b}");
        }
    }
    // The dark pixel at the edge takes a little of the bright side, as a filter should.
    assert!(even.pixel(3, 1)[0] > 0.5 && even.pixel(3, 1)[0] < 3.0);
}

#[test]
fn merging_splatted_films_equals_splatting_everything() {
    let (w, h) = (6, 5);
    let (all, samples) = splatted_film((w, h), 4, 9, PixelFilter::GAUSSIAN);
    let mut parts = [Film::new(w, h), Film::new(w, h)];
    for (k, &(x, y, c)) in samples.iter().enumerate() {
        parts[k % 2].splat(x, y, c, PixelFilter::GAUSSIAN);
    }
    let mut merged = parts[0].clone();
    merged.merge(&parts[1]);
    for y in 0..h {
        for x in 0..w {
            assert_eq!(merged.samples(x, y), all.samples(x, y));
            for (a, b) in merged.pixel(x, y).iter().zip(all.pixel(x, y)) {
                assert!((a - b).abs() < 1e-12);
            }
            let (ea, eb) = (merged.standard_error(x, y), all.standard_error(x, y));
            assert!((ea - eb).abs() < 1e-12, "{ea} vs {eb}");
        }
    }
}

/// The Gaussian averages each pixel over its neighbours' samples: for independent noise its
/// pixels vary about a quarter as much as the box's (Σ K² / (Σ K)² ≈ 0.28 for the pixel
/// weights K), and the standard error it reports is what the pixels really vary by.
#[test]
fn the_gaussian_filter_lowers_the_noise_and_says_how_much() {
    let (w, h, n) = (48u32, 48u32, 8u64);
    let noise = |filter| {
        let mut film = Film::new(w, h);
        for y in 0..h {
            for x in 0..w {
                for k in 0..n {
                    let mut s = Sampler::new(3, u64::from(y * w + x), k);
                    film.splat(x, y, [s.next_f64(); 3], filter);
                }
            }
        }
        // Interior pixels: their spread about the true mean ½, and their mean reported error².
        let inner: Vec<(f64, f64)> = (2..h - 2)
            .flat_map(|y| (2..w - 2).map(move |x| (x, y)))
            .map(|(x, y)| (film.pixel(x, y)[0] - 0.5, film.standard_error(x, y)))
            .collect();
        let m = inner.len() as f64;
        let spread = inner.iter().map(|v| v.0 * v.0).sum::<f64>() / m;
        let reported = inner.iter().map(|v| v.1 * v.1).sum::<f64>() / m;
        (spread, reported)
    };
    let (box_spread, box_reported) = noise(PixelFilter::Box);
    let (gauss_spread, gauss_reported) = noise(PixelFilter::GAUSSIAN);
    // The box: variance 1/12 over 8 samples.
    assert!(
        (box_spread / (1.0 / 96.0) - 1.0).abs() < 0.1,
        "{box_spread}"
    );
    assert!((box_reported / box_spread - 1.0).abs() < 0.1);
    let ratio = gauss_spread / box_spread;
    assert!((0.25..0.42).contains(&ratio), "{ratio}");
    assert!(
        (gauss_reported / gauss_spread - 1.0).abs() < 0.15,
        "{gauss_reported} {gauss_spread}"
    );
}

#[test]
#[should_panic]
fn merging_films_of_different_sizes_panics() {
    Film::new(2, 2).merge(&Film::new(2, 3));
}

#[test]
fn rows_equal_single_samples() {
    let (w, h) = (4, 3);
    let mut by_pixel = Film::new(w, h);
    let mut by_row = Film::new(w, h);
    for pass in 0..3 {
        for y in 0..h {
            let row: Vec<[f64; 3]> = (0..w)
                .map(|x| {
                    [
                        f64::from(x + pass),
                        f64::from(y),
                        if x == 2 { f64::NAN } else { 0.5 },
                    ]
                })
                .collect();
            for (x, c) in row.iter().enumerate() {
                by_pixel.add(x as u32, y, *c);
            }
            by_row.add_row(y, &row);
        }
    }
    assert_eq!(by_pixel, by_row);
    assert_eq!(by_row.dropped(), 9);
}

#[test]
fn non_finite_samples_are_dropped_and_counted() {
    let mut film = Film::new(2, 1);
    film.add(0, 0, [1.0, 1.0, 1.0]);
    film.add(0, 0, [f64::NAN, 1.0, 1.0]);
    film.add(0, 0, [1.0, f64::INFINITY, 1.0]);
    film.add(0, 0, [1.0, 1.0, f64::NEG_INFINITY]);
    film.add(1, 0, [f64::NAN; 3]);
    assert_eq!(film.dropped(), 4);
    assert_eq!(film.pixel(0, 0), [1.0; 3]);
    assert_eq!(film.samples(0, 0), 1);
    assert_eq!(film.samples(1, 0), 0);
    assert_eq!(film.pixel(1, 0), [0.0; 3]);
    // Nothing non-finite reaches the outputs.
    let png = film.to_png_bytes(0.0).unwrap();
    assert!(image::load_from_memory(&png).is_ok());
}

#[test]
#[should_panic]
fn adding_outside_the_film_panics() {
    Film::new(2, 2).add(2, 0, [0.0; 3]);
}

#[test]
fn exr_round_trips() {
    use exr::prelude::*;

    let (w, h) = (7u32, 5u32);
    let (mut film, _) = random_film(w, h, 3, 4);
    film.add(6, 4, [1e4, 1e-6, 123.456]);
    let bytes = film.to_exr_bytes().unwrap();
    let image = read()
        .no_deep_data()
        .largest_resolution_level()
        .rgb_channels(
            |size, _| vec![vec![[0f32; 3]; size.width()]; size.height()],
            |rows: &mut Vec<Vec<[f32; 3]>>, p: Vec2<usize>, (r, g, b): (f32, f32, f32)| {
                rows[p.y()][p.x()] = [r, g, b];
            },
        )
        .first_valid_layer()
        .all_attributes()
        .from_buffered(Cursor::new(bytes))
        .unwrap();
    let layer = &image.layer_data;
    assert_eq!(layer.size, Vec2(w as usize, h as usize));
    let names: Vec<String> = {
        let (r, g, b) = &layer.channel_data.channels;
        [r, g, b].iter().map(|c| c.name.to_string()).collect()
    };
    assert_eq!(names, ["R", "G", "B"]);
    assert_eq!(layer.channel_data.channels.0.sample_type, SampleType::F32);
    let rows = &layer.channel_data.pixels;
    for y in 0..h {
        for x in 0..w {
            let expected = film.pixel(x, y).map(|v| v as f32);
            assert_eq!(rows[y as usize][x as usize], expected, "pixel ({x}, {y})");
        }
    }
}

#[test]
fn png_decodes_to_the_tone_mapped_pixels() {
    let (w, h) = (6u32, 3u32);
    let (mut film, _) = random_film(w, h, 2, 8);
    film.add(0, 2, [50.0, 0.0, 0.0]);
    for exposure in [0.0, -1.5, 2.0] {
        let png = film.to_png_bytes(exposure).unwrap();
        let decoded = image::load_from_memory_with_format(&png, image::ImageFormat::Png)
            .unwrap()
            .to_rgb8();
        assert_eq!(decoded.dimensions(), (w, h));
        for y in 0..h {
            for x in 0..w {
                assert_eq!(
                    decoded.get_pixel(x, y).0,
                    tone_map(film.pixel(x, y), exposure)
                );
            }
        }
    }
}

#[test]
fn tone_map_is_monotone_and_saturates() {
    assert_eq!(tone_map([0.0; 3], 0.0), [0; 3]);
    assert_eq!(tone_map([0.0; 3], 5.0), [0; 3]);
    assert_eq!(tone_map([1e6; 3], 0.0), [255; 3]);
    assert_eq!(tone_map([f64::INFINITY; 3], 0.0), [255; 3]);
    assert_eq!(tone_map([f64::NAN, -1.0, f64::NEG_INFINITY], 0.0), [0; 3]);
    let mut previous = 0u8;
    for k in 0..=4000 {
        let x = 1e-4 * 1.005f64.powi(k);
        let [r, g, b] = tone_map([x, x, x], 0.0);
        assert!(r == g && g == b);
        assert!(r >= previous, "not monotone at {x}");
        previous = r;
    }
    assert_eq!(previous, 255);
    // Channels are mapped independently, and an exposure of +1 stop doubles the input.
    assert_eq!(
        tone_map([0.1, 0.2, 0.4], 1.0),
        tone_map([0.2, 0.4, 0.8], 0.0)
    );
    let [r, g, b] = tone_map([0.05, 0.2, 1.0], 0.0);
    assert!(r < g && g < b);
    // Mid grey lands in the middle of the range.
    let [grey, _, _] = tone_map([0.18; 3], 0.0);
    assert!((80..=160).contains(&grey), "{grey}");
}

/// A fresh, empty directory for one test, removed when the test ends (also when it fails).
fn scratch_dir(name: &str) -> tempfile::TempDir {
    tempfile::Builder::new()
        .prefix(&format!("orbifold-film-{name}-"))
        .tempdir()
        .unwrap()
}

fn entries(dir: &Path) -> Vec<String> {
    let mut names: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    names
}

#[test]
fn write_is_atomic_and_chooses_the_format_by_extension() {
    let tmp = scratch_dir("write");
    let dir = tmp.path();
    let (film, _) = random_film(4, 4, 2, 1);
    let png = dir.join("out.png");
    let exr = dir.join("out.EXR");
    film.write(&png, 0.5).unwrap();
    film.write(&exr, 0.0).unwrap();
    assert_eq!(
        std::fs::read(&png).unwrap(),
        film.to_png_bytes(0.5).unwrap()
    );
    assert_eq!(std::fs::read(&exr).unwrap(), film.to_exr_bytes().unwrap());
    // Overwriting replaces the file, and no temporary file is left behind.
    let (other, _) = random_film(4, 4, 2, 2);
    other.write(&png, 0.5).unwrap();
    assert_eq!(
        std::fs::read(&png).unwrap(),
        other.to_png_bytes(0.5).unwrap()
    );
    assert_eq!(entries(dir), ["out.EXR", "out.png"]);

    // Unknown or missing extensions are errors that say what was wrong, and write nothing.
    let error = film.write(&dir.join("out.tiff"), 0.0).unwrap_err();
    assert!(error.contains(".tiff"), "{error}");
    let error = film.write(&dir.join("out"), 0.0).unwrap_err();
    assert!(error.contains("no extension"), "{error}");
    assert_eq!(entries(dir), ["out.EXR", "out.png"]);

    // A directory that does not exist: an error, and nothing is created.
    let missing = dir.join("missing").join("out.png");
    assert!(film.write(&missing, 0.0).is_err());
    assert_eq!(entries(dir), ["out.EXR", "out.png"]);
}

#[test]
fn a_failed_rename_leaves_no_temporary_file() {
    // The target is a non-empty directory: the rename fails after the temporary file exists.
    let tmp = scratch_dir("rename");
    let dir = tmp.path();
    let target = dir.join("taken.png");
    std::fs::create_dir(&target).unwrap();
    std::fs::write(target.join("keep"), b"x").unwrap();
    let (film, _) = random_film(2, 2, 2, 3);
    assert!(film.write(&target, 0.0).is_err());
    assert_eq!(entries(dir), ["taken.png"]);
}

/// The error of estimating the area of a disc in the unit square (π/16 for radius 1/4 about the
/// centre, an edge through many pixels' strata) with `n` points of a sampler's first two
/// dimensions, root mean square over many pixels.
fn disc_area_rms(n: u64, make: impl Fn(u64, u64) -> Sampler) -> f64 {
    let truth = PI / 16.0;
    let pixels = 400u64;
    let sum: f64 = (0..pixels)
        .map(|p| {
            let inside = (0..n)
                .filter(|&k| {
                    let (x, y) = make(p, k).next_2d();
                    (x - 0.5).powi(2) + (y - 0.5).powi(2) < 1.0 / 16.0
                })
                .count();
            (inside as f64 / n as f64 - truth).powi(2)
        })
        .sum();
    (sum / pixels as f64).sqrt()
}

#[test]
fn stratified_samples_estimate_an_edge_much_better_than_random_ones() {
    for n in [16, 64] {
        let random = disc_area_rms(n, |p, k| Sampler::new(3, p, k));
        let stratified = disc_area_rms(n, |p, k| Sampler::stratified(3, p, k));
        // Random: √(A(1 − A)/n); stratified points converge as n^(-3/4) along an edge.
        assert!(
            stratified < 0.5 * random,
            "{n} samples: stratified {stratified:.4}, random {random:.4}"
        );
    }
}

#[test]
fn stratified_streams_are_uniform_reproducible_and_aligned_per_bounce() {
    // Each dimension alone is uniform over the samples of a pixel, bounce after bounce.
    for bounce in [0u32, 3, 40] {
        let values = (0..DRAWS as u64).map(|k| {
            let mut s = Sampler::stratified(8, 5, k % 4096 + (k / 4096) * 65_536);
            s.start_bounce(bounce);
            s.next_f64()
        });
        assert!(uniform_chi_square(values, 32) < CHI2_31, "bounce {bounce}");
    }
    // Reproducible, and a bounce's numbers do not depend on how many were drawn before it
    // (but for the jitter below the f32 resolution, which comes from the random stream).
    let mut a = Sampler::stratified(1, 2, 3);
    let mut b = Sampler::stratified(1, 2, 3);
    a.next_2d();
    (0..5).for_each(|_| {
        b.next_f64();
        b.next_independent_f64();
    });
    a.start_bounce(2);
    b.start_bounce(2);
    assert!((a.next_f64() - b.next_f64()).abs() < 2.0f64.powi(-22));
    assert_eq!(
        Sampler::stratified(1, 2, 3).next_f64(),
        Sampler::stratified(1, 2, 3).next_f64()
    );
    // Different pixels are scrambled differently.
    assert_ne!(
        Sampler::stratified(1, 2, 3).next_f64(),
        Sampler::stratified(1, 9, 3).next_f64()
    );
}

/// Random samples for some random pixels of a `w` × `h` image, in pixel order (as a render's
/// round adds them): a round over a few of the pixels (the middle one always), or over all.
fn round_of_splats(rng: &mut Sampler, w: u32, h: u32) -> Vec<orbifold_render::film::Splat> {
    let share = if rng.next_f64() < 0.3 {
        1.0
    } else {
        rng.next_f64() * 0.3
    };
    let mut splats = Vec::new();
    for y in 0..h {
        for x in 0..w {
            if rng.next_f64() < share || (x, y) == (w / 2, h / 2) {
                let v = rng.next_f64() * 4.0;
                splats.push(orbifold_render::film::Splat {
                    x,
                    y,
                    radiance: [v, 0.5 * v, 1.0],
                });
            }
        }
    }
    splats
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(24))]
    /// Rounds added at once, which filter afresh only the pixels near the ones that got
    /// samples, leave the film exactly as the samples added one by one (each refiltering its
    /// neighbourhood) do, under either filter and when the filter changes between rounds.
    #[test]
    fn rounds_refilter_exactly_the_pixels_they_change(seed in 0u64..10_000, rounds in 1usize..6) {
        let (w, h) = (9u32, 7u32);
        let mut rng = Sampler::new(seed, 0, 0);
        let (mut at_once, mut one_by_one) = (Film::new(w, h), Film::new(w, h));
        for _ in 0..rounds {
            let filter = if rng.next_f64() < 0.8 { PixelFilter::GAUSSIAN } else { PixelFilter::Box };
            let splats = round_of_splats(&mut rng, w, h);
            at_once.splat_all(&splats, filter);
            for s in &splats {
                one_by_one.splat(s.x, s.y, s.radiance, filter);
            }
            prop_assert!(at_once == one_by_one, "the films differ");
        }
    }
}
