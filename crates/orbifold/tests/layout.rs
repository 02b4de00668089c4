//! Polygon layout checked against geometric invariants: corner angles, sides on geodesics,
//! convexity and simplicity, Gauss–Bonnet area (computed independently from the corners), and
//! invariance under placement.

use std::f64::consts::PI;

use glam::DVec3;
use num_complex::Complex64;
use orbifold::layout::{Layout, LayoutError, LayoutOptions, Shape};
use orbifold::space::{ModelGeodesic, Space};
use orbifold::{Geometry, Order, Signature};
use proptest::prelude::*;

fn sig(s: &str) -> Signature {
    s.parse().unwrap()
}

fn layout(s: &str, shape: Shape) -> Layout {
    Layout::new(
        &sig(s),
        &LayoutOptions {
            shape,
            ..LayoutOptions::default()
        },
    )
    .unwrap_or_else(|e| panic!("{s}: {e}"))
}

/// Distance in model coordinates from a point to a drawn geodesic.
fn off_geodesic(g: &ModelGeodesic, z: Complex64) -> f64 {
    match *g {
        ModelGeodesic::Circle { centre, radius } => {
            ((z - centre).norm() - radius).abs() / radius.max(1.0)
        }
        ModelGeodesic::Line { point, direction } => {
            let d = z - point;
            (d.re * direction.im - d.im * direction.re).abs()
        }
    }
}

fn tangent(g: &ModelGeodesic, z: Complex64) -> Complex64 {
    match *g {
        ModelGeodesic::Circle { centre, .. } => {
            let t = Complex64::i() * (z - centre);
            t / t.norm()
        }
        ModelGeodesic::Line { direction, .. } => direction,
    }
}

/// Area of a geodesic triangle from its ambient corners (Oosterom–Strackee, and its hyperbolic
/// analogue); ideal corners have weight 0 and any positive scale.
fn triangle_area(space: Space, p: [DVec3; 3], finite: [f64; 3]) -> f64 {
    let det = p[0].dot(p[1].cross(p[2])).abs();
    let k = space.kappa();
    let dot = |a: DVec3, b: DVec3| space.point_dot(a, b);
    let denominator = finite[0] * finite[1] * finite[2]
        + k * (dot(p[0], p[1]) * finite[2]
            + dot(p[1], p[2]) * finite[0]
            + dot(p[2], p[0]) * finite[1]);
    2.0 * det.atan2(denominator)
}

/// The area of the polygon as a fan of triangles from its centre, from the corner positions alone.
fn fan_area(layout: &Layout) -> f64 {
    let space = layout.space();
    let n = layout.vertices.len();
    let ambient = |v: &orbifold::layout::Vertex| {
        if v.ideal {
            (DVec3::new(v.position.re, v.position.im, 1.0), 0.0)
        } else {
            (space.to_ambient(v.position), 1.0)
        }
    };
    let o = space.to_ambient(layout.centre);
    (0..n)
        .map(|i| {
            let (a, wa) = ambient(&layout.vertices[i]);
            let (b, wb) = ambient(&layout.vertices[(i + 1) % n]);
            if space.kappa() == 0.0 {
                let (za, zb, zo) = (
                    layout.vertices[i].position,
                    layout.vertices[(i + 1) % n].position,
                    layout.centre,
                );
                let cross = (za - zo).re * (zb - zo).im - (za - zo).im * (zb - zo).re;
                2.0 * cross.abs()
            } else {
                triangle_area(space, [o, a, b], [1.0, wa, wb])
            }
        })
        .sum()
}

