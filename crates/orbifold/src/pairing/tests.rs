//! Poincaré's conditions for every construction: pairings are isometries that take the partner
//! edge onto the edge with the right orientation, neighbour(j) = neighbour(i)⁻¹, angle sums per
//! cycle, area 2π|χ|, convexity, no NaN.

use glam::{DMat3, DVec3};
use proptest::prelude::*;

use super::*;
use crate::layout::{LayoutOptions, Shape};

fn build(symbol: &str) -> FundamentalPolygon {
    let s: OrbifoldSymbol = symbol.parse().unwrap();
    FundamentalPolygon::new(&s, &LayoutOptions::default())
        .unwrap_or_else(|e| panic!("{symbol}: {e}"))
}

/// The null direction or point, scaled so that comparisons do not depend on its scale.
fn same_point(space: Space, a: DVec3, b: DVec3, ideal: bool) -> bool {
    if ideal {
        let (a, b) = (a / a.z, b / b.z);
        (a - b).length() < 1e-7
    } else {
        // Far from the centre the chord loses precision with the square of the coordinates.
        space.ambient_distance(a, b) < 1e-7 * (1.0 + a.length_squared())
    }
}

fn is_isometry(space: Space, m: DMat3) -> bool {
    let k = space.kappa();
    if k == 0.0 {
        let (a, b) = (m.x_axis, m.y_axis);
        let ok = (a.truncate().length() - 1.0).abs() < 1e-9
            && (b.truncate().length() - 1.0).abs() < 1e-9
            && a.truncate().dot(b.truncate()).abs() < 1e-9
            && a.z.abs() < 1e-12
            && b.z.abs() < 1e-12
            && (m.z_axis.z - 1.0).abs() < 1e-12;
        return ok;
    }
    let g = DMat3::from_diagonal(DVec3::new(1.0, 1.0, k));
    let scale = m.to_cols_array().iter().fold(1.0f64, |a, b| a.max(b.abs()));
    (m.transpose() * g * m).abs_diff_eq(g, 1e-9 * scale * scale)
}

