//! Conway's notation for every 2D orbifold: χ, bad orbifolds, canonical forms, and the classical
//! groups (the 17 wallpaper groups are exactly the compact Euclidean orbifolds).

use std::collections::{BTreeMap, BTreeSet};

use orbifold::{Geometry, GroupFamily, OrbifoldSymbol, Order};
use proptest::prelude::*;

fn sym(s: &str) -> OrbifoldSymbol {
    s.parse().unwrap_or_else(|e| panic!("{s:?}: {e}"))
}

#[test]
fn euler_characteristics() {
    let chi = |s: &str| sym(s).euler_characteristic().to_string();
    assert_eq!(chi("632"), "0");
    assert_eq!(chi("4*2"), "0");
    assert_eq!(chi("2*22"), "0");
    assert_eq!(chi("22×"), "0");
    assert_eq!(chi("**"), "0");
    assert_eq!(chi("*×"), "0");
    assert_eq!(chi("××"), "0");
    assert_eq!(chi("o"), "0");
    assert_eq!(chi("22222"), "-1/2");
    assert_eq!(chi("532"), "1/30");
    assert_eq!(chi("1"), "2");
    assert_eq!(chi("×"), "1");
    assert_eq!(chi("oo"), "-2");
    assert_eq!(chi("*632"), "0");
    assert_eq!(chi("∞∞∞"), "-1");
    assert_eq!(sym("22222").geometry(), Geometry::Hyperbolic);
}

#[test]
fn the_seventeen_wallpaper_groups_by_name() {
    let table = [
        ("o", "p1"),
        ("2222", "p2"),
        ("**", "pm"),
        ("*×", "cm"),
        ("××", "pg"),
        ("22*", "pmg"),
        ("22×", "pgg"),
        ("*2222", "pmm"),
        ("2*22", "cmm"),
        ("442", "p4"),
        ("*442", "p4m"),
        ("4*2", "p4g"),
        ("333", "p3"),
        ("*333", "p3m1"),
        ("3*3", "p31m"),
        ("632", "p6"),
        ("*632", "p6m"),
    ];
    for (conway, name) in table {
        let group = sym(conway)
            .symmetry_group()
            .unwrap_or_else(|| panic!("{conway} unnamed"));
        assert_eq!(group.name, name, "{conway}");
        assert_eq!(group.conway, conway);
        assert_eq!(group.family, GroupFamily::Wallpaper);
        assert_eq!(sym(conway).geometry(), Geometry::Euclidean);
    }
    // Each name is read as its group's symbol: the name the symbol's group gets back.
    for (conway, name) in table {
        assert_eq!(sym(name), sym(conway), "{name}");
        assert_eq!(sym(name).symmetry_group().unwrap().name, name);
        let kaleidoscopic = sym(conway).as_kaleidoscopic().is_some();
        assert_eq!(
            name.parse::<orbifold::Signature>().is_ok(),
            kaleidoscopic,
            "{name}"
        );
    }
    assert!("p7".parse::<OrbifoldSymbol>().is_err());
    // Other spellings of the same orbifold get the same name.
    assert_eq!(sym("*236").symmetry_group().unwrap().name, "p6m");
    assert_eq!(sym("236").symmetry_group().unwrap().name, "p6");
    assert_eq!(sym("*424").symmetry_group().unwrap().name, "p4m");
    assert_eq!(sym("*x").symmetry_group().unwrap().name, "cm");
}

#[test]
fn spherical_families() {
    let name = |s: &str| sym(s).symmetry_group().map(|g| g.name);
    assert_eq!(name("1").as_deref(), Some("C1"));
    assert_eq!(name("55").as_deref(), Some("C5"));
    assert_eq!(name("5×").as_deref(), Some("S10"));
    assert_eq!(name("×").as_deref(), Some("Ci"));
    assert_eq!(name("*").as_deref(), Some("Cs"));
    assert_eq!(name("*55").as_deref(), Some("C5v"));
    assert_eq!(name("5*").as_deref(), Some("C5h"));
    assert_eq!(name("225").as_deref(), Some("D5"));
    assert_eq!(name("2*5").as_deref(), Some("D5d"));
    assert_eq!(name("*225").as_deref(), Some("D5h"));
    assert_eq!(name("332").as_deref(), Some("T"));
    assert_eq!(name("3*2").as_deref(), Some("Th"));
    assert_eq!(name("*332").as_deref(), Some("Td"));
    assert_eq!(name("432").as_deref(), Some("O"));
    assert_eq!(name("*432").as_deref(), Some("Oh"));
    assert_eq!(name("532").as_deref(), Some("I"));
    assert_eq!(name("*532").as_deref(), Some("Ih"));
    assert_eq!(name("*(12)(12)").as_deref(), Some("C12v"));
    assert_eq!(
        sym("*(12)(12)").symmetry_group().unwrap().conway,
        "*(12)(12)"
    );
    assert_eq!(sym("*532").group_order(), Some(120));
    assert_eq!(sym("532").group_order(), Some(60));
    assert_eq!(sym("3*2").group_order(), Some(24));
    assert_eq!(sym("5×").group_order(), Some(10));
}

