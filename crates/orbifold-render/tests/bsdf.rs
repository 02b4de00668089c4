//! Tests of the BSDF module: normalisation and consistency of `eval`/`pdf`/`sample`
//! (Monte Carlo integrals and a pbrt-style chi-square test), reciprocity, energy conservation,
//! Fresnel terms, the smooth dielectric's laws of reflection and refraction, robustness
//! (property tests), and the marble texture.

use std::f64::consts::PI;

use glam::DVec3;
use orbifold_render::materials::bsdf::{Bsdf, Rgb, fresnel_conductor, fresnel_dielectric, marble};
use proptest::prelude::*;

/// A small deterministic generator (SplitMix64), independent of the renderer's sampler.
struct Rng(u64);

impl Rng {
    fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    fn f64(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 / (1u64 << 53) as f64
    }

    fn u2(&mut self) -> (f64, f64) {
        (self.f64(), self.f64())
    }
}

/// The unit direction with polar angle `theta` and azimuth `phi` (radians).
fn spherical(theta: f64, phi: f64) -> DVec3 {
    DVec3::new(
        theta.sin() * phi.cos(),
        theta.sin() * phi.sin(),
        theta.cos(),
    )
}

/// An outgoing direction at `degrees` from the normal (azimuth fixed, off the axes).
fn wo_at(degrees: f64) -> DVec3 {
    spherical(degrees.to_radians(), 0.7)
}

fn uniform_sphere(u: (f64, f64)) -> DVec3 {
    let z = 1.0 - 2.0 * u.0;
    let r = (1.0 - z * z).max(0.0).sqrt();
    let phi = 2.0 * PI * u.1;
    DVec3::new(r * phi.cos(), r * phi.sin(), z)
}

/// ∫ g(w) dw over the sphere with `n`×`n` jittered strata of (z, φ): uniform directions,
/// stratified (n² ≈ 2·10⁵ samples for n = 448).
fn integrate_sphere(n: usize, rng: &mut Rng, mut g: impl FnMut(DVec3) -> f64) -> f64 {
    let mut sum = 0.0;
    for i in 0..n {
        for j in 0..n {
            let u = (
                (i as f64 + rng.f64()) / n as f64,
                (j as f64 + rng.f64()) / n as f64,
            );
            sum += g(uniform_sphere(u));
        }
    }
    4.0 * PI * sum / (n * n) as f64
}

fn channel_mean(c: Rgb) -> f64 {
    (c[0] + c[1] + c[2]) / 3.0
}

fn close(a: f64, b: f64, rel: f64) -> bool {
    (a - b).abs() <= rel * a.abs().max(b.abs()).max(1e-300)
}

/// A conductor that reflects everything (F ≈ 1): isolates the microfacet terms.
fn white_conductor(roughness: f64) -> Bsdf {
    Bsdf::conductor([1.0; 3], [1e4; 3], roughness)
}

/// Non-delta materials (the smooth plastic has a delta coat over its diffuse base).
fn non_delta_materials() -> Vec<(&'static str, Bsdf)> {
    vec![
        ("diffuse", Bsdf::diffuse([0.7, 0.5, 0.3])),
        ("gold 0.1", Bsdf::gold(0.1)),
        ("gold 0.4", Bsdf::gold(0.4)),
        ("gold 1.0", Bsdf::gold(1.0)),
        ("plastic 0", Bsdf::plastic([0.6, 0.3, 0.2], 0.0)),
        ("plastic 0.1", Bsdf::plastic([0.6, 0.3, 0.2], 0.1)),
        ("plastic 0.4", Bsdf::plastic([0.6, 0.3, 0.2], 0.4)),
        ("plastic 1.0", Bsdf::plastic([0.9, 0.9, 0.9], 1.0)),
    ]
}

// --------------------------------------------------------------------------------------------
// (a) Normalisation of the pdf, (b) sample ⇔ eval/pdf consistency and the chi-square test.

