//! In `*2222`, a rectangular room, every echo is the classic image-source model's (Allen &
//! Berkley, "Image method for efficiently simulating small-room acoustics", JASA 65, 1979),
//! written here independently from the rectangle's corners: times to a sample, amplitudes to
//! 1e-9 relative, the same echoes kept by the amplitude limit.

mod common;

use glam::DVec2;
use orbifold_scene::Scene;
use orbifold_scene::sound::Absorption;
use orbifold_sound::Hearing;
use proptest::prelude::*;

/// One image of the classic model: time (s) and amplitude.
#[derive(Clone, Copy, Debug)]
struct Image {
    time: f64,
    amplitude: f64,
}

/// Allen & Berkley's images of a box [0, Lx] × [0, Ly] × [0, Lz] (metres) with reflection
/// coefficients β per wall (x = 0, x = Lx, y = 0, y = Ly, z = 0, z = Lz), every one within
/// `seconds` and at least `min_amplitude`.
fn allen_berkley(
    size: [f64; 3],
    beta: [f64; 6],
    source: [f64; 3],
    listener: [f64; 3],
    speed: f64,
    seconds: f64,
    min_amplitude: f64,
) -> Vec<Image> {
    let reach = speed * seconds;
    let mut out = Vec::new();
    let range = |l: f64| {
        let n = (reach / (2.0 * l)).ceil() as i64 + 1;
        -n..=n
    };
    for l in range(size[0]) {
        for m in range(size[1]) {
            for n in range(size[2]) {
                for p in 0..8 {
                    let q = [p & 1, (p >> 1) & 1, (p >> 2) & 1];
                    let r = [l, m, n];
                    let mut d2 = 0.0;
                    let mut a = 1.0;
                    for axis in 0..3 {
                        let image = (1 - 2 * q[axis]) as f64 * source[axis]
                            + 2.0 * r[axis] as f64 * size[axis];
                        d2 += (image - listener[axis]).powi(2);
                        a *= beta[2 * axis].powi((r[axis] - q[axis]).abs() as i32)
                            * beta[2 * axis + 1].powi(r[axis].abs() as i32);
                    }
                    let d = d2.sqrt();
                    let amplitude = a / (4.0 * std::f64::consts::PI * d);
                    if d / speed <= seconds && amplitude >= min_amplitude {
                        out.push(Image {
                            time: d / speed,
                            amplitude,
                        });
                    }
                }
            }
        }
    }
    out
}

/// The box's frame in the room: corner v0, unit axes along v0→v1 and v0→v3, sides.
struct BoxFrame {
    origin: DVec2,
    axes: [DVec2; 2],
    sides: [f64; 2],
    /// The layout edge of each box wall: x = 0, x = Lx, y = 0, y = Ly.
    edges: [usize; 4],
}

fn box_frame(scene: &Scene) -> BoxFrame {
    let layout = scene.layout().unwrap();
    let space = layout.space();
    // Euclidean ambient coordinates are (2x, 2y, 1): intrinsic lengths are twice the model's.
    let corner = |i: usize| {
        let z = layout.vertices[i].position;
        DVec2::new(2.0 * z.re, 2.0 * z.im)
    };
    let (v0, v1, v2, v3) = (corner(0), corner(1), corner(2), corner(3));
    let edge_through = |a: DVec2, b: DVec2| {
        layout
            .edges
            .iter()
            .position(|e| {
                let on = |p: DVec2| e.wall.dot(glam::DVec3::new(p.x, p.y, 1.0)).abs() < 1e-9;
                on(a) && on(b)
            })
            .unwrap()
    };
    let _ = space;
    BoxFrame {
        origin: v0,
        axes: [(v1 - v0).normalize(), (v3 - v0).normalize()],
        sides: [(v1 - v0).length(), (v3 - v0).length()],
        edges: [
            edge_through(v0, v3),
            edge_through(v1, v2),
            edge_through(v0, v1),
            edge_through(v3, v2),
        ],
    }
}