/// Checks Poincaré's conditions and the bookkeeping of a polygon.
fn check(p: &FundamentalPolygon) {
    let name = p.symbol.to_string();
    let space = p.space();
    let n = p.vertices.len();
    assert_eq!(p.edges.len(), n.max(1), "{name}");
    for v in &p.vertices {
        assert!(
            v.ambient.is_finite() && v.angle.is_finite(),
            "{name}: NaN vertex"
        );
        assert!(v.angle <= std::f64::consts::PI + 1e-9, "{name}: not convex");
    }
    let mut in_cycles = vec![0; n];
    for c in &p.cycles {
        for &v in &c.vertices {
            in_cycles[v] += 1;
        }
        let want = c.expected_angle_sum();
        // Angles at far corners are measured from coordinates of size cosh(distance).
        let reach = p
            .vertices
            .iter()
            .filter(|v| !v.ideal)
            .fold(1.0f64, |m, v| m.max(v.ambient.length()));
        assert!(
            (c.angle_sum - want).abs() < 1e-8 * reach,
            "{name}: cycle {:?} ({:?}, order {}) sums to {} not {want}",
            c.vertices,
            c.kind,
            c.order,
            c.angle_sum
        );
    }
    assert!(in_cycles.iter().all(|&k| k == 1), "{name}: {in_cycles:?}");
    for (i, e) in p.edges.iter().enumerate() {
        assert!(
            e.neighbour.is_finite() && e.wall.is_finite(),
            "{name}: NaN edge {i}"
        );
        assert!(
            is_isometry(space, e.neighbour),
            "{name}: edge {i} {:?}",
            e.neighbour
        );
        let g = p.neighbour(i);
        match e.kind {
            EdgeKind::Mirror => {
                assert!(e.reverses_orientation(), "{name}");
                let scale = e
                    .neighbour
                    .to_cols_array()
                    .iter()
                    .fold(1.0f64, |a, b| a.max(b.abs()));
                assert!(
                    (e.neighbour * e.neighbour).abs_diff_eq(DMat3::IDENTITY, 1e-9 * scale * scale)
                );
                for v in [e.from, e.to].into_iter().flatten() {
                    let x = p.vertices[v];
                    assert!(same_point(
                        space,
                        g.apply_ambient(x.ambient),
                        x.ambient,
                        x.ideal
                    ));
                }
            }
            EdgeKind::Paired { partner } => {
                let f = &p.edges[partner];
                let product = e.neighbour * f.neighbour;
                let scale = e
                    .neighbour
                    .to_cols_array()
                    .iter()
                    .fold(1.0f64, |a, b| a.max(b.abs()));
                assert!(
                    product.abs_diff_eq(DMat3::IDENTITY, 1e-9 * scale * scale),
                    "{name}: neighbour({i}) neighbour({partner}) = {product:?}"
                );
                let (s, t) = (e.from.unwrap(), e.to.unwrap());
                let (s2, t2) = (f.from.unwrap(), f.to.unwrap());
                // Orientation-preserving pairings reverse the boundary direction.
                let (to_s2, to_t2) = if e.reverses_orientation() {
                    (s, t)
                } else {
                    (t, s)
                };
                for (from, to) in [(s2, to_s2), (t2, to_t2)] {
                    let (a, b) = (p.vertices[from], p.vertices[to]);
                    assert_eq!(a.ideal, b.ideal, "{name}: edge {i}");
                    assert!(
                        same_point(space, g.apply_ambient(a.ambient), b.ambient, a.ideal),
                        "{name}: neighbour({i}) takes vertex {from} to {:?}, not vertex {to}",
                        g.apply_ambient(a.ambient)
                    );
                }
                // The polygon's side of the partner goes to the far side of this edge.
                let image = g.apply_wall(f.wall);
                assert!(
                    (image + e.wall).length() < 1e-7 * (1.0 + e.wall.length()),
                    "{name}: edge {i}: {image:?} vs {:?}",
                    e.wall
                );
            }
        }
    }
    if let Some(area) = p.symbol.area() {
        assert!(
            (p.area - area).abs() < 1e-8 * area.max(1.0),
            "{name}: area {} not {area}",
            p.area
        );
    }
    assert_eq!(
        p.parameters.len() + p.missing_parameters,
        p.symbol.free_parameters(),
        "{name}"
    );
    assert_eq!(p.parameters.len(), p.parameter_meanings.len(), "{name}");
    assert!(p.contains(p.centre, 0.0), "{name}: centre outside");
}

#[test]
fn all_seventeen_wallpaper_groups() {
    for s in [
        "o", "2222", "**", "*×", "××", "22*", "22×", "*2222", "2*22", "442", "*442", "4*2", "333",
        "*333", "3*3", "632", "*632",
    ] {
        let p = build(s);
        assert_eq!(p.geometry, Geometry::Euclidean, "{s}");
        check(&p);
        assert_eq!(
            p.missing_parameters, 0,
            "{s}: every lattice parameter is offered"
        );
    }
}

#[test]
fn spherical_families() {
    for s in ["532", "432", "332", "3*2", "×", "*532", "*", "*22"] {
        check(&build(s));
    }
    for n in 2..=8 {
        for s in [
            format!("22({n})"),
            format!("({n})({n})"),
            format!("2*({n})"),
            format!("({n})*"),
            format!("({n})×"),
            format!("*22({n})"),
            format!("*({n})({n})"),
        ] {
            let p = build(&s);
            assert_eq!(p.geometry, Geometry::Spherical, "{s}");
            check(&p);
        }
    }
}