/// ∫ pdf over the sphere equals the probability that `sample` returns a non-delta direction
/// (1 for the diffuse material; less where microfacet samples fall below the horizon or the
/// delta coat of smooth plastic is chosen), and never exceeds 1.
fn check_pdf_integral(name: &str, bsdf: &Bsdf) {
    let mut rng = Rng(0x5EED_0001);
    for degrees in [0.0, 60.0, 88.0] {
        let wo = wo_at(degrees);
        let integral = integrate_sphere(448, &mut rng, |wi| bsdf.pdf(wo, wi));
        let n = 50_000;
        let accepted = (0..n)
            .filter(|_| {
                let (u, uc) = (rng.u2(), rng.f64());
                bsdf.sample(wo, u, uc).is_some_and(|s| !s.delta)
            })
            .count() as f64
            / n as f64;
        assert!(
            integral <= 1.02,
            "{name}, θo = {degrees}°: ∫ pdf = {integral} > 1"
        );
        assert!(
            (integral - accepted).abs() < 0.03,
            "{name}, θo = {degrees}°: ∫ pdf = {integral} but {accepted} of samples are non-delta"
        );
        if matches!(bsdf, Bsdf::Diffuse { .. }) {
            assert!((integral - 1.0).abs() < 0.01, "{name}: ∫ pdf = {integral}");
        }
    }
}

/// The upper tail probability of χ² with `dof` degrees of freedom, through the
/// Wilson–Hilferty normal approximation (ample for a loose threshold).
fn chi2_z_score(chi2: f64, dof: f64) -> f64 {
    let k = 2.0 / (9.0 * dof);
    ((chi2 / dof).powf(1.0 / 3.0) - (1.0 - k)) / k.sqrt()
}

/// pbrt-style chi-square test: the histogram of sampled directions on a (θ, φ) grid against
/// the pdf integrated over each cell; plus the per-sample identities
/// weight = eval·|cos|/pdf and sample.pdf = pdf(wo, wi).
fn check_sampling(name: &str, bsdf: &Bsdf) {
    const THETA: usize = 10;
    const PHI: usize = 20;
    const SUB: usize = 16;
    let n_samples = 60_000;
    let mut rng = Rng(0x5EED_0002);
    for degrees in [30.0, 80.0] {
        let wo = wo_at(degrees);
        let mut observed = vec![0.0; THETA * PHI];
        let mut other = 0.0; // rejected or delta samples
        for _ in 0..n_samples {
            let (u, uc) = (rng.u2(), rng.f64());
            let Some(s) = bsdf.sample(wo, u, uc) else {
                other += 1.0;
                continue;
            };
            assert!((s.wi.length() - 1.0).abs() < 1e-9, "{name}: wi not unit");
            if s.delta {
                other += 1.0;
                continue;
            }
            let pdf = bsdf.pdf(wo, s.wi);
            assert!(
                close(pdf, s.pdf, 1e-9),
                "{name}: sample pdf {} vs pdf() {pdf}",
                s.pdf
            );
            let f = bsdf.eval(wo, s.wi);
            for (&w, &fc) in s.weight.iter().zip(&f) {
                let expected = fc * s.wi.z.abs() / pdf;
                assert!(
                    close(w, expected, 1e-9) || (w - expected).abs() < 1e-12,
                    "{name}: weight {:?} vs eval·cos/pdf {expected}",
                    s.weight
                );
            }
            let theta = s.wi.z.clamp(-1.0, 1.0).acos();
            let phi = s.wi.y.atan2(s.wi.x).rem_euclid(2.0 * PI);
            let ti = ((theta / PI * THETA as f64) as usize).min(THETA - 1);
            let pi = ((phi / (2.0 * PI) * PHI as f64) as usize).min(PHI - 1);
            observed[ti * PHI + pi] += 1.0;
        }
        // Expected frequencies: the pdf integrated over each cell (midpoint rule, SUB² points).
        let mut expected = vec![0.0; THETA * PHI];
        let (dt, dp) = (PI / THETA as f64, 2.0 * PI / PHI as f64);
        for ti in 0..THETA {
            for pi in 0..PHI {
                let mut sum = 0.0;
                for a in 0..SUB {
                    let theta = (ti as f64 + (a as f64 + 0.5) / SUB as f64) * dt;
                    for b in 0..SUB {
                        let phi = (pi as f64 + (b as f64 + 0.5) / SUB as f64) * dp;
                        sum += bsdf.pdf(wo, spherical(theta, phi)) * theta.sin();
                    }
                }
                expected[ti * PHI + pi] = sum * dt * dp / (SUB * SUB) as f64 * n_samples as f64;
            }
        }
        let expected_other = (n_samples as f64 - expected.iter().sum::<f64>()).max(0.0);
        observed.push(other);
        expected.push(expected_other);
        // Pool the cells with small expectations, as pbrt does.
        let (mut chi2, mut dof) = (0.0f64, 0.0f64);
        let (mut pooled_obs, mut pooled_exp) = (0.0, 0.0);
        for (&o, &e) in observed.iter().zip(&expected) {
            if e == 0.0 {
                assert!(
                    o <= 1.0,
                    "{name}, θo = {degrees}°: {o} samples where the pdf is zero"
                );
            } else if e < 5.0 {
                pooled_obs += o;
                pooled_exp += e;
            } else {
                chi2 += (o - e) * (o - e) / e;
                dof += 1.0;
            }
        }
        if pooled_exp > 0.0 {
            chi2 += (pooled_obs - pooled_exp) * (pooled_obs - pooled_exp) / pooled_exp;
            dof += 1.0;
        }
        dof -= 1.0;
        let z = chi2_z_score(chi2, dof.max(1.0));
        assert!(
            z < 5.0,
            "{name}, θo = {degrees}°: χ² = {chi2:.1} for {dof} degrees of freedom (z = {z:.2})"
        );
    }
}