/// Every invariant of ARCHITECTURE.md §5, for one layout.
fn check(layout: &Layout) {
    let space = layout.space();
    let name = layout.symbol.to_string();
    let n = layout.vertices.len();
    assert_eq!(layout.edges.len(), n.max(1));
    for (i, v) in layout.vertices.iter().enumerate() {
        let (prev, next) = (
            &layout.vertices[(i + n - 1) % n],
            &layout.vertices[(i + 1) % n],
        );
        let (wall_in, wall_out) = (&layout.edges[(i + n - 1) % n], &layout.edges[i]);
        // The corner lies on both of its walls.
        assert!(
            off_geodesic(&wall_in.geodesic, v.position) < 1e-9,
            "{name}: corner {i} off wall {}",
            (i + n - 1) % n
        );
        assert!(
            off_geodesic(&wall_out.geodesic, v.position) < 1e-9,
            "{name}: corner {i} off wall {i}"
        );
        if v.ideal {
            assert!(
                (v.position.norm() - 1.0).abs() < 1e-12,
                "{name}: ideal corner {i} not at infinity"
            );
            // The two walls are tangent there.
            let (a, b) = (
                tangent(&wall_in.geodesic, v.position),
                tangent(&wall_out.geodesic, v.position),
            );
            assert!(
                (a.re * b.im - a.im * b.re).abs() < 1e-7,
                "{name}: walls at ideal corner {i} not tangent"
            );
            continue;
        }
        assert!(
            v.position.norm() < 1.0 || space.kappa() >= 0.0,
            "{name}: corner {i} outside the disk"
        );
        if n == 2 {
            continue;
        }
        // The corner angle between the two walls' geodesics at the corner, each tangent pointing
        // along its side (the model is conformal, so model angles are true angles).
        let to_next = space.direction(v.position, next.position);
        let to_prev = space.direction(v.position, prev.position);
        let along =
            |t: Complex64, towards: Complex64| if (t * towards.conj()).re < 0.0 { -t } else { t };
        let t_next = along(tangent(&wall_out.geodesic, v.position), to_next);
        let t_prev = along(tangent(&wall_in.geodesic, v.position), to_prev);
        let angle = (t_prev / t_next).arg();
        assert!(
            (angle - v.angle).abs() < 1e-9,
            "{name}: corner {i} has angle {angle}, expected {}",
            v.angle
        );
        // The same from the corner positions alone.
        let chord_angle = (to_prev / to_next).arg();
        assert!(
            (chord_angle - v.angle).abs() < 1e-9,
            "{name}: corner {i} has chord angle {chord_angle}"
        );
        assert!((v.angle - v.order.corner_angle()).abs() < 1e-15);
    }
    // Convex and simple: every corner is on the inner side of every wall, and the corners go
    // once around the centre, counter-clockwise.
    for (i, v) in layout.vertices.iter().enumerate() {
        if v.ideal {
            continue;
        }
        let p = space.to_ambient(v.position);
        for e in &layout.edges {
            assert!(
                e.wall.dot(p) > -1e-9 * p.length(),
                "{name}: corner {i} outside wall {:?}",
                e.from
            );
        }
    }
    if n >= 3 {
        let turning: f64 = (0..n)
            .map(|i| {
                // Bearings of the corners as seen along geodesics from the centre.
                let a = space.direction(layout.centre, layout.vertices[i].position);
                let b = space.direction(layout.centre, layout.vertices[(i + 1) % n].position);
                let step = (b / a).arg();
                assert!(
                    step > 0.0,
                    "{name}: corners not counter-clockwise around the centre"
                );
                step
            })
            .sum();
        assert!(
            (turning - 2.0 * PI).abs() < 1e-9,
            "{name}: corners wind {turning}"
        );
    }
    // The centre is inside.
    let c = space.to_ambient(layout.centre);
    for e in &layout.edges {
        assert!(e.wall.dot(c) > 0.0, "{name}: centre outside a wall");
    }
    // Gauss–Bonnet: the area from the corners alone equals 2π|χ|.
    if space.kappa() != 0.0 && n >= 3 {
        let expected = layout.symbol.euler_characteristic().area();
        assert!((layout.area - expected).abs() <= 1e-12 * expected.max(1.0));
        let measured = fan_area(layout);
        assert!(
            (measured - expected).abs() <= 1e-8 * expected,
            "{name}: fan area {measured}, 2π|χ| = {expected}"
        );
    }
    if space.kappa() == 0.0 {
        assert!((fan_area(layout) - layout.area).abs() < 1e-9 * layout.area);
    }
}

#[test]
fn spherical_list() {
    for s in [
        "*",
        "*22",
        "*55",
        "*222",
        "*227",
        "*233",
        "*234",
        "*235",
        "*532",
        "*(3/2)33",
        "*(3/2)(3/2)",
    ] {
        let l = layout(s, Shape::Default);
        assert_eq!(l.geometry, Geometry::Spherical);
        check(&l);
    }
    assert!((layout("*", Shape::Default).area - 2.0 * PI).abs() < 1e-15);
    let lune = layout("*33", Shape::Default);
    assert!((lune.vertices[0].position - Complex64::new(1.0, 0.0)).norm() < 1e-15);
    assert!((lune.vertices[1].position - Complex64::new(-1.0, 0.0)).norm() < 1e-15);
}