#[test]
fn hyperbolic_examples() {
    for s in [
        "2223",
        "4*3",
        "*2×",
        "××",
        "oo",
        "o2",
        "237",
        "23∞",
        "∞∞∞",
        "2*34",
        "3*∞",
        "***",
        "×××",
        "o*",
        "22222",
        "3333",
        "o×",
        "**2",
        "2**",
        "∞∞",
        "∞×",
        "2∞*",
    ] {
        let symbol: OrbifoldSymbol = s.parse().unwrap();
        if symbol.geometry() == Geometry::Hyperbolic {
            check(&build(s));
        }
    }
}

/// Handles, cones, boundaries and cross-caps, as `OrbifoldSymbol::new` takes them.
type Features = (u32, Vec<Order>, Vec<Vec<Order>>, u32);

/// Hyperbolic symbols with a mirror boundary that has one to three corners and up to two more
/// features (cones, boundaries, a handle, cross-caps), corner and cone orders 2…5 and ∞, build
/// and meet Poincaré's conditions; so do the ones the cap construction could not build.
#[test]
fn boundaries_with_corners_build() {
    let orders: Vec<Order> = (2..=5)
        .map(Order::integer)
        .chain([Order::Infinite])
        .collect();
    // Corner lists of length 1…3 (orders nondecreasing keeps the list short; the order of the
    // corners does not change the construction's feasibility, only its cycle bookkeeping).
    let mut corner_lists: Vec<Vec<Order>> = Vec::new();
    for a in &orders {
        corner_lists.push(vec![*a]);
        for b in &orders {
            corner_lists.push(vec![*a, *b]);
            for c in &orders {
                corner_lists.push(vec![*a, *b, *c]);
            }
        }
    }
    let mut built = 0;
    for corners in &corner_lists {
        let mut others: Vec<Features> = vec![
            (0, vec![], vec![], 0),
            (1, vec![], vec![], 0),
            (0, vec![], vec![], 1),
            (0, vec![], vec![vec![]], 0),
            (0, vec![], vec![vec![Order::integer(2)]], 0),
            (0, vec![], vec![vec![Order::integer(3)], vec![]], 0),
            (0, vec![], vec![], 2),
        ];
        for a in &orders {
            others.push((0, vec![*a], vec![], 0));
            others.push((0, vec![*a], vec![], 1));
            others.push((0, vec![*a], vec![vec![]], 0));
            others.push((1, vec![*a], vec![], 0));
            others.push((0, vec![*a], vec![vec![*a]], 0));
            others.push((0, vec![], vec![vec![*a]], 1));
            others.push((0, vec![], vec![vec![*a, *a]], 0));
            for b in &orders {
                others.push((0, vec![*a, *b], vec![], 0));
            }
        }
        for (h, cones, mut boundaries, x) in others {
            boundaries.insert(0, corners.clone());
            let s = OrbifoldSymbol::new(h, cones, boundaries, x);
            if s.geometry() != Geometry::Hyperbolic || s.is_bad() || s.as_kaleidoscopic().is_some()
            {
                continue;
            }
            let p = FundamentalPolygon::new(&s, &LayoutOptions::default())
                .unwrap_or_else(|e| panic!("{s}: {e}"));
            check(&p);
            built += 1;
        }
    }
    assert!(built > 1000, "{built}");
    for s in [
        "o*2", "*2*3", "2*2222", "3*33", "∞*∞", "*2×", "*23*", "**2", "23*2", "2*2×",
    ] {
        check(&build(s));
    }
}

#[test]
fn kaleidoscopic_symbols_keep_their_layout() {
    for s in ["*2333", "*2222", "*632", "*∞∞∞", "*23456"] {
        let p = build(s);
        let layout = Layout::new(&s.parse().unwrap(), &LayoutOptions::default()).unwrap();
        assert_eq!(p.layout.as_ref(), Some(&layout));
        assert_eq!(p.parameters, layout.parameters);
        for (v, w) in p.vertices.iter().zip(&layout.vertices) {
            assert_eq!(v.position, w.position);
        }
        check(&p);
    }
}

