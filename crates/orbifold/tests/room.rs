//! Room tessellation: floors tile the polygon exactly (intrinsic areas add up to 2π|χ| less the
//! cusps cut off), lie inside it, face up, and meet the resolution; walls lie on their walls.

use glam::{DMat3, DVec3};
use num_complex::Complex64;
use orbifold::room::wall::WallRect;
use orbifold::room::{FloorMethod, RoomMesher, RoomOptions, Surface};
use orbifold::space::Space;
use orbifold::{Geometry, Layout, LayoutOptions, Order, Shape, Signature};
use proptest::prelude::*;

const METHODS: [FloorMethod; 2] = [FloorMethod::Contour, FloorMethod::Geodesic];

fn mesher(sig: &str, options: &LayoutOptions, room: RoomOptions) -> (Layout, RoomMesher) {
    let s: Signature = sig.parse().unwrap();
    let layout = Layout::new(&s, options).unwrap();
    let mesher = RoomMesher::new(&layout, &room).unwrap();
    (layout, mesher)
}

/// Every check of a floor; `stretch` bounds the longest edge relative to the resolution.
fn check_floor(layout: &Layout, mesher: &RoomMesher, floor: &Surface, stretch: f64) {
    let space = layout.space();
    let sig = &layout.symbol;
    assert!(!floor.triangles.is_empty(), "{sig}: empty floor");
    // Inside: every vertex on the inner side of every wall.
    for p in &floor.points {
        for (i, e) in layout.edges.iter().enumerate() {
            assert!(e.wall.dot(*p) > -1e-9, "{sig}: vertex {p} outside wall {i}");
        }
    }
    // Facing up, none degenerate.
    for t in &floor.triangles {
        let [a, b, c] = t.map(|i| floor.points[i as usize]);
        let det = DMat3::from_cols(a, b, c).determinant();
        // The determinant of three vectors of length up to |p| rounds to about ε|p|³ (far out on
        // the hyperboloid |p| ~ cosh of the distance): below that a sign is not a mesh defect.
        let far = a.length().max(b.length()).max(c.length());
        let rounding = 1e-15 * far.powi(3);
        assert!(
            det > 0.0 || det.abs() < rounding,
            "{sig}: triangle {t:?} faces down or is degenerate ({det})"
        );
    }
    // Positively oriented triangles inside the polygon whose areas add up to the polygon's cover
    // it exactly once.
    let area = floor.horizontal_area(space);
    let expected = gauss_bonnet(mesher).unwrap_or(mesher.meshed_area());
    // The determinant behind each triangle's area rounds to about 6ε|p|³: far out on the
    // hyperboloid (|p| ~ cosh of the distance) that is the precision there is.
    let rounding: f64 = floor
        .triangles
        .iter()
        .map(|t| {
            1e-15
                * t.iter()
                    .map(|&i| floor.points[i as usize].length())
                    .fold(0.0, f64::max)
                    .powi(3)
        })
        .sum();
    assert!(
        (area - expected).abs() < 1e-10 * expected.max(1.0) + rounding,
        "{sig}: floor area {area} but polygon {expected} (cusps {})",
        mesher.cusp_area()
    );
    // 2π|χ| less the cusps; far-out layouts pin their corners down less precisely.
    assert!((mesher.meshed_area() - expected).abs() < 1e-6 * expected.max(1.0));
    let q = floor.quality(space);
    assert!(
        q.largest_edge <= stretch * mesher.options.resolution + 1e-9,
        "{sig}: edge {} for resolution {}",
        q.largest_edge,
        mesher.options.resolution
    );
    assert!(q.smallest_angle > 0.0, "{sig}: a degenerate triangle");
}

/// The area of the meshed loop from its corner angles (Gauss–Bonnet), for κ ≠ 0.
fn gauss_bonnet(mesher: &RoomMesher) -> Option<f64> {
    let b = &mesher.boundary;
    let space = b.space;
    if space.kappa() == 0.0 {
        return None;
    }
    let n = b.len();
    let angles: f64 = (0..n)
        .map(|i| {
            orbifold::room::surface::angle(
                space,
                b.corners[i],
                b.corners[(i + n - 1) % n],
                b.corners[(i + 1) % n],
            )
        })
        .sum();
    Some((angles - (n as f64 - 2.0) * std::f64::consts::PI) / space.kappa())
}

