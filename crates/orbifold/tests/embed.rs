//! Objects are rigid: embedding keeps distances and bearings from the centre, and moving an
//! object keeps every pairwise intrinsic distance of its vertices.

use glam::DVec3;
use num_complex::Complex64;
use orbifold::Geometry;
use orbifold::embed::{Placement, centre_of_mass, embed, place};
use orbifold::space::Space;
use proptest::prelude::*;

const GEOMETRIES: [Geometry; 3] = [
    Geometry::Spherical,
    Geometry::Euclidean,
    Geometry::Hyperbolic,
];

fn product_distance(space: Space, a: (DVec3, f64), b: (DVec3, f64)) -> f64 {
    space.ambient_distance(a.0, b.0).hypot(a.1 - b.1)
}

fn vertices() -> impl Strategy<Value = Vec<[f64; 3]>> {
    prop::collection::vec(prop::array::uniform3(-0.6f64..0.6), 2..40)
}

fn placement() -> impl Strategy<Value = Placement> {
    (0.0f64..0.8, 0.0f64..6.3, 0.0f64..2.0, -7.0f64..7.0).prop_map(|(r, theta, height, yaw)| {
        Placement {
            at: Complex64::from_polar(r, theta),
            height,
            yaw,
        }
    })
}

proptest! {
    #[test]
    fn moving_an_object_keeps_its_shape(v in vertices(), a in placement(), b in placement(), scale in 0.1f64..2.0) {
        for g in GEOMETRIES {
            let space = Space::new(g);
            let e = embed(space, &v, DVec3::ZERO, scale);
            let (pa, pb) = (place(space, &e, &a), place(space, &e, &b));
            for i in 0..v.len() {
                for j in 0..i {
                    let da = product_distance(space, (pa.points[i], pa.heights[i]), (pa.points[j], pa.heights[j]));
                    let db = product_distance(space, (pb.points[i], pb.heights[i]), (pb.points[j], pb.heights[j]));
                    let d0 = product_distance(space, (e.points[i], e.heights[i]), (e.points[j], e.heights[j]));
                    prop_assert!((da - db).abs() < 1e-9 && (da - d0).abs() < 1e-9, "{g:?}: {da} {db} {d0}");
                }
            }
            // The placement's centre is where the centre of mass went.
            let centre = place(space, &embed(space, &[[0.0; 3]], DVec3::ZERO, 1.0), &a);
            prop_assert!((space.to_model(centre.points[0]) - a.at).norm() < 1e-12);
        }
    }

    #[test]
    fn the_exponential_map_keeps_distance_and_bearing(v in vertices(), scale in 0.1f64..2.0) {
        for g in GEOMETRIES {
            let space = Space::new(g);
            let e = embed(space, &v, DVec3::ZERO, scale);
            for (p, q) in v.iter().zip(&e.points) {
                let r = scale * p[0].hypot(p[2]);
                prop_assert!((space.ambient_distance(DVec3::Z, *q) - r).abs() < 1e-12);
                if r > 1e-6 {
                    // Bearing: object x is model x, object z is model −y (not mirrored from above).
                    let z = space.to_model(*q);
                    let expected = Complex64::new(p[0], -p[2]).arg();
                    let d = (z.arg() - expected).rem_euclid(std::f64::consts::TAU);
                    prop_assert!(!(1e-9..=std::f64::consts::TAU - 1e-9).contains(&d));
                }
            }
            let lowest = e.heights.iter().cloned().fold(f64::INFINITY, f64::min);
            prop_assert!(lowest.abs() < 1e-15);
        }
    }
}

#[test]
fn centre_of_mass_of_a_solid() {
    // A tetrahedron with one corner at the origin: its centroid is the mean of its corners.
    let p = [
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        [0.0, 0.0, 1.0],
    ];
    let t = [[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]];
    let c = centre_of_mass(&p, &t);
    assert!((c - DVec3::splat(0.25)).length() < 1e-15);
    // A flat square: the centre of its surface.
    let p = [
        [0.0, 0.0, 0.0],
        [2.0, 0.0, 0.0],
        [2.0, 0.0, 2.0],
        [0.0, 0.0, 2.0],
    ];
    let c = centre_of_mass(&p, &[[0, 1, 2], [0, 2, 3]]);
    assert!((c - DVec3::new(1.0, 0.0, 1.0)).length() < 1e-15);
}