#[test]
fn diffuse_pdf_and_sampling() {
    let bsdf = Bsdf::diffuse([0.7, 0.5, 0.3]);
    check_pdf_integral("diffuse", &bsdf);
    check_sampling("diffuse", &bsdf);
}

#[test]
fn conductor_pdf_and_sampling() {
    for (name, bsdf) in non_delta_materials() {
        if matches!(bsdf, Bsdf::Conductor { .. }) {
            check_pdf_integral(name, &bsdf);
            check_sampling(name, &bsdf);
        }
    }
}

#[test]
fn plastic_pdf_and_sampling() {
    for (name, bsdf) in non_delta_materials() {
        if matches!(bsdf, Bsdf::Plastic { .. }) {
            check_pdf_integral(name, &bsdf);
            check_sampling(name, &bsdf);
        }
    }
}

#[test]
fn rough_microfacets_reject_some_grazing_samples() {
    // The visible-normal sampler still reflects some directions below the horizon: the pdf
    // integrates to less than 1 there (and `check_pdf_integral` shows it matches the rate).
    let bsdf = Bsdf::gold(1.0);
    let wo = wo_at(85.0);
    let mut rng = Rng(3);
    let rejected = (0..10_000)
        .filter(|_| bsdf.sample(wo, rng.u2(), 0.5).is_none())
        .count();
    assert!(rejected > 100, "{rejected}");
}

// --------------------------------------------------------------------------------------------
// (c) Reciprocity.

#[test]
fn reciprocity() {
    let materials = [
        Bsdf::diffuse([0.7, 0.5, 0.3]),
        Bsdf::gold(0.05),
        Bsdf::copper(0.3),
        Bsdf::aluminium(1.0),
        // With the smooth-interface transmittance factors the plastic approximation happens to
        // be reciprocal too (Mitsuba's tabulated rough transmittances, and pbrt-v3's
        // FresnelBlend, are not exactly); its sampling probabilities are not symmetric.
        Bsdf::plastic([0.6, 0.3, 0.2], 0.0),
        Bsdf::plastic([0.6, 0.3, 0.2], 0.3),
    ];
    let mut rng = Rng(0x5EED_0003);
    for bsdf in materials {
        for _ in 0..2000 {
            let a = uniform_sphere(rng.u2());
            let b = uniform_sphere(rng.u2());
            let (wo, wi) = (
                DVec3::new(a.x, a.y, a.z.abs()),
                DVec3::new(b.x, b.y, b.z.abs()),
            );
            let (f, g) = (bsdf.eval(wo, wi), bsdf.eval(wi, wo));
            for c in 0..3 {
                assert!(
                    close(f[c], g[c], 1e-9) || (f[c] - g[c]).abs() < 1e-14,
                    "{bsdf:?}: f(wo, wi) = {f:?} but f(wi, wo) = {g:?}"
                );
            }
        }
    }
}