#[test]
fn frieze_groups() {
    for (conway, name) in [
        ("∞∞", "p1"),
        ("∞×", "p11g"),
        ("*∞∞", "p1m1"),
        ("22∞", "p2"),
        ("2*∞", "p2mg"),
        ("∞*", "p11m"),
        ("*22∞", "p2mm"),
    ] {
        let group = sym(conway)
            .symmetry_group()
            .unwrap_or_else(|| panic!("{conway}"));
        assert_eq!(
            (group.name.as_str(), group.family),
            (name, GroupFamily::Frieze),
            "{conway}"
        );
        assert_eq!(sym(conway).geometry(), Geometry::Euclidean);
    }
}

#[test]
fn bad_orbifolds() {
    for s in ["2", "7", "23", "45", "∞", "2∞", "*2", "*23"] {
        assert!(sym(s).is_bad(), "{s}");
        assert!(sym(s).reason().is_some());
        assert_eq!(sym(s).group_order(), None);
    }
    for s in ["22", "77", "2*", "*22", "∞∞", "×", "2×"] {
        assert!(!sym(s).is_bad(), "{s}");
    }
    assert!(sym("23").reason().unwrap().contains("spindle"));
    assert!(sym("5").reason().unwrap().contains("teardrop"));
}

#[test]
fn hyperbolic_deformation_dimensions() {
    assert_eq!(sym("*2223").free_parameters(), 1);
    assert_eq!(sym("237").free_parameters(), 0);
    assert_eq!(sym("2222 2").free_parameters(), 4);
    assert_eq!(sym("oo").free_parameters(), 6);
    assert_eq!(sym("o2").free_parameters(), 2);
    assert_eq!(sym("2*22").free_parameters(), 1);
    assert_eq!(sym("o").free_parameters(), 2);
    assert_eq!(sym("532").free_parameters(), 0);
}

/// Every symbol whose χ could be ≥ 0: each cone costs at least 1/2 and each corner at least 1/4,
/// so the underlying surface (χ(X) = 2 − 2h − c − b) bounds how many there can be.
fn small_symbols(orders: &[Order]) -> Vec<OrbifoldSymbol> {
    let mut out = Vec::new();
    for handles in 0..=1u32 {
        for crosscaps in 0..=2u32 {
            for boundaries in 0..=2usize {
                let chi_x = 2 - 2 * handles as i64 - crosscaps as i64 - boundaries as i64;
                if chi_x < 0 {
                    continue;
                }
                let max_cones = 2 * chi_x as usize;
                for cones in multisets(orders, max_cones) {
                    let budget = 4 * chi_x as usize - 2 * cones.len();
                    for corners in boundary_lists(orders, boundaries, budget) {
                        out.push(OrbifoldSymbol::new(
                            handles,
                            cones.clone(),
                            corners,
                            crosscaps,
                        ));
                    }
                }
            }
        }
    }
    out
}

fn multisets(orders: &[Order], max: usize) -> Vec<Vec<Order>> {
    let mut out = vec![vec![]];
    for size in 1..=max {
        let mut v = vec![0usize; size];
        loop {
            out.push(v.iter().map(|&i| orders[i]).collect());
            let Some(pos) = (0..size).rev().find(|&p| v[p] + 1 < orders.len()) else {
                break;
            };
            let next = v[pos] + 1;
            v[pos..].iter_mut().for_each(|x| *x = next);
        }
    }
    out
}

fn sequences(orders: &[Order], max: usize) -> Vec<Vec<Order>> {
    let mut out = vec![vec![]];
    let mut frontier = vec![vec![]];
    for _ in 0..max {
        frontier = frontier
            .iter()
            .flat_map(|s: &Vec<Order>| orders.iter().map(move |&k| [s.clone(), vec![k]].concat()))
            .collect();
        out.extend(frontier.iter().cloned());
    }
    out
}

fn boundary_lists(orders: &[Order], count: usize, budget: usize) -> Vec<Vec<Vec<Order>>> {
    if count == 0 {
        return vec![vec![]];
    }
    let mut out = Vec::new();
    for first in sequences(orders, budget) {
        for rest in boundary_lists(orders, count - 1, budget - first.len()) {
            out.push([vec![first.clone()], rest].concat());
        }
    }
    out
}

