//! Animation paths: inside the room, closed, constant speed, facing the right way; keyframes.

use num_complex::Complex64;
use orbifold::Layout;
use orbifold_scene::Scene;
use orbifold_scene::animation::{Path, Pose};
use proptest::prelude::*;

fn layout(signature: &str) -> Layout {
    let mut scene = Scene::default();
    scene.orbifold.signature = signature.into();
    scene.layout().unwrap()
}

fn inside(layout: &Layout, at: [f64; 2]) -> bool {
    let space = layout.space();
    let p = space.to_ambient(Complex64::new(at[0], at[1]));
    layout.edges.iter().all(|e| e.wall.dot(p) > 0.0)
}

fn z(pose: &Pose) -> Complex64 {
    Complex64::new(pose.at[0], pose.at[1])
}

/// The smallest difference between two bearings, degrees.
fn turn(a: f64, b: f64) -> f64 {
    ((a - b + 180.0).rem_euclid(360.0) - 180.0).abs()
}

const SIGNATURES: [&str; 8] = [
    "*235",
    "*22",
    "*333",
    "*2222",
    "*22222",
    "*2223",
    "*∞∞∞",
    "*23456",
];

#[test]
fn the_walk_along_the_walls_stays_inside_and_closes() {
    for signature in SIGNATURES {
        let layout = layout(signature);
        let space = layout.space();
        let start = Pose {
            at: [layout.centre.re, layout.centre.im],
            height: 0.5,
            yaw: 0.0,
            pitch: -10.0,
        };
        let n = 400;
        let poses: Vec<Pose> = (0..=n)
            .map(|i| Path::Walls.pose(&layout, start, i, n))
            .collect();
        let steps: Vec<f64> = poses
            .windows(2)
            .map(|w| space.distance(z(&w[0]), z(&w[1])))
            .collect();
        for (i, pose) in poses.iter().enumerate() {
            assert!(
                inside(&layout, pose.at),
                "{signature}: frame {i} {:?} outside",
                pose.at
            );
            assert_eq!((pose.height, pose.pitch), (0.5, -10.0));
        }
        // Closed: frame n is frame 0.
        assert!(
            space.distance(z(&poses[0]), z(&poses[n])) < 1e-9,
            "{signature}"
        );
        assert!(turn(poses[0].yaw, poses[n].yaw) < 1e-6, "{signature}");
        // Constant speed along the sides (a frame that turns a corner cuts it: shorter).
        let mut sorted = steps.clone();
        sorted.sort_by(f64::total_cmp);
        let step = sorted[n / 2];
        let even = steps
            .iter()
            .filter(|s| (*s - step).abs() < 1e-6 * (1.0 + step))
            .count();
        assert!(
            even >= n - layout.vertices.len(),
            "{signature}: {even} of {n} even steps"
        );
        assert!(
            steps.iter().all(|s| *s <= step * (1.0 + 1e-6)),
            "{signature}"
        );
        // Facing the way it goes, except while turning a corner.
        let mut facing = 0;
        for w in poses.windows(2) {
            let travel = space.direction(z(&w[0]), z(&w[1])).arg().to_degrees();
            if turn(travel, w[0].yaw) < 45.0 {
                facing += 1;
            }
        }
        assert!(
            facing * 10 >= n * 7,
            "{signature}: facing the way it goes in {facing} of {n}"
        );
    }
}

#[test]
fn an_orbit_keeps_its_distance_and_faces_the_centre() {
    for signature in SIGNATURES {
        let layout = layout(signature);
        let space = layout.space();
        let c = layout.centre;
        let start_point = c + (layout.vertices[0].position - c) * 0.2;
        let start = Pose {
            at: [start_point.re, start_point.im],
            height: 0.3,
            yaw: 17.0,
            pitch: 5.0,
        };
        let radius = space.distance(c, start_point);
        for i in 0..24 {
            let pose = Path::Orbit.pose(&layout, start, i, 24);
            assert!(
                (space.distance(c, z(&pose)) - radius).abs() < 1e-9,
                "{signature}"
            );
            let towards = space.direction(z(&pose), c).arg().to_degrees();
            assert!(turn(towards, pose.yaw) < 1e-6, "{signature} frame {i}");
        }
        let first = Path::Orbit.pose(&layout, start, 0, 24);
        assert!(space.distance(z(&first), start_point) < 1e-9);
    }
}

proptest! {
    #[test]
    fn keyframes_are_met_and_joined_by_geodesics(
        keys in prop::collection::vec(
            ((-0.3f64..0.3), (-0.3f64..0.3), (0.1f64..0.9), (-180f64..180.0), (-40f64..40.0)),
            2..6,
        ),
        per_key in 1usize..5,
    ) {
        let layout = layout("*2223");
        let space = layout.space();
        let poses: Vec<Pose> = keys
            .iter()
            .map(|&(x, y, height, yaw, pitch)| Pose { at: [x, y], height, yaw, pitch })
            .collect();
        let path = Path::Keyframes(poses.clone());
        let count = (poses.len() - 1) * per_key + 1;
        for (k, key) in poses.iter().enumerate() {
            let pose = path.pose(&layout, poses[0], k * per_key, count);
            prop_assert!(space.distance(z(&pose), z(key)) < 1e-9);
            prop_assert!(turn(pose.yaw, key.yaw) < 1e-9);
            prop_assert!((pose.height - key.height).abs() < 1e-12);
        }
        // Between two keys the walker is on the geodesic joining them.
        for i in 0..count {
            let pose = path.pose(&layout, poses[0], i, count);
            let k = (i / per_key).min(poses.len() - 2);
            let (a, b) = (z(&poses[k]), z(&poses[k + 1]));
            let d = space.distance(a, z(&pose)) + space.distance(z(&pose), b);
            prop_assert!((d - space.distance(a, b)).abs() < 1e-9);
        }
    }
}

#[test]
fn keyframe_files_report_bad_lines() {
    let error = Path::parse_keyframes("0 0 0.5 0\n\n1 2 3\n").unwrap_err();
    assert!(error.contains("line 3"), "{error}");
    let error = Path::parse_keyframes("# nothing\n").unwrap_err();
    assert!(error.contains("no keyframes"), "{error}");
    let error = Path::parse_keyframes("0 0 0.5 inf").unwrap_err();
    assert!(error.contains("line 1"), "{error}");
    assert!(Path::parse_keyframes("0,0,0.5,0,10 # a comment").is_ok());
}