fn check_walls(layout: &Layout, mesher: &RoomMesher) {
    let space = layout.space();
    let height = mesher.options.height;
    for (i, edge) in layout.edges.iter().enumerate() {
        let wall = mesher.whole_wall(i).unwrap();
        for (p, h) in wall.points.iter().zip(&wall.heights) {
            let scale = 1.0 + p.length() * edge.wall.length();
            assert!(
                edge.wall.dot(*p).abs() < 1e-13 * scale,
                "{}: wall {i} vertex off the wall by {}",
                layout.symbol,
                edge.wall.dot(*p)
            );
            assert!((-1e-12..=height + 1e-12).contains(h));
        }
        // The wall is flat in (arc length, height): its triangles' areas add up to length × height.
        let area: f64 = wall
            .triangles
            .iter()
            .map(|t| {
                let [a, b, c] = t.map(|k| (wall.points[k as usize], wall.heights[k as usize]));
                flat_area(space, a, b, c)
            })
            .sum();
        let expected = mesher.wall_length(i).unwrap() * height;
        assert!(
            (area - expected).abs() < 1e-9 * expected,
            "{}: wall {i} area {area} vs {expected}",
            layout.symbol
        );
        assert!(wall.quality(space).largest_edge <= mesher.options.resolution * 2f64.sqrt() + 1e-9);
    }
}

/// The area of a triangle on a wall (a flat strip: distance along the wall × height).
fn flat_area(space: Space, a: (DVec3, f64), b: (DVec3, f64), c: (DVec3, f64)) -> f64 {
    let (ab, ac) = (
        space.ambient_distance(a.0, b.0),
        space.ambient_distance(a.0, c.0),
    );
    let bc = space.ambient_distance(b.0, c.0);
    // Signed positions along the wall: a at 0, b at ±ab, c at ±ac with |b − c| = bc.
    let sc = if (ab - ac).abs() - bc < 1e-9 && (ab + ac - bc).abs() > 1e-9 {
        ac
    } else {
        -ac
    };
    let (u, v) = ((ab, b.1 - a.1), (sc, c.1 - a.1));
    0.5 * (u.0 * v.1 - u.1 * v.0).abs()
}

#[test]
fn every_kind_of_room_meshes() {
    let cases = [
        "*",
        "*22",
        "*33",
        "*55",
        "*222",
        "*223",
        "*233",
        "*234",
        "*235",
        "*2222",
        "*333",
        "*244",
        "*236",
        "*237",
        "*2223",
        "*2333",
        "*22222",
        "*∞∞∞",
        "*23∞",
        "*2∞∞",
        "*∞∞∞∞",
        "*22∞∞",
        "*23456789(10)(11)",
    ];
    for sig in cases {
        for method in METHODS {
            for resolution in [0.5, 0.07] {
                let room = RoomOptions {
                    resolution,
                    method,
                    height: 1.5,
                    ..RoomOptions::default()
                };
                let (layout, mesher) = mesher(sig, &LayoutOptions::default(), room);
                let stretch = if method == FloorMethod::Contour {
                    2.0
                } else {
                    1.0
                };
                check_floor(&layout, &mesher, &mesher.floor(), stretch);
                check_walls(&layout, &mesher);
                let ceiling = mesher.ceiling();
                assert!(ceiling.heights.iter().all(|&h| h == 1.5));
            }
        }
    }
}

#[test]
fn polygon_area_is_two_pi_chi() {
    for sig in ["*2223", "*333", "*236", "*22", "*"] {
        let (layout, mesher) = mesher(sig, &LayoutOptions::default(), RoomOptions::default());
        let chi = layout.symbol.euler_characteristic().to_f64();
        if layout.geometry != Geometry::Euclidean {
            assert!(
                (mesher.meshed_area() - 2.0 * std::f64::consts::PI * chi.abs()).abs() < 1e-9,
                "{sig}"
            );
        }
    }
}

#[test]
fn cusps_are_cut_where_asked() {
    let (layout, near) = mesher(
        "*∞∞∞",
        &LayoutOptions::default(),
        RoomOptions {
            cusp_distance: Some(2.0),
            ..RoomOptions::default()
        },
    );
    let (_, far) = mesher(
        "*∞∞∞",
        &LayoutOptions::default(),
        RoomOptions {
            cusp_distance: Some(4.0),
            ..RoomOptions::default()
        },
    );
    assert_eq!(near.boundary.cusp_distance, Some(2.0));
    let space = layout.space();
    let centre = space.to_ambient(layout.centre);
    for (p, side) in near.boundary.corners.iter().zip(&near.boundary.sides) {
        if side.wall.is_none() {
            assert!((space.ambient_distance(centre, *p) - 2.0).abs() < 1e-9);
        }
    }
    // Deeper cuts lose less: a cusp beyond distance r has area about e^{−r}.
    assert!(far.cusp_area() < near.cusp_area() && far.cusp_area() > 0.0);
    assert!(near.cusp_area() < 3.0);
    // A cut that would not clear the corners is moved out.
    let (_, clamped) = mesher(
        "*2∞∞",
        &LayoutOptions::default(),
        RoomOptions {
            cusp_distance: Some(0.01),
            ..RoomOptions::default()
        },
    );
    assert!(clamped.boundary.cusp_distance.unwrap() > 0.01);
}

