//! The analytic room: exits lie on their face and nowhere outside the room, mirror coordinates
//! agree with the room mesher's, and partial mirrors are found where they are.

use num_complex::Complex64;
use orbifold::room::{RoomMesher, RoomOptions};
use orbifold::{Geometry, Layout, LayoutOptions, Order, Shape, Signature};
use orbifold_trace::geodesic::Ray;
use orbifold_trace::room::{AnalyticRoom, MirrorRect, RoomSurface};
use proptest::prelude::*;

fn random_signature() -> impl Strategy<Value = Signature> {
    let order = prop_oneof![8 => (2u64..=9).prop_map(Order::integer), 1 => Just(Order::Infinite)];
    prop::collection::vec(order, 0..=7).prop_filter_map("buildable", |c| {
        let s = Signature::new(c).ok()?;
        s.is_buildable().then_some(s)
    })
}

fn layout(s: &Signature, raw: &[f64]) -> Option<Layout> {
    let n = s.corner_count();
    let shape = if s.geometry() == Geometry::Hyperbolic && n > 3 {
        Shape::Parameters(raw[..n - 3].to_vec())
    } else {
        Shape::Default
    };
    Layout::new(
        s,
        &LayoutOptions {
            shape,
            ..LayoutOptions::default()
        },
    )
    .ok()
}

/// A point strictly inside: part of the way from the centre towards a corner (or a wall point).
fn inside(layout: &Layout, t: f64, k: usize) -> Complex64 {
    let target = if layout.vertices.is_empty() {
        Complex64::new(1.0, 0.0)
    } else {
        let v = layout.vertices[k % layout.vertices.len()].position;
        if layout.vertices[k % layout.vertices.len()].ideal {
            v * 0.9
        } else {
            v
        }
    };
    layout.centre + (target - layout.centre) * t
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(200))]

    #[test]
    fn exits_lie_on_their_face(
        s in random_signature(),
        raw in prop::collection::vec(0.3f64..4.0, 8),
        t in 0.0f64..0.8,
        k in 0usize..8,
        yaw in 0.0f64..6.3,
        pitch in -1.5f64..1.5,
        h in 0.05f64..0.95,
    ) {
        let Some(layout) = layout(&s, &raw) else { return Ok(()); };
        let room = AnalyticRoom::all_mirrors(&layout, 1.0, [0.9; 3]).unwrap();
        let space = layout.space();
        let ray = Ray::from_model(space, inside(&layout, t, k), h, yaw, pitch);
        let Some(exit) = room.exit(&ray) else {
            // Only a horizontal ray can run out, through an ideal corner.
            prop_assert!(pitch.abs() < 1e-9 || layout.vertices.iter().any(|v| v.ideal));
            return Ok(());
        };
        prop_assert!(exit.s >= 0.0);
        let (p, height) = ray.point_at(space, exit.s);
        let scale = p.length().max(1.0);
        match exit.surface {
            RoomSurface::Floor => prop_assert!(height.abs() < 1e-9),
            RoomSurface::Ceiling => prop_assert!((height - 1.0).abs() < 1e-9),
            RoomSurface::Wall(i) => prop_assert!(layout.edges[i].wall.dot(p).abs() < 1e-9 * scale),
        }
        for (i, e) in layout.edges.iter().enumerate() {
            prop_assert!(e.wall.dot(p) > -1e-9 * scale, "{s}: exit outside wall {i}");
        }
        prop_assert!((-1e-9..=1.0 + 1e-9).contains(&height));
    }

    #[test]
    fn mirror_fractions_agree_with_the_mesher(
        s in random_signature(),
        raw in prop::collection::vec(0.3f64..4.0, 8),
        f in 0.0f64..1.0,
    ) {
        let Some(layout) = layout(&s, &raw) else { return Ok(()); };
        let room = AnalyticRoom::all_mirrors(&layout, 1.0, [0.9; 3]).unwrap();
        let mesher = RoomMesher::new(&layout, &RoomOptions { resolution: 1.0, ..RoomOptions::default() }).unwrap();
        for wall in 0..layout.edges.len() {
            let p = mesher.wall_point(wall, f).unwrap();
            let along = room.along(wall, p);
            prop_assert!((along - f).abs() < 1e-9, "{s}: wall {wall} at {f} reads {along}");
        }
    }
}

#[test]
fn partial_mirrors_are_found_where_they_are() {
    let layout = Layout::new(&"*2222".parse().unwrap(), &LayoutOptions::default()).unwrap();
    let upper = MirrorRect {
        from: 0.25,
        to: 0.75,
        bottom: 0.5,
        top: 1.0,
        reflectance: [0.5, 0.6, 0.7],
    };
    let room = AnalyticRoom::new(&layout, 1.0, None, &[vec![upper]]).unwrap();
    let mesher = RoomMesher::new(&layout, &RoomOptions::default()).unwrap();
    let middle = mesher.wall_point(0, 0.5).unwrap();
    let edge = mesher.wall_point(0, 0.1).unwrap();
    assert!(room.mirror_at(0, middle, 0.7).is_some());
    assert!(room.mirror_at(0, middle, 0.3).is_none());
    assert!(room.mirror_at(0, edge, 0.7).is_none());
    assert!(room.mirror_at(1, middle, 0.7).is_none());
}

#[test]
fn the_perpendicular_from_the_centre_meets_its_wall_at_the_distance() {
    for sig in ["*333", "*444", "*555", "*22", "*235", "*2222"] {
        let layout = Layout::new(&sig.parse().unwrap(), &LayoutOptions::default()).unwrap();
        let space = layout.space();
        let room = AnalyticRoom::all_mirrors(&layout, 1.0, [1.0; 3]).unwrap();
        let centre = space.to_ambient(layout.centre);
        for (i, e) in layout.edges.iter().enumerate() {
            // The foot of the perpendicular from the centre: the inner normal at the centre
            // points away from the wall, so head against it.
            let normal = glam::DVec3::new(e.wall.x, e.wall.y, space.kappa() * e.wall.z);
            let k = space.kappa();
            let towards = if k == 0.0 {
                -glam::DVec3::new(normal.x, normal.y, 0.0)
            } else {
                -(normal - centre * (space.point_dot(centre, normal) / k))
            };
            let ray = Ray::new(space, centre, towards, 0.5, 0.0);
            let exit = room.exit(&ray).unwrap();
            let distance = space.asin(e.wall.dot(centre));
            // Every wall of these polygons is tangent to the circle about the centre through
            // the nearest wall points, so the perpendicular meets its own wall first.
            assert_eq!(exit.surface, RoomSurface::Wall(i), "{sig}");
            assert!((exit.s - distance).abs() < 1e-12, "{sig} wall {i}");
        }
    }
}