/// Compares the response of a `*2222` scene with the classic model; returns the echoes
/// compared.
fn compare(scene: &Scene) -> usize {
    let hearing = Hearing::from_scene(scene, None).unwrap();
    let response = hearing.mono(&|_, _| {});
    let settings = hearing.settings;
    let frame = box_frame(scene);
    let r = settings.metres_per_unit;
    let local = |at: glam::DVec3, height: f64| {
        let p = DVec2::new(at.x, at.y) - frame.origin;
        [
            p.dot(frame.axes[0]) * r,
            p.dot(frame.axes[1]) * r,
            height * r,
        ]
    };
    // Walls 0 and 2 of the layout carry mirrors (see `shoebox_scene`), the others none.
    let beta_of = |edge: usize| {
        let mirrored = scene
            .wall_mirrors(edge)
            .iter()
            .any(|m| m.from <= 0.0 && m.to >= 1.0);
        if mirrored {
            settings.reflection.mirror[0]
        } else {
            settings.reflection.wall[0]
        }
    };
    let beta = [
        beta_of(frame.edges[0]),
        beta_of(frame.edges[1]),
        beta_of(frame.edges[2]),
        beta_of(frame.edges[3]),
        settings.reflection.floor[0],
        settings.reflection.ceiling[0],
    ];
    let mut expected = allen_berkley(
        [
            frame.sides[0] * r,
            frame.sides[1] * r,
            scene.room.height * r,
        ],
        beta,
        local(hearing.source.at, hearing.source.height),
        local(hearing.listener.at, hearing.listener.height),
        settings.speed,
        settings.seconds,
        settings.min_amplitude,
    );
    expected.sort_by(|a, b| a.time.total_cmp(&b.time));
    let ours = &response.arrivals;
    assert_eq!(response.lost, 0);
    assert_eq!(ours.len(), expected.len(), "number of echoes");
    // Match each classic image to an unused echo at the same time (images at the same
    // distance may come in either order).
    let mut used = vec![false; ours.len()];
    let sample = 1.0 / f64::from(settings.sample_rate);
    for e in &expected {
        let start = ours.partition_point(|a| a.time < e.time - 1e-9);
        let found = (start..ours.len())
            .take_while(|&i| ours[i].time <= e.time + 1e-9)
            .find(|&i| !used[i] && ((ours[i].amplitude - e.amplitude).abs() <= 1e-9 * e.amplitude));
        let i = found.unwrap_or_else(|| panic!("no echo matches {e:?}"));
        used[i] = true;
        assert!((ours[i].time - e.time).abs() < sample);
    }
    expected.len()
}

fn shoebox_scene(seconds: f64) -> Scene {
    let mut scene = common::scene("*2222", seconds);
    // Mirrors on walls 0 and 2 only: the others absorb more.
    scene.room.mirrors = orbifold_scene::MirrorDefault::None;
    for index in [0, 2] {
        scene.walls.push(orbifold_scene::Wall {
            index,
            material: None,
            mirrors: vec![orbifold_scene::Mirror {
                from: 0.0,
                to: 1.0,
                bottom: 0.0,
                top: None,
                reflectance: [0.9; 3],
            }],
        });
    }
    scene.sound.floor_absorption = Absorption::Flat(0.15);
    scene.sound.ceiling_absorption = Absorption::Flat(0.4);
    scene
}

#[test]
fn every_echo_of_a_shoebox_is_allen_and_berkley_s() {
    let n = compare(&shoebox_scene(0.25));
    assert!(n > 300, "{n} echoes");
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(12))]
    #[test]
    fn a_shoebox_agrees_with_allen_and_berkley_anywhere(
        s in (0.05f64..0.95, 0.05f64..0.95, 0.02f64..0.98),
        l in (0.05f64..0.95, 0.05f64..0.95, 0.02f64..0.98),
        min_level in -70.0f64..-30.0,
    ) {
        let mut scene = shoebox_scene(0.12);
        scene.sound.min_level = min_level;
        let layout = scene.layout().unwrap();
        // Points by fractions of the rectangle's sides from its first corner.
        let v = |i: usize| layout.vertices[i].position;
        let at = |(a, b): (f64, f64)| {
            let z = v(0) + (v(1) - v(0)) * a + (v(3) - v(0)) * b;
            [z.re, z.im]
        };
        scene.sound.source = Some(orbifold_scene::sound::Place { at: at((s.0, s.1)), height: s.2 });
        scene.sound.listener = Some(orbifold_scene::sound::Place { at: at((l.0, l.1)), height: l.2 });
        compare(&scene);
    }
}