#[test]
fn partial_walls_share_their_edges() {
    let (_, m) = mesher(
        "*2223",
        &LayoutOptions::default(),
        RoomOptions {
            resolution: 0.1,
            ..RoomOptions::default()
        },
    );
    let left = m
        .wall(
            1,
            WallRect {
                along: [0.0, 0.4],
                heights: [0.2, 0.7],
            },
        )
        .unwrap();
    let right = m
        .wall(
            1,
            WallRect {
                along: [0.4, 1.0],
                heights: [0.2, 0.7],
            },
        )
        .unwrap();
    let column = |s: &Surface, t: f64| -> Vec<(DVec3, f64)> {
        let p = m.wall_point(1, t).unwrap();
        s.points
            .iter()
            .zip(&s.heights)
            .filter(|(q, _)| (**q - p).length() < 1e-12)
            .map(|(q, h)| (*q, *h))
            .collect()
    };
    let (a, b) = (column(&left, 0.4), column(&right, 0.4));
    assert!(!a.is_empty());
    assert_eq!(a, b);
}

#[test]
fn bad_options_are_errors() {
    let s: Signature = "*333".parse().unwrap();
    let layout = Layout::new(&s, &LayoutOptions::default()).unwrap();
    for o in [
        RoomOptions {
            height: 0.0,
            ..RoomOptions::default()
        },
        RoomOptions {
            resolution: -1.0,
            ..RoomOptions::default()
        },
        RoomOptions {
            resolution: f64::NAN,
            ..RoomOptions::default()
        },
        RoomOptions {
            resolution: 1e-6,
            ..RoomOptions::default()
        },
        RoomOptions {
            cusp_distance: Some(f64::INFINITY),
            ..RoomOptions::default()
        },
    ] {
        let e = RoomMesher::new(&layout, &o).unwrap_err();
        assert!(e.to_string().starts_with("cannot mesh the room"), "{e}");
    }
}

#[test]
fn triangle_area_agrees_with_angle_excess() {
    for g in [Geometry::Spherical, Geometry::Hyperbolic] {
        let space = Space::new(g);
        let z = [
            Complex64::new(0.1, 0.2),
            Complex64::new(-0.3, 0.1),
            Complex64::new(0.2, -0.5),
        ];
        let [a, b, c] = z.map(|z| space.to_ambient(z));
        let angle = |p, q, r| orbifold::room::surface::angle(space, p, q, r);
        let sum = angle(a, b, c) + angle(b, c, a) + angle(c, a, b);
        let excess = (sum - std::f64::consts::PI) / space.kappa();
        assert!(
            (space.triangle_area(a, b, c) - excess).abs() < 1e-12,
            "{g:?}"
        );
    }
}

fn random_signature() -> impl Strategy<Value = Signature> {
    let order = prop_oneof![8 => (2u64..=9).prop_map(Order::integer), 1 => Just(Order::Infinite)];
    prop::collection::vec(order, 0..=8).prop_filter_map("buildable", |c| {
        let s = Signature::new(c).ok()?;
        s.is_buildable().then_some(s)
    })
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(120))]

    #[test]
    fn random_rooms(
        s in random_signature(),
        raw in prop::collection::vec(0.2f64..5.0, 8),
        at in (0.0f64..0.6, 0.0f64..6.3),
        angle in 0.0f64..6.3,
        resolution in 0.05f64..0.8,
        geodesic: bool,
    ) {
        let n = s.corner_count();
        let shape = if s.geometry() == Geometry::Hyperbolic && n > 3 { Shape::Parameters(raw[..n - 3].to_vec()) } else { Shape::Default };
        let options = LayoutOptions { shape, at: Complex64::from_polar(at.0, at.1), angle };
        let Ok(layout) = Layout::new(&s, &options) else { return Ok(()); };
        let method = if geodesic { FloorMethod::Geodesic } else { FloorMethod::Contour };
        let room = RoomOptions { resolution, method, ..RoomOptions::default() };
        let Ok(m) = RoomMesher::new(&layout, &room) else { return Ok(()); };
        check_floor(&layout, &m, &m.floor(), if geodesic { 1.0 } else { 2.0 });
        check_walls(&layout, &m);
    }
}