#[test]
fn three_cones_are_two_triangles_of_the_reflection_group() {
    for s in ["237", "245", "333", "532", "2 3 ∞"] {
        let rot = build(&s.replace(' ', ""));
        let kal = build(&format!("*{}", s.replace(' ', "")));
        // Kite P, R', Q, R: P, Q, R are the corners of the reflection group's triangle.
        let corners = [0, 2, 3].map(|i| rot.vertices[i].position);
        for (z, v) in corners.iter().zip(&kal.vertices) {
            assert!((z - v.position).norm() < 1e-12, "{s}");
        }
        // R' is R reflected in the wall PQ, the first neighbour of the reflection group.
        let r2 = kal.neighbour(0).apply_ambient(rot.vertices[3].ambient);
        let r2_ideal = rot.vertices[1].ideal;
        assert!(
            same_point(rot.space(), r2, rot.vertices[1].ambient, r2_ideal),
            "{s}"
        );
    }
}

#[test]
fn the_torus_takes_every_lattice() {
    let s: OrbifoldSymbol = "o".parse().unwrap();
    for (ratio, angle) in [(1.0, 90.0), (0.3, 20.0), (5.0, 170.0), (1.0, 60.0)] {
        let p = FundamentalPolygon::new(
            &s,
            &LayoutOptions {
                shape: Shape::Parameters(vec![ratio, angle]),
                ..Default::default()
            },
        )
        .unwrap();
        assert_eq!(p.missing_parameters, 0);
        check(&p);
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]

    /// p2 takes every lattice: the translations a (pairing the left side with the right) and b
    /// (the product of the two half-turns) are the lattice's, whatever its shape.
    #[test]
    fn p2_takes_every_lattice(ratio in 0.05f64..20.0, angle in 1.0f64..179.0) {
        let p = FundamentalPolygon::new(
            &"2222".parse().unwrap(),
            &LayoutOptions {
                shape: Shape::Parameters(vec![ratio, angle]),
                ..Default::default()
            },
        )
        .unwrap();
        prop_assert_eq!(p.missing_parameters, 0);
        prop_assert_eq!(p.construction, Construction::FoldedParallelogram);
        check(&p);
        // E²'s ambient coordinates of a model point z are (2z, 1) (stereographic scale), and the
        // polygon was moved to its standard place: compare through the ambient images.
        let space = p.space();
        let at = |z: num_complex::Complex64| space.to_ambient(z);
        let (o, a) = (p.vertices[0].position, p.vertices[2].position);
        let b = num_complex::Complex64::from_polar(ratio, angle.to_radians()) * (a - o);
        let is_translation = |m: DMat3, by: num_complex::Complex64| {
            m.x_axis.abs_diff_eq(DVec3::X, 1e-12)
                && m.y_axis.abs_diff_eq(DVec3::Y, 1e-12)
                && (m * at(o)).abs_diff_eq(at(o + by), 1e-9)
        };
        prop_assert!(is_translation(p.edges[2].neighbour, a - o));
        prop_assert!(is_translation(p.edges[3].neighbour * p.edges[0].neighbour, b));
        let (ea, eb) = (at(a) - at(o), at(o + b) - at(o));
        prop_assert!((p.area - ea.cross(eb).length() / 2.0).abs() < 1e-9 * (1.0 + p.area));
    }
}

#[test]
fn parameters_are_checked() {
    let s: OrbifoldSymbol = "2*22".parse().unwrap();
    let with = |v: Vec<f64>| {
        FundamentalPolygon::new(
            &s,
            &LayoutOptions {
                shape: Shape::Parameters(v),
                ..Default::default()
            },
        )
    };
    assert!(with(vec![0.3]).is_ok());
    assert!(matches!(
        with(vec![1.5]),
        Err(LayoutError::ParameterOutOfRange { .. })
    ));
    assert!(matches!(
        with(vec![f64::NAN]),
        Err(LayoutError::InvalidParameter { .. })
    ));
    assert!(matches!(
        with(vec![]),
        Err(LayoutError::ParameterCount {
            expected: 1,
            given: 0
        })
    ));
    let one: OrbifoldSymbol = "1".parse().unwrap();
    assert!(matches!(
        FundamentalPolygon::new(&one, &Default::default()),
        Err(LayoutError::Unsupported(_))
    ));
    let bad: OrbifoldSymbol = "23".parse().unwrap();
    assert!(matches!(
        FundamentalPolygon::new(&bad, &Default::default()),
        Err(LayoutError::NotBuildable(_))
    ));
    let frieze: OrbifoldSymbol = "22∞".parse().unwrap();
    assert!(matches!(
        FundamentalPolygon::new(&frieze, &Default::default()),
        Err(LayoutError::Unsupported(_))
    ));
}