// --------------------------------------------------------------------------------------------
// (d) Energy.

/// The directional albedo ∫ f |cos θi| dwi by uniform (stratified) sphere sampling, per channel.
fn albedo_uniform(bsdf: &Bsdf, wo: DVec3, n: usize, rng: &mut Rng) -> Rgb {
    std::array::from_fn(|c| integrate_sphere(n, rng, |wi| bsdf.eval(wo, wi)[c] * wi.z.abs()))
}

/// The expected sample weight: the albedo including delta components, by importance sampling.
fn albedo_sampled(bsdf: &Bsdf, wo: DVec3, n: usize, rng: &mut Rng) -> Rgb {
    let mut sum = [0.0; 3];
    for _ in 0..n {
        if let Some(s) = bsdf.sample(wo, rng.u2(), rng.f64()) {
            for (total, w) in sum.iter_mut().zip(s.weight) {
                *total += w;
            }
        }
    }
    sum.map(|x| x / n as f64)
}

#[test]
fn white_diffuse_has_albedo_one() {
    let bsdf = Bsdf::diffuse([1.0; 3]);
    let mut rng = Rng(0x5EED_0004);
    for degrees in [0.0, 45.0, 89.9] {
        let wo = wo_at(degrees);
        let a = albedo_uniform(&bsdf, wo, 300, &mut rng);
        assert!(a.iter().all(|&x| (x - 1.0).abs() < 0.005), "{a:?}");
        for _ in 0..1000 {
            let s = bsdf.sample(wo, rng.u2(), rng.f64()).unwrap();
            assert_eq!(s.weight, [1.0; 3]);
        }
    }
}

#[test]
fn white_rough_materials_conserve_energy() {
    let mut rng = Rng(0x5EED_0005);
    let materials = [
        ("white conductor 0.05", white_conductor(0.05)),
        ("white conductor 0.3", white_conductor(0.3)),
        ("white conductor 1.0", white_conductor(1.0)),
        ("white plastic 0", Bsdf::plastic([1.0; 3], 0.0)),
        ("white plastic 0.2", Bsdf::plastic([1.0; 3], 0.2)),
        ("white plastic 1.0", Bsdf::plastic([1.0; 3], 1.0)),
    ];
    for (name, bsdf) in materials {
        for degrees in [0.0, 50.0, 80.0, 89.0] {
            let wo = wo_at(degrees);
            let sampled = channel_mean(albedo_sampled(&bsdf, wo, 20_000, &mut rng));
            assert!(
                sampled <= 1.0 + 1e-3,
                "{name}, θo = {degrees}°: albedo {sampled}"
            );
            if matches!(bsdf, Bsdf::Plastic { roughness, .. } if roughness > 0.0)
                || matches!(bsdf, Bsdf::Conductor { roughness, .. } if roughness >= 0.3)
            {
                // Independent estimate by uniform sampling (the smooth coat's delta part is
                // invisible to eval, and narrow lobes need too many uniform samples).
                let uniform = channel_mean(albedo_uniform(&bsdf, wo, 200, &mut rng));
                assert!(uniform <= 1.02, "{name}, θo = {degrees}°: albedo {uniform}");
                assert!(
                    (uniform - sampled).abs() < 0.02,
                    "{name}, θo = {degrees}°: uniform {uniform} vs sampled {sampled}"
                );
            }
            if matches!(bsdf, Bsdf::Plastic { .. }) && degrees <= 50.0 {
                // A white base under a clear coat loses little: most light comes back.
                assert!(sampled > 0.9, "{name}, θo = {degrees}°: albedo {sampled}");
            }
        }
    }
}

