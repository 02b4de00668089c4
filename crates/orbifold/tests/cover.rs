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

mod geometry {
    use glam::DMat3;
    use num_complex::Complex64;
    use orbifold::cover::{Bound, Cover};
    use orbifold::growth::growth_series;
    use orbifold::space::Space;
    use orbifold::{Order, Signature};
    use proptest::prelude::*;

    fn cover(sig: &str, depth: usize) -> Cover {
        Cover::enumerate(&sig.parse().unwrap(), Bound::Depth(depth), true).unwrap()
    }

    fn image(space: Space, m: &DMat3, z: Complex64) -> Complex64 {
        space.to_model(*m * space.to_ambient(z))
    }

    /// Tiles are pairwise distinct (their centres differ), and each tile's isometry maps the
    /// polygon's corners to corners of the tiling (points where some tile has a corner).
    #[test]
    fn tiles_are_distinct_and_corners_go_to_corners() {
        for (sig, depth) in [
            ("*2222222", 4),
            ("*237", 9),
            ("*2323", 5),
            ("*333", 6),
            ("*235", 15),
            ("*2∞∞", 5),
        ] {
            let c = cover(sig, depth);
            let space = c.layout.space();
            let centres: Vec<Complex64> = c
                .tiles
                .iter()
                .map(|t| image(space, &t.matrix, c.layout.centre))
                .collect();
            let mut keys: Vec<(i64, i64)> = centres
                .iter()
                .map(|z| ((z.re * 1e9).round() as i64, (z.im * 1e9).round() as i64))
                .collect();
            keys.sort_unstable();
            keys.dedup();
            assert_eq!(keys.len(), c.tiles.len(), "{sig}: two tiles share a centre");
            // Every finite corner of every tile is a corner of its neighbour across either wall
            // at that corner: in particular it is shared by at least two tiles of the cover.
            for tile in c.tiles.iter().take(200) {
                for v in c.layout.vertices.iter().filter(|v| !v.ideal) {
                    let p = tile.matrix * space.to_ambient(v.position);
                    let z = space.to_model(p);
                    let shared = c.tiles.iter().filter(|other| {
                        c.layout.vertices.iter().any(|w| {
                            !w.ideal && (image(space, &other.matrix, w.position) - z).norm() < 1e-9
                        })
                    });
                    assert!(
                        shared.count() >= 2 || tile.depth as usize == depth,
                        "{sig}: corner not shared"
                    );
                }
            }
        }
    }

    /// Adjacent tiles (parent and child) share exactly one wall: the child is its parent
    /// reflected in the wall it was reached across.
    #[test]
    fn children_are_reflections_across_one_wall() {
        let c = cover("*2223", 6);
        let space = c.layout.space();
        for tile in c.tiles.iter().filter(|t| t.depth > 0).take(500) {
            let wall = tile.wall.unwrap() as usize;
            // The shared wall's two corners are fixed by the reflection that relates the tiles.
            let (a, b) = (
                c.layout.vertices[wall].position,
                c.layout.vertices[(wall + 1) % 4].position,
            );
            let parent =
                tile.matrix * orbifold::cover::reflection(space, c.layout.edges[wall].wall);
            for corner in [a, b] {
                assert!(
                    (image(space, &tile.matrix, corner) - image(space, &parent, corner)).norm()
                        < 1e-9
                );
            }
            assert_ne!(tile.reflected, tile.depth % 2 == 0);
        }
    }

    /// Deep covers stay exact: the ideal triangle *∞∞∞ (a triangle group, whose descents are
    /// decided geometrically) reaches tiles more than 20 units from the base by depth 21, and its
    /// counts still equal the growth series.
    #[test]
    fn exact_twenty_units_from_the_base() {
        let s: Signature = "*∞∞∞".parse().unwrap();
        let c = Cover::enumerate(&s, Bound::Depth(21), false).unwrap();
        let series: Vec<u64> = growth_series(&s, 21)
            .unwrap()
            .into_iter()
            .map(|x| x as u64)
            .collect();
        assert_eq!(c.counts_by_depth, series);
        assert!(c.farthest > 20.0, "farthest tile only {}", c.farthest);
    }

    fn signature() -> impl Strategy<Value = Signature> {
        let order =
            prop_oneof![6 => (2u64..=9).prop_map(Order::integer), 1 => Just(Order::Infinite)];
        prop::collection::vec(order, 3..=8).prop_map(|c| Signature::new(c).unwrap())
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(64))]

        /// Random signatures (triangles to octagons, ideal corners included): counts per depth
        /// equal Steinberg's growth series.
        #[test]
        fn random_signatures_match_growth_series(s in signature()) {
            prop_assume!(orbifold::layout::Layout::new(&s, &Default::default()).is_ok());
            let depth = match s.corner_count() { 3 => 9, 4 => 7, 5 => 6, _ => 5 };
            let c = Cover::enumerate(&s, Bound::Depth(depth), false).unwrap();
            let mut series: Vec<u64> = growth_series(&s, depth).unwrap().into_iter().map(|x| x as u64).collect();
            while series.last() == Some(&0) { series.pop(); }
            prop_assert_eq!(c.counts_by_depth, series);
        }
    }
}

/// `Bound::Radius` finds every tile whose centre is within the radius: compare with a deep
/// enumeration filtered by distance.
#[test]
fn radius_bound_finds_every_tile_within_it() {
    use orbifold::space::Space;
    for (sig, radius, depth) in [
        ("*2222222", 4.0, 9),
        ("*237", 3.0, 26),
        ("*2∞∞", 4.0, 14),
        ("*333", 5.0, 20),
        ("*22222", 5.0, 12),
    ] {
        let s: Signature = sig.parse().unwrap();
        let by_radius = Cover::enumerate(&s, Bound::Radius(radius), true).unwrap();
        let deep = Cover::enumerate(&s, Bound::Depth(depth), true).unwrap();
        let space = Space::new(s.geometry());
        let o = space.to_ambient(num_complex::Complex64::new(0.0, 0.0));
        let distance = |m: &glam::DMat3| {
            let c = *m * o;
            space.distance(num_complex::Complex64::new(0.0, 0.0), space.to_model(c))
        };
        let inside = deep
            .tiles
            .iter()
            .filter(|t| distance(&t.matrix) <= radius)
            .count();
        assert_eq!(by_radius.tiles.len(), inside, "{sig}");
        assert!(
            deep.tiles
                .iter()
                .filter(|t| t.depth as usize == depth)
                .all(|t| distance(&t.matrix) > radius),
            "{sig}: depth {depth} too shallow for the check"
        );
    }
}
