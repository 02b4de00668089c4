//! The growth series of a polygon reflection group (how many tiles at each word length), from
//! Steinberg's formula, independently of any enumeration.
//!
//! For an infinite Coxeter group W with generators S, 1/W(1/x) = Σ (−1)^|T| / W_T(x) over the
//! subsets T ⊆ S that generate finite groups. For a polygon these are ∅, every single wall
//! (W_T = 1 + x) and every corner of finite order k (W_T = (1 + x)(1 + x + … + x^(k−1))). So
//! W(x) = 1 / (1 − N x/(1 + x) + Σ_corners x^k / ((1 + x)(1 + x + … + x^(k−1)))), a power series
//! with integer coefficients. Finite (spherical) groups are products of dihedral and polyhedral
//! groups whose growth polynomials are products of \[dᵢ\] = 1 + x + … + x^(dᵢ−1) over their degrees.

use crate::euler::Geometry;
use crate::order::Order;
use crate::signature::{Kind, Signature};

/// The number of tiles at word lengths 0, 1, …, `depth` of the universal cover of a good
/// kaleidoscopic orbifold; `None` for bad orbifolds and non-orbifold rooms (no group), and when a
/// count exceeds `u128`.
///
/// ```
/// use orbifold::growth::growth_series;
/// // The {4,4} grid *2222: 1, 4, 8, 12, 16, …
/// let counts = growth_series(&"*2222".parse().unwrap(), 4).unwrap();
/// assert_eq!(counts, vec![1, 4, 8, 12, 16]);
/// // *235 is the icosahedral group of order 120.
/// let h3 = growth_series(&"*235".parse().unwrap(), 20).unwrap();
/// assert_eq!(h3.iter().sum::<u128>(), 120);
/// ```
pub fn growth_series(signature: &Signature, depth: usize) -> Option<Vec<u128>> {
    if signature.kind() != Kind::Orbifold {
        return None;
    }
    let orders: Vec<Option<u64>> = signature.corners().iter().map(Order::as_integer).collect();
    let n = orders.len();
    let length = depth + 1;
    match (n, signature.geometry()) {
        (0, _) => Some(truncate(vec![1, 1], length)),
        (2, _) => match orders[0] {
            Some(k) => Some(truncate(polynomial(&[2, k as usize]), length)),
            // The infinite dihedral group of the strip *∞∞: no finite corner.
            None => infinite_series(2, &[], length),
        },
        (_, Geometry::Spherical) => {
            let mut k: Vec<usize> = orders
                .iter()
                .map(|k| k.map(|k| k as usize))
                .collect::<Option<_>>()?;
            k.sort_unstable();
            let degrees: Vec<usize> = match k.as_slice() {
                [2, 2, m] => vec![2, 2, *m],
                [2, 3, 3] => vec![2, 3, 4],
                [2, 3, 4] => vec![2, 4, 6],
                [2, 3, 5] => vec![2, 6, 10],
                _ => return None,
            };
            Some(truncate(polynomial(&degrees), length))
        }
        _ => infinite_series(n, &orders, length),
    }
}

/// Π [dᵢ] with [d] = 1 + x + … + x^(d−1).
fn polynomial(degrees: &[usize]) -> Vec<i128> {
    degrees
        .iter()
        .fold(vec![1i128], |p, &d| multiply(&p, &vec![1; d], usize::MAX))
}

fn multiply(a: &[i128], b: &[i128], length: usize) -> Vec<i128> {
    let size = (a.len() + b.len() - 1).min(length);
    let mut out = vec![0i128; size];
    for (i, &x) in a.iter().enumerate().take(size) {
        for (j, &y) in b.iter().enumerate().take(size - i) {
            out[i + j] += x * y;
        }
    }
    out
}

fn truncate(mut p: Vec<i128>, length: usize) -> Vec<u128> {
    p.resize(length, 0);
    p.into_iter().map(|c| c as u128).collect()
}

/// The power series 1/q to `length` terms, for q with constant term 1; `None` on overflow.
fn inverse(q: &[i128], length: usize) -> Option<Vec<i128>> {
    let mut out = vec![0i128; length];
    out[0] = 1;
    for i in 1..length {
        let mut sum = 0i128;
        for j in 1..=i.min(q.len() - 1) {
            sum = sum.checked_add(q[j].checked_mul(out[i - j])?)?;
        }
        out[i] = -sum;
    }
    Some(out)
}

fn infinite_series(walls: usize, orders: &[Option<u64>], length: usize) -> Option<Vec<u128>> {
    let n = walls as i128;
    // 1/(1 + x) = 1 − x + x² − …
    let alternating: Vec<i128> = (0..length)
        .map(|i| if i % 2 == 0 { 1 } else { -1 })
        .collect();
    // f(1/x) = 1 − N x/(1 + x) + Σ x^k/((1 + x)[k])
    let mut f = vec![0i128; length];
    f[0] = 1;
    for i in 1..length {
        f[i] -= n * alternating[i - 1];
    }
    for k in orders.iter().flatten() {
        let k = *k as usize;
        if k >= length {
            continue;
        }
        let term = inverse(&multiply(&[1, 1], &vec![1; k], length), length - k)?;
        for (i, c) in term.iter().enumerate() {
            f[i + k] += c;
        }
    }
    let series = inverse(&f, length)?;
    series.into_iter().map(|c| u128::try_from(c).ok()).collect()
}