#[test]
fn smooth_conductor_and_dielectric_weights_at_most_one() {
    let mut rng = Rng(0x5EED_0006);
    let metals = [
        Bsdf::gold(0.0),
        Bsdf::silver(0.0),
        Bsdf::copper(0.0),
        Bsdf::aluminium(0.0),
    ];
    for bsdf in metals {
        assert!(bsdf.is_delta());
        for degrees in [0.0, 30.0, 60.0, 85.0, 89.99] {
            let wo = wo_at(degrees);
            let s = bsdf.sample(wo, rng.u2(), rng.f64()).unwrap();
            assert!(s.delta);
            assert!((s.wi - DVec3::new(-wo.x, -wo.y, wo.z)).length() < 1e-15);
            assert!(s.weight.iter().all(|&w| (0.0..=1.0).contains(&w)), "{s:?}");
            assert_eq!(bsdf.eval(wo, s.wi), [0.0; 3]);
            assert_eq!(bsdf.pdf(wo, s.wi), 0.0);
        }
    }
    let glass = Bsdf::Dielectric {
        eta: 1.5,
        tint: [0.9, 0.8, 1.0],
    };
    for _ in 0..2000 {
        let wo = uniform_sphere(rng.u2());
        let s = glass.sample(wo, rng.u2(), rng.f64()).unwrap();
        let refracted = s.wi.z * wo.z < 0.0;
        if !refracted {
            assert_eq!(s.weight, [1.0; 3]);
        } else if wo.z > 0.0 {
            // Entering: T / (T · η²) · tint.
            assert!(s.weight.iter().all(|&w| w <= 1.0), "{s:?}");
        } else {
            // Leaving: radiance scaled up by η² (undoes the entry's 1/η² on a round trip).
            for c in 0..3 {
                assert!(close(s.weight[c], 2.25 * [0.9, 0.8, 1.0][c], 1e-12));
            }
        }
    }
}

// --------------------------------------------------------------------------------------------
// Fresnel.

#[test]
fn dielectric_fresnel() {
    for eta in [1.1f64, 1.33, 1.5, 2.4] {
        let r0 = ((eta - 1.0) / (eta + 1.0)).powi(2);
        assert!(close(fresnel_dielectric(1.0, eta), r0, 1e-12));
        assert!(
            close(fresnel_dielectric(-1.0, eta), r0, 1e-12),
            "from inside"
        );
        assert_eq!(fresnel_dielectric(0.0, eta), 1.0);
        assert!(fresnel_dielectric(1e-9, eta) > 0.999_999);
        // Total internal reflection beyond the critical angle, from inside.
        let critical = (1.0 / eta).asin();
        assert_eq!(fresnel_dielectric(-(critical + 1e-6).cos(), eta), 1.0);
        assert_eq!(fresnel_dielectric(-0.01, eta), 1.0);
        assert!(fresnel_dielectric(-(critical - 1e-3).cos(), eta) < 1.0);
        // Monotone in the angle from outside, within [0, 1].
        let mut last = 0.0;
        for i in (0..=100).rev() {
            let r = fresnel_dielectric(i as f64 / 100.0, eta);
            assert!((0.0..=1.0).contains(&r) && r >= last - 1e-15);
            last = r;
        }
    }
    assert_eq!(fresnel_dielectric(0.7, 1.0), 0.0);
}

