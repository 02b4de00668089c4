//! χ, geometry, kind, area, group order and free parameters of kaleidoscopic signatures.

use std::f64::consts::PI;

use orbifold::{Geometry, Kind, Order, Signature};
use proptest::prelude::*;

fn sig(s: &str) -> Signature {
    s.parse().unwrap_or_else(|e| panic!("{s:?}: {e}"))
}

#[test]
fn table_4_1_examples_land_in_the_right_geometry() {
    for s in [
        "*236", "*244", "*333", "*2222", "*632", "*362", "*442", "*∞∞", "*22∞",
    ] {
        assert_eq!(sig(s).geometry(), Geometry::Euclidean, "{s}");
    }
    for s in [
        "*", "*22", "*33", "*77", "*222", "*223", "*22(100)", "*233", "*234", "*235", "*532",
    ] {
        assert_eq!(sig(s).geometry(), Geometry::Spherical, "{s}");
    }
    for s in [
        "*237",
        "*23(100)",
        "*245",
        "*255",
        "*2(17)(99)",
        "*334",
        "*344",
        "*444",
        "*2223",
        "*2323",
        "*22222",
        "*23456789(10)(11)",
        "*∞∞∞",
        "*2∞∞",
        "*23∞",
        "*222∞∞",
        "*∞∞∞∞",
    ] {
        assert_eq!(sig(s).geometry(), Geometry::Hyperbolic, "{s}");
    }
}

#[test]
fn exact_euler_characteristics() {
    let chi = |s: &str| sig(s).euler_characteristic().to_string();
    assert_eq!(chi("*"), "1");
    assert_eq!(chi("*22"), "1/2");
    assert_eq!(chi("*235"), "1/60");
    assert_eq!(chi("*236"), "0");
    assert_eq!(chi("*237"), "-1/84");
    assert_eq!(chi("*22222"), "-1/4");
    assert_eq!(chi("*2333"), "-1/4");
    assert_eq!(chi("*∞∞∞"), "-1/2");
    assert_eq!(chi("*(3/2)33"), "1/6");
    assert_eq!(chi("*(1.5)33"), "1/6");
    // Large coprime orders must not overflow: the denominator is 2·p₁⋯p₈, about 2·10⁴⁸.
    let big = sig("*(1000003)(1000033)(1000037)(1000039)(1000081)(1000099)(1000117)(1000121)");
    let exact = big.euler_characteristic().to_string();
    let denominator = exact.split('/').nth(1).unwrap();
    assert_eq!(denominator.len(), 49, "{exact}");
    assert!((big.euler_characteristic().to_f64() - (-3.0 + 0.5 * 8.0 / 1.00006e6)).abs() < 1e-9);
}

#[test]
fn bad_orbifolds_are_recognised_and_explained() {
    for s in ["*2", "*7", "*∞", "*23", "*2∞", "*(12)(13)"] {
        let sig = sig(s);
        assert_eq!(sig.kind(), Kind::Bad, "{s}");
        assert!(!sig.is_buildable());
        assert_eq!(sig.area(), None);
        assert_eq!(sig.group_order(), None);
        assert_eq!(sig.free_parameters(), 0);
        assert!(sig.family().is_none());
    }
    assert!(
        sig("*23")
            .reason()
            .unwrap()
            .contains("two mirrors that meet twice must meet at the same angle both times")
    );
    assert!(sig("*5").reason().unwrap().contains("single mirror"));
    assert_eq!(sig("*33").kind(), Kind::Orbifold);
    assert_eq!(sig("*33").reason(), None);
}

#[test]
fn non_orbifold_rooms() {
    let s = sig("*(3/2)33");
    assert_eq!(s.kind(), Kind::NonOrbifold);
    assert!(s.is_buildable());
    assert_eq!(s.geometry(), Geometry::Spherical);
    assert!((s.area().unwrap() - PI / 3.0).abs() < 1e-12);
    assert_eq!(s.group_order(), None);
    let reason = s.reason().unwrap();
    assert!(
        reason.contains("corner 1") && reason.contains("3/2") && reason.contains("2π/3"),
        "{reason}"
    );
    let lune = sig("*(3/2)(5/2)");
    assert_eq!(lune.kind(), Kind::NonOrbifold);
    assert!(!lune.is_buildable());
    assert!(lune.reason().unwrap().contains("cannot be built"));
}

#[test]
fn spherical_group_orders() {
    let order = |s: &str| sig(s).group_order();
    assert_eq!(order("*"), Some(2));
    assert_eq!(order("*22"), Some(4));
    assert_eq!(order("*77"), Some(14));
    assert_eq!(order("*222"), Some(8));
    assert_eq!(order("*22(10)"), Some(40));
    assert_eq!(order("*233"), Some(24));
    assert_eq!(order("*234"), Some(48));
    assert_eq!(order("*235"), Some(120));
    assert_eq!(order("*236"), None);
    assert_eq!(order("*237"), None);
    assert_eq!(
        order("*(18446744073709551615)(18446744073709551615)"),
        Some(2 * u128::from(u64::MAX))
    );
}

