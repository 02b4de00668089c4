//! Procedural marble (Perlin 1985): veins of one colour in a ground of another, the level sets
//! of a sine perturbed by turbulence, a sum of octaves of |gradient noise|. A solid texture: it
//! is a function of the point in space, so that an object's surface cuts through its veins.

use std::f64::consts::PI;

use glam::DVec3;

use crate::lights::Rgb;

/// A procedural marble albedo at the point `p`: veins of colour `vein` in a `base` ground,
/// the veins being the level sets of a sine of x perturbed by turbulence (a sum of octaves of
/// |gradient noise|, Perlin 1985). `scale` is the spatial frequency (features about 1/`scale`
/// across). The result is deterministic, continuous in `p`, and each channel lies between
/// `base` and `vein`. Non-finite `p` or `scale` give `base`.
///
/// The noise is Perlin's improved gradient noise with a quintic fade, its lattice gradients
/// chosen by a SplitMix64 hash of the integer cell coordinates (no permutation table).
///
/// ```
/// use glam::DVec3;
/// use orbifold_render::textures::marble;
///
/// let (base, vein) = ([0.9, 0.9, 0.85], [0.2, 0.25, 0.3]);
/// let c = marble(DVec3::new(0.3, -1.2, 4.0), base, vein, 2.0);
/// for i in 0..3 {
///     assert!(vein[i] <= c[i] && c[i] <= base[i]);
/// }
/// assert_eq!(c, marble(DVec3::new(0.3, -1.2, 4.0), base, vein, 2.0));
/// ```
pub fn marble(p: DVec3, base: Rgb, vein: Rgb, scale: f64) -> Rgb {
    let q = p * scale;
    if !q.is_finite() {
        return base;
    }
    let turb = turbulence(q, 6);
    let s = (PI * (q.x + 0.5 * q.y + 3.0 * turb)).sin();
    // Narrow veins where the sine crosses zero.
    let t = (1.0 - s.abs()).clamp(0.0, 1.0).powi(4);
    std::array::from_fn(|c| {
        let (lo, hi) = (base[c].min(vein[c]), base[c].max(vein[c]));
        (base[c] + (vein[c] - base[c]) * t).clamp(lo, hi)
    })
}

/// Σₒ |noise(2ᵒ p)| / 2ᵒ over `octaves` octaves.
fn turbulence(p: DVec3, octaves: u32) -> f64 {
    let mut sum = 0.0;
    let mut frequency = 1.0;
    for _ in 0..octaves {
        sum += gradient_noise(p * frequency).abs() / frequency;
        frequency *= 2.0;
    }
    sum
}

/// Perlin's improved gradient noise: a C² function of `p`, zero on the integer lattice, of
/// magnitude about 1 at most.
fn gradient_noise(p: DVec3) -> f64 {
    let cell = p.floor();
    let f = p - cell;
    let i = [cell.x as i64, cell.y as i64, cell.z as i64];
    let fade = |t: f64| t * t * t * (t * (t * 6.0 - 15.0) + 10.0);
    let (u, v, w) = (fade(f.x), fade(f.y), fade(f.z));
    let corner = |dx: i64, dy: i64, dz: i64| {
        let g = lattice_gradient(
            i[0].wrapping_add(dx),
            i[1].wrapping_add(dy),
            i[2].wrapping_add(dz),
        );
        g.dot(f - DVec3::new(dx as f64, dy as f64, dz as f64))
    };
    let lerp = |t: f64, a: f64, b: f64| a + t * (b - a);
    let x00 = lerp(u, corner(0, 0, 0), corner(1, 0, 0));
    let x10 = lerp(u, corner(0, 1, 0), corner(1, 1, 0));
    let x01 = lerp(u, corner(0, 0, 1), corner(1, 0, 1));
    let x11 = lerp(u, corner(0, 1, 1), corner(1, 1, 1));
    lerp(w, lerp(v, x00, x10), lerp(v, x01, x11))
}

/// One of Perlin's 12 cube-edge gradients, chosen by a hash of the lattice point.
fn lattice_gradient(x: i64, y: i64, z: i64) -> DVec3 {
    const GRADIENTS: [[f64; 3]; 12] = [
        [1.0, 1.0, 0.0],
        [-1.0, 1.0, 0.0],
        [1.0, -1.0, 0.0],
        [-1.0, -1.0, 0.0],
        [1.0, 0.0, 1.0],
        [-1.0, 0.0, 1.0],
        [1.0, 0.0, -1.0],
        [-1.0, 0.0, -1.0],
        [0.0, 1.0, 1.0],
        [0.0, -1.0, 1.0],
        [0.0, 1.0, -1.0],
        [0.0, -1.0, -1.0],
    ];
    let h = splitmix64(splitmix64(splitmix64(x as u64) ^ y as u64) ^ z as u64);
    DVec3::from(GRADIENTS[(h % 12) as usize])
}

/// The SplitMix64 finaliser (Steele, Lea & Flood 2014).
fn splitmix64(x: u64) -> u64 {
    let mut z = x.wrapping_add(0x9E37_79B9_7F4A_7C15);
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^ (z >> 31)
}