#[test]
fn placement_moves_the_polygon_rigidly() {
    let s: OrbifoldSymbol = "2223".parse().unwrap();
    let moved = FundamentalPolygon::new(
        &s,
        &LayoutOptions {
            at: num_complex::Complex64::new(0.3, -0.2),
            angle: 0.7,
            ..Default::default()
        },
    )
    .unwrap();
    check(&moved);
    assert!((moved.centre - num_complex::Complex64::new(0.3, -0.2)).norm() < 1e-12);
}

/// A random hyperbolic symbol that is not kaleidoscopic, with at most `limit` features.
fn symbol() -> impl Strategy<Value = OrbifoldSymbol> {
    let order = prop_oneof![
        8 => (2u64..8).prop_map(Order::integer),
        1 => Just(Order::Infinite),
    ];
    (
        0u32..3,
        proptest::collection::vec(order.clone(), 0..5),
        proptest::collection::vec(proptest::collection::vec(order, 0..4), 0..3),
        0u32..3,
    )
        .prop_map(|(h, c, b, x)| OrbifoldSymbol::new(h, c, b, x))
        .prop_filter("hyperbolic, not kaleidoscopic, small", |s| {
            s.geometry() == Geometry::Hyperbolic
                && s.as_kaleidoscopic().is_none()
                && !s.is_bad()
                && 4 * s.handles() as usize
                    + s.cones().len()
                    + s.boundaries().len()
                    + 2 * s.crosscaps() as usize
                    <= 9
        })
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(256))]

    #[test]
    fn random_hyperbolic_symbols_meet_poincare(s in symbol(), seeds in proptest::collection::vec(0.0f64..1.0, 24)) {
        let default = FundamentalPolygon::new(&s, &LayoutOptions::default());
        prop_assert!(default.is_ok(), "{s}: {:?}", default.err());
        let p = default.unwrap();
        check(&p);
        // Random values across each parameter's documented range.
        let values: Vec<f64> = p
            .parameter_meanings
            .iter()
            .zip(&seeds)
            .map(|(m, &u)| {
                if m.contains("(0.98, 1.02)") {
                    0.9801 + 0.0398 * u
                } else if m.contains("(0, 180)") {
                    1.0 + 178.0 * u
                } else if m.contains("(0, 1)") {
                    0.02 + 0.96 * u
                } else if m.contains("1/√2") {
                    std::f64::consts::FRAC_1_SQRT_2 * 2f64.powf(0.98 * u + 0.01)
                } else if m.contains("(0, 2)") {
                    0.02 + 1.96 * u
                } else {
                    0.05 * 60f64.powf(u)
                }
            })
            .collect();
        let shaped = FundamentalPolygon::new(
            &s,
            &LayoutOptions { shape: Shape::Parameters(values.clone()), ..Default::default() },
        );
        prop_assert!(shaped.is_ok(), "{s} {values:?}: {:?}", shaped.err());
        check(&shaped.unwrap());
    }
}

fn with_factors(s: &OrbifoldSymbol, factors: Vec<f64>) -> Result<FundamentalPolygon, LayoutError> {
    FundamentalPolygon::new(
        s,
        &LayoutOptions {
            shape: Shape::Parameters(factors),
            ..Default::default()
        },
    )
}