#[test]
fn conductor_fresnel() {
    let mut rng = Rng(0x5EED_0007);
    for bsdf in [
        Bsdf::gold(0.0),
        Bsdf::silver(0.0),
        Bsdf::copper(0.0),
        Bsdf::aluminium(0.0),
    ] {
        let Bsdf::Conductor { eta, k, .. } = bsdf else {
            unreachable!()
        };
        let r0 = fresnel_conductor(1.0, eta, k);
        for c in 0..3 {
            let expected =
                ((eta[c] - 1.0).powi(2) + k[c] * k[c]) / ((eta[c] + 1.0).powi(2) + k[c] * k[c]);
            assert!(close(r0[c], expected, 1e-12));
        }
        for _ in 0..1000 {
            let r = fresnel_conductor(rng.f64(), eta, k);
            assert!(r.iter().all(|x| (0.0..=1.0).contains(x)));
        }
        assert!(
            fresnel_conductor(0.0, eta, k)
                .iter()
                .all(|&x| close(x, 1.0, 1e-12))
        );
        assert!(fresnel_conductor(1e-6, eta, k).iter().all(|&x| x > 0.9999));
        assert!(fresnel_conductor(0.01, eta, k).iter().all(|&x| x > 0.95));
    }
    // With k = 0 the conductor formula is the dielectric one.
    for i in 0..=20 {
        let cos = i as f64 / 20.0;
        let r = fresnel_conductor(cos, [1.5; 3], [0.0; 3]);
        assert!(close(r[0], fresnel_dielectric(cos, 1.5), 1e-9) || cos == 0.0);
    }
}

// --------------------------------------------------------------------------------------------
// The smooth dielectric.

#[test]
fn dielectric_obeys_snell_and_reflection_laws() {
    let eta = 1.5;
    let glass = Bsdf::dielectric(eta);
    let mut rng = Rng(0x5EED_0008);
    let (mut reflections, mut refractions) = (0, 0);
    for _ in 0..20_000 {
        let wo = uniform_sphere(rng.u2());
        let s = glass.sample(wo, rng.u2(), rng.f64()).unwrap();
        assert!(s.delta);
        assert!((s.wi.length() - 1.0).abs() < 1e-12);
        if s.wi.z * wo.z > 0.0 || wo.z == 0.0 {
            reflections += 1;
            assert_eq!(s.wi, DVec3::new(-wo.x, -wo.y, wo.z));
        } else {
            refractions += 1;
            // Snell: n_o sin θo = n_i sin θi, with the outside index 1 and the inside η.
            let (n_o, n_i) = if wo.z > 0.0 { (1.0, eta) } else { (eta, 1.0) };
            let sin_o = wo.truncate().length();
            let sin_i = s.wi.truncate().length();
            assert!((n_o * sin_o - n_i * sin_i).abs() < 1e-12, "{wo} → {}", s.wi);
            // In the plane of incidence, on the other side of the normal.
            assert!(wo.truncate().perp_dot(s.wi.truncate()).abs() < 1e-12);
            assert!(wo.truncate().dot(s.wi.truncate()) <= 0.0);
        }
    }
    assert!(reflections > 500 && refractions > 10_000);
}

#[test]
fn dielectric_reflects_with_fresnel_probability() {
    let glass = Bsdf::dielectric(1.5);
    let mut rng = Rng(0x5EED_0009);
    // Outside at 70°, inside at 30° (below the critical angle 41.8°), outside near grazing.
    for wo in [wo_at(70.0), -wo_at(30.0), wo_at(87.0)] {
        let f = fresnel_dielectric(wo.z, 1.5);
        let n = 100_000;
        let reflected = (0..n)
            .filter(|_| {
                let s = glass.sample(wo, rng.u2(), rng.f64()).unwrap();
                let is_reflection = s.wi.z * wo.z > 0.0;
                let expected_pdf = if is_reflection { f } else { 1.0 - f };
                assert!(close(s.pdf, expected_pdf, 1e-12));
                is_reflection
            })
            .count() as f64;
        let sigma = (n as f64 * f * (1.0 - f)).sqrt();
        assert!(
            (reflected - n as f64 * f).abs() < 5.0 * sigma,
            "{reflected} reflections of {n}, Fresnel {f}"
        );
    }
    // Total internal reflection: always reflects.
    let wo = -wo_at(60.0);
    for _ in 0..1000 {
        let s = glass.sample(wo, rng.u2(), rng.f64()).unwrap();
        assert_eq!(s.wi, DVec3::new(-wo.x, -wo.y, wo.z));
        assert_eq!(s.weight, [1.0; 3]);
    }
}