#[test]
fn euclidean_list() {
    for s in ["*333", "*244", "*236", "*2222", "*(1.5)(6)(6)"] {
        let l = layout(s, Shape::Default);
        assert_eq!(l.geometry, Geometry::Euclidean);
        check(&l);
    }
    let rect = layout("*2222", Shape::Parameters(vec![3.0]));
    assert!((rect.edges[0].length / rect.edges[1].length - 3.0).abs() < 1e-12);
    assert_eq!(layout("*2222", Shape::Incircle).parameters, vec![1.0]);
}

#[test]
fn seed_examples() {
    for s in [
        "*23456",
        "*23456789(10)(11)",
        "*∞∞∞",
        "*∞∞∞∞",
        "*∞∞∞∞∞",
        "*2352",
        "*22222",
        "*2223",
        "*237",
        "*2∞∞",
        "*222∞∞",
    ] {
        for shape in [Shape::Default, Shape::Incircle] {
            let l = layout(s, shape);
            assert_eq!(l.geometry, Geometry::Hyperbolic);
            check(&l);
        }
    }
}

#[test]
fn non_orbifold_hyperbolic_rooms() {
    for s in [
        "*22(3/2)222",
        "*(3/2)22222",
        "*(3/2)(3/2)(3/2)(3/2)(3/2)(3/2)(3/2)",
        "*2(5/4)2(5/4)2(5/4)2",
        "*(7/5)∞∞",
        "*(5/4)(3/2)22∞",
    ] {
        for shape in [Shape::Default, Shape::Incircle] {
            let l = layout(s, shape);
            assert_eq!(l.geometry, Geometry::Hyperbolic, "{s}");
            check(&l);
        }
    }
    check(&layout(
        "*22(5/2)222",
        Shape::Parameters(vec![0.3, 4.0, 2.0]),
    ));
    let err = Layout::new(
        &sig("*(3/2)22222"),
        &LayoutOptions {
            shape: Shape::Parameters(vec![1.0; 3]),
            ..LayoutOptions::default()
        },
    );
    assert!(
        matches!(err, Err(LayoutError::Unsupported(message)) if message.contains("--shape incircle"))
    );
}

#[test]
fn parameters_scale_the_wall_distances_of_the_balanced_polygon() {
    let distances = |l: &Layout| {
        let space = l.space();
        let n = l.vertices.len();
        (1..=n - 3)
            .map(|j| (-space.wall_dot(l.edges[n - 1].wall, l.edges[j].wall)).acosh())
            .collect::<Vec<f64>>()
    };
    let balanced = layout("*234567", Shape::Incircle);
    assert_eq!(balanced.parameters, vec![1.0; 3]);
    // All parameters 1 rebuild the balanced polygon.
    let ones = layout("*234567", Shape::Parameters(vec![1.0; 3]));
    for (a, b) in balanced.edges.iter().zip(&ones.edges) {
        assert!(
            (a.length - b.length).abs() < 1e-9,
            "{} vs {}",
            a.length,
            b.length
        );
    }
    let values = vec![0.07, 2.5, 9.0];
    let deformed = layout("*234567", Shape::Parameters(values.clone()));
    assert_eq!(deformed.parameters, values);
    for ((c, c0), p) in distances(&deformed)
        .iter()
        .zip(distances(&balanced))
        .zip(&values)
    {
        assert!((c - c0 * p.powf(0.125)).abs() < 1e-9, "{c} vs {c0}·{p}^⅛");
    }
}