#[test]
fn wallpaper_groups_are_exactly_the_compact_euclidean_orbifolds() {
    let orders: Vec<Order> = (2..=8).map(Order::integer).collect();
    let euclidean: BTreeMap<String, OrbifoldSymbol> = small_symbols(&orders)
        .into_iter()
        .filter(|s| s.geometry() == Geometry::Euclidean && !s.is_bad())
        .map(|s| (s.canonical().to_string(), s))
        .collect();
    assert_eq!(
        euclidean.len(),
        17,
        "{:?}",
        euclidean.keys().collect::<Vec<_>>()
    );
    let names: BTreeSet<String> = euclidean
        .values()
        .map(|s| {
            let group = s.symmetry_group().unwrap_or_else(|| panic!("{s} unnamed"));
            assert_eq!(group.family, GroupFamily::Wallpaper);
            group.name
        })
        .collect();
    assert_eq!(names.len(), 17);
}

#[test]
fn good_spherical_orbifolds_are_named_point_groups_of_order_two_over_chi() {
    let mut orders: Vec<Order> = (2..=9).map(Order::integer).collect();
    orders.push(Order::Infinite);
    let mut seen = BTreeSet::new();
    for s in small_symbols(&orders) {
        let geometry = s.geometry();
        if s.is_bad() {
            assert_eq!(
                geometry,
                Geometry::Spherical,
                "bad orbifolds have χ > 0: {s}"
            );
            continue;
        }
        let group = s.symmetry_group();
        match geometry {
            Geometry::Spherical => {
                let group = group.unwrap_or_else(|| panic!("{s} unnamed"));
                assert_eq!(group.family, GroupFamily::Spherical);
                assert!(s.group_order().is_some());
                assert_eq!(
                    sym(&group.conway).canonical(),
                    s.canonical(),
                    "{s} spelled {}",
                    group.conway
                );
                seen.insert(group.name);
            }
            Geometry::Euclidean => {
                let group = group.unwrap_or_else(|| panic!("{s} unnamed"));
                let has_cusp = s
                    .cones()
                    .iter()
                    .chain(s.boundaries().iter().flatten())
                    .any(Order::is_infinite);
                assert_eq!(group.family == GroupFamily::Frieze, has_cusp, "{s}");
                assert_eq!(sym(&group.conway).canonical(), s.canonical());
            }
            Geometry::Hyperbolic => assert!(group.is_none(), "{s}"),
        }
    }
    for name in [
        "C1", "Ci", "Cs", "T", "Th", "Td", "O", "Oh", "I", "Ih", "C7", "S14", "C7v", "C7h", "D7",
        "D7d", "D7h",
    ] {
        assert!(seen.contains(name), "{name} never produced");
    }
}

fn symbol() -> impl Strategy<Value = OrbifoldSymbol> {
    let order = prop_oneof![4 => (2u64..=7).prop_map(Order::integer), 1 => Just(Order::Infinite)];
    (
        0u32..=1,
        prop::collection::vec(order.clone(), 0..=4),
        prop::collection::vec(prop::collection::vec(order, 0..=4), 0..=3),
        0u32..=2,
    )
        .prop_map(|(h, c, b, x)| OrbifoldSymbol::new(if x > 0 { 0 } else { h }, c, b, x))
}

proptest! {
    /// Permuting cones and boundaries, rotating each boundary, and reversing (all boundaries at
    /// once, or each one alone when there is a cross-cap) never changes the canonical form.
    #[test]
    fn canonical_form_is_invariant(s in symbol(), seed in any::<u64>()) {
        let mut rng = seed;
        let mut next = move |n: usize| { rng = rng.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407); (rng >> 33) as usize % n.max(1) };
        let mut cones = s.cones().to_vec();
        let shift = next(cones.len());
        cones.rotate_left(shift);
        cones.reverse();
        let flip_all = next(2) == 1;
        let mut boundaries: Vec<Vec<Order>> = s.boundaries().iter().map(|b| {
            let mut b = b.clone();
            let n = b.len();
            let shift = next(n);
            b.rotate_left(shift);
            let flip = if s.crosscaps() > 0 { next(2) == 1 } else { flip_all };
            if flip { b.reverse(); }
            b
        }).collect();
        let n = boundaries.len();
        let shift = next(n);
        boundaries.rotate_left(shift);
        let moved = OrbifoldSymbol::new(s.handles(), cones, boundaries, s.crosscaps());
        prop_assert_eq!(moved.canonical(), s.canonical());
        prop_assert_eq!(moved.euler_characteristic(), s.euler_characteristic());
        let reread: OrbifoldSymbol = s.canonical().to_string().parse().unwrap();
        prop_assert_eq!(reread.canonical(), s.canonical());
    }
}

#[test]
fn orientable_boundaries_reverse_together() {
    // *23*45 with no cross-cap: reversing one boundary alone gives a different orbifold
    // (a chiral pair); reversing both gives the same one.
    let a = sym("*234*567").canonical();
    let b = sym("*432*567").canonical();
    let c = sym("*432*765").canonical();
    assert_ne!(a, b);
    assert_eq!(a, c);
    // With a cross-cap each boundary can be turned over alone.
    assert_eq!(sym("*234*567×").canonical(), sym("*432*567×").canonical());
}