/// Reads the parameters back from the pairings alone and compares them with the factors asked
/// for.
fn check_lengths(s: &OrbifoldSymbol, p: &FundamentalPolygon, factors: &[f64]) {
    let (words, defaults) = deform::words_for(s);
    let lengths = deform::lengths_in(p, &words);
    assert_eq!(lengths.len(), factors.len(), "{s}");
    for (k, ((l, l0), f)) in lengths.iter().zip(&defaults).zip(factors).enumerate() {
        assert!(
            (l / l0 - f).abs() < 1e-8,
            "{s}: parameter {k} asked {f}, the pairings give {}",
            l / l0
        );
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(96))]

    /// Every hyperbolic star offers all of Thurston's parameters, and
    /// every value in the documented range gives a polygon that meets Poincaré's conditions with
    /// the closed geodesics' lengths asked for.
    #[test]
    fn deformed_stars_meet_poincare(
        s in symbol(),
        seeds in proptest::collection::vec(0.0f64..1.0, 24),
        extreme in proptest::bool::ANY,
    ) {
        let p = FundamentalPolygon::new(&s, &LayoutOptions::default()).unwrap();
        prop_assume!(p.construction == Construction::Star);
        prop_assert_eq!(p.parameters.len() + p.missing_parameters, s.free_parameters());
        prop_assert_eq!(p.missing_parameters, 0, "{}", s);
        let (lo, hi) = deform::FACTOR_RANGE;
        // Half of the cases at the range's corners, where the lengths are furthest apart.
        let factors: Vec<f64> = seeds
            .iter()
            .take(p.parameters.len())
            .map(|&u| {
                let u = if extreme { if u < 0.5 { 1e-6 } else { 1.0 - 1e-6 } } else { 0.001 + 0.998 * u };
                lo + (hi - lo) * u
            })
            .collect();
        let shaped = with_factors(&s, factors.clone());
        prop_assert!(shaped.is_ok(), "{} {:?}: {:?}", s, factors, shaped.err());
        let shaped = shaped.unwrap();
        check(&shaped);
        check_lengths(&s, &shaped, &factors);
        prop_assert_eq!(shaped.parameters, factors);
    }
}

#[test]
fn each_parameter_moves_its_own_length() {
    for name in ["oo", "2223", "o*2", "*2*3", "2∞*", "o×", "23*2", "×××"] {
        let s: OrbifoldSymbol = name.parse().unwrap();
        let default = build(name);
        let t = default.parameters.len();
        assert_eq!(t, s.free_parameters(), "{name}");
        for k in 0..t {
            let mut factors = vec![1.0; t];
            factors[k] = 1.015;
            let p = with_factors(&s, factors.clone()).unwrap();
            check(&p);
            // Only length k moves: the Jacobian of the lengths has rank T, and the group is not
            // conjugate to the star's (a conjugacy invariant differs).
            check_lengths(&s, &p, &factors);
            let moved = p
                .vertices
                .iter()
                .zip(&default.vertices)
                .any(|(a, b)| (a.position - b.position).norm() > 1e-4);
            assert!(moved, "{name}: parameter {k} did not move the polygon");
        }
    }
}

#[test]
fn default_factors_give_todays_star() {
    for name in [
        "oo",
        "2223",
        "o*2",
        "*2*3",
        "3*33",
        "∞∞2∞",
        "2∞*",
        "**2",
        "ooo",
    ] {
        let s: OrbifoldSymbol = name.parse().unwrap();
        let default = build(name);
        let ones = with_factors(&s, vec![1.0; default.parameters.len()]).unwrap();
        assert_eq!(default, ones, "{name}");
        // Today's construction, finished without the deformation.
        let space = Space::new(s.geometry());
        let star = star::draft(&s, space, None).unwrap();
        let today = finish(&s, space, star, DMat3::IDENTITY).unwrap();
        assert_eq!(default.vertices, today.vertices, "{name}");
        assert_eq!(default.edges, today.edges, "{name}");
    }
}

