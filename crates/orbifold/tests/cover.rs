//! The universal cover against Steinberg's growth series, and its tiles against the geometry.

use orbifold::Signature;
use orbifold::cover::{Bound, Cover};
use orbifold::growth::growth_series;

fn counts(sig: &str, depth: usize) -> (Vec<u64>, Vec<u64>) {
    let s: Signature = sig.parse().unwrap();
    let cover = Cover::enumerate(&s, Bound::Depth(depth), false).unwrap();
    let series: Vec<u64> = growth_series(&s, depth)
        .unwrap()
        .into_iter()
        .map(|c| c as u64)
        .collect();
    let mut series = series;
    while series.last() == Some(&0) {
        series.pop();
    }
    (cover.counts_by_depth, series)
}

#[test]
fn counts_match_growth_series() {
    for (sig, depth) in [
        ("*2222", 12),
        ("*333", 12),
        ("*244", 12),
        ("*236", 12),
        ("*237", 14),
        ("*2222222", 7),
        ("*22222", 9),
        ("*2323", 9),
        ("*∞∞∞", 10),
        ("*2∞∞", 10),
        ("*23∞", 12),
        ("*345", 10),
        ("*444", 10),
        ("*2223", 10),
        ("*23456789(10)(11)", 6),
        ("*∞∞∞∞∞", 6),
        ("*245", 12),
        ("*334", 12),
        ("*2∞3∞", 8),
        ("*32222", 8),
        ("*222222", 8),
        ("*55", 12),
        ("*", 3),
    ] {
        let (cover, series) = counts(sig, depth);
        assert_eq!(cover, series, "{sig}");
    }
}

#[test]
fn spherical_groups_are_enumerated_completely() {
    for (sig, order) in [
        ("*", 2),
        ("*22", 4),
        ("*77", 14),
        ("*222", 8),
        ("*225", 20),
        ("*233", 24),
        ("*234", 48),
        ("*235", 120),
    ] {
        let s: Signature = sig.parse().unwrap();
        let cover = Cover::enumerate(&s, Bound::All, true).unwrap();
        assert_eq!(cover.tiles.len() as u128, s.group_order().unwrap(), "{sig}");
        assert_eq!(cover.tiles.len(), order);
        let series: Vec<u64> = growth_series(&s, 40)
            .unwrap()
            .into_iter()
            .map(|c| c as u64)
            .filter(|&c| c > 0)
            .collect();
        assert_eq!(cover.counts_by_depth, series, "{sig}");
    }
}