#[test]
fn impossible_requests_are_clear_errors() {
    let err = |s: &str, shape: Shape| {
        Layout::new(
            &sig(s),
            &LayoutOptions {
                shape,
                ..LayoutOptions::default()
            },
        )
        .unwrap_err()
    };
    assert!(matches!(
        err("*23", Shape::Default),
        LayoutError::NotBuildable(_)
    ));
    assert!(
        err("*5", Shape::Default)
            .to_string()
            .contains("single mirror")
    );
    assert!(matches!(
        err("*(3/2)(3/2)(3/2)(3/2)", Shape::Default),
        LayoutError::Unsupported(_)
    ));
    assert!(matches!(
        err("*∞∞", Shape::Default),
        LayoutError::Unsupported(_)
    ));
    assert_eq!(
        err("*22222", Shape::Parameters(vec![1.0])),
        LayoutError::ParameterCount {
            expected: 2,
            given: 1
        }
    );
    assert_eq!(
        err("*235", Shape::Parameters(vec![1.0])),
        LayoutError::ParameterCount {
            expected: 0,
            given: 1
        }
    );
    assert_eq!(
        err("*22222", Shape::Parameters(vec![1.0, -2.0])),
        LayoutError::InvalidParameter {
            index: 1,
            value: -2.0
        }
    );
    assert!(matches!(
        err("*22222", Shape::Parameters(vec![f64::NAN, 1.0])),
        LayoutError::InvalidParameter { .. }
    ));
    let outside = Layout::new(
        &sig("*22222"),
        &LayoutOptions {
            at: Complex64::new(0.8, 0.8),
            ..LayoutOptions::default()
        },
    );
    assert!(matches!(outside, Err(LayoutError::Placement(_))));
}

fn hyperbolic_signature() -> impl Strategy<Value = Signature> {
    let order = prop_oneof![8 => (2u64..=20).prop_map(Order::integer), 1 => Just(Order::Infinite)];
    prop::collection::vec(order, 3..=30)
        .prop_map(|c| Signature::new(c).unwrap())
        .prop_filter("hyperbolic", |s| s.geometry() == Geometry::Hyperbolic)
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(300))]

    #[test]
    fn random_hyperbolic_polygons(
        s in hyperbolic_signature(),
        raw in prop::collection::vec(0.05f64..10.0, 27),
        at in (0.0f64..0.9, 0.0f64..(2.0 * PI)),
        angle in 0.0f64..360.0,
        incircle: bool,
    ) {
        let n = s.corner_count();
        let shape = if incircle || n == 3 { Shape::Incircle } else { Shape::Parameters(raw[..n - 3].to_vec()) };
        let here = LayoutOptions { shape: shape.clone(), ..LayoutOptions::default() };
        let there = LayoutOptions { shape, at: Complex64::from_polar(at.0, at.1), angle: angle.to_radians() };
        let a = Layout::new(&s, &here).unwrap();
        let b = Layout::new(&s, &there).unwrap();
        check(&a);
        check(&b);
        // Placement is an isometry: the sides keep their lengths.
        for (ea, eb) in a.edges.iter().zip(&b.edges) {
            prop_assert!(ea.length == eb.length || (ea.length - eb.length).abs() < 1e-7 * ea.length.max(1.0));
        }
    }

    /// Non-orbifold corners, obtuse ones included, wherever the comb accepts them.
    #[test]
    fn random_non_orbifold_polygons(
        orders in prop::collection::vec((1u64..=6, 1u64..=40), 3..=12),
        raw in prop::collection::vec(0.05f64..10.0, 9),
    ) {
        let corners = orders.iter().map(|&(q, extra)| Order::ratio(q + extra, q).unwrap());
        let s = Signature::new(corners).unwrap();
        prop_assume!(s.geometry() == Geometry::Hyperbolic);
        let n = s.corner_count();
        check(&Layout::new(&s, &LayoutOptions { shape: Shape::Incircle, ..LayoutOptions::default() }).unwrap());
        let with_params = Layout::new(&s, &LayoutOptions { shape: Shape::Parameters(raw[..n.saturating_sub(3)].to_vec()), ..LayoutOptions::default() });
        match with_params {
            Ok(l) => check(&l),
            Err(e) => prop_assert!(matches!(e, LayoutError::Unsupported(_)), "{e}"),
        }
    }

    #[test]
    fn spherical_and_euclidean_placements(
        s in prop::sample::select(vec!["*", "*22", "*77", "*222", "*22(11)", "*233", "*234", "*235", "*333", "*244", "*236", "*2222"]),
        at in (0.0f64..0.9, 0.0f64..(2.0 * PI)),
        angle in 0.0f64..360.0,
        aspect in 0.05f64..10.0,
    ) {
        let s = sig(s);
        let shape = if s.free_parameters() == 1 { Shape::Parameters(vec![aspect]) } else { Shape::Default };
        let l = Layout::new(&s, &LayoutOptions { shape, at: Complex64::from_polar(at.0, at.1), angle: angle.to_radians() }).unwrap();
        check(&l);
    }
}