#[test]
fn parameters_out_of_range_are_refused() {
    let s: OrbifoldSymbol = "oo".parse().unwrap();
    let mut factors = vec![1.0; 6];
    factors[2] = 1.2;
    assert!(matches!(
        with_factors(&s, factors),
        Err(LayoutError::ParameterOutOfRange { index: 2, .. })
    ));
}

/// `2*k₁…kₙ` in the polygon of `*k₁…kₙ22`: the same corners, the side between the two right
/// angles folded at its midpoint.
#[test]
fn a_cone_of_order_two_and_a_mirror_fold_the_reflection_polygon() {
    for (s, reflections) in [
        ("2*2222", "*222222"),
        ("2*234", "*23422"),
        ("2*3∞", "*3∞22"),
        ("2*∞∞", "*∞∞22"),
        ("2*∞∞∞", "*∞∞∞22"),
    ] {
        let p = build(s);
        assert_eq!(p.construction, Construction::FoldedPolygon, "{s}");
        assert_eq!(p.missing_parameters, 0, "{s}");
        check(&p);
        let layout = Layout::new(&reflections.parse().unwrap(), &LayoutOptions::default()).unwrap();
        // The same corners up to the placement: the same distances between finite ones.
        let n = layout.vertices.len() - 2;
        let space = p.space();
        let mut corners: Vec<_> = p.vertices.iter().collect();
        let mid = corners.remove(n + 1);
        let finite = |i: usize| !layout.vertices[i].ideal;
        for i in (0..n + 2).filter(|&i| finite(i)) {
            for j in (0..i).filter(|&j| finite(j)) {
                let ours = space.ambient_distance(corners[i].ambient, corners[j].ambient);
                let (a, b) = (layout.vertices[i].position, layout.vertices[j].position);
                let theirs = space.ambient_distance(space.to_ambient(a), space.to_ambient(b));
                assert!((ours - theirs).abs() < 1e-9, "{s}: corners {i}, {j}");
            }
        }
        let (a, b) = (corners[n].ambient, corners[n + 1].ambient);
        let (to_a, to_b) = (
            space.ambient_distance(a, mid.ambient),
            space.ambient_distance(mid.ambient, b),
        );
        assert!(
            (to_a - to_b).abs() < 1e-12 && to_a > 1e-3,
            "{s}: M halves PQ"
        );
        let cone = p.cycles.iter().find(|c| c.vertices == [n + 1]).unwrap();
        assert_eq!(
            (cone.kind, cone.order),
            (CycleKind::Cone, Order::integer(2)),
            "{s}"
        );
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]

    /// Every value of every parameter in (0, ∞) gives a polygon that meets Poincaré's
    /// conditions, for random corners (`∞` among them) of `2*k₁…kₙ`.
    #[test]
    fn folded_polygons_take_every_parameter(
        orders in proptest::collection::vec(prop_oneof![2u64..7, Just(0u64)], 3..7),
        values in proptest::collection::vec(-3.0f64..3.0, 6),
    ) {
        let corners: String = orders
            .iter()
            .map(|&k| if k == 0 { "∞".to_string() } else { k.to_string() })
            .collect();
        let s: OrbifoldSymbol = format!("2*{corners}").parse().unwrap();
        let count = s.free_parameters();
        prop_assert_eq!(count, orders.len() - 1);
        let parameters: Vec<f64> = values[..count].iter().map(|&e| 10f64.powf(e)).collect();
        let p = FundamentalPolygon::new(
            &s,
            &LayoutOptions {
                shape: Shape::Parameters(parameters.clone()),
                ..Default::default()
            },
        )
        .unwrap_or_else(|e| panic!("{s} {parameters:?}: {e}"));
        prop_assert_eq!(p.construction, Construction::FoldedPolygon);
        prop_assert_eq!(&p.parameters, &parameters);
        prop_assert_eq!(p.missing_parameters, 0);
        check(&p);
    }
}