#[test]
fn opaque_materials_ignore_directions_below_the_surface() {
    let mut rng = Rng(0x5EED_000A);
    for bsdf in [
        Bsdf::diffuse([0.5; 3]),
        Bsdf::gold(0.0),
        Bsdf::gold(0.3),
        Bsdf::plastic([0.5; 3], 0.0),
        Bsdf::plastic([0.5; 3], 0.3),
    ] {
        let below = -wo_at(40.0);
        assert!(bsdf.sample(below, rng.u2(), rng.f64()).is_none());
        assert_eq!(bsdf.eval(below, DVec3::Z), [0.0; 3]);
        assert_eq!(bsdf.pdf(below, DVec3::Z), 0.0);
        assert_eq!(bsdf.eval(DVec3::Z, below), [0.0; 3]);
        assert_eq!(bsdf.pdf(DVec3::Z, below), 0.0);
        let grazing = DVec3::X;
        assert!(bsdf.sample(grazing, rng.u2(), rng.f64()).is_none());
        assert_eq!(bsdf.eval(DVec3::Z, grazing), [0.0; 3]);
    }
}

// --------------------------------------------------------------------------------------------
// Robustness.

fn direction() -> impl Strategy<Value = DVec3> {
    prop_oneof![
        // Anywhere on the sphere.
        (-1.0f64..=1.0, 0.0f64..(2.0 * PI)).prop_map(|(z, phi)| {
            let r = (1.0 - z * z).max(0.0).sqrt();
            DVec3::new(r * phi.cos(), r * phi.sin(), z)
        }),
        // Exactly or nearly grazing, on either side.
        (
            prop_oneof![
                Just(0.0),
                Just(-0.0),
                Just(1e-300),
                Just(-1e-300),
                Just(1e-12),
                Just(-1e-12),
                Just(1e-6),
            ],
            0.0f64..(2.0 * PI)
        )
            .prop_map(|(z, phi): (f64, f64)| {
                let r = (1.0 - z * z).sqrt();
                DVec3::new(r * phi.cos(), r * phi.sin(), z)
            }),
        // Along the normal.
        prop_oneof![Just(DVec3::Z), Just(-DVec3::Z)],
    ]
}

fn roughness() -> impl Strategy<Value = f64> {
    prop_oneof![
        Just(0.0),
        Just(1e-4),
        Just(1e-3),
        Just(1e-3 - 1e-12),
        Just(1.0),
        Just(2.0),
        0.0f64..=1.0,
    ]
}

fn unit_interval() -> impl Strategy<Value = f64> {
    prop_oneof![
        Just(0.0),
        Just(1.0 - f64::EPSILON / 2.0),
        Just(0.5),
        0.0f64..1.0
    ]
}

fn material() -> impl Strategy<Value = Bsdf> {
    let colour = || prop::array::uniform3(0.0f64..=1.0);
    prop_oneof![
        colour().prop_map(Bsdf::diffuse),
        (prop_oneof![Just(1.0), Just(1.5), 0.2f64..4.0], colour())
            .prop_map(|(eta, tint)| Bsdf::Dielectric { eta, tint }),
        (
            prop::array::uniform3(0.0f64..5.0),
            prop::array::uniform3(0.0f64..10.0),
            roughness()
        )
            .prop_map(|(eta, k, r)| Bsdf::conductor(eta, k, r)),
        roughness().prop_map(Bsdf::gold),
        (colour(), roughness(), prop_oneof![Just(1.0), 1.0f64..3.0]).prop_map(
            |(albedo, roughness, eta)| Bsdf::Plastic {
                albedo,
                roughness,
                eta
            }
        ),
    ]
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 2000, ..ProptestConfig::default() })]

    #[test]
    fn never_nan_or_negative(
        bsdf in material(),
        wo in direction(),
        wi in direction(),
        u0 in unit_interval(),
        u1 in unit_interval(),
        uc in unit_interval(),
    ) {
        let f = bsdf.eval(wo, wi);
        prop_assert!(f.iter().all(|x| x.is_finite() && *x >= 0.0), "eval {:?}", f);
        let p = bsdf.pdf(wo, wi);
        prop_assert!(p.is_finite() && p >= 0.0, "pdf {}", p);
        if let Some(s) = bsdf.sample(wo, (u0, u1), uc) {
            prop_assert!(s.wi.is_finite() && (s.wi.length() - 1.0).abs() < 1e-9, "{:?}", s);
            prop_assert!(s.pdf.is_finite() && s.pdf > 0.0, "{:?}", s);
            prop_assert!(s.weight.iter().all(|x| x.is_finite() && *x >= 0.0), "{:?}", s);
            let f = bsdf.eval(wo, s.wi);
            let p = bsdf.pdf(wo, s.wi);
            prop_assert!(f.iter().all(|x| x.is_finite()) && p.is_finite());
        }
        let c = fresnel_dielectric(wo.z, 1.5);
        prop_assert!((0.0..=1.0).contains(&c));
        let c = fresnel_conductor(wo.z, [0.2, 0.9, 1.1], [3.9, 2.5, 2.1]);
        prop_assert!(c.iter().all(|x| (0.0..=1.0).contains(x)));
    }
}

