//! Enumeration against brute force, against the bracelet-counting formula, and against Table 4.1.

use std::collections::BTreeSet;

use orbifold::necklace::Bracelets;
use orbifold::table::{FAMILIES, Walls};
use orbifold::{Enumeration, EnumerationOptions, Geometry, Kind, Order, Signature};

fn alphabet(max_order: u64, ideal: bool) -> Vec<Order> {
    let mut a: Vec<Order> = (2..=max_order).map(Order::integer).collect();
    if ideal {
        a.push(Order::Infinite);
    }
    a
}

/// Every word of length n, canonicalised, good ones kept: the dihedral classes by brute force.
fn brute_force(n: usize, max_order: u64, ideal: bool) -> BTreeSet<Signature> {
    let a = alphabet(max_order, ideal);
    let total = a.len().pow(n as u32);
    (0..total)
        .map(|mut index| {
            let corners = (0..n).map(|_| {
                let k = a[index % a.len()];
                index /= a.len();
                k
            });
            Signature::new(corners.collect::<Vec<_>>())
                .unwrap()
                .canonical()
        })
        .filter(|s| s.kind() == Kind::Orbifold)
        .collect()
}

fn enumerate(n: usize, max_order: u64, ideal: bool, geometry: Option<Geometry>) -> Vec<Signature> {
    Enumeration::new(EnumerationOptions {
        corners: n,
        max_order,
        ideal,
        geometry,
    })
    .unwrap()
    .collect()
}

#[test]
fn enumeration_equals_brute_force_dihedral_classes() {
    for (n, k, ideal) in [
        (0, 5, false),
        (1, 6, true),
        (2, 7, true),
        (3, 7, false),
        (3, 5, true),
        (4, 5, true),
        (5, 4, false),
        (6, 4, true),
        (7, 3, true),
        (8, 3, false),
    ] {
        let listed = enumerate(n, k, ideal, None);
        let unique: BTreeSet<Signature> = listed.iter().cloned().collect();
        assert_eq!(
            unique.len(),
            listed.len(),
            "duplicates for N={n} K={k} ideal={ideal}"
        );
        assert!(listed.iter().all(Signature::is_canonical));
        assert!(
            listed.windows(2).all(|w| w[0].corners() < w[1].corners()),
            "not in lexicographic order"
        );
        assert_eq!(
            unique,
            brute_force(n, k, ideal),
            "N={n} K={k} ideal={ideal}"
        );
    }
}

/// Number of bracelets of length n over k colours (OEIS A081720), from Burnside's lemma.
fn bracelet_formula(n: u64, k: u64) -> u64 {
    fn gcd(a: u64, b: u64) -> u64 {
        if b == 0 { a } else { gcd(b, a % b) }
    }
    let rotations: u64 = (0..n).map(|i| k.pow(gcd(i, n) as u32)).sum();
    let reflections = if n % 2 == 1 {
        n * k.pow(n.div_ceil(2) as u32)
    } else {
        n / 2 * (k.pow(n as u32 / 2) + k.pow(n as u32 / 2 + 1))
    };
    (rotations + reflections) / (2 * n)
}

#[test]
fn bracelets_match_burnside_count() {
    for n in 1..=9 {
        for k in 1..=5 {
            assert_eq!(
                Bracelets::new(n, k).count() as u64,
                bracelet_formula(n as u64, k as u64),
                "n={n} k={k}"
            );
        }
    }
    assert_eq!(Bracelets::new(0, 3).count(), 1);
    assert_eq!(
        enumerate(10, 4, false, None).len() as u64,
        bracelet_formula(10, 3)
    );
}

#[test]
fn geometry_filter_partitions_the_list() {
    for (n, k) in [(2, 9), (3, 12), (4, 4)] {
        let all = enumerate(n, k, true, None);
        let parts: usize = Geometry::ALL
            .iter()
            .map(|&g| enumerate(n, k, true, Some(g)).len())
            .sum();
        assert_eq!(parts, all.len());
        for g in Geometry::ALL {
            assert!(
                enumerate(n, k, true, Some(g))
                    .iter()
                    .all(|s| s.geometry() == g)
            );
        }
    }
    let euclidean: Vec<String> = enumerate(3, 20, false, Some(Geometry::Euclidean))
        .iter()
        .map(ToString::to_string)
        .collect();
    assert_eq!(euclidean, ["*236", "*244", "*333"]);
    let spherical3: Vec<String> = enumerate(3, 5, false, Some(Geometry::Spherical))
        .iter()
        .map(ToString::to_string)
        .collect();
    assert_eq!(
        spherical3,
        ["*222", "*223", "*224", "*225", "*233", "*234", "*235"]
    );
    assert!(enumerate(4, 9, true, Some(Geometry::Spherical)).is_empty());
    let e4: Vec<String> = enumerate(4, 9, false, Some(Geometry::Euclidean))
        .iter()
        .map(ToString::to_string)
        .collect();
    assert_eq!(e4, ["*2222"]);
    assert!(enumerate(5, 4, true, Some(Geometry::Euclidean)).is_empty());
}

#[test]
fn no_orders_is_an_error() {
    let err = Enumeration::new(EnumerationOptions {
        corners: 3,
        max_order: 1,
        ideal: false,
        geometry: None,
    })
    .unwrap_err();
    assert!(err.to_string().contains("at least 2"));
    assert_eq!(enumerate(3, 1, true, None).len(), 1, "only *∞∞∞");
}

/// Every good orbifold lies in exactly one family of Table 4.1, in its row and geometry.
#[test]
fn table_4_1_families_cover_every_orbifold_exactly_once() {
    let mut used = BTreeSet::new();
    for n in 0..=7 {
        let k = if n <= 3 { 14 } else { 4 };
        for s in enumerate(n, k, true, None) {
            let matching: Vec<_> = FAMILIES
                .iter()
                .enumerate()
                .filter(|(_, f)| f.contains(&s))
                .collect();
            assert_eq!(matching.len(), 1, "{s} matches {} families", matching.len());
            let (index, family) = matching[0];
            assert_eq!(family.geometry, s.geometry(), "{s} in {}", family.pattern);
            assert!(family.walls.contains(s.wall_count()));
            assert_eq!(s.family().map(|f| f.pattern), Some(family.pattern));
            used.insert(index);
        }
    }
    assert_eq!(used.len(), FAMILIES.len(), "every family has members");
    // Every family's examples are members of it.
    for family in FAMILIES {
        for example in family.examples {
            let s: Signature = example.parse().unwrap();
            assert_eq!(
                s.canonical().to_string(),
                *example,
                "examples are canonical"
            );
            assert!(
                family.contains(&s.canonical()),
                "{example} in {}",
                family.pattern
            );
        }
        if let Walls::AtLeast(m) = family.walls {
            assert_eq!(m, 5);
        }
    }
}