#[test]
fn free_parameters() {
    let free = |s: &str| sig(s).free_parameters();
    assert_eq!(free("*"), 0);
    assert_eq!(free("*33"), 0);
    assert_eq!(free("*235"), 0);
    assert_eq!(free("*333"), 0);
    assert_eq!(free("*237"), 0);
    assert_eq!(free("*2222"), 1);
    assert_eq!(free("*2223"), 1);
    assert_eq!(free("*22222"), 2);
    assert_eq!(free("*23456789(10)(11)"), 7);
    assert_eq!(free("*∞∞∞∞∞"), 2);
}

#[test]
fn areas_follow_gauss_bonnet() {
    assert!((sig("*").area().unwrap() - 2.0 * PI).abs() < 1e-12);
    assert!((sig("*235").area().unwrap() - PI / 30.0).abs() < 1e-12);
    assert!((sig("*22222").area().unwrap() - PI / 2.0).abs() < 1e-12);
    assert!((sig("*∞∞∞").area().unwrap() - PI).abs() < 1e-12);
    assert_eq!(sig("*2222").area(), None);
}

#[test]
fn canonical_forms() {
    assert_eq!(sig("*632").canonical(), sig("*236"));
    assert_eq!(sig("*362").canonical(), sig("*236"));
    assert_eq!(sig("*3332").canonical().to_string(), "*2333");
    assert_eq!(sig("*3232").canonical().to_string(), "*2323");
    assert_eq!(sig("*∞2∞3").canonical().to_string(), "*2∞3∞");
    assert_eq!(sig("*(12)2(3/2)").canonical().to_string(), "*(3/2)2(12)");
    assert!(sig("*2333").is_canonical());
    assert!(!sig("*3332").is_canonical());
}

/// Orders for property tests: integers 1..=12 (1 is dropped), ∞, and rationals p/q > 1.
fn order() -> impl Strategy<Value = Order> {
    prop_oneof![
        6 => (1u64..=12).prop_map(Order::integer),
        1 => Just(Order::Infinite),
        2 => (1u64..=7, 2u64..=60).prop_map(|(q, p)| Order::ratio(p.max(q + 1), q).unwrap()),
    ]
}

fn signature() -> impl Strategy<Value = Signature> {
    prop::collection::vec(order(), 0..=9).prop_map(|c| Signature::new(c).unwrap())
}

fn rotate_reverse(s: &Signature, shift: usize, reverse: bool) -> Signature {
    let mut c = s.corners().to_vec();
    let n = c.len();
    if n > 0 {
        c.rotate_left(shift % n);
    }
    if reverse {
        c.reverse();
    }
    Signature::new(c).unwrap()
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(2000))]

    /// The sign of χ agrees with the angle sum against (N − 2)π.
    #[test]
    fn chi_sign_matches_angle_sum(s in signature()) {
        let chi = s.euler_characteristic();
        let defect = s.angle_sum() - (s.corner_count() as f64 - 2.0) * PI;
        prop_assert!((2.0 * PI * chi.to_f64() - defect).abs() < 1e-9);
        if defect.abs() > 1e-9 {
            prop_assert_eq!(chi.geometry(), if defect > 0.0 { Geometry::Spherical } else { Geometry::Hyperbolic });
        }
    }

    /// The canonical form is the same for every rotation and reversal, and is one of them.
    #[test]
    fn canonical_form_is_dihedrally_invariant(s in signature(), shift in 0usize..20, reverse: bool) {
        let other = rotate_reverse(&s, shift, reverse);
        prop_assert_eq!(other.canonical(), s.canonical());
        prop_assert!(s.canonical().is_canonical());
        prop_assert_eq!(other.euler_characteristic(), s.euler_characteristic());
        prop_assert_eq!(other.kind(), s.kind());
    }

    /// Canonicalisation is idempotent and survives printing and reading back.
    #[test]
    fn canonical_form_is_a_fixed_point(s in signature()) {
        let canon = s.canonical();
        prop_assert_eq!(canon.canonical(), canon.clone());
        let reread: Signature = canon.to_string().parse().unwrap();
        prop_assert_eq!(reread, canon);
    }

    /// The canonical form is no larger than any reading.
    #[test]
    fn canonical_form_is_the_smallest_reading(s in signature()) {
        let canon = s.canonical();
        for shift in 0..s.corner_count() {
            for reverse in [false, true] {
                let reading = rotate_reverse(&s, shift, reverse);
                prop_assert!(canon.corners() <= reading.corners());
            }
        }
    }

    /// Good orbifolds with integer orders are exactly what the seed's rules say.
    #[test]
    fn kind_rules(s in signature()) {
        let expected = if !s.corners().iter().all(Order::is_orbifold_order) {
            Kind::NonOrbifold
        } else {
            match s.corners() {
                [_] => Kind::Bad,
                [a, b] if a != b => Kind::Bad,
                _ => Kind::Orbifold,
            }
        };
        prop_assert_eq!(s.kind(), expected);
    }

    /// Spherical group orders are 2/χ and the area of the polygon times the order is 4π.
    #[test]
    fn group_order_tiles_the_sphere(s in signature()) {
        if let Some(order) = s.group_order() {
            let area = s.area().unwrap();
            prop_assert!((area * order as f64 - 4.0 * PI).abs() < 1e-9);
        }
    }
}