// --------------------------------------------------------------------------------------------
// Marble.

const BASE: Rgb = [0.92, 0.9, 0.86];
const VEIN: Rgb = [0.25, 0.3, 0.4];

#[test]
fn marble_is_deterministic_and_bounded() {
    let mut rng = Rng(0x5EED_000B);
    let mut min = [f64::INFINITY; 3];
    let mut max = [f64::NEG_INFINITY; 3];
    for _ in 0..20_000 {
        let p = DVec3::new(rng.f64(), rng.f64(), rng.f64()) * 200.0 - 100.0;
        let scale = 0.1 + 5.0 * rng.f64();
        let c = marble(p, BASE, VEIN, scale);
        assert_eq!(c, marble(p, BASE, VEIN, scale));
        for i in 0..3 {
            assert!(VEIN[i] <= c[i] && c[i] <= BASE[i], "{c:?}");
            min[i] = min[i].min(c[i]);
            max[i] = max[i].max(c[i]);
        }
        // Swapped colours stay within the same bounds.
        let d = marble(p, VEIN, BASE, scale);
        assert!((0..3).all(|i| VEIN[i] <= d[i] && d[i] <= BASE[i]));
    }
    // Both the ground and the veins actually occur.
    for i in 0..3 {
        assert!(
            max[i] - min[i] > 0.5 * (BASE[i] - VEIN[i]),
            "{min:?} {max:?}"
        );
    }
    // Far away, and with non-finite input.
    for p in [DVec3::splat(1e12), DVec3::new(-1e15, 3.0, 7e9)] {
        let c = marble(p, BASE, VEIN, 1.0);
        assert!((0..3).all(|i| VEIN[i] <= c[i] && c[i] <= BASE[i]));
    }
    assert_eq!(marble(DVec3::splat(f64::NAN), BASE, VEIN, 1.0), BASE);
    assert_eq!(marble(DVec3::ONE, BASE, VEIN, f64::INFINITY), BASE);
}

#[test]
fn marble_is_continuous() {
    let mut rng = Rng(0x5EED_000C);
    for _ in 0..5000 {
        let p = DVec3::new(rng.f64(), rng.f64(), rng.f64()) * 20.0 - 10.0;
        let step = uniform_sphere(rng.u2()) * 1e-7;
        let (a, b) = (
            marble(p, BASE, VEIN, 2.0),
            marble(p + step, BASE, VEIN, 2.0),
        );
        for i in 0..3 {
            assert!((a[i] - b[i]).abs() < 1e-4, "{p}: {a:?} vs {b:?}");
        }
    }
    // Across integer lattice planes too (where the noise changes cells).
    for i in -5..5 {
        let p = DVec3::new(i as f64 * 0.5, 0.25, -0.75);
        let (a, b) = (
            marble(p - DVec3::X * 1e-9, BASE, VEIN, 2.0),
            marble(p + DVec3::X * 1e-9, BASE, VEIN, 2.0),
        );
        assert!((0..3).all(|c| (a[c] - b[c]).abs() < 1e-5));
    }
}
